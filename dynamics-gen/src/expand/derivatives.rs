//! Symbolic derivatives of the dynamics for optimal control, on one graph that imports the
//! dynamics ([`super::Dynamics`]) with [`ExprGraph::import`].
//!
//! Derivatives with respect to the configuration are taken in the tangent space (nv
//! columns), as Pinocchio does: column `j` of `∂f/∂q` is the directional derivative of `f`
//! along the configuration rate ([`super::base::configuration_rate`]) of the unit velocity
//! `ν = e_j`. On a fixed base this is the plain partial `∂f/∂θ_j`. On a floating base
//! (`q = (p, quat, θ)`, `ν = (ω_b, v_b, θ̇)`) the joint columns are plain partials too, and
//! the base's six columns are the derivatives along the body-frame motions
//! ```text
//! ṗ = R v_b,   quaṫ = ½ quat ⊗ (ω_b, 0)     with (ω_b, v_b) = e_k, k = 0..6
//! ```
//! (one forward-mode sweep [`ExprGraph::jvp`] each, its seeds the configuration rate with the
//! `ν` inputs replaced by the unit vector, [`ExprGraph::substitute`]). Derivatives with
//! respect to `ν` are plain partials ([`ExprGraph::diff_many`]).
//!
//! With `τ = ID(q, ν, ν̇)` (inverse dynamics), `g(q)` (gravity) and `M(q)`:
//! ```text
//! ∂τ/∂q, ∂τ/∂ν       tangent / plain partials of ID, ν̇ held fixed;  ∂τ/∂ν̇ = M
//! ∂g/∂q              tangent partials of g
//! M⁻¹                columns M⁻¹ e_j by the unrolled Lᵀ D L factor (ldlt::ltdl_apply),
//!                    lower triangle computed, upper mirrored
//! ∂ν̇/∂q = −M⁻¹ ∂τ/∂q |_{ν̇ = FD(q, ν, τ)},   ∂ν̇/∂ν = −M⁻¹ ∂τ/∂ν |_{ν̇ = FD(q, ν, τ)},   ∂ν̇/∂τ = M⁻¹
//! ```
//! The last two follow from differentiating `ID(q, ν, FD(q, ν, τ)) = τ` (implicit function
//! theorem, in the tangent space as well): the partials of inverse dynamics are built with
//! the `ν̇` inputs ([`QDD`]) free, then those inputs are replaced by the forward-dynamics
//! expressions (which read [`TAU`]), and each column is solved with the factor of `M`
//! (`−M⁻¹ b` by `ltdl_apply`, which keeps a tree's structural zeros).
//!
//! On a fixed base without mimic joints `∂τ/∂q`, `∂τ/∂q̇` and `∂g/∂q` are also expanded by
//! the analytical recursion of Carpentier & Mansard ([`rnea_derivatives`], in joint frames,
//! its pair terms in either frame of [`PairFrame`]), and each matrix keeps the form with the
//! fewest operations (the pair of `∂τ` matrices counted together, as they share nodes): on
//! the Panda the recursion needs 3,406 operations for both against 6,301 by forward mode.
//! On the Lagrangian route ([`super::Method::Lagrangian`]) the recursion is not used: every
//! derivative is the forward-mode derivative of the Lagrangian's expressions.
//! `−M⁻¹ B` is taken either by solves with the factor or as the product with `M⁻¹`, the
//! fewer operations.
//!
//! Every matrix is nv×nv row-major, `[i * nv + j] = ∂f_i/∂x_j`.

use super::rnea_derivatives::PairFrame;
use super::spatial::VectorOps;
#[cfg(doc)]
use super::TAU;
use super::{base, frames, input, ldlt, mimic, rnea_derivatives, Dynamics, Q, QD, QDD};
use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::Robot;

