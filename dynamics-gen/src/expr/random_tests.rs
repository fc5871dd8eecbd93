//! Randomised tests: invariants under random operation sequences, eval
//! against direct `f64` computation, and derivatives against finite
//! differences. Uses a small seeded xorshift RNG (deterministic).

use super::{ExprGraph, ExprId, Input, Node};

/// xorshift64* pseudo random numbers.
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub(super) fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in `0..n`.
    pub(super) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// Uniform in `[lo, hi)`.
    pub(super) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

/// Calls the constructor matching `node` on its operands.
pub(super) fn rebuild(g: &mut ExprGraph, node: &Node) -> ExprId {
    match *node {
        Node::Const(c) => g.constant(c.value()),
        Node::Input(x) => g.input(x),
        Node::Neg(a) => g.neg(a),
        Node::Add(a, b) => g.add(a, b),
        Node::Sub(a, b) => g.sub(a, b),
        Node::Mul(a, b) => g.mul(a, b),
        Node::Div(a, b) => g.div(a, b),
        Node::Sqrt(a) => g.sqrt(a),
        Node::Sin(a) => g.sin(a),
        Node::Cos(a) => g.cos(a),
    }
}

/// Constants that trigger the special-case rules.
const SPECIAL: [f64; 11] = [
    0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, 3.0, 0.25, 1e300, -1e-300,
];

/// Every stored node must be in normal form and be a fixed point of its
/// constructor.
fn assert_normal_form(g: &mut ExprGraph) {
    g.verify().unwrap_or_else(|e| panic!("verify failed: {e}"));
    let n = g.len();
    for i in 0..n {
        let node = *g.node(ExprId(i as u32));
        assert_eq!(
            rebuild(g, &node),
            ExprId(i as u32),
            "{node:?} is not a fixed point"
        );
    }
    assert_eq!(g.len(), n, "rebuilding added nodes");
}

#[test]
fn random_operation_sequences_keep_invariants() {
    for seed in 0..40 {
        let mut rng = Rng::new(seed);
        let mut g = ExprGraph::new();
        let mut pool: Vec<ExprId> = (0..3).map(|i| g.input(Input::new(0, i))).collect();
        for _ in 0..300 {
            let a = pool[rng.below(pool.len())];
            let b = pool[rng.below(pool.len())];
            let r = match rng.below(12) {
                0 => g.constant(SPECIAL[rng.below(SPECIAL.len())]),
                1 => g.neg(a),
                2 => g.add(a, b),
                3 => g.sub(a, b),
                4 | 5 => g.mul(a, b),
                6 => g.div(a, b),
                7 => g.sqrt(a),
                8 => g.sin(a),
                9 => g.cos(a),
                10 => g.input(Input::new(rng.below(2) as u8, rng.below(4) as u16)),
                _ => {
                    let x = Input::new(0, rng.below(3) as u16);
                    g.diff(a, x)
                }
            };
            pool.push(r);
        }
        assert_normal_form(&mut g);
    }
}

/// A random well-conditioned expression over inputs `x0..x2` of group 0,
/// with its value computed directly in `f64` at `xs`, and a bound `m` on
/// the sensitivity of the value to rounding (absolute error ≲ ε·m).
struct Built {
    id: ExprId,
    val: f64,
    m: f64,
}

fn build(g: &mut ExprGraph, rng: &mut Rng, xs: &[f64; 3], depth: u32) -> Built {
    if depth == 0 || rng.below(6) == 0 {
        if rng.below(3) == 0 {
            let v = if rng.below(4) == 0 {
                SPECIAL[rng.below(9)]
            } else {
                (rng.range(-2.0, 2.0) * 8.0).round() / 8.0
            };
            return Built {
                id: g.constant(v),
                val: v,
                m: v.abs().max(1.0),
            };
        }
        let i = rng.below(3);
        let v = xs[i];
        return Built {
            id: g.input(Input::new(0, i as u16)),
            val: v,
            m: v.abs().max(1.0),
        };
    }
    let a = build(g, rng, xs, depth - 1);
    match rng.below(8) {
        0 => Built {
            id: g.neg(a.id),
            val: -a.val,
            m: a.m,
        },
        1 => Built {
            id: g.sin(a.id),
            val: a.val.sin(),
            m: a.m,
        },
        2 => Built {
            id: g.cos(a.id),
            val: a.val.cos(),
            m: a.m,
        },
        3 => {
            // sqrt(a*a + c), c > 0
            let c = rng.range(0.5, 2.0);
            let k = g.constant(c);
            let u = g.mul_add(a.id, a.id, k);
            let m = (a.m * a.m + c) / (2.0 * c.sqrt()) + 1.0;
            Built {
                id: g.sqrt(u),
                val: (a.val * a.val + c).sqrt(),
                m,
            }
        }
        op => {
            let b = build(g, rng, xs, depth - 1);
            match op {
                4 => Built {
                    id: g.add(a.id, b.id),
                    val: a.val + b.val,
                    m: a.m + b.m,
                },
                5 => Built {
                    id: g.sub(a.id, b.id),
                    val: a.val - b.val,
                    m: a.m + b.m,
                },
                6 => Built {
                    id: g.mul(a.id, b.id),
                    val: a.val * b.val,
                    m: a.m * b.m,
                },
                _ => {
                    // a / ±(b*b + c), c > 0
                    let c = rng.range(0.5, 2.0);
                    let k = g.constant(c);
                    let mut den = g.mul_add(b.id, b.id, k);
                    let mut den_val = b.val * b.val + c;
                    if rng.below(2) == 0 {
                        den = g.neg(den);
                        den_val = -den_val;
                    }
                    let m = a.m * (1.0 + (b.m * b.m + c) / c) / c;
                    Built {
                        id: g.div(a.id, den),
                        val: a.val / den_val,
                        m,
                    }
                }
            }
        }
    }
}

