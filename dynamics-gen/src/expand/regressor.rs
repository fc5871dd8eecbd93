//! The inertial-parameter regressor and the base (identifiable) parameters.
//!
//! The joint forces are linear in the bodies' standard inertial parameters (Atkeson, An and
//! Hollerbach 1986):
//!
//! ```text
//! τ(q, ν, ν̇) = Y(q, ν, ν̇) π,   π_b = (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)_b
//! ```
//!
//! per moving body b (a floating base first, then the links in the robot's order), each in
//! the body's own frame {b} with `I` about the frame's origin, `I = I_c − m [c]²`: the order
//! and frames of Pinocchio's `computeJointTorqueRegressor`. Column `(b, k)` of `Y` is the
//! Newton–Euler expansion ([`super::rnea`]) of the robot whose bodies are all massless but
//! b, which has the single unit parameter `π_{b,k} = 1`: the recursion is linear in the
//! inertias, so this is `∂τ/∂π_{b,k}` exactly. The kinematics (twists, accelerations) are the
//! same for every column and are shared in the graph; gravity is in every column, as in `τ`.
//! The rotors' armature (`a_i q̈_i`), a joint's parameter rather than a body's, is not in `Y`:
//! `τ = Y π + diag(a) q̈` (and friction is not either).
//!
//! The base parameters (Gautier and Khalil 1990, found numerically as in Gautier 1991):
//! `Y` evaluated at seeded random states (at least [`BASE_STATES`]) is stacked into `W`,
//! and Gram–Schmidt with column pivoting picks its columns: of the columns whose residual
//! after projection on the kept ones still exceeds [`RANK_TOLERANCE`] of their norm, the one
//! with the largest residual is kept next. The columns with the largest effect on τ are
//! kept, and every dropped column is then exactly (to rounding; the residuals measured are
//! below 1e-14) `y_d = Σ_k β_dk y_k` over the kept columns, with β by least squares, so
//!
//! ```text
//! τ = Y_b π_base,   π_base,k = π_k + Σ_d β_dk π_d,
//! ```
//!
//! with `Y_b` the kept columns of `Y` (full column rank); β is rounded to 12 significant
//! digits (the coefficients are the robot's lengths and their products, and get back their
//! short forms). Columns that are zero at every
//! state (`‖y‖ ≤ ZERO_TOLERANCE · max ‖y‖`: parameters with no effect on τ, such as the
//! first link's mass on a fixed base) are dropped with no regrouping. β's entries below
//! [`BETA_ZERO`] of the largest are exact zeros.
//!
//! Run-time parameters ([`super::parameters`]): with run-time gravity `Y` reads the gravity
//! leaves, and each sample state of the reduction draws its own random gravity vector, so
//! the base parameters hold for every gravity, not only the file's direction (which can
//! hide a parameter, e.g. behind a vertical first axis). A run-time payload has no column of
//! its own: it is part of its link's parameters, and `inertial_parameters` adds its ten
//! standard parameters to the link's.

use super::frames;
use super::rnea::{self, LinkForce};
use super::spatial::VectorOps;
use super::{base, cheaper, input, joint_motions, mimic, prune_if, Inputs, QD, QDD};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::random::Rng;
use dynamics_model::{Robot, SpatialInertia};
use nalgebra::DMatrix;

/// Input group of the standard inertial parameters π (argument of `base_parameters`).
pub const PI: u8 = 4;

/// The ten standard parameters of a body, in Pinocchio's order (`I` about the body frame's
/// origin).
pub const PARAMETER_NAMES: [&str; 10] = [
    "m", "mc_x", "mc_y", "mc_z", "I_xx", "I_xy", "I_yy", "I_xz", "I_yz", "I_zz",
];

/// The least number of seeded random states at which `Y` is evaluated for the base
/// parameters; more when needed for `W` (nv rows per state) to have four times as many rows
/// as columns.
pub const BASE_STATES: usize = 30;

/// Relative residual below which a column of `W` is a combination of the kept ones.
pub const RANK_TOLERANCE: f64 = 1e-6;

/// Norm, relative to the largest column's, below which a column of `W` is zero (rounding).
pub const ZERO_TOLERANCE: f64 = 1e-12;

