//! The gravity torques `g(θ)` (Modern Robotics §8.3.3).

use crate::inverse_dynamics::inverse_dynamics;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `g(θ) = ∂P/∂θ = ID(θ, 0, 0, g, F_tip = 0)`, the book's `GravityForces`; `gravity` is the
/// gravity vector in {0}.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn gravity_forces(robot: &Robot, q: &[f64], gravity: &Vector3<f64>) -> DVector<f64> {
    let zero = vec![0.0; robot.dof()];
    inverse_dynamics(robot, q, &zero, &zero, gravity, &Vector6::zeros())
}
