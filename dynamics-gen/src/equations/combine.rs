//! Products of sines and cosines of different angles combined where that is shorter: two
//! terms `k R cos α cos β − k R sin α sin β` become the one term `k R cos(α + β)` (and the
//! same for `cos(α − β)`, `sin(α ± β)`), repeatedly, so a planar chain's `c1c2c3 − …` becomes
//! `cos(θ1+θ2+θ3)`. Only exact pairs are combined (coefficients equal to 1e-12 relative), so
//! the value is unchanged.

use super::poly::{Monomial, Poly, Var};
use std::collections::BTreeMap;

/// An angle `Σ ±θ_i`: joints in increasing order, each with its sign (the first positive).
pub type Angle = Vec<(u16, i8)>;

/// A factor of a printed term.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Factor {
    /// A variable of [`Poly`] other than a single angle's sine or cosine.
    Var(Var),
    /// `cos` (true) or `sin` (false, printed first) of an angle.
    Trig(bool, Angle),
}

/// A printed term: coefficient and factors with their powers, in printing order.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// The coefficient.
    pub coef: f64,
    /// The factors.
    pub factors: Vec<(Factor, u32)>,
}

/// The other factors of a term and the two angles of a pair of its sines and cosines.
type PairKey = (Vec<(Factor, u32)>, Angle, Angle);

fn factors_of(m: &Monomial) -> Vec<(Factor, u32)> {
    let mut out: Vec<(Factor, u32)> = m
        .iter()
        .map(|&(v, p)| match v {
            Var::Sin(i) => (Factor::Trig(false, vec![(i, 1)]), p),
            Var::Cos(i) => (Factor::Trig(true, vec![(i, 1)]), p),
            v => (Factor::Var(v), p),
        })
        .collect();
    out.sort();
    out
}

fn negate(a: &Angle) -> Angle {
    a.iter().map(|&(i, s)| (i, -s)).collect()
}

/// `a + b` of angles on disjoint joints, and whether it was negated to make its first sign
/// positive.
fn add(a: &Angle, b: &Angle) -> (Angle, bool) {
    let mut out: Angle = a.iter().chain(b).copied().collect();
    out.sort();
    if out[0].1 < 0 {
        (negate(&out), true)
    } else {
        (out, false)
    }
}

fn disjoint(a: &Angle, b: &Angle) -> bool {
    a.iter().all(|(i, _)| b.iter().all(|(j, _)| i != j))
}

fn same(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-12 * x.abs().max(y.abs())
}

