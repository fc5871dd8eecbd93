//! Kinetic energy of the chain (Modern Robotics §8.1).

use crate::mass_matrix::mass_matrix;
use dynamics_model::Robot;
use nalgebra::DVector;

/// `K(θ, θ̇) = ½ θ̇ᵀ M(θ) θ̇`.
///
/// # Panics
/// If `q` or `qd` does not have `robot.dof()` entries.
pub fn kinetic_energy(robot: &Robot, q: &[f64], qd: &[f64]) -> f64 {
    crate::check::joint_vector(robot, "qd", qd);
    let qd = DVector::from_column_slice(qd);
    0.5 * qd.dot(&(mass_matrix(robot, q) * &qd))
}
