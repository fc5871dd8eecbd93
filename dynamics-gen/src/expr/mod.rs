//! Hash-consed scalar expression graph with simplification at insertion.
//!
//! The graph knows nothing about robots: it holds constants, opaque input
//! leaves ([`Input`]) and the operations `neg + - * / sqrt sin cos`.
//!
//! # Invariants
//!
//! An [`ExprGraph`] stores its [`Node`]s in a flat vector indexed by
//! [`ExprId`], and maintains (checked by [`ExprGraph::verify`]):
//!
//! * **Topological order**: every operand id is smaller than the id of the
//!   node using it. Passes (liveness, evaluation, differentiation) are
//!   therefore single forward or backward sweeps, never recursive.
//! * **Hash-consing**: a node is stored at most once; the constructors
//!   return the existing id for an identical node, so common
//!   sub-expressions are shared by construction. The memo map is only used
//!   for lookups, so no result depends on hash map iteration order.
//! * **Finite constants**: [`Const`] holds a finite `f64` by bit pattern,
//!   with `-0.0` normalised to `+0.0`.
//! * **Normal form**: nodes are only created by the simplifying
//!   constructors ([`ExprGraph::add`], [`ExprGraph::mul`], ...). They fold
//!   constants (IEEE `+ - * /`, `f64::sqrt`, `libm::sin`/`libm::cos`, only
//!   when the result is finite), and apply cheap local rules: `x*0 -> 0`,
//!   `x*1 -> x`, `x*(-1) -> -x`, `x+0 -> x`, `x-0 -> x`, `0-x -> -x`,
//!   `x-x -> 0`, `x+x -> 2*x`, `-(-x) -> x`, `-(a-b) -> b-a`,
//!   `c*(d*x) -> (c*d)*x` (but `(c*x)*y` stays: hoisting the constant would
//!   cost a product wherever `c*x` is shared), negations pulled out of products, quotients
//!   and `sin` (and dropped by `cos`), `a+(-b) -> a-b`, `(-a)+b -> b-a`,
//!   `a-(-b) -> a+b`, like terms `c*x + d*x -> (c+d)*x` and
//!   `c*x - d*x -> (c-d)*x` (with `x = 1*x`, `-x = (-1)*x`; an exact 0
//!   when the factors cancel), `x/1 -> x`, `x/2^k -> 2^-k*x`, `0/x -> 0`,
//!   `x/x -> 1`. `Add` and `Mul` operands are in ascending id order, with a
//!   constant factor always first in `Mul` (`c*x`). Products are never
//!   distributed over sums (that would blow up the expression size).
//!   Consequently rebuilding any stored node through its constructor
//!   returns the node itself.
//!
//! # Identically zero nodes
//!
//! A cancellation spread over several nodes is invisible to the local
//! rules; [`ExprGraph::prune_zeros`] (in [`zeros`]) finds such nodes by
//! evaluating the graph at random inputs against a rounding bound, and
//! rebuilds the graph with them replaced by the constant 0.
//!
//! # Numerical assumptions
//!
//! All inputs are assumed finite, and divisors non-zero wherever the
//! expression is evaluated; under that assumption the rewrites preserve
//! values up to ordinary floating point rounding (details in the docs of
//! the constructors and in `simplify.rs`).

mod constant;
mod diff;
mod dot;
pub mod equivalent;
mod eval;
mod graph;
mod import;
mod node;
pub mod reassociate;
pub mod sexp;
pub mod shape;
mod simplify;
mod stats;
mod verify;
pub mod zeros;

#[cfg(test)]
mod random_tests;
#[cfg(test)]
mod simplify_tests;

pub use constant::Const;
pub use graph::ExprGraph;
pub use node::{ExprId, Input, Node};
pub use stats::OpCounts;
