//! The [`ExprGraph`] arena: storage, hash-consing, leaves and accessors.
//!
//! The simplifying operator constructors (`neg`, `add`, `mul`, ...) live in
//! `simplify.rs`; this file holds everything that does not
//! rewrite.

use rustc_hash::FxHashMap;
use std::collections::hash_map::Entry;

use super::constant::Const;
use super::node::{ExprId, Input, Node};

/// A hash-consed DAG of scalar expressions in topological order.
///
/// See the [module documentation](super) for the invariants.
#[derive(Clone, Debug, Default)]
pub struct ExprGraph {
    /// All nodes; operands always have smaller ids than their user.
    pub(super) nodes: Vec<Node>,
    /// Node -> id, used for lookups only (never iterated, so its hasher cannot change the
    /// output). FxHash: hashing nodes is most of the expansion's time, and the keys are the
    /// generator's own nodes, not hostile input that could aim at collisions.
    pub(super) memo: FxHashMap<Node, ExprId>,
}

impl ExprGraph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Returns the id of `node`, appending it if it is not yet present.
    ///
    /// No rewriting happens here: callers (the constructors) must only pass
    /// nodes that are already in simplified normal form.
    pub(super) fn intern(&mut self, node: Node) -> ExprId {
        match self.memo.entry(node) {
            Entry::Occupied(e) => *e.get(),
            Entry::Vacant(e) => {
                let id =
                    ExprId(u32::try_from(self.nodes.len()).expect("expression graph overflow"));
                debug_assert!(node.operands().all(|o| o < id), "operand out of range");
                self.nodes.push(node);
                e.insert(id);
                id
            }
        }
    }

    /// The constant `v`, or `None` if `v` is NaN or infinite.
    /// `-0.0` is stored as `+0.0`.
    pub fn try_constant(&mut self, v: f64) -> Option<ExprId> {
        Const::new(v).map(|c| self.intern(Node::Const(c)))
    }

    /// The constant `v`.
    ///
    /// # Panics
    /// If `v` is NaN or infinite (the graph only holds finite constants).
    pub fn constant(&mut self, v: f64) -> ExprId {
        self.try_constant(v)
            .unwrap_or_else(|| panic!("non-finite constant {v} in expression graph"))
    }

    /// The constant `0`.
    pub fn zero(&mut self) -> ExprId {
        self.constant(0.0)
    }

    /// The constant `1`.
    pub fn one(&mut self) -> ExprId {
        self.constant(1.0)
    }

    /// The leaf for input `x`.
    pub fn input(&mut self, x: Input) -> ExprId {
        self.intern(Node::Input(x))
    }

    /// The id of the leaf `x` if it is already present, without adding it.
    pub fn find_input(&self, x: Input) -> Option<ExprId> {
        self.memo.get(&Node::Input(x)).copied()
    }

    /// The node with id `id`.
    ///
    /// # Panics
    /// If `id` does not belong to this graph.
    #[inline]
    pub fn node(&self, id: ExprId) -> &Node {
        &self.nodes[id.index()]
    }

    /// All nodes in id (= topological) order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph has no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The value of `id` if it is a constant node.
    #[inline]
    pub fn as_const(&self, id: ExprId) -> Option<f64> {
        self.node(id).as_const()
    }

    /// Whether `id` is the constant zero.
    #[inline]
    pub fn is_zero(&self, id: ExprId) -> bool {
        self.as_const(id) == Some(0.0)
    }

    /// Whether `id` is the constant one.
    #[inline]
    pub fn is_one(&self, id: ExprId) -> bool {
        self.as_const(id) == Some(1.0)
    }

    /// The input leaves present in the graph, in id order.
    pub fn inputs(&self) -> impl Iterator<Item = Input> + '_ {
        self.nodes.iter().filter_map(|n| match n {
            Node::Input(x) => Some(*x),
            _ => None,
        })
    }

    /// `terms[0] + terms[1] + ...`, summed left to right; `0` if empty.
    pub fn sum(&mut self, terms: &[ExprId]) -> ExprId {
        match terms.split_first() {
            None => self.zero(),
            Some((&first, rest)) => rest.iter().fold(first, |acc, &t| self.add(acc, t)),
        }
    }

    /// `a[0]*b[0] + a[1]*b[1] + ...`; `0` if empty.
    ///
    /// # Panics
    /// If the slices have different lengths.
    pub fn dot(&mut self, a: &[ExprId], b: &[ExprId]) -> ExprId {
        assert_eq!(a.len(), b.len(), "dot: length mismatch");
        let mut acc: Option<ExprId> = None;
        for (&x, &y) in a.iter().zip(b) {
            acc = Some(match acc {
                None => self.mul(x, y),
                Some(s) => self.mul_add(x, y, s),
            });
        }
        acc.unwrap_or_else(|| self.zero())
    }

    /// `a*b + c`, built from an ordinary product and sum (no fused node).
    pub fn mul_add(&mut self, a: ExprId, b: ExprId, c: ExprId) -> ExprId {
        let p = self.mul(a, b);
        self.add(p, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_consing_of_leaves() {
        let mut g = ExprGraph::new();
        assert!(g.is_empty());
        let q0 = g.input(Input::new(0, 0));
        let two = g.constant(2.0);
        assert_eq!(g.input(Input::new(0, 0)), q0);
        assert_eq!(g.constant(2.0), two);
        assert_eq!(g.constant(-0.0), g.zero());
        assert_eq!(g.len(), 3);
        assert_eq!(g.try_constant(f64::NAN), None);
        assert_eq!(g.as_const(two), Some(2.0));
        let z = g.zero();
        assert!(g.is_zero(z));
        assert!(!g.is_zero(q0));
        assert_eq!(g.find_input(Input::new(0, 0)), Some(q0));
        assert_eq!(g.find_input(Input::new(0, 1)), None);
        g.input(Input::new(1, 0));
        assert_eq!(
            g.inputs().collect::<Vec<_>>(),
            vec![Input::new(0, 0), Input::new(1, 0)]
        );
    }

    #[test]
    #[should_panic(expected = "non-finite")]
    fn constant_panics_on_inf() {
        ExprGraph::new().constant(f64::INFINITY);
    }

    #[test]
    fn sum_dot_mul_add() {
        let mut g = ExprGraph::new();
        let x: Vec<_> = (0..3).map(|i| g.input(Input::new(0, i))).collect();
        let y: Vec<_> = (0..3).map(|i| g.input(Input::new(1, i))).collect();
        assert_eq!(g.sum(&[]), g.zero());
        assert_eq!(g.sum(&[x[1]]), x[1]);
        let s = g.sum(&x);
        let s01 = g.add(x[0], x[1]);
        assert_eq!(s, g.add(s01, x[2]));
        let d = g.dot(&x, &y);
        let p0 = g.mul(x[0], y[0]);
        let p1 = g.mul_add(x[1], y[1], p0);
        assert_eq!(d, g.mul_add(x[2], y[2], p1));
        assert_eq!(g.dot(&[], &[]), g.zero());
    }
}
