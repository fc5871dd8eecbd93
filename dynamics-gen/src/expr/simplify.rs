//! The simplifying operator constructors of [`ExprGraph`].
//!
//! Every constructor looks only at its operands and their top-level nodes
//! (O(1) per rule, bounded recursion), rewrites to a normal form and then
//! hash-conses the result. The rules are listed in the `expr` module
//! documentation; [`ExprGraph::verify`] checks that every
//! stored node is in the normal form these constructors produce.
//!
//! Numerical contract: constant folding uses plain IEEE `f64` arithmetic for
//! `+ - * /`, `f64::sqrt` (correctly rounded) and `libm::sin`/`libm::cos`
//! (so folded values never depend on the host's libm). A fold is only done
//! if the result is finite; otherwise the node is kept unfolded. Rewrites
//! such as `x*0 -> 0`, `0/x -> 0` and `x/x -> 1` assume that every input is
//! finite and that divisors are non-zero where they are evaluated.
//! Sign rewrites (`-(a-b) -> b-a`, `(-a)*b -> -(a*b)`, ...) are exact;
//! re-association of constant factors (`c*(d*x) -> (c*d)*x`) and merging
//! of like terms (`c*x + d*x -> (c+d)*x`, `c*x - d*x -> (c-d)*x`) may
//! change the result by ordinary rounding, never more. A like-term merge
//! whose factor is exactly zero (`d == -c` in a sum, `d == c` in a
//! difference) gives the exact constant 0, as `x - x` does.

use super::constant::Const;
use super::graph::ExprGraph;
use super::node::{ExprId, Node};

/// Outcome of trying to constant-fold a node.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(super) enum Fold {
    /// Some operand is not a constant (or the node is a leaf).
    NotConst,
    /// All operands are constants and the result is finite.
    Value(Const),
    /// All operands are constants but the result is NaN or infinite.
    NonFinite,
}

/// `c*d` if it may replace the factors `c`, `d` (finite and non-zero, so
/// that neither overflow nor underflow to zero is introduced).
pub(super) fn merge_scale(c: f64, d: f64) -> Option<f64> {
    let p = c * d;
    (p.is_finite() && p != 0.0).then_some(p)
}

/// `1/c` if dividing by `c` equals multiplying by `1/c` exactly, i.e. both
/// `c` and `1/c` are normal powers of two.
pub(super) fn exact_recip(c: f64) -> Option<f64> {
    const MANTISSA: u64 = (1 << 52) - 1;
    let r = 1.0 / c;
    let pow2 = |v: f64| v.is_normal() && v.to_bits() & MANTISSA == 0;
    (pow2(c) && pow2(r)).then_some(r)
}

impl ExprGraph {
    /// Constant-folds `node` if all its operands are constants.
    pub(super) fn try_fold(&self, node: &Node) -> Fold {
        let c = |id: ExprId| self.as_const(id);
        let v = match *node {
            Node::Const(_) | Node::Input(_) => None,
            Node::Neg(a) => c(a).map(|x| -x),
            Node::Add(a, b) => c(a).zip(c(b)).map(|(x, y)| x + y),
            Node::Sub(a, b) => c(a).zip(c(b)).map(|(x, y)| x - y),
            Node::Mul(a, b) => c(a).zip(c(b)).map(|(x, y)| x * y),
            Node::Div(a, b) => c(a).zip(c(b)).map(|(x, y)| x / y),
            Node::Sqrt(a) => c(a).map(f64::sqrt),
            Node::Sin(a) => c(a).map(libm::sin),
            Node::Cos(a) => c(a).map(libm::cos),
        };
        match v {
            None => Fold::NotConst,
            Some(v) => Const::new(v).map_or(Fold::NonFinite, Fold::Value),
        }
    }

    /// Folds `node` if possible, else returns `None`.
    fn fold_node(&mut self, node: Node) -> Option<ExprId> {
        match self.try_fold(&node) {
            Fold::Value(k) => Some(self.intern(Node::Const(k))),
            _ => None,
        }
    }

    /// `Some(x)` if `id` is `Neg(x)`.
    pub(super) fn neg_arg(&self, id: ExprId) -> Option<ExprId> {
        match *self.node(id) {
            Node::Neg(x) => Some(x),
            _ => None,
        }
    }

    /// `Some((c, x))` if `id` is `Mul(c, x)` with constant `c` and
    /// non-constant `x` (a "scaled" term).
    pub(super) fn scaled(&self, id: ExprId) -> Option<(f64, ExprId)> {
        match *self.node(id) {
            Node::Mul(c, x) if self.as_const(x).is_none() => self.as_const(c).map(|c| (c, x)),
            _ => None,
        }
    }

