//! Sums rebuilt for instruction-level parallelism: tree-height reduction under a latency model.
//!
//! The recursions build their sums in the order the algebra reads (`r₀ a₀ + r₁ a₁ + r₂ a₂`,
//! the link's own force plus the child's transported one), and a sum built left to right is
//! a chain: each addition waits for the one before. Where a late term (one at the end of a
//! long dependency chain: the forward pass's last link, the backward pass's accumulated
//! wrench) comes first, every later term waits for it, and the whole function's critical
//! path grows. Generated dynamics are bound by that path rather than by their operation
//! count (measured: three multiplications for four in every plane rotation made a 7-joint
//! arm's inverse dynamics 13 % *slower*).
//!
//! [`reassociate`] flattens every maximal sum tree (additions, subtractions and negations
//! used once, by the sum) into signed terms and adds them up again, earliest first: the two
//! terms ready soonest are combined, their sum goes back among the terms, until one is left
//! (Huffman's construction with `max(a, b) + latency` for `a + b`; with a single addition
//! latency it minimises the sum's completion time). A product used once is a term that the
//! emitted code fuses into its addition (`fma`), so it counts from its operands' time plus
//! a fused multiply-add's latency. A sum is replaced only where the rebuilt one is ready
//! sooner under the model than the sum as built ([`MIN_GAIN`]): elsewhere the association
//! stays, and with it the emitted code. The numbers of additions and multiplications are
//! unchanged; only the association (and with it the rounding, within the sum's ordinary
//! rounding error) changes.
//!
//! Measured side by side in one binary (medians of 9 rounds of 20,000 calls, results by
//! value and by reference): a 7-joint general-geometry arm's inverse dynamics −5 to −7 %,
//! forward dynamics −6 to −12 %, gravity −19 to −23 %; the UR5 −1 to −5 %. The Panda's
//! inverse dynamics moved by +2 % (by reference) to +12 % (by value): the machine-code
//! effect of results returned by value that `docs/performance.md` describes, which moves
//! with any change of the body.

use super::{ExprGraph, ExprId, Node};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Latencies (cycles) of the model, typical of current x86-64 and AArch64 cores: an addition
/// or a product 3, a fused multiply-add 4, a quotient 13, a square root 15; every sine and
/// cosine is ready at [`TRIG`] (they are computed together, first).
pub mod latency {
    /// `a + b`, `a − b`.
    pub const ADD: u32 = 3;
    /// `a · b`.
    pub const MUL: u32 = 3;
    /// `a · b + c`.
    pub const FMA: u32 = 4;
    /// `a / b`.
    pub const DIV: u32 = 13;
    /// `√a`.
    pub const SQRT: u32 = 15;
    /// The sines and cosines of the joint angles.
    pub const TRIG: u32 = 50;
}

/// The time (cycles, [`latency`] model) at which each node of `g` is ready, a product that
/// is an operand of a sum counted as fused into it.
pub fn ready_times(g: &ExprGraph) -> Vec<u32> {
    let mut ready = Vec::with_capacity(g.len());
    for node in g.nodes() {
        let t = node_time(g, node, &ready);
        ready.push(t);
    }
    ready
}

fn node_time(g: &ExprGraph, node: &Node, ready: &[u32]) -> u32 {
    use latency::*;
    let ops = node.operands().map(|o| ready[o.index()]).max().unwrap_or(0);
    // A product operand of a sum is fused into it (the later of two; the other is computed
    // first): it counts from its operands' time.
    let product = |o: ExprId| match *g.node(o) {
        Node::Mul(x, y) => Some(ready[x.index()].max(ready[y.index()])),
        _ => None,
    };
    match *node {
        Node::Const(_) | Node::Input(_) => 0,
        Node::Neg(_) => ops,
        Node::Add(a, b) | Node::Sub(a, b) => match (product(a), product(b)) {
            (None, None) => ops + ADD,
            (Some(p), None) => p.max(ready[b.index()]) + FMA,
            (None, Some(p)) => p.max(ready[a.index()]) + FMA,
            (Some(p), Some(q)) => (p.min(q) + MUL).max(p.max(q)) + FMA,
        },
        Node::Mul(..) => ops + MUL,
        Node::Div(..) => ops + DIV,
        Node::Sqrt(_) => ops + SQRT,
        Node::Sin(_) | Node::Cos(_) => ops.max(TRIG),
    }
}

/// How much sooner (cycles) a re-associated sum must be ready to replace the sum as built.
const MIN_GAIN: u32 = 1;

