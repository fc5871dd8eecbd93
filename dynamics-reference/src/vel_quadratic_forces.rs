//! The Coriolis and centripetal torques `c(θ, θ̇)` (Modern Robotics §8.3.3).

use crate::inverse_dynamics::inverse_dynamics;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `c(θ, θ̇) = C(θ, θ̇) θ̇ = ID(θ, θ̇, 0, g = 0, F_tip = 0)`, the book's `VelQuadraticForces`.
///
/// # Panics
/// If `q` or `qd` does not have `robot.dof()` entries.
pub fn vel_quadratic_forces(robot: &Robot, q: &[f64], qd: &[f64]) -> DVector<f64> {
    let zero = vec![0.0; robot.dof()];
    inverse_dynamics(robot, q, qd, &zero, &Vector3::zeros(), &Vector6::zeros())
}
