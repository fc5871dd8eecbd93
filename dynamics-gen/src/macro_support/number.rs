//! Numbers in the macros: integer or float literals, combined by constant arithmetic
//! (`+ - * /`, unary `-`, parentheses) over a closed list of named constants.
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := '-' unary | '+' unary | primary
//! primary := INT | FLOAT | CONSTANT | '(' expr ')'
//! ```
//!
//! Evaluated in `f64`, left to right, like Rust's own constant folding of the same expression;
//! a division by zero or a non-finite result is an error.

use proc_macro2::{Delimiter, Ident, TokenStream, TokenTree};

/// The named constants a number may use: the `core::f64::consts` of the same name.
pub const CONSTANTS: &[(&str, f64)] = &[
    ("PI", core::f64::consts::PI),
    ("TAU", core::f64::consts::TAU),
    ("FRAC_PI_2", core::f64::consts::FRAC_PI_2),
    ("FRAC_PI_3", core::f64::consts::FRAC_PI_3),
    ("FRAC_PI_4", core::f64::consts::FRAC_PI_4),
    ("FRAC_PI_6", core::f64::consts::FRAC_PI_6),
    ("FRAC_PI_8", core::f64::consts::FRAC_PI_8),
    ("FRAC_1_PI", core::f64::consts::FRAC_1_PI),
    ("FRAC_2_PI", core::f64::consts::FRAC_2_PI),
    ("SQRT_2", core::f64::consts::SQRT_2),
    ("FRAC_1_SQRT_2", core::f64::consts::FRAC_1_SQRT_2),
    ("E", core::f64::consts::E),
];

/// The value of the named constant `name`, if it is one of [`CONSTANTS`].
pub fn constant(name: &str) -> Option<f64> {
    CONSTANTS.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
}

/// What a number may be, for messages.
pub fn allowed() -> String {
    let names: Vec<&str> = CONSTANTS.iter().map(|(n, _)| *n).collect();
    format!(
        "a number is an integer or float literal, or constant arithmetic (+ - * /, parentheses) over literals and the constants {}",
        names.join(", ")
    )
}

/// Evaluates the tokens of one number.
pub fn evaluate(tokens: &[TokenTree]) -> syn::Result<f64> {
    let stream: TokenStream = tokens.iter().cloned().collect();
    if tokens.is_empty() {
        return Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            format!("expected a number; {}", allowed()),
        ));
    }
    let mut p = Parser { tokens, pos: 0 };
    let x = p.expr()?;
    if let Some(t) = p.peek() {
        return Err(syn::Error::new(
            t.span(),
            format!("unexpected `{t}` in a number; {}", allowed()),
        ));
    }
    if !x.is_finite() {
        return Err(syn::Error::new_spanned(
            stream,
            format!("this number is not finite ({x})"),
        ));
    }
    Ok(x)
}

struct Parser<'a> {
    tokens: &'a [TokenTree],
    pos: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&TokenTree> {
        self.tokens.get(self.pos)
    }

    fn punct(&self) -> Option<char> {
        match self.peek() {
            Some(TokenTree::Punct(p)) => Some(p.as_char()),
            _ => None,
        }
    }

    fn expr(&mut self) -> syn::Result<f64> {
        let mut x = self.term()?;
        while let Some(op @ ('+' | '-')) = self.punct() {
            self.pos += 1;
            let y = self.term()?;
            x = if op == '+' { x + y } else { x - y };
        }
        Ok(x)
    }

    fn term(&mut self) -> syn::Result<f64> {
        let mut x = self.unary()?;
        while let Some(op @ ('*' | '/')) = self.punct() {
            let op_token = self.tokens[self.pos].clone();
            self.pos += 1;
            let y = self.unary()?;
            if op == '/' {
                if y == 0.0 {
                    return Err(syn::Error::new(op_token.span(), "division by zero"));
                }
                x /= y;
            } else {
                x *= y;
            }
        }
        Ok(x)
    }

    fn unary(&mut self) -> syn::Result<f64> {
        match self.punct() {
            Some('-') => {
                self.pos += 1;
                Ok(-self.unary()?)
            }
            Some('+') => {
                self.pos += 1;
                self.unary()
            }
            _ => self.primary(),
        }
    }

    fn primary(&mut self) -> syn::Result<f64> {
        let Some(t) = self.peek().cloned() else {
            let span = self
                .tokens
                .last()
                .map_or_else(proc_macro2::Span::call_site, TokenTree::span);
            return Err(syn::Error::new(
                span,
                format!("the number ends too early; {}", allowed()),
            ));
        };
        self.pos += 1;
        match &t {
            TokenTree::Literal(lit) => literal(lit),
            TokenTree::Ident(id) => ident(id),
            TokenTree::Group(g) if g.delimiter() == Delimiter::Parenthesis => {
                let inner: Vec<TokenTree> = g.stream().into_iter().collect();
                if inner.is_empty() {
                    return Err(syn::Error::new(g.span(), "empty parentheses in a number"));
                }
                evaluate(&inner)
            }
            _ => Err(syn::Error::new(
                t.span(),
                format!("expected a number, found `{t}`; {}", allowed()),
            )),
        }
    }
}

