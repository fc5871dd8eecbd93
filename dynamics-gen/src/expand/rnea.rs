//! Symbolic recursive Newton–Euler inverse dynamics (Modern Robotics §8.3.2), in joint frames.
//!
//! ```text
//! forward, i = 1..n:   V_i  = [Ad_{T_{i,i−1}}] V_{i−1} + A_i θ̇_i
//!                      V̇_i  = [Ad_{T_{i,i−1}}] V̇_{i−1} + [ad_{V_i}] A_i θ̇_i + A_i θ̈_i
//! backward, i = n..1:  F_i  = [Ad_{T_{i+1,i}}]ᵀ F_{i+1} + G_i V̇_i − [ad_{V_i}]ᵀ G_i V_i
//!                      τ_i  = F_iᵀ A_i
//! ```
//!
//! with `V_0 = 0`, `V̇_0 = (0, −g)` (gravity enters as an upward acceleration of the base) and
//! `F_{n+1} = 0`. In joint frames `A_i` is `e_z` in the angular (revolute) or linear
//! (prismatic) part, so `[ad_{V_i}] A_i θ̇_i` and `τ_i` are single components.
//!
//! `τ = M(θ) θ̈ + c(θ, θ̇) + g(θ)`; `g(θ)` is this with `θ̇ = θ̈ = 0`, `c(θ, θ̇)` with `θ̈ = 0` and
//! no gravity.

use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// How the link wrench `F_i = G_i V̇_i − [ad_{V_i}]ᵀ G_i V_i` is written out; the two forms
/// are equal, and which needs fewer operations depends on the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkForce {
    /// Spatial: momentum `G V` and the spatial cross product.
    Spatial,
    /// Classical: `n = I ω̇ + ω × I ω + h × a`, `f = m a + ω̇ × h + ω × (ω × h)` with the
    /// classical acceleration `a = v̇ + ω × v`.
    Classical,
}

/// The base's motion seen by the recursions: its twist `V_0` and its acceleration with
/// gravity folded in, `V̇_0 − (0, g_0)` (g_0: gravity in the base frame). A fixed base has
/// `V_0 = 0` and `V̇_0 = (0, −g)`; a floating one its body twist and acceleration from the
/// inputs, and gravity turned into the base frame (see [`super::base`]).
#[derive(Clone, Copy, Debug)]
pub struct BaseMotion {
    /// `V_0`.
    pub v: Spatial,
    /// `V̇_0 − (0, g_0)`.
    pub vd: Spatial,
}

/// A wrench the robot applies to its environment at one body, in that body's joint frame
/// (`F_{n+1}` of Modern Robotics §8.3.2, the end effector's `F_tip` moved to its link's
/// joint frame): the backward pass adds it to the body's own wrench, so that it reaches the
/// base along the rotations the pass makes anyway.
#[derive(Clone, Copy, Debug)]
pub struct ExternalWrench {
    /// The joint whose child body carries it; `None`: the base (no torque on a fixed one).
    pub joint: Option<usize>,
    /// `(m, f)` in that joint's frame (in {0} on the base).
    pub wrench: Spatial,
}

/// The generalised forces for the given symbolic velocities and accelerations (use constant
/// zeros to drop terms), the base's motion `base` included: with a floating base
/// (`base_inertia`, in the base frame) the six base entries (the wrench `(m, f)` on the
/// base, in its frame) come first; `external`: a wrench the robot applies as well.
#[allow(clippy::too_many_arguments)]
pub fn rnea(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    base: &BaseMotion,
    base_inertia: Option<&super::frames::BodyInertia>,
    qd: &[ExprId],
    qdd: &[ExprId],
    form: LinkForce,
    external: Option<&ExternalWrench>,
) -> Vec<ExprId> {
    let n = joints.len();
    let mut vs: Vec<Spatial> = Vec::with_capacity(n);
    let mut vds: Vec<Spatial> = Vec::with_capacity(n);
    let mut forces = Vec::with_capacity(n);
    // Forward pass: twists and accelerations; the link wrench G V̇ − adᵀ_V G V.
    for (i, jm) in joints.iter().enumerate() {
        let (v, vd) = match jm.frame.parent {
            Some(p) => (vs[p], vds[p]),
            None => (base.v, base.vd),
        };
        let mut vi = jm.motion_to_child(g, v);
        let mut vdi = jm.motion_to_child(g, vd);
        // [ad_V] A θ̇: for A = (e_z, 0) it is (ω × e_z, v × e_z) θ̇; for A = (0, e_z), (0, ω × e_z) θ̇.
        let (ad_ang, ad_lin) = match jm.frame.kind {
            JointKind::Revolute => {
                let a = [vi.ang[1], g.neg(vi.ang[0]), g.zero()];
                let b = [vi.lin[1], g.neg(vi.lin[0]), g.zero()];
                (a, b)
            }
            JointKind::Prismatic => {
                let b = [vi.ang[1], g.neg(vi.ang[0]), g.zero()];
                (g.zero3(), b)
            }
        };
        let ad_ang = g.scale3(qd[i], ad_ang);
        let ad_lin = g.scale3(qd[i], ad_lin);
        vdi.ang = g.add3(vdi.ang, ad_ang);
        vdi.lin = g.add3(vdi.lin, ad_lin);
        let k = match jm.frame.kind {
            JointKind::Revolute => &mut vi.ang[2],
            JointKind::Prismatic => &mut vi.lin[2],
        };
        *k = g.add(*k, qd[i]);
        let k = match jm.frame.kind {
            JointKind::Revolute => &mut vdi.ang[2],
            JointKind::Prismatic => &mut vdi.lin[2],
        };
        *k = g.add(*k, qdd[i]);
        let gi = super::parameters::link_inertia(g, jm.frame);
        forces.push(link_force(g, &gi, &vi, &vdi, form));
        vs.push(vi);
        vds.push(vdi);
    }
    let base_force = base_inertia.map(|b| {
        let gb = Inertia::constant(g, b);
        link_force(g, &gb, &base.v, &base.vd, form)
    });
    backward_pass(g, joints, &forces, base_force, external)
}

