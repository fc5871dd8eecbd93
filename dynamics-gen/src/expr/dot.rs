//! Graphviz dump for debugging.

use std::fmt::Write as _;

use super::graph::ExprGraph;
use super::node::{ExprId, Node};

impl ExprGraph {
    /// A Graphviz `digraph` of the nodes live from `roots`. Nodes are
    /// labelled with their operator (or value / input name) and id; edges
    /// point from a node to its operands (labelled `0`/`1` for the
    /// non-commutative `-` and `/`); roots are drawn as double octagons.
    pub fn to_dot(&self, roots: &[ExprId]) -> String {
        let live = self.live(roots);
        let mut out = String::from("digraph expr {\n  node [shape=box, fontname=\"monospace\"];\n");
        for (i, node) in self.nodes.iter().enumerate().filter(|&(i, _)| live[i]) {
            let id = ExprId(i as u32);
            let label = match node {
                Node::Const(c) => c.to_string(),
                Node::Input(x) => x.to_string(),
                _ => node.op_name().to_string(),
            };
            let shape = if roots.contains(&id) {
                ", shape=doubleoctagon"
            } else if matches!(node, Node::Const(_) | Node::Input(_)) {
                ", shape=ellipse"
            } else {
                ""
            };
            let _ = writeln!(out, "  n{i} [label=\"{label}\\n{id}\"{shape}];");
            let ordered = matches!(node, Node::Sub(..) | Node::Div(..));
            for (k, o) in node.operands().enumerate() {
                let _ = if ordered {
                    writeln!(out, "  n{i} -> n{} [label=\"{k}\"];", o.0)
                } else {
                    writeln!(out, "  n{i} -> n{};", o.0)
                };
            }
        }
        out.push_str("}\n");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::node::Input;
    use super::*;

    #[test]
    fn dot_lists_live_nodes_and_edges() {
        let mut g = ExprGraph::new();
        let x = g.input(Input::new(0, 0));
        let y = g.input(Input::new(0, 1));
        let _dead = g.sin(y);
        let d = g.sub(x, y);
        let dot = g.to_dot(&[d]);
        assert!(dot.starts_with("digraph expr {"));
        assert!(dot.contains("n0 [label=\"in0_0\\ne0\", shape=ellipse];"));
        assert!(dot.contains("n3 [label=\"-\\ne3\", shape=doubleoctagon];"));
        assert!(dot.contains("n3 -> n0 [label=\"0\"];"));
        assert!(dot.contains("n3 -> n1 [label=\"1\"];"));
        assert!(!dot.contains("sin"));
        assert!(dot.trim_end().ends_with('}'));
    }
}
