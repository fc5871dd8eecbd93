//! Symbolic forward dynamics by the articulated-body algorithm (Featherstone, *Rigid Body
//! Dynamics Algorithms*, ch. 7), in joint frames and the book's twist/wrench conventions.
//!
//! ```text
//! pass 1, i = 1..n:   V_i   = [Ad_{T_{i,i−1}}] V_{i−1} + S_i θ̇_i
//!                     c_i   = [ad_{V_i}] S_i θ̇_i
//!                     I^A_i = G_i,   p^A_i = −[ad_{V_i}]ᵀ G_i V_i
//! pass 2, i = n..1:   U_i   = I^A_i S_i,   D_i = S_iᵀ U_i,   u_i = τ_i − S_iᵀ p^A_i
//!                     I^a_i = I^A_i − U_i D_i⁻¹ U_iᵀ
//!                     p^a_i = p^A_i + I^a_i c_i + U_i D_i⁻¹ u_i
//!                     I^A_{i−1} += [Ad_{T_{i,i−1}}]ᵀ I^a_i [Ad_{T_{i,i−1}}]
//!                     p^A_{i−1} += [Ad_{T_{i,i−1}}]ᵀ p^a_i
//! pass 3, i = 1..n:   a'_i  = [Ad_{T_{i,i−1}}] a_{i−1} + c_i
//!                     θ̈_i   = D_i⁻¹ u_i − W_iᵀ a'_i,   W_i = U_i D_i⁻¹,   a_i = a'_i + S_i θ̈_i
//! ```
//!
//! with `V_0 = 0` and `a_0 = (0, −g)`: gravity enters as an upward acceleration of the base,
//! as in [`super::rnea`]. On a tree `i − 1` reads `λ(i)`: pass 2 adds each articulated
//! inertia and bias force into the parent's. A floating base is body 0 with its own rigid
//! inertia and bias force; after pass 2 its acceleration (gravity offset included) solves
//! `I^A_0 a_0 = τ_0 − p^A_0` (an unrolled 6×6 LDLᵀ), and `ν̇_0 = a_0 + (0, g_0)`. The articulated inertias `I^A_i` are general symmetric 6×6
//! matrices ([`SymInertia`]), moved to the parent in two stages (the joint's own motion,
//! then the constant `C_i`) so that the zeros of the constants fold away.
//!
//! In joint frames `S_i` is `e_z` in the angular (revolute) or linear (prismatic) part, at
//! index `s` of the 6-vector, so `U_i` is column `s` of `I^A_i`, `D_i` its entry `s` and
//! `S_iᵀ p` one component. Three exact identities are used instead of letting rounding
//! decide: row and column `s` of `I^a_i` are zero (`I^a_i S_i = U_i − U_i D_i⁻¹ D_i = 0`),
//! `S_iᵀ p^a_i = τ_i`, and `a_{i,s} = a'_{i,s} + θ̈_i = D_i⁻¹ u_i − Σ_{j≠s} W_{i,j} a'_{i,j}`.
//! One division per joint, `1/D_i`, in pass 2 only: pass 3 reads `W_i` (which pass 2 forms
//! for `I^a_i` and `p^a_i` anyway) and `D_i⁻¹ u_i` (a joint on a fixed base, which forms no
//! `W_i`, keeps `D_i⁻¹ (u_i − U_iᵀ a'_i)`), so that six values per joint wait for it
//! instead of seven (`U_i`, `D_i⁻¹`, `u_i`), and its chain from joint to joint is one
//! multiplication shorter; the operation count is the same. Measured (old and new generated
//! code in one binary, medians of 15 interleaved rounds, six processes): TALOS' forward
//! dynamics −1.4 to −5.8 %, Solo-12's −3.7 to +2.8 %, G1's −11.8 to +3.2 % (1,191 → 1,161
//! spill stores in its AVX-512 copy).
//!
//! The shifts of the articulated inertias ([`ShiftForm`]) and the bias wrenches
//! ([`LinkForce`]) can each be written out in equal forms; the caller picks the cheapest.

use super::frames::BodyInertia;
use super::rnea::{link_force, BaseMotion, LinkForce};
use super::spatial::{Inertia, JointMotion, ShiftForm, Spatial, SymInertia, VectorOps};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// Index of the joint's axis in the 6-vector `(ω, v)`: 2 (revolute) or 5 (prismatic).
fn axis(kind: JointKind) -> usize {
    match kind {
        JointKind::Revolute => 2,
        JointKind::Prismatic => 5,
    }
}

fn get(x: &Spatial, k: usize) -> ExprId {
    if k < 3 {
        x.ang[k]
    } else {
        x.lin[k - 3]
    }
}

