//! The base's motion as the recursions see it ([`BaseMotion`]): fixed, or floating.
//!
//! A fixed base has `V_0 = 0` and `V̇_0 = (0, −g)`: gravity enters as an upward acceleration
//! of the base. A floating base (a free joint between the world {0} and the base) has the
//! body twist `ν_0 = (ω_b, v_b)` and acceleration `ν̇_0` from the inputs, and gravity turned
//! into the base frame, `V̇_0 = ν̇_0 + (0, −Rᵀ g)`, with `R` the base orientation from the
//! quaternion `(x, y, z, w) = q[3..7]` (scalar last), normalised on the way:
//!
//! ```text
//! s = x² + y² + z² + w²,   k = 2 / s
//! R = [[1 − k(y² + z²),  k(xy − zw),      k(xz + yw)    ],
//!      [k(xy + zw),      1 − k(x² + z²),  k(yz − xw)    ],
//!      [k(xz − yw),      k(yz + xw),      1 − k(x² + y²)]]
//! ```
//!
//! which is the rotation of `quat / |quat|` for any non-zero quaternion (the code never
//! trusts it to be unit). The base position `q[0..3]` does not enter the dynamics.

use super::rnea::BaseMotion;
use super::spatial::{Spatial, VectorOps, V3};
use super::{input, Q};
use crate::expr::{ExprGraph, ExprId, Input};

/// Index of the quaternion's first entry (x) in q.
pub const QUAT: usize = 3;
/// Number of configuration entries of a floating base (position and quaternion).
pub const NQ_BASE: usize = 7;
/// Number of velocity entries of a floating base (its body twist).
pub const NV_BASE: usize = 6;

/// `R`, the base orientation in {0} (rows), from the (normalised) quaternion inputs
/// `q[3..7]` (see the module docs).
pub fn base_rotation(g: &mut ExprGraph) -> [[ExprId; 3]; 3] {
    let [x, y, z, w] = std::array::from_fn(|k| g.input(input(Q, QUAT + k)));
    let sq = |g: &mut ExprGraph, a: ExprId| g.mul(a, a);
    let (xx, yy, zz, ww) = (sq(g, x), sq(g, y), sq(g, z), sq(g, w));
    let s = g.sum(&[xx, yy, zz, ww]);
    let two = g.constant(2.0);
    let k = g.div(two, s);
    let one = g.one();
    let prod = |g: &mut ExprGraph, a: ExprId, b: ExprId| g.mul(a, b);
    let (xy, zw, xz, yw, yz, xw) = (
        prod(g, x, y),
        prod(g, z, w),
        prod(g, x, z),
        prod(g, y, w),
        prod(g, y, z),
        prod(g, x, w),
    );
    let diag = |g: &mut ExprGraph, a: ExprId, b: ExprId| {
        let t = g.add(a, b);
        let t = g.mul(k, t);
        g.sub(one, t)
    };
    let off = |g: &mut ExprGraph, a: ExprId, b: ExprId, plus: bool| {
        let t = if plus { g.add(a, b) } else { g.sub(a, b) };
        g.mul(k, t)
    };
    [
        [diag(g, yy, zz), off(g, xy, zw, false), off(g, xz, yw, true)],
        [off(g, xy, zw, true), diag(g, xx, zz), off(g, yz, xw, false)],
        [off(g, xz, yw, false), off(g, yz, xw, true), diag(g, xx, yy)],
    ]
}

/// `Rᵀ g` for the gravity vector `gravity` in {0}, with `R` from the (normalised)
/// quaternion inputs `q[3..7]` ([`base_rotation`]).
pub fn gravity_in_base(g: &mut ExprGraph, gravity: V3) -> V3 {
    let r = base_rotation(g);
    // (Rᵀ g)_j = Σ_i R_ij g_i; zero components of g fold away.
    std::array::from_fn(|j| {
        let nonzero: Vec<usize> = (0..3).filter(|&i| !g.is_zero(gravity[i])).collect();
        let terms: Vec<ExprId> = nonzero
            .into_iter()
            .map(|i| g.mul(gravity[i], r[i][j]))
            .collect();
        g.sum(&terms)
    })
}

