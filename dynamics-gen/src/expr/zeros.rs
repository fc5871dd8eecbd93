//! Finding nodes that are identically zero although no insertion rule saw it.
//!
//! The constructors only look at the top of their operands, so a cancellation spread across
//! a sum (`(a + b) - (a + c)` with `b = c` after many steps, or the Panda's `g₁`, which is 0
//! for every `q` because its first axis is vertical) survives insertion and is computed at
//! run time as rounding noise of size ~1e-15. [`ExprGraph::prune_zeros`] finds such nodes
//! numerically and rebuilds the graph with them replaced by the constant 0.
//!
//! # Test
//!
//! Only sums and differences are tested: they are where a cancellation happens. A product,
//! quotient, negation, square root or sine of a zero node becomes zero by the constructors
//! once its operand is replaced (analytic functions have no zero divisors, so a product is
//! identically zero only if a factor is).
//!
//! Every live node `v` is evaluated (sines and cosines through `libm`, as constant folding
//! does, so the decision does not depend on the host) at [`SAMPLES`] seeded random input
//! vectors `x_k`
//! together with its *magnitude* `m(v)`, a first-order bound on how much the rounding
//! errors of the evaluation can move `v` (relative errors of size `u` in every leaf and
//! operation, to first order):
//!
//! ```text
//! m(c) = |c|          m(x) = |x|            m(a ± b) = m(a) + m(b)      m(-a) = m(a)
//! m(a·b) = |a|·m(b) + m(a)·|b|              m(a/b) = (m(a) + |a/b|·m(b)) / |b|
//! m(sqrt a) = m(a) / (2·sqrt|a|)            m(sin a) = |cos a|·m(a) + |sin a|
//! m(cos a) = |sin a|·m(a) + |cos a|
//! ```
//!
//! For leaves, sums and differences this is the value the node would have if every
//! operation were done on absolute values; for a product it is *not* `m(a)·m(b)`: that
//! over-estimates the rounding error of a product of two factors that each carry a
//! cancellation by the product of their cancellation ratios, and in testing it made
//! products of genuinely non-zero (merely cancelled) factors look like rounding noise.
//! By induction `m(v) ≥ |v|`, and the computed value `v̂` satisfies, to first order,
//! `|v̂ − v| ≤ d(v)·u·m(v)` with `u = ε/2` and `d(v)` the depth of `v` (leaves 0, every
//! operation one more than its deepest operand): the classical running error bound
//! (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.1, 3.3).
//!
//! A sum or difference `v` is declared zero if, at every sample,
//!
//! ```text
//! |v̂(x_k)| ≤ tol · m(v)(x_k),   tol = TOL_FACTOR · ε = ε,   0 < m(v)(x_k) < ∞.
//! ```
//!
//! The tolerance is deliberately *not* the worst-case bound `d(v)·u`: `m` is a worst case
//! (every rounding error at its maximum, all with the same sign, no cancellation among
//! them) and over-estimates the actual error of deep expressions by many orders of
//! magnitude. Measured on the expansion (largest `|v̂|/(ε·m)` over the 4 samples, per
//! sum): the Panda's zero sums (the ones making up `g₁`) are at ≈ 0.01, its non-zero sums
//! at ≥ 1e11; on a 12-joint random chain's articulated-body algorithm non-zero sums go down
//! to ≈ 100 (with the depth-scaled `16·d·ε` this pass pruned some of them, caught by the
//! property test `pruning_zeros_keeps_values_on_random_chains`). `ε` sits in the gap with
//! two decades of margin on either side; a zero it misses is merely left unpruned.
//!
//! # Why this is sound
//!
//! Every node is an analytic function of the inputs on the open set where its divisors
//! are non-zero and its square-root arguments positive. If such a function `f` is not
//! identically zero, the set where `|f| ≤ tol·m` is, for any `tol` small against
//! `|f|/m` somewhere, a thin neighbourhood of the measure-zero zero set of `f`; the chance
//! that all [`SAMPLES`] independent random points fall in it is negligible. If instead
//! `|f| ≤ tol·m` holds (nearly) everywhere, `f` is itself of the size of the rounding error
//! of its own evaluation, and replacing it by 0 changes the node by at most `tol·m`, which
//! is the same order as the error the evaluation already makes: the output changes by no
//! more than the rounding noise it already carries. A node exactly zero at some samples
//! but not all is kept (the test must hold at every sample), and so is a node with `m = 0`
//! or a non-finite value or magnitude at any sample.
//!
//! The argument bounds the change of the pruned node, not of the outputs: where `m`
//! over-estimates the rounding error by many orders of magnitude (deep trees: the
//! articulated inertias of a 15-body branch), a genuinely non-zero sum can fall under
//! `ε·m`, and its removal is then amplified downstream. The expansion therefore checks every
//! pruning by evaluating the outputs before and after at fresh samples
//! (`expand::prune_checked`) and retries with a tighter tolerance, or keeps the graph
//! unpruned, when they differ.
//!
//! To stay on the safe side, a node that is used directly as a divisor or under a square
//! root is never replaced: there a change at rounding level is not small after the
//! operation (`1/v`, `√v`).
//!
//! The rebuilt graph re-inserts every live node in id order through the simplifying
//! constructors with its operands mapped, and the zero nodes replaced by the constant 0;
//! the zeros then propagate (`0·x → 0`, `x + 0 → x`, ...), so the whole computation of a
//! zero output disappears.

