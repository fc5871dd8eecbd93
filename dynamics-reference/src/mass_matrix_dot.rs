//! The time derivative of the mass matrix in closed form (Modern Robotics §8.4, Exercise 8.7).

use crate::chain::ChainFrames;
use crate::check;
use dynamics_model::lie::ad;
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix6};

/// `Ṁ(θ, θ̇) = dM/dt = Σ_k ∂M/∂θ_k θ̇_k`, from the closed form of the dynamics (§8.4),
/// `M = AᵀLᵀGLA`, with
///
/// - `A = blockdiag(A_1, …, A_n)` (6n×n), the screw axes in the link frames;
/// - `G = blockdiag(G_1, …, G_n)` (6n×6n);
/// - `W(θ)` (6n×6n) with the blocks `[Ad_{T_{i,i−1}}]` on the block sub-diagonal (i = 2..n);
/// - `L = (1 − W)⁻¹ = 1 + W + ⋯ + W^{n−1}` (W is nilpotent): block (i, j) is
///   `[Ad_{T_{ij}}] = [Ad_{T_{i,i−1}}] ⋯ [Ad_{T_{j+1,j}}]` for i ≥ j, built here by products;
/// - `[ad_{Aθ̇}] = blockdiag([ad_{A_1 θ̇_1}], …, [ad_{A_n θ̇_n}])`.
///
/// Since `d/dt [Ad_{T_{i,i−1}}] = −[ad_{A_i θ̇_i}] [Ad_{T_{i,i−1}}]`, `Ẇ = −[ad_{Aθ̇}] W` and
/// `L̇ = L Ẇ L = −L [ad_{Aθ̇}] W L`, hence (Exercise 8.7)
/// ```text
/// Ṁ = −( AᵀLᵀWᵀ[ad_{Aθ̇}]ᵀLᵀ G L A  +  AᵀLᵀ G L [ad_{Aθ̇}] W L A )
/// ```
/// Ṁ is linear in θ̇, so `Ṁ(θ, e_k) = ∂M/∂θ_k` exactly (see [`crate::mass_matrix_partials`]).
///
/// # Panics
/// If `q` or `qd` does not have `robot.dof()` entries.
pub fn mass_matrix_dot(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    check::joint_vector(robot, "qd", qd);
    let n = robot.dof();
    let chain = ChainFrames::new(robot, q);
    let a = &chain.a;
    let ad_t_i_im1 = &chain.ad_t_i_im1;
    let g_list = robot.g_list();
    let size = 6 * n;

    let mut a_mat = DMatrix::zeros(size, n); // A
    let mut g_mat = DMatrix::zeros(size, size); // G
    let mut w = DMatrix::zeros(size, size); // W
    let mut ad_a_qd = DMatrix::zeros(size, size); // [ad_{Aθ̇}]
    for i in 0..n {
        a_mat.view_mut((6 * i, i), (6, 1)).copy_from(&a[i]);
        g_mat.view_mut((6 * i, 6 * i), (6, 6)).copy_from(&g_list[i]);
        ad_a_qd
            .view_mut((6 * i, 6 * i), (6, 6))
            .copy_from(&ad(&(a[i] * qd[i])));
        if i > 0 {
            w.view_mut((6 * i, 6 * (i - 1)), (6, 6))
                .copy_from(&ad_t_i_im1[i]);
        }
    }

    // L = (1 − W)⁻¹, block (i, j) = [Ad_{T_{ij}}] for i ≥ j.
    let mut l = DMatrix::zeros(size, size);
    for j in 0..n {
        let mut ad_t_ij = Matrix6::identity();
        l.view_mut((6 * j, 6 * j), (6, 6)).copy_from(&ad_t_ij);
        for i in j + 1..n {
            ad_t_ij = ad_t_i_im1[i] * ad_t_ij;
            l.view_mut((6 * i, 6 * j), (6, 6)).copy_from(&ad_t_ij);
        }
    }

    let la = &l * &a_mat; // L A
    let term1 = la.transpose() * w.transpose() * ad_a_qd.transpose() * l.transpose() * &g_mat * &la;
    let term2 = la.transpose() * &g_mat * &l * &ad_a_qd * &w * &la;
    -(term1 + term2)
}
