//! The gravity forces `g(q)` (Modern Robotics §8.3.3).

use crate::inverse_dynamics::inverse_dynamics;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `g(q) = ∂P/∂q = ID(q, 0, 0, g, F_tip = 0)`, the book's `GravityForces`; `gravity` is the
/// gravity vector in {0}. On a floating base the first six entries are the wrench, in the
/// base frame, that holds the whole robot up against gravity (the derivative of P along the
/// base's body twist).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn gravity_forces(robot: &Robot, q: &[f64], gravity: &Vector3<f64>) -> DVector<f64> {
    let zero = vec![0.0; robot.nv()];
    inverse_dynamics(robot, q, &zero, &zero, gravity, &Vector6::zeros())
}