/// The derivatives, on their own graph (inputs [`super::Q`], [`QD`], [`QDD`], [`super::TAU`]).
#[derive(Clone, Debug)]
pub struct Derivatives {
    /// The combined graph.
    pub graph: ExprGraph,
    /// nv, the size of every (square) matrix.
    pub nv: usize,
    /// `∂τ/∂q` (tangent space) of inverse dynamics; reads q, ν, ν̇.
    pub d_tau_dq: Vec<ExprId>,
    /// `∂τ/∂ν` of inverse dynamics; reads q, ν.
    pub d_tau_dqd: Vec<ExprId>,
    /// `∂g/∂q` (tangent space); reads q.
    pub gravity_derivative: Vec<ExprId>,
    /// `M⁻¹` (symmetric); reads q.
    pub mass_matrix_inverse: Vec<ExprId>,
    /// `∂ν̇/∂q` (tangent space) of forward dynamics; reads q, ν, τ.
    pub d_qdd_dq: Vec<ExprId>,
    /// `∂ν̇/∂ν` of forward dynamics; reads q, ν, τ.
    pub d_qdd_dqd: Vec<ExprId>,
    /// Inverse dynamics `τ` (as in [`Dynamics::inverse_dynamics`]), for the functions that
    /// return the value with its derivatives.
    pub inverse_dynamics: Vec<ExprId>,
    /// Forward dynamics `ν̇` (as in [`Dynamics::forward_dynamics`]).
    pub forward_dynamics: Vec<ExprId>,
    /// How each matrix was obtained (the form with the fewer operations), for the docs.
    pub method: DerivativeMethod,
}

/// Which form [`expand_derivatives`] kept for each matrix.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DerivativeMethod {
    /// `∂τ/∂q` by the analytical recursion ([`rnea_derivatives`]); otherwise forward mode.
    pub d_tau_dq_analytical: bool,
    /// `∂τ/∂ν` by the analytical recursion; otherwise forward mode.
    pub d_tau_dqd_analytical: bool,
    /// `∂g/∂q` by the analytical recursion; otherwise forward mode.
    pub gravity_derivative_analytical: bool,
    /// `−M⁻¹ B` as the product with `M⁻¹`; otherwise by solves with the factor of `M`.
    pub by_product: bool,
}

/// The seeds of [`ExprGraph::jvp`] for each of the nv tangent directions of the
/// configuration: the configuration rate of `ν = e_j`.
pub fn tangent_seeds(g: &mut ExprGraph, floating: bool, dof: usize) -> Vec<Vec<(Input, ExprId)>> {
    let nv = if floating { dof + base::NV_BASE } else { dof };
    let rate = base::configuration_rate(g, floating, dof);
    let (zero, one) = (g.zero(), g.one());
    (0..nv)
        .map(|j| {
            let exprs: Vec<ExprId> = rate.iter().map(|&(_, e)| e).collect();
            let unit = g.substitute(&exprs, &|x: Input| {
                (x.group == QD).then_some(if x.index as usize == j { one } else { zero })
            });
            rate.iter()
                .zip(unit)
                .map(|(&(x, _), e)| (x, e))
                .filter(|&(_, e)| !g.is_zero(e))
                .collect()
        })
        .collect()
}

/// `∂f/∂q` in the tangent space, `f.len()`×nv row-major (see the module docs).
pub fn tangent_jacobian(
    g: &mut ExprGraph,
    f: &[ExprId],
    seeds: &[Vec<(Input, ExprId)>],
) -> Vec<ExprId> {
    let cols: Vec<Vec<ExprId>> = seeds
        .iter()
        .map(|s| match s.as_slice() {
            // One unit seed: a plain partial (diff_many skips what does not depend on it).
            [(x, e)] if g.is_one(*e) => g.diff_many(f, *x),
            _ => g.jvp(f, s),
        })
        .collect();
    transpose(&cols, f.len())
}

/// `∂f/∂x` for the inputs `x` of `group` with indices `0..n`, `f.len()`×n row-major.
pub(crate) fn partials(g: &mut ExprGraph, f: &[ExprId], group: u8, n: usize) -> Vec<ExprId> {
    let cols: Vec<Vec<ExprId>> = (0..n).map(|j| g.diff_many(f, input(group, j))).collect();
    transpose(&cols, f.len())
}

/// Row-major matrix from its columns.
fn transpose(cols: &[Vec<ExprId>], rows: usize) -> Vec<ExprId> {
    (0..rows)
        .flat_map(|i| cols.iter().map(move |c| c[i]))
        .collect()
}

/// `−M⁻¹ B` for `B` nv×nv row-major, column by column from the factor `(h, inv_d)`.
fn neg_solve(g: &mut ExprGraph, h: &[ExprId], inv_d: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let nv = inv_d.len();
    let cols: Vec<Vec<ExprId>> = (0..nv)
        .map(|j| {
            let col: Vec<ExprId> = (0..nv).map(|i| g.neg(b[i * nv + j])).collect();
            ldlt::ltdl_apply(g, h, inv_d, &col)
        })
        .collect();
    transpose(&cols, nv)
}

