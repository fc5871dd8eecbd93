//! The end effector's wrench in the joint space, and the dynamics in the task space (Modern
//! Robotics §8.3.3, §8.6), on one graph that combines the dynamics ([`super::Dynamics`]) and
//! the end effector's kinematics ([`super::kinematics::Kinematics`]), imported with
//! [`ExprGraph::import`] so that their common nodes (inputs, `sin q_i`, …) are shared.
//!
//! With `F_tip = (m, f)` the wrench the end effector applies to the environment, in its own
//! frame, and `J_b` its body Jacobian (6×nv):
//! ```text
//! τ_tip = J_bᵀ F_tip                                   (end_effector_forces, §8.3.3)
//! τ     = M ν̇ + h + J_bᵀ F_tip                         (inverse_dynamics_with_tip)
//!                                   (or Newton–Euler with F_{n+1} = F_tip, if cheaper)
//! ν̇     = M⁻¹ (τ − h − J_bᵀ F_tip)                     (forward_dynamics_with_tip)
//! ```
//! and, for the end effector's body acceleration `V̇ = J_b ν̇ + J̇_b ν`,
//! ```text
//! F = Λ V̇ + η,   Λ = (J_b M⁻¹ J_bᵀ)⁻¹,   η = Λ (J_b M⁻¹ h − J̇_b ν)          (§8.6)
//! ```
//! which reduces to the book's `Λ = J_b⁻ᵀ M J_b⁻¹`, `η = J_b⁻ᵀ h − Λ J̇_b J_b⁻¹ V` for a
//! square `J_b` and holds for redundant arms too. No explicit inverse of M: `X = M⁻¹ J_bᵀ` by
//! the unrolled factorisation `M = Lᵀ D L` ([`super::ldlt::ltdl_factor`]); `A = J_b X` is
//! factorised as `A = L D Lᵀ` ([`super::ldlt::ldlt_factor`], rows in the order
//! `ω₁ ω₂ ω₃ v₁ v₂ v₃`, no pivoting) and `Λ = A⁻¹` solved column by column from it, `η` by one
//! more solve. `A`'s pivots `D_k` and diagonal `A_kk` are outputs too: the generated code
//! returns `None` when some `D_k ≤ √ε · A_kk` (a singular or nearly singular `J_b`), which is
//! also how `dynamics_reference::task_space_mass_matrix` decides.

use super::kinematics::Kinematics;
use super::{input, ldlt, Dynamics, QD, TAU};
use crate::expr::{ExprGraph, ExprId};

/// Input group of the tip wrench `F_tip = (m, f)`.
pub const F_TIP: u8 = 4;

/// The outputs, on their own graph.
#[derive(Clone, Debug)]
pub struct TaskSpace {
    /// The combined graph.
    pub graph: ExprGraph,
    /// `J_bᵀ F_tip`, nv.
    pub end_effector_forces: Vec<ExprId>,
    /// `M ν̇ + h + J_bᵀ F_tip`, nv.
    pub inverse_dynamics_with_tip: Vec<ExprId>,
    /// `M⁻¹ (τ − h − J_bᵀ F_tip)`, nv.
    pub forward_dynamics_with_tip: Vec<ExprId>,
    /// `Λ`, 6×6 row-major; empty when nv < 6 (then `A` is singular).
    pub mass_matrix: Vec<ExprId>,
    /// `η`, 6; empty when nv < 6.
    pub bias: Vec<ExprId>,
    /// `(D_k, A_kk)` for k = 0..6: `Λ` and `η` are valid where every `D_k > √ε · A_kk`;
    /// empty when nv < 6.
    pub pivots: Vec<(ExprId, ExprId)>,
}

