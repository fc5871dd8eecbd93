//! Symbolic expansion of a robot's dynamics over the expression graph, with every constant
//! of the robot folded in.
//!
//! The recursions are the generator's own (they share no code with the reference
//! implementation in `dynamics-reference`, so that comparing the two means something):
//! [`frames`] prepares the chain in joint frames, [`rnea`] expands Newton–Euler, [`crba`] the
//! composite-rigid-body mass matrix, and forward dynamics takes one of two routes:
//!
//! * [`ForwardRoute::Ldlt`]: `M(θ)` by [`crba`], the bias `c + g` by [`rnea`] with `θ̈ = 0`,
//!   and the unrolled [`ldlt`] solve of `M θ̈ = τ − c − g`;
//! * [`ForwardRoute::Aba`]: the articulated-body algorithm, [`aba`].
//!
//! Both are expanded (the articulated-body algorithm in its six equal forms, the cheapest
//! kept) and [`expand`] keeps the route whose live graph needs fewer operations
//! (`op_counts(..).total()`, every kind weighted 1; a tie keeps LDLᵀ; where a joint carries two
//! or more branches, or on a floating base, LDLᵀ only at nine tenths of the articulated-body
//! algorithm's count or below, `TREE_LDLT_SHARE`);
//! [`Dynamics::forward_route`] records the choice. Which one wins depends on the robot: the
//! LDLᵀ solve grows as n³ (the mass matrix as n²) but is cheap on short chains with general
//! geometry, where the articulated inertias' 21 entries cost more to move from frame to
//! frame; the articulated-body algorithm grows as n and needs one division fewer (the last
//! `D_n` is a constant). At the time of writing the articulated-body algorithm wins on
//! 12-joint random chains, the factorisation on the two-joint pendulum (since the bias's
//! Newton–Euler took the tensor form of [`rnea_classical::Euler`]), the UR5, the Panda and
//! rand7.
//! Likewise each Newton–Euler expansion keeps the cheapest of four equal forms (the link
//! wrench spatial or classical, [`rnea::LinkForce`]; classical accelerations with cross
//! products or through each body's tensor `W`, [`rnea_classical::Euler`]).
//!
//! Before the routes are compared, the graph is rebuilt by [`ExprGraph::prune_zeros`] from
//! the outputs and both forward-dynamics candidates: nodes that are identically zero up to
//! rounding (a cancellation no insertion rule sees, such as `g₁` of a robot whose first
//! axis is vertical) become exact zeros, so both the route choice and the emitted code see
//! the pruned counts. The choice among the Newton–Euler forms is made before pruning.
//!
//! The leaves of the graph are the inputs of the generated functions: `q`, `q̇`, `q̈`, `τ`
//! (groups [`Q`], [`QD`], [`QDD`], [`TAU`]), and `sin q_i`, `cos q_i` of revolute joints.
//!
//! Mimic joints ([`mimic`]): the inputs are the independent coordinates only; a follower's
//! angle is `m·q_L + (o + θ₀)` and its rates `m·q̇_L`, `m·q̈_L`, the recursions run over the
//! physical joints unchanged, and their outputs are projected (`τ_L = Σ m_f τ_f`,
//! `M = Jᵀ M J`). Forward dynamics then takes [`ForwardRoute::Ldlt`] alone: the
//! articulated-body algorithm assumes one coordinate per joint and is not expanded.
//!
//! Armature ([`dynamics_model::Joint::armature`], `G² I_rotor`): added to the joint's diagonal
//! entry of M after CRBA and as `armature · θ̈_i` to its Newton–Euler force, so every output
//! built on them (forward dynamics, energies, task space) has it. Forward dynamics then takes
//! [`ForwardRoute::Ldlt`] alone too: the articulated-body expansion's shortcut `D_i =
//! I^A_{i,ss}` (row and column s of `I^a` vanish) no longer holds once `D_i` has the armature.

pub mod aba;
pub mod base;
pub mod crba;
pub mod derivatives;
pub mod frames;
pub mod kinematics;
pub mod kinetic;
pub mod lagrangian;
pub mod ldlt;
pub mod mimic;
pub mod parameters;
pub mod regressor;
pub mod rnea;
pub mod rnea_classical;
pub mod rnea_derivatives;
pub mod spatial;
pub mod task_space;

use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::{JointKind, Robot};
use rnea::LinkForce;
use rnea_classical::Euler;
use spatial::{JointMotion, ShiftForm, VectorOps};

/// Input group of the joint positions q.
pub const Q: u8 = 0;
/// Input group of the joint velocities q̇.
pub const QD: u8 = 1;
/// Input group of the joint accelerations q̈.
pub const QDD: u8 = 2;
/// Input group of the joint forces τ.
pub const TAU: u8 = 3;

