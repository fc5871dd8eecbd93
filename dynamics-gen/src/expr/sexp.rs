//! S-expression text form, e.g. `(+ (* 2 in0_0) (sin in0_1))`.
//!
//! Grammar: a constant (Rust float syntax, printed as the shortest text
//! that reads back exactly), an input name, or `(op arg...)` with `op` one
//! of `+ - * / sqrt sin cos` (`(- a)` is negation). Printing expands the
//! DAG into a tree, so it is meant for small expressions and debugging.

use super::graph::ExprGraph;
use super::node::{ExprId, Input, Node};

/// Default input naming: `in{group}_{index}`.
pub fn default_input_name(x: Input) -> String {
    x.to_string()
}

/// Parses the default input naming `in{group}_{index}`.
pub fn parse_default_input_name(s: &str) -> Option<Input> {
    let (g, i) = s.strip_prefix("in")?.split_once('_')?;
    Some(Input::new(g.parse().ok()?, i.parse().ok()?))
}

impl ExprGraph {
    /// Text form of `id` with default input names (`in0_3`).
    pub fn to_sexp(&self, id: ExprId) -> String {
        self.to_sexp_with(id, &default_input_name)
    }

    /// Text form of `id`, rendering inputs with `name`.
    pub fn to_sexp_with(&self, id: ExprId, name: &dyn Fn(Input) -> String) -> String {
        let mut out = String::new();
        self.write_sexp(id, name, &mut out);
        out
    }

    fn write_sexp(&self, id: ExprId, name: &dyn Fn(Input) -> String, out: &mut String) {
        let node = *self.node(id);
        let op = match node {
            Node::Const(c) => return out.push_str(&c.to_string()),
            Node::Input(x) => return out.push_str(&name(x)),
            Node::Neg(_) => "-",
            _ => node.op_name(),
        };
        out.push('(');
        out.push_str(op);
        for o in node.operands() {
            out.push(' ');
            self.write_sexp(o, name, out);
        }
        out.push(')');
    }

    /// Parses `text` (default input names) and builds it with the
    /// simplifying constructors.
    pub fn parse_sexp(&mut self, text: &str) -> Result<ExprId, String> {
        self.parse_sexp_with(text, &parse_default_input_name)
    }

    /// Parses `text`, resolving input names with `names`. `+` and `*`
    /// accept two or more arguments (folded left to right).
    pub fn parse_sexp_with(
        &mut self,
        text: &str,
        names: &dyn Fn(&str) -> Option<Input>,
    ) -> Result<ExprId, String> {
        let spaced = text.replace('(', " ( ").replace(')', " ) ");
        let tokens: Vec<&str> = spaced.split_whitespace().collect();
        let mut pos = 0;
        let id = self.parse_expr(&tokens, &mut pos, names)?;
        if pos != tokens.len() {
            return Err(format!("trailing input at token {pos}: {:?}", tokens[pos]));
        }
        Ok(id)
    }

    fn parse_expr(
        &mut self,
        tokens: &[&str],
        pos: &mut usize,
        names: &dyn Fn(&str) -> Option<Input>,
    ) -> Result<ExprId, String> {
        let tok = *tokens.get(*pos).ok_or("unexpected end of input")?;
        *pos += 1;
        match tok {
            ")" => return Err(format!("unexpected ')' at token {}", *pos - 1)),
            "(" => {}
            atom => {
                if let Ok(v) = atom.parse::<f64>() {
                    return self
                        .try_constant(v)
                        .ok_or(format!("non-finite constant {atom}"));
                }
                return names(atom)
                    .map(|x| self.input(x))
                    .ok_or(format!("unknown input name {atom:?}"));
            }
        }
        let op = *tokens.get(*pos).ok_or("unexpected end of input")?;
        *pos += 1;
        let mut args = Vec::new();
        while tokens.get(*pos) != Some(&")") {
            if *pos >= tokens.len() {
                return Err("missing ')'".into());
            }
            args.push(self.parse_expr(tokens, pos, names)?);
        }
        *pos += 1;
        match (op, args.as_slice()) {
            ("-" | "neg", &[a]) => Ok(self.neg(a)),
            ("-", &[a, b]) => Ok(self.sub(a, b)),
            ("/", &[a, b]) => Ok(self.div(a, b)),
            ("sqrt", &[a]) => Ok(self.sqrt(a)),
            ("sin", &[a]) => Ok(self.sin(a)),
            ("cos", &[a]) => Ok(self.cos(a)),
            ("+", &[first, ref rest @ ..]) if !rest.is_empty() => {
                Ok(rest.iter().fold(first, |acc, &t| self.add(acc, t)))
            }
            ("*", &[first, ref rest @ ..]) if !rest.is_empty() => {
                Ok(rest.iter().fold(first, |acc, &t| self.mul(acc, t)))
            }
            _ => Err(format!(
                "bad operator or arity: ({op} ...) with {} arguments",
                args.len()
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prints_small_examples() {
        let mut g = ExprGraph::new();
        let q0 = g.input(Input::new(0, 0));
        let q1 = g.input(Input::new(0, 1));
        let two = g.constant(2.0);
        let a = g.mul(q0, two);
        let b = g.sin(q1);
        let f = g.add(a, b);
        assert_eq!(g.to_sexp(f), "(+ (* 2 in0_0) (sin in0_1))");
        let names = |x: Input| format!("q{}", x.index);
        assert_eq!(g.to_sexp_with(f, &names), "(+ (* 2 q0) (sin q1))");
        let n = g.neg(b);
        let h = g.constant(-0.25);
        let d = g.div(n, q0);
        let s = g.sqrt(d);
        let c = g.cos(h);
        let m = g.sub(s, c);
        assert_eq!(g.to_sexp(n), "(- (sin in0_1))");
        assert_eq!(g.to_sexp(d), "(- (/ (sin in0_1) in0_0))");
        assert_eq!(
            g.to_sexp(m),
            format!("(- (sqrt (- (/ (sin in0_1) in0_0))) {})", libm::cos(-0.25))
        );
        assert_eq!(g.to_sexp(h), "-0.25");
    }

    #[test]
    fn parses_and_round_trips() {
        let mut g = ExprGraph::new();
        let f = g.parse_sexp("(+ (* in0_0 2) (sin in0_1))").unwrap();
        assert_eq!(g.to_sexp(f), "(+ (* 2 in0_0) (sin in0_1))");
        let n = g.len();
        assert_eq!(g.parse_sexp(&g.to_sexp(f)).unwrap(), f);
        assert_eq!(g.len(), n, "re-parsing a normal form adds no nodes");
        let s = g.parse_sexp("(+ 1 2 (* 3 4 0.5))").unwrap();
        assert_eq!(g.as_const(s), Some(9.0));
        let t = g.parse_sexp("(- (- in1_2))").unwrap();
        assert_eq!(g.to_sexp(t), "in1_2");
        for bad in [
            "(+ 1)",
            "(foo 1 2)",
            "(+ 1 2",
            "x",
            "(+ 1 2))",
            ")",
            "",
            "inf",
        ] {
            assert!(g.parse_sexp(bad).is_err(), "{bad:?} should not parse");
        }
        assert_eq!(parse_default_input_name("in3_14"), Some(Input::new(3, 14)));
        assert_eq!(parse_default_input_name("in3"), None);
    }
}
