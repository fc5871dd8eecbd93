//! Forward kinematics of every link frame (product of exponentials, Modern Robotics §4.1).

use crate::check;
use dynamics_model::lie::exp6;
use dynamics_model::Robot;
use nalgebra::Matrix4;

/// `T_{0i}(θ) = e^{[S_1]θ_1} ⋯ e^{[S_i]θ_i} M_{0i}` for the links i = 1..n (0-based in the
/// result), with `M_{0i} = M_{01} ⋯ M_{i−1,i}` the home pose of {i}. Joints beyond i do not
/// move {i}.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn link_poses(robot: &Robot, q: &[f64]) -> Vec<Matrix4<f64>> {
    check::joint_vector(robot, "q", q);
    let home = robot.home_poses();
    let mut t = Matrix4::<f64>::identity();
    robot
        .s_list()
        .iter()
        .zip(q)
        .enumerate()
        .map(|(i, (s, &theta))| {
            t *= exp6(s, theta);
            t * home[i + 1]
        })
        .collect()
}
