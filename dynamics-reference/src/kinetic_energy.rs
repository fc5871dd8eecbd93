//! Kinetic energy of the robot (Modern Robotics §8.1).

use crate::mass_matrix::mass_matrix;
use dynamics_model::Robot;
use nalgebra::DVector;

/// `K(q, ν) = ½ νᵀ M(q) ν` (the base's kinetic energy included on a floating base, and the
/// rotors' `½ G_i² I_rotor,i θ̇_i²` through the armature on M's diagonal).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn kinetic_energy(robot: &Robot, q: &[f64], qd: &[f64]) -> f64 {
    crate::check::velocity(robot, "qd", qd);
    let qd = DVector::from_column_slice(qd);
    0.5 * qd.dot(&(mass_matrix(robot, q) * &qd))
}
