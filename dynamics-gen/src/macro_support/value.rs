//! Values of the `robot!` grammar, with the tokens they came from (for error spans).
//!
//! ```text
//! value := number                      (see [`super::number`])
//!        | WORD                        (an identifier that is not a constant, e.g. `origin`)
//!        | "string"
//!        | '[' value (',' value)* ','? ']'
//!        | '{' KEY ':' value (',' KEY ':' value)* ','? '}'
//! ```

use super::number;
use proc_macro2::{Delimiter, Ident, TokenStream, TokenTree};
use quote::ToTokens;

/// A parsed value and its tokens.
#[derive(Clone, Debug)]
pub struct Value {
    /// What it is.
    pub kind: Kind,
    /// The tokens it was written as (spans of errors about it).
    pub tokens: TokenStream,
}

/// The kinds of values.
#[derive(Clone, Debug)]
pub enum Kind {
    /// A number (already evaluated).
    Number(f64),
    /// An identifier that is not a named constant.
    Word(Ident),
    /// A string literal's value.
    Str(String),
    /// `[a, b, …]`.
    Array(Vec<Value>),
    /// `{ key: value, … }`.
    Table(Vec<Entry>),
    /// A value whose error has already been reported.
    Error,
}

/// `key: value` inside a table, or an item of a block.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The key.
    pub key: Ident,
    /// The value.
    pub value: Value,
    /// The tokens of the whole entry.
    pub tokens: TokenStream,
}

/// Accumulated errors.
#[derive(Default)]
pub struct Errors(Option<syn::Error>);

impl Errors {
    /// Adds an error.
    pub fn push(&mut self, e: syn::Error) {
        match &mut self.0 {
            Some(all) => all.combine(e),
            None => self.0 = Some(e),
        }
    }

    /// Adds an error spanning `tokens`.
    pub fn at(&mut self, tokens: impl ToTokens, message: impl std::fmt::Display) {
        self.push(syn::Error::new_spanned(tokens, message));
    }

    /// Whether any error was added.
    pub fn any(&self) -> bool {
        self.0.is_some()
    }

    /// All errors, combined.
    pub fn take(self) -> Option<syn::Error> {
        self.0
    }
}

/// Splits `tokens` at top-level commas (a trailing comma is allowed).
pub fn split_commas(tokens: TokenStream) -> Vec<Vec<TokenTree>> {
    let mut out = vec![Vec::new()];
    for t in tokens {
        match &t {
            TokenTree::Punct(p) if p.as_char() == ',' => out.push(Vec::new()),
            _ => out.last_mut().expect("never empty").push(t),
        }
    }
    if out.last().is_some_and(Vec::is_empty) {
        out.pop();
    }
    out
}

/// Parses one value from its tokens; problems are added to `errors` and give [`Kind::Error`].
pub fn parse_value(tokens: &[TokenTree], errors: &mut Errors) -> Value {
    let stream: TokenStream = tokens.iter().cloned().collect();
    let kind = match tokens {
        [] => {
            errors.push(syn::Error::new(
                proc_macro2::Span::call_site(),
                "expected a value",
            ));
            Kind::Error
        }
        [TokenTree::Group(g)] if g.delimiter() == Delimiter::Bracket => Kind::Array(
            split_commas(g.stream())
                .iter()
                .map(|item| parse_value(item, errors))
                .collect(),
        ),
        [TokenTree::Group(g)] if g.delimiter() == Delimiter::Brace => {
            Kind::Table(parse_entries(g.stream(), errors))
        }
        [TokenTree::Ident(id)] if number::constant(&id.to_string()).is_none() => {
            Kind::Word(id.clone())
        }
        [TokenTree::Literal(lit)] if lit.to_string().starts_with('"') => {
            match syn::parse2::<syn::LitStr>(stream.clone()) {
                Ok(s) => Kind::Str(s.value()),
                Err(e) => {
                    errors.push(e);
                    Kind::Error
                }
            }
        }
        _ => match number::evaluate(tokens) {
            Ok(x) => Kind::Number(x),
            Err(e) => {
                errors.push(e);
                Kind::Error
            }
        },
    };
    Value {
        kind,
        tokens: stream,
    }
}

/// Parses `key: value, …` (the inside of a table).
pub fn parse_entries(tokens: TokenStream, errors: &mut Errors) -> Vec<Entry> {
    let mut out = Vec::new();
    for item in split_commas(tokens) {
        let stream: TokenStream = item.iter().cloned().collect();
        match item.as_slice() {
            [TokenTree::Ident(key), TokenTree::Punct(colon), rest @ ..]
                if colon.as_char() == ':' && !rest.is_empty() =>
            {
                out.push(Entry {
                    key: key.clone(),
                    value: parse_value(rest, errors),
                    tokens: stream,
                });
            }
            _ => errors.at(stream, "expected `key: value`"),
        }
    }
    out
}

impl Value {
    /// A short name of the value's kind, for messages.
    pub fn describe(&self) -> &'static str {
        match self.kind {
            Kind::Number(_) => "a number",
            Kind::Word(_) => "a name",
            Kind::Str(_) => "a string",
            Kind::Array(_) => "a list",
            Kind::Table(_) => "a table `{ … }`",
            Kind::Error => "an invalid value",
        }
    }

    /// As a number; a wrong kind is an error naming `what` was expected.
    pub fn number(&self, errors: &mut Errors) -> Option<f64> {
        match &self.kind {
            Kind::Number(x) => Some(*x),
            Kind::Error => None,
            Kind::Word(id) => {
                errors.at(
                    id,
                    format!("unknown constant `{id}`; {}", number::allowed()),
                );
                None
            }
            _ => {
                errors.at(
                    &self.tokens,
                    format!("expected a number, found {}", self.describe()),
                );
                None
            }
        }
    }

    /// As a list of numbers (`[a, b, …]`).
    pub fn numbers(&self, errors: &mut Errors) -> Option<Vec<f64>> {
        match &self.kind {
            Kind::Array(items) => {
                let xs: Vec<Option<f64>> = items.iter().map(|v| v.number(errors)).collect();
                xs.into_iter().collect()
            }
            Kind::Error => None,
            _ => {
                errors.at(
                    &self.tokens,
                    format!(
                        "expected a list of numbers `[a, b, …]`, found {}",
                        self.describe()
                    ),
                );
                None
            }
        }
    }

    /// As a matrix (a list of rows of numbers).
    pub fn matrix(&self, errors: &mut Errors) -> Option<Vec<Vec<f64>>> {
        match &self.kind {
            Kind::Array(rows) => {
                let rows: Vec<Option<Vec<f64>>> = rows.iter().map(|r| r.numbers(errors)).collect();
                rows.into_iter().collect()
            }
            Kind::Error => None,
            _ => {
                errors.at(
                    &self.tokens,
                    format!(
                        "expected a matrix, a list of rows `[[a, b, …], …]`, found {}",
                        self.describe()
                    ),
                );
                None
            }
        }
    }

    /// As a string or a bare name.
    pub fn name(&self, errors: &mut Errors) -> Option<String> {
        match &self.kind {
            Kind::Str(s) => Some(s.clone()),
            Kind::Word(id) => Some(id.to_string()),
            Kind::Error => None,
            _ => {
                errors.at(
                    &self.tokens,
                    format!("expected a name or a string, found {}", self.describe()),
                );
                None
            }
        }
    }
}

/// The tokens `a b` as one stream (spans from the first to the last token).
pub fn join(a: &impl ToTokens, b: &impl ToTokens) -> TokenStream {
    let mut t = a.to_token_stream();
    b.to_tokens(&mut t);
    t
}
