//! The mass matrix by the composite-rigid-body algorithm (CRBA), from the quantities of the
//! Newton–Euler recursion (Modern Robotics §8.3.2 and §8.4).

use crate::chain::ChainFrames;
use dynamics_model::Robot;
use nalgebra::DMatrix;

/// `M(θ)`, the n×n joint-space mass matrix, by the composite-rigid-body algorithm.
///
/// Column j of `M` is the torque `ID(θ, 0, e_j)` with no gravity and no tip wrench: a unit
/// acceleration of joint j accelerates the links j..n rigidly, `V̇_k = [Ad_{T_{kj}}] A_j`. Their
/// inertias, gathered in frame {i}, form the composite inertia
/// ```text
/// Ic_n = G_n,     Ic_i = G_i + [Ad_{T_{i+1,i}}]ᵀ Ic_{i+1} [Ad_{T_{i+1,i}}]    (tip to root)
/// ```
/// so joint i's unit acceleration needs the wrench `F = Ic_i A_i` on the body i..n, and
/// carried down to each frame {j} (j ≤ i) by `F ← [Ad_{T_{j+1,j}}]ᵀ F`:
/// ```text
/// M_ii = A_iᵀ Ic_i A_i,    M_ji = M_ij = A_jᵀ [Ad_{T_{ij}}]ᵀ Ic_i A_i   (j < i)
/// ```
/// This equals `AᵀLᵀGLA` of the closed form (8.57) and the book's `MassMatrix` (n Newton–Euler
/// calls), and is symmetric by construction.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn mass_matrix(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    let n = robot.dof();
    let chain = ChainFrames::new(robot, q);
    let a = &chain.a;
    let ad_t_i_im1 = &chain.ad_t_i_im1;

    // ic[i] = Ic_{i+1}: composite inertia of links i+1..n in frame {i+1} (0-based i).
    let mut ic = robot.g_list();
    for i in (0..n.saturating_sub(1)).rev() {
        let x = &ad_t_i_im1[i + 1];
        let carried = x.transpose() * ic[i + 1] * x;
        ic[i] += carried;
    }

    let mut m = DMatrix::zeros(n, n);
    for i in 0..n {
        // f: the wrench on the composite body for a unit acceleration of joint i, in frame {i}.
        let mut f = ic[i] * a[i];
        m[(i, i)] = a[i].dot(&f);
        for j in (0..i).rev() {
            f = ad_t_i_im1[j + 1].transpose() * f;
            m[(i, j)] = a[j].dot(&f);
            m[(j, i)] = m[(i, j)];
        }
    }
    m
}
