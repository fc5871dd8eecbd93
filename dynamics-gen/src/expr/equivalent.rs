//! Nodes equal as functions of the inputs, up to a constant factor, merged: identities the
//! constructors cannot see.
//!
//! Hash-consing merges nodes that are built alike; the simplifying constructors fold what
//! they see at the top of their operands. Neither knows `sin² θ + cos² θ = 1`, so a product
//! of a rotation and its transpose survives expansion: the UR5's space Jacobian has
//! `s₀ (0.425 s₀ c₁) + c₀ (0.425 c₀ c₁)`, which is `0.425 c₁`, and the composite inertias of
//! the mass matrix and the Coriolis terms have many such sums. [`merge_equivalent`] finds,
//! for one function's live nodes, the pairs `v = k·w` with `w` an earlier node (an input or a
//! constant included: `s² + c²` is `1`) and `k` a constant, and rebuilds the function with
//! `v` replaced by `w`, `−w` or `k·w`: of the equivalent nodes, the one ready soonest under
//! [`super::reassociate`]'s latency model, and only if `k·w` is ready no later than `v`.
//!
//! # Test
//!
//! Every live node is evaluated at [`SAMPLES`] seeded random points (every input uniform in
//! `(−2, 2)`, sines and cosines through `libm`), with the magnitude `m(v)` of
//! [`super::zeros`] (a first-order bound on the rounding error of the evaluation). Nodes whose
//! values are proportional at every sample are candidates (hashed by their value vector
//! divided by its first entry, rounded to 1e-7); `v` is declared `k·w`, with `k` the ratio at
//! the sample where `|w|` is largest, if at every sample
//!
//! ```text
//! |v̂ − k·ŵ| ≤ TOL_FACTOR · ε · (m(v) + |k|·m(w)),   all values and magnitudes finite.
//! ```
//!
//! The argument is [`super::zeros`]'s for the difference `v − k·w` (a sum of two nodes): an
//! analytic function that is not identically zero is this small at every random sample only
//! with negligible probability, and replacing one that is by zero changes `v` by the rounding
//! noise its evaluation already carries. A divisor or square-root argument is never replaced
//! (there a rounding-level change is not small afterwards), nor is any node a non-finite
//! value reaches. `k` is a sample's ratio, exact to rounding, or the simple fraction (`±1`,
//! `6`, `−1/3`) within 64 ε of it, if the test holds with it: `v = ±w` costs nothing and a
//! scale costs one product.
//!
//! # Guard
//!
//! The rebuilt function is kept only if it needs at least [`MIN_SAVING`] fewer operations
//! ([`ExprGraph::op_counts`]) and its outputs agree with the original's at [`CHECK_SAMPLES`]
//! fresh points to `CHECK_FACTOR · ε · m` of the original output; otherwise the function is
//! left as it was (`None`: the caller emits the graph it has). The values it computes then differ from the unmerged function's by
//! rounding only: the generated code is compared with the reference at its usual tolerance.
//!
//! Why a threshold: a merge moves values' lives (`w` read where `v` was), and the register
//! allocator's spills move with them. Measured on the default x86-64 target's AVX2 copies
//! (instructions in the machine code, old → merged): the UR5's mass matrix (−6.7 % of its
//! operations) 232 → 209, Coriolis (−7.3 %) 307 → 277, forward dynamics (−5.7 %) 644 → 603,
//! the Panda's mass matrix (−6.0 %) 578 → 525; but, merged without the threshold, a
//! general-geometry 7-joint arm's mass matrix (−3.4 %) 901 → 975 and its inverse dynamics
//! (−0.5 %) 1,007 → 1,016. Savings of a few percent are within what any change of a body's
//! schedule moves its machine code by (`docs/performance.md`).

use super::reassociate::{latency, ready_times};
use super::zeros::{value_and_magnitude, SplitMix};
use super::{ExprGraph, ExprId, Input, Node};
use std::collections::HashMap;

/// Random points each node is evaluated at.
pub const SAMPLES: usize = 6;

/// Multiple of `ε` (times the magnitudes) below which `v − k·w` counts as rounding noise.
pub const TOL_FACTOR: f64 = 4.0;

/// The least fraction of a function's operations the merging must save to be kept (below
/// it the function stays as it was; see the module documentation's "Guard").
pub const MIN_SAVING: f64 = 0.05;

/// Fresh points the rebuilt outputs are checked at.
pub const CHECK_SAMPLES: usize = 3;

/// Multiple of `ε` (times an output's magnitude) by which a rebuilt output may differ.
pub const CHECK_FACTOR: f64 = 1024.0;

/// The samples' seed (any fixed value: the result must not depend on the host or the run).
const SEED: u64 = 0x6571_7569_7661_6c65;

