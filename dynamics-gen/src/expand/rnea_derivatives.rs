//! The analytical derivatives of Newton–Euler (Carpentier & Mansard, RSS 2018), expanded in
//! joint frames: `∂τ/∂q` and `∂τ/∂q̇` of a fixed-base tree from composite quantities and one
//! dot product per entry, instead of one forward-mode sweep per joint.
//!
//! With `S_i` the axis of joint i, `v_i`, `a_i` the twist and acceleration of link i (`a_0 =
//! −g`), `λ(i)` its parent, `I_i` its inertia, `h_i = I_i v_i`, `f_i = I_i a_i + v_i ×* h_i`,
//! and for a subtree rooted at k the composites `I^C_k = Σ I_l`, `H_k = Σ h_l`, `F_k = Σ f_l`
//! and `İ^C_k = Σ (v_l ×* I_l − I_l v_l ×)` (the rate of `I^C_k`, a rigid-body inertia with
//! `m = 0`):
//! ```text
//! Ψ̇_i = v_λ(i) × S_i,   Ψ̈_i = a_λ(i) × S_i + v_λ(i) × Ψ̇_i,   B^C_k x = İ^C_k x + x ×* H_k
//! i ⪯ k (i on the path to k):  ∂τ_k/∂q_i = α_k·Ψ̈_i + β_k·Ψ̇_i,   ∂τ_k/∂q̇_i = 2 α_k·Ψ̇_i + β_k·S_i
//!                              α_k = I^C_k S_k,   β_k = B^C_kᵀ S_k = İ^C_k S_k − S_k ×* H_k
//! k ≺ i (k strictly above i):  ∂τ_k/∂q_i = S_k·P_i,   ∂τ_k/∂q̇_i = S_k·R_i
//!                              P_i = I^C_i Ψ̈_i + B^C_i Ψ̇_i + S_i ×* F_i,   R_i = 2 I^C_i Ψ̇_i + B^C_i S_i
//! ```
//! and 0 between joints of different branches. The first follows from moving joint i: the
//! subtree below it turns rigidly about `S_i` (which leaves every `S_kᵀ F_k` of that subtree
//! unchanged) while its links' twists gain `Ψ̇_i` and their accelerations `Ψ̈_i − v_l × Ψ̇_i`,
//! so `∂f_l/∂q_i = S_i ×* f_l + I_l Ψ̈_i + B_l Ψ̇_i`; likewise `∂f_l/∂q̇_i = 2 I_l Ψ̇_i + B_l
//! S_i`. Every quantity of joint i lives in frame {J_i}, where `S_i` is `e_z`; the pair
//! terms are dot products in the deeper joint's frame, with `S_i`, `Ψ̇_i`, `Ψ̈_i` carried down
//! the tree by the joints' twist transforms.

use super::rnea::{link_force, BaseMotion, LinkForce};
use super::spatial::{Inertia, JointMotion, Spatial, VectorOps};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// `x × y = (ω × ω', ω × v' + v × ω')` for twists `x = (ω, v)`, `y = (ω', v')`.
fn cross_motion(g: &mut ExprGraph, x: &Spatial, y: &Spatial) -> Spatial {
    let ang = g.cross(x.ang, y.ang);
    let a = g.cross(x.ang, y.lin);
    let b = g.cross(x.lin, y.ang);
    Spatial {
        ang,
        lin: g.add3(a, b),
    }
}

/// `x ×* f = (ω × n + v × f, ω × f)` for a twist `x = (ω, v)` and a wrench `f = (n, f)`.
fn cross_force(g: &mut ExprGraph, x: &Spatial, f: &Spatial) -> Spatial {
    let a = g.cross(x.ang, f.ang);
    let b = g.cross(x.lin, f.lin);
    Spatial {
        ang: g.add3(a, b),
        lin: g.cross(x.ang, f.lin),
    }
}

fn add6(g: &mut ExprGraph, a: &Spatial, b: &Spatial) -> Spatial {
    Spatial {
        ang: g.add3(a.ang, b.ang),
        lin: g.add3(a.lin, b.lin),
    }
}

