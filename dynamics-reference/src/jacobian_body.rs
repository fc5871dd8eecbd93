//! The body Jacobian of the end-effector frame {n+1} (Modern Robotics §5.1.3, the book's
//! `JacobianBody`).

use crate::check;
use dynamics_model::lie::{adjoint, exp6};
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix4};

/// `J_b(θ)`, 6×n, with columns in {n+1}, from the body-frame screw axes
/// `B_i = [Ad_{M⁻¹}] S_i` (M = `M_{0,n+1}`):
/// ```text
/// J_bn = B_n,    J_bi = [Ad_{e^{−[B_n]θ_n} ⋯ e^{−[B_{i+1}]θ_{i+1}}}] B_i    (i = n−1..1)
/// ```
/// so that the end-effector twist in {n+1} is `V_b = J_b θ̇`, and `J_b = [Ad_{T⁻¹}] J_s` with
/// `T` the end-effector pose.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn jacobian_body(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    check::joint_vector(robot, "q", q);
    let b_list = robot.body_frame_screws();
    let n = robot.dof();
    let mut j_b = DMatrix::zeros(6, n);
    let mut t = Matrix4::<f64>::identity();
    for i in (0..n).rev() {
        if i + 1 < n {
            t *= exp6(&b_list[i + 1], -q[i + 1]);
        }
        j_b.column_mut(i).copy_from(&(adjoint(&t) * b_list[i]));
    }
    j_b
}
