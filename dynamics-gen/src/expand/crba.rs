//! Symbolic composite-rigid-body algorithm for the mass matrix (Featherstone's CRBA, in the
//! book's notation and in joint frames), over a tree with λ(i) the parent of i:
//!
//! ```text
//! I^c_i = G_i + Σ_{children c of i} [Ad_{T_{c,i}}]ᵀ I^c_c [Ad_{T_{c,i}}]     (i = n..1)
//! F = I^c_i A_i;  M_ii = A_iᵀ F;  for j = λ(i), λ(λ(i)), …:  F ← [Ad_{T_{k,j}}]ᵀ F (k the
//! previous joint on the path),  M_ji = A_jᵀ F
//! ```
//!
//! Entries between joints on different branches are structural zeros and never built. With
//! a floating base (body 0, inertia `G_0`, the six base dofs = its body twist): `I^c_0`, the
//! composite inertia of the whole robot, is the base block, and the `F` that reaches the base
//! is the base column of joint i (`M_{0i} = F`, the base dofs' "axes" being the unit twists).
//!
//! Only the lower triangle is computed; the upper one is its mirror.

use super::frames::BodyInertia;
use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// `M(θ)` as nv×nv symbolic entries, row-major, symmetric (nv = n, or n + 6 with a floating
/// base, whose inertia in its frame is `base`; its rows and columns come first).
pub fn crba(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    base: Option<&BodyInertia>,
) -> Vec<ExprId> {
    let n = joints.len();
    let off = if base.is_some() { 6 } else { 0 };
    let nv = n + off;
    let zero = g.zero();
    let mut m = vec![zero; nv * nv];
    let mut composite: Vec<Inertia> = joints
        .iter()
        .map(|jm| super::parameters::link_inertia(g, jm.frame))
        .collect();
    let mut base_composite = base.map(|b| Inertia::constant(g, b));
    for i in (0..n).rev() {
        match joints[i].frame.parent {
            Some(p) => {
                let moved = joints[i].inertia_to_parent(g, &composite[i]);
                composite[p] = Inertia::add(g, &composite[p], &moved);
            }
            None => {
                if let Some(b) = &base_composite {
                    let moved = joints[i].inertia_to_parent(g, &composite[i]);
                    base_composite = Some(Inertia::add(g, b, &moved));
                }
            }
        }
    }
    for i in 0..n {
        // F = I^c_i A_i.
        let z = g.zero3();
        let mut a = Spatial { ang: z, lin: z };
        let one = g.one();
        match joints[i].frame.kind {
            JointKind::Revolute => a.ang[2] = one,
            JointKind::Prismatic => a.lin[2] = one,
        }
        let mut f = composite[i].apply(g, &a);
        let (ri, mut k) = (off + i, i);
        m[ri * nv + ri] = component(&f, joints[i].frame.kind);
        while let Some(j) = joints[k].frame.parent {
            f = joints[k].force_to_parent(g, f);
            let mji = component(&f, joints[j].frame.kind);
            m[ri * nv + off + j] = mji;
            m[(off + j) * nv + ri] = mji;
            k = j;
        }
        if base.is_some() {
            f = joints[k].force_to_parent(g, f);
            let column = [f.ang, f.lin].concat();
            for (r, &x) in column.iter().enumerate() {
                m[ri * nv + r] = x;
                m[r * nv + ri] = x;
            }
        }
    }
    if let Some(ic) = &base_composite {
        // The base block: the composite inertia as a 6×6 matrix, column by column.
        for c in 0..6 {
            let z = g.zero3();
            let mut e = Spatial { ang: z, lin: z };
            let one = g.one();
            if c < 3 {
                e.ang[c] = one;
            } else {
                e.lin[c - 3] = one;
            }
            let col = ic.apply(g, &e);
            let col = [col.ang, col.lin].concat();
            for (r, &x) in col.iter().enumerate() {
                m[r * nv + c] = x;
            }
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