/// The leaf for input `group` at joint `index`.
pub fn input(group: u8, index: usize) -> Input {
    Input {
        group,
        index: index as u16,
    }
}

/// The algorithm behind [`Dynamics::forward_dynamics`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForwardRoute {
    /// Mass matrix by CRBA, bias by Newton–Euler, unrolled LDLᵀ solve.
    Ldlt,
    /// Featherstone's articulated-body algorithm.
    Aba,
}

/// How the dynamics are derived.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// Recursive Newton–Euler for the forces, the composite-rigid-body algorithm for `M`,
    /// and forward dynamics by LDLᵀ or the articulated-body algorithm (the default).
    #[default]
    NewtonEuler,
    /// The Euler–Lagrange equations of `K − P`, by symbolic differentiation on the graph
    /// ([`lagrangian`]); forward dynamics by LDLᵀ of that `M`.
    Lagrangian,
}

impl Method {
    /// `newton_euler` or `lagrangian`, as the options write it.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::NewtonEuler => "newton_euler",
            Method::Lagrangian => "lagrangian",
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "newton_euler" => Ok(Method::NewtonEuler),
            "lagrangian" => Ok(Method::Lagrangian),
            other => Err(format!(
                "unknown method `{other}`: use `newton_euler` (the default) or `lagrangian`"
            )),
        }
    }
}

/// The expanded dynamics of one robot: a graph and the outputs of each function.
#[derive(Clone, Debug)]
pub struct Dynamics {
    /// How the dynamics were derived.
    pub method: Method,
    /// The shared expression graph.
    pub graph: ExprGraph,
    /// k, the number of joint coordinates: the joints that mimic no other (n, the number of
    /// joints, for a robot without mimic joints).
    pub dof: usize,
    /// The length of q: k, or k + 7 with a floating base.
    pub nq: usize,
    /// The length of ν, ν̇ and τ: k, or k + 6 with a floating base.
    pub nv: usize,
    /// `M(q)`, nv×nv row-major.
    pub mass_matrix: Vec<ExprId>,
    /// `c(q, ν)`: Coriolis and centrifugal terms.
    pub coriolis: Vec<ExprId>,
    /// `g(q)`: gravity terms.
    pub gravity: Vec<ExprId>,
    /// `τ = M ν̇ + c + g`.
    pub inverse_dynamics: Vec<ExprId>,
    /// `ν̇ = M⁻¹(τ − c − g)`.
    pub forward_dynamics: Vec<ExprId>,
    /// The algorithm `forward_dynamics` was expanded with.
    pub forward_route: ForwardRoute,
    /// `K(q, ν) = ½ νᵀ M ν`: the route's own (the bodies' twists, [`kinetic`], for
    /// Newton–Euler; the Lagrangian's `K`) or `Σ_i ν_i (½ M_ii ν_i + Σ_{j>i} M_ij ν_j)` on
    /// the mass matrix's nodes, the cheaper.
    pub kinetic_energy: ExprId,
    /// `Ṁ(q, ν) = Σ_k ∂M/∂q_k q̇_k`: the directional derivative of `mass_matrix`'s graph
    /// along the configuration rate ([`base::configuration_rate`]), nv×nv row-major.
    pub mass_matrix_dot: Vec<ExprId>,
    /// `C(q, ν)` with `C ν = c` and `Ṁ − 2C` skew-symmetric: the Christoffel symbols of
    /// `mass_matrix` (and the base's Euler–Poincaré term), nv×nv row-major; see
    /// `coriolis_matrix`.
    pub coriolis_matrix: Vec<ExprId>,
    /// `h(q, ν) = c(q, ν) + g(q)`: Newton–Euler with `ν̇ = 0` (the bias of forward dynamics).
    pub bias: Vec<ExprId>,
    /// `L` of `M = Lᵀ D L` ([`ldlt::ltdl_factor`]): nv×nv row-major, its strictly lower
    /// triangle (L has a unit diagonal; the other entries hold leftovers of the
    /// factorisation and must not be read).
    pub mass_matrix_factor: Vec<ExprId>,
    /// `1 / D_k` of the same factorisation.
    pub mass_matrix_inv_d: Vec<ExprId>,
    /// `q̈₀ = M⁻¹ (τ − h)` by the same factor ([`ldlt::ltdl_apply`]): the unconstrained
    /// accelerations that constrained forward dynamics starts from (the same nodes as
    /// `forward_dynamics` where that takes the `Lᵀ D L` route).
    pub unconstrained: Vec<ExprId>,
    /// `τ + J_bᵀ F_tip` by Newton–Euler with the end effector's wrench `F_tip` (inputs
    /// [`task_space::F_TIP`]) applied at its link ([`rnea::ExternalWrench`]); empty where not
    /// expanded (the Lagrangian route: [`task_space`] then adds `J_bᵀ F_tip`).
    pub inverse_dynamics_with_tip: Vec<ExprId>,
    /// `h + J_bᵀ F_tip` the same way (the bias of `forward_dynamics_with_tip`).
    pub bias_with_tip: Vec<ExprId>,
}

