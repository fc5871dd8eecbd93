//! Iterative LQR (Li & Todorov 2004; the Levenberg–Marquardt regularisation and line search
//! of Tassa, Erez & Todorov 2012) for a robot's joint-space trajectory, on the generated
//! `forward_dynamics_with_derivatives`: `no_std`, no allocation (the caller owns the
//! trajectory buffers), no panics.
//!
//! Discrete dynamics: semi-implicit Euler on the state `x = (q, q̇)` with the joint forces
//! `u = τ` as controls,
//! ```text
//! q̇⁺ = q̇ + h q̈(q, q̇, τ),   q⁺ = q + h q̇⁺,
//! ∂q̇⁺/∂(q, q̇, τ) = h (∂q̈/∂q, ∂q̈/∂q̇, M⁻¹) + (0, I, 0),   ∂q⁺/∂· = (I, 0, 0) + h ∂q̇⁺/∂·.
//! ```
//! Cost: `Σ_k ½ (q_k − q*)ᵀ W_q (q_k − q*) + ½ Δτ_kᵀ R Δτ_k` with `Δτ = τ − g(q*)` (torque
//! beyond holding the goal) plus the terminal `½ (q_N − q*)ᵀ P_q (q_N − q*) + ½ q̇_Nᵀ P_v q̇_N`;
//! weights diagonal.

use nalgebra::{SMatrix, SVector};

/// The linearised dynamics of one step: `(x⁺, ∂x⁺/∂x, ∂x⁺/∂u)`.
pub type Linearised<const NX: usize, const NU: usize> =
    (SVector<f64, NX>, SMatrix<f64, NX, NX>, SMatrix<f64, NX, NU>);

/// A quadratic tracking cost, diagonal weights (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Cost<const NX: usize, const NU: usize> {
    /// Goal state `x*` (velocities included; the running cost weighs what `running` weighs).
    pub goal: SVector<f64, NX>,
    /// Control offset: the running cost weighs `u − u_ref`.
    pub u_ref: SVector<f64, NU>,
    /// Running weights on `x − x*` (per step).
    pub running: SVector<f64, NX>,
    /// Weights on `u − u_ref` (per step).
    pub control: SVector<f64, NU>,
    /// Terminal weights on `x_N − x*`.
    pub terminal: SVector<f64, NX>,
}

impl<const NX: usize, const NU: usize> Cost<NX, NU> {
    fn stage(&self, x: &SVector<f64, NX>, u: &SVector<f64, NU>) -> f64 {
        let dx = x - self.goal;
        let du = u - self.u_ref;
        0.5 * (dx.component_mul(&dx).dot(&self.running) + du.component_mul(&du).dot(&self.control))
    }

    fn last(&self, x: &SVector<f64, NX>) -> f64 {
        let dx = x - self.goal;
        0.5 * dx.component_mul(&dx).dot(&self.terminal)
    }

    /// The total cost of a trajectory (`xs.len() = us.len() + 1`).
    pub fn total(&self, xs: &[SVector<f64, NX>], us: &[SVector<f64, NU>]) -> f64 {
        let running: f64 = xs.iter().zip(us).map(|(x, u)| self.stage(x, u)).sum();
        running + xs.last().map_or(0.0, |x| self.last(x))
    }
}

/// What one iteration did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Iteration {
    /// Cost after the iteration.
    pub cost: f64,
    /// Line-search step taken (0 when none was accepted).
    pub step: f64,
    /// The Levenberg–Marquardt regularisation used.
    pub mu: f64,
    /// `max_k |k_k|∞`, the largest feed-forward change: small at convergence.
    pub feedforward: f64,
}

/// Why [`solve`] could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IlqrError {
    /// The buffers do not fit: `xs.len()` must be `us.len() + 1`, and the gain buffers
    /// `us.len()` long; `history` non-empty.
    Buffers,
}

