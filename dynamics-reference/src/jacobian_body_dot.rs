//! The time derivative of the body Jacobian of a frame, column by column from the Lie bracket
//! (Modern Robotics Exercise 8.6(b)), on a kinematic tree and a floating base.

use crate::base::joint_offset;
use crate::check;
use crate::coupling::Coupled;
use crate::jacobian_body::frame_jacobian_body;
use dynamics_model::lie::ad;
use dynamics_model::{Frame, Robot};
use nalgebra::{DMatrix, Vector6};

/// [`frame_jacobian_body_dot`] of the end effector: `J̇_b(q, ν)`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn jacobian_body_dot(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    frame_jacobian_body_dot(robot, &robot.end_effector, q, qd)
}

/// `J̇_b(q, ν) = dJ_b/dt`, 6×nv, the rate of the body Jacobian of
/// [`crate::frame_jacobian_body`] while the robot moves with ν (so that the frame's body
/// acceleration is `V̇_b = J_b ν̇ + J̇_b ν`).
///
/// Column i of `J_b` (joint i on the path to the frame) depends only on the joints after it on
/// that path, between it and the frame (Exercise 8.6(b)):
/// ```text
/// ∂J_b,i/∂θ_j = [ad_{J_b,i}] J_b,j    for j after i on the path,   0 otherwise
/// J̇_b,i = Σ_{j after i} [ad_{J_b,i}] J_b,j θ̇_j
/// ```
/// Columns of joints off the path stay zero.
///
/// Floating base: the joint columns do not depend on the base pose (the body Jacobian is seen
/// from the frame itself), and the six base columns `[Ad_{T_{bf}⁻¹}]` change with the frame's
/// pose in the base frame: `Ṫ_{bf} = T_{bf} [V_rel]`, `V_rel = Σ_{j on the path} J_b,j θ̇_j`, so
/// `d/dt [Ad_{T_{bf}⁻¹}] = −[ad_{V_rel}] [Ad_{T_{bf}⁻¹}]`. The base counts as joints before every
/// joint:
/// ```text
/// J̇_b,k = [ad_{J_b,k}] V_rel = −[ad_{V_rel}] J_b,k            (k = 0..6, base)
/// ```
/// This is `dJ_b/dt` along [`crate::configuration_rate`].
///
/// Mimic joints: `J_b = J_b,phys J` with constant J, so `J̇_b = J̇_b,phys(q_phys, J ν) J`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn frame_jacobian_body_dot(
    robot: &Robot,
    frame: &Frame,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    check::configuration(robot, "q", q);
    check::velocity(robot, "qd", qd);
    if let Some(c) = Coupled::of(robot) {
        return c.columns(&frame_jacobian_body_dot(
            &c.physical,
            frame,
            &c.q(q),
            &c.v(qd),
        ));
    }
    let j_b = frame_jacobian_body(robot, frame, q);
    let col = |k: usize| -> Vector6<f64> { j_b.fixed_view::<6, 1>(0, k).into_owned() };
    let off = joint_offset(robot);
    let mut j_dot = DMatrix::zeros(6, robot.nv());

    let path = robot.frame_path(frame);
    for (l, &i) in path.iter().enumerate() {
        let ad_j_bi = ad(&col(off + i));
        let mut d = Vector6::zeros();
        for &j in &path[l + 1..] {
            d += ad_j_bi * col(off + j) * qd[off + j];
        }
        j_dot.column_mut(off + i).copy_from(&d);
    }

    // Base columns: [ad_{J_b,k}] V_rel, V_rel the frame's body twist relative to the base.
    let mut v_rel = Vector6::zeros();
    for &j in &path {
        v_rel += col(off + j) * qd[off + j];
    }
    for k in 0..off {
        j_dot.column_mut(k).copy_from(&(ad(&col(k)) * v_rel));
    }
    j_dot
}
