//! The body Jacobian of a frame (Modern Robotics §5.1.3, the book's `JacobianBody`): the
//! end-effector frame {n+1} or a named frame, on a kinematic tree and a floating base.

use crate::base::{joint_offset, joint_values};
use crate::coupling::Coupled;
use crate::end_effector_pose::frame_pose_in_base;
use dynamics_model::lie::{adjoint, exp6, trans_inv};
use dynamics_model::{Frame, Robot};
use nalgebra::{DMatrix, Matrix4};

/// [`frame_jacobian_body`] of the end effector.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn jacobian_body(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    frame_jacobian_body(robot, &robot.end_effector, q)
}

/// `J_b(q)`, 6×nv, with columns in the frame {f} ({n+1} for the end effector), from the
/// body-frame screw axes `B_i = [Ad_{M⁻¹}] S_i` (M = `M_{0f}`) of the joints `k1..km` on the
/// path from the base to the frame (all joints for the end effector of a serial chain):
/// ```text
/// J_b,km = B_km,    J_b,kl = [Ad_{e^{−[B_km]θ_km} ⋯ e^{−[B_k(l+1)]θ_k(l+1)}}] B_kl
/// ```
/// and zero columns for the joints off the path, so that the frame's twist in {f} is
/// `V_b = J_b ν`, and `J_b = [Ad_{T⁻¹}] J_s` with `T` the frame's pose.
///
/// Floating base: the six base columns are `[Ad_{T_{bf}⁻¹}]`, which map the base's body twist
/// into {f} (`T_{bf}` is the frame's pose in the base frame).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn frame_jacobian_body(robot: &Robot, frame: &Frame, q: &[f64]) -> DMatrix<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return c.columns(&frame_jacobian_body(&c.physical, frame, &c.q(q)));
    }
    let t_b_ee = frame_pose_in_base(robot, frame, q);
    let theta = joint_values(robot, q);
    let b_list = robot.frame_screws(frame);
    let off = joint_offset(robot);
    let mut j_b = DMatrix::zeros(6, robot.nv());
    let mut t = Matrix4::<f64>::identity();
    let path = robot.frame_path(frame);
    for (l, &i) in path.iter().enumerate().rev() {
        if l + 1 < path.len() {
            let k = path[l + 1];
            t *= exp6(&b_list[k], -theta[k]);
        }
        j_b.column_mut(off + i)
            .copy_from(&(adjoint(&t) * b_list[i]));
    }
    if robot.base.floating {
        j_b.view_mut((0, 0), (6, 6))
            .copy_from(&adjoint(&trans_inv(&t_b_ee)));
    }
    j_b
}