/// A term of a sum being rebuilt.
#[derive(Clone, Copy)]
struct Term {
    /// The node in the new graph.
    id: ExprId,
    /// Subtracted rather than added.
    neg: bool,
    /// A product used only here, fused into the addition that takes it.
    product: bool,
    /// When it can enter an addition: its value's time, or a fused product's operands'.
    time: u32,
}

/// `g` with every sum of the nodes live from `roots` re-associated (see the module docs),
/// and the roots in the new graph.
pub fn reassociate(g: &ExprGraph, roots: &[ExprId]) -> (ExprGraph, Vec<ExprId>) {
    let live = g.live(roots);
    let uses = g.use_counts(roots);
    let is_sum = |id: ExprId| matches!(g.node(id), Node::Add(..) | Node::Sub(..) | Node::Neg(_));
    // Interior nodes: sums used once, by a sum, which flattens them into its own terms.
    let mut interior = vec![false; g.len()];
    for (k, node) in g.nodes().iter().enumerate() {
        if live[k] && is_sum(ExprId(k as u32)) {
            for o in node.operands() {
                if uses[o.index()] == 1 && is_sum(o) {
                    interior[o.index()] = true;
                }
            }
        }
    }
    for r in roots {
        interior[r.index()] = false;
    }
    let mut out = ExprGraph::new();
    let mut ready: Vec<u32> = Vec::new();
    let mut map: Vec<Option<ExprId>> = vec![None; g.len()];
    let mut stack = Vec::new();
    let mut terms = Vec::new();
    for (k, node) in g.nodes().iter().enumerate() {
        if !live[k] {
            continue;
        }
        let m = |o: ExprId| map[o.index()].expect("operands are mapped before their users");
        // The node as it is (for a sum: its association as built).
        let same = match *node {
            Node::Const(c) => out.constant(c.value()),
            Node::Input(x) => out.input(x),
            Node::Mul(a, b) => out.mul(m(a), m(b)),
            Node::Div(a, b) => out.div(m(a), m(b)),
            Node::Sqrt(a) => out.sqrt(m(a)),
            Node::Sin(a) => out.sin(m(a)),
            Node::Cos(a) => out.cos(m(a)),
            Node::Add(a, b) => out.add(m(a), m(b)),
            Node::Sub(a, b) => out.sub(m(a), m(b)),
            Node::Neg(a) => out.neg(m(a)),
        };
        extend(&mut ready, &out);
        let id = match *node {
            _ if interior[k] => same,
            Node::Add(..) | Node::Sub(..) | Node::Neg(_) => {
                // Flatten the tree under this root into signed terms.
                terms.clear();
                stack.push((ExprId(k as u32), false));
                while let Some((id, neg)) = stack.pop() {
                    let inner = id.index() == k || interior[id.index()];
                    match *g.node(id) {
                        Node::Add(a, b) if inner => {
                            stack.push((b, neg));
                            stack.push((a, neg));
                        }
                        Node::Sub(a, b) if inner => {
                            stack.push((b, !neg));
                            stack.push((a, neg));
                        }
                        Node::Neg(a) if inner => stack.push((a, !neg)),
                        _ => {
                            let new = m(id);
                            let (product, time) = match *out.node(new) {
                                Node::Mul(x, y) if uses[id.index()] == 1 => {
                                    (true, ready[x.index()].max(ready[y.index()]))
                                }
                                _ => (false, ready[new.index()]),
                            };
                            terms.push(Term {
                                id: new,
                                neg,
                                product,
                                time,
                            });
                        }
                    }
                }
                let sum = rebuild(&mut out, &mut ready, &terms);
                // Re-associated only where that makes the sum ready sooner.
                if ready[sum.index()] + MIN_GAIN <= ready[same.index()] {
                    sum
                } else {
                    same
                }
            }
            _ => same,
        };
        map[k] = Some(id);
    }
    let roots = roots
        .iter()
        .map(|r| map[r.index()].expect("roots are live"))
        .collect();
    (out, roots)
}

/// Extends `ready` over the nodes `out` gained since it was last extended.
fn extend(ready: &mut Vec<u32>, out: &ExprGraph) {
    for k in ready.len()..out.len() {
        let t = node_time(out, &out.nodes()[k], ready);
        ready.push(t);
    }
}

