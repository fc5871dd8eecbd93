//! Named parameters of a robot file: `[parameters] m1 = 2.0, L1 = 1.0` and the arithmetic
//! expressions over them that stand for numbers (`mass = "m1"`, `home = { xyz = ["L1", 0, 0] }`,
//! `inertia = ["m1*L1^2/12", 0, …]`).
//!
//! The loader evaluates every expression with the declared values, so the robot is an
//! ordinary numeric robot and every function of the generator treats it as written. It also
//! keeps the expressions of the fields the closed-form equations can carry as symbols
//! ([`Parameters`]): gravity, a joint's screw axis (`screw`, or the `point` of `axis` +
//! `point`), the translation of a link's home, and a link's `mass`, `com` and `inertia`. A
//! parameter used anywhere else is recorded with the field's path, so that asking for it as
//! a symbol is refused with the field named, never silently frozen.
//!
//! # Expressions
//!
//! ```text
//! expr  = term (("+" | "−") term)*
//! term  = unary (("*" | "/") unary)*
//! unary = "-" unary | power
//! power = atom ("^" unary)?
//! atom  = number | name | "(" expr ")"
//! ```
//! Names are the declared parameters and `pi`. Numbers are Rust's `f64` syntax (`1`, `0.5`,
//! `1e-3`).

use std::collections::{BTreeMap, BTreeSet};

/// An arithmetic expression over the parameters (indices into [`Parameters::names`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number.
    Num(f64),
    /// A parameter.
    Param(usize),
    /// `−a`.
    Neg(Box<Expr>),
    /// `a + b`.
    Add(Box<Expr>, Box<Expr>),
    /// `a − b`.
    Sub(Box<Expr>, Box<Expr>),
    /// `a · b`.
    Mul(Box<Expr>, Box<Expr>),
    /// `a / b`.
    Div(Box<Expr>, Box<Expr>),
    /// `a ^ b`.
    Pow(Box<Expr>, Box<Expr>),
}

impl Expr {
    /// The value with the parameters' `values`.
    pub fn eval(&self, values: &[f64]) -> f64 {
        match self {
            Expr::Num(x) => *x,
            Expr::Param(i) => values[*i],
            Expr::Neg(a) => -a.eval(values),
            Expr::Add(a, b) => a.eval(values) + b.eval(values),
            Expr::Sub(a, b) => a.eval(values) - b.eval(values),
            Expr::Mul(a, b) => a.eval(values) * b.eval(values),
            Expr::Div(a, b) => a.eval(values) / b.eval(values),
            Expr::Pow(a, b) => {
                let (a, b) = (a.eval(values), b.eval(values));
                if b == b.round() && b.abs() <= 64.0 {
                    a.powi(b as i32)
                } else {
                    a.powf(b)
                }
            }
        }
    }

    /// The parameters it uses.
    pub fn params(&self, out: &mut BTreeSet<usize>) {
        match self {
            Expr::Num(_) => {}
            Expr::Param(i) => {
                out.insert(*i);
            }
            Expr::Neg(a) => a.params(out),
            Expr::Add(a, b)
            | Expr::Sub(a, b)
            | Expr::Mul(a, b)
            | Expr::Div(a, b)
            | Expr::Pow(a, b) => {
                a.params(out);
                b.params(out);
            }
        }
    }

    /// The expression written out with the parameters' `names` (fully parenthesised where
    /// it matters: `-(L1 + L2)`, `m1*L1^2/12`).
    pub fn to_text(&self, names: &[String]) -> String {
        let wrap = |e: &Expr| match e {
            Expr::Num(x) if *x >= 0.0 => e.to_text(names),
            Expr::Param(_) | Expr::Pow(..) => e.to_text(names),
            _ => format!("({})", e.to_text(names)),
        };
        match self {
            Expr::Num(x) => format!("{x}"),
            Expr::Param(i) => names[*i].clone(),
            Expr::Neg(a) => format!("-{}", wrap(a)),
            Expr::Add(a, b) => format!("{} + {}", a.to_text(names), b.to_text(names)),
            Expr::Sub(a, b) => format!("{} - {}", a.to_text(names), wrap(b)),
            Expr::Mul(a, b) => format!("{}*{}", wrap(a), wrap(b)),
            Expr::Div(a, b) => format!("{}/{}", wrap(a), wrap(b)),
            Expr::Pow(a, b) => format!("{}^{}", wrap(a), wrap(b)),
        }
    }

