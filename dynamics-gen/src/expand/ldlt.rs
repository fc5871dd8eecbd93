//! Symbolic forward dynamics by an unrolled LDLᵀ factorisation of the mass matrix:
//!
//! ```text
//! M θ̈ = τ − c(θ, θ̇) − g(θ),   M = L D Lᵀ (L unit lower triangular, D diagonal)
//! D_j = M_jj − Σ_{k<j} L_jk Y_jk,     Y_ij = M_ij − Σ_{k<j} Y_ik L_jk  (= L_ij D_j),  L_ij = Y_ij / D_j
//! z = L⁻¹ b,  y = D⁻¹ z,  θ̈ = L⁻ᵀ y
//! ```
//!
//! No pivoting: M is symmetric positive definite for a physical robot. One division per
//! joint (`1/D_j`), shared by the factor and the solve.

use crate::expr::{ExprGraph, ExprId};

/// Solves `M x = b` symbolically; `m` is n×n row-major and symmetric (only the lower
/// triangle is read).
pub fn ldlt_solve(g: &mut ExprGraph, m: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let (l, _, inv_d) = ldlt_factor(g, m);
    ldlt_apply(g, &l, &inv_d, b)
}

/// The factorisation `M = L D Lᵀ` of [`ldlt_solve`]: `L` (n×n row-major, strictly lower
/// triangle set, the rest 0), `D` and `1 / D_j`.
pub fn ldlt_factor(g: &mut ExprGraph, m: &[ExprId]) -> (Vec<ExprId>, Vec<ExprId>, Vec<ExprId>) {
    let n = m.len().isqrt();
    let zero = g.zero();
    let one = g.one();
    let mut l = vec![zero; n * n];
    let mut inv_d = vec![one; n];
    let mut diag = vec![zero; n];
    for j in 0..n {
        // Y_jk = L_jk D_k for k < j is kept in y_row to save multiplications.
        let mut d = m[j * n + j];
        // Y_jk for k < j.
        let mut y_row = vec![zero; j];
        for k in 0..j {
            let mut y = m[j * n + k];
            for p in 0..k {
                let t = g.mul(y_row[p], l[k * n + p]);
                y = g.sub(y, t);
            }
            y_row[k] = y;
            l[j * n + k] = g.mul(y, inv_d[k]);
        }
        for k in 0..j {
            let t = g.mul(l[j * n + k], y_row[k]);
            d = g.sub(d, t);
        }
        diag[j] = d;
        inv_d[j] = g.div(one, d);
    }
    (l, diag, inv_d)
}

/// `x = M⁻¹ b` from the factors of [`ldlt_factor`]: `L z = b`, `y = D⁻¹ z`, `Lᵀ x = y`.
pub fn ldlt_apply(g: &mut ExprGraph, l: &[ExprId], inv_d: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let n = b.len();
    // Forward substitution L z = b.
    let mut z = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            let t = g.mul(l[i * n + k], z[k]);
            z[i] = g.sub(z[i], t);
        }
    }
    // y = D⁻¹ z, then back substitution Lᵀ x = y.
    let mut x: Vec<ExprId> = (0..n).map(|i| g.mul(z[i], inv_d[i])).collect();
    for i in (0..n).rev() {
        for k in i + 1..n {
            let t = g.mul(l[k * n + i], x[k]);
            x[i] = g.sub(x[i], t);
        }
    }
    x
}

/// Solves `M x = b` symbolically by the factorisation `M = Lᵀ D L` from the last row up
/// (Featherstone's LTDL, *Rigid Body Dynamics Algorithms* §6.5):
///
/// ```text
/// for k = n..1:  D_k = M_kk;  L_ki = M_ki / D_k (i < k);  M_ij −= L_ki M_kj (j ≤ i < k)
/// y = L⁻ᵀ b,  z = D⁻¹ y,  x = L⁻¹ z
/// ```
///
/// On a tree in topological order (every joint after its parent) `M_ki` is non-zero only
/// for ancestors i of k, and the update touches only pairs of ancestors, which are non-zero
/// already: no fill-in, so the structural zeros of `M` (exact zeros in the graph) stay zero
/// and cost nothing. `m` is n×n row-major and symmetric (only the lower triangle is read).
pub fn ltdl_solve(g: &mut ExprGraph, m: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let (h, inv_d) = ltdl_factor(g, m);
    ltdl_apply(g, &h, &inv_d, b)
}

/// The factorisation `M = Lᵀ D L` of [`ltdl_solve`]: `L` (n×n row-major; its strictly lower
/// triangle is `L`, the rest is `M`'s lower triangle's leftovers and must not be read) and
/// `1 / D_k`.
pub fn ltdl_factor(g: &mut ExprGraph, m: &[ExprId]) -> (Vec<ExprId>, Vec<ExprId>) {
    let n = m.len().isqrt();
    let zero = g.zero();
    let one = g.one();
    // The lower triangle, overwritten by L below the diagonal.
    let mut h: Vec<ExprId> = (0..n * n)
        .map(|k| if k % n <= k / n { m[k] } else { zero })
        .collect();
    let mut inv_d = vec![one; n];
    for k in (0..n).rev() {
        inv_d[k] = g.div(one, h[k * n + k]);
        // i descending, so that M_kj (j < i) is read before it is overwritten by L_kj.
        for i in (0..k).rev() {
            let l = g.mul(h[k * n + i], inv_d[k]);
            if g.is_zero(l) {
                continue;
            }
            for j in 0..=i {
                let t = g.mul(l, h[k * n + j]);
                h[i * n + j] = g.sub(h[i * n + j], t);
            }
            h[k * n + i] = l;
        }
        // Entries with L_ki = 0 keep M_ki = 0 there (structural zeros), so h[k][i] is L_ki.
    }
    (h, inv_d)
}

/// `x = M⁻¹ b` from the factors of [`ltdl_factor`]: `Lᵀ y = b`, `z = D⁻¹ y`, `L x = z`.
pub fn ltdl_apply(g: &mut ExprGraph, h: &[ExprId], inv_d: &[ExprId], b: &[ExprId]) -> Vec<ExprId> {
    let n = b.len();
    // Lᵀ y = b, from the last row up.
    let mut y = b.to_vec();
    for k in (0..n).rev() {
        for i in 0..k {
            let t = g.mul(h[k * n + i], y[k]);
            y[i] = g.sub(y[i], t);
        }
    }
    // z = D⁻¹ y, then L x = z from the first row down.
    let mut x: Vec<ExprId> = (0..n).map(|i| g.mul(y[i], inv_d[i])).collect();
    for i in 0..n {
        for j in 0..i {
            let t = g.mul(h[i * n + j], x[j]);
            x[i] = g.sub(x[i], t);
        }
    }
    x
}
