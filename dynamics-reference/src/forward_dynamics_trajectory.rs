//! Simulation by forward dynamics and explicit Euler integration (the book's
//! `ForwardDynamicsTrajectory`, Modern Robotics §8.5), on a tree and a floating base.

use crate::configuration_rate::configuration_rate;
use crate::error::ReferenceError;
use crate::forward_dynamics::forward_dynamics;
use dynamics_model::Robot;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

/// Integrates the equations of motion from `(q_0, ν_0)` = (`q0`, `qd0`) under the forces
/// `taumat` (N×nv, row k = τ at step k) and tip wrenches `ftipmat` (N×6, row k = `F_tip` in
/// {n+1}), like the book's library:
///
/// ```text
/// row 0 = (q_0, ν_0)
/// for k = 0..N−2, repeated int_res times with h = dt / int_res:
///     ν̇ = ForwardDynamics(q, ν, τ_k, g, F_tip,k)
///     (q, ν) = (q + h q̇(q, ν), ν + h ν̇)
/// row k+1 = (q, ν)
/// ```
///
/// with `q̇` from [`crate::configuration_rate`]: on a fixed base `q̇ = θ̇` and the step is
/// exactly the book's `EulerStep` ([`crate::euler_step`]); on a floating base the base
/// position and quaternion follow the base twist (the quaternion is not renormalised; every
/// function normalises it when reading it).
///
/// Row k is the state at time `k·dt`; the last rows of `taumat` and `ftipmat` are not used.
/// Returns `(thetamat, dthetamat)`, N×nq and N×nv.
///
/// # Errors
/// [`ReferenceError::MassMatrixNotPositiveDefinite`] (with the row being integrated) when
/// forward dynamics fails.
///
/// # Panics
/// If `q0` does not have nq entries or `qd0` nv, `taumat` is not N×nv, `ftipmat` is not N×6,
/// or N = 0.
pub fn forward_dynamics_trajectory(
    robot: &Robot,
    q0: &[f64],
    qd0: &[f64],
    taumat: &DMatrix<f64>,
    gravity: &Vector3<f64>,
    ftipmat: &DMatrix<f64>,
    dt: f64,
    int_res: usize,
) -> Result<(DMatrix<f64>, DMatrix<f64>), ReferenceError> {
    crate::check::configuration(robot, "q0", q0);
    crate::check::velocity(robot, "qd0", qd0);
    let (nq, nv) = (robot.nq(), robot.nv());
    let steps = taumat.nrows();
    assert!(
        steps > 0 && taumat.ncols() == nv && ftipmat.nrows() == steps && ftipmat.ncols() == 6,
        "dynamics-reference: forward_dynamics_trajectory needs taumat N×{nv} and ftipmat N×6 with N ≥ 1, got {}×{} and {}×{}",
        taumat.nrows(),
        taumat.ncols(),
        ftipmat.nrows(),
        ftipmat.ncols()
    );
    let h = dt / int_res as f64;
    let mut thetamat = DMatrix::zeros(steps, nq);
    let mut dthetamat = DMatrix::zeros(steps, nv);
    let mut q = DVector::from_column_slice(q0);
    let mut qd = DVector::from_column_slice(qd0);
    thetamat.row_mut(0).copy_from(&q.transpose());
    dthetamat.row_mut(0).copy_from(&qd.transpose());
    for k in 0..steps - 1 {
        let tau: Vec<f64> = taumat.row(k).iter().copied().collect();
        let f_tip = Vector6::from_iterator(ftipmat.row(k).iter().copied());
        for _ in 0..int_res {
            let qdd = forward_dynamics(robot, q.as_slice(), qd.as_slice(), &tau, gravity, &f_tip)
                .map_err(|e| match e {
                ReferenceError::MassMatrixNotPositiveDefinite { q, .. } => {
                    ReferenceError::MassMatrixNotPositiveDefinite { q, step: Some(k) }
                }
            })?;
            let q_dot = configuration_rate(robot, q.as_slice(), qd.as_slice());
            q += &q_dot * h;
            qd += &qdd * h;
        }
        thetamat.row_mut(k + 1).copy_from(&q.transpose());
        dthetamat.row_mut(k + 1).copy_from(&qd.transpose());
    }
    Ok((thetamat, dthetamat))
}
