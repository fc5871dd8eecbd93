//! The Coriolis and centripetal forces `c(q, ν)` (Modern Robotics §8.3.3).

use crate::inverse_dynamics::inverse_dynamics;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `c(q, ν) = C(q, ν) ν = ID(q, ν, 0, g = 0, F_tip = 0)`, the book's `VelQuadraticForces`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn vel_quadratic_forces(robot: &Robot, q: &[f64], qd: &[f64]) -> DVector<f64> {
    let zero = vec![0.0; robot.nv()];
    inverse_dynamics(robot, q, qd, &zero, &Vector3::zeros(), &Vector6::zeros())
}
