//! The space Jacobian (Modern Robotics §5.1.1, the book's `JacobianSpace`) of a frame (the end
//! effector or a named frame), on a kinematic tree and a floating base.

use crate::base::{base_pose, joint_offset, joint_values};
use crate::coupling::Coupled;
use dynamics_model::lie::{adjoint, exp6};
use dynamics_model::{Frame, Robot};
use nalgebra::{DMatrix, Matrix4};

/// [`frame_jacobian_space`] of the end effector.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn jacobian_space(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    frame_jacobian_space(robot, &robot.end_effector, q)
}

/// `J_s(q)`, 6×nv, with columns in {0}, for the joints `k1..km` on the path from the base to
/// the frame (all joints for the end effector of a serial chain):
/// ```text
/// J_s,k1 = S_k1,    J_s,kl = [Ad_{e^{[S_k1]θ_k1} ⋯ e^{[S_k(l−1)]θ_k(l−1)}}] S_kl
/// ```
/// and zero columns for the joints off the path, so that the frame's twist in {0} is
/// `V_s = J_s ν`.
///
/// Floating base: the base's body twist `ν_b` moves everything, and `V_s = [Ad_{T_{0b}}] (ν_b +
/// J_s,fixed θ̇)`, so the six base columns are `[Ad_{T_{0b}}]` and the joint columns the
/// fixed-base ones (computed in the base frame) times `[Ad_{T_{0b}}]`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn frame_jacobian_space(robot: &Robot, frame: &Frame, q: &[f64]) -> DMatrix<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return c.columns(&frame_jacobian_space(&c.physical, frame, &c.q(q)));
    }
    let t_0b = base_pose(robot, q);
    let theta = joint_values(robot, q);
    let off = joint_offset(robot);
    let mut j_s = DMatrix::zeros(6, robot.nv());
    let mut t = Matrix4::<f64>::identity();
    let path = robot.frame_path(frame);
    for (l, &i) in path.iter().enumerate() {
        if l > 0 {
            let k = path[l - 1];
            t *= exp6(&robot.joints[k].screw, theta[k]);
        }
        let column = adjoint(&t) * robot.joints[i].screw; // in the base frame
        if robot.base.floating {
            j_s.column_mut(off + i)
                .copy_from(&(adjoint(&t_0b) * column));
        } else {
            j_s.column_mut(off + i).copy_from(&column);
        }
    }
    if robot.base.floating {
        j_s.view_mut((0, 0), (6, 6)).copy_from(&adjoint(&t_0b));
    }
    j_s
}
