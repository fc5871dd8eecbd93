//! The kinetic energy by the bodies' twists (Featherstone, *Rigid Body Dynamics Algorithms*,
//! §2.13), in joint frames:
//!
//! ```text
//! forward, i = 1..n:  V_i = [Ad_{T_{i,i−1}}] V_{i−1} + A_i θ̇_i          (as in Newton–Euler)
//! K = Σ_i ½ V_iᵀ G_i V_i,   ½ Vᵀ G V = ½ ωᵀ I_o ω + h · (v × ω) + ½ m v · v
//! ```
//!
//! with `V = (ω, v)`, `G = [[I_o, [h]], [[h]ᵀ, m·1₃]]` (`h = m c`, `I_o` about the frame's
//! origin), `V_0` the base's twist (zero for a fixed base), plus a floating base's own
//! `½ V_0ᵀ G_0 V_0` and the rotors' `½ a_i θ̇_i²` (armature). It equals `½ νᵀ M ν` with the
//! mass matrix of [`super::crba`] and needs no mass matrix: a forward pass and a quadratic form
//! per body, about 25 multiplications each against the `n²` entries of `M` and the products
//! that build them.

use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use crate::expr::{ExprGraph, ExprId};

/// `K` for the joints' rates `qd` (one per joint, in the order of `joints`), the base's twist
/// `v0`, a floating base's inertia `base_inertia` and the joints' armatures `armature` (one
/// per joint).
pub fn kinetic_energy(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    v0: Spatial,
    base_inertia: Option<&super::frames::BodyInertia>,
    qd: &[ExprId],
    armature: &[f64],
) -> ExprId {
    let twists = super::lagrangian::link_twists(g, joints, v0, qd);
    let mut terms = Vec::with_capacity(2 * joints.len() + 1);
    for (i, (jm, v)) in joints.iter().zip(&twists).enumerate() {
        let gi = super::parameters::link_inertia(g, jm.frame);
        terms.push(body_energy(g, &gi, v));
        if armature[i] != 0.0 {
            let sq = g.mul(qd[i], qd[i]);
            terms.push(g.cmul(0.5 * armature[i], sq));
        }
    }
    if let Some(b) = base_inertia {
        let gb = Inertia::constant(g, b);
        terms.push(body_energy(g, &gb, &v0));
    }
    g.sum(&terms)
}

/// `½ Vᵀ G V = ½ ωᵀ I_o ω + h · (v × ω) + ½ m v · v` of one body.
fn body_energy(g: &mut ExprGraph, gi: &Inertia, v: &Spatial) -> ExprId {
    let [wx, wy, wz] = v.ang;
    let [xx, yy, zz, xy, xz, yz] = gi.i;
    let half = g.constant(0.5);
    // ½ ωᵀ I_o ω = ½ (I_xx ω_x² + I_yy ω_y² + I_zz ω_z²) + I_xy ω_x ω_y + I_xz ω_x ω_z + I_yz ω_y ω_z.
    let squares = [g.mul(wx, wx), g.mul(wy, wy), g.mul(wz, wz)];
    let diagonal = g.dot(&[xx, yy, zz], &squares);
    let diagonal = g.mul(half, diagonal);
    let products = [g.mul(wx, wy), g.mul(wx, wz), g.mul(wy, wz)];
    let off_diagonal = g.dot(&[xy, xz, yz], &products);
    let vxw = g.cross(v.lin, v.ang);
    let coupling = g.dot(&gi.h, &vxw);
    let vv = g.dot(&v.lin, &v.lin);
    let half_m = g.mul(half, gi.m);
    let translational = g.mul(half_m, vv);
    g.sum(&[diagonal, off_diagonal, coupling, translational])
}