fn ident(id: &Ident) -> syn::Result<f64> {
    let name = id.to_string();
    constant(&name).ok_or_else(|| {
        let hint = match name.as_str() {
            "pi" | "Pi" => " (did you mean `PI`?)",
            "tau" => " (did you mean `TAU`?)",
            _ => "",
        };
        syn::Error::new(
            id.span(),
            format!("unknown constant `{name}`{hint}; {}", allowed()),
        )
    })
}

fn literal(lit: &proc_macro2::Literal) -> syn::Result<f64> {
    match syn::Lit::new(lit.clone()) {
        syn::Lit::Int(i) if i.suffix().is_empty() => i
            .base10_digits()
            .parse::<f64>()
            .map_err(|e| syn::Error::new(lit.span(), format!("cannot read this integer: {e}"))),
        syn::Lit::Float(f) if f.suffix().is_empty() || f.suffix() == "f64" => f
            .base10_digits()
            .parse::<f64>()
            .map_err(|e| syn::Error::new(lit.span(), format!("cannot read this float: {e}"))),
        syn::Lit::Str(_) => Err(syn::Error::new(
            lit.span(),
            format!("expected a number, found a string; {}", allowed()),
        )),
        _ => Err(syn::Error::new(
            lit.span(),
            format!(
                "expected a number, found `{lit}`; {} (no type suffix)",
                allowed()
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    fn eval(ts: TokenStream) -> syn::Result<f64> {
        evaluate(&ts.into_iter().collect::<Vec<_>>())
    }

    #[test]
    fn arithmetic_follows_rust_precedence() {
        assert_eq!(eval(quote!(1 + 2 * 3)).unwrap(), 7.0);
        assert_eq!(eval(quote!((1 + 2) * 3)).unwrap(), 9.0);
        assert_eq!(eval(quote!(-2 - -3)).unwrap(), 1.0);
        assert_eq!(eval(quote!(8 / 2 / 2)).unwrap(), 2.0);
        assert_eq!(eval(quote!(1e-3)).unwrap(), 1e-3);
        assert_eq!(eval(quote!(0.089159)).unwrap(), 0.089159);
        assert_eq!(eval(quote!(PI / 2)).unwrap(), core::f64::consts::PI / 2.0);
        assert_eq!(
            eval(quote!(-FRAC_PI_2)).unwrap(),
            -core::f64::consts::FRAC_PI_2
        );
    }

    #[test]
    fn errors_say_what_is_allowed() {
        let e = eval(quote!(2 * pi)).unwrap_err().to_string();
        assert!(
            e.contains("unknown constant `pi`") && e.contains("PI, TAU"),
            "{e}"
        );
        let e = eval(quote!(1 / 0)).unwrap_err().to_string();
        assert!(e.contains("division by zero"), "{e}");
        let e = eval(quote!(1 +)).unwrap_err().to_string();
        assert!(e.contains("ends too early"), "{e}");
        let e = eval(quote!(1u8)).unwrap_err().to_string();
        assert!(e.contains("no type suffix"), "{e}");
        let e = eval(quote!(1 2)).unwrap_err().to_string();
        assert!(e.contains("unexpected `2`"), "{e}");
    }
}