/// Values and magnitudes of the live nodes of `g` at `samples` random points, by node then
/// sample (`[i * samples + s]`).
fn evaluate(g: &ExprGraph, live: &[bool], samples: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let n = g.len();
    let (mut val, mut mag) = (vec![0.0f64; n * samples], vec![0.0f64; n * samples]);
    let mut rng = SplitMix(seed);
    for s in 0..samples {
        let (v, m) = values(g, live, &mut |_| rng.uniform(-2.0, 2.0));
        for i in (0..n).filter(|&i| live[i]) {
            val[i * samples + s] = v[i];
            mag[i * samples + s] = m[i];
        }
    }
    (val, mag)
}

/// The function `roots` of `g` rebuilt with its live nodes that equal a constant times an
/// earlier live node replaced by that multiple (module documentation), and its roots in the
/// new graph (which may also hold nodes the roots no longer read); `None` when the function
/// stays as it is (nothing to merge, too little saved, or the guard failed).
pub fn merge_equivalent(g: &ExprGraph, roots: &[ExprId]) -> Option<(ExprGraph, Vec<ExprId>)> {
    let live = g.live(roots);
    let n = g.len();
    let (val, mag) = evaluate(g, &live, SAMPLES, SEED);
    let ready = ready_times(g);
    let at = |i: usize| &val[i * SAMPLES..(i + 1) * SAMPLES];
    let mag_at = |i: usize| &mag[i * SAMPLES..(i + 1) * SAMPLES];
    let mut protected = vec![false; n];
    for (i, node) in g.nodes().iter().enumerate() {
        if live[i] {
            match *node {
                Node::Div(_, b) => protected[b.index()] = true,
                Node::Sqrt(a) => protected[a.index()] = true,
                _ => {}
            }
        }
    }
    let finite = |i: usize| at(i).iter().chain(mag_at(i)).all(|x| x.is_finite());
    // Representatives by the shape of their value vectors; `rep[v] = (w, k)`.
    let mut buckets: HashMap<Vec<i64>, Vec<usize>> = HashMap::new();
    let mut rep: Vec<Option<(usize, f64)>> = vec![None; n];
    let tol = TOL_FACTOR * f64::EPSILON;
    for (i, node) in g.nodes().iter().enumerate() {
        if !live[i] || !finite(i) {
            continue;
        }
        let v = at(i);
        if v.contains(&0.0) {
            continue;
        }
        let key: Vec<i64> = v[1..]
            .iter()
            .map(|&x| ((x / v[0]) * 1e7).round() as i64)
            .collect();
        let bucket = buckets.entry(key).or_default();
        if !protected[i] && !matches!(node, Node::Input(_) | Node::Const(_)) {
            // The equivalent node ready soonest, if `k·w` is ready no later than `v`.
            rep[i] = bucket
                .iter()
                .filter_map(|&w| {
                    let wv = at(w);
                    let s = (0..SAMPLES).max_by(|&a, &b| wv[a].abs().total_cmp(&wv[b].abs()))?;
                    let k = snapped(v[s] / wv[s]);
                    let t = ready[w] + if k.abs() == 1.0 { 0 } else { latency::MUL };
                    let equal = (0..SAMPLES).all(|s| {
                        (v[s] - k * wv[s]).abs() <= tol * (mag_at(i)[s] + k.abs() * mag_at(w)[s])
                    });
                    (equal && t <= ready[i]).then_some((t, w, k))
                })
                .min_by_key(|&(t, w, _)| (t, w))
                .map(|(_, w, k)| (w, k));
        }
        if rep[i].is_none() {
            bucket.push(i);
        }
    }
    if rep.iter().all(Option::is_none) {
        return None;
    }
    let mut out = ExprGraph::new();
    let mut map = vec![ExprId(u32::MAX); n];
    for (i, node) in g.nodes().iter().enumerate() {
        if !live[i] {
            continue;
        }
        map[i] = match rep[i] {
            // The constructor writes `±1·w` as `w` and `−w`.
            Some((w, k)) => {
                let k = out.constant(k);
                out.mul(k, map[w])
            }
            None => out.rebuild(*node, &map, &mut |o, x| o.input(x)),
        };
    }
    let new_roots: Vec<ExprId> = roots.iter().map(|r| map[r.index()]).collect();
    let (before, after) = (
        g.op_counts(roots).total(),
        out.op_counts(&new_roots).total(),
    );
    if (after as f64) > (1.0 - MIN_SAVING) * before as f64 || !agrees(g, roots, &out, &new_roots) {
        return None;
    }
    Some((out, new_roots))
}

/// `k`, or the fraction `p/q` with `q ≤ 12` within 64 ε of it (the sample's ratio carries the
/// rounding of two evaluations: `6s² + 8`, not `5.999999999999999 s² + 8`).
fn snapped(k: f64) -> f64 {
    (1..=12u32)
        .map(|q| (k * f64::from(q)).round() / f64::from(q))
        .find(|r| (r - k).abs() <= 64.0 * f64::EPSILON * k.abs())
        .unwrap_or(k)
}