/// The terms of `p`, with pairs combined into sines and cosines of sums and differences.
pub fn combined(p: &Poly) -> Vec<Term> {
    let mut terms: Vec<Term> = p
        .terms
        .iter()
        .map(|(m, &c)| Term {
            coef: c,
            factors: factors_of(m),
        })
        .collect();
    loop {
        // (rest, α, β) → [cos α cos β, sin α sin β, sin α cos β, cos α sin β] term indices.
        let mut pairs: BTreeMap<PairKey, [Option<usize>; 4]> = BTreeMap::new();
        for (t, term) in terms.iter().enumerate() {
            let trig: Vec<usize> = (0..term.factors.len())
                .filter(|&k| matches!(term.factors[k], (Factor::Trig(..), 1)))
                .collect();
            for (x, &a) in trig.iter().enumerate() {
                for &b in &trig[x + 1..] {
                    let (Factor::Trig(ca, ref alpha), _) = term.factors[a] else {
                        continue;
                    };
                    let (Factor::Trig(cb, ref beta), _) = term.factors[b] else {
                        continue;
                    };
                    // The pair in a canonical order, so both terms of a pair find it.
                    let (sa, sb, alpha, beta) = if alpha <= beta {
                        (!ca, !cb, alpha, beta)
                    } else {
                        (!cb, !ca, beta, alpha)
                    };
                    if !disjoint(alpha, beta) {
                        continue;
                    }
                    let rest: Vec<(Factor, u32)> = term
                        .factors
                        .iter()
                        .enumerate()
                        .filter(|&(k, _)| k != a && k != b)
                        .map(|(_, f)| f.clone())
                        .collect();
                    let kind = match (sa, sb) {
                        (false, false) => 0,
                        (true, true) => 1,
                        (true, false) => 2,
                        (false, true) => 3,
                    };
                    let slot = pairs
                        .entry((rest, alpha.clone(), beta.clone()))
                        .or_insert([None; 4]);
                    slot[kind].get_or_insert(t);
                }
            }
        }
        let mut used = vec![false; terms.len()];
        let mut new_terms = Vec::new();
        for ((rest, alpha, beta), slot) in pairs {
            for (first, second, is_sin) in [(0, 1, false), (2, 3, true)] {
                let (Some(x), Some(y)) = (slot[first], slot[second]) else {
                    continue;
                };
                if used[x] || used[y] {
                    continue;
                }
                let (kx, ky) = (terms[x].coef, terms[y].coef);
                // cos α cos β ∓ sin α sin β = cos(α ± β); sin α cos β ± cos α sin β = sin(α ± β).
                let plus = if is_sin { same(kx, ky) } else { same(kx, -ky) };
                let minus = if is_sin { same(kx, -ky) } else { same(kx, ky) };
                if !(plus || minus) {
                    continue;
                }
                let other = if plus { beta.clone() } else { negate(&beta) };
                let (angle, flipped) = add(&alpha, &other);
                let coef = if flipped && is_sin { -kx } else { kx };
                let mut factors = rest.clone();
                factors.push((Factor::Trig(!is_sin, angle), 1));
                factors.sort();
                used[x] = true;
                used[y] = true;
                new_terms.push(Term { coef, factors });
            }
        }
        if new_terms.is_empty() {
            break;
        }
        let mut next: Vec<Term> = terms
            .into_iter()
            .zip(used)
            .filter(|(_, u)| !u)
            .map(|(t, _)| t)
            .collect();
        // Equal factors after combining (cos(θ1+θ2) twice) become a power.
        for t in new_terms {
            let mut factors: Vec<(Factor, u32)> = Vec::new();
            for (f, p) in t.factors {
                match factors.last_mut() {
                    Some((g, q)) if *g == f => *q += p,
                    _ => factors.push((f, p)),
                }
            }
            match next.iter_mut().find(|u| u.factors == factors) {
                Some(u) => u.coef += t.coef,
                None => next.push(Term {
                    coef: t.coef,
                    factors,
                }),
            }
        }
        next.retain(|t| t.coef != 0.0);
        terms = next;
    }
    terms
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(terms: &[Term], q: &[f64]) -> f64 {
        terms
            .iter()
            .map(|t| {
                t.coef
                    * t.factors
                        .iter()
                        .map(|(f, p)| {
                            let x = match f {
                                Factor::Trig(c, a) => {
                                    let th: f64 =
                                        a.iter().map(|&(i, s)| s as f64 * q[i as usize]).sum();
                                    if *c {
                                        th.cos()
                                    } else {
                                        th.sin()
                                    }
                                }
                                Factor::Var(Var::Qd(i)) => q[*i as usize] * 0.3,
                                Factor::Var(_) => 1.7,
                            };
                            x.powi(*p as i32)
                        })
                        .product::<f64>()
            })
            .sum()
    }

    fn poly(terms: &[(f64, &[(Var, u32)])]) -> Poly {
        let mut p = Poly::default();
        for (c, m) in terms {
            p.terms.insert(m.to_vec(), *c);
        }
        p
    }

    #[test]
    fn planar_chains_combine_into_sums_of_angles() {
        use Var::{Cos, Qd, Sin};
        let q: [f64; 3] = [0.3, -1.1, 0.7];
        // c1c2 − s1s2 → cos(θ1+θ2); s1c2 + c1s2 → sin(θ1+θ2); c1c2 + s1s2 → cos(θ1−θ2).
        let cases: Vec<(Poly, usize, &str)> = vec![
            (
                poly(&[
                    (3.0, &[(Cos(0), 1), (Cos(1), 1)]),
                    (-3.0, &[(Sin(0), 1), (Sin(1), 1)]),
                ]),
                1,
                "cos(θ1+θ2)",
            ),
            (
                poly(&[
                    (2.0, &[(Sin(0), 1), (Cos(1), 1)]),
                    (2.0, &[(Cos(0), 1), (Sin(1), 1)]),
                ]),
                1,
                "sin(θ1+θ2)",
            ),
            (
                poly(&[
                    (2.0, &[(Cos(0), 1), (Cos(1), 1)]),
                    (2.0, &[(Sin(0), 1), (Sin(1), 1)]),
                ]),
                1,
                "cos(θ1−θ2)",
            ),
            (
                poly(&[
                    (1.5, &[(Qd(0), 1), (Cos(0), 1), (Cos(1), 1), (Cos(2), 1)]),
                    (-1.5, &[(Qd(0), 1), (Sin(0), 1), (Sin(1), 1), (Cos(2), 1)]),
                    (-1.5, &[(Qd(0), 1), (Sin(0), 1), (Cos(1), 1), (Sin(2), 1)]),
                    (-1.5, &[(Qd(0), 1), (Cos(0), 1), (Sin(1), 1), (Sin(2), 1)]),
                ]),
                1,
                "cos(θ1+θ2+θ3)",
            ),
            // Unequal coefficients stay apart.
            (
                poly(&[
                    (3.0, &[(Cos(0), 1), (Cos(1), 1)]),
                    (-2.0, &[(Sin(0), 1), (Sin(1), 1)]),
                ]),
                2,
                "",
            ),
        ];
        for (p, count, printed) in cases {
            let t = combined(&p);
            assert_eq!(t.len(), count, "{p:?} → {t:?}");
            let text = crate::equations::poly_string(&p, false, 6, &[]);
            assert!(text.contains(printed), "{text}");
            let want = p.eval(&|v| match v {
                Sin(i) => q[i as usize].sin(),
                Cos(i) => q[i as usize].cos(),
                Qd(i) => q[i as usize] * 0.3,
                _ => 1.7,
            });
            assert!((eval(&t, &q) - want).abs() < 1e-12);
        }
    }
}