fn sub6(g: &mut ExprGraph, a: &Spatial, b: &Spatial) -> Spatial {
    Spatial {
        ang: g.sub3(a.ang, b.ang),
        lin: g.sub3(a.lin, b.lin),
    }
}

fn dot6(g: &mut ExprGraph, a: &Spatial, b: &Spatial) -> ExprId {
    let x = [a.ang[0], a.ang[1], a.ang[2], a.lin[0], a.lin[1], a.lin[2]];
    let y = [b.ang[0], b.ang[1], b.ang[2], b.lin[0], b.lin[1], b.lin[2]];
    g.dot(&x, &y)
}

/// `S_i` in its own frame: `e_z` in the angular (revolute) or linear (prismatic) part.
fn axis(g: &mut ExprGraph, kind: JointKind) -> Spatial {
    let (z, one) = (g.zero(), g.one());
    let ez = [z, z, one];
    match kind {
        JointKind::Revolute => Spatial {
            ang: ez,
            lin: [z; 3],
        },
        JointKind::Prismatic => Spatial {
            ang: [z; 3],
            lin: ez,
        },
    }
}

/// The rate `İ = v ×* I − I v×` of a link's inertia `I` (in its frame) moving with twist
/// `v = (ω, v)`: a rigid-body inertia with `m = 0`, `h = ω × h + m v` and
/// `I_o = [ω] I_o − I_o [ω] + 2 (v·h) 1 − (h vᵀ + v hᵀ)`.
fn inertia_rate(g: &mut ExprGraph, i: &Inertia, v: &Spatial) -> Inertia {
    let w = v.ang;
    let wxh = g.cross(w, i.h);
    let mv = g.scale3(i.m, v.lin);
    let h = g.add3(wxh, mv);
    // [ω] I_o, column by column (I_o symmetric: its columns are its rows).
    let [xx, yy, zz, xy, xz, yz] = i.i;
    let cols = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
    let wi: Vec<[ExprId; 3]> = cols.iter().map(|c| g.cross(w, *c)).collect();
    // (j, k) entry of [ω] I_o is wi[k][j].
    let vh = g.dot(&v.lin, &i.h);
    let two_vh = g.cmul(2.0, vh);
    let mut entry = |j: usize, k: usize| {
        let s = g.add(wi[k][j], wi[j][k]);
        let hv = g.mul(i.h[j], v.lin[k]);
        let vh_ = g.mul(v.lin[j], i.h[k]);
        let t = g.add(hv, vh_);
        let s = g.sub(s, t);
        if j == k {
            g.add(s, two_vh)
        } else {
            s
        }
    };
    let io = [
        entry(0, 0),
        entry(1, 1),
        entry(2, 2),
        entry(0, 1),
        entry(0, 2),
        entry(1, 2),
    ];
    Inertia {
        m: g.zero(),
        h,
        i: io,
    }
}

/// Where the pair terms' dot products are taken; the results are equal, and which needs
/// fewer operations depends on the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairFrame {
    /// In the deeper joint's frame: the ancestors' `S_i`, `Ψ̇_i`, `Ψ̈_i` are carried down
    /// the tree by twist transforms (three per pair).
    Deeper,
    /// In the ancestor's frame: the deeper joint's `α_k`, `β_k`, `P_k`, `R_k` are carried up
    /// toward the base by wrench transforms (four per pair), where `S_i = e_z` makes three of
    /// the six dot products a single component and `Ψ̇_i` is sparse.
    Ancestor,
}

