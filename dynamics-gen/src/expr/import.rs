//! Copying expressions from one graph into another.

use super::graph::ExprGraph;
use super::node::{ExprId, Node};

impl ExprGraph {
    /// Copies the live part of `other` under `roots` into this graph and returns the roots'
    /// ids here (same order). Every node is re-inserted through the simplifying constructors,
    /// so nodes the two graphs share (inputs, `sin q_i`, common subexpressions) are merged by
    /// hash-consing: expressions of two expansions can be combined in one function.
    pub fn import(&mut self, other: &ExprGraph, roots: &[ExprId]) -> Vec<ExprId> {
        let live = other.live(roots);
        let mut map = vec![ExprId(u32::MAX); other.len()];
        for (i, node) in other.nodes().iter().enumerate() {
            if !live[i] {
                continue;
            }
            let m = |id: ExprId| map[id.index()];
            map[i] = match *node {
                Node::Const(c) => self.constant(c.value()),
                Node::Input(x) => self.input(x),
                Node::Neg(a) => self.neg(m(a)),
                Node::Add(a, b) => self.add(m(a), m(b)),
                Node::Sub(a, b) => self.sub(m(a), m(b)),
                Node::Mul(a, b) => self.mul(m(a), m(b)),
                Node::Div(a, b) => self.div(m(a), m(b)),
                Node::Sqrt(a) => self.sqrt(m(a)),
                Node::Sin(a) => self.sin(m(a)),
                Node::Cos(a) => self.cos(m(a)),
            };
        }
        roots.iter().map(|id| map[id.index()]).collect()
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
}