/// Expands the tip-wrench and task-space functions from the robot's dynamics and
/// kinematics.
pub fn expand_task_space(d: &Dynamics, k: &Kinematics) -> TaskSpace {
    let nv = d.nv;
    let mut g = ExprGraph::new();
    let m = g.import(&d.graph, &d.mass_matrix);
    let h = g.import(&d.graph, &d.bias);
    let id = g.import(&d.graph, &d.inverse_dynamics);
    let jb = g.import(&k.graph, &k.end_effector.jacobian_body);
    let jb_dot = g.import(&k.graph, &k.jacobian_body_dot);
    let f: Vec<ExprId> = (0..6).map(|i| g.input(input(F_TIP, i))).collect();
    let tau: Vec<ExprId> = (0..nv).map(|i| g.input(input(TAU, i))).collect();
    let v: Vec<ExprId> = (0..nv).map(|i| g.input(input(QD, i))).collect();
    // J_bᵀ F_tip.
    let tip: Vec<ExprId> = (0..nv)
        .map(|j| {
            let col: Vec<ExprId> = (0..6).map(|r| jb[r * nv + j]).collect();
            g.dot(&col, &f)
        })
        .collect();
    let mut id_tip: Vec<ExprId> = (0..nv).map(|i| g.add(id[i], tip[i])).collect();
    let mut rhs: Vec<ExprId> = (0..nv)
        .map(|i| {
            let t = g.sub(tau[i], h[i]);
            g.sub(t, tip[i])
        })
        .collect();
    // Newton–Euler with F_tip entered at the end effector's link, where expanded: the
    // backward pass carries it along the rotations it makes anyway (rand7: 810 → 591
    // multiplications for `inverse_dynamics_with_tip`). The cheaper of the two.
    if !d.inverse_dynamics_with_tip.is_empty() {
        let by_rnea = g.import(&d.graph, &d.inverse_dynamics_with_tip);
        id_tip = super::cheaper(&g, id_tip, by_rnea);
        let h_tip = g.import(&d.graph, &d.bias_with_tip);
        let by_rnea: Vec<ExprId> = (0..nv).map(|i| g.sub(tau[i], h_tip[i])).collect();
        rhs = super::cheaper(&g, rhs, by_rnea);
    }
    let (lm, inv_dm) = ldlt::ltdl_factor(&mut g, &m);
    let fd_tip = ldlt::ltdl_apply(&mut g, &lm, &inv_dm, &rhs);
    let mut out = TaskSpace {
        graph: ExprGraph::new(),
        end_effector_forces: tip,
        inverse_dynamics_with_tip: id_tip,
        forward_dynamics_with_tip: fd_tip,
        mass_matrix: Vec::new(),
        bias: Vec::new(),
        pivots: Vec::new(),
    };
    if nv >= 6 {
        // X = M⁻¹ J_bᵀ, column r from row r of J_b.
        let x: Vec<Vec<ExprId>> = jb
            .chunks(nv)
            .map(|row| ldlt::ltdl_apply(&mut g, &lm, &inv_dm, row))
            .collect();
        // A = J_b X, symmetric: the lower triangle, mirrored.
        let zero = g.zero();
        let mut a = vec![zero; 36];
        for r in 0..6 {
            for s in 0..=r {
                let e = g.dot(&jb[r * nv..(r + 1) * nv], &x[s]);
                a[r * 6 + s] = e;
                a[s * 6 + r] = e;
            }
        }
        let (la, da, inv_da) = ldlt::ldlt_factor(&mut g, &a);
        let mut lambda = vec![zero; 36];
        for c in 0..6 {
            let mut e = vec![zero; 6];
            e[c] = g.one();
            let col = ldlt::ldlt_apply(&mut g, &la, &inv_da, &e);
            for r in 0..6 {
                lambda[r * 6 + c] = col[r];
            }
        }
        // u = J_b M⁻¹ h − J̇_b ν = Xᵀ h − J̇_b ν, η = A⁻¹ u.
        let u: Vec<ExprId> = (0..6)
            .map(|r| {
                let xh = g.dot(&x[r], &h);
                let jd = g.dot(&jb_dot[r * nv..(r + 1) * nv], &v);
                g.sub(xh, jd)
            })
            .collect();
        out.bias = ldlt::ldlt_apply(&mut g, &la, &inv_da, &u);
        out.mass_matrix = lambda;
        out.pivots = (0..6).map(|k| (da[k], a[k * 6 + k])).collect();
    }
    out.graph = g;
    out
}
