//! The error of the reference dynamics.

use std::fmt;

/// What can go wrong in the reference dynamics for a valid call.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ReferenceError {
    /// `M(θ)` is not (numerically) positive definite, so `M θ̈ = rhs` has no unique solution:
    /// the Cholesky factorisation failed.
    MassMatrixNotPositiveDefinite {
        /// The configuration θ.
        q: Vec<f64>,
        /// The row of the trajectory being integrated, for [`crate::forward_dynamics_trajectory`].
        step: Option<usize>,
    },
}

impl fmt::Display for ReferenceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReferenceError::MassMatrixNotPositiveDefinite { q, step } => {
                write!(
                    f,
                    "the mass matrix M(θ) is not positive definite at θ = {q:?}"
                )?;
                if let Some(k) = step {
                    write!(f, " (trajectory row {k})")?;
                }
                write!(
                    f,
                    "; forward dynamics needs every joint to move some mass or inertia: \
                     give the links beyond each joint a positive mass or rotational inertia about that joint's axis"
                )
            }
        }
    }
}

impl std::error::Error for ReferenceError {}