/// Feedback and feed-forward gains of one step.
#[derive(Clone, Copy, Debug)]
pub struct Gains<const NX: usize, const NU: usize> {
    /// Feed-forward `k`.
    pub k: SVector<f64, NU>,
    /// Feedback `K`.
    pub big_k: SMatrix<f64, NU, NX>,
}

impl<const NX: usize, const NU: usize> Default for Gains<NX, NU> {
    fn default() -> Self {
        Self {
            k: SVector::zeros(),
            big_k: SMatrix::zeros(),
        }
    }
}

/// Runs iLQR from `xs[0]` with the initial controls `us` (updated in place; `xs` receives
/// the rollout), at most `history.len()` iterations; returns how many ran, each recorded in
/// `history` (`history[i].cost` after iteration i). Stops when the relative cost decrease
/// falls below `tol` or the regularisation exceeds 1e10 (no descent left).
///
/// `step(x, u)` is the discrete dynamics with its Jacobians; `scratch` holds the
/// linearisation of each step (`us.len()` long).
pub fn solve<const NX: usize, const NU: usize>(
    step: &dyn Fn(&SVector<f64, NX>, &SVector<f64, NU>) -> Linearised<NX, NU>,
    cost: &Cost<NX, NU>,
    xs: &mut [SVector<f64, NX>],
    us: &mut [SVector<f64, NU>],
    scratch: &mut [(SMatrix<f64, NX, NX>, SMatrix<f64, NX, NU>)],
    gains: &mut [Gains<NX, NU>],
    history: &mut [Iteration],
    tol: f64,
) -> Result<usize, IlqrError> {
    let n = us.len();
    if xs.len() != n + 1 || scratch.len() != n || gains.len() != n || history.is_empty() {
        return Err(IlqrError::Buffers);
    }
    // Initial rollout.
    for k in 0..n {
        let (next, a, b) = step(&xs[k], &us[k]);
        xs[k + 1] = next;
        scratch[k] = (a, b);
    }
    let mut j = cost.total(xs, us);
    let mut mu = 1e-6;
    for (it, record) in history.iter_mut().enumerate() {
        // Backward pass; on a non-positive-definite Q_uu raise μ and redo.
        let expected = loop {
            match backward(cost, xs, us, scratch, gains, mu) {
                Some(e) => break Some(e),
                None if mu > 1e10 => break None,
                None => mu *= 10.0,
            }
        };
        let Some((d1, d2)) = expected else {
            *record = Iteration {
                cost: j,
                step: 0.0,
                mu,
                feedforward: 0.0,
            };
            return Ok(it + 1);
        };
        let feedforward = gains.iter().fold(0.0f64, |m, g| m.max(g.k.amax()));
        // Forward pass with a backtracking line search (Armijo on the predicted decrease).
        let mut accepted = 0.0;
        let mut alpha = 1.0;
        while alpha > 1e-4 {
            let (new_j, ok) = forward(step, cost, xs, us, scratch, gains, alpha, j, d1, d2);
            if ok {
                accepted = alpha;
                let decrease = j - new_j;
                j = new_j;
                mu = (mu / 4.0).max(1e-9);
                *record = Iteration {
                    cost: j,
                    step: alpha,
                    mu,
                    feedforward,
                };
                if decrease <= tol * j.abs() {
                    return Ok(it + 1);
                }
                break;
            }
            alpha *= 0.5;
        }
        if accepted == 0.0 {
            mu *= 10.0;
            *record = Iteration {
                cost: j,
                step: 0.0,
                mu,
                feedforward,
            };
            if mu > 1e10 {
                return Ok(it + 1);
            }
        }
    }
    Ok(history.len())
}

