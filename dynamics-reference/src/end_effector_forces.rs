//! The joint torques that balance a tip wrench (Modern Robotics §5.2 and §8.3.3).

use crate::jacobian_body::jacobian_body;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector6};

/// `J_b(q)ᵀ F_tip`, the joint torques needed to apply the wrench `F_tip = (m, f)` (in {n+1})
/// to the environment; the book's `EndEffectorForces`, which computes the same as
/// `ID(q, 0, 0, g = 0, F_tip)`. Computed here from the body Jacobian, so that comparing it
/// with [`crate::inverse_dynamics`] checks one against the other. Joints off the end
/// effector's path get zero; on a floating base the first six entries are the wrench on the
/// base, in the base frame.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn end_effector_forces(robot: &Robot, q: &[f64], f_tip: &Vector6<f64>) -> DVector<f64> {
    jacobian_body(robot, q).transpose() * f_tip
}