fn set(x: &mut Spatial, k: usize, value: ExprId) {
    if k < 3 {
        x.ang[k] = value;
    } else {
        x.lin[k - 3] = value;
    }
}

fn add(g: &mut ExprGraph, x: &Spatial, y: &Spatial) -> Spatial {
    Spatial {
        ang: g.add3(x.ang, y.ang),
        lin: g.add3(x.lin, y.lin),
    }
}

/// `θ̈ = M(θ)⁻¹ (τ − c(θ, θ̇) − g(θ))` for the symbolic `θ̇`, `τ` and gravity `gravity` in {0};
/// the articulated inertias are shifted as `form` says, and the bias wrenches
/// `−[ad_{V_i}]ᵀ G_i V_i` written out as `bias` says.
#[allow(clippy::too_many_arguments)]
pub fn aba(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    base: &BaseMotion,
    base_inertia: Option<&BodyInertia>,
    qd: &[ExprId],
    tau: &[ExprId],
    form: ShiftForm,
    bias: LinkForce,
) -> Vec<ExprId> {
    let n = joints.len();
    let zero3 = g.zero3();
    // With a floating base, τ holds the base wrench first.
    let (tau_base, tau) = match base_inertia {
        Some(_) => tau.split_at(6),
        None => tau.split_at(0),
    };
    // Pass 1: velocities, velocity-product accelerations c_i, rigid inertias and bias forces.
    let mut vs: Vec<Spatial> = Vec::with_capacity(n);
    let mut c = Vec::with_capacity(n);
    let mut ia = Vec::with_capacity(n);
    let mut pa = Vec::with_capacity(n);
    for (i, jm) in joints.iter().enumerate() {
        let v = jm.frame.parent.map_or(base.v, |p| vs[p]);
        let mut vi = jm.motion_to_child(g, v);
        // [ad_V] S θ̇: (ω × e_z, v × e_z) θ̇ (revolute) or (0, ω × e_z) θ̇ (prismatic); the
        // joint's own S θ̇ drops out of the cross product, so V before adding it serves.
        let w_ez = [vi.ang[1], g.neg(vi.ang[0]), g.zero()];
        let ci = match jm.frame.kind {
            JointKind::Revolute => {
                let v_ez = [vi.lin[1], g.neg(vi.lin[0]), g.zero()];
                Spatial {
                    ang: g.scale3(qd[i], w_ez),
                    lin: g.scale3(qd[i], v_ez),
                }
            }
            JointKind::Prismatic => Spatial {
                ang: zero3,
                lin: g.scale3(qd[i], w_ez),
            },
        };
        let s = axis(jm.frame.kind);
        let v_s = g.add(get(&vi, s), qd[i]);
        set(&mut vi, s, v_s);
        let gi = super::parameters::link_inertia(g, jm.frame);
        pa.push(bias_force(g, &gi, &vi, bias));
        ia.push(SymInertia::rigid(g, &gi));
        c.push(ci);
        vs.push(vi);
    }
    // The floating base: its rigid inertia and bias force start its articulated ones.
    let mut base_art = base_inertia.map(|b| {
        let gb = Inertia::constant(g, b);
        (SymInertia::rigid(g, &gb), bias_force(g, &gb, &base.v, bias))
    });
    // Pass 2: articulated inertias and bias forces, tip to base.
    let zero = g.zero();
    let one = g.one();
    // Per joint, what pass 3 reads: `W = U D⁻¹` and `u D⁻¹` (see the module docs), or, for
    // a joint on a fixed base (which forms no `W`), `U`, `u` and `D⁻¹`.
    let mut third = vec![
        Pass3 {
            coefficients: [zero; 6],
            numerator: zero,
            scale: None,
        };
        n
    ];
    for i in (0..n).rev() {
        let s = axis(joints[i].frame.kind);
        let col: [ExprId; 6] = std::array::from_fn(|j| ia[i].entry(j, s));
        let d_inv = g.div(one, col[s]);
        let u = g.sub(tau[i], get(&pa[i], s));
        let parent = joints[i].frame.parent;
        if parent.is_none() && base_art.is_none() {
            // A fixed base takes no articulated inertia.
            third[i] = Pass3 {
                coefficients: col,
                numerator: u,
                scale: Some(d_inv),
            };
            continue;
        }
        // W = U D⁻¹ (W_s = 1 exactly, and unused: row and column s of I^a vanish).
        let w: [ExprId; 6] =
            std::array::from_fn(|j| if j == s { one } else { g.mul(col[j], d_inv) });
        third[i] = Pass3 {
            coefficients: w,
            numerator: g.mul(u, d_inv),
            scale: None,
        };
        let ia_i = ia[i];
        let ia_small = SymInertia::from_upper(|j, k| {
            if j == s || k == s {
                zero
            } else {
                let t = g.mul(w[j], col[k]);
                g.sub(ia_i.entry(j, k), t)
            }
        });
        let iac = ia_small.apply(g, &c[i]);
        let mut pa_small = add(g, &pa[i], &iac);
        for j in 0..6 {
            let value = if j == s {
                tau[i]
            } else {
                let t = g.mul(w[j], u);
                g.add(get(&pa_small, j), t)
            };
            set(&mut pa_small, j, value);
        }
        let moved = joints[i].sym_inertia_to_parent(g, &ia_small, form);
        let fp = joints[i].force_to_parent(g, pa_small);
        let (ia_p, pa_p) = match (parent, &mut base_art) {
            (Some(p), _) => (&mut ia[p], &mut pa[p]),
            (None, Some((ib, pb))) => (ib, pb),
            (None, None) => continue,
        };
        *ia_p = SymInertia::add(g, ia_p, &moved);
        *pa_p = add(g, pa_p, &fp);
    }
    // The base's acceleration: given (fixed base), or from I^A_0 a_0 = τ_0 − p^A_0.
    let (a0, base_qdd) = match &base_art {
        None => (base.vd, Vec::new()),
        Some((ib, pb)) => {
            let m: Vec<ExprId> = (0..36).map(|k| ib.entry(k / 6, k % 6)).collect();
            let rhs: Vec<ExprId> = (0..6).map(|k| g.sub(tau_base[k], get(pb, k))).collect();
            let a0 = super::ldlt::ldlt_solve(g, &m, &rhs);
            let a0 = Spatial {
                ang: [a0[0], a0[1], a0[2]],
                lin: [a0[3], a0[4], a0[5]],
            };
            // ν̇_0 = a_0 − (V̇_0 − ν̇_0): remove the gravity offset folded into base.vd.
            let out: Vec<ExprId> = (0..6)
                .map(|k| {
                    let offset = get(&base.vd, k);
                    g.sub(get(&a0, k), offset)
                })
                .collect();
            (a0, out)
        }
    };
    // Pass 3: accelerations, base to tip.
    let mut accs: Vec<Spatial> = Vec::with_capacity(n);
    let mut qdd = vec![zero; n];
    for (i, jm) in joints.iter().enumerate() {
        let a = jm.frame.parent.map_or(a0, |p| accs[p]);
        let moved = jm.motion_to_child(g, a);
        let ai = add(g, &moved, &c[i]);
        let s = axis(jm.frame.kind);
        let p = &third[i];
        let (ws, as_): (Vec<ExprId>, Vec<ExprId>) = (0..6)
            .filter(|&j| j != s)
            .map(|j| (p.coefficients[j], get(&ai, j)))
            .unzip();
        let wa = g.dot(&ws, &as_);
        // a_{i,s} = a'_{i,s} + θ̈_i = u D⁻¹ − Σ_{j≠s} W_j a'_{i,j}.
        let num = g.sub(p.numerator, wa);
        let a_s = match p.scale {
            Some(d_inv) => g.mul(d_inv, num),
            None => num,
        };
        qdd[i] = g.sub(a_s, get(&ai, s));
        let mut a = ai;
        set(&mut a, s, a_s);
        accs.push(a);
    }
    let mut out = base_qdd;
    out.extend(qdd);
    out
}

/// What pass 3 reads of a joint: `a_{i,s} = scale · (numerator − Σ_{j≠s} coefficients_j a'_{i,j})`.
#[derive(Clone, Copy)]
struct Pass3 {
    /// `W_i` (or `U_i` where `scale` is `D_i⁻¹`).
    coefficients: [ExprId; 6],
    /// `D_i⁻¹ u_i` (or `u_i`).
    numerator: ExprId,
    /// `None` (or `D_i⁻¹`: a joint on a fixed base, for which pass 2 forms no `W_i`).
    scale: Option<ExprId>,
}

/// The bias wrench `−[ad_V]ᵀ G V` of a body with inertia `gi` and twist `v`: the link wrench
/// of Newton–Euler at zero acceleration (its zero terms fold away as they are built).
fn bias_force(g: &mut ExprGraph, gi: &Inertia, vi: &Spatial, bias: LinkForce) -> Spatial {
    let zero = g.zero3();
    let at_rest = Spatial {
        ang: zero,
        lin: zero,
    };
    link_force(g, gi, vi, &at_rest, bias)
}