use super::graph::ExprGraph;
use super::node::{ExprId, Input, Node};

/// Number of random input vectors each node is evaluated at.
pub const SAMPLES: usize = 4;

/// Multiple of `ε` (times the magnitude `m`) below which a sum counts as rounding noise.
pub const TOL_FACTOR: f64 = 1.0;

/// A SplitMix64 stream (deterministic on every host; also the samples of
/// [`crate::check`]).
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

impl ExprGraph {
    /// The live nodes of `roots` that are identically zero up to rounding (see the
    /// [module documentation](self)): `zero[i]` is true for such a node `i`. Input `x` is
    /// sampled uniformly in `range(x) = (lo, hi)`; the samples are seeded with `seed`.
    pub fn find_zeros(
        &self,
        roots: &[ExprId],
        range: &dyn Fn(Input) -> (f64, f64),
        seed: u64,
    ) -> Vec<bool> {
        self.find_zeros_with(roots, range, seed, TOL_FACTOR)
    }

    /// [`find_zeros`](Self::find_zeros) with the tolerance `tol_factor · ε · m`.
    pub fn find_zeros_with(
        &self,
        roots: &[ExprId],
        range: &dyn Fn(Input) -> (f64, f64),
        seed: u64,
        tol_factor: f64,
    ) -> Vec<bool> {
        let n = self.len();
        let live = self.live(roots);
        // Nodes whose rounding-level change is not small after their user.
        let mut protected = vec![false; n];
        for (i, node) in self.nodes.iter().enumerate() {
            if !live[i] {
                continue;
            }
            match *node {
                Node::Div(_, b) => protected[b.index()] = true,
                Node::Sqrt(a) => protected[a.index()] = true,
                _ => {}
            }
        }
        // Candidates: live sums and differences; cleared at the first refuting sample.
        let mut zero: Vec<bool> = self
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                live[i] && !protected[i] && matches!(node, Node::Add(..) | Node::Sub(..))
            })
            .collect();
        let mut rng = SplitMix(seed);
        let mut val = vec![0.0f64; n];
        let mut mag = vec![0.0f64; n];
        for _ in 0..SAMPLES {
            for (i, node) in self.nodes.iter().enumerate() {
                if !live[i] {
                    continue;
                }
                let (vi, mi) = value_and_magnitude(node, &val, &mag, &mut |x| {
                    let (lo, hi) = range(x);
                    rng.uniform(lo, hi)
                });
                val[i] = vi;
                mag[i] = mi;
                if zero[i] {
                    let tol = tol_factor * f64::EPSILON;
                    zero[i] = mi > 0.0 && mi.is_finite() && vi.is_finite() && vi.abs() <= tol * mi;
                }
            }
        }
        zero
    }

    /// The graph rebuilt from the live nodes of `roots` with the nodes found by
    /// [`find_zeros`](Self::find_zeros) replaced by the constant 0, and the roots mapped
    /// into it (same shape as `roots`). Every live node is re-inserted in id order through
    /// the simplifying constructors, so the zeros propagate; dead nodes are dropped.
    pub fn prune_zeros(
        &self,
        roots: &[&[ExprId]],
        range: &dyn Fn(Input) -> (f64, f64),
        seed: u64,
    ) -> (ExprGraph, Vec<Vec<ExprId>>) {
        self.prune_zeros_with(roots, range, seed, TOL_FACTOR)
    }

    /// [`prune_zeros`](Self::prune_zeros) with the tolerance `tol_factor · ε · m`; a factor
    /// of 0 prunes only nodes that are exactly zero at every sample.
    pub fn prune_zeros_with(
        &self,
        roots: &[&[ExprId]],
        range: &dyn Fn(Input) -> (f64, f64),
        seed: u64,
        tol_factor: f64,
    ) -> (ExprGraph, Vec<Vec<ExprId>>) {
        let all: Vec<ExprId> = roots.iter().flat_map(|r| r.iter().copied()).collect();
        let zero = self.find_zeros_with(&all, range, seed, tol_factor);
        let live = self.live(&all);
        let mut g = ExprGraph::new();
        let mut map = vec![ExprId(u32::MAX); self.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            if !live[i] {
                continue;
            }
            let m = |id: ExprId| map[id.index()];
            map[i] = if zero[i] {
                g.zero()
            } else {
                match *node {
                    Node::Const(c) => g.constant(c.value()),
                    Node::Input(x) => g.input(x),
                    Node::Neg(a) => g.neg(m(a)),
                    Node::Add(a, b) => g.add(m(a), m(b)),
                    Node::Sub(a, b) => g.sub(m(a), m(b)),
                    Node::Mul(a, b) => g.mul(m(a), m(b)),
                    Node::Div(a, b) => g.div(m(a), m(b)),
                    Node::Sqrt(a) => g.sqrt(m(a)),
                    Node::Sin(a) => g.sin(m(a)),
                    Node::Cos(a) => g.cos(m(a)),
                }
            };
        }
        let roots = roots
            .iter()
            .map(|r| r.iter().map(|id| map[id.index()]).collect())
            .collect();
        (g, roots)
    }
}