/// The backward pass: gains for every step; `Some((d1, d2))`, the expected decrease
/// `α d1 + α² d2`, or `None` when some `Q_uu + μI` is not positive definite.
fn backward<const NX: usize, const NU: usize>(
    cost: &Cost<NX, NU>,
    xs: &[SVector<f64, NX>],
    us: &[SVector<f64, NU>],
    scratch: &[(SMatrix<f64, NX, NX>, SMatrix<f64, NX, NU>)],
    gains: &mut [Gains<NX, NU>],
    mu: f64,
) -> Option<(f64, f64)> {
    let n = us.len();
    let x_last = xs.last()?;
    let mut v_x = (x_last - cost.goal).component_mul(&cost.terminal);
    let mut v_xx = SMatrix::<f64, NX, NX>::from_diagonal(&cost.terminal);
    let (mut d1, mut d2) = (0.0, 0.0);
    for k in (0..n).rev() {
        let (a, b) = &scratch[k];
        let l_x = (xs[k] - cost.goal).component_mul(&cost.running);
        let l_u = (us[k] - cost.u_ref).component_mul(&cost.control);
        let q_x = l_x + a.transpose() * v_x;
        let q_u = l_u + b.transpose() * v_x;
        let vb = v_xx * b;
        let q_xx = SMatrix::<f64, NX, NX>::from_diagonal(&cost.running) + a.transpose() * v_xx * a;
        let q_ux = vb.transpose() * a;
        let q_uu = SMatrix::<f64, NU, NU>::from_diagonal(&cost.control) + b.transpose() * vb;
        let mut reg = q_uu;
        for i in 0..NU {
            reg[(i, i)] += mu;
        }
        let chol = cholesky(&reg)?;
        let kk = -solve_chol(&chol, &q_u);
        let mut big_k = SMatrix::<f64, NU, NX>::zeros();
        for c in 0..NX {
            big_k.set_column(c, &-solve_chol(&chol, &q_ux.column(c).into_owned()));
        }
        d1 += kk.dot(&q_u);
        d2 += 0.5 * kk.dot(&(q_uu * kk));
        v_x = q_x + big_k.transpose() * q_uu * kk + big_k.transpose() * q_u + q_ux.transpose() * kk;
        v_xx = q_xx
            + big_k.transpose() * q_uu * big_k
            + big_k.transpose() * q_ux
            + q_ux.transpose() * big_k;
        v_xx = 0.5 * (v_xx + v_xx.transpose());
        gains[k] = Gains { k: kk, big_k };
    }
    Some((d1, d2))
}

/// A forward pass with step `alpha`: on acceptance (cost decreased by at least a tenth of
/// the predicted decrease) the new trajectory and linearisation replace the old ones.
#[allow(clippy::too_many_arguments)]
fn forward<const NX: usize, const NU: usize>(
    step: &dyn Fn(&SVector<f64, NX>, &SVector<f64, NU>) -> Linearised<NX, NU>,
    cost: &Cost<NX, NU>,
    xs: &mut [SVector<f64, NX>],
    us: &mut [SVector<f64, NU>],
    scratch: &mut [(SMatrix<f64, NX, NX>, SMatrix<f64, NX, NU>)],
    gains: &[Gains<NX, NU>],
    alpha: f64,
    j: f64,
    d1: f64,
    d2: f64,
) -> (f64, bool) {
    // Cost of the candidate first, without touching the buffers.
    let mut x = xs[0];
    let mut total = 0.0;
    for k in 0..us.len() {
        let u = us[k] + alpha * gains[k].k + gains[k].big_k * (x - xs[k]);
        total += cost.stage(&x, &u);
        x = step(&x, &u).0;
        if !x.iter().all(|v| v.is_finite()) {
            return (j, false);
        }
    }
    total += cost.last(&x);
    let predicted = -(alpha * d1 + alpha * alpha * d2);
    let accepted = total < j && j - total >= 0.1 * predicted;
    if !accepted {
        return (j, false);
    }
    // Accepted: the rollout again, storing it with its linearisation.
    let mut x = xs[0];
    for k in 0..us.len() {
        let u = us[k] + alpha * gains[k].k + gains[k].big_k * (x - xs[k]);
        let (next, a, b) = step(&x, &u);
        xs[k] = x;
        us[k] = u;
        scratch[k] = (a, b);
        x = next;
    }
    if let Some(last) = xs.last_mut() {
        *last = x;
    }
    (total, true)
}

