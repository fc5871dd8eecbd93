//! Numeric evaluation (a test oracle, not the generated code).
//!
//! Evaluation uses the host's `f64::sin`/`f64::cos`, so it may differ from
//! folded constants (computed with `libm`) in the last bits.

use super::graph::ExprGraph;
use super::node::{ExprId, Input, Node};

impl ExprGraph {
    /// Value of one node given the values of all older nodes.
    fn eval_node(node: &Node, vals: &[f64], inputs: &dyn Fn(Input) -> f64) -> f64 {
        let v = |id: ExprId| vals[id.index()];
        match *node {
            Node::Const(c) => c.value(),
            Node::Input(x) => inputs(x),
            Node::Neg(a) => -v(a),
            Node::Add(a, b) => v(a) + v(b),
            Node::Sub(a, b) => v(a) - v(b),
            Node::Mul(a, b) => v(a) * v(b),
            Node::Div(a, b) => v(a) / v(b),
            Node::Sqrt(a) => v(a).sqrt(),
            Node::Sin(a) => v(a).sin(),
            Node::Cos(a) => v(a).cos(),
        }
    }

    /// Values of `roots`, computing only the nodes they depend on.
    /// `inputs` is called once for every live input leaf.
    pub fn eval(&self, roots: &[ExprId], inputs: &dyn Fn(Input) -> f64) -> Vec<f64> {
        let live = self.live(roots);
        let mut vals = vec![f64::NAN; self.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            if live[i] {
                vals[i] = Self::eval_node(node, &vals, inputs);
            }
        }
        roots.iter().map(|r| vals[r.index()]).collect()
    }

    /// Values of every node, indexed by id.
    pub fn eval_all(&self, inputs: &dyn Fn(Input) -> f64) -> Vec<f64> {
        let mut vals = Vec::with_capacity(self.len());
        for node in &self.nodes {
            let v = Self::eval_node(node, &vals, inputs);
            vals.push(v);
        }
        vals
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eval_matches_direct_computation() {
        let mut g = ExprGraph::new();
        let x = g.input(Input::new(0, 0));
        let y = g.input(Input::new(1, 3));
        let unused = g.input(Input::new(2, 0));
        let three = g.constant(3.0);
        // f = (3*x - sin(y)) / sqrt(x*x + cos(y)*cos(y) + 1)
        let a = g.mul(three, x);
        let sy = g.sin(y);
        let num = g.sub(a, sy);
        let xx = g.mul(x, x);
        let cy = g.cos(y);
        let cc = g.mul(cy, cy);
        let one = g.one();
        let s = g.sum(&[xx, cc, one]);
        let den = g.sqrt(s);
        let f = g.div(num, den);
        let _ = unused;
        let (xv, yv) = (0.7_f64, -1.3_f64);
        let env = |i: Input| match (i.group, i.index) {
            (0, 0) => xv,
            (1, 3) => yv,
            _ => panic!("dead input {i} evaluated"),
        };
        let expect = (3.0 * xv - yv.sin()) / (xv * xv + yv.cos() * yv.cos() + 1.0).sqrt();
        let got = g.eval(&[f, num, x], &env);
        assert_eq!(got, vec![expect, 3.0 * xv - yv.sin(), xv]);
        let all = g.eval_all(&|i| if i.group == 2 { 9.0 } else { env(i) });
        assert_eq!(all[f.index()], expect);
        assert_eq!(all[unused.index()], 9.0);
        assert_eq!(all.len(), g.len());
    }
}
