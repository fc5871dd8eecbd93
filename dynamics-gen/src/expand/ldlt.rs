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
    let n = b.len();
    let zero = g.zero();
    let one = g.one();
    let mut l = vec![zero; n * n];
    let mut inv_d = vec![one; n];
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
        inv_d[j] = g.div(one, d);
    }
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
