//! Symbolic composite-rigid-body algorithm for the mass matrix (Featherstone's CRBA, in the
//! book's notation and in joint frames).
//!
//! ```text
//! I^c_n = G_n;   I^c_{i−1} = G_{i−1} + [Ad_{T_{i,i−1}}]ᵀ I^c_i [Ad_{T_{i,i−1}}]
//! F = I^c_i A_i;  M_ii = A_iᵀ F;  for j = i−1..1:  F ← [Ad_{T_{j+1,j}}]ᵀ F,  M_ji = A_jᵀ F
//! ```
//!
//! Only the lower triangle is computed; the upper one is its mirror.

use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// `M(θ)` as n×n symbolic entries, row-major, symmetric.
pub fn crba(g: &mut ExprGraph, joints: &[JointMotion<'_>]) -> Vec<ExprId> {
    let n = joints.len();
    let zero = g.zero();
    let mut m = vec![zero; n * n];
    let mut composite: Vec<Option<Inertia>> = vec![None; n];
    for i in (0..n).rev() {
        let mut ic = Inertia::constant(g, &joints[i].frame.inertia);
        if i + 1 < n {
            if let Some(child) = &composite[i + 1] {
                let moved = joints[i + 1].inertia_to_parent(g, child);
                ic = Inertia::add(g, &ic, &moved);
            }
        }
        composite[i] = Some(ic);
    }
    for i in 0..n {
        let Some(ic) = &composite[i] else { continue };
        // F = I^c_i A_i.
        let z = g.zero3();
        let mut a = Spatial { ang: z, lin: z };
        let one = g.one();
        match joints[i].frame.kind {
            JointKind::Revolute => a.ang[2] = one,
            JointKind::Prismatic => a.lin[2] = one,
        }
        let mut f = ic.apply(g, &a);
        m[i * n + i] = component(&f, joints[i].frame.kind);
        for j in (0..i).rev() {
            f = joints[j + 1].force_to_parent(g, f);
            let mji = component(&f, joints[j].frame.kind);
            m[i * n + j] = mji;
            m[j * n + i] = mji;
        }
    }
    m
}

fn component(f: &Spatial, kind: JointKind) -> ExprId {
    match kind {
        JointKind::Revolute => f.ang[2],
        JointKind::Prismatic => f.lin[2],
    }
}