    /// Whether it uses any parameter.
    pub fn is_constant(&self) -> bool {
        let mut s = BTreeSet::new();
        self.params(&mut s);
        s.is_empty()
    }

    /// Parses `text`, resolving names with `names` (`pi` is π). The error says what is wrong
    /// and where (a character position).
    pub fn parse(text: &str, names: &[String]) -> Result<Expr, String> {
        let tokens = tokenize(text)?;
        let mut p = Parser {
            tokens: &tokens,
            at: 0,
            names,
        };
        let e = p.expr()?;
        match p.tokens.get(p.at) {
            None => Ok(e),
            Some(t) => Err(format!("unexpected `{}` after a complete expression", t)),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Num(f64),
    Name(String),
    Op(char),
}

impl std::fmt::Display for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Token::Num(x) => write!(f, "{x}"),
            Token::Name(n) => write!(f, "{n}"),
            Token::Op(c) => write!(f, "{c}"),
        }
    }
}

fn tokenize(text: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len()
                && (chars[i].is_ascii_digit()
                    || chars[i] == '.'
                    || chars[i] == 'e'
                    || chars[i] == 'E'
                    || ((chars[i] == '+' || chars[i] == '-') && matches!(chars[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            let s: String = chars[start..i].iter().collect();
            let x: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
            out.push(Token::Num(x));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token::Name(chars[start..i].iter().collect()));
        } else if "+-*/^()".contains(c) {
            out.push(Token::Op(c));
            i += 1;
        } else {
            return Err(format!(
                "`{c}` is not part of an expression (numbers, parameter names, pi, + - * / ^ and parentheses)"
            ));
        }
    }
    if out.is_empty() {
        return Err("the expression is empty".into());
    }
    Ok(out)
}

struct Parser<'a> {
    tokens: &'a [Token],
    at: usize,
    names: &'a [String],
}

