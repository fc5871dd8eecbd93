//! The end effector's task-space bias force (Modern Robotics §8.6): Coriolis, centripetal
//! and gravity terms seen at the tip.

use crate::check;
use crate::inverse_dynamics::inverse_dynamics;
use crate::jacobian_body_dot::jacobian_body_dot;
use crate::task_space_mass_matrix::TaskSpace;
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `η(q, ν) = Λ (J_b M⁻¹ h − J̇_b ν)`, the task-space bias wrench of the end effector {n+1}
/// in {n+1}, with `h = c(q, ν) + g(q)` ([`crate::inverse_dynamics`] at ν̇ = 0, no tip wrench),
/// `Λ` of [`crate::task_space_mass_matrix`] and `J̇_b` of [`crate::jacobian_body_dot`], so that
/// ```text
/// F = Λ V̇_b + η,    V̇_b = J_b ν̇ + J̇_b ν
/// ```
/// (§8.6, eq. 8.89 in body coordinates): with `M ν̇ + h = J_bᵀ F`,
/// `V̇_b = J_b M⁻¹ (J_bᵀ F − h) + J̇_b ν = Λ⁻¹ F − J_b M⁻¹ h + J̇_b ν`. Valid for redundant arms:
/// there, any joint force τ gives `Λ V̇_b + η = Λ J_b M⁻¹ τ`, which is F for `τ = J_bᵀ F` (plus
/// any τ₀ with `J_b M⁻¹ τ₀ = 0`).
///
/// `None` exactly when [`crate::task_space_mass_matrix`] is `None`. `Λ (…)` is applied by
/// solving with the `L D Lᵀ` factors of `A = Λ⁻¹`.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn task_space_bias(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    gravity: &Vector3<f64>,
) -> Option<Vector6<f64>> {
    check::velocity(robot, "qd", qd);
    let ts = TaskSpace::new(robot, q)?;
    let zero = vec![0.0; robot.nv()];
    let h = inverse_dynamics(robot, q, qd, &zero, gravity, &Vector6::zeros());
    let j_dot_qd = jacobian_body_dot(robot, q, qd) * DVector::from_column_slice(qd);
    let y = &ts.j_b * ts.m.solve(&h) - j_dot_qd;
    Some(Vector6::from_iterator(ts.a.solve(&y).iter().copied()))
}
