//! Symbolic differentiation over the live sub-graph: forward mode ([`ExprGraph::jvp`], one
//! sweep per direction) and reverse mode ([`ExprGraph::grad`], the whole gradient of one
//! scalar in one sweep).

use super::graph::ExprGraph;
use super::node::{ExprId, Input, Node};

impl ExprGraph {
    /// `∂f/∂x`, built with the simplifying constructors.
    ///
    /// Derivatives of shared sub-expressions are computed once (memoised
    /// for the duration of the call). Sub-expressions that do not depend on
    /// `x` differentiate to the constant `0` and vanish from products.
    pub fn diff(&mut self, f: ExprId, x: Input) -> ExprId {
        self.diff_many(&[f], x)[0]
    }

    /// `∂f/∂x` for every `f` in `fs`, sharing one memo (so common
    /// sub-expressions of the `fs` are differentiated once).
    pub fn diff_many(&mut self, fs: &[ExprId], x: Input) -> Vec<ExprId> {
        // Independent of x: zeros, without adding the seed's 1 to the graph.
        let depends = self
            .find_input(x)
            .is_some_and(|id| self.live(fs)[id.index()]);
        if !depends {
            let zero = self.zero();
            return vec![zero; fs.len()];
        }
        let one = self.one();
        self.jvp(fs, &[(x, one)])
    }

    /// The directional derivative (Jacobian-vector product) `Σ_x ∂f/∂x · ẋ` of every `f` in
    /// `fs`, for the tangents `seeds` = `(x, ẋ)` (expressions of the graph; inputs not listed
    /// have tangent 0). With `ẋ` the time derivatives of the inputs this is `df/dt`.
    pub fn jvp(&mut self, fs: &[ExprId], seeds: &[(Input, ExprId)]) -> Vec<ExprId> {
        let live = self.live(fs);
        // Only nodes older than the newest root matter; derivative nodes are
        // appended behind them and never need derivatives themselves.
        let n = fs.iter().map(|f| f.index() + 1).max().unwrap_or(0);
        let mut d: Vec<ExprId> = Vec::with_capacity(n);
        // Nodes are in topological order, so one forward sweep computes each
        // derivative after those of its operands (no recursion, no stack
        // depth issues on deep expressions).
        for i in 0..n {
            let id = ExprId(i as u32);
            // Dead nodes get a placeholder that is never read (live nodes
            // only have live operands).
            let di = if live[i] {
                self.diff_node(id, seeds, &d)
            } else {
                id
            };
            d.push(di);
        }
        fs.iter().map(|f| d[f.index()]).collect()
    }

    /// The gradient `∂f/∂x` of the scalar `f` for every `x` in `xs`, by reverse-mode
    /// accumulation: one backward sweep over `f`'s live nodes (users before operands, as the
    /// graph is topologically ordered), each node's adjoint `f̄_i = Σ_users ū ∂u/∂i` summed
    /// once all its users are done, so the cost is a small multiple of `f`'s own whatever
    /// the number of inputs (forward mode costs that per input). Inputs `f` does not read get
    /// the constant 0.
    pub fn grad(&mut self, f: ExprId, xs: &[Input]) -> Vec<ExprId> {
        let n = f.index() + 1;
        let live = self.live(&[f]);
        let zero = self.zero();
        // The adjoint's terms of each node, then the adjoint itself.
        let mut terms: Vec<Vec<ExprId>> = vec![Vec::new(); n];
        let mut bar: Vec<ExprId> = vec![zero; n];
        terms[f.index()].push(self.one());
        for i in (0..n).rev() {
            if !live[i] || terms[i].is_empty() {
                continue;
            }
            let a = self.sum(&std::mem::take(&mut terms[i]));
            bar[i] = a;
            if self.is_zero(a) {
                continue;
            }
            let id = ExprId(i as u32);
            let mut push = |g: &mut Self, x: ExprId, t: ExprId| {
                if !g.is_zero(t) {
                    terms[x.index()].push(t);
                }
            };
            match *self.node(id) {
                Node::Const(_) | Node::Input(_) => {}
                Node::Neg(x) => {
                    let t = self.neg(a);
                    push(self, x, t);
                }
                Node::Add(x, y) => {
                    push(self, x, a);
                    push(self, y, a);
                }
                Node::Sub(x, y) => {
                    push(self, x, a);
                    let t = self.neg(a);
                    push(self, y, t);
                }
                Node::Mul(x, y) => {
                    let tx = self.mul(a, y);
                    push(self, x, tx);
                    let ty = self.mul(a, x);
                    push(self, y, ty);
                }
                Node::Div(x, y) => {
                    // ∂(x/y)/∂x = 1/y, ∂(x/y)/∂y = −(x/y)/y.
                    let ay = self.div(a, y);
                    push(self, x, ay);
                    let t = self.mul(ay, id);
                    let t = self.neg(t);
                    push(self, y, t);
                }
                Node::Sqrt(x) => {
                    let two = self.constant(2.0);
                    let den = self.mul(two, id);
                    let t = self.div(a, den);
                    push(self, x, t);
                }
                Node::Sin(x) => {
                    let c = self.cos(x);
                    let t = self.mul(a, c);
                    push(self, x, t);
                }
                Node::Cos(x) => {
                    let s = self.sin(x);
                    let t = self.mul(a, s);
                    let t = self.neg(t);
                    push(self, x, t);
                }
            }
        }
        xs.iter()
            .map(|&x| match self.find_input(x) {
                Some(id) if id.index() < n => bar[id.index()],
                _ => zero,
            })
            .collect()
    }