/// Relative size below which a regrouping coefficient is an exact zero.
pub const BETA_ZERO: f64 = 1e-10;

/// The regressor of one robot and its base parameters.
#[derive(Clone, Debug)]
pub struct Regressor {
    /// The expression graph of `y` and `base_map`.
    pub graph: ExprGraph,
    /// The length of q.
    pub nq: usize,
    /// The length of ν and τ (rows of `Y`).
    pub nv: usize,
    /// The bodies whose parameters are the columns (a floating base, then the links).
    pub bodies: Vec<String>,
    /// `Y(q, ν, ν̇)`, nv × 10·bodies, row-major.
    pub y: Vec<ExprId>,
    /// The robot's own standard parameters π (10 per body).
    pub parameters: Vec<f64>,
    /// The columns of `Y` kept for the base regressor `Y_b`, in order.
    pub base_columns: Vec<usize>,
    /// Per kept column: the dropped columns regrouped into it, `(d, β_dk)`.
    pub regrouped: Vec<Vec<(usize, f64)>>,
    /// The columns with no effect on τ (zero at every state).
    pub unidentifiable: Vec<usize>,
    /// `π_base` as expressions of the inputs π (group [`PI`]), one per kept column.
    pub base_map: Vec<ExprId>,
    /// `π_base` of the robot's own π.
    pub base_values: Vec<f64>,
    /// The robot's own π as constant nodes.
    pub parameter_nodes: Vec<ExprId>,
}

impl Regressor {
    /// The number of standard parameters, 10 per body.
    pub fn n_parameters(&self) -> usize {
        self.parameters.len()
    }

    /// `body.parameter` for column `j`.
    pub fn parameter_name(&self, j: usize) -> String {
        format!("{}.{}", self.bodies[j / 10], PARAMETER_NAMES[j % 10])
    }

    /// The kept columns of `Y`: `Y_b`, nv × base_columns, row-major.
    pub fn base_y(&self) -> Vec<ExprId> {
        let p = self.n_parameters();
        (0..self.nv)
            .flat_map(|i| self.base_columns.iter().map(move |&j| self.y[i * p + j]))
            .collect()
    }
}

/// A body's ten standard parameters (in Pinocchio's order) from its spatial inertia.
pub fn standard_parameters(g: &SpatialInertia) -> [f64; 10] {
    let b = frames::BodyInertia::from_spatial(g);
    let [xx, yy, zz, xy, xz, yz] = b.i;
    [b.m, b.h[0], b.h[1], b.h[2], xx, xy, yy, xz, yz, zz]
}

/// The spatial inertia with the single parameter `k` (Pinocchio's order) equal to 1.
fn unit_inertia(k: usize) -> SpatialInertia {
    let mut p = [0.0; 10];
    p[k] = 1.0;
    let [m, hx, hy, hz, xx, xy, yy, xz, yz, zz] = p;
    frames::BodyInertia {
        m,
        h: [hx, hy, hz],
        i: [xx, yy, zz, xy, xz, yz],
    }
    .to_spatial()
}