/// The value of `node` and its magnitude `m` (module documentation), its operands' values
/// and magnitudes in `val` and `mag` (by node index), an input's value drawn by `input`.
pub(super) fn value_and_magnitude(
    node: &Node,
    val: &[f64],
    mag: &[f64],
    input: &mut dyn FnMut(Input) -> f64,
) -> (f64, f64) {
    let v = |id: ExprId| val[id.index()];
    let m = |id: ExprId| mag[id.index()];
    match *node {
        Node::Const(c) => (c.value(), c.value().abs()),
        Node::Input(x) => {
            let s = input(x);
            (s, s.abs())
        }
        Node::Neg(a) => (-v(a), m(a)),
        Node::Add(a, b) => (v(a) + v(b), m(a) + m(b)),
        Node::Sub(a, b) => (v(a) - v(b), m(a) + m(b)),
        Node::Mul(a, b) => (v(a) * v(b), v(a).abs() * m(b) + m(a) * v(b).abs()),
        Node::Div(a, b) => {
            let q = v(a) / v(b);
            (q, (m(a) + q.abs() * m(b)) / v(b).abs())
        }
        Node::Sqrt(a) => {
            let r = v(a).sqrt();
            (r, m(a) / (2.0 * r))
        }
        Node::Sin(a) => {
            let (s, c) = (libm::sin(v(a)), libm::cos(v(a)));
            (s, c.abs() * m(a) + s.abs())
        }
        Node::Cos(a) => {
            let (s, c) = (libm::sin(v(a)), libm::cos(v(a)));
            (c, s.abs() * m(a) + c.abs())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(_: Input) -> (f64, f64) {
        (-1.0, 1.0)
    }

    #[test]
    fn spread_cancellation_is_found_and_pruned() {
        let mut g = ExprGraph::new();
        let x = g.input(Input::new(0, 0));
        let y = g.input(Input::new(0, 1));
        let (sx, cx) = (g.sin(x), g.cos(x));
        // f = (0.3 sin x + y cos x) + 0.7 sin x - (y cos x + sin x): zero, but no rule sees it.
        let k3 = g.constant(0.3);
        let k7 = g.constant(0.7);
        let a = g.mul(k3, sx);
        let ycx = g.mul(y, cx);
        let b = g.add(a, ycx);
        let c = g.mul(k7, sx);
        let d = g.add(b, c);
        let e = g.add(ycx, sx);
        let f = g.sub(d, e);
        assert!(!g.is_zero(f));
        let h = g.mul(f, y);
        let out = g.add(h, sx);
        let (p, roots) = g.prune_zeros(&[&[f, out, x]], &unit, 1);
        assert!(p.is_zero(roots[0][0]));
        assert_eq!(*p.node(roots[0][1]), Node::Sin(roots[0][2]));
        p.verify().unwrap();
    }

    #[test]
    fn nonzero_and_sometimes_zero_nodes_are_kept() {
        let mut g = ExprGraph::new();
        let x = g.input(Input::new(0, 0));
        let y = g.input(Input::new(0, 1));
        // Tiny but not rounding noise relative to its magnitude.
        let tiny = g.constant(1e-30);
        let t = g.mul(tiny, x);
        // (x + 1e-9) - x is small against m = 2|x| but well above rounding.
        let eps = g.constant(1e-9);
        let xe = g.add(x, eps);
        let s = g.sub(xe, x);
        // max(0, .)-like: zero for half the inputs is impossible here, but a node
        // exactly zero at some samples only: x*y is never zero at random samples,
        // and sqrt(x*x) - x is 0 for x > 0 only.
        let xx = g.mul(x, x);
        let r = g.sqrt(xx);
        let half = g.sub(r, x);
        let z = g.find_zeros(&[t, s, half, y], &unit, 3);
        assert!(!z[t.index()] && !z[s.index()] && !z[half.index()]);
        assert!(z.iter().all(|&b| !b));
    }

    #[test]
    fn divisors_and_square_root_arguments_are_protected() {
        let mut g = ExprGraph::new();
        let x = g.input(Input::new(0, 0));
        let (sx, cx) = (g.sin(x), g.cos(x));
        let s2 = g.mul(sx, sx);
        let c2 = g.mul(cx, cx);
        let one = g.one();
        let sum = g.add(s2, c2);
        let zero_ish = g.sub(sum, one); // sin² + cos² - 1
        let q = g.div(x, zero_ish);
        let r = g.sqrt(zero_ish);
        let plain = g.mul(zero_ish, x);
        let z = g.find_zeros(&[q, r, plain], &unit, 5);
        assert!(!z[zero_ish.index()], "divisor kept");
        let z = g.find_zeros(&[plain], &unit, 5);
        assert!(z[zero_ish.index()], "sin² + cos² - 1 is found elsewhere");
    }
}