/// Expands the five functions of `robot` (gravity as in `robot.gravity`), forward dynamics
/// by the cheaper of the two routes (ties: [`ForwardRoute::Ldlt`]; with mimic joints always
/// LDLᵀ).
pub fn expand(robot: &Robot) -> Dynamics {
    expand_routes(robot, None, true)
}

/// [`expand`] with forward dynamics by the given route (LDLᵀ for a robot with mimic joints,
/// whatever is asked).
pub fn expand_with_route(robot: &Robot, route: ForwardRoute) -> Dynamics {
    expand_routes(robot, Some(route), true)
}

/// What both routes start from: the joint frames (mimic offsets applied), the coupling,
/// the sizes, and a graph with the inputs `x` (the k coordinates, after a floating base's
/// seven q entries), `ν`, `ν̇`, `τ`.
pub(crate) struct Inputs {
    pub(crate) frames: frames::JointFrames,
    pub(crate) coupling: mimic::Coupling,
    /// k coordinates (n physical joints when none mimics another).
    pub(crate) k: usize,
    /// Offsets of the joints in q and in ν: after the base's position and quaternion, and
    /// after its twist.
    pub(crate) oq: usize,
    pub(crate) ov: usize,
    pub(crate) nv: usize,
    pub(crate) g: ExprGraph,
    pub(crate) x: Vec<ExprId>,
    pub(crate) xd: Vec<ExprId>,
    pub(crate) xdd: Vec<ExprId>,
    pub(crate) tau: Vec<ExprId>,
}

impl Inputs {
    pub(crate) fn new(robot: &Robot) -> Self {
        let mut frames = frames::joint_frames(robot);
        let coupling = mimic::Coupling::new(robot);
        mimic::offsets(&mut frames, robot);
        let k = robot.n_coordinates();
        let (oq, ov) = if frames.base.is_some() {
            (base::NQ_BASE, base::NV_BASE)
        } else {
            (0, 0)
        };
        let nv = k + ov;
        let mut g = ExprGraph::new();
        let x = (0..k).map(|i| g.input(input(Q, oq + i))).collect();
        let xd = (0..nv).map(|i| g.input(input(QD, i))).collect();
        let xdd = (0..nv).map(|i| g.input(input(QDD, i))).collect();
        let tau = (0..nv).map(|i| g.input(input(TAU, i))).collect();
        Self {
            frames,
            coupling,
            k,
            oq,
            ov,
            nv,
            g,
            x,
            xd,
            xdd,
            tau,
        }
    }
}

/// [`expand`] by the given method.
pub fn expand_method(robot: &Robot, method: Method) -> Dynamics {
    match method {
        Method::NewtonEuler => expand(robot),
        Method::Lagrangian => expand_lagrangian(robot, true),
    }
}

/// The Lagrangian route ([`lagrangian`]): `M`, `c`, `g` from `K − P`, `τ = M ν̇ + c + g`, and
/// forward dynamics by the cheaper LDLᵀ solve of that `M`; `prune` as in [`expand_routes`].
pub(crate) fn expand_lagrangian(robot: &Robot, prune: bool) -> Dynamics {
    let Inputs {
        frames,
        coupling,
        k,
        oq,
        nv,
        mut g,
        x,
        xd,
        xdd,
        tau,
        ..
    } = Inputs::new(robot);
    let t = lagrangian::lagrangian(&mut g, robot, &frames, &coupling, &x, &xd);
    let bias: Vec<ExprId> = (0..nv)
        .map(|i| g.add(t.coriolis[i], t.gravity[i]))
        .collect();
    // τ assembled as M ν̇ + c + g, or as the Euler–Lagrange equations' total time
    // derivative: the fewer operations.
    let assembled: Vec<ExprId> = (0..nv)
        .map(|i| {
            let m = g.dot(&t.mass_matrix[i * nv..(i + 1) * nv], &xdd);
            g.add(m, bias[i])
        })
        .collect();
    let inverse_dynamics = cheaper(&g, assembled, t.euler_lagrange);
    let rhs: Vec<ExprId> = (0..nv).map(|i| g.sub(tau[i], bias[i])).collect();
    let by_ldlt = ldlt::ldlt_solve(&mut g, &t.mass_matrix, &rhs);
    let by_ltdl = ldlt::ltdl_solve(&mut g, &t.mass_matrix, &rhs);
    let forward_dynamics = cheaper(&g, by_ldlt, by_ltdl);
    let kinetic = [t.kinetic_energy];
    let roots: [&[ExprId]; 7] = [
        &t.mass_matrix,
        &t.coriolis,
        &t.gravity,
        &inverse_dynamics,
        &bias,
        &forward_dynamics,
        &kinetic,
    ];
    let (g, pruned) = prune_if(prune, g, &roots);
    let mut pruned = pruned.into_iter();
    let mut next = || pruned.next().unwrap_or_default();
    let outputs = Outputs {
        mass_matrix: next(),
        coriolis: next(),
        gravity: next(),
        inverse_dynamics: next(),
        bias: next(),
        forward_dynamics: next(),
        inverse_dynamics_with_tip: Vec::new(),
        bias_with_tip: Vec::new(),
    };
    let kinetic_energy = next().first().copied();
    finish(
        g,
        Method::Lagrangian,
        ForwardRoute::Ldlt,
        (k, oq, nv),
        outputs,
        kinetic_energy,
    )
}