fn point(rng: &mut Rng) -> [f64; 3] {
    [
        rng.range(-1.5, 1.5),
        rng.range(-1.5, 1.5),
        rng.range(-1.5, 1.5),
    ]
}

fn env(xs: [f64; 3]) -> impl Fn(Input) -> f64 {
    move |x: Input| xs[x.index as usize]
}

#[test]
fn eval_matches_direct_f64() {
    let mut rng = Rng::new(7);
    let mut g = ExprGraph::new();
    let mut checked = 0;
    for _ in 0..500 {
        let xs = point(&mut rng);
        let b = build(&mut g, &mut rng, &xs, 5);
        let got = g.eval(&[b.id], &env(xs))[0];
        let tol = 1e-12 * b.m;
        assert!(
            (got - b.val).abs() <= tol,
            "{} vs {} (m = {})",
            got,
            b.val,
            b.m
        );
        checked += usize::from(b.m < 1e3);
    }
    assert!(checked > 250, "too few well-conditioned cases: {checked}");
    assert_normal_form(&mut g);
}

/// d/dx_i of the expression `f` at `xs` by Richardson-extrapolated central
/// differences of `eval`.
fn finite_diff(g: &ExprGraph, f: ExprId, xs: [f64; 3], i: usize) -> f64 {
    let central = |h: f64| {
        let (mut p, mut m) = (xs, xs);
        p[i] += h;
        m[i] -= h;
        (g.eval(&[f], &env(p))[0] - g.eval(&[f], &env(m))[0]) / (2.0 * h)
    };
    let h = 1e-3;
    (4.0 * central(h / 2.0) - central(h)) / 3.0
}

fn assert_close(sym: f64, fd: f64, what: &str) {
    let err = (sym - fd).abs() / sym.abs().max(1.0);
    assert!(
        err <= 1e-6,
        "{what}: symbolic {sym} vs finite difference {fd} (rel err {err:e})"
    );
}

#[test]
fn derivatives_match_finite_differences() {
    let mut rng = Rng::new(42);
    let mut g = ExprGraph::new();
    let vars: Vec<Input> = (0..3).map(|i| Input::new(0, i)).collect();
    let mut nonzero = 0;
    for case in 0..150 {
        let xs = point(&mut rng);
        let f = build(&mut g, &mut rng, &xs, 4).id;
        let grads = g.diff_many(&[f, f], vars[0]);
        assert_eq!(grads[0], grads[1]);
        for (i, &x) in vars.iter().enumerate() {
            let df = g.diff(f, x);
            let sym = g.eval(&[df], &env(xs))[0];
            assert_close(
                sym,
                finite_diff(&g, f, xs, i),
                &format!("case {case} d/dx{i}"),
            );
            nonzero += usize::from(sym.abs() > 1e-3);
            // Second derivatives: finite differences of the first derivative.
            let j = rng.below(3);
            let d2 = g.diff(df, vars[j]);
            let sym2 = g.eval(&[d2], &env(xs))[0];
            assert_close(
                sym2,
                finite_diff(&g, df, xs, j),
                &format!("case {case} d2/dx{i}dx{j}"),
            );
            // Mixed partials commute (up to rounding).
            let other = g.diff(f, vars[j]);
            let d2t = g.diff(other, x);
            let sym2t = g.eval(&[d2t], &env(xs))[0];
            assert_close(sym2, sym2t, &format!("case {case} symmetry {i},{j}"));
        }
    }
    assert!(nonzero > 200, "too many trivial derivatives: {nonzero}");
    assert_normal_form(&mut g);
}

#[test]
fn derivative_of_independent_expression_is_zero() {
    let mut g = ExprGraph::new();
    let y = g.input(Input::new(1, 0));
    let s = g.sin(y);
    let f = g.mul(s, y);
    let before = g.len();
    assert_eq!(g.diff(f, Input::new(0, 0)), g.zero());
    assert!(g.len() <= before + 1, "only the zero constant may be added");
}
