//! The rate of the configuration, `q̇` from `(q, ν)`: the kinematics of a floating base.

use crate::base::quaternion_rotation;
use crate::check;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3};

/// `q̇(q, ν)`, nq entries: `θ̇` itself on a fixed base; on a floating base, with
/// `ν = (ω_b, v_b, θ̇)` and `quat = (u, w)` (vector part u, scalar last),
/// ```text
/// ṗ = R v_b,    quaṫ = ½ quat ⊗ (ω_b, 0) = ½ (w ω_b + u × ω_b, −u · ω_b),    θ̇
/// ```
/// `R` comes from the normalised quaternion; the quaternion rate is taken from `quat` as
/// given, so that it keeps `|quat|` constant and `quat/|quat|` follows `Ṙ = R [ω_b]` exactly.
///
/// Integrating this (e.g. [`crate::forward_dynamics_trajectory`]) lets `|quat|` drift by the
/// integration error; every function here normalises it, so nothing else changes.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn configuration_rate(robot: &Robot, q: &[f64], qd: &[f64]) -> DVector<f64> {
    check::configuration(robot, "q", q);
    check::velocity(robot, "qd", qd);
    if !robot.base.floating {
        return DVector::from_column_slice(qd);
    }
    let r = quaternion_rotation(&[q[3], q[4], q[5], q[6]]);
    let (u, w) = (Vector3::new(q[3], q[4], q[5]), q[6]);
    let omega = Vector3::new(qd[0], qd[1], qd[2]);
    let v_b = Vector3::new(qd[3], qd[4], qd[5]);
    let p_dot = r * v_b;
    let u_dot = (omega * w + u.cross(&omega)) * 0.5;
    let w_dot = -0.5 * u.dot(&omega);
    let mut q_dot = DVector::zeros(robot.nq());
    q_dot.rows_mut(0, 3).copy_from(&p_dot);
    q_dot.rows_mut(3, 3).copy_from(&u_dot);
    q_dot[6] = w_dot;
    q_dot
        .rows_mut(7, robot.n_coordinates())
        .copy_from_slice(&qd[6..]);
    q_dot
}
