//! Liveness, use counts and operation counts.

use std::fmt;

use super::graph::ExprGraph;
use super::node::{ExprId, Node};

/// Number of arithmetic operations needed to evaluate a set of roots once,
/// with every shared node computed once.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct OpCounts {
    /// Multiplications (including multiplications by a constant).
    pub mul: usize,
    /// Additions and subtractions.
    pub add_sub: usize,
    /// Divisions.
    pub div: usize,
    /// Square roots.
    pub sqrt: usize,
    /// Negations.
    pub neg: usize,
    /// Distinct arguments `x` with a live `sin(x)` and/or `cos(x)`
    /// (a sine/cosine pair of the same argument costs one `sin_cos`).
    pub sin_cos: usize,
}

impl OpCounts {
    /// Total number of operations (every kind weighted 1).
    pub fn total(&self) -> usize {
        self.mul + self.add_sub + self.div + self.sqrt + self.neg + self.sin_cos
    }
}

impl fmt::Display for OpCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "mul {}, add/sub {}, div {}, sqrt {}, neg {}, sin_cos {}",
            self.mul, self.add_sub, self.div, self.sqrt, self.neg, self.sin_cos
        )
    }
}

impl ExprGraph {
    /// `live[i]` is true iff node `i` is reachable from some root.
    /// The result has one entry per node of the graph.
    ///
    /// # Panics
    /// If a root does not belong to this graph.
    pub fn live(&self, roots: &[ExprId]) -> Vec<bool> {
        let mut live = vec![false; self.len()];
        for r in roots {
            live[r.index()] = true;
        }
        // Operands are older than their users: one backward sweep suffices.
        for i in (0..self.len()).rev() {
            if live[i] {
                for o in self.nodes[i].operands() {
                    live[o.index()] = true;
                }
            }
        }
        live
    }

    /// Number of uses of every node: one per operand slot of a live node
    /// (so `x*x` uses `x` twice) plus one per occurrence in `roots`.
    /// Dead nodes have count 0.
    pub fn use_counts(&self, roots: &[ExprId]) -> Vec<u32> {
        let live = self.live(roots);
        let mut uses = vec![0u32; self.len()];
        for r in roots {
            uses[r.index()] += 1;
        }
        for (node, _) in self.nodes.iter().zip(&live).filter(|(_, &l)| l) {
            for o in node.operands() {
                uses[o.index()] += 1;
            }
        }
        uses
    }

    /// Operation counts of the nodes live from `roots`.
    pub fn op_counts(&self, roots: &[ExprId]) -> OpCounts {
        let live = self.live(roots);
        let mut trig_arg = vec![false; self.len()];
        let mut c = OpCounts::default();
        for (node, _) in self.nodes.iter().zip(&live).filter(|(_, &l)| l) {
            match *node {
                Node::Const(_) | Node::Input(_) => {}
                Node::Neg(_) => c.neg += 1,
                Node::Add(..) | Node::Sub(..) => c.add_sub += 1,
                Node::Mul(..) => c.mul += 1,
                Node::Div(..) => c.div += 1,
                Node::Sqrt(_) => c.sqrt += 1,
                Node::Sin(x) | Node::Cos(x) => {
                    if !trig_arg[x.index()] {
                        trig_arg[x.index()] = true;
                        c.sin_cos += 1;
                    }
                }
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::super::node::Input;
    use super::*;

    #[test]
    fn hand_counted_example() {
        // f = 2*sin(q0)*cos(q0) + sqrt(q1)/(q1 - q0) - sin(q1)   (plus a dead node)
        let mut g = ExprGraph::new();
        let q0 = g.input(Input::new(0, 0));
        let q1 = g.input(Input::new(0, 1));
        let two = g.constant(2.0);
        let s0 = g.sin(q0);
        let c0 = g.cos(q0);
        let t = g.mul(two, s0);
        let t = g.mul(t, c0); // (2*sin)*cos: two muls
        let sq = g.sqrt(q1); // sqrt 1
        let d = g.sub(q1, q0); // add_sub 1
        let r = g.div(sq, d); // div 1
        let s1 = g.sin(q1);
        let u = g.add(t, r); // add_sub 2
        let f = g.sub(u, s1); // add_sub 3
        let dead = g.mul(q0, q1);
        let dead = g.neg(dead);
        let counts = g.op_counts(&[f]);
        let expected = OpCounts {
            mul: 2,
            add_sub: 3,
            div: 1,
            sqrt: 1,
            neg: 0,
            sin_cos: 2,
        };
        assert_eq!(counts, expected);
        assert_eq!(counts.total(), 9);
        let both = g.op_counts(&[f, dead]);
        assert_eq!(
            both,
            OpCounts {
                mul: 3,
                neg: 1,
                ..expected
            }
        );

        let live = g.live(&[f]);
        assert!(live[q0.index()] && live[two.index()] && live[f.index()]);
        assert!(!live[dead.index()]);
        let uses = g.use_counts(&[f, f]);
        assert_eq!(uses[f.index()], 2);
        assert_eq!(uses[q0.index()], 3); // sin, cos, sub
        assert_eq!(uses[q1.index()], 3); // sqrt, sub, sin
        assert_eq!(uses[dead.index()], 0);
        let sq_self = g.mul(q1, q1);
        assert_eq!(g.use_counts(&[sq_self])[q1.index()], 2);
    }
}
