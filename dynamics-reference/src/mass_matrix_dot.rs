//! The time derivative of the mass matrix in closed form (Modern Robotics §8.4, Exercise 8.7),
//! on a kinematic tree and a floating base.

use crate::base::{joint_offset, joint_part};
use crate::check;
use crate::coupling::Coupled;
use crate::frames::TreeFrames;
use dynamics_model::lie::ad;
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix6};

/// `Ṁ(q, ν) = dM/dt = Σ_k ∂M/∂θ_k θ̇_k`, from the closed form of the dynamics (§8.4),
/// `M = AᵀLᵀGLA`, over the bodies of the robot (the links, and on a floating base the base as
/// body 0 before them), with
///
/// - `A` (6·bodies × nv): block (i, i) = `A_i` for link i, and the 6×6 identity for the base
///   (its velocity is the base twist itself);
/// - `G = blockdiag(G_b, G_1, …, G_n)` (`G_b` only on a floating base);
/// - `W(q)` with the blocks `[Ad_{T_{i,λ(i)}}]` at (i, λ(i)) (λ(i) = the base body for a root
///   link on a floating base; none for a root link on a fixed base);
/// - `L = (1 − W)⁻¹ = 1 + W + W² + ⋯` (W is nilpotent): block (i, j) is
///   `[Ad_{T_{ij}}] = [Ad_{T_{i,λ(i)}}] ⋯ [Ad_{T_{k,j}}]` when j is on the path from the base to
///   i, and zero otherwise; built here by products along the parents;
/// - `[ad_{Aθ̇}] = blockdiag(0, [ad_{A_1 θ̇_1}], …, [ad_{A_n θ̇_n}])`.
///
/// Since `d/dt [Ad_{T_{i,λ(i)}}] = −[ad_{A_i θ̇_i}] [Ad_{T_{i,λ(i)}}]`, `Ẇ = −[ad_{Aθ̇}] W` and
/// `L̇ = L Ẇ L = −L [ad_{Aθ̇}] W L`, hence (Exercise 8.7)
/// ```text
/// Ṁ = −( AᵀLᵀWᵀ[ad_{Aθ̇}]ᵀLᵀ G L A  +  AᵀLᵀ G L [ad_{Aθ̇}] W L A )
/// ```
/// On a floating base M depends on θ only (every body is seen from the base frame), so only
/// the joint rates θ̇ of ν enter. Ṁ is linear in ν, so `Ṁ(q, e_k) = ∂M/∂θ_k` exactly (see
/// [`crate::mass_matrix_partials`]).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn mass_matrix_dot(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    check::velocity(robot, "qd", qd);
    if let Some(c) = Coupled::of(robot) {
        check::configuration(robot, "q", q);
        return c.matrix(&mass_matrix_dot(&c.physical, &c.q(q), &c.v(qd)));
    }
    let n = robot.dof();
    let frames = TreeFrames::new(robot, q);
    let a = &frames.a;
    let ad_t_i_parent = &frames.ad_t_i_parent;
    let g_list = robot.g_list();
    let theta_d = joint_part(robot, qd);
    let off = joint_offset(robot);
    // Bodies: the base as body 0 on a floating base (b0 = 1), then link i as body b0 + i.
    let b0 = usize::from(robot.base.floating);
    let bodies = n + b0;
    let body_parent = |k: usize| -> Option<usize> {
        if k < b0 {
            return None; // the base body hangs from the world
        }
        match frames.parent[k - b0] {
            Some(p) => Some(b0 + p),
            None if robot.base.floating => Some(0),
            None => None,
        }
    };
    let size = 6 * bodies;
    let nv = robot.nv();

    let mut a_mat = DMatrix::zeros(size, nv); // A
    let mut g_mat = DMatrix::zeros(size, size); // G
    let mut w = DMatrix::zeros(size, size); // W
    let mut ad_a_qd = DMatrix::zeros(size, size); // [ad_{Aθ̇}]
    if robot.base.floating {
        a_mat
            .view_mut((0, 0), (6, 6))
            .copy_from(&Matrix6::<f64>::identity());
        g_mat
            .view_mut((0, 0), (6, 6))
            .copy_from(&robot.base.inertia.0);
    }
    for i in 0..n {
        let k = 6 * (b0 + i);
        a_mat.view_mut((k, off + i), (6, 1)).copy_from(&a[i]);
        g_mat.view_mut((k, k), (6, 6)).copy_from(&g_list[i]);
        ad_a_qd
            .view_mut((k, k), (6, 6))
            .copy_from(&ad(&(a[i] * theta_d[i])));
        if let Some(p) = body_parent(b0 + i) {
            w.view_mut((k, 6 * p), (6, 6)).copy_from(&ad_t_i_parent[i]);
        }
    }

    // L = (1 − W)⁻¹: block (i, j) = [Ad_{T_{ij}}] = W_{i,λ(i)} L_{λ(i),j} when j is on the
    // path to i (below[i]), zero otherwise.
    let mut l = DMatrix::zeros(size, size);
    for j in 0..bodies {
        let mut below = vec![false; bodies];
        below[j] = true;
        l.view_mut((6 * j, 6 * j), (6, 6))
            .copy_from(&Matrix6::<f64>::identity());
        for i in j + 1..bodies {
            let Some(p) = body_parent(i) else { continue };
            if below[p] {
                below[i] = true;
                let ad_t_pj: Matrix6<f64> = l.fixed_view::<6, 6>(6 * p, 6 * j).into_owned();
                let ad_t_ij = ad_t_i_parent[i - b0] * ad_t_pj;
                l.view_mut((6 * i, 6 * j), (6, 6)).copy_from(&ad_t_ij);
            }
        }
    }

    let la = &l * &a_mat; // L A
    let term1 = la.transpose() * w.transpose() * ad_a_qd.transpose() * l.transpose() * &g_mat * &la;
    let term2 = la.transpose() * &g_mat * &l * &ad_a_qd * &w * &la;
    -(term1 + term2)
}