/// `(∂τ/∂q, ∂τ/∂q̇)`, n×n row-major, of a fixed-base tree's Newton–Euler inverse dynamics
/// with the given joint rates (see the module docs), the pair terms in `frame`, and `τ`
/// itself (`S_kᵀ F_k`, without armature); `base` as for [`super::rnea::rnea`].
pub fn rnea_derivatives(
    g: &mut ExprGraph,
    joints: &[JointMotion<'_>],
    base: &BaseMotion,
    qd: &[ExprId],
    qdd: &[ExprId],
    frame: PairFrame,
) -> (Vec<ExprId>, Vec<ExprId>, Vec<ExprId>) {
    let n = joints.len();
    let mut vs: Vec<Spatial> = Vec::with_capacity(n);
    let mut vds: Vec<Spatial> = Vec::with_capacity(n);
    let mut s_axis = Vec::with_capacity(n);
    let mut psi_d = Vec::with_capacity(n);
    let mut psi_dd = Vec::with_capacity(n);
    let mut ic = Vec::with_capacity(n);
    let mut dc = Vec::with_capacity(n);
    let mut hc = Vec::with_capacity(n);
    let mut fc = Vec::with_capacity(n);
    // Forward pass: twists, accelerations, Ψ̇, Ψ̈, and the links' own inertias, rates,
    // momenta and wrenches.
    for (i, jm) in joints.iter().enumerate() {
        let (v, vd) = match jm.frame.parent {
            Some(p) => (vs[p], vds[p]),
            None => (base.v, base.vd),
        };
        let u = jm.motion_to_child(g, v);
        let w = jm.motion_to_child(g, vd);
        let s = axis(g, jm.frame.kind);
        let pd = cross_motion(g, &u, &s);
        let ws = cross_motion(g, &w, &s);
        let upd = cross_motion(g, &u, &pd);
        let pdd = add6(g, &ws, &upd);
        let sqd = Spatial {
            ang: g.scale3(qd[i], s.ang),
            lin: g.scale3(qd[i], s.lin),
        };
        let vi = add6(g, &u, &sqd);
        // v̇_i = X v̇_λ + Ψ̇_i q̇_i + S_i q̈_i (Ψ̇_i = v_λ × S_i = v_i × S_i).
        let pq = Spatial {
            ang: g.scale3(qd[i], pd.ang),
            lin: g.scale3(qd[i], pd.lin),
        };
        let sqdd = Spatial {
            ang: g.scale3(qdd[i], s.ang),
            lin: g.scale3(qdd[i], s.lin),
        };
        let vdi = add6(g, &w, &pq);
        let vdi = add6(g, &vdi, &sqdd);
        let gi = super::parameters::link_inertia(g, jm.frame);
        fc.push(link_force(g, &gi, &vi, &vdi, LinkForce::Spatial));
        hc.push(gi.apply(g, &vi));
        dc.push(inertia_rate(g, &gi, &vi));
        ic.push(gi);
        vs.push(vi);
        vds.push(vdi);
        s_axis.push(s);
        psi_d.push(pd);
        psi_dd.push(pdd);
    }
    // Backward pass: the composites, children before parents.
    for i in (0..n).rev() {
        if let Some(p) = joints[i].frame.parent {
            let jm = &joints[i];
            let x = jm.inertia_to_parent(g, &ic[i]);
            ic[p] = Inertia::add(g, &ic[p], &x);
            let x = jm.inertia_to_parent(g, &dc[i]);
            dc[p] = Inertia::add(g, &dc[p], &x);
            let x = jm.force_to_parent(g, hc[i]);
            hc[p] = add6(g, &hc[p], &x);
            let x = jm.force_to_parent(g, fc[i]);
            fc[p] = add6(g, &fc[p], &x);
        }
    }
    let tau: Vec<ExprId> = (0..n)
        .map(|k| match joints[k].frame.kind {
            JointKind::Revolute => fc[k].ang[2],
            JointKind::Prismatic => fc[k].lin[2],
        })
        .collect();
    let zero = g.zero();
    let mut dq = vec![zero; n * n];
    let mut dqd = vec![zero; n * n];
    if frame == PairFrame::Ancestor {
        for k in 0..n {
            let s = s_axis[k];
            let [mut alpha, mut beta, mut p, mut r] =
                pair_vectors(g, &ic[k], &dc[k], &hc[k], &fc[k], &s, &psi_d[k], &psi_dd[k]);
            // Up the path from k to the base: at each joint i on it, in {J_i}.
            let mut i = k;
            loop {
                let a = dot6(g, &alpha, &psi_dd[i]);
                let b = dot6(g, &beta, &psi_d[i]);
                dq[k * n + i] = g.add(a, b);
                let a = dot6(g, &alpha, &psi_d[i]);
                let a = g.cmul(2.0, a);
                let b = dot6(g, &beta, &s_axis[i]);
                dqd[k * n + i] = g.add(a, b);
                if i != k {
                    dq[i * n + k] = dot6(g, &s_axis[i], &p);
                    dqd[i * n + k] = dot6(g, &s_axis[i], &r);
                }
                let Some(parent) = joints[i].frame.parent else {
                    break;
                };
                let jm = &joints[i];
                [alpha, beta, p, r] = [alpha, beta, p, r].map(|x| jm.force_to_parent(g, x));
                i = parent;
            }
        }
        return (dq, dqd, tau);
    }
    // For each joint k, its ancestors' (i, S_i, Ψ̇_i, Ψ̈_i) expressed in {J_k}, k itself last.
    let mut carried: Vec<Vec<(usize, Spatial, Spatial, Spatial)>> = Vec::with_capacity(n);
    for k in 0..n {
        let jm = &joints[k];
        let mut list: Vec<(usize, Spatial, Spatial, Spatial)> = match jm.frame.parent {
            Some(p) => carried[p]
                .clone()
                .into_iter()
                .map(|(i, s, pd, pdd)| {
                    (
                        i,
                        jm.motion_to_child(g, s),
                        jm.motion_to_child(g, pd),
                        jm.motion_to_child(g, pdd),
                    )
                })
                .collect(),
            None => Vec::new(),
        };
        list.push((k, s_axis[k], psi_d[k], psi_dd[k]));
        let [alpha, beta, p, r] = pair_vectors(
            g, &ic[k], &dc[k], &hc[k], &fc[k], &s_axis[k], &psi_d[k], &psi_dd[k],
        );
        for (i, si, pdi, pddi) in &list {
            let a = dot6(g, &alpha, pddi);
            let b = dot6(g, &beta, pdi);
            dq[k * n + i] = g.add(a, b);
            let a = dot6(g, &alpha, pdi);
            let a = g.cmul(2.0, a);
            let b = dot6(g, &beta, si);
            dqd[k * n + i] = g.add(a, b);
            if *i != k {
                dq[i * n + k] = dot6(g, si, &p);
                dqd[i * n + k] = dot6(g, si, &r);
            }
        }
        carried.push(list);
    }
    (dq, dqd, tau)
}

/// `[α_k, β_k, P_k, R_k]` of joint k from its composites (see the module docs).
#[allow(clippy::too_many_arguments)]
fn pair_vectors(
    g: &mut ExprGraph,
    ic: &Inertia,
    dc: &Inertia,
    hc: &Spatial,
    fc: &Spatial,
    s: &Spatial,
    psi_d: &Spatial,
    psi_dd: &Spatial,
) -> [Spatial; 4] {
    let alpha = ic.apply(g, s);
    let ds = dc.apply(g, s);
    let sh = cross_force(g, s, hc);
    let beta = sub6(g, &ds, &sh);
    let i_pdd = ic.apply(g, psi_dd);
    let d_pd = dc.apply(g, psi_d);
    let pd_h = cross_force(g, psi_d, hc);
    let s_f = cross_force(g, s, fc);
    let p = add6(g, &i_pdd, &d_pd);
    let p = add6(g, &p, &pd_h);
    let p = add6(g, &p, &s_f);
    let i_pd = ic.apply(g, psi_d);
    let two_i_pd = Spatial {
        ang: i_pd.ang.map(|x| g.cmul(2.0, x)),
        lin: i_pd.lin.map(|x| g.cmul(2.0, x)),
    };
    let r = add6(g, &two_i_pd, &ds);
    let r = add6(g, &r, &sh);
    [alpha, beta, p, r]
}