/// Lower Cholesky factor of a symmetric matrix, `None` unless positive definite.
fn cholesky<const N: usize>(m: &SMatrix<f64, N, N>) -> Option<SMatrix<f64, N, N>> {
    let mut l = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let mut d = m[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        // (NaN fails this test too.)
        if d.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return None;
        }
        let d = libm::sqrt(d);
        l[(j, j)] = d;
        for i in j + 1..N {
            let mut s = m[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / d;
        }
    }
    Some(l)
}

/// `x` with `L Lᵀ x = b`.
fn solve_chol<const N: usize>(l: &SMatrix<f64, N, N>, b: &SVector<f64, N>) -> SVector<f64, N> {
    let mut y = *b;
    for i in 0..N {
        for k in 0..i {
            y[i] -= l[(i, k)] * y[k];
        }
        y[i] /= l[(i, i)];
    }
    for i in (0..N).rev() {
        for k in i + 1..N {
            y[i] -= l[(k, i)] * y[k];
        }
        y[i] /= l[(i, i)];
    }
    y
}

/// One semi-implicit Euler step of `h` seconds on `x = (q, q̇)` (`NX = 2N`, else `None`)
/// with its Jacobians (see the module docs), from `fd(q, q̇, τ) = (q̈, ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)`:
/// the generated `forward_dynamics_with_derivatives`.
#[allow(clippy::type_complexity)]
pub fn semi_implicit_euler<const N: usize, const NX: usize>(
    h: f64,
    x: &SVector<f64, NX>,
    tau: &SVector<f64, N>,
    fd: &dyn Fn(
        &SVector<f64, N>,
        &SVector<f64, N>,
        &SVector<f64, N>,
    ) -> (
        SVector<f64, N>,
        SMatrix<f64, N, N>,
        SMatrix<f64, N, N>,
        SMatrix<f64, N, N>,
    ),
) -> Option<Linearised<NX, N>> {
    if NX != 2 * N {
        return None;
    }
    let q: SVector<f64, N> = x.fixed_rows::<N>(0).into_owned();
    let qd: SVector<f64, N> = x.fixed_rows::<N>(N).into_owned();
    let (qdd, d_q, d_qd, m_inv) = fd(&q, &qd, tau);
    let qd_next = qd + h * qdd;
    let q_next = q + h * qd_next;
    let mut next = SVector::<f64, NX>::zeros();
    next.fixed_rows_mut::<N>(0).copy_from(&q_next);
    next.fixed_rows_mut::<N>(N).copy_from(&qd_next);
    // ∂q̇⁺/∂q = h ∂q̈/∂q, ∂q̇⁺/∂q̇ = I + h ∂q̈/∂q̇, ∂q̇⁺/∂τ = h M⁻¹; ∂q⁺ = (I, 0, 0) + h ∂q̇⁺.
    let identity = SMatrix::<f64, N, N>::identity();
    let v_q = h * d_q;
    let v_v = identity + h * d_qd;
    let v_u = h * m_inv;
    let mut a = SMatrix::<f64, NX, NX>::zeros();
    a.fixed_view_mut::<N, N>(0, 0)
        .copy_from(&(identity + h * v_q));
    a.fixed_view_mut::<N, N>(0, N).copy_from(&(h * v_v));
    a.fixed_view_mut::<N, N>(N, 0).copy_from(&v_q);
    a.fixed_view_mut::<N, N>(N, N).copy_from(&v_v);
    let mut b = SMatrix::<f64, NX, N>::zeros();
    b.fixed_view_mut::<N, N>(0, 0).copy_from(&(h * v_u));
    b.fixed_view_mut::<N, N>(N, 0).copy_from(&v_u);
    Some((next, a, b))
}
