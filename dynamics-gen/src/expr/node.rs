//! Node identifiers, input leaves and the [`Node`] enum itself.

use std::fmt;

use super::constant::Const;

/// Index of a node in an [`ExprGraph`](super::ExprGraph).
///
/// Ids are dense and allocated in topological order: the operands of a node
/// always have strictly smaller ids than the node itself. Ids are only
/// meaningful for the graph that produced them.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct ExprId(pub u32);

impl ExprId {
    /// The id as a `usize`, for indexing per-node side tables.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for ExprId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "e{}", self.0)
    }
}

/// An opaque, named leaf of the graph (a free variable).
///
/// The graph attaches no meaning to `group` and `index`; the user decides,
/// e.g. group 0 = joint positions, group 1 = joint velocities.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct Input {
    /// Which family of variables this leaf belongs to.
    pub group: u8,
    /// Index within the group.
    pub index: u16,
}

impl Input {
    /// Creates an input leaf descriptor.
    pub const fn new(group: u8, index: u16) -> Self {
        Self { group, index }
    }
}

impl fmt::Display for Input {
    /// Default rendering `in{group}_{index}`, e.g. `in0_3`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "in{}_{}", self.group, self.index)
    }
}

/// One operation of the expression graph. Operands refer to earlier nodes.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    /// A finite floating point constant.
    Const(Const),
    /// A free variable.
    Input(Input),
    /// Negation `-a`.
    Neg(ExprId),
    /// Sum `a + b` (operands in canonical order, see the module docs).
    Add(ExprId, ExprId),
    /// Difference `a - b`.
    Sub(ExprId, ExprId),
    /// Product `a * b` (constant first, otherwise canonical order).
    Mul(ExprId, ExprId),
    /// Quotient `a / b`.
    Div(ExprId, ExprId),
    /// Square root.
    Sqrt(ExprId),
    /// Sine (radians).
    Sin(ExprId),
    /// Cosine (radians).
    Cos(ExprId),
}

impl Node {
    /// The operands of this node, in order (empty for leaves).
    pub fn operands(&self) -> impl Iterator<Item = ExprId> {
        let z = ExprId(0);
        let (ops, n) = match *self {
            Node::Const(_) | Node::Input(_) => ([z, z], 0),
            Node::Neg(a) | Node::Sqrt(a) | Node::Sin(a) | Node::Cos(a) => ([a, z], 1),
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => ([a, b], 2),
        };
        ops.into_iter().take(n)
    }

    /// The constant value if this is a [`Node::Const`].
    pub fn as_const(&self) -> Option<f64> {
        match self {
            Node::Const(c) => Some(c.value()),
            _ => None,
        }
    }

    /// Short operator name used by the text and graphviz dumps
    /// (`+`, `-`, `*`, `/`, `neg`, `sqrt`, `sin`, `cos`, `const`, `input`).
    pub fn op_name(&self) -> &'static str {
        match self {
            Node::Const(_) => "const",
            Node::Input(_) => "input",
            Node::Neg(_) => "neg",
            Node::Add(..) => "+",
            Node::Sub(..) => "-",
            Node::Mul(..) => "*",
            Node::Div(..) => "/",
            Node::Sqrt(_) => "sqrt",
            Node::Sin(_) => "sin",
            Node::Cos(_) => "cos",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_and_operands() {
        assert_eq!(ExprId(17).to_string(), "e17");
        assert_eq!(Input::new(1, 4).to_string(), "in1_4");
        let ops: Vec<_> = Node::Sub(ExprId(3), ExprId(1)).operands().collect();
        assert_eq!(ops, vec![ExprId(3), ExprId(1)]);
        let ops: Vec<_> = Node::Sin(ExprId(2)).operands().collect();
        assert_eq!(ops, vec![ExprId(2)]);
        assert_eq!(Node::Input(Input::new(0, 0)).operands().count(), 0);
        assert!(Input::new(0, 9) < Input::new(1, 0));
    }
}
