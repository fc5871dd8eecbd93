//! The space Jacobian (Modern Robotics §5.1.1, the book's `JacobianSpace`).

use crate::check;
use dynamics_model::lie::{adjoint, exp6};
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix4};

/// `J_s(θ)`, 6×n, with columns in {0}:
/// ```text
/// J_s1 = S_1,    J_si = [Ad_{e^{[S_1]θ_1} ⋯ e^{[S_{i−1}]θ_{i−1}}}] S_i    (i = 2..n)
/// ```
/// so that the end-effector twist in {0} is `V_s = J_s θ̇`.
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn jacobian_space(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    check::joint_vector(robot, "q", q);
    let s_list = robot.s_list();
    let n = robot.dof();
    let mut j_s = DMatrix::zeros(6, n);
    let mut t = Matrix4::<f64>::identity();
    for i in 0..n {
        if i > 0 {
            t *= exp6(&s_list[i - 1], q[i - 1]);
        }
        j_s.column_mut(i).copy_from(&(adjoint(&t) * s_list[i]));
    }
    j_s
}