    /// `Some((c, x))` if `id` is a multiple `c*x` of a non-constant `x`:
    /// `Mul(c, x)` gives `(c, x)`, `Neg(x)` gives `(-1, x)` and any other
    /// non-constant node `x` gives `(1, x)` (`x = 1*x`). `None` for constants.
    pub(super) fn term(&self, id: ExprId) -> Option<(f64, ExprId)> {
        if let Some(t) = self.scaled(id) {
            return Some(t);
        }
        if let Some(x) = self.neg_arg(id) {
            return Some((-1.0, x));
        }
        self.as_const(id).is_none().then_some((1.0, id))
    }

    /// `Some((c ± d, x))` if `a = c*x` and `b = d*x` are multiples of the same
    /// non-constant `x` (see [`Self::term`]) and the merged factor `c ± d`
    /// (`+` if `add`) is finite. The merged factor is rounded once (IEEE),
    /// so `c*x + d*x -> (c+d)*x` may change the value by ordinary rounding;
    /// `c + d == 0` (e.g. `d == -c`) is exact and gives the constant 0.
    pub(super) fn like_terms(&self, a: ExprId, b: ExprId, add: bool) -> Option<(f64, ExprId)> {
        let (c, x) = self.term(a)?;
        let (d, y) = self.term(b)?;
        let s = if add { c + d } else { c - d };
        (x == y && s.is_finite()).then_some((s, x))
    }

    fn both_const(&self, a: ExprId, b: ExprId) -> bool {
        self.as_const(a).is_some() && self.as_const(b).is_some()
    }

