//! One test per simplification rule, plus hash-consing.

use super::{ExprGraph, ExprId, Input, Node};

struct T {
    g: ExprGraph,
    x: ExprId,
    y: ExprId,
}

fn setup() -> T {
    let mut g = ExprGraph::new();
    let x = g.input(Input::new(0, 0));
    let y = g.input(Input::new(0, 1));
    T { g, x, y }
}

impl T {
    fn c(&mut self, v: f64) -> ExprId {
        self.g.constant(v)
    }
    fn s(&self, id: ExprId) -> String {
        self.g.to_sexp(id)
    }
}

#[test]
fn constant_folding() {
    let mut t = setup();
    let (a, b) = (t.c(1.5), t.c(-4.0));
    let g = &mut t.g;
    let r = [g.add(a, b), g.sub(a, b), g.mul(a, b), g.div(a, b), g.neg(a)];
    let v: Vec<_> = r.iter().map(|&r| g.as_const(r)).collect();
    assert_eq!(
        v,
        [Some(-2.5), Some(5.5), Some(-6.0), Some(-0.375), Some(-1.5)]
    );
    let two = g.constant(2.0);
    let sq = g.sqrt(two);
    assert_eq!(g.as_const(sq), Some(2f64.sqrt()));
    let (s, c) = (g.sin(a), g.cos(a));
    assert_eq!(g.as_const(s), Some(libm::sin(1.5)));
    assert_eq!(g.as_const(c), Some(libm::cos(1.5)));
    // -0.0 results are normalised: 0 * -4 = -0.0 -> 0
    let z = g.zero();
    assert_eq!(g.mul(z, b), z);
    let mz = g.neg(z);
    assert_eq!(mz, z);
    g.verify().unwrap();
}

#[test]
fn non_finite_folds_are_kept_unfolded() {
    let mut t = setup();
    let (big, z, m1, one) = (t.c(1e300), t.c(0.0), t.c(-1.0), t.c(1.0));
    let g = &mut t.g;
    let p = g.mul(big, big);
    assert_eq!(*g.node(p), Node::Mul(big, big));
    let d = g.div(one, z);
    assert_eq!(*g.node(d), Node::Div(one, z));
    let s = g.sqrt(m1);
    assert_eq!(*g.node(s), Node::Sqrt(m1));
    let x = t.x;
    let q = g.div(x, z);
    assert_eq!(*g.node(q), Node::Div(x, z));
    assert_eq!(g.eval(&[p, d, q], &|_| 1.0), vec![f64::INFINITY; 3]);
    // Constant factors are not merged if their product overflows or
    // underflows to zero.
    let tiny = g.constant(1e-200);
    let tx = g.mul(tiny, x);
    let ttx = g.mul(tiny, tx);
    assert_eq!(*g.node(ttx), Node::Mul(tiny, tx));
    let bx = g.mul(big, x);
    let bbx = g.mul(bx, big);
    assert_eq!(*g.node(bbx), Node::Mul(big, bx));
    g.verify().unwrap();
}

#[test]
fn multiplication_rules() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let (z, one, m1, two, three) = (t.c(0.0), t.c(1.0), t.c(-1.0), t.c(2.0), t.c(3.0));
    let g = &mut t.g;
    assert_eq!(g.mul(x, z), z);
    assert_eq!(g.mul(z, x), z);
    assert_eq!(g.mul(x, one), x);
    assert_eq!(g.mul(one, x), x);
    let nx = g.mul(x, m1);
    assert_eq!(*g.node(nx), Node::Neg(x));
    assert_eq!(g.mul(m1, x), nx);
    // constant first
    let tx = g.mul(x, two);
    assert_eq!(*g.node(tx), Node::Mul(two, x));
    // c*(d*x) and (c*x)*d
    let sx = g.mul(three, tx);
    let six = g.constant(6.0);
    assert_eq!(*g.node(sx), Node::Mul(six, x));
    assert_eq!(g.mul(tx, three), sx);
    let half = g.constant(0.5);
    let hx = g.mul(half, x);
    assert_eq!(g.mul(hx, two), x, "0.5*(2*x) folds to x");
    // signs
    let ny = g.neg(y);
    let xy = g.mul(x, y);
    let nxy = g.neg(xy);
    assert_eq!(g.mul(nx, y), nxy);
    assert_eq!(g.mul(x, ny), nxy);
    assert_eq!(g.mul(nx, ny), xy);
    let m2x = g.mul(two, nx);
    assert_eq!(
        g.as_const(match *g.node(m2x) {
            Node::Mul(c, _) => c,
            _ => panic!("expected c*x"),
        }),
        Some(-2.0)
    );
    // no hoisting: (2x)*(3y) stays a product of the two scaled terms
    let ty = g.mul(three, y);
    let p = g.mul(tx, ty);
    assert_eq!(*g.node(p), Node::Mul(tx.min(ty), tx.max(ty)));
    // commutativity
    assert_eq!(g.mul(y, x), xy);
    g.verify().unwrap();
}

