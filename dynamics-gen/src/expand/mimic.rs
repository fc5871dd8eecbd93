//! Mimic joints in the expansion: the graph's inputs are the independent coordinates, the
//! recursions run on the physical joints, and their outputs are projected back.
//!
//! With `x` the independent joint values and `J`, `o` of [`dynamics_model::mimic`] (joint i
//! follows coordinate k(i) with multiplier `m_i` and offset `o_i`; an independent joint has
//! `m = 1`, `o = 0`; a floating base's entries pass unchanged):
//! ```text
//! θ_i = m_i x_k(i) + o_i,    θ̇_i = m_i ẋ_k(i),    θ̈_i = m_i ẍ_k(i)      (J constant, J̇ = 0)
//! τ_x = Jᵀ τ:   τ_x,k = Σ_{i: k(i) = k} m_i τ_i
//! M_x = Jᵀ M J: M_x,kl = Σ_{i: k(i) = k} Σ_{j: k(j) = l} m_i m_j M_ij
//! ```
//! and likewise `c_x = Jᵀ c`, `g_x = Jᵀ g`. The offset `o_i` joins the joint's home offset in
//! its frame ([`offsets`]), so a follower's angle costs one multiplication (none for `m = ±1`
//! up to a negation). Forward dynamics solves `M_x ẍ = τ_x − Jᵀ (c + g)` by LDLᵀ; the
//! articulated-body recursion assumes one coordinate per joint and is not expanded for
//! coupled robots. Without mimic joints every function here returns its input unchanged.

use super::frames::JointFrames;
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::Robot;

/// The coupling of a robot's physical joints to its coordinates.
#[derive(Clone, Debug)]
pub struct Coupling {
    /// The floating base's entries in ν (6) or 0.
    ov: usize,
    /// For every physical joint: its coordinate (in the joint part) and multiplier.
    rows: Vec<(usize, f64)>,
    /// For every entry of the reduced ν: the entries of the physical ν that follow it, with
    /// their multipliers (the base's entries: themselves).
    members: Vec<Vec<(usize, f64)>>,
    /// No joint mimics another.
    identity: bool,
}

impl Coupling {
    /// The coupling of `robot` (a validated robot).
    pub fn new(robot: &Robot) -> Self {
        let ov = if robot.base.floating { 6 } else { 0 };
        let rows: Vec<(usize, f64)> = robot
            .couplings()
            .iter()
            .map(|c| (c.coordinate, c.multiplier))
            .collect();
        let mut members: Vec<Vec<(usize, f64)>> = (0..ov).map(|b| vec![(b, 1.0)]).collect();
        members.extend((0..robot.n_coordinates()).map(|_| Vec::new()));
        for (i, &(k, m)) in rows.iter().enumerate() {
            members[ov + k].push((ov + i, m));
        }
        Self {
            ov,
            rows,
            members,
            identity: !robot.has_mimic(),
        }
    }

    /// Whether no joint mimics another.
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// The physical joints that follow reduced ν entry `r` (base entries: themselves), as
    /// indices into the physical ν.
    pub fn members(&self, r: usize) -> impl Iterator<Item = usize> + '_ {
        self.members[r].iter().map(|&(i, _)| i)
    }

    /// `m_i x_k(i)` for every physical joint, from the joint coordinates `x` (the offsets are
    /// in the frames, [`offsets`]).
    pub fn positions(&self, g: &mut ExprGraph, x: &[ExprId]) -> Vec<ExprId> {
        if self.identity {
            return x.to_vec();
        }
        self.rows.iter().map(|&(k, m)| scaled(g, m, x[k])).collect()
    }

    /// `(ν_base, J ẋ)`: a physical velocity or acceleration from a reduced one.
    pub fn rates(&self, g: &mut ExprGraph, v: &[ExprId]) -> Vec<ExprId> {
        if self.identity {
            return v.to_vec();
        }
        let mut out = v[..self.ov].to_vec();
        out.extend(self.rows.iter().map(|&(k, m)| scaled(g, m, v[self.ov + k])));
        out
    }

    /// `Jᵀ f`: a reduced force from a physical one.
    pub fn forces(&self, g: &mut ExprGraph, f: &[ExprId]) -> Vec<ExprId> {
        if self.identity {
            return f.to_vec();
        }
        self.members
            .iter()
            .map(|terms| weighted_sum(g, terms.iter().map(|&(i, m)| (m, f[i]))))
            .collect()
    }

    /// `Jᵀ M J` (row-major) from the physical `M` (row-major, nv_phys × nv_phys); symmetric
    /// by construction (the lower triangle is the upper's nodes).
    pub fn matrix(&self, g: &mut ExprGraph, m: &[ExprId]) -> Vec<ExprId> {
        if self.identity {
            return m.to_vec();
        }
        let (n_full, n) = (self.ov + self.rows.len(), self.members.len());
        // MJ, column by column: (MJ)_{i,c} = Σ_{j ∈ c} m_j M_ij.
        let mj: Vec<Vec<ExprId>> = (0..n)
            .map(|c| {
                (0..n_full)
                    .map(|i| {
                        let terms = self.members[c].iter().map(|&(j, w)| (w, m[i * n_full + j]));
                        weighted_sum(g, terms)
                    })
                    .collect()
            })
            .collect();
        let mut out = vec![g.zero(); n * n];
        for r in 0..n {
            for c in r..n {
                let terms = self.members[r].iter().map(|&(i, w)| (w, mj[c][i]));
                let x = weighted_sum(g, terms);
                out[r * n + c] = x;
                out[c * n + r] = x;
            }
        }
        out
    }
}

/// Adds every follower's mimic offset `o_i` to its joint's home offset in `frames`, so that
/// the joint's angle is `m_i x + (o_i + θ₀)`.
pub fn offsets(frames: &mut JointFrames, robot: &Robot) {
    let couplings = robot.couplings();
    for (i, frame) in frames.joints.iter_mut().enumerate() {
        if robot.joints[i].mimic.is_some() {
            frame.offset += couplings[i].offset;
        }
    }
}

/// `m·x`: `x` itself for m = 1, `−x` for m = −1.
fn scaled(g: &mut ExprGraph, m: f64, x: ExprId) -> ExprId {
    if m == 1.0 {
        x
    } else if m == -1.0 {
        g.neg(x)
    } else {
        let c = g.constant(m);
        g.mul(c, x)
    }
}

/// `Σ m_t x_t` in the order given (0 for no terms); `±1` weights add or subtract.
fn weighted_sum(g: &mut ExprGraph, terms: impl Iterator<Item = (f64, ExprId)>) -> ExprId {
    let mut acc: Option<ExprId> = None;
    for (m, x) in terms {
        acc = Some(match acc {
            None => scaled(g, m, x),
            Some(a) if m == 1.0 => g.add(a, x),
            Some(a) if m == -1.0 => g.sub(a, x),
            Some(a) => {
                let t = scaled(g, m, x);
                g.add(a, t)
            }
        });
    }
    acc.unwrap_or_else(|| g.zero())
}
