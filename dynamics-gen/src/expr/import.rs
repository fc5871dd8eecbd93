//! Copying expressions from one graph into another.

use super::graph::ExprGraph;
use super::node::{ExprId, Input, Node};

impl ExprGraph {
    /// Copies the live part of `other` under `roots` into this graph and returns the roots'
    /// ids here (same order). Every node is re-inserted through the simplifying constructors,
    /// so nodes the two graphs share (inputs, `sin q_i`, common subexpressions) are merged by
    /// hash-consing: expressions of two expansions can be combined in one function.
    pub fn import(&mut self, other: &ExprGraph, roots: &[ExprId]) -> Vec<ExprId> {
        let live = other.live(roots);
        let mut map = vec![ExprId(u32::MAX); other.len()];
        for (i, node) in other.nodes().iter().enumerate() {
            if live[i] {
                map[i] = self.rebuild(*node, &map, &mut |g, x| g.input(x));
            }
        }
        roots.iter().map(|id| map[id.index()]).collect()
    }

    /// The expressions `roots` with input leaves replaced: every input `x` for which
    /// `f(x)` is `Some(e)` (an expression of this graph) becomes `e`, the others stay. The
    /// live part of `roots` is rebuilt through the simplifying constructors, like
    /// [`ExprGraph::import`]; nodes that read no replaced input come back as themselves
    /// (rebuilding a stored node returns it), so only what depends on a replaced input is
    /// new.
    pub fn substitute(
        &mut self,
        roots: &[ExprId],
        f: &dyn Fn(Input) -> Option<ExprId>,
    ) -> Vec<ExprId> {
        let live = self.live(roots);
        let n = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
        let mut map = vec![ExprId(u32::MAX); n];
        for i in 0..n {
            if live[i] {
                let node = *self.node(ExprId(i as u32));
                map[i] = self.rebuild(node, &map, &mut |g, x| f(x).unwrap_or_else(|| g.input(x)));
            }
        }
        roots.iter().map(|id| map[id.index()]).collect()
    }

    /// `node` re-inserted through the constructors, its operands mapped by `map` and its
    /// input (if a leaf) by `leaf`.
    pub(super) fn rebuild(
        &mut self,
        node: Node,
        map: &[ExprId],
        leaf: &mut dyn FnMut(&mut Self, Input) -> ExprId,
    ) -> ExprId {
        let m = |id: ExprId| map[id.index()];
        match node {
            Node::Const(c) => self.constant(c.value()),
            Node::Input(x) => leaf(self, x),
            Node::Neg(a) => self.neg(m(a)),
            Node::Add(a, b) => self.add(m(a), m(b)),
            Node::Sub(a, b) => self.sub(m(a), m(b)),
            Node::Mul(a, b) => self.mul(m(a), m(b)),
            Node::Div(a, b) => self.div(m(a), m(b)),
            Node::Sqrt(a) => self.sqrt(m(a)),
            Node::Sin(a) => self.sin(m(a)),
            Node::Cos(a) => self.cos(m(a)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Input;

    #[test]
    fn imported_expressions_share_common_nodes() {
        let x = Input::new(0, 0);
        let mut a = ExprGraph::new();
        let xa = a.input(x);
        let s = a.sin(xa);
        let two = a.constant(2.0);
        let f = a.mul(two, s);
        let mut b = ExprGraph::new();
        let xb = b.input(x);
        let sb = b.sin(xb);
        let before = b.len();
        let got = b.import(&a, &[f, s]);
        assert_eq!(got[1], sb);
        assert_eq!(b.len(), before + 2); // the constant 2 and the product
        assert_eq!(b.eval(&got, &|_| 0.5), a.eval(&[f, s], &|_| 0.5));
        b.verify().unwrap();
    }

    #[test]
    fn substitution_rebuilds_only_what_reads_the_input() {
        let (x, y) = (Input::new(0, 0), Input::new(1, 0));
        let mut g = ExprGraph::new();
        let xe = g.input(x);
        let ye = g.input(y);
        let s = g.sin(ye);
        let f = g.mul(xe, s);
        let c = g.cos(xe);
        let two = g.constant(2.0);
        let sub = g.substitute(&[f, s], &|i| (i == y).then_some(two));
        assert_eq!(sub[1], g.constant(2f64.sin()));
        let k = g.constant(2f64.sin());
        assert_eq!(sub[0], g.mul(k, xe));
        // Nothing reads y: the same node.
        assert_eq!(g.substitute(&[c], &|i| (i == y).then_some(two)), vec![c]);
        g.verify().unwrap();
    }
}
