//! Shapes of nodes: a hash of an expression's tree of operations that leaves out its
//! constants' values, its inputs' indices and its signs, and takes sums and products in
//! either order. The torques of a quadruped's four hips have one shape: each leg's chain of
//! the same operations on its own constants and its own joints' inputs. The emitter computes
//! nodes of one shape together, in the lanes of vector operations (`emit::pack`).

use super::{ExprGraph, ExprId, Node};

/// The shapes of the nodes of `g` live in `live` (0 elsewhere), in id order.
pub fn shapes(g: &ExprGraph, live: &[bool]) -> Vec<u64> {
    fn mix(a: u64, b: u64) -> u64 {
        (a ^ b.rotate_left(29))
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .rotate_left(31)
            ^ b
    }
    let either = |tag: u64, a: u64, b: u64| mix(tag, mix(a.min(b), a.max(b)));
    let mut h = vec![0u64; g.len()];
    for (k, node) in g.nodes().iter().enumerate() {
        if !live[k] {
            continue;
        }
        let s = |id: ExprId| h[id.index()];
        h[k] = match *node {
            Node::Const(_) => 1,
            Node::Input(x) => mix(2, u64::from(x.group)),
            Node::Neg(a) => s(a),
            Node::Add(a, b) | Node::Sub(a, b) => either(3, s(a), s(b)),
            Node::Mul(a, b) => either(4, s(a), s(b)),
            Node::Div(a, b) => mix(5, mix(s(a), s(b))),
            Node::Sqrt(a) => mix(6, s(a)),
            Node::Sin(a) => mix(7, s(a)),
            Node::Cos(a) => mix(8, s(a)),
        };
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Input;

    #[test]
    fn alike_trees_have_one_shape() {
        let mut g = ExprGraph::new();
        // Two legs: s_i x_i·c + y_i, each with its own inputs and constants; a sign flipped.
        let leg = |g: &mut ExprGraph, k: u16, c: f64, flip: bool| {
            let (x, y) = (g.input(Input::new(0, k)), g.input(Input::new(1, k)));
            let s = g.sin(x);
            let cx = g.constant(c);
            let p = g.mul(s, cx);
            let p = g.mul(p, x);
            if flip {
                g.sub(y, p)
            } else {
                g.add(p, y)
            }
        };
        let a = leg(&mut g, 0, 0.3, false);
        let b = leg(&mut g, 1, -1.7, true);
        let x0 = g.input(Input::new(0, 0));
        let y0 = g.input(Input::new(1, 0));
        let other = g.add(x0, y0);
        let live = vec![true; g.len()];
        let h = shapes(&g, &live);
        assert_eq!(h[a.index()], h[b.index()]);
        assert_ne!(h[a.index()], h[other.index()]);
    }
}