/// The functions' outputs before [`finish`] adds the ones derived from them.
struct Outputs {
    mass_matrix: Vec<ExprId>,
    coriolis: Vec<ExprId>,
    gravity: Vec<ExprId>,
    inverse_dynamics: Vec<ExprId>,
    bias: Vec<ExprId>,
    forward_dynamics: Vec<ExprId>,
    /// Empty where not expanded (the Lagrangian route).
    inverse_dynamics_with_tip: Vec<ExprId>,
    bias_with_tip: Vec<ExprId>,
}

/// The outputs derived from the mass matrix (`K`, unless the given one is cheaper, `Ṁ`,
/// `C`, the `Lᵀ D L` factor), and the whole [`Dynamics`]; `(k, oq, nv)` the sizes.
fn finish(
    mut g: ExprGraph,
    method: Method,
    forward_route: ForwardRoute,
    (k, oq, nv): (usize, usize, usize),
    o: Outputs,
    kinetic_energy: Option<ExprId>,
) -> Dynamics {
    let floating = oq != 0;
    // The expansion's own kinetic energy, or `½ νᵀ M ν` where that is cheaper.
    let from_mass_matrix = self::kinetic_energy(&mut g, &o.mass_matrix, nv);
    let kinetic_energy = match kinetic_energy {
        Some(own) => cheaper(&g, vec![own], vec![from_mass_matrix])[0],
        None => from_mass_matrix,
    };
    let rate = base::configuration_rate(&mut g, floating, k);
    let mass_matrix_dot = g.jvp(&o.mass_matrix, &rate);
    let coriolis_matrix = coriolis_matrix(&mut g, &o.mass_matrix, &mass_matrix_dot, floating, k);
    let (factor, inv_d) = ldlt::ltdl_factor(&mut g, &o.mass_matrix);
    let rhs: Vec<ExprId> = (0..nv)
        .map(|i| {
            let tau = g.input(input(TAU, i));
            g.sub(tau, o.bias[i])
        })
        .collect();
    let unconstrained = ldlt::ltdl_apply(&mut g, &factor, &inv_d, &rhs);
    Dynamics {
        method,
        graph: g,
        dof: k,
        nq: k + oq,
        nv,
        mass_matrix: o.mass_matrix,
        coriolis: o.coriolis,
        gravity: o.gravity,
        inverse_dynamics: o.inverse_dynamics,
        forward_dynamics: o.forward_dynamics,
        forward_route,
        kinetic_energy,
        mass_matrix_dot,
        coriolis_matrix,
        bias: o.bias,
        inverse_dynamics_with_tip: o.inverse_dynamics_with_tip,
        bias_with_tip: o.bias_with_tip,
        mass_matrix_factor: factor,
        mass_matrix_inv_d: inv_d,
        unconstrained,
    }
}

/// Where a joint carries two or more branches, or on a floating base, the share of the
/// articulated-body algorithm's operations at or below which CRBA + LDLᵀ is taken for forward
/// dynamics. Counted operations misjudge the two routes there (2026-12-05, AVX2 copies):
/// TALOS' upper body (20 joints, the arms and head branching off the torso) by CRBA +
/// `Lᵀ D L` with 2 % fewer operations ran 20 % slower than by the articulated-body algorithm,
/// G1 on a fixed pelvis with about 4 % fewer 1–2 % faster; Solo-12 on a fixed trunk (four
/// legs off the base, no joint with two children: not affected) with 15 % fewer 14 % faster.
const TREE_LDLT_SHARE: f64 = 0.9;

/// The share of the articulated-body algorithm's operations at or below which forward
/// dynamics takes CRBA + LDLᵀ: [`TREE_LDLT_SHARE`] where a joint carries two or more branches
/// or the base floats, 1 elsewhere.
fn ldlt_share(robot: &Robot) -> f64 {
    let parents = robot.parents();
    let mut children = vec![0usize; parents.len()];
    for p in parents.into_iter().flatten() {
        children[p] += 1;
    }
    if robot.base.floating || children.iter().any(|&c| c > 1) {
        TREE_LDLT_SHARE
    } else {
        1.0
    }
}