/// The analytical derivatives of [`rnea_derivatives`], on the inputs of the graph.
pub(crate) struct Analytical {
    /// `∂τ/∂q`.
    pub d_tau_dq: Vec<ExprId>,
    /// `∂τ/∂q̇`.
    pub d_tau_dqd: Vec<ExprId>,
    /// `∂g/∂q` (the same at `q̇ = q̈ = 0`).
    pub gravity_derivative: Vec<ExprId>,
    /// `τ` from the same recursion (its composite wrenches), the armature included.
    pub inverse_dynamics: Vec<ExprId>,
}

/// [`Analytical`] for a fixed-base robot without mimic joints (`None` otherwise): for each
/// matrix the cheapest of the given pair frames.
pub(crate) fn analytical(
    g: &mut ExprGraph,
    robot: &Robot,
    pair_frames: &[PairFrame],
) -> Option<Analytical> {
    if robot.base.floating || !mimic::Coupling::new(robot).is_identity() {
        return None;
    }
    let frames = frames::joint_frames(robot);
    let n = frames.joints.len();
    let q: Vec<ExprId> = (0..n).map(|i| g.input(input(Q, i))).collect();
    let qd: Vec<ExprId> = (0..n).map(|i| g.input(input(QD, i))).collect();
    let qdd: Vec<ExprId> = (0..n).map(|i| g.input(input(QDD, i))).collect();
    let motions = super::joint_motions(g, &frames, &q);
    let gravity = super::parameters::gravity(g, &frames);
    let base = base::base_motion(g, false, &[], &[], gravity);
    let zeros = vec![g.zero(); n];
    let cost = |g: &ExprGraph, x: &[ExprId], y: &[ExprId]| g.op_counts(&[x, y].concat()).total();
    let mut best: Option<Analytical> = None;
    for &frame in pair_frames {
        let (d_tau_dq, d_tau_dqd, mut tau) =
            rnea_derivatives::rnea_derivatives(g, &motions, &base, &qd, &qdd, frame);
        let (gravity_derivative, _, _) =
            rnea_derivatives::rnea_derivatives(g, &motions, &base, &zeros, &zeros, frame);
        for (i, f) in frames.joints.iter().enumerate() {
            if f.armature != 0.0 {
                let t = g.cmul(f.armature, qdd[i]);
                tau[i] = g.add(tau[i], t);
            }
        }
        let x = Analytical {
            d_tau_dq,
            d_tau_dqd,
            gravity_derivative,
            inverse_dynamics: tau,
        };
        best = Some(match best {
            None => x,
            Some(b) => {
                let mut b = b;
                if cost(g, &x.d_tau_dq, &x.d_tau_dqd) < cost(g, &b.d_tau_dq, &b.d_tau_dqd) {
                    (b.d_tau_dq, b.d_tau_dqd) = (x.d_tau_dq, x.d_tau_dqd);
                }
                if g.op_counts(&x.gravity_derivative).total()
                    < g.op_counts(&b.gravity_derivative).total()
                {
                    b.gravity_derivative = x.gravity_derivative;
                }
                b
            }
        });
    }
    best
}

/// `−A B` for `A`, `B` nv×nv row-major.
fn neg_product(g: &mut ExprGraph, nv: usize, a: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let mut out = Vec::with_capacity(nv * nv);
    for i in 0..nv {
        for j in 0..nv {
            let col: Vec<ExprId> = (0..nv).map(|k| b[k * nv + j]).collect();
            let x = g.dot(&a[i * nv..(i + 1) * nv], &col);
            out.push(g.neg(x));
        }
    }
    out
}