    /// Derivative of node `id` given the derivatives `d` of all older nodes.
    fn diff_node(&mut self, id: ExprId, seeds: &[(Input, ExprId)], d: &[ExprId]) -> ExprId {
        let dd = |a: ExprId| d[a.index()];
        let node = *self.node(id);
        // Constant with respect to x: build nothing (not even cos(a) for sin).
        if !matches!(node, Node::Input(_)) && node.operands().all(|o| self.is_zero(dd(o))) {
            return self.zero();
        }
        match node {
            Node::Const(_) => self.zero(),
            Node::Input(y) => match seeds.iter().find(|(x, _)| *x == y) {
                Some(&(_, t)) => t,
                None => self.zero(),
            },
            Node::Neg(a) => self.neg(dd(a)),
            Node::Add(a, b) => self.add(dd(a), dd(b)),
            Node::Sub(a, b) => self.sub(dd(a), dd(b)),
            Node::Mul(a, b) => {
                // (ab)' = a'b + ab'
                let l = self.mul(dd(a), b);
                let r = self.mul(a, dd(b));
                self.add(l, r)
            }
            Node::Div(a, b) => {
                // (a/b)' = (a' - (a/b) b') / b   (reuses the quotient itself)
                let t = self.mul(id, dd(b));
                let num = self.sub(dd(a), t);
                self.div(num, b)
            }
            Node::Sqrt(a) => {
                // sqrt(a)' = a' / (2 sqrt(a))
                let two = self.constant(2.0);
                let den = self.mul(two, id);
                self.div(dd(a), den)
            }
            Node::Sin(a) => {
                let c = self.cos(a);
                self.mul(c, dd(a))
            }
            Node::Cos(a) => {
                let s = self.sin(a);
                let p = self.mul(s, dd(a));
                self.neg(p)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_derivatives_are_simplified() {
        let mut g = ExprGraph::new();
        let qx = Input::new(0, 0);
        let qy = Input::new(0, 1);
        let x = g.input(qx);
        let y = g.input(qy);
        let sx = g.sin(x);
        let cx = g.cos(x);
        assert_eq!(g.diff(sx, qx), cx);
        let msx = g.neg(sx);
        assert_eq!(g.diff(cx, qx), msx);
        assert_eq!(g.diff(sx, qy), g.zero());
        // d(x*y)/dx = y ; d(3x)/dx = 3
        let xy = g.mul(x, y);
        assert_eq!(g.diff(xy, qx), y);
        let three = g.constant(3.0);
        let tx = g.mul(three, x);
        assert_eq!(g.diff(tx, qx), three);
        // d(x*x)/dx = 2x
        let xx = g.mul(x, x);
        let two = g.constant(2.0);
        let two_x = g.mul(two, x);
        assert_eq!(g.diff(xx, qx), two_x);
        // d(1/y)/dy = -(1/y)/y
        let one = g.one();
        let inv = g.div(one, y);
        let expect = {
            let q = g.div(inv, y);
            g.neg(q)
        };
        assert_eq!(g.diff(inv, qy), expect);
        // diff_many shares work and keeps order
        let ds = g.diff_many(&[xy, sx, y], qx);
        assert_eq!(ds, vec![y, cx, g.zero()]);
        g.verify().unwrap();
    }

    /// Reverse mode equals forward mode, in numbers, on a random expression of every node
    /// kind.
    #[test]
    fn gradient_equals_forward_mode() {
        let mut g = ExprGraph::new();
        let xs: Vec<Input> = (0..4)
            .map(|i| Input::new((i % 2) as u8, i as u16))
            .collect();
        let v: Vec<ExprId> = xs.iter().map(|&x| g.input(x)).collect();
        let mut pool = v.clone();
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = |m: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % m as u64) as usize
        };
        for k in 0..200 {
            let a = pool[next(pool.len())];
            let b = pool[next(pool.len())];
            let e = match k % 9 {
                0 => g.add(a, b),
                1 => g.sub(a, b),
                2 => g.mul(a, b),
                3 => {
                    let two = g.constant(2.0);
                    let s = g.mul(b, b);
                    let d = g.add(s, two);
                    g.div(a, d)
                }
                4 => g.sin(a),
                5 => g.cos(a),
                6 => g.neg(a),
                7 => {
                    let s = g.mul(a, a);
                    let one = g.one();
                    let d = g.add(s, one);
                    g.sqrt(d)
                }
                _ => {
                    let half = g.constant(0.5);
                    g.mul(half, a)
                }
            };
            pool.push(e);
        }
        let tail: Vec<ExprId> = pool[pool.len() - 20..].to_vec();
        let f = g.sum(&tail);
        let rev = g.grad(f, &xs);
        let fwd: Vec<ExprId> = xs.iter().map(|&x| g.diff(f, x)).collect();
        g.verify().unwrap();
        let at = |x: Input| 0.3 + 0.7 * x.index as f64 - 0.2 * x.group as f64;
        let (r, w) = (g.eval(&rev, &at), g.eval(&fwd, &at));
        for (a, b) in r.iter().zip(&w) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{r:?} vs {w:?}");
        }
        // Not vacuous: every input reaches f.
        assert!(r.iter().all(|x| *x != 0.0), "{r:?}");
        let unused = g.grad(f, &[Input::new(3, 0)]);
        assert!(g.is_zero(unused[0]));
    }
}
