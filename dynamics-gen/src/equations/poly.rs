//! Polynomials in `sin θ_i`, `cos θ_i`, `θ_i` (prismatic joints), `θ̇_i` and `θ̈_i`, with
//! `sin² + cos² = 1` applied (every `cos²θ_i` becomes `1 − sin²θ_i`, so each term has at most
//! one cosine per joint), and the conversion of an expression graph into them.

use crate::expr::{ExprGraph, ExprId, Input, Node};
use std::collections::BTreeMap;

/// A variable of the polynomials. The order is the printing order inside a term: parameters
/// first, then rates, then positions, then the trigonometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Var {
    /// A named parameter kept as a symbol (index in the robot's parameters).
    Param(u16),
    /// `θ̈_i` (index in ν̇).
    Qdd(u16),
    /// `θ̇_i` (index in ν).
    Qd(u16),
    /// `θ_i` itself (a prismatic joint's coordinate, index in q).
    Q(u16),
    /// `sin θ_i`.
    Sin(u16),
    /// `cos θ_i`.
    Cos(u16),
}

/// A product of powers of variables, sorted by variable, every power ≥ 1.
pub type Monomial = Vec<(Var, u32)>;

/// A polynomial: monomials and their coefficients (none zero).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Poly {
    /// The terms, in the monomials' order.
    pub terms: BTreeMap<Monomial, f64>,
}

/// Why a graph has no polynomial form.
#[derive(Clone, Debug, PartialEq)]
pub enum PolyError {
    /// A division or square root (only forward dynamics and a floating base's quaternion
    /// have them).
    NotPolynomial(&'static str),
    /// `sin`/`cos` of something other than `Σ a_j θ_j + constant` with whole `a_j`, `|a_j| ≤ 8`.
    Argument,
    /// More terms than the limit in one expression.
    TooLarge(usize),
}

impl std::fmt::Display for PolyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PolyError::NotPolynomial(op) => {
                write!(f, "the expression has a {op}, so it is not a polynomial")
            }
            PolyError::Argument => write!(
                f,
                "a sine or cosine of something other than a sum of joint angles times whole numbers up to 8, plus a constant (a mimic joint with a multiplier such as 0.5)"
            ),
            PolyError::TooLarge(n) => write!(f, "an expression has more than {n} terms"),
        }
    }
}

/// The most terms one intermediate polynomial may have.
pub const MAX_TERMS: usize = 200_000;

impl Poly {
    /// The constant `c`.
    pub fn constant(c: f64) -> Self {
        let mut p = Poly::default();
        if c != 0.0 {
            p.terms.insert(Vec::new(), c);
        }
        p
    }

    /// The variable `v`.
    pub fn var(v: Var) -> Self {
        let mut p = Poly::default();
        p.terms.insert(vec![(v, 1)], 1.0);
        p
    }

    /// The largest coefficient's magnitude.
    pub fn scale(&self) -> f64 {
        self.terms.values().fold(0.0, |m, c| m.max(c.abs()))
    }

    /// `a·self + b·other`.
    pub fn combine(&self, a: f64, other: &Poly, b: f64) -> Poly {
        let mut out = Poly::default();
        for (m, c) in &self.terms {
            out.add_term(m.clone(), a * c);
        }
        for (m, c) in &other.terms {
            out.add_term(m.clone(), b * c);
        }
        out
    }

    /// `c·self`.
    pub fn scaled(&self, c: f64) -> Poly {
        self.combine(c, &Poly::default(), 0.0)
    }

    fn add_term(&mut self, m: Monomial, c: f64) {
        if c == 0.0 {
            return;
        }
        match self.terms.entry(m) {
            std::collections::btree_map::Entry::Vacant(v) => {
                v.insert(c);
            }
            std::collections::btree_map::Entry::Occupied(mut o) => {
                *o.get_mut() += c;
                if *o.get() == 0.0 {
                    o.remove();
                }
            }
        }
    }

