//! The time derivative of the space Jacobian of a frame, column by column from the Lie
//! bracket (Modern Robotics Exercise 8.6(a)), on a kinematic tree and a floating base.

use crate::base::joint_offset;
use crate::check;
use crate::coupling::Coupled;
use crate::jacobian_space::frame_jacobian_space;
use dynamics_model::lie::ad;
use dynamics_model::{Frame, Robot};
use nalgebra::{DMatrix, Vector6};

/// [`frame_jacobian_space_dot`] of the end effector: `J̇_s(q, ν)`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn jacobian_space_dot(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    frame_jacobian_space_dot(robot, &robot.end_effector, q, qd)
}

/// `J̇_s(q, ν) = dJ_s/dt`, 6×nv, the rate of the space Jacobian of
/// [`crate::frame_jacobian_space`] while the robot moves with ν (so that the frame's spatial
/// acceleration is `V̇_s = J_s ν̇ + J̇_s ν`).
///
/// Column i of `J_s` (joint i on the path to the frame) depends only on the joints before it
/// on that path (Exercise 8.6(a)):
/// ```text
/// ∂J_s,i/∂θ_j = [ad_{J_s,j}] J_s,i    for j before i on the path,   0 otherwise
/// J̇_s,i = Σ_{j before i} [ad_{J_s,j}] J_s,i θ̇_j
/// ```
/// (the bracket `[J_s,j, J_s,i]`; the reversed order has the wrong sign). Columns of joints off
/// the path stay zero.
///
/// Floating base: `J_s = [Ad_{T_{0b}}] [1 | J_s^b(θ)]` with `J_s^b` the fixed-base Jacobian in
/// the base frame, and `Ṫ_{0b} = T_{0b} [ν_b]` gives `d/dt [Ad_{T_{0b}}] = [Ad_{T_{0b}}] [ad_{ν_b}]
/// = [ad_{V_b}] [Ad_{T_{0b}}]` with `V_b = [Ad_{T_{0b}}] ν_b = Σ_{k<6} J_s,k ν_k`, the base's
/// spatial twist. So the six base columns count as joints before every joint, among
/// themselves all at once:
/// ```text
/// J̇_s,k = [ad_{V_b}] J_s,k                                   (k = 0..6, base)
/// J̇_s,i = [ad_{V_b}] J_s,i + Σ_{j before i} [ad_{J_s,j}] J_s,i θ̇_j    (joint i)
/// ```
/// This is `dJ_s/dt` along [`crate::configuration_rate`] (`ṗ = R v_b`, `Ṙ = R [ω_b]`).
///
/// Mimic joints: `J_s = J_s,phys J` with constant J, so `J̇_s = J̇_s,phys(q_phys, J ν) J`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn frame_jacobian_space_dot(
    robot: &Robot,
    frame: &Frame,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    check::configuration(robot, "q", q);
    check::velocity(robot, "qd", qd);
    if let Some(c) = Coupled::of(robot) {
        return c.columns(&frame_jacobian_space_dot(
            &c.physical,
            frame,
            &c.q(q),
            &c.v(qd),
        ));
    }
    let j_s = frame_jacobian_space(robot, frame, q);
    let col = |k: usize| -> Vector6<f64> { j_s.fixed_view::<6, 1>(0, k).into_owned() };
    let off = joint_offset(robot);
    let mut j_dot = DMatrix::zeros(6, robot.nv());

    // The base's spatial twist V_b = Σ_k J_s,k ν_k (zero on a fixed base).
    let mut v_b = Vector6::zeros();
    for k in 0..off {
        v_b += col(k) * qd[k];
    }
    for k in 0..off {
        j_dot.column_mut(k).copy_from(&(ad(&v_b) * col(k)));
    }

    let path = robot.frame_path(frame);
    for (l, &i) in path.iter().enumerate() {
        let j_si = col(off + i);
        let mut d = ad(&v_b) * j_si;
        for &j in &path[..l] {
            d += ad(&col(off + j)) * j_si * qd[off + j];
        }
        j_dot.column_mut(off + i).copy_from(&d);
    }
    j_dot
}
