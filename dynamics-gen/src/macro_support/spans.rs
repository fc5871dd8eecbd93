//! Where each field of an inline robot was written, so that a model error
//! ([`Invalid`]: subject + field) becomes a compile error on the offending tokens.

use dynamics_model::{Invalid, Subject};
use proc_macro2::TokenStream;
use std::collections::HashMap;

/// The part of the robot a field belongs to (as [`Subject`], by position in the chain).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// Top-level keys (`gravity`, `name`).
    Robot,
    /// Joint i (0-based).
    Joint(usize),
    /// Link i (0-based).
    Link(usize),
    /// The end-effector frame.
    EndEffector,
    /// A named frame, by name.
    Frame(String),
}

impl Part {
    fn of(subject: &Subject) -> Option<Self> {
        match subject {
            Subject::Robot => Some(Part::Robot),
            Subject::Joint { index: Some(i), .. } => Some(Part::Joint(*i)),
            Subject::Link { index: Some(i), .. } => Some(Part::Link(*i)),
            Subject::EndEffector => Some(Part::EndEffector),
            Subject::Frame(name) => Some(Part::Frame(name.clone())),
            _ => None,
        }
    }
}

/// The tokens of every field, keyed by part and field path (`home`, `home.xyz`,
/// `body[tube].mass`, …, as the model names fields); the empty field is the part's header.
pub struct SpanMap {
    fields: HashMap<(Part, String), TokenStream>,
    /// Where errors with no better place go (the struct's name, or the attribute).
    pub fallback: TokenStream,
}

impl SpanMap {
    /// An empty map.
    pub fn new(fallback: TokenStream) -> Self {
        Self {
            fields: HashMap::new(),
            fallback,
        }
    }

    /// Records `tokens` as the place of `field` of `part` (the first record wins).
    pub fn insert(&mut self, part: Part, field: impl Into<String>, tokens: TokenStream) {
        self.fields.entry((part, field.into())).or_insert(tokens);
    }

    fn get(&self, part: &Part, field: &str) -> Option<&TokenStream> {
        self.fields.get(&(part.clone(), field.to_string()))
    }

    /// The tokens an error about `field` of `part` points at: the field itself, else the
    /// keys it may have been written with (`axis` for `screw`; the inertial keys for a
    /// link's `inertia`), else its enclosing field (`home` for `home.xyz`), else the header
    /// of the part (and of its joint, for a link), else the fallback.
    pub fn locate(&self, part: &Part, field: &str) -> &TokenStream {
        let aliases: &[&str] = match (part, field) {
            (Part::Joint(_), "screw") => &["screw", "axis"],
            (Part::Joint(_), "axis") => &["axis", "screw"],
            (Part::Link(_), "inertia") => &["inertia", "spatial_inertia", "shape", "mass", "body"],
            (Part::Link(_), "mass") => &["mass", "density", "shape", "inertia"],
            _ => &[],
        };
        for alias in aliases {
            if let Some(t) = self.get(part, alias) {
                return t;
            }
        }
        let mut f = field;
        loop {
            if let Some(t) = self.get(part, f) {
                return t;
            }
            match f.rfind(['.', '[']) {
                Some(i) => f = &f[..i],
                None => break,
            }
        }
        if let Some(t) = self.get(part, "") {
            return t;
        }
        if let Part::Link(i) = part {
            if let Some(t) = self.get(&Part::Joint(*i), "") {
                return t;
            }
        }
        &self.fallback
    }

    /// A compile error for `e`, on its field's tokens.
    pub fn error(&self, e: &Invalid) -> syn::Error {
        let tokens = match Part::of(&e.subject) {
            Some(part) => self.locate(&part, &e.field),
            None => &self.fallback,
        };
        syn::Error::new_spanned(tokens, message(e))
    }
}

/// The message of a model error in a compile error: subject, field, problem and fix.
pub fn message(e: &Invalid) -> String {
    let mut s = String::new();
    if let Some(file) = &e.file {
        s.push_str(file);
        s.push_str(": ");
    }
    s.push_str(&format!("{}, `{}`: {}", e.subject, e.field, e.problem));
    if !e.fix.is_empty() {
        s.push_str(&format!("\n       fix: {}", e.fix));
    }
    s
}