/// The cheaper of two equal expansions (ties keep `a`).
pub(crate) fn cheaper(g: &ExprGraph, a: Vec<ExprId>, b: Vec<ExprId>) -> Vec<ExprId> {
    if g.op_counts(&b).total() < g.op_counts(&a).total() {
        b
    } else {
        a
    }
}

/// The expansion; `prune`: replace identically zero nodes by 0 ([`ExprGraph::prune_zeros`]).
pub(crate) fn expand_routes(robot: &Robot, route: Option<ForwardRoute>, prune: bool) -> Dynamics {
    let Inputs {
        frames,
        coupling,
        k,
        oq,
        ov,
        nv,
        mut g,
        x,
        xd,
        xdd,
        tau,
    } = Inputs::new(robot);
    let floating = frames.base.is_some();
    // With mimic joints or an armature only LDLᵀ applies (see [`mimic`], and the
    // articulated-body algorithm's `D_i = I^A_{i,ss}` shortcut, which an armature breaks).
    let armature: Vec<f64> = frames.joints.iter().map(|f| f.armature).collect();
    let has_armature = armature.iter().any(|&a| a != 0.0);
    let ldlt_only = !coupling.is_identity() || has_armature;
    let route = if ldlt_only {
        Some(ForwardRoute::Ldlt)
    } else {
        route
    };
    // The physical joints' positions, velocities and accelerations (the inputs themselves
    // without mimic joints).
    let q = coupling.positions(&mut g, &x);
    let qd = coupling.rates(&mut g, &xd);
    let qdd = coupling.rates(&mut g, &xdd);
    let nv_phys = qd.len();
    let zero = g.zero();
    let zeros = vec![zero; nv_phys];
    let motions = joint_motions(&mut g, &frames, &q);
    let base_inertia = frames.base.as_ref();
    let no_gravity = g.zero3();
    let gravity_vec = parameters::gravity(&mut g, &frames);
    let mut mass_matrix = crba::crba(&mut g, &motions, base_inertia);
    // The armature on the joints' diagonal entries (Modern Robotics §8.9.2).
    let nv_joints = ov + armature.len();
    for (i, &a) in armature.iter().enumerate() {
        if a != 0.0 {
            let k = (ov + i) * nv_joints + ov + i;
            let c = g.constant(a);
            mass_matrix[k] = g.add(mass_matrix[k], c);
        }
    }
    let mass_matrix = coupling.matrix(&mut g, &mass_matrix);
    let best_rnea = |g: &mut ExprGraph,
                     v: &[ExprId],
                     vd: &[ExprId],
                     gravity: spatial::V3,
                     external: Option<&rnea::ExternalWrench>| {
        let base = base::base_motion(g, floating, &v[..ov], &vd[..ov], gravity);
        let (v, vd) = (&v[ov..], &vd[ov..]);
        let forms = [LinkForce::Spatial, LinkForce::Classical];
        let [a, b] =
            forms.map(|f| rnea::rnea(g, &motions, &base, base_inertia, v, vd, f, external));
        let [c, d] = [Euler::Vector, Euler::Tensor].map(|e| {
            rnea_classical::rnea_classical(g, &motions, &base, base_inertia, v, vd, external, e)
        });
        // The cheapest of the equal forms (ties keep the earlier one), projected onto the
        // coordinates.
        let best = cheaper(g, a, b);
        let best = cheaper(g, best, c);
        let mut best = cheaper(g, best, d);
        // The rotors' inertial forces, armature · θ̈_i.
        for (i, &arm) in armature.iter().enumerate() {
            if arm != 0.0 {
                let t = g.cmul(arm, vd[i]);
                best[ov + i] = g.add(best[ov + i], t);
            }
        }
        coupling.forces(g, &best)
    };
    let coriolis = best_rnea(&mut g, &qd, &zeros, no_gravity, None);
    let gravity = best_rnea(&mut g, &zeros, &zeros, gravity_vec, None);
    let inverse_dynamics = best_rnea(&mut g, &qd, &qdd, gravity_vec, None);
    let bias = best_rnea(&mut g, &qd, &zeros, gravity_vec, None);
    // With the end effector's wrench F_tip (inputs `task_space::F_TIP`) as F_{n+1}.
    let tip = tip_wrench(&mut g, robot, &frames);
    let inverse_dynamics_with_tip = best_rnea(&mut g, &qd, &qdd, gravity_vec, Some(&tip));
    let bias_with_tip = best_rnea(&mut g, &qd, &zeros, gravity_vec, Some(&tip));
    let rhs: Vec<ExprId> = (0..nv).map(|i| g.sub(tau[i], bias[i])).collect();
    // The factorisation from the first row (L D Lᵀ) or from the last (Lᵀ D L, which keeps a
    // tree's structural zeros): the cheaper.
    let by_ldlt = ldlt::ldlt_solve(&mut g, &mass_matrix, &rhs);
    let by_ltdl = ldlt::ltdl_solve(&mut g, &mass_matrix, &rhs);
    let by_ldlt = cheaper(&g, by_ldlt, by_ltdl);
    // The cheapest of the equal ways of writing out the articulated inertias' shifts and
    // the bias wrenches (ties keep the earlier one).
    let aba_base = base::base_motion(&mut g, floating, &qd[..ov], &zeros[..ov], gravity_vec);
    let mut by_aba: Option<Vec<ExprId>> = None;
    // The articulated-body algorithm has one coordinate per joint: not for mimic joints.
    let aba_forms = if ldlt_only {
        &[][..]
    } else {
        &[LinkForce::Spatial, LinkForce::Classical][..]
    };
    for &bias in aba_forms {
        for form in [ShiftForm::Direct, ShiftForm::Folded, ShiftForm::Sparse] {
            let candidate = aba::aba(
                &mut g,
                &motions,
                &aba_base,
                base_inertia,
                &qd[ov..],
                &tau,
                form,
                bias,
            );
            by_aba = Some(match by_aba {
                None => candidate,
                Some(best) => cheaper(&g, best, candidate),
            });
        }
    }
    let by_aba = by_aba.unwrap_or_default();
    // The kinetic energy by the bodies' twists; `finish` keeps it or `½ νᵀ M ν`, the cheaper.
    let v0 = base::base_motion(&mut g, floating, &qd[..ov], &zeros[..ov], no_gravity).v;
    let kinetic = [kinetic::kinetic_energy(
        &mut g,
        &motions,
        v0,
        base_inertia,
        &qd[ov..],
        &armature,
    )];
    // Identically zero nodes (cancellations spread over a sum, such as g₁ of a robot with
    // a vertical first axis) become exact zeros, before the routes are compared. Only the
    // candidate routes are rebuilt (the losing Newton–Euler forms are dropped).
    let candidates: Vec<&[ExprId]> = match route {
        None => vec![&by_ldlt, &by_aba],
        Some(ForwardRoute::Ldlt) => vec![&by_ldlt],
        Some(ForwardRoute::Aba) => vec![&by_aba],
    };
    let mut roots: Vec<&[ExprId]> = vec![
        &mass_matrix,
        &coriolis,
        &gravity,
        &inverse_dynamics,
        &bias,
        &inverse_dynamics_with_tip,
        &bias_with_tip,
        &kinetic,
    ];
    roots.extend(candidates);
    let (g, pruned) = prune_if(prune, g, &roots);
    let mut pruned = pruned.into_iter();
    let mut next = || pruned.next().unwrap_or_default();
    let (mass_matrix, coriolis, gravity, inverse_dynamics, bias) =
        (next(), next(), next(), next(), next());
    let (inverse_dynamics_with_tip, bias_with_tip) = (next(), next());
    let kinetic_energy = next().first().copied();
    let (by_ldlt, by_aba) = match route {
        None => (next(), next()),
        Some(ForwardRoute::Ldlt) => (next(), Vec::new()),
        Some(ForwardRoute::Aba) => (Vec::new(), next()),
    };
    let route = route.unwrap_or_else(|| {
        let (aba, ldlt) = (g.op_counts(&by_aba).total(), g.op_counts(&by_ldlt).total());
        if (ldlt as f64) <= ldlt_share(robot) * aba as f64 {
            ForwardRoute::Ldlt
        } else {
            ForwardRoute::Aba
        }
    });
    let forward_dynamics = match route {
        ForwardRoute::Ldlt => by_ldlt,
        ForwardRoute::Aba => by_aba,
    };
    let outputs = Outputs {
        mass_matrix,
        coriolis,
        gravity,
        inverse_dynamics,
        forward_dynamics,
        bias,
        inverse_dynamics_with_tip,
        bias_with_tip,
    };
    finish(
        g,
        Method::NewtonEuler,
        route,
        (k, oq, nv),
        outputs,
        kinetic_energy,
    )
}