    /// `self · other`, reduced with `cos² = 1 − sin²`.
    pub fn mul(&self, other: &Poly) -> Result<Poly, PolyError> {
        let mut out = Poly::default();
        for (a, ca) in &self.terms {
            for (b, cb) in &other.terms {
                for (m, c) in reduce(product(a, b)) {
                    out.add_term(m, c * ca * cb);
                }
            }
            if out.terms.len() > MAX_TERMS {
                return Err(PolyError::TooLarge(MAX_TERMS));
            }
        }
        Ok(out)
    }

    /// Drops the terms whose coefficients are rounding leftovers: below `rel` times the
    /// largest coefficient.
    pub fn cleaned(mut self, rel: f64) -> Poly {
        let tol = rel * self.scale();
        self.terms.retain(|_, c| c.abs() > tol);
        self
    }

    /// The value at the given variables.
    pub fn eval(&self, value: &dyn Fn(Var) -> f64) -> f64 {
        self.terms
            .iter()
            .map(|(m, c)| {
                c * m
                    .iter()
                    .map(|&(v, p)| value(v).powi(p as i32))
                    .product::<f64>()
            })
            .sum()
    }

    /// The polynomial as `Σ a_j·θ_j + b` in position variables with whole coefficients `a_j`
    /// (`±1` for a joint, the sums of a run of parallel joints, `2` where a mimic joint
    /// turns with its leader): `([(index, a_j)], b)`.
    fn as_angle(&self) -> Option<(Vec<(u16, i32)>, f64)> {
        let mut vars = Vec::new();
        let mut b = 0.0;
        for (m, &c) in &self.terms {
            match m.as_slice() {
                [] => b = c,
                [(Var::Q(i), 1)] if c.fract() == 0.0 && c.abs() <= 8.0 => {
                    vars.push((*i, c as i32));
                }
                _ => return None,
            }
        }
        (!vars.is_empty()).then_some((vars, b))
    }

    /// `(sin x, cos x)` of the angle `x = Σ a_j·θ_j + b` ([`Self::as_angle`]) by the angle
    /// addition formulas, in `sin θ_j`, `cos θ_j`: `sin(x ± θ) = sin x cos θ ± cos x sin θ`,
    /// `cos(x ± θ) = cos x cos θ ∓ sin x sin θ`, from `(sin b, cos b)`.
    fn sin_cos_of_angle(vars: &[(u16, i32)], b: f64) -> Result<(Poly, Poly), PolyError> {
        let (sb, cb) = exact_sin_cos(b);
        let (mut sin, mut cos) = (Poly::constant(sb), Poly::constant(cb));
        for &(j, a) in vars {
            let (sj, cj) = (Poly::var(Var::Sin(j)), Poly::var(Var::Cos(j)));
            let sign = f64::from(a.signum());
            for _ in 0..a.unsigned_abs() {
                let s = sin.mul(&cj)?.combine(1.0, &cos.mul(&sj)?, sign);
                let c = cos.mul(&cj)?.combine(1.0, &sin.mul(&sj)?, -sign);
                (sin, cos) = (s, c);
            }
        }
        Ok((sin, cos))
    }
}

/// The product of two monomials.
fn product(a: &Monomial, b: &Monomial) -> Monomial {
    let mut out: Monomial = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        if j == b.len() || (i < a.len() && a[i].0 < b[j].0) {
            out.push(a[i]);
            i += 1;
        } else if i == a.len() || b[j].0 < a[i].0 {
            out.push(b[j]);
            j += 1;
        } else {
            out.push((a[i].0, a[i].1 + b[j].1));
            i += 1;
            j += 1;
        }
    }
    out
}

/// `m` with every `cos^p θ_i`, p ≥ 2, replaced by `cos^(p−2) θ_i (1 − sin²θ_i)`, as terms.
fn reduce(m: Monomial) -> Vec<(Monomial, f64)> {
    let Some(k) = m
        .iter()
        .position(|&(v, p)| matches!(v, Var::Cos(_)) && p >= 2)
    else {
        return vec![(m, 1.0)];
    };
    let (Var::Cos(i), p) = m[k] else {
        unreachable!("position found a cosine")
    };
    let mut rest = m.clone();
    if p == 2 {
        rest.remove(k);
    } else {
        rest[k].1 = p - 2;
    }
    let sin2 = product(&rest, &vec![(Var::Sin(i), 2)]);
    let mut out = reduce(rest);
    out.extend(reduce(sin2).into_iter().map(|(m, c)| (m, -c)));
    out
}

