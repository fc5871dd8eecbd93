//! Forward dynamics by solving the equations of motion (Modern Robotics §8.5), on a tree and
//! on a floating base.

use crate::error::ReferenceError;
use crate::inverse_dynamics::inverse_dynamics;
use crate::mass_matrix::mass_matrix;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `ν̇` from `M(q) ν̇ = τ − c(q, ν) − g(q) − J_b(q)ᵀ F_tip`, the book's `ForwardDynamics`
/// (on a floating base ν̇ = (ω̇_b, v̇_b, θ̈) and τ = (m_b, f_b, τ_θ), see the crate docs).
///
/// The right-hand side takes one Newton–Euler pass, `c + g + J_bᵀ F_tip = ID(q, ν, 0, g, F_tip)`;
/// `M` comes from [`mass_matrix`] (armature included) and is factorised by Cholesky,
/// `M = L Lᵀ`, and solved (never inverted). Friction is not included: pass
/// `τ − τ_friction` ([`crate::friction_forces`]) for a joint with friction. The book inverts `M` explicitly, so results differ from it at rounding level.
///
/// # Errors
/// [`ReferenceError::MassMatrixNotPositiveDefinite`] when the Cholesky factorisation fails.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` or `tau` not `robot.nv()`.
pub fn forward_dynamics(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    gravity: &Vector3<f64>,
    f_tip: &Vector6<f64>,
) -> Result<DVector<f64>, ReferenceError> {
    crate::check::velocity(robot, "tau", tau);
    let zero = vec![0.0; robot.nv()];
    let bias = inverse_dynamics(robot, q, qd, &zero, gravity, f_tip);
    let rhs = DVector::from_column_slice(tau) - bias;
    let m = mass_matrix(robot, q);
    match m.cholesky() {
        Some(chol) => Ok(chol.solve(&rhs)),
        None => Err(ReferenceError::MassMatrixNotPositiveDefinite {
            q: q.to_vec(),
            step: None,
        }),
    }
}
