//! Structural self-check of an [`ExprGraph`].

use super::graph::ExprGraph;
use super::node::{ExprId, Node};
use super::simplify::{exact_recip, merge_scale, Fold};

impl ExprGraph {
    /// Checks every invariant of the graph (see the module docs):
    ///
    /// * operands have smaller ids than their user (topological order);
    /// * every node is its own memo entry and the memo holds nothing else
    ///   (hence there are no duplicate nodes);
    /// * constants are finite and not `-0.0`;
    /// * every node is in the normal form produced by the simplifying
    ///   constructors (no foldable constants, no `x*1`, `x+0`, `-(-x)`,
    ///   non-canonical commutative order, ...).
    ///
    /// Returns a description of the first violation found.
    pub fn verify(&self) -> Result<(), String> {
        if self.memo.len() != self.nodes.len() {
            return Err(format!(
                "memo has {} entries for {} nodes",
                self.memo.len(),
                self.nodes.len()
            ));
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let id = ExprId(i as u32);
            let fail = |msg: &str| Err(format!("{id} = {node:?}: {msg}"));
            if let Some(o) = node.operands().find(|&o| o >= id) {
                return fail(&format!("operand {o} is not older than the node"));
            }
            if self.memo.get(node) != Some(&id) {
                return fail("not its own memo entry (duplicate or stale memo)");
            }
            if let Err(msg) = self.check_normal_form(node) {
                return fail(&msg);
            }
        }
        Ok(())
    }

    /// Whether `node` (whose operands are assumed valid) is in normal form.
    fn check_normal_form(&self, node: &Node) -> Result<(), String> {
        let ensure = |ok: bool, msg: &str| if ok { Ok(()) } else { Err(msg.to_string()) };
        let k = |id: ExprId| self.as_const(id);
        let is_neg = |id: ExprId| self.neg_arg(id).is_some();
        match self.try_fold(node) {
            Fold::Value(_) => return Err("foldable constant expression".into()),
            Fold::NonFinite => {
                // Unfoldable constant operation: only the order is checked.
                return match *node {
                    Node::Add(a, b) | Node::Mul(a, b) => ensure(a <= b, "non-canonical order"),
                    _ => Ok(()),
                };
            }
            Fold::NotConst => {}
        }
        match *node {
            Node::Const(c) => {
                let v = c.value();
                ensure(v.is_finite(), "non-finite constant")?;
                ensure(c.to_bits() != (-0.0f64).to_bits(), "negative zero constant")
            }
            Node::Input(_) | Node::Sqrt(_) => Ok(()),
            Node::Neg(a) => {
                ensure(!is_neg(a), "double negation")?;
                ensure(!matches!(self.node(a), Node::Sub(..)), "negated difference")?;
                ensure(self.scaled(a).is_none(), "negated scaled term")
            }
            Node::Add(a, b) => {
                ensure(k(a) != Some(0.0) && k(b) != Some(0.0), "adds zero")?;
                ensure(!is_neg(a) && !is_neg(b), "adds a negation")?;
                ensure(a < b, "non-canonical order or x+x")?;
                ensure(self.like_terms(a, b, true).is_none(), "unmerged like terms")
            }
            Node::Sub(a, b) => {
                ensure(k(a) != Some(0.0) && k(b) != Some(0.0), "subtracts zero")?;
                ensure(!is_neg(a) && !is_neg(b), "subtracts a negation")?;
                ensure(a != b, "x-x")?;
                ensure(
                    self.like_terms(a, b, false).is_none(),
                    "unmerged like terms",
                )
            }
            Node::Mul(a, b) => {
                ensure(k(b).is_none(), "constant is not the first factor")?;
                ensure(!is_neg(a) && !is_neg(b), "multiplies a negation")?;
                if let Some(c) = k(a) {
                    ensure(c != 0.0 && c != 1.0 && c != -1.0, "trivial constant factor")?;
                    let mergeable = self
                        .scaled(b)
                        .is_some_and(|(d, _)| merge_scale(c, d).is_some());
                    ensure(!mergeable, "unmerged constant factors")
                } else {
                    ensure(a <= b, "non-canonical order")
                }
            }
            Node::Div(a, b) => {
                if let Some(c) = k(b) {
                    ensure(c != 1.0 && c != -1.0, "division by +-1")?;
                    ensure(exact_recip(c).is_none(), "division by a power of two")?;
                }
                ensure(k(a) != Some(0.0), "zero numerator")?;
                ensure(a != b, "x/x")?;
                ensure(!is_neg(a) && !is_neg(b), "divides a negation")
            }
            Node::Sin(a) | Node::Cos(a) => ensure(!is_neg(a), "trigonometric of a negation"),
        }
    }
}