/// Expands the derivatives of `d`, the dynamics of `robot` (see the module docs).
pub fn expand_derivatives(d: &Dynamics, robot: &Robot) -> Derivatives {
    let nv = d.nv;
    let floating = d.nq != d.nv;
    let mut g = ExprGraph::new();
    let mut id = g.import(&d.graph, &d.inverse_dynamics);
    let gravity = g.import(&d.graph, &d.gravity);
    let fd = g.import(&d.graph, &d.forward_dynamics);
    let h = g.import(&d.graph, &d.mass_matrix_factor);
    let inv_d = g.import(&d.graph, &d.mass_matrix_inv_d);
    let seeds = tangent_seeds(&mut g, floating, d.dof);
    let mut d_tau_dq = tangent_jacobian(&mut g, &id, &seeds);
    let mut d_tau_dqd = partials(&mut g, &id, QD, nv);
    let mut gravity_derivative = tangent_jacobian(&mut g, &gravity, &seeds);
    // The analytical recursion where it applies, for each matrix the form of the pair with
    // the fewest operations (they share nodes), and for ∂g/∂q the fewer. Not on the
    // Lagrangian route: there every derivative is taken of the Lagrangian's own expressions.
    let mut method = DerivativeMethod::default();
    let recursion = match d.method {
        super::Method::NewtonEuler => {
            analytical(&mut g, robot, &[PairFrame::Deeper, PairFrame::Ancestor])
        }
        super::Method::Lagrangian => None,
    };
    if let Some(a) = recursion {
        let cost =
            |g: &ExprGraph, x: &[ExprId], y: &[ExprId]| g.op_counts(&[x, y].concat()).total();
        let forms = [
            (&d_tau_dq, &d_tau_dqd),
            (&a.d_tau_dq, &d_tau_dqd),
            (&d_tau_dq, &a.d_tau_dqd),
            (&a.d_tau_dq, &a.d_tau_dqd),
        ];
        let best = (0..forms.len())
            .min_by_key(|&k| cost(&g, forms[k].0, forms[k].1))
            .unwrap_or(0);
        (d_tau_dq, d_tau_dqd) = (forms[best].0.to_vec(), forms[best].1.to_vec());
        method.d_tau_dq_analytical = best & 1 == 1;
        method.d_tau_dqd_analytical = best & 2 == 2;
        if g.op_counts(&a.gravity_derivative).total() < g.op_counts(&gravity_derivative).total() {
            gravity_derivative = a.gravity_derivative;
            method.gravity_derivative_analytical = true;
        }
        // τ for the value-with-derivatives forms: read off the recursion where that is cheaper.
        let with = |g: &ExprGraph, tau: &[ExprId]| {
            g.op_counts(&[tau, &d_tau_dq[..], &d_tau_dqd[..]].concat())
                .total()
        };
        if with(&g, &a.inverse_dynamics) < with(&g, &id) {
            id = a.inverse_dynamics;
        }
    }
    // M⁻¹: columns M⁻¹ e_j, or `L⁻¹ D⁻¹ L⁻ᵀ`, the cheaper.
    let by_columns = ldlt::ltdl_inverse_by_columns(&mut g, &h, &inv_d);
    let by_inverse = ldlt::ltdl_inverse(&mut g, &h, &inv_d);
    let mass_matrix_inverse = super::cheaper(&g, by_columns, by_inverse);
    // ν̇ := FD(q, ν, τ) in the partials of inverse dynamics, then −M⁻¹ ·.
    let at_fd = |g: &mut ExprGraph, m: &[ExprId]| {
        g.substitute(m, &|x: Input| {
            (x.group == QDD).then(|| fd[x.index as usize])
        })
    };
    let dq = at_fd(&mut g, &d_tau_dq);
    let dqd = at_fd(&mut g, &d_tau_dqd);
    // −M⁻¹ B by solves with the factor, or by the product with M⁻¹ (which the forward
    // dynamics derivatives return anyway): the fewer operations.
    let by_solve = [
        neg_solve(&mut g, &h, &inv_d, &dq),
        neg_solve(&mut g, &h, &inv_d, &dqd),
    ];
    let by_product = [
        neg_product(&mut g, nv, &mass_matrix_inverse, &dq),
        neg_product(&mut g, nv, &mass_matrix_inverse, &dqd),
    ];
    let cost = |g: &ExprGraph, x: &[Vec<ExprId>; 2]| {
        g.op_counts(&[&x[0][..], &x[1][..], &mass_matrix_inverse[..]].concat())
            .total()
    };
    method.by_product = cost(&g, &by_product) < cost(&g, &by_solve);
    let [d_qdd_dq, d_qdd_dqd] = if method.by_product {
        by_product
    } else {
        by_solve
    };
    // Sums that cancel to zero (a tree's independent branches, symmetric terms) removed,
    // checked numerically as in `expand`.
    let roots: [&[ExprId]; 8] = [
        &d_tau_dq,
        &d_tau_dqd,
        &gravity_derivative,
        &mass_matrix_inverse,
        &d_qdd_dq,
        &d_qdd_dqd,
        &id,
        &fd,
    ];
    let (graph, pruned) = super::prune_checked(g, &roots);
    let mut pruned = pruned.into_iter();
    let mut next = || pruned.next().unwrap_or_default();
    Derivatives {
        nv,
        d_tau_dq: next(),
        d_tau_dqd: next(),
        gravity_derivative: next(),
        mass_matrix_inverse: next(),
        d_qdd_dq: next(),
        d_qdd_dqd: next(),
        inverse_dynamics: next(),
        forward_dynamics: next(),
        graph,
        method,
    }
}
