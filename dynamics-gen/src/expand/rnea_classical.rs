//! Symbolic Newton–Euler with classical accelerations (the Luh–Walker–Paul form), in joint
//! frames: the same τ as [`super::rnea`], often with fewer operations once the masses have
//! been regrouped onto the base (see `frames::regroup`).
//!
//! ```text
//! forward, i = 1..n (K: frame {J_i} before the joint's own motion, C_i = (R, p)):
//!   ω_K = R ω_{i−1},  ω̇_K = R ω̇_{i−1},  r = −p (origin of K seen from {J_{i−1}}, in K)
//!   a_K = R a_{i−1} + ω̇_K × r + ω_K × (ω_K × r)
//!   revolute:  ω_i = Rot_z(−θ) ω_K + θ̇ e_z,  ω̇_i = Rot_z(−θ) ω̇_K + ω_i × e_z θ̇ + θ̈ e_z,
//!              a_i = Rot_z(−θ) a_K
//!   prismatic: ω_i = ω_K,  ω̇_i = ω̇_K,  with s = (0, 0, θ):
//!              a_i = a_K + ω̇_i × s + ω_i × (ω_i × s) + 2 ω_i × e_z θ̇ + θ̈ e_z
//!   n_i = I_i ω̇_i + ω_i × I_i ω_i + h_i × a_i,   f_i = m_i a_i + ω̇_i × h_i + ω_i × (ω_i × h_i)
//!   with ω × (ω × r) = ω (ω·r) − r |ω|², and |ω_i|² = |ω_{i−1}|² + θ̇_i (2 ω_{K,z} + θ̇_i) carried along
//! backward, i = n..1:  F_i = (n_i, f_i) + [Ad_{T_{i+1,i}}]ᵀ F_{i+1},  τ_i = F_iᵀ A_i
//! ```
//!
//! with `ω_0 = ω̇_0 = 0` and `a_0 = −g` on a fixed base (gravity is an upward acceleration of
//! the base), or the floating base's `ω_0`, `ω̇_0` and `a_0 = v̇_0 + ω_0 × v_0 − g_0`; on a
//! tree `i − 1` reads `λ(i)` and the backward pass adds each wrench into its parent's.

use super::frames::BodyInertia;
use super::rnea::{link_force, BaseMotion, LinkForce};
use super::spatial::{rot_z_t, Inertia, JointMotion, Spatial, VectorOps, V3};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// `ω × (ω × r) = ω (ω·r) − r |ω|²`, with `|ω|²` given (it is carried along the chain).
fn double_cross(g: &mut ExprGraph, w: V3, w_sq: ExprId, r: V3) -> V3 {
    let wr = g.dot(&w, &r);
    let a = g.scale3(wr, w);
    let b = g.scale3(w_sq, r);
    g.sub3(a, b)
}

/// `a + ω̇ × r + ω × (ω × r)`: the acceleration of a point at `r` on a body.
fn transport(g: &mut ExprGraph, a: V3, w: V3, w_sq: ExprId, wd: V3, r: V3) -> V3 {
    let wdr = g.cross(wd, r);
    let wwr = double_cross(g, w, w_sq, r);
    let t = g.add3(wdr, wwr);
    g.add3(a, t)
}

/// The generalised forces for the given symbolic velocities and accelerations and the
/// base's motion, as [`super::rnea::rnea`] (base entries first with a floating base;
/// `external` as there).
pub fn rnea_classical(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    base: &BaseMotion,
    base_inertia: Option<&BodyInertia>,
    qd: &[ExprId],
    qdd: &[ExprId],
    external: Option<&super::rnea::ExternalWrench>,
) -> Vec<ExprId> {
    let n = joints.len();
    // The base's ω, |ω|², ω̇ and the classical acceleration a = v̇ + ω × v of its origin.
    let base_w = base.v.ang;
    let base_w_sq = g.dot(&base_w, &base_w);
    let base_wxv = g.cross(base.v.ang, base.v.lin);
    let base_a = g.add3(base.vd.lin, base_wxv);
    // Per joint: ω, |ω|² (carried along: a rotation keeps it, and a revolute joint adds
    // θ̇ (2 ω_z + θ̇)), ω̇, a.
    let mut states: Vec<(V3, ExprId, V3, V3)> = Vec::with_capacity(n);
    let mut forces = Vec::with_capacity(n);
    for (i, jm) in joints.iter().enumerate() {
        let (mut w, mut w_sq, mut wd, mut a) = match jm.frame.parent {
            Some(p) => states[p],
            None => (base_w, base_w_sq, base.vd.ang, base_a),
        };
        let f = jm.frame;
        let w_k = g.rot(&f.r, w);
        let wd_k = g.rot(&f.r, wd);
        let ra = g.rot(&f.r, a);
        let r = g.const3([-f.p[0], -f.p[1], -f.p[2]]);
        let a_k = transport(g, ra, w_k, w_sq, wd_k, r);
        match f.kind {
            JointKind::Revolute => {
                w = rot_z_t(g, jm.sin, jm.cos, w_k);
                wd = rot_z_t(g, jm.sin, jm.cos, wd_k);
                a = rot_z_t(g, jm.sin, jm.cos, a_k);
                // ω_i × e_z θ̇ = (ω_y θ̇, −ω_x θ̇, 0) (θ̇ e_z itself drops out of the cross).
                let t0 = g.mul(w[1], qd[i]);
                let t1 = g.mul(w[0], qd[i]);
                wd[0] = g.add(wd[0], t0);
                wd[1] = g.sub(wd[1], t1);
                wd[2] = g.add(wd[2], qdd[i]);
                let two_wz = g.cmul(2.0, w[2]);
                let grow = g.add(two_wz, qd[i]);
                let grow = g.mul(qd[i], grow);
                w_sq = g.add(w_sq, grow);
                w[2] = g.add(w[2], qd[i]);
            }
            JointKind::Prismatic => {
                w = w_k;
                wd = wd_k;
                let zero = g.zero();
                let s = [zero, zero, jm.q];
                a = transport(g, a_k, w, w_sq, wd, s);
                // 2 ω × e_z θ̇ = 2θ̇ (ω_y, −ω_x, 0).
                let two_qd = g.cmul(2.0, qd[i]);
                let t0 = g.mul(w[1], two_qd);
                let t1 = g.mul(w[0], two_qd);
                a[0] = g.add(a[0], t0);
                a[1] = g.sub(a[1], t1);
                a[2] = g.add(a[2], qdd[i]);
            }
        }
        let gi = super::parameters::link_inertia(g, f);
        let iwd = gi.rotational(g, wd);
        let iw = gi.rotational(g, w);
        let w_iw = g.cross(w, iw);
        let hxa = g.cross(gi.h, a);
        let n1 = g.add3(iwd, w_iw);
        let ma = g.scale3(gi.m, a);
        let wdxh = g.cross(wd, gi.h);
        let wwh = double_cross(g, w, w_sq, gi.h);
        let f1 = g.add3(ma, wdxh);
        forces.push(Spatial {
            ang: g.add3(n1, hxa),
            lin: g.add3(f1, wwh),
        });
        states.push((w, w_sq, wd, a));
    }
    let base_force = base_inertia.map(|b| {
        let gb = Inertia::constant(g, b);
        link_force(g, &gb, &base.v, &base.vd, LinkForce::Classical)
    });
    super::rnea::backward_pass(g, joints, &forces, base_force, external)
}