/// The wrench `F = G V̇ − [ad_V]ᵀ G V` of a body with inertia `gi`, twist `v` and
/// acceleration `vd`, written out as `form` says.
pub fn link_force(
    g: &mut ExprGraph,
    gi: &Inertia,
    vi: &Spatial,
    vdi: &Spatial,
    form: LinkForce,
) -> Spatial {
    let (f_ang, f_lin) = match form {
        LinkForce::Spatial => {
            // F = G V̇ − [ad_V]ᵀ G V, with −[ad_V]ᵀ (k, l) = (ω × k + v × l, ω × l).
            let gvd = gi.apply(g, vdi);
            let p = gi.apply(g, vi);
            let wk = g.cross(vi.ang, p.ang);
            let vl = g.cross(vi.lin, p.lin);
            let wl = g.cross(vi.ang, p.lin);
            let bias_ang = g.add3(wk, vl);
            (g.add3(gvd.ang, bias_ang), g.add3(gvd.lin, wl))
        }
        LinkForce::Classical => {
            // The same wrench through the classical acceleration a = v̇ + ω × v of the
            // frame's origin: n = I ω̇ + ω × I ω + h × a, f = m a + ω̇ × h + ω × (ω × h).
            let wxv = g.cross(vi.ang, vi.lin);
            let a = g.add3(vdi.lin, wxv);
            let iwd = gi.rotational(g, vdi.ang);
            let iw = gi.rotational(g, vi.ang);
            let w_iw = g.cross(vi.ang, iw);
            let hxa = g.cross(gi.h, a);
            let n1 = g.add3(iwd, w_iw);
            let ma = g.scale3(gi.m, a);
            let wdxh = g.cross(vdi.ang, gi.h);
            let wxh = g.cross(vi.ang, gi.h);
            let wwh = g.cross(vi.ang, wxh);
            let f1 = g.add3(ma, wdxh);
            (g.add3(n1, hxa), g.add3(f1, wwh))
        }
    };
    Spatial {
        ang: f_ang,
        lin: f_lin,
    }
}

/// The backward pass shared by the Newton–Euler forms: accumulate the link wrenches toward
/// the base, `F_λ(i) += [Ad_{T_{i,λ(i)}}]ᵀ F_i` (children before parents: reverse order),
/// and read `τ_i = A_iᵀ F_i`; with a floating base (`base_force` = the base body's own
/// wrench) the six base entries, the total wrench on the base, come first. `external` is
/// added to its body's wrench first.
pub fn backward_pass(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    forces: &[Spatial],
    base_force: Option<Spatial>,
    external: Option<&ExternalWrench>,
) -> Vec<ExprId> {
    let n = joints.len();
    let mut acc = forces.to_vec();
    let mut base = base_force;
    if let Some(e) = external {
        let target = match e.joint {
            Some(j) => Some(&mut acc[j]),
            None => base.as_mut(),
        };
        if let Some(t) = target {
            *t = Spatial {
                ang: g.add3(t.ang, e.wrench.ang),
                lin: g.add3(t.lin, e.wrench.lin),
            };
        }
    }
    let mut tau = vec![g.zero(); n];
    for i in (0..n).rev() {
        let f = acc[i];
        tau[i] = match joints[i].frame.kind {
            JointKind::Revolute => f.ang[2],
            JointKind::Prismatic => f.lin[2],
        };
        let target = match joints[i].frame.parent {
            Some(p) => &mut acc[p],
            None => match &mut base {
                Some(b) => b,
                None => continue,
            },
        };
        let fp = joints[i].force_to_parent(g, f);
        let sum = Spatial {
            ang: g.add3(target.ang, fp.ang),
            lin: g.add3(target.lin, fp.lin),
        };
        *target = sum;
    }
    match base {
        Some(b) => {
            let mut out = Vec::with_capacity(n + 6);
            out.extend(b.ang);
            out.extend(b.lin);
            out.extend(tau);
            out
        }
        None => tau,
    }
}
