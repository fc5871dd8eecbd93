//! Forward dynamics under velocity constraints `A(q) ν = 0` (Modern Robotics §8.7, Exercise
//! 8.10), by the saddle-point (KKT) system of the equations of motion and the constraints.

use crate::check;
use crate::inverse_dynamics::inverse_dynamics;
use crate::ldlt::Ldlt;
use crate::mass_matrix::mass_matrix;
use dynamics_model::Robot;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

/// `(ν̇, λ)` of the constrained equations of motion with K constraints `A(q) ν = 0`:
/// ```text
/// M(q) ν̇ + h(q, ν) = τ + Aᵀ λ
/// A ν̇ + Ȧ ν = 0                     (the constraint differentiated once)
/// ```
/// with `h = c + g` ([`crate::inverse_dynamics`] at ν̇ = 0, no tip wrench), `a` = A (K×nv),
/// `a_dot_qd` = `Ȧ ν` (K entries; zero for a constant A), and λ the K constraint forces
/// (`Aᵀ λ` is the joint force the constraints apply; §8.7's `λ` with the sign of `τ + Aᵀλ`).
/// Both unknowns come from one linear solve of the saddle-point system
/// ```text
/// [ M  −Aᵀ ] [ ν̇ ]   [ τ − h  ]
/// [ A   0  ] [ λ  ] = [ −Ȧ ν  ]
/// ```
/// by LU with partial pivoting (not the Schur complement `A M⁻¹ Aᵀ` the generated code takes).
/// The solution is the book's `ν̇ = P_ν̇ M⁻¹ (τ − h) − M⁻¹Aᵀ(AM⁻¹Aᵀ)⁻¹ Ȧν` with
/// `P_ν̇ = 1 − M⁻¹Aᵀ(AM⁻¹Aᵀ)⁻¹A` (Exercise 8.10).
///
/// `None` when the constraints are dependent or M is singular: M not positive definite
/// (Cholesky fails), or the `L D Lᵀ` factorisation of `A M⁻¹ Aᵀ` without pivoting meets a
/// diagonal entry that is not positive and finite or a pivot `d_k ≤ √ε · (A M⁻¹ Aᵀ)_kk`
/// (ε = `f64::EPSILON`; the test of [`crate::task_space_mass_matrix`]). K = 0 is plain
/// forward dynamics (λ empty).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, `qd` or `tau` not `robot.nv()`, `a` not nv
/// columns, or `a_dot_qd` not one entry per row of `a`.
pub fn constrained_forward_dynamics(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    a: &DMatrix<f64>,
    a_dot_qd: &DVector<f64>,
    gravity: &Vector3<f64>,
) -> Option<(DVector<f64>, DVector<f64>)> {
    check::configuration(robot, "q", q);
    check::velocity(robot, "qd", qd);
    check::velocity(robot, "tau", tau);
    let (nv, k) = (robot.nv(), a.nrows());
    assert!(
        a.ncols() == nv,
        "dynamics-reference: constrained_forward_dynamics: `a` has {} columns but robot `{}` has nv = {nv}; pass one row per constraint, one column per velocity",
        a.ncols(),
        robot.name
    );
    assert!(
        a_dot_qd.len() == k,
        "dynamics-reference: constrained_forward_dynamics: `a_dot_qd` has {} entries but `a` has {k} rows; pass Ȧν, one entry per constraint",
        a_dot_qd.len()
    );

    let m = mass_matrix(robot, q);
    let zero = vec![0.0; nv];
    let h = inverse_dynamics(robot, q, qd, &zero, gravity, &Vector6::zeros());

    // The singularity test on A M⁻¹ Aᵀ.
    let chol = m.clone().cholesky()?;
    let schur = a * chol.solve(&a.transpose());
    Ldlt::new(&schur)?;

    let mut kkt = DMatrix::zeros(nv + k, nv + k);
    kkt.view_mut((0, 0), (nv, nv)).copy_from(&m);
    kkt.view_mut((0, nv), (nv, k)).copy_from(&(-a.transpose()));
    kkt.view_mut((nv, 0), (k, nv)).copy_from(a);
    let mut rhs = DVector::zeros(nv + k);
    rhs.rows_mut(0, nv)
        .copy_from(&(DVector::from_column_slice(tau) - h));
    rhs.rows_mut(nv, k).copy_from(&(-a_dot_qd));
    let x = kkt.lu().solve(&rhs)?;
    Some((x.rows(0, nv).into_owned(), x.rows(nv, k).into_owned()))
}