#[test]
fn addition_and_subtraction_rules() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let z = t.c(0.0);
    let g = &mut t.g;
    assert_eq!(g.add(x, z), x);
    assert_eq!(g.add(z, x), x);
    assert_eq!(g.sub(x, z), x);
    let nx = g.sub(z, x);
    assert_eq!(*g.node(nx), Node::Neg(x));
    assert_eq!(g.sub(x, x), z);
    let xy = g.add(x, y);
    assert_eq!(g.add(y, x), xy);
    assert_eq!(*g.node(xy), Node::Add(x, y));
    let ny = g.neg(y);
    let x_y = g.sub(x, y);
    let y_x = g.sub(y, x);
    assert_eq!(g.add(x, ny), x_y, "a + (-b) -> a - b");
    assert_eq!(g.add(nx, y), y_x, "(-a) + b -> b - a");
    assert_eq!(g.sub(x, ny), xy, "a - (-b) -> a + b");
    let nxy = g.neg(xy);
    assert_eq!(g.add(nx, ny), nxy, "(-a) + (-b) -> -(a + b)");
    assert_eq!(g.sub(nx, y), nxy, "(-a) - b -> -(a + b)");
    let two = g.constant(2.0);
    let twox = g.mul(two, x);
    assert_eq!(g.add(x, x), twox);
    assert_eq!(t.s(x_y), "(- in0_0 in0_1)");
    t.g.verify().unwrap();
}

#[test]
fn negation_rules() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let three = t.c(3.0);
    let g = &mut t.g;
    let nx = g.neg(x);
    assert_eq!(g.neg(nx), x);
    let d = g.sub(x, y);
    let e = g.sub(y, x);
    assert_eq!(g.neg(d), e, "-(a - b) -> b - a");
    let tx = g.mul(three, x);
    let ntx = g.neg(tx);
    let m3 = g.constant(-3.0);
    assert_eq!(*g.node(ntx), Node::Mul(m3, x), "-(c*x) -> (-c)*x");
    assert_eq!(g.neg(ntx), tx);
    let c = g.neg(three);
    assert_eq!(c, m3);
    g.verify().unwrap();
}

#[test]
fn division_rules() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let (z, one, m1, four, three) = (t.c(0.0), t.c(1.0), t.c(-1.0), t.c(4.0), t.c(3.0));
    let g = &mut t.g;
    assert_eq!(g.div(x, one), x);
    let nx = g.neg(x);
    assert_eq!(g.div(x, m1), nx);
    assert_eq!(g.div(z, x), z);
    assert_eq!(g.div(x, x), one);
    let q = g.div(x, four);
    let quarter = g.constant(0.25);
    assert_eq!(*g.node(q), Node::Mul(quarter, x), "x/4 -> 0.25*x");
    let q3 = g.div(x, three);
    assert_eq!(
        *g.node(q3),
        Node::Div(x, three),
        "x/3 is not exact as a product"
    );
    let xy = g.div(x, y);
    let ny = g.neg(y);
    let nxy = g.neg(xy);
    assert_eq!(g.div(nx, y), nxy);
    assert_eq!(g.div(x, ny), nxy);
    assert_eq!(g.div(nx, ny), xy);
    let yx = g.div(y, x);
    assert_ne!(yx, xy);
    g.verify().unwrap();
}

#[test]
fn trig_and_sqrt_rules() {
    let mut t = setup();
    let x = t.x;
    let g = &mut t.g;
    let nx = g.neg(x);
    let s = g.sin(x);
    let ns = g.neg(s);
    assert_eq!(g.sin(nx), ns);
    let c = g.cos(x);
    assert_eq!(g.cos(nx), c);
    let r = g.sqrt(x);
    assert_eq!(*g.node(r), Node::Sqrt(x));
    g.verify().unwrap();
}

#[test]
fn hash_consing_builds_nothing_twice() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let build = |g: &mut ExprGraph| {
        let s = g.sin(x);
        let c = g.cos(y);
        let p = g.mul(s, c);
        let k = g.constant(0.75);
        let d = g.div(p, k);
        let q = g.sqrt(d);
        g.sub(q, x)
    };
    let a = build(&mut t.g);
    let n = t.g.len();
    let b = build(&mut t.g);
    assert_eq!(a, b);
    assert_eq!(t.g.len(), n);
    let xy = t.g.mul(x, y);
    assert_eq!(t.g.mul(y, x), xy);
    let sxy = t.g.add(x, y);
    assert_eq!(t.g.add(y, x), sxy);
    // Rebuilding every node from its operands returns the node itself.
    let nodes = t.g.nodes().to_vec();
    for (i, node) in nodes.iter().enumerate() {
        assert_eq!(
            super::random_tests::rebuild(&mut t.g, node),
            ExprId(i as u32)
        );
    }
    assert_eq!(t.g.len(), n + 2);
}