    /// `-a`. Rules: fold constants, `-(-x) -> x`, `-(x-y) -> y-x`,
    /// `-(c*x) -> (-c)*x`.
    pub fn neg(&mut self, a: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Neg(a)) {
            return k;
        }
        if let Some(x) = self.neg_arg(a) {
            return x;
        }
        if let Node::Sub(x, y) = *self.node(a) {
            return self.sub(y, x);
        }
        if let Some((c, x)) = self.scaled(a) {
            let k = self.constant(-c);
            return self.mul(k, x);
        }
        self.intern(Node::Neg(a))
    }

    /// `a + b`. Rules: fold constants, `x+0 -> x`, `0+x -> x`,
    /// `(-x)+(-y) -> -(x+y)`, `a+(-y) -> a-y`, `(-x)+b -> b-x`,
    /// `x+x -> 2*x`, like terms `c*x + d*x -> (c+d)*x` (also `x + d*x`;
    /// `0` if `c+d == 0`); operands stored in ascending id order.
    pub fn add(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Add(a, b)) {
            return k;
        }
        if !self.both_const(a, b) {
            if self.is_zero(a) {
                return b;
            }
            if self.is_zero(b) {
                return a;
            }
            match (self.neg_arg(a), self.neg_arg(b)) {
                (Some(x), Some(y)) => {
                    let s = self.add(x, y);
                    return self.neg(s);
                }
                (None, Some(y)) => return self.sub(a, y),
                (Some(x), None) => return self.sub(b, x),
                (None, None) => {}
            }
            if a == b {
                let two = self.constant(2.0);
                return self.mul(two, a);
            }
            if let Some((s, x)) = self.like_terms(a, b, true) {
                let k = self.constant(s);
                return self.mul(k, x);
            }
        }
        self.intern(Node::Add(a.min(b), a.max(b)))
    }

    /// `a - b`. Rules: fold constants, `x-0 -> x`, `0-x -> -x`, `x-x -> 0`,
    /// `a-(-y) -> a+y`, `(-x)-b -> -(x+b)`, like terms
    /// `c*x - d*x -> (c-d)*x` (also `x - d*x`, `c*x - x`; `0` if `c == d`,
    /// e.g. for two distinct nodes `c*x`).
    pub fn sub(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Sub(a, b)) {
            return k;
        }
        if !self.both_const(a, b) {
            if self.is_zero(b) {
                return a;
            }
            if self.is_zero(a) {
                return self.neg(b);
            }
            if a == b {
                return self.zero();
            }
            if let Some(y) = self.neg_arg(b) {
                return self.add(a, y);
            }
            if let Some(x) = self.neg_arg(a) {
                let s = self.add(x, b);
                return self.neg(s);
            }
            if let Some((s, x)) = self.like_terms(a, b, false) {
                let k = self.constant(s);
                return self.mul(k, x);
            }
        }
        self.intern(Node::Sub(a, b))
    }

    /// `a * b`. Rules: fold constants; constant operand first;
    /// `0*x -> 0`, `1*x -> x`, `(-1)*x -> -x`, `c*(-y) -> (-c)*y`,
    /// `c*(d*y) -> (c*d)*y`; for non-constant operands `(-x)*(-y) -> x*y`,
    /// `(-x)*b -> -(x*b)`, `a*(-y) -> -(a*y)`, and operands are stored in
    /// ascending id order (a constant factor of a non-constant operand stays there).
    pub fn mul(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Mul(a, b)) {
            return k;
        }
        if self.both_const(a, b) {
            return self.intern(Node::Mul(a.min(b), a.max(b)));
        }
        // Constant (if any) first.
        let (a, b) = if self.as_const(b).is_some() {
            (b, a)
        } else {
            (a, b)
        };
        if let Some(c) = self.as_const(a) {
            if c == 0.0 {
                return self.zero();
            }
            if c == 1.0 {
                return b;
            }
            if c == -1.0 {
                return self.neg(b);
            }
            if let Some(y) = self.neg_arg(b) {
                let k = self.constant(-c);
                return self.mul(k, y);
            }
            if let Some((d, y)) = self.scaled(b) {
                if let Some(p) = merge_scale(c, d) {
                    let k = self.constant(p);
                    return self.mul(k, y);
                }
            }
            return self.intern(Node::Mul(a, b));
        }
        match (self.neg_arg(a), self.neg_arg(b)) {
            (Some(x), Some(y)) => return self.mul(x, y),
            (Some(x), None) => {
                let p = self.mul(x, b);
                return self.neg(p);
            }
            (None, Some(y)) => {
                let p = self.mul(a, y);
                return self.neg(p);
            }
            (None, None) => {}
        }
        // A constant factor of an operand stays where it is: `(c*x)*b` is not rewritten to
        // `c*(x*b)`. Hoisting it made a second product wherever `c*x` had other uses (and
        // put the constant after the late operand); without it every function of the arms
        // has fewer multiplications (rand7's forward dynamics derivatives 4660 -> 4410).
        self.intern(Node::Mul(a.min(b), a.max(b)))
    }

    /// `a / b`. Rules: fold constants, `x/1 -> x`, `x/(-1) -> -x`,
    /// `x/c -> (1/c)*x` when `c` is a power of two (exact), `0/x -> 0`,
    /// `x/x -> 1`, `(-x)/(-y) -> x/y`, `(-x)/b -> -(x/b)`,
    /// `a/(-y) -> -(a/y)`. The last three assume nothing; `0/x` and `x/x`
    /// assume `x != 0` wherever the result is evaluated.
    pub fn div(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Div(a, b)) {
            return k;
        }
        if !self.both_const(a, b) {
            if let Some(c) = self.as_const(b) {
                if c == 1.0 {
                    return a;
                }
                if c == -1.0 {
                    return self.neg(a);
                }
                if let Some(r) = exact_recip(c) {
                    let k = self.constant(r);
                    return self.mul(k, a);
                }
            }
            if self.is_zero(a) {
                return self.zero();
            }
            if a == b {
                return self.one();
            }
            match (self.neg_arg(a), self.neg_arg(b)) {
                (Some(x), Some(y)) => return self.div(x, y),
                (Some(x), None) => {
                    let q = self.div(x, b);
                    return self.neg(q);
                }
                (None, Some(y)) => {
                    let q = self.div(a, y);
                    return self.neg(q);
                }
                (None, None) => {}
            }
        }
        self.intern(Node::Div(a, b))
    }

    /// `sqrt(a)`. Folds non-negative constants (`f64::sqrt`, exact IEEE).
    pub fn sqrt(&mut self, a: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Sqrt(a)) {
            return k;
        }
        self.intern(Node::Sqrt(a))
    }

    /// `sin(a)`. Folds constants with `libm::sin`; `sin(-x) -> -sin(x)`.
    pub fn sin(&mut self, a: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Sin(a)) {
            return k;
        }
        if let Some(x) = self.neg_arg(a) {
            let s = self.sin(x);
            return self.neg(s);
        }
        self.intern(Node::Sin(a))
    }

    /// `cos(a)`. Folds constants with `libm::cos`; `cos(-x) -> cos(x)`.
    pub fn cos(&mut self, a: ExprId) -> ExprId {
        if let Some(k) = self.fold_node(Node::Cos(a)) {
            return k;
        }
        if let Some(x) = self.neg_arg(a) {
            return self.cos(x);
        }
        self.intern(Node::Cos(a))
    }
}
