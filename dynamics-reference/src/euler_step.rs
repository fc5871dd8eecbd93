//! One explicit Euler step of the joint state (the book's `EulerStep`).

use nalgebra::DVector;

/// One first-order Euler step of length `dt`, both updates from the old values:
/// ```text
/// θ_new = θ + dt θ̇,    θ̇_new = θ̇ + dt θ̈
/// ```
/// Returns `(θ_new, θ̇_new)`. This is the step of a fixed base, where `q̇ = θ̇`; on a floating
/// base q has seven base entries against ν's six, so step q with
/// `q + dt q̇` and `q̇` from [`crate::configuration_rate`] (as
/// [`crate::forward_dynamics_trajectory`] does).
///
/// # Panics
/// If the three slices do not have the same length.
pub fn euler_step(q: &[f64], qd: &[f64], qdd: &[f64], dt: f64) -> (DVector<f64>, DVector<f64>) {
    assert!(
        q.len() == qd.len() && q.len() == qdd.len(),
        "dynamics-reference: euler_step got q, qd, qdd of lengths {}, {}, {}; pass one value per joint each",
        q.len(),
        qd.len(),
        qdd.len()
    );
    let q = DVector::from_column_slice(q);
    let qd = DVector::from_column_slice(qd);
    let qdd = DVector::from_column_slice(qdd);
    (&q + &qd * dt, &qd + &qdd * dt)
}