#[test]
fn like_terms_cancel_exactly() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let (c, mc) = (t.c(0.176), t.c(-0.176));
    let z = t.c(0.0);
    let g = &mut t.g;
    let s = g.sin(x);
    let cs = g.mul(c, s);
    let mcs = g.mul(mc, s);
    assert_eq!(g.add(cs, mcs), z, "c*x + (-c)*x -> 0");
    assert_eq!(g.add(mcs, cs), z, "(-c)*x + c*x -> 0");
    // c*x - c*x built twice is one node, and the difference the exact 0.
    let sy = g.mul(s, y);
    let a = g.mul(c, sy);
    let b = g.mul(c, sy);
    assert_eq!(a, b, "hash-consing shares c*(s*y)");
    assert_eq!(g.sub(a, b), z);
    // (c*y)*s is not rewritten to c*(s*y): a constant factor is not hoisted.
    let cy = g.mul(c, y);
    assert_ne!(g.mul(s, cy), a);
    // -(c*x) is (-c)*x, so c*x - (-(c*x)) merges too.
    let n = g.neg(cs);
    assert_eq!(n, mcs);
    let two_c = g.constant(2.0 * 0.176);
    assert_eq!(
        {
            let r = g.sub(cs, n);
            *g.node(r)
        },
        Node::Mul(two_c, s)
    );
    // x + (-1)*x and x - 1*x
    let nx = g.neg(s);
    assert_eq!(g.add(s, nx), z);
    let one = g.one();
    let os = g.mul(one, s);
    assert_eq!(g.sub(s, os), z);
    g.verify().unwrap();
}

#[test]
fn like_terms_merge_factors() {
    let mut t = setup();
    let (x, y) = (t.x, t.y);
    let (two, three, half) = (t.c(2.0), t.c(3.0), t.c(0.5));
    let g = &mut t.g;
    let xy = g.mul(x, y);
    let a = g.mul(two, xy);
    let b = g.mul(three, xy);
    let five = g.constant(5.0);
    assert_eq!(
        {
            let r = g.add(a, b);
            *g.node(r)
        },
        Node::Mul(five, xy),
        "2x + 3x -> 5x"
    );
    assert_eq!(
        {
            let r = g.sub(a, b);
            *g.node(r)
        },
        Node::Neg(xy),
        "2x - 3x -> -x"
    );
    assert_eq!(g.sub(b, a), xy, "3x - 2x -> x");
    assert_eq!(
        {
            let r = g.add(xy, a);
            *g.node(r)
        },
        Node::Mul(three, xy),
        "x + 2x -> 3x"
    );
    assert_eq!(
        {
            let r = g.add(a, xy);
            *g.node(r)
        },
        Node::Mul(three, xy),
        "2x + x -> 3x"
    );
    assert_eq!(g.sub(a, xy), xy, "2x - x -> x");
    let hx = g.mul(half, xy);
    assert_eq!(
        {
            let r = g.sub(xy, hx);
            *g.node(r)
        },
        Node::Mul(half, xy),
        "x - 0.5x -> 0.5x"
    );
    // -x - 2x: (-x) - b -> -(x + 2x) -> -(3x) -> (-3)*x
    let nxy = g.neg(xy);
    let m3 = g.constant(-3.0);
    assert_eq!(
        {
            let r = g.sub(nxy, a);
            *g.node(r)
        },
        Node::Mul(m3, xy)
    );
    // Different bases are not merged.
    let bx = g.mul(three, x);
    let s = g.add(a, bx);
    assert_eq!(*g.node(s), Node::Add(a.min(bx), a.max(bx)));
    // Merged factors that overflow are left alone.
    let big = g.constant(1.5e308);
    let p = g.mul(big, xy);
    let q = g.add(p, p);
    assert_eq!(*g.node(q), Node::Mul(two, p), "x+x keeps 2*(big*x)");
    let r = g.add(p, q);
    assert!(
        matches!(g.node(r), Node::Add(..)),
        "1.5e308 + 3e308 overflows"
    );
    g.verify().unwrap();
}

#[test]
fn verify_rejects_unmerged_like_terms() {
    let mut t = setup();
    let (x, c, d) = (t.x, t.c(2.0), t.c(3.0));
    let g = &mut t.g;
    let a = g.mul(c, x);
    let b = g.mul(d, x);
    let node = Node::Add(a, b);
    let id = ExprId(g.nodes.len() as u32);
    g.nodes.push(node);
    g.memo.insert(node, id);
    assert!(g.verify().unwrap_err().contains("unmerged like terms"));
}