impl Parser<'_> {
    fn peek_op(&self) -> Option<char> {
        match self.tokens.get(self.at) {
            Some(Token::Op(c)) => Some(*c),
            _ => None,
        }
    }

    fn expr(&mut self) -> Result<Expr, String> {
        let mut e = self.term()?;
        while let Some(op @ ('+' | '-')) = self.peek_op() {
            self.at += 1;
            let r = self.term()?;
            e = if op == '+' {
                Expr::Add(Box::new(e), Box::new(r))
            } else {
                Expr::Sub(Box::new(e), Box::new(r))
            };
        }
        Ok(e)
    }

    fn term(&mut self) -> Result<Expr, String> {
        let mut e = self.unary()?;
        while let Some(op @ ('*' | '/')) = self.peek_op() {
            self.at += 1;
            let r = self.unary()?;
            e = if op == '*' {
                Expr::Mul(Box::new(e), Box::new(r))
            } else {
                Expr::Div(Box::new(e), Box::new(r))
            };
        }
        Ok(e)
    }

    fn unary(&mut self) -> Result<Expr, String> {
        if self.peek_op() == Some('-') {
            self.at += 1;
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        let base = self.atom()?;
        if self.peek_op() == Some('^') {
            self.at += 1;
            let exponent = self.unary()?;
            return Ok(Expr::Pow(Box::new(base), Box::new(exponent)));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Expr, String> {
        let t = self.tokens.get(self.at).cloned();
        self.at += 1;
        match t {
            Some(Token::Num(x)) => Ok(Expr::Num(x)),
            Some(Token::Name(n)) => match self.names.iter().position(|m| *m == n) {
                Some(i) => Ok(Expr::Param(i)),
                None if n == "pi" => Ok(Expr::Num(std::f64::consts::PI)),
                None if self.names.is_empty() => Err(format!(
                    "`{n}` is not a declared parameter (the file declares none: add `[parameters]` with `{n} = VALUE`)"
                )),
                None => Err(format!(
                    "`{n}` is not a declared parameter (declared: {}; or add `{n} = VALUE` to `[parameters]`)",
                    self.names.join(", ")
                )),
            },
            Some(Token::Op('(')) => {
                let e = self.expr()?;
                if self.peek_op() != Some(')') {
                    return Err("a `(` is not closed".into());
                }
                self.at += 1;
                Ok(e)
            }
            Some(t) => Err(format!("unexpected `{t}`")),
            None => Err("the expression ends early".into()),
        }
    }
}

/// How a joint's screw axis is written, with expressions.
#[derive(Clone, Debug, PartialEq)]
pub enum ScrewSpec {
    /// `screw = [ω, v]`, in {0}.
    Screw([Expr; 6]),
    /// `axis` (a number each, normalised) and `point` (expressions): `S = (ω̂, −ω̂ × point)`.
    Point {
        /// ω̂, unit.
        axis: [f64; 3],
        /// A point on the axis in {0}.
        point: [Expr; 3],
    },
}

/// A link's inertial keys (`mass`, `com`, `inertia`), with expressions.
#[derive(Clone, Debug, PartialEq)]
pub struct InertialSpec {
    /// m.
    pub mass: Expr,
    /// The centre of mass in {i}.
    pub com: [Expr; 3],
    /// `[ixx, iyy, izz, ixy, ixz, iyz]`.
    pub inertia: [Expr; 6],
    /// The inertia is about the origin of {i} (`inertia_about = "origin"`), not the centre
    /// of mass.
    pub about_origin: bool,
}

/// The named parameters of a robot and the fields written with them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Parameters {
    /// The declared names, in the file's order.
    pub names: Vec<String>,
    /// Their values.
    pub values: Vec<f64>,
    /// Gravity, when any of its entries is written with a parameter.
    pub gravity: Option<[Expr; 3]>,
    /// Joint index → its screw, when written with a parameter.
    pub screws: BTreeMap<usize, ScrewSpec>,
    /// Link index → the translation of `M_{λ(i),i}` (`home.xyz`), when written with a
    /// parameter (the rotation is the model's).
    pub homes: BTreeMap<usize, [Expr; 3]>,
    /// Link index → its inertial keys, when any is written with a parameter.
    pub inertias: BTreeMap<usize, InertialSpec>,
    /// Fields written with parameters where a parameter cannot stay a symbol: the field's
    /// path, the parameters it uses and why.
    pub elsewhere: Vec<(String, BTreeSet<usize>, String)>,
}

impl Parameters {
    /// Whether the file declared no parameter.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The index of the parameter `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        vec!["m1".into(), "L1".into()]
    }

    #[test]
    fn expressions_parse_and_evaluate() {
        let v = [2.0, 3.0];
        let cases = [
            ("m1", 2.0),
            ("-L1", -3.0),
            ("m1*L1^2/12", 1.5),
            ("(m1 + L1) * 2", 10.0),
            ("2 - -L1", 5.0),
            ("1e-3 * L1", 3e-3),
            ("L1/2 + 1.5e1", 16.5),
            ("-L1^2", -9.0),
            ("2^3^2", 512.0),
            ("pi/2", std::f64::consts::FRAC_PI_2),
        ];
        for (text, want) in cases {
            let e = Expr::parse(text, &names()).unwrap();
            assert!((e.eval(&v) - want).abs() < 1e-12, "{text}");
            let again = Expr::parse(&e.to_text(&names()), &names()).unwrap();
            assert!(
                (again.eval(&v) - want).abs() < 1e-12,
                "{text}: {}",
                e.to_text(&names())
            );
        }
    }

    #[test]
    fn bad_expressions_say_why() {
        for (text, says) in [
            ("m2", "`m2` is not a declared parameter (declared: m1, L1"),
            ("", "empty"),
            ("m1 +", "ends early"),
            ("(m1", "not closed"),
            ("m1 L1", "unexpected `L1`"),
            ("m1 % 2", "`%` is not part of an expression"),
            ("1.2.3", "`1.2.3` is not a number"),
        ] {
            let e = Expr::parse(text, &names()).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}
