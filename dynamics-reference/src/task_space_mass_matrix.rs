//! The end effector's task-space mass matrix (Modern Robotics §8.6), in the end-effector
//! frame: the inertia the robot shows at its tip.

use crate::jacobian_body::jacobian_body;
use crate::ldlt::Ldlt;
use crate::mass_matrix::mass_matrix;
use dynamics_model::Robot;
use nalgebra::{Cholesky, DMatrix, Dyn, Matrix6};

/// `Λ(q) = (J_b M⁻¹ J_bᵀ)⁻¹`, 6×6, the task-space mass matrix of the end effector {n+1} with
/// the body Jacobian `J_b` (rows `(ω, v)` in {n+1}; [`crate::jacobian_body`]) and the mass
/// matrix M (armature included): the wrench `F = Λ V̇_b + η` ([`crate::task_space_bias`])
/// accelerates the end effector by `V̇_b` (§8.6, eq. 8.88 with the body Jacobian). On a robot
/// with more than six velocities (redundant, or a floating base) this is the dynamically
/// consistent form `(J M⁻¹ Jᵀ)⁻¹`, not `J⁻ᵀ M J⁻¹`, which needs a square J.
///
/// Singularities (the same contract as the generated code): `None` when
///
/// - nv < 6 (`A = J_b M⁻¹ J_bᵀ` has rank < 6), or M is not positive definite;
/// - the `L D Lᵀ` factorisation of A without pivoting, rows in the order ω₁ ω₂ ω₃ v₁ v₂ v₃,
///   meets a diagonal entry `A_kk` that is not positive and finite or a pivot
///   `d_k ≤ √ε · A_kk` (ε = `f64::EPSILON`): the end effector cannot be accelerated in some
///   direction (a kinematic singularity).
///
/// Otherwise `Λ = A⁻¹` by that factorisation (`M⁻¹ J_bᵀ` by Cholesky; nothing is inverted
/// explicitly but A).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn task_space_mass_matrix(robot: &Robot, q: &[f64]) -> Option<Matrix6<f64>> {
    let ts = TaskSpace::new(robot, q)?;
    Some(Matrix6::from_iterator(ts.a.inverse().iter().copied()))
}

/// The factorised pieces shared with [`crate::task_space_bias`].
pub(crate) struct TaskSpace {
    /// `M = L Lᵀ`.
    pub m: Cholesky<f64, Dyn>,
    /// `J_b`, 6×nv.
    pub j_b: DMatrix<f64>,
    /// `A = J_b M⁻¹ J_bᵀ = L D Lᵀ`.
    pub a: Ldlt,
}

impl TaskSpace {
    /// `None` on the singularities of [`task_space_mass_matrix`].
    pub fn new(robot: &Robot, q: &[f64]) -> Option<Self> {
        crate::check::configuration(robot, "q", q);
        if robot.nv() < 6 {
            return None;
        }
        let m = mass_matrix(robot, q).cholesky()?;
        let j_b = jacobian_body(robot, q);
        let m_inv_jt = m.solve(&j_b.transpose());
        let a = Ldlt::new(&(&j_b * m_inv_jt))?;
        Some(Self { m, j_b, a })
    }
}