/// Expands the regressor of `robot` and finds its base parameters (see the module docs).
pub fn expand_regressor(robot: &Robot) -> Regressor {
    let Inputs {
        coupling,
        ov,
        nv,
        mut g,
        x,
        xd,
        xdd,
        ..
    } = Inputs::new(robot);
    let floating = robot.base.floating;
    let q = coupling.positions(&mut g, &x);
    let qd = coupling.rates(&mut g, &xd);
    let qdd = coupling.rates(&mut g, &xdd);
    // The massless robot: no link inertia, no rotor.
    let mut massless = robot.clone();
    massless.base.inertia = SpatialInertia::zero();
    for l in &mut massless.links {
        l.inertia = SpatialInertia::zero();
    }
    for j in &mut massless.joints {
        j.rotor_inertia = 0.0;
    }
    // A run-time payload is an inertia too: not in the columns (`inertial_parameters` has it).
    massless.runtime.payload = None;
    let mut bodies = Vec::new();
    let mut parameters = Vec::new();
    if floating {
        bodies.push(robot.base.name.clone());
        parameters.extend(standard_parameters(&robot.base.inertia));
    }
    for l in &robot.links {
        bodies.push(l.name.clone());
        parameters.extend(standard_parameters(&l.inertia));
    }
    let n_params = parameters.len();
    let mut columns: Vec<Vec<ExprId>> = Vec::with_capacity(n_params);
    for j in 0..n_params {
        let (b, k) = (j / 10, j % 10);
        let mut r = massless.clone();
        match (floating, b) {
            (true, 0) => r.base.inertia = unit_inertia(k),
            (true, b) => r.links[b - 1].inertia = unit_inertia(k),
            (false, b) => r.links[b].inertia = unit_inertia(k),
        }
        let mut jf = frames::joint_frames(&r);
        mimic::offsets(&mut jf, &r);
        let motions = joint_motions(&mut g, &jf, &q);
        let gravity = super::parameters::gravity(&mut g, &jf);
        let base = base::base_motion(&mut g, floating, &qd[..ov], &qdd[..ov], gravity);
        let (v, vd) = (&qd[ov..], &qdd[ov..]);
        let bi = jf.base.as_ref();
        let a = rnea::rnea(&mut g, &motions, &base, bi, v, vd, LinkForce::Spatial, None);
        let c = rnea::rnea(
            &mut g,
            &motions,
            &base,
            bi,
            v,
            vd,
            LinkForce::Classical,
            None,
        );
        let d = super::rnea_classical::rnea_classical(
            &mut g,
            &motions,
            &base,
            bi,
            v,
            vd,
            None,
            super::rnea_classical::Euler::Vector,
        );
        let best = cheaper(&g, a, c);
        let best = cheaper(&g, best, d);
        columns.push(coupling.forces(&mut g, &best));
    }
    let y: Vec<ExprId> = (0..nv)
        .flat_map(|i| columns.iter().map(move |c| c[i]))
        .collect();
    let (mut g, pruned) = prune_if(true, g, &[&y]);
    let y = pruned.into_iter().next().unwrap_or_default();
    let reduction = reduce(&g, robot, &y, nv, n_params);
    let pi: Vec<ExprId> = (0..n_params).map(|j| g.input(input(PI, j))).collect();
    let base_map: Vec<ExprId> = reduction
        .kept
        .iter()
        .zip(&reduction.regrouped)
        .map(|(&k, terms)| {
            let mut sum = pi[k];
            for &(d, beta) in terms {
                let t = g.cmul(beta, pi[d]);
                sum = g.add(sum, t);
            }
            sum
        })
        .collect();
    let base_values = reduction
        .kept
        .iter()
        .zip(&reduction.regrouped)
        .map(|(&k, terms)| {
            terms
                .iter()
                .fold(parameters[k], |s, &(d, beta)| s + beta * parameters[d])
        })
        .collect();
    let mut parameter_nodes: Vec<ExprId> = parameters.iter().map(|&v| g.constant(v)).collect();
    // A run-time payload's standard parameters, added to its link's.
    if let Some(link) = robot.runtime.payload {
        let first = 10 * (link + usize::from(floating));
        let payload = super::parameters::payload_standard_parameters(&mut g);
        for (k, p) in payload.into_iter().enumerate() {
            parameter_nodes[first + k] = g.add(parameter_nodes[first + k], p);
        }
    }
    Regressor {
        parameter_nodes,
        graph: g,
        nq: robot.nq(),
        nv,
        bodies,
        y,
        parameters,
        base_columns: reduction.kept,
        regrouped: reduction.regrouped,
        unidentifiable: reduction.zero,
        base_map,
        base_values,
    }
}

/// The outcome of the numerical reduction.
struct Reduction {
    kept: Vec<usize>,
    regrouped: Vec<Vec<(usize, f64)>>,
    zero: Vec<usize>,
}

/// `x` to `digits` significant digits: the coefficients are the robot's lengths and
/// their products, found to rounding (≈1e-15); this gives them back their short form
/// (1, 0.425, 0.180625) at a change below 5e-13 of their value.
fn round_significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = x.abs().log10().floor() as i32;
    let scale = 10f64.powi(digits - 1 - e);
    let r = (x * scale).round() / scale;
    // Printing `r` gives the short decimal; parse it back for the nearest double to it.
    format!("{r:.*e}", (digits - 1) as usize)
        .parse()
        .unwrap_or(x)
}

