//! Forward kinematics of every link frame (product of exponentials, Modern Robotics §4.1), on
//! a kinematic tree.

use crate::base::{base_pose, joint_values};
use crate::coupling::Coupled;
use dynamics_model::lie::exp6;
use dynamics_model::Robot;
use nalgebra::Matrix4;

/// `T_{0i}(q)` for the links i = 1..n (0-based in the result): the product of the exponentials
/// of the joints on the path from the base to i (`path_to(i)`, base side first),
/// ```text
/// T_{0i} = T_{0b} e^{[S_{k1}]θ_{k1}} ⋯ e^{[S_i]θ_i} M_{0i},    P_i = P_{λ(i)} e^{[S_i]θ_i}
/// ```
/// with `M_{0i}` the home pose of {i} and `T_{0b}` the base pose ([`crate::base_pose`], the
/// identity on a fixed base). On a serial chain the path is joints 1..i. Joints off the path do
/// not move {i}.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn link_poses(robot: &Robot, q: &[f64]) -> Vec<Matrix4<f64>> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return link_poses(&c.physical, &c.q(q));
    }
    let t_0b = base_pose(robot, q);
    let theta = joint_values(robot, q);
    let home = robot.home_poses();
    // products[i] = P_i, the exponentials along the path to link i.
    let mut products: Vec<Matrix4<f64>> = Vec::with_capacity(robot.dof());
    for (i, (link, joint)) in robot.links.iter().zip(&robot.joints).enumerate() {
        let p_parent = link.parent.map_or(Matrix4::identity(), |p| products[p]);
        products.push(p_parent * exp6(&joint.screw, theta[i]));
    }
    products
        .iter()
        .enumerate()
        .map(|(i, p_i)| {
            let t_bi = p_i * home[i + 1];
            if robot.base.floating {
                t_0b * t_bi
            } else {
                t_bi
            }
        })
        .collect()
}
