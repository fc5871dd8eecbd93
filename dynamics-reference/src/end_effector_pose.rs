//! Forward kinematics of a frame (Modern Robotics §4.1, the book's `FKinSpace`): the
//! end-effector frame or a named frame, through the path to its link.

use crate::base::{base_pose, joint_values};
use crate::coupling::Coupled;
use dynamics_model::lie::exp6;
use dynamics_model::{Frame, Robot};
use nalgebra::Matrix4;

/// `T_{0,n+1}(q)`: [`frame_pose`] of the end effector.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn end_effector_pose(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    frame_pose(robot, &robot.end_effector, q)
}

/// `T_{0f}(q) = T_{0b} e^{[S_{k1}]θ_{k1}} ⋯ e^{[S_{km}]θ_{km}} M_{0f}`, with `k1..km` the
/// joints on the path from the base to the frame's link (all joints 1..n for the end effector
/// of a serial chain), `M_{0f}` the frame's home pose in {0} and `T_{0b}` the base pose
/// ([`crate::base_pose`]; the identity on a fixed base).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn frame_pose(robot: &Robot, frame: &Frame, q: &[f64]) -> Matrix4<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return frame_pose(&c.physical, frame, &c.q(q));
    }
    let t_b = frame_pose_in_base(robot, frame, q);
    if robot.base.floating {
        base_pose(robot, q) * t_b
    } else {
        t_b
    }
}

/// `T_{bf}(θ)`: a frame's pose in the base frame (= {0} on a fixed base).
pub(crate) fn frame_pose_in_base(robot: &Robot, frame: &Frame, q: &[f64]) -> Matrix4<f64> {
    let theta = joint_values(robot, q);
    let mut t = Matrix4::<f64>::identity();
    for i in robot.frame_path(frame) {
        t *= exp6(&robot.joints[i].screw, theta[i]);
    }
    t * robot.frame_home(frame)
}
