//! Inverse dynamics along a trajectory (the book's `InverseDynamicsTrajectory`).

use crate::inverse_dynamics::inverse_dynamics;
use dynamics_model::Robot;
use nalgebra::{DMatrix, Vector3, Vector6};

/// Row k of the result (N×nv) is `τ_k = ID(q_k, ν_k, ν̇_k, g, F_tip,k)`, with `thetamat` N×nq,
/// `dthetamat` and `ddthetamat` N×nv (one row per time step) and `ftipmat` N×6 (`F_tip` in
/// {n+1}).
///
/// # Panics
/// If the matrices do not have N rows each, nq or nv columns (6 for `ftipmat`).
pub fn inverse_dynamics_trajectory(
    robot: &Robot,
    thetamat: &DMatrix<f64>,
    dthetamat: &DMatrix<f64>,
    ddthetamat: &DMatrix<f64>,
    gravity: &Vector3<f64>,
    ftipmat: &DMatrix<f64>,
) -> DMatrix<f64> {
    let (nq, nv) = (robot.nq(), robot.nv());
    let steps = thetamat.nrows();
    let fits = |m: &DMatrix<f64>, cols: usize| m.nrows() == steps && m.ncols() == cols;
    assert!(
        fits(thetamat, nq) && fits(dthetamat, nv) && fits(ddthetamat, nv) && fits(ftipmat, 6),
        "dynamics-reference: inverse_dynamics_trajectory needs thetamat N×{nq}, dthetamat and ddthetamat N×{nv} and ftipmat N×6"
    );
    let mut taumat = DMatrix::zeros(steps, nv);
    for k in 0..steps {
        let row = |m: &DMatrix<f64>| -> Vec<f64> { m.row(k).iter().copied().collect() };
        let f_tip = Vector6::from_iterator(ftipmat.row(k).iter().copied());
        let tau = inverse_dynamics(
            robot,
            &row(thetamat),
            &row(dthetamat),
            &row(ddthetamat),
            gravity,
            &f_tip,
        );
        taumat.row_mut(k).copy_from(&tau.transpose());
    }
    taumat
}