/// The polynomials of `roots` in `graph`, whose inputs map to variables by `var` (q of a
/// revolute joint appears only inside `sin`/`cos`; `None`: the input has no variable).
pub fn from_graph(
    graph: &ExprGraph,
    roots: &[ExprId],
    var: &dyn Fn(Input) -> Option<Var>,
) -> Result<Vec<Poly>, PolyError> {
    let live = graph.live(roots);
    let n = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
    // Uses left of each node, so its polynomial is dropped after its last user.
    let mut uses = vec![0u32; n];
    for i in (0..n).filter(|&i| live[i]) {
        for o in graph.node(ExprId(i as u32)).operands() {
            uses[o.index()] += 1;
        }
    }
    for r in roots {
        uses[r.index()] += 1;
    }
    let empty = Poly::default();
    let mut polys: Vec<Option<Poly>> = vec![None; n];
    // Nodes are topologically ordered: operands first.
    for i in 0..n {
        if !live[i] {
            continue;
        }
        let node = *graph.node(ExprId(i as u32));
        let get = |id: ExprId| polys[id.index()].as_ref().unwrap_or(&empty);
        let p = match node {
            Node::Const(c) => Poly::constant(c.value()),
            Node::Input(x) => match var(x) {
                Some(v) => Poly::var(v),
                None => Poly::default(),
            },
            Node::Neg(a) => get(a).scaled(-1.0),
            Node::Add(a, b) => get(a).combine(1.0, get(b), 1.0),
            Node::Sub(a, b) => get(a).combine(1.0, get(b), -1.0),
            Node::Mul(a, b) => get(a).mul(get(b))?,
            Node::Div(..) => return Err(PolyError::NotPolynomial("division")),
            Node::Sqrt(..) => return Err(PolyError::NotPolynomial("square root")),
            Node::Sin(a) | Node::Cos(a) => {
                let (vars, b) = get(a).as_angle().ok_or(PolyError::Argument)?;
                let (sin, cos) = Poly::sin_cos_of_angle(&vars, b)?;
                if matches!(node, Node::Sin(_)) {
                    sin
                } else {
                    cos
                }
            }
        };
        for o in node.operands() {
            uses[o.index()] -= 1;
            if uses[o.index()] == 0 {
                polys[o.index()] = None;
            }
        }
        polys[i] = Some(p);
    }
    Ok(roots
        .iter()
        .map(|r| polys[r.index()].clone().unwrap_or_default())
        .collect())
}

/// `(sin b, cos b)`, exact at multiples of π/2 (no 6e-17 leftovers).
fn exact_sin_cos(b: f64) -> (f64, f64) {
    let k = b / std::f64::consts::FRAC_PI_2;
    if (k - k.round()).abs() < 1e-12 {
        match (k.round() as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        b.sin_cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cosine_squares_become_sines() {
        // cos²θ₀ · cos θ₀ = cos θ₀ − sin²θ₀ cos θ₀
        let c = Poly::var(Var::Cos(0));
        let c3 = c.mul(&c).unwrap().mul(&c).unwrap();
        let want: Vec<(Monomial, f64)> = vec![
            (vec![(Var::Sin(0), 2), (Var::Cos(0), 1)], -1.0),
            (vec![(Var::Cos(0), 1)], 1.0),
        ];
        let mut got: Vec<(Monomial, f64)> = c3.terms.into_iter().collect();
        got.sort_by(|a, b| a.0.cmp(&b.0));
        let mut want = want;
        want.sort_by(|a, b| a.0.cmp(&b.0));
        assert_eq!(got, want);
        // sin² + cos² = 1
        let s = Poly::var(Var::Sin(0));
        let one = s.mul(&s).unwrap().combine(1.0, &c.mul(&c).unwrap(), 1.0);
        assert_eq!(one, Poly::constant(1.0));
    }
}
