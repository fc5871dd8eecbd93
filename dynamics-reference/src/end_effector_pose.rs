//! Forward kinematics of the end-effector frame (Modern Robotics §4.1, the book's `FKinSpace`).

use crate::check;
use dynamics_model::lie::exp6;
use dynamics_model::Robot;
use nalgebra::Matrix4;

/// `T_{0,n+1}(θ) = e^{[S_1]θ_1} ⋯ e^{[S_n]θ_n} M`, with `M = M_{01} M_{12} ⋯ M_{n,n+1}` the home
/// pose of the end-effector frame {n+1}.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn end_effector_pose(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    check::joint_vector(robot, "q", q);
    let home = robot.home_poses();
    let mut t = Matrix4::<f64>::identity();
    for (s, &theta) in robot.s_list().iter().zip(q) {
        t *= exp6(s, theta);
    }
    t * home[robot.dof() + 1]
}