/// The end effector's wrench `F_tip = (m, f)` (inputs [`task_space::F_TIP`], in the end
/// effector's frame `f`) in the joint frame of its link: with `(R, p) = T_{J,f}`, `(R m + p ×
/// R f, R f)` (`[Ad_{T_{f,J}}]ᵀ F_tip`); on the base, in {0}.
fn tip_wrench(
    g: &mut ExprGraph,
    robot: &Robot,
    frames: &frames::JointFrames,
) -> rnea::ExternalWrench {
    let ee = &robot.end_effector;
    let home = robot.frame_home(ee);
    let k = match ee.parent {
        Some(j) => dynamics_model::lie::trans_inv(&frames.homes[j]) * home,
        None => home,
    };
    let r: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| k[(i, j)]));
    let p = g.const3([k[(0, 3)], k[(1, 3)], k[(2, 3)]]);
    let m: spatial::V3 = std::array::from_fn(|i| g.input(input(task_space::F_TIP, i)));
    let f: spatial::V3 = std::array::from_fn(|i| g.input(input(task_space::F_TIP, 3 + i)));
    let rf = g.rot(&r, f);
    let rm = g.rot(&r, m);
    let pxrf = g.cross(p, rf);
    rnea::ExternalWrench {
        joint: ee.parent,
        wrench: spatial::Spatial {
            ang: g.add3(rm, pxrf),
            lin: rf,
        },
    }
}

