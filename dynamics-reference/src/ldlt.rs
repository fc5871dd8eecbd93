//! The `L D Lᵀ` factorisation without pivoting and its singularity test, shared by the task
//! space and the constrained dynamics (the generated code applies the same test).

use nalgebra::{DMatrix, DVector};

/// `A = L D Lᵀ` of a symmetric matrix: `L` unit lower triangular, `D = diag(d)`.
pub(crate) struct Ldlt {
    /// `L`, unit lower triangular (the diagonal holds 1).
    l: DMatrix<f64>,
    /// The pivots `d_k`.
    d: DVector<f64>,
}

impl Ldlt {
    /// Factorises `a` (its lower triangle is read) row by row in the given order, no pivoting:
    /// ```text
    /// d_k  = A_kk − Σ_{j<k} L_kj² d_j
    /// L_ik = (A_ik − Σ_{j<k} L_ij L_kj d_j) / d_k        (i > k)
    /// ```
    /// `None` (numerically singular, or not positive definite) as soon as a diagonal entry
    /// `A_kk` is not positive and finite, or a pivot fails `d_k > √ε · A_kk` (ε =
    /// `f64::EPSILON`; NaN fails too).
    pub(crate) fn new(a: &DMatrix<f64>) -> Option<Self> {
        let n = a.nrows();
        assert_eq!(
            a.ncols(),
            n,
            "dynamics-reference: LDLᵀ of a non-square matrix"
        );
        let tol = f64::EPSILON.sqrt();
        let mut l = DMatrix::identity(n, n);
        let mut d = DVector::zeros(n);
        for k in 0..n {
            let a_kk = a[(k, k)];
            if !(a_kk > 0.0 && a_kk.is_finite()) {
                return None;
            }
            let mut d_k = a_kk;
            for j in 0..k {
                d_k -= l[(k, j)] * l[(k, j)] * d[j];
            }
            if d_k.is_nan() || d_k <= tol * a_kk {
                return None;
            }
            d[k] = d_k;
            for i in k + 1..n {
                let mut x = a[(i, k)];
                for j in 0..k {
                    x -= l[(i, j)] * l[(k, j)] * d[j];
                }
                l[(i, k)] = x / d_k;
            }
        }
        Some(Self { l, d })
    }

    /// `x = A⁻¹ b`: `L y = b` forward, `z = D⁻¹ y`, `Lᵀ x = z` backward.
    pub(crate) fn solve(&self, b: &DVector<f64>) -> DVector<f64> {
        let n = self.d.len();
        let mut x = b.clone();
        for i in 0..n {
            for j in 0..i {
                x[i] -= self.l[(i, j)] * x[j];
            }
        }
        for i in 0..n {
            x[i] /= self.d[i];
        }
        for i in (0..n).rev() {
            for j in i + 1..n {
                x[i] -= self.l[(j, i)] * x[j];
            }
        }
        x
    }

    /// `A⁻¹`, column by column, made exactly symmetric (`(X + Xᵀ)/2`).
    pub(crate) fn inverse(&self) -> DMatrix<f64> {
        let n = self.d.len();
        let mut inv = DMatrix::zeros(n, n);
        for k in 0..n {
            let mut e_k = DVector::zeros(n);
            e_k[k] = 1.0;
            inv.column_mut(k).copy_from(&self.solve(&e_k));
        }
        (&inv + inv.transpose()) * 0.5
    }
}

#[cfg(test)]
mod tests {
    use super::Ldlt;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn solves_and_inverts() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0]);
        let f = Ldlt::new(&a).expect("positive definite");
        let b = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let x = f.solve(&b);
        assert!((&a * x - b).amax() < 1e-15);
        assert!((&a * f.inverse() - DMatrix::identity(3, 3)).amax() < 1e-15);
    }

    #[test]
    fn refuses_singular_and_indefinite_matrices() {
        // Rank 1: the second pivot is 0.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        assert!(Ldlt::new(&a).is_none());
        // A pivot just above √ε·A_kk passes, one just below fails.
        let s = f64::EPSILON.sqrt();
        let near = |p: f64| DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0 + p]);
        assert!(Ldlt::new(&near(4.0 * s)).is_some());
        assert!(Ldlt::new(&near(0.25 * s)).is_none());
        // Non-positive or non-finite diagonal.
        assert!(Ldlt::new(&DMatrix::from_row_slice(1, 1, &[0.0])).is_none());
        assert!(Ldlt::new(&DMatrix::from_row_slice(1, 1, &[-1.0])).is_none());
        assert!(Ldlt::new(&DMatrix::from_row_slice(1, 1, &[f64::NAN])).is_none());
        assert!(Ldlt::new(&DMatrix::from_row_slice(1, 1, &[f64::INFINITY])).is_none());
        // Indefinite: negative second pivot.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(Ldlt::new(&a).is_none());
    }
}
