//! The Lagrangian route (Modern Robotics §8.1, Exercise 8.4): the dynamics as the
//! Euler–Lagrange equations of `L = K − P`, by symbolic differentiation on the graph, with no
//! Newton–Euler, composite-rigid-body or articulated-body recursion in it.
//!
//! ```text
//! V_i  = [Ad_{T_{i,λ(i)}}] V_λ(i) + A_i θ̇_i          the body twist of link i (V_0 = 0, or ν_b)
//! K    = ½ Σ_i V_iᵀ G_i V_i  (+ ½ ν_bᵀ G_b ν_b)  (+ ½ Σ_i a_i θ̇_i², the rotors' armature)
//! P    = −Σ_i m_i gᵀ p_i                           (the centres of mass p_i in {0})
//! p    = ∂K/∂ν                                     the generalised momentum
//! M    = ∂²K/∂ν²  = ∂p/∂ν
//! c    = d/dt p |_{ν̇ = 0} − ∂K/∂q  = Ṁ ν − ∂K/∂q
//! g    = ∂P/∂q
//! τ    = M ν̇ + c + g  =  d/dt p − ∂K/∂q + ∂P/∂q
//! ```
//!
//! `p` and `∂K/∂q` come from one reverse-mode sweep over `K` ([`ExprGraph::grad`]), `g` from
//! one over `P`, so they cost a small multiple of `K` and `P` themselves (forward mode would
//! cost that per coordinate). `M` is `∂p/∂ν` by forward mode over that gradient, or over
//! forward-mode `∂K/∂ν_j` (which keeps the links' Jacobian columns apart): the fewer
//! operations. `τ` is either assembled as `M ν̇ + c + g` or taken as the total time derivative
//! along `(q̇, ν̇)` without forming `M ν̇` (`super::expand_lagrangian` keeps the one with
//! fewer operations).
//!
//! `c` is the Christoffel form `c_i = Σ_jk Γ_ijk ν_j ν_k`, `Γ_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j
//! − ∂M_jk/∂q_i)`, contracted with `ν` before differentiating: under the symmetric sum the
//! first two terms of `Γ` are equal and give `(Ṁ ν)_i`, and the third gives `½ νᵀ ∂M/∂q_i ν =
//! ∂K/∂q_i`. So one forward-mode sweep along the configuration rate (`Ṁ ν`) and one per
//! coordinate (`∂K/∂q_i`) replace the n³ symbols. The Coriolis matrix `C` itself is built
//! from the symbols of this `M` as on the Newton–Euler route (`super::coriolis_matrix`).
//!
//! The twists run in the joint frames of [`super::frames`], with their inertias as regrouped
//! there: the regrouped masses lie on a joint's axis and move with either link, so `K` is
//! unchanged. `P` is built from the file's inertias (`kinematics::potential_energy_of`).
//!
//! Mimic joints: `K` and `P` are functions of the independent coordinates (the followers'
//! angles and rates are `m x + o` and `m ẋ`), so their derivatives are the projected
//! `Jᵀ M J`, `Jᵀ (c + g)` with nothing more to do.
//!
//! Floating base (`ν = (ω_b, v_b, θ̇)`, the base's body twist, which is not the derivative of
//! any coordinate): the Euler–Poincaré form of the equations. Derivatives with respect to the
//! configuration are taken in the tangent space (as [`super::derivatives`] does), `K` does
//! not depend on the base's pose, and the base's rows get the term of the moving frame:
//! ```text
//! c_b = d/dt p_b − [ad_{ν_b}]ᵀ p_b,    −[ad_V]ᵀ (k, l) = (ω × k + v × l, ω × l)
//! ```
//! with `p_b = (k, l)` the base's six entries of the momentum (a free rigid body's
//! `F = G V̇ − [ad_V]ᵀ G V` is this with `K = ½ Vᵀ G V`).

use super::derivatives::tangent_seeds;
use super::frames::JointFrames;
use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use super::{base, input, kinematics, Q, QD, QDD};
use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::{JointKind, Robot};

