//! The body Jacobian of the end-effector frame {n+1} (Modern Robotics §5.1.3, the book's
//! `JacobianBody`), on a kinematic tree and a floating base.

use crate::base::{joint_offset, joint_values};
use crate::coupling::Coupled;
use crate::end_effector_pose::{end_effector_path, end_effector_pose_in_base};
use dynamics_model::lie::{adjoint, exp6, trans_inv};
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix4};

/// `J_b(q)`, 6×nv, with columns in {n+1}, from the body-frame screw axes `B_i = [Ad_{M⁻¹}] S_i`
/// (M = `M_{0,n+1}`) of the joints `k1..km` on the path from the base to the end effector (all
/// joints on a serial chain):
/// ```text
/// J_b,km = B_km,    J_b,kl = [Ad_{e^{−[B_km]θ_km} ⋯ e^{−[B_k(l+1)]θ_k(l+1)}}] B_kl
/// ```
/// and zero columns for the joints off the path, so that the end-effector twist in {n+1} is
/// `V_b = J_b ν`, and `J_b = [Ad_{T⁻¹}] J_s` with `T` the end-effector pose.
///
/// Floating base: the six base columns are `[Ad_{T_{b,n+1}⁻¹}]`, which map the base's body
/// twist into {n+1} (`T_{b,n+1}` is the end-effector pose in the base frame).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn jacobian_body(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return c.columns(&jacobian_body(&c.physical, &c.q(q)));
    }
    let t_b_ee = end_effector_pose_in_base(robot, q);
    let theta = joint_values(robot, q);
    let b_list = robot.body_frame_screws();
    let off = joint_offset(robot);
    let mut j_b = DMatrix::zeros(6, robot.nv());
    let mut t = Matrix4::<f64>::identity();
    let path = end_effector_path(robot);
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