/// The Coriolis matrix from the Christoffel symbols of the first kind of `m` (nv×nv
/// row-major), with `m_dot` = Ṁ:
/// ```text
/// C_ij = Σ_k Γ_ijk ν_k,   Γ_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i)
///   ⇒  C = ½ (Ṁ + P − Pᵀ),   P_ij = ∂(M ν)_i/∂q_j  (ν held constant)
/// ```
/// (the first sum is Ṁ, the second and third are P and Pᵀ), so `C ν = c` and `Ṁ − 2C =
/// Pᵀ − P` is skew-symmetric (Modern Robotics §8.1.2). P's columns are the partial
/// derivatives of the momentum `p = M ν` along each joint coordinate (one forward-mode
/// sweep each); on a floating base M does not depend on the base pose, so the base's six
/// columns of P are zero, and its base block gets the Euler–Poincaré term `−H(h_b)` of the
/// body twist, `H(h) V = [ad_V]ᵀ h` with `h_b = p[0..6]` (see `dynamics_reference`'s
/// `coriolis_matrix`), which keeps both properties.
pub(crate) fn coriolis_matrix(
    g: &mut ExprGraph,
    m: &[ExprId],
    m_dot: &[ExprId],
    floating: bool,
    k: usize,
) -> Vec<ExprId> {
    let (oq, ov) = if floating {
        (base::NQ_BASE, base::NV_BASE)
    } else {
        (0, 0)
    };
    let nv = k + ov;
    let v: Vec<ExprId> = (0..nv).map(|i| g.input(input(QD, i))).collect();
    let p: Vec<ExprId> = m.chunks(nv).map(|row| g.dot(row, &v)).collect();
    let zero = g.zero();
    // dp[j] = ∂p/∂q_j (column j of P).
    let mut dp = vec![vec![zero; nv]; nv];
    for j in 0..k {
        dp[ov + j] = g.diff_many(&p, input(Q, oq + j));
    }
    let mut c = vec![zero; nv * nv];
    for i in 0..nv {
        for j in 0..nv {
            let skew = g.sub(dp[j][i], dp[i][j]);
            let sum = g.add(m_dot[i * nv + j], skew);
            c[i * nv + j] = g.cmul(0.5, sum);
        }
    }
    if floating {
        // −H(h_b) = −[[ [h_ω], [h_f] ], [ [h_f], 0 ]], [x] the cross-product matrix.
        let h: Vec<ExprId> = p[..6].to_vec();
        let cross = |g: &mut ExprGraph, x: &[ExprId]| -> [[ExprId; 3]; 3] {
            let neg = |g: &mut ExprGraph, a| g.neg(a);
            let (nx0, nx1, nx2) = (neg(g, x[0]), neg(g, x[1]), neg(g, x[2]));
            [[zero, nx2, x[1]], [x[2], zero, nx0], [nx1, x[0], zero]]
        };
        let hw = cross(g, &h[..3]);
        let hf = cross(g, &h[3..]);
        for r in 0..3 {
            for s in 0..3 {
                for (row, col, x) in [(r, s, hw[r][s]), (r, 3 + s, hf[r][s]), (3 + r, s, hf[r][s])]
                {
                    let e = &mut c[row * nv + col];
                    *e = g.sub(*e, x);
                }
            }
        }
    }
    c
}

/// `½ νᵀ M ν` from the nv×nv row-major `m` (see [`Dynamics::kinetic_energy`]).
fn kinetic_energy(g: &mut ExprGraph, m: &[ExprId], nv: usize) -> ExprId {
    let v: Vec<ExprId> = (0..nv).map(|i| g.input(input(QD, i))).collect();
    let terms: Vec<ExprId> = (0..nv)
        .map(|i| {
            let c = g.constant(0.5);
            let half = g.mul(c, m[i * nv + i]);
            let mut row = vec![g.mul(half, v[i])];
            row.extend((i + 1..nv).map(|j| g.mul(m[i * nv + j], v[j])));
            let inner = g.sum(&row);
            g.mul(v[i], inner)
        })
        .collect();
    g.sum(&terms)
}

