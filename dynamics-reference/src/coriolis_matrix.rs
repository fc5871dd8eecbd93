//! The Coriolis matrix from the Christoffel symbols of the mass matrix (Modern Robotics §8.1.2).

use crate::check;
use crate::mass_matrix_dot::mass_matrix_dot;
use dynamics_model::Robot;
use nalgebra::DMatrix;

/// `∂M/∂θ_k` for k = 1..n (0-based), exactly: `∂M/∂θ_k = Ṁ(θ, e_k)` by the closed form of
/// [`mass_matrix_dot`] (Ṁ is linear in θ̇). No finite differences.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn mass_matrix_partials(robot: &Robot, q: &[f64]) -> Vec<DMatrix<f64>> {
    check::joint_vector(robot, "q", q);
    let n = robot.dof();
    (0..n)
        .map(|k| {
            let mut e_k = vec![0.0; n];
            e_k[k] = 1.0;
            mass_matrix_dot(robot, q, &e_k)
        })
        .collect()
}

/// `C(θ, θ̇)` with the Christoffel symbols of the first kind:
/// ```text
/// C_ij = Σ_k Γ_ijk θ̇_k,    Γ_ijk = ½ (∂M_ij/∂θ_k + ∂M_ik/∂θ_j − ∂M_jk/∂θ_i)
/// ```
/// With this choice `c(θ, θ̇) = C θ̇` and `Ṁ − 2C` is skew-symmetric (§8.1.2, Proposition 8.1).
///
/// # Panics
/// If `q` or `qd` does not have `robot.dof()` entries.
pub fn coriolis_matrix(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    check::joint_vector(robot, "qd", qd);
    let n = robot.dof();
    let dm = mass_matrix_partials(robot, q); // dm[k] = ∂M/∂θ_k
    let mut c = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let gamma_ijk = 0.5 * (dm[k][(i, j)] + dm[j][(i, k)] - dm[i][(j, k)]);
                c[(i, j)] += gamma_ijk * qd[k];
            }
        }
    }
    c
}