/// The sum of `terms`, the two soonest ready combined first.
fn rebuild(out: &mut ExprGraph, ready: &mut Vec<u32>, terms: &[Term]) -> ExprId {
    use latency::*;
    // Ties in term order, so that the result does not depend on anything but the graph.
    let mut heap: BinaryHeap<Reverse<(u32, usize)>> = terms
        .iter()
        .enumerate()
        .map(|(i, t)| Reverse((t.time, i)))
        .collect();
    let mut items: Vec<Term> = terms.to_vec();
    while heap.len() > 1 {
        let Reverse((_, i)) = heap.pop().expect("two items");
        let Reverse((_, j)) = heap.pop().expect("two items");
        let (a, b) = (items[i], items[j]);
        // a is ready no later than b: if both are products, a is computed alone and b fused.
        let time = match (a.product, b.product) {
            (false, false) => a.time.max(b.time) + ADD,
            (true, true) => (a.time + MUL).max(b.time) + FMA,
            _ => a.time.max(b.time) + FMA,
        };
        let before = out.len();
        let (id, neg) = match (a.neg, b.neg) {
            (false, false) => (out.add(a.id, b.id), false),
            (false, true) => (out.sub(a.id, b.id), false),
            (true, false) => (out.sub(b.id, a.id), false),
            (true, true) => (out.add(a.id, b.id), true),
        };
        extend(ready, out);
        // A new node gets the model's time (fused products); an existing one keeps its own.
        if id.index() >= before {
            ready[id.index()] = time;
        }
        let time = ready[id.index()];
        items.push(Term {
            id,
            neg,
            product: false,
            time,
        });
        heap.push(Reverse((time, items.len() - 1)));
    }
    let Reverse((_, i)) = heap.pop().expect("a sum has a term");
    let t = items[i];
    if t.neg {
        let id = out.neg(t.id);
        extend(ready, out);
        id
    } else {
        t.id
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Input;

    /// The latest output's time.
    fn critical(g: &ExprGraph, roots: &[ExprId]) -> u32 {
        let ready = ready_times(g);
        roots.iter().map(|r| ready[r.index()]).max().unwrap_or(0)
    }

    #[test]
    fn a_late_term_is_added_last() {
        // ((late + a) + b) + c, with `late` at the end of a chain of products.
        let mut g = ExprGraph::new();
        let x: Vec<ExprId> = (0..4).map(|i| g.input(Input::new(0, i))).collect();
        let mut late = x[0];
        for _ in 0..10 {
            late = g.mul(late, x[0]);
        }
        let s1 = g.add(late, x[1]);
        let s2 = g.add(s1, x[2]);
        let root = g.sub(s2, x[3]);
        let (h, roots) = reassociate(&g, &[root]);
        assert!(critical(&h, &roots) < critical(&g, &[root]));
        assert_eq!(critical(&h, &roots), 9 * latency::MUL + latency::FMA);
        let args = [1.5, 0.25, -0.5, 2.0];
        let inputs = |i: Input| args[i.index as usize];
        let want = g.eval(&[root], &inputs)[0];
        let got = h.eval(&roots, &inputs)[0];
        assert!((got - want).abs() <= 1e-12 * want.abs(), "{got} vs {want}");
        assert_eq!(h.op_counts(&roots), g.op_counts(&[root]));
    }

    #[test]
    fn a_sum_with_nothing_to_gain_is_kept() {
        let mut g = ExprGraph::new();
        let x: Vec<ExprId> = (0..3).map(|i| g.input(Input::new(0, i))).collect();
        let p = g.mul(x[0], x[1]);
        let s = g.add(x[2], p);
        let root = g.neg(s);
        let (h, roots) = reassociate(&g, &[root]);
        assert_eq!(h.nodes(), g.nodes());
        assert_eq!(roots, vec![root]);
    }

    #[test]
    fn shared_sums_stay_whole_and_values_are_kept() {
        // A sum used twice is a term of both users, not flattened into either.
        let mut g = ExprGraph::new();
        let x: Vec<ExprId> = (0..5).map(|i| g.input(Input::new(0, i))).collect();
        let mut late = x[4];
        for _ in 0..6 {
            late = g.mul(late, x[3]);
        }
        let shared = g.add(late, x[0]);
        let a = g.add(shared, x[1]);
        let a = g.sub(a, x[2]);
        let b = g.mul(shared, x[2]);
        let c = g.add(b, x[1]);
        let c = g.add(c, x[0]);
        let (h, roots) = reassociate(&g, &[a, c]);
        let args = [0.3, -1.25, 0.75, 1.1, -0.9];
        let inputs = |i: Input| args[i.index as usize];
        let want = g.eval(&[a, c], &inputs);
        let got = h.eval(&roots, &inputs);
        for (x, y) in got.iter().zip(&want) {
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{x} vs {y}");
        }
        assert_eq!(h.op_counts(&roots), g.op_counts(&[a, c]));
        assert!(critical(&h, &roots) <= critical(&g, &[a, c]));
        // Deterministic.
        let (h2, roots2) = reassociate(&g, &[a, c]);
        assert_eq!(h2.nodes(), h.nodes());
        assert_eq!(roots2, roots);
    }
}