/// [`prune_checked`] when `prune`, else the graph and the roots unchanged.
fn prune_if(prune: bool, g: ExprGraph, roots: &[&[ExprId]]) -> (ExprGraph, Vec<Vec<ExprId>>) {
    if prune {
        prune_checked(g, roots)
    } else {
        (g, roots.iter().map(|r| r.to_vec()).collect())
    }
}

/// The tolerances (multiples of `ε·m`, see [`crate::expr::zeros`]) tried in turn by
/// [`prune_checked`]: the default, a tighter one, and exact zeros only.
const PRUNE_TOLERANCES: [f64; 3] = [crate::expr::zeros::TOL_FACTOR, 1e-3, 0.0];

/// Relative change of any output, at the check's samples, beyond which a pruning is refused.
const PRUNE_CHECK: f64 = 1e-9;

/// [`ExprGraph::prune_zeros`], checked: the outputs of the pruned graph are evaluated at
/// fresh random inputs beside the unpruned ones, and where any output group differs by more
/// than [`PRUNE_CHECK`] (relative to the group's largest value), the pruning is redone with
/// the next, tighter tolerance of [`PRUNE_TOLERANCES`]; the graph stays unpruned if none
/// passes. (Deep trees need this: there the rounding bound that decides what is zero can
/// exceed a genuinely non-zero sum.)
fn prune_checked(g: ExprGraph, roots: &[&[ExprId]]) -> (ExprGraph, Vec<Vec<ExprId>>) {
    let mut rng = crate::expr::zeros::SplitMix(ZERO_SEED ^ 0xC4EC);
    let samples: Vec<Vec<(Input, f64)>> = (0..3)
        .map(|_| {
            g.inputs()
                .map(|x| {
                    let (lo, hi) = sample_range(x);
                    (x, rng.uniform(lo, hi))
                })
                .collect()
        })
        .collect();
    let value = |sample: &[(Input, f64)], x: Input| {
        sample
            .iter()
            .find(|(y, _)| *y == x)
            .map_or(0.0, |(_, v)| *v)
    };
    let before: Vec<Vec<Vec<f64>>> = samples
        .iter()
        .map(|s| roots.iter().map(|r| g.eval(r, &|x| value(s, x))).collect())
        .collect();
    for tol in PRUNE_TOLERANCES {
        let (pg, pruned) = g.prune_zeros_with(roots, &sample_range, ZERO_SEED, tol);
        let agrees = samples.iter().zip(&before).all(|(s, want)| {
            pruned.iter().zip(want).all(|(r, y)| {
                let x = pg.eval(r, &|x| value(s, x));
                let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                x.iter()
                    .zip(y)
                    .all(|(a, b)| (a - b).abs() <= PRUNE_CHECK * scale + 1e-300)
            })
        });
        if agrees {
            return (pg, pruned);
        }
    }
    (g.clone(), roots.iter().map(|r| r.to_vec()).collect())
}

/// Seed of the random inputs at which [`ExprGraph::prune_zeros`] looks for zero nodes.
const ZERO_SEED: u64 = 0x5EED_2E60;

/// Where the zero test samples the inputs: `q` in `[−π, π]` (every angle, and its sine and
/// cosine, takes general values), `q̇`, `q̈`, `τ` in `[−1, 1]`.
fn sample_range(x: Input) -> (f64, f64) {
    use std::f64::consts::PI;
    match x.group {
        Q => (-PI, PI),
        _ => (-1.0, 1.0),
    }
}

/// The symbolic state of every joint: `θ_i + θ₀` (or `d_i + q_i`) and, for revolute joints,
/// its sine and cosine.
pub(crate) fn joint_motions<'a>(
    g: &mut ExprGraph,
    frames: &'a frames::JointFrames,
    q: &[ExprId],
) -> Vec<JointMotion<'a>> {
    let zero = g.zero();
    frames
        .joints
        .iter()
        .enumerate()
        .map(|(i, f)| {
            // The joint variable with its home offset: θ_i + θ₀ or d_i + q_i.
            let offset = g.constant(f.offset);
            let angle = g.add(q[i], offset);
            let (sin, cos) = match f.kind {
                JointKind::Revolute => (g.sin(angle), g.cos(angle)),
                JointKind::Prismatic => (zero, zero),
            };
            JointMotion {
                frame: f,
                sin,
                cos,
                q: angle,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod tree_tests;

#[cfg(test)]
mod mimic_tests;

#[cfg(test)]
mod kinematics_tests;

#[cfg(test)]
mod derivatives_tests;

#[cfg(test)]
mod lagrangian_tests;

#[cfg(test)]
mod regressor_tests;

#[cfg(test)]
mod parameters_tests;
