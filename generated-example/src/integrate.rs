//! Fixed-step integrators for `q̈ = f(q, q̇)`, the state being `(q, q̇)`.
//!
//! `f` is typically a generated `forward_dynamics` with the joint forces held fixed over the
//! step. All three are `no_std` and allocation-free.

use nalgebra::SVector;

/// A joint-space state `(q, q̇)`.
pub type State<const N: usize> = (SVector<f64, N>, SVector<f64, N>);

/// Explicit (forward) Euler, the book's `EulerStep`: both updates from the old state,
/// ```text
/// q_{k+1} = q_k + h q̇_k,   q̇_{k+1} = q̇_k + h f(q_k, q̇_k).
/// ```
/// First order; it gains energy on a conservative system.
pub fn explicit_euler<const N: usize>(
    f: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    (q, qd): State<N>,
    h: f64,
) -> State<N> {
    let qdd = f(&q, &qd);
    (q + qd * h, qd + qdd * h)
}

/// Semi-implicit (symplectic) Euler: the velocity first, then the position with the new
/// velocity,
/// ```text
/// q̇_{k+1} = q̇_k + h f(q_k, q̇_k),   q_{k+1} = q_k + h q̇_{k+1}.
/// ```
/// First order. For a constant mass matrix (a separable Hamiltonian) it is symplectic and its
/// energy error stays bounded instead of drifting; with a configuration-dependent `M(q)` the
/// update in velocity coordinates is no longer symplectic (that needs the momenta `M q̇` and
/// an implicit step), and the energy can drift, more slowly than with explicit Euler.
pub fn semi_implicit_euler<const N: usize>(
    f: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    (q, qd): State<N>,
    h: f64,
) -> State<N> {
    let qd_new = qd + f(&q, &qd) * h;
    (q + qd_new * h, qd_new)
}

/// Classical fourth-order Runge–Kutta on `ẋ = (q̇, f(q, q̇))`:
/// ```text
/// k1 = F(x),  k2 = F(x + h/2 k1),  k3 = F(x + h/2 k2),  k4 = F(x + h k3),
/// x_{k+1} = x + h/6 (k1 + 2 k2 + 2 k3 + k4).
/// ```
pub fn rk4<const N: usize>(
    f: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
    (q, qd): State<N>,
    h: f64,
) -> State<N> {
    let (k1q, k1v) = (qd, f(&q, &qd));
    let (q2, v2) = (q + k1q * (h / 2.0), qd + k1v * (h / 2.0));
    let (k2q, k2v) = (v2, f(&q2, &v2));
    let (q3, v3) = (q + k2q * (h / 2.0), qd + k2v * (h / 2.0));
    let (k3q, k3v) = (v3, f(&q3, &v3));
    let (q4, v4) = (q + k3q * h, qd + k3v * h);
    let (k4q, k4v) = (v4, f(&q4, &v4));
    (
        q + (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (h / 6.0),
        qd + (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (h / 6.0),
    )
}
