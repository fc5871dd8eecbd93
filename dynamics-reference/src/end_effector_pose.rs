//! Forward kinematics of the end-effector frame (Modern Robotics §4.1, the book's `FKinSpace`),
//! through the path to the end effector's link.

use crate::base::{base_pose, joint_values};
use crate::coupling::Coupled;
use dynamics_model::lie::exp6;
use dynamics_model::Robot;
use nalgebra::Matrix4;

/// `T_{0,n+1}(q) = T_{0b} e^{[S_{k1}]θ_{k1}} ⋯ e^{[S_{km}]θ_{km}} M`, with `k1..km` the joints on
/// the path from the base to the end effector's link (all joints 1..n on a serial chain), `M`
/// the home pose of the end-effector frame {n+1} and `T_{0b}` the base pose
/// ([`crate::base_pose`]; the identity on a fixed base).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn end_effector_pose(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return end_effector_pose(&c.physical, &c.q(q));
    }
    let t_0b = base_pose(robot, q);
    let t_b = end_effector_pose_in_base(robot, q);
    if robot.base.floating {
        t_0b * t_b
    } else {
        t_b
    }
}

/// `T_{b,n+1}(θ)`: the end-effector pose in the base frame (= {0} on a fixed base).
pub(crate) fn end_effector_pose_in_base(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    let theta = joint_values(robot, q);
    let home = robot.home_poses();
    let mut t = Matrix4::<f64>::identity();
    for i in end_effector_path(robot) {
        t *= exp6(&robot.joints[i].screw, theta[i]);
    }
    t * home[robot.dof() + 1]
}

/// The joints on the path from the base to the end effector, base side first.
pub(crate) fn end_effector_path(robot: &Robot) -> Vec<usize> {
    robot
        .end_effector
        .parent
        .map_or(Vec::new(), |p| robot.path_to(p))
}