/// The base's motion: fixed (`velocity`, `acceleration` unused), or floating with the
/// base entries of `velocity` and `acceleration` (ν and ν̇, base first); `gravity` in {0}.
pub fn base_motion(
    g: &mut ExprGraph,
    floating: bool,
    velocity: &[ExprId],
    acceleration: &[ExprId],
    gravity: V3,
) -> BaseMotion {
    if !floating {
        let zero = g.zero3();
        return BaseMotion {
            v: Spatial {
                ang: zero,
                lin: zero,
            },
            vd: Spatial {
                ang: zero,
                lin: [g.neg(gravity[0]), g.neg(gravity[1]), g.neg(gravity[2])],
            },
        };
    }
    let v = Spatial {
        ang: [velocity[0], velocity[1], velocity[2]],
        lin: [velocity[3], velocity[4], velocity[5]],
    };
    let mut vd = Spatial {
        ang: [acceleration[0], acceleration[1], acceleration[2]],
        lin: [acceleration[3], acceleration[4], acceleration[5]],
    };
    if gravity.iter().any(|&x| !g.is_zero(x)) {
        let gb = gravity_in_base(g, gravity);
        vd.lin = g.sub3(vd.lin, gb);
    }
    BaseMotion { v, vd }
}

/// The time derivatives of the `q` inputs as graph tangents (for [`ExprGraph::jvp`]), from
/// the velocity inputs `ν` (group [`super::QD`]); `k` joint coordinates. On a fixed base
/// `θ̇ = ν`. On a floating base (as `dynamics_reference::configuration_rate`):
///
/// ```text
/// ṗ = R v_b,    quaṫ = ½ quat ⊗ (ω_b, 0) = ½ (w ω_b + u × ω_b, −u · ω_b),    θ̇
/// ```
///
/// with `quat = (u, w)` as given (this rate keeps `|quat|`, and `quat/|quat|` follows
/// `Ṙ = R [ω_b]` exactly, so the derivative of anything built on the normalised quaternion is
/// right for any non-zero length).
pub fn configuration_rate(g: &mut ExprGraph, floating: bool, k: usize) -> Vec<(Input, ExprId)> {
    let qd = |g: &mut ExprGraph, i: usize| g.input(input(super::QD, i));
    if !floating {
        return (0..k).map(|i| (input(Q, i), qd(g, i))).collect();
    }
    let r = base_rotation(g);
    let w: V3 = std::array::from_fn(|i| qd(g, i));
    let v: V3 = std::array::from_fn(|i| qd(g, 3 + i));
    let mut out = Vec::with_capacity(NQ_BASE + k);
    for (i, row) in r.iter().enumerate() {
        let terms: Vec<ExprId> = (0..3).map(|j| g.mul(row[j], v[j])).collect();
        out.push((input(Q, i), g.sum(&terms)));
    }
    let u: V3 = std::array::from_fn(|i| g.input(input(Q, QUAT + i)));
    let qw = g.input(input(Q, QUAT + 3));
    let wu = g.scale3(qw, w);
    let uxw = g.cross(u, w);
    let sum = g.add3(wu, uxw);
    for (i, x) in sum.into_iter().enumerate() {
        out.push((input(Q, QUAT + i), g.cmul(0.5, x)));
    }
    let dots: Vec<ExprId> = (0..3).map(|i| g.mul(u[i], w[i])).collect();
    let dot = g.sum(&dots);
    out.push((input(Q, QUAT + 3), g.cmul(-0.5, dot)));
    out.extend((0..k).map(|i| (input(Q, NQ_BASE + i), qd(g, NV_BASE + i))));
    out
}