/// A seeded random state: q (a floating base's quaternion normalised), ν, ν̇.
pub(crate) fn random_state(rng: &mut Rng, robot: &Robot) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (nq, nv) = (robot.nq(), robot.nv());
    let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
    if robot.base.floating {
        let quat = &mut q[base::NQ_BASE - 4..base::NQ_BASE];
        let n = quat.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
        quat.iter_mut().for_each(|x| *x /= n);
    }
    let v = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
    let a = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
    (q, v, a)
}

/// Stacks `Y` at [`BASE_STATES`] random states and keeps its independent columns in order
/// (see the module docs).
fn reduce(g: &ExprGraph, robot: &Robot, y: &[ExprId], nv: usize, p: usize) -> Reduction {
    let mut rng = Rng::new(0x5eed_ba5e);
    let states = BASE_STATES.max((4 * p).div_ceil(nv.max(1)));
    let rows = states * nv;
    let mut w = DMatrix::<f64>::zeros(rows, p);
    for s in 0..states {
        let (q, v, a) = random_state(&mut rng, robot);
        // Run-time gravity: a random vector at each state, so that the base parameters hold
        // for every gravity vector, not only the default's direction.
        let gravity = robot
            .runtime
            .gravity
            .then(|| [0; 3].map(|_| rng.uniform(-10.0, 10.0)));
        let values = g.eval(y, &|x| {
            let i = x.index as usize;
            match x.group {
                super::Q => q[i],
                QD => v[i],
                QDD => a[i],
                super::parameters::PARAM => gravity.map_or(f64::NAN, |g| g[i]),
                _ => 0.0,
            }
        });
        for i in 0..nv {
            for j in 0..p {
                w[(s * nv + i, j)] = values[i * p + j];
            }
        }
    }
    let norms: Vec<f64> = (0..p).map(|j| w.column(j).norm()).collect();
    let largest = norms.iter().fold(0.0f64, |m, &x| m.max(x));
    let zero: Vec<usize> = (0..p)
        .filter(|&j| norms[j] <= ZERO_TOLERANCE * largest)
        .collect();
    // Gram–Schmidt with column pivoting: of the columns not yet explained by the kept ones
    // (relative residual above the tolerance), the one with the largest residual is kept
    // next (ties: the lower index). The columns with the largest effect on τ are kept and
    // the others regroup into them with small coefficients, so `π_base` has little
    // cancellation.
    let mut candidates: Vec<usize> = (0..p).filter(|j| !zero.contains(j)).collect();
    let mut residual: Vec<nalgebra::DVector<f64>> =
        (0..p).map(|j| w.column(j).clone_owned()).collect();
    let mut kept: Vec<usize> = Vec::new();
    loop {
        let mut best: Option<(usize, f64)> = None;
        for (slot, &j) in candidates.iter().enumerate() {
            let r = residual[j].norm();
            if r > RANK_TOLERANCE * norms[j] && best.is_none_or(|(_, b)| r > b) {
                best = Some((slot, r));
            }
        }
        let Some((slot, r)) = best else { break };
        let j = candidates.remove(slot);
        let e = &residual[j] / r;
        for &c in &candidates {
            // Twice, for a residual accurate to rounding ("twice is enough").
            for _ in 0..2 {
                let d = e.dot(&residual[c]);
                residual[c] -= &e * d;
            }
        }
        kept.push(j);
    }
    kept.sort_unstable();
    let dropped = candidates;
    // β of each dropped column: least squares on the kept columns.
    let mut regrouped = vec![Vec::new(); kept.len()];
    if !kept.is_empty() && !dropped.is_empty() {
        let wk = DMatrix::from_fn(rows, kept.len(), |r, c| w[(r, kept[c])]);
        let qr = wk.clone().qr();
        let (qm, rm) = (qr.q(), qr.r());
        for &d in &dropped {
            let rhs = qm.transpose() * w.column(d);
            let beta = rm
                .solve_upper_triangular(&rhs)
                .unwrap_or_else(|| nalgebra::DVector::zeros(kept.len()));
            let big = beta.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (c, &b) in beta.iter().enumerate() {
                if b.abs() > BETA_ZERO * big {
                    regrouped[c].push((d, round_significant(b, 12)));
                }
            }
        }
    }
    Reduction {
        kept,
        regrouped,
        zero,
    }
}