/// The terms of the Euler–Lagrange equations, on the caller's graph.
pub struct Terms {
    /// `K(q, ν)`.
    pub kinetic_energy: ExprId,
    /// `M(q) = ∂²K/∂ν²`, nv×nv row-major (exactly symmetric: the upper triangle mirrored).
    pub mass_matrix: Vec<ExprId>,
    /// `c(q, ν) = Ṁ ν − ∂K/∂q` (and the base's Euler–Poincaré term).
    pub coriolis: Vec<ExprId>,
    /// `g(q) = ∂P/∂q`.
    pub gravity: Vec<ExprId>,
    /// `τ = d/dt ∂K/∂ν − ∂K/∂q + ∂P/∂q` (the base's term included) as one total time
    /// derivative along `(q̇, ν̇)`: the Euler–Lagrange equations without forming `M ν̇`.
    pub euler_lagrange: Vec<ExprId>,
}

/// The body twists `V_i` of every link in its joint frame, from the base's twist `v0` and
/// the physical joint rates `qd`.
pub(crate) fn link_twists(
    g: &mut ExprGraph,
    motions: &[JointMotion<'_>],
    v0: Spatial,
    qd: &[ExprId],
) -> Vec<Spatial> {
    let mut out: Vec<Spatial> = Vec::with_capacity(motions.len());
    for (i, m) in motions.iter().enumerate() {
        let parent = m.frame.parent.map_or(v0, |p| out[p]);
        let mut v = m.motion_to_child(g, parent);
        // A_i θ̇_i: e_z in the angular (revolute) or linear (prismatic) part.
        let k = match m.frame.kind {
            JointKind::Revolute => &mut v.ang[2],
            JointKind::Prismatic => &mut v.lin[2],
        };
        *k = g.add(*k, qd[i]);
        out.push(v);
    }
    out
}

/// `Vᵀ G V` of a body with inertia `gi`.
fn twice_kinetic(g: &mut ExprGraph, gi: Inertia, v: &Spatial) -> ExprId {
    let p = gi.apply(g, v);
    let a = g.dot(&v.ang, &p.ang);
    let l = g.dot(&v.lin, &p.lin);
    g.add(a, l)
}

/// The Euler–Lagrange terms of `robot` (see the module docs): `x` the k independent joint
/// coordinates (the q inputs after a floating base's seven), `xd` the nv velocity inputs.
pub fn lagrangian(
    g: &mut ExprGraph,
    robot: &Robot,
    frames: &JointFrames,
    coupling: &super::mimic::Coupling,
    x: &[ExprId],
    xd: &[ExprId],
) -> Terms {
    let k = x.len();
    let nv = xd.len();
    let floating = frames.base.is_some();
    let ov = nv - k;
    let q = coupling.positions(g, x);
    let qd = coupling.rates(g, xd);
    let motions = super::joint_motions(g, frames, &q);
    let zero = g.zero3();
    let v0 = if floating {
        Spatial {
            ang: [qd[0], qd[1], qd[2]],
            lin: [qd[3], qd[4], qd[5]],
        }
    } else {
        Spatial {
            ang: zero,
            lin: zero,
        }
    };
    let twists = link_twists(g, &motions, v0, &qd[ov..]);
    // 2K, link by link, the floating base's own body and the rotors.
    let mut terms: Vec<ExprId> = motions
        .iter()
        .zip(&twists)
        .map(|(m, v)| {
            let gi = super::parameters::link_inertia(g, m.frame);
            twice_kinetic(g, gi, v)
        })
        .collect();
    if let Some(b) = &frames.base {
        let gb = Inertia::constant(g, b);
        terms.push(twice_kinetic(g, gb, &v0));
    }
    for (i, f) in frames.joints.iter().enumerate() {
        if f.armature != 0.0 {
            let r = qd[ov + i];
            let sq = g.mul(r, r);
            terms.push(g.cmul(f.armature, sq));
        }
    }
    let twice = g.sum(&terms);
    let kinetic_energy = g.cmul(0.5, twice);
    let potential = kinematics::potential_energy_of(g, robot, frames, &q);
    // p = ∂K/∂ν and ∂K/∂θ in one reverse sweep; ∂P/∂q in another.
    let oq = if floating { base::NQ_BASE } else { 0 };
    let mut wrt: Vec<Input> = (0..nv).map(|j| input(QD, j)).collect();
    wrt.extend((0..k).map(|j| input(Q, oq + j)));
    let grad_k = g.grad(kinetic_energy, &wrt);
    let momentum = grad_k[..nv].to_vec();
    // ∂K/∂q in the tangent space: K does not depend on a floating base's pose.
    let mut dk = vec![g.zero(); ov];
    dk.extend_from_slice(&grad_k[nv..]);
    let gravity = tangent_gradient(g, potential, floating, k);
    // M = ∂p/∂ν, forward over reverse or forward over forward (p_j = ∂K/∂ν_j one input at a
    // time, which keeps each link's twist columns apart): the fewer operations.
    let by_reverse = hessian(g, &momentum);
    let forward: Vec<ExprId> = (0..nv)
        .map(|j| g.diff(kinetic_energy, input(QD, j)))
        .collect();
    let by_forward = hessian(g, &forward);
    let mass_matrix = super::cheaper(g, by_reverse, by_forward);
    // c = d/dt p (ν held) − ∂K/∂q; the Euler–Lagrange τ = d/dt p − ∂K/∂q + ∂P/∂q in full.
    let rate = base::configuration_rate(g, floating, k);
    let p_dot = g.jvp(&momentum, &rate);
    let mut coriolis: Vec<ExprId> = (0..nv).map(|i| g.sub(p_dot[i], dk[i])).collect();
    let mut full_rate = rate;
    full_rate.extend((0..nv).map(|j| (input(QD, j), g.input(input(QDD, j)))));
    let p_dot_full = g.jvp(&momentum, &full_rate);
    let mut euler_lagrange: Vec<ExprId> = (0..nv)
        .map(|i| {
            let t = g.sub(p_dot_full[i], dk[i]);
            g.add(t, gravity[i])
        })
        .collect();
    if floating {
        // −[ad_{ν_b}]ᵀ p_b = (ω × k + v × l, ω × l).
        let (w, v) = ([xd[0], xd[1], xd[2]], [xd[3], xd[4], xd[5]]);
        let (kk, l) = (
            [momentum[0], momentum[1], momentum[2]],
            [momentum[3], momentum[4], momentum[5]],
        );
        let wk = g.cross(w, kk);
        let vl = g.cross(v, l);
        let ang = g.add3(wk, vl);
        let lin = g.cross(w, l);
        for (r, (a, l)) in ang.into_iter().zip(lin).enumerate() {
            for c in [&mut coriolis, &mut euler_lagrange] {
                c[r] = g.add(c[r], a);
                c[3 + r] = g.add(c[3 + r], l);
            }
        }
    }
    Terms {
        kinetic_energy,
        mass_matrix,
        coriolis,
        gravity,
        euler_lagrange,
    }
}

/// `∂p/∂ν` (nv×nv row-major) of the momentum `p`: its upper triangle by one forward sweep
/// per column, mirrored, so the result is exactly symmetric.
pub(crate) fn hessian(g: &mut ExprGraph, p: &[ExprId]) -> Vec<ExprId> {
    let nv = p.len();
    let mut m = vec![g.zero(); nv * nv];
    for j in 0..nv {
        let col = g.diff_many(&p[..=j], input(QD, j));
        for (i, &e) in col.iter().enumerate() {
            m[i * nv + j] = e;
            m[j * nv + i] = e;
        }
    }
    m
}

/// `∂P/∂q` of a function of the q inputs in the tangent space ([`tangent_seeds`]): its
/// gradient by one reverse sweep, then for each tangent direction `Σ_x ∂P/∂x · ẋ`.
fn tangent_gradient(g: &mut ExprGraph, p: ExprId, floating: bool, k: usize) -> Vec<ExprId> {
    let nq = if floating { base::NQ_BASE + k } else { k };
    let xs: Vec<Input> = (0..nq).map(|i| input(Q, i)).collect();
    let grad = g.grad(p, &xs);
    let seeds = tangent_seeds(g, floating, k);
    seeds
        .iter()
        .map(|s| {
            let terms: Vec<ExprId> = s
                .iter()
                .map(|&(x, e)| g.mul(grad[x.index as usize], e))
                .collect();
            g.sum(&terms)
        })
        .collect()
}