/// Whether the outputs `b_roots` of `b` equal `a_roots` of `a` at fresh random points, to
/// `CHECK_FACTOR · ε` times the magnitude of `a`'s output.
fn agrees(a: &ExprGraph, a_roots: &[ExprId], b: &ExprGraph, b_roots: &[ExprId]) -> bool {
    let mut rng = SplitMix(SEED ^ 0x5a5a_5a5a);
    for _ in 0..CHECK_SAMPLES {
        // The same inputs on both sides: a value per input, drawn once per sample.
        let mut drawn: HashMap<Input, f64> = HashMap::new();
        let mut input = |x: Input| *drawn.entry(x).or_insert_with(|| rng.uniform(-2.0, 2.0));
        let (va, ma) = values(a, &a.live(a_roots), &mut input);
        let (vb, _) = values(b, &b.live(b_roots), &mut input);
        for (ra, rb) in a_roots.iter().zip(b_roots) {
            let (x, y, m) = (va[ra.index()], vb[rb.index()], ma[ra.index()]);
            let close = (x - y).abs() <= CHECK_FACTOR * f64::EPSILON * m;
            if !(x.is_finite() && y.is_finite() && close) {
                return false;
            }
        }
    }
    true
}

/// Values and magnitudes (by node index) of the `live` nodes of `g` at one point, inputs
/// from `input`.
fn values(
    g: &ExprGraph,
    live: &[bool],
    input: &mut dyn FnMut(Input) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let (mut v, mut m) = (vec![0.0f64; g.len()], vec![0.0f64; g.len()]);
    for (i, node) in g.nodes().iter().enumerate() {
        if live[i] {
            (v[i], m[i]) = value_and_magnitude(node, &v, &m, input);
        }
    }
    (v, m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An input `x`, `s = sin q`, `c = cos q`.
    fn leaves(g: &mut ExprGraph) -> (ExprId, ExprId, ExprId) {
        let q = g.input(Input::new(0, 0));
        let x = g.input(Input::new(1, 0));
        (x, g.sin(q), g.cos(q))
    }

    /// `s·(s·a) + c·(c·a)`.
    fn rotated_back(g: &mut ExprGraph, s: ExprId, c: ExprId, a: ExprId) -> ExprId {
        let sa = g.mul(s, a);
        let ssa = g.mul(s, sa);
        let ca = g.mul(c, a);
        let cca = g.mul(c, ca);
        g.add(ssa, cca)
    }

    #[test]
    fn a_rotation_and_its_transpose_cancel() {
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let v = rotated_back(&mut g, s, c, x);
        let (h, r) = merge_equivalent(&g, &[v]).expect("merged");
        assert_eq!(h.op_counts(&r).total(), 0, "{:?}", h.node(r[0]));
        assert!(matches!(h.node(r[0]), Node::Input(i) if *i == Input::new(1, 0)));
    }

    #[test]
    fn a_multiple_costs_one_product() {
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let half = g.constant(-0.425);
        let a = g.mul(half, x);
        let v = rotated_back(&mut g, s, c, a);
        let y = g.input(Input::new(1, 1));
        let out = g.add(v, y);
        let (h, r) = merge_equivalent(&g, &[out]).expect("merged");
        assert_eq!(h.op_counts(&r).total(), 2); // −0.425·x + y
    }

    #[test]
    fn sines_squared_and_cosines_squared_are_one() {
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let ss = g.mul(s, s);
        let cc = g.mul(c, c);
        let one = g.add(ss, cc);
        let v = g.mul(one, x);
        let (h, r) = merge_equivalent(&g, &[v]).expect("merged");
        assert_eq!(h.op_counts(&r).total(), 0);
    }

    #[test]
    fn different_functions_stay_apart() {
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let y = g.input(Input::new(1, 1));
        // s²x + c²y is not x (nor y): nothing to merge, the function comes back as it was.
        let sx = g.mul(s, x);
        let ssx = g.mul(s, sx);
        let cy = g.mul(c, y);
        let ccy = g.mul(c, cy);
        let v = g.add(ssx, ccy);
        assert!(merge_equivalent(&g, &[v, x]).is_none());
    }

    #[test]
    fn a_divisor_is_never_replaced() {
        // d = s²z + c²z is z, but it divides: kept as computed (x/d is no other node).
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let z = g.input(Input::new(1, 1));
        let d = rotated_back(&mut g, s, c, z);
        let v = g.div(x, d);
        assert!(merge_equivalent(&g, &[v]).is_none());
    }

    #[test]
    fn small_savings_leave_the_function_as_it_was() {
        // One cancellation among many other operations: below MIN_SAVING, so unchanged.
        let mut g = ExprGraph::new();
        let (x, s, c) = leaves(&mut g);
        let v = rotated_back(&mut g, s, c, x);
        let mut acc = v;
        for k in 0..60 {
            let y = g.input(Input::new(2, k));
            let p = g.mul(acc, y);
            acc = g.add(p, y);
        }
        let before = g.op_counts(&[acc]).total();
        assert!(5 * 20 < before, "the merge would save 5 of {before}");
        assert!(merge_equivalent(&g, &[acc]).is_none());
    }
}
