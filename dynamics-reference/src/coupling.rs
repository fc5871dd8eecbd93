//! Mimic joints: the map between the independent coordinates a caller passes and the physical
//! joints the algorithms run on ([`dynamics_model::mimic`]).
//!
//! With `x` the independent joint values, `θ = J x + o`, where row i of the constant n×k
//! matrix `J` holds `m_i` in the column of joint i's leader (1 in its own column for an
//! independent joint) and `o_i` the offset; a floating base's seven q entries and six ν
//! entries pass unchanged (`J` is the identity there). Because `J` is constant (`J̇ = 0`),
//! ```text
//! q_phys = (q_base, J x + o),    ν_phys = (ν_base, J ẋ),    ν̇_phys = (ν̇_base, J ẍ)
//! ```
//! and every result of the physical algorithms is projected by the principle of virtual
//! work: a force-like vector by `Jᵀ` (`τ = Jᵀ τ_phys`), a matrix of the equations of motion
//! by `Jᵀ · J` (`M = Jᵀ M_phys J`, `Ṁ = Jᵀ Ṁ_phys J`), a Jacobian by `· J` (`J_s = J_s,phys J`).
//! Energies and poses need no projection. Forward dynamics then solves `M ẍ = τ − Jᵀ bias_phys`
//! with the projected M and bias, and the Coriolis matrix of the Christoffel symbols of the
//! projected M equals `Jᵀ C_phys J` (J is constant), so both need nothing of their own.

use dynamics_model::{Coupling, Robot};
use nalgebra::{DMatrix, DVector};

/// A robot with mimic joints, seen as its physical robot (every joint independent) and `J`.
pub(crate) struct Coupled {
    /// The same robot with no joint coupled: the algorithms run on it.
    pub physical: Robot,
    /// `J`, nv_phys × nv (the floating base's 6×6 identity block first).
    j: DMatrix<f64>,
    /// The joint rows: how each physical joint follows the coordinates.
    couplings: Vec<Coupling>,
    /// The floating base's entries in q (7) and ν (6), or 0.
    base_q: usize,
    base_v: usize,
}

impl Coupled {
    /// The coupled view of `robot`, `None` when no joint mimics another (the algorithms then
    /// run on `robot` itself, unchanged).
    pub fn of(robot: &Robot) -> Option<Self> {
        if !robot.has_mimic() {
            return None;
        }
        let couplings = robot.couplings();
        let mut physical = robot.clone();
        for joint in &mut physical.joints {
            joint.mimic = None;
        }
        let (base_q, base_v) = if robot.base.floating { (7, 6) } else { (0, 0) };
        let mut j = DMatrix::zeros(physical.nv(), robot.nv());
        for b in 0..base_v {
            j[(b, b)] = 1.0;
        }
        for (i, c) in couplings.iter().enumerate() {
            j[(base_v + i, base_v + c.coordinate)] = c.multiplier;
        }
        Some(Self {
            physical,
            j,
            couplings,
            base_q,
            base_v,
        })
    }

    /// `q_phys = (q_base, J x + o)` from the caller's `q`.
    pub fn q(&self, q: &[f64]) -> Vec<f64> {
        let x = &q[self.base_q..];
        let mut out = q[..self.base_q].to_vec();
        out.extend(
            self.couplings
                .iter()
                .map(|c| c.multiplier * x[c.coordinate] + c.offset),
        );
        out
    }

    /// `ν_phys = (ν_base, J ẋ)` from a velocity or acceleration of the caller.
    pub fn v(&self, v: &[f64]) -> Vec<f64> {
        let x = &v[self.base_v..];
        let mut out = v[..self.base_v].to_vec();
        out.extend(
            self.couplings
                .iter()
                .map(|c| c.multiplier * x[c.coordinate]),
        );
        out
    }

    /// `Jᵀ f` for a force-like vector of the physical robot.
    pub fn forces(&self, f: &DVector<f64>) -> DVector<f64> {
        self.j.transpose() * f
    }

    /// `Jᵀ A J` for a symmetric matrix of the physical equations of motion (M, Ṁ), made
    /// exactly symmetric (`(X + Xᵀ)/2`: the two triangles are summed in different orders).
    pub fn matrix(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        let x = self.j.transpose() * a * &self.j;
        (&x + x.transpose()) * 0.5
    }

    /// `A J` for a Jacobian of the physical robot (columns per physical velocity).
    pub fn columns(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        a * &self.j
    }
}
