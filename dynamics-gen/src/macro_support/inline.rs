//! `robot! { … }`: the inline robot, read into the TOML format's document and built by the
//! TOML loader, so that both front ends share one meaning of every key.
//!
//! Trees and the base follow the TOML keys too:
//!
//! ```text
//! base pelvis { floating: true, mass: 5, inertia: [..], com: [..] },  // [base]: name, then
//!                                  // `floating` and a link's inertial keys and `body` blocks
//! joint revolute torso_yaw { .., link torso { .. } },
//! joint revolute left_shoulder { parent: torso, .. },   // the link it hangs from (a name or
//!                                  // a string); default: the previous joint's link
//! end_effector hand { parent: left_forearm, home: { .. } },  // default: the last joint's link
//! frame left_foot { parent: left_shin, home: { xyz: [0, 0, -0.3] } },  // named frames, any number
//! ```
//!
//! Each key is checked here (known, not repeated, of the right kind, with its tokens
//! recorded in a [`SpanMap`]); the numbers, array lengths and physics are then checked by
//! the model ([`dynamics_model::toml_format`] and [`dynamics_model::validate`]), whose errors
//! name a subject and a field that the span map turns back into tokens.

use super::schema::{self, Type, BODY_KEYS, HOME, JOINT_KEYS, ROBOT_KEYS, SHAPES};
use super::spans::{Part, SpanMap};
use super::value::{parse_entries, parse_value, split_commas, Entry, Errors, Kind, Value};
use dynamics_model::validate::{check_home, check_screw};
use dynamics_model::{Invalid, JointKind, ModelError, Robot, Subject};
use nalgebra::{Matrix4, Vector6};
use proc_macro2::{Delimiter, Ident, TokenStream, TokenTree};
use quote::ToTokens;
use syn::parse::{ParseStream, Parser};
use toml::{Table, Value as Toml};

/// The head of the macro: `#[attrs] VIS struct NAME;`.
pub struct Head {
    /// Outer attributes (doc comments, derives).
    pub attrs: Vec<syn::Attribute>,
    /// The struct's visibility.
    pub vis: syn::Visibility,
    /// The struct's name.
    pub ident: Ident,
}

/// The parsed macro: its head and the robot (or the errors).
pub struct Inline {
    /// `#[attrs] VIS struct NAME;`.
    pub head: Head,
    /// The robot as written and the span of every field, and the generation options.
    pub robot: Result<(Robot, Generation), syn::Error>,
}

/// The keys of `robot!` that are generation options rather than parts of the robot.
#[derive(Clone, Debug, Default)]
pub struct Generation {
    /// `method: newton_euler | lagrangian`.
    pub method: crate::Method,
    /// `runtime_parameters: true`.
    pub runtime_parameters: bool,
    /// `payload_link: LINK` (checked against the robot's links).
    pub payload_link: Option<String>,
    /// `cpu_dispatch: false` (default `true`).
    pub no_cpu_dispatch: bool,
    /// `sin_cos_variants: true` (default `false`).
    pub sin_cos_variants: bool,
}

/// One item of a block: `key: value` or `keyword ARGS { … }`.
enum Item {
    Entry(Entry),
    Block(Block),
}

/// `keyword ARGS { items }`.
struct Block {
    keyword: Ident,
    args: Vec<TokenTree>,
    items: Vec<Item>,
    /// `keyword ARGS`.
    header: TokenStream,
}

const BLOCKS: &[&str] = &["joint", "link", "body", "end_effector", "frame", "base"];

/// `parent: LINK` of a joint and of the end effector (the TOML `parent`).
const PARENT: (&str, Type) = ("parent", Type::Name);

/// The prefix of the base's fields in the span map (under [`Part::Robot`]).
const BASE: &str = "base.";

/// Parses the whole macro input.
pub fn parse(input: TokenStream) -> syn::Result<Inline> {
    let (head, rest) = (|input: ParseStream<'_>| {
        let attrs = input.call(syn::Attribute::parse_outer)?;
        let vis: syn::Visibility = input.parse()?;
        input.parse::<syn::Token![struct]>()?;
        let ident: Ident = input.parse()?;
        input.parse::<syn::Token![;]>()?;
        let rest: TokenStream = input.parse()?;
        Ok((Head { attrs, vis, ident }, rest))
    })
    .parse2(input)
    .map_err(|e| {
        let mut err = syn::Error::new(
            e.span(),
            "a robot! starts with the struct to define: `pub struct Name;`",
        );
        err.combine(e);
        err
    })?;
    let robot = build(&head.ident, rest);
    Ok(Inline { head, robot })
}

/// Reads the items after the head and builds the robot.
fn build(ident: &Ident, rest: TokenStream) -> Result<(Robot, Generation), syn::Error> {
    let mut errors = Errors::default();
    let mut spans = SpanMap::new(ident.to_token_stream());
    let items = parse_items(rest, &mut errors);
    let mut doc = Table::new();
    let mut joints = Vec::new();
    let mut end_effector: Option<Table> = None;
    let mut frames: Vec<Toml> = Vec::new();
    let mut base: Option<Table> = None;
    let mut seen = Vec::new();
    let mut early = Vec::new();
    let mut generation = Generation::default();
    let mut payload_tokens: Option<TokenStream> = None;
    let mut runtime_tokens: Option<TokenStream> = None;
    for item in items {
        match item {
            Item::Entry(e) => {
                let Some(ty) = key_type(&e, ROBOT_KEYS, &mut seen, "the robot", &mut errors)
                else {
                    continue;
                };
                spans.insert(Part::Robot, e.key.to_string(), e.tokens.clone());
                let v = to_toml(&e.value, ty, &mut errors);
                if e.key == "method" {
                    // A generation option, not part of the robot: `newton_euler` or `lagrangian`.
                    if let Some(Toml::String(s)) = v {
                        match s.parse() {
                            Ok(m) => generation.method = m,
                            Err(_) => errors.at(
                                &e.tokens,
                                format!("unknown method `{s}`: the methods are `newton_euler` (the default) and `lagrangian`"),
                            ),
                        }
                    }
                } else if e.key == "runtime_parameters" {
                    match v {
                        Some(Toml::String(s)) if s == "true" || s == "false" => {
                            generation.runtime_parameters = s == "true";
                            runtime_tokens = Some(e.tokens.clone());
                        }
                        Some(_) => errors.at(
                            &e.tokens,
                            "`runtime_parameters` is `true` (gravity and a payload become fields of the struct, read at run time) or `false` (the default)",
                        ),
                        None => {}
                    }
                } else if e.key == "cpu_dispatch" {
                    match v {
                        Some(Toml::String(s)) if s == "true" || s == "false" => {
                            generation.no_cpu_dispatch = s == "false";
                        }
                        Some(_) => errors.at(
                            &e.tokens,
                            "`cpu_dispatch` is `true` (the default: on x86-64 copies of each function compiled for AVX-512 and for AVX2, chosen at run time) or `false` (one copy, no `unsafe`)",
                        ),
                        None => {}
                    }
                } else if e.key == "sin_cos_variants" {
                    match v {
                        Some(Toml::String(s)) if s == "true" || s == "false" => {
                            generation.sin_cos_variants = s == "true";
                        }
                        Some(_) => errors.at(
                            &e.tokens,
                            "`sin_cos_variants` is `true` (also a `*_from_sin_cos` variant of each function that takes the joints' sines and cosines, and `sin_cos(q)`) or `false` (the default)",
                        ),
                        None => {}
                    }
                } else if e.key == "payload_link" {
                    if let Some(Toml::String(s)) = v {
                        generation.payload_link = Some(s);
                        payload_tokens = Some(e.tokens.clone());
                    }
                } else if let Some(v) = v {
                    doc.insert(e.key.to_string(), v);
                }
            }
            Item::Block(b) => match b.keyword.to_string().as_str() {
                "joint" => {
                    let i = joints.len();
                    joints.push(Toml::Table(joint(i, b, &mut spans, &mut early, &mut errors)));
                }
                "end_effector" => {
                    if end_effector.is_some() {
                        errors.at(&b.header, "duplicate `end_effector`: a robot has one end-effector frame");
                        continue;
                    }
                    end_effector = Some(frame_table(b, false, &mut spans, &mut errors));
                }
                "frame" => {
                    let t = frame_table(b, true, &mut spans, &mut errors);
                    frames.push(Toml::Table(t));
                }
                "base" => {
                    if base.is_some() {
                        errors.at(&b.header, "duplicate `base`: a robot has one base");
                        continue;
                    }
                    base = Some(base_table(b, &mut spans, &mut errors));
                }
                _ => errors.at(
                    &b.keyword,
                    format!(
                        "a `{}` block goes inside a joint; at the top level are `joint`, `base`, `end_effector`, `frame` and the keys {}",
                        b.keyword,
                        schema::names(ROBOT_KEYS)
                    ),
                ),
            },
        }
    }
    if !doc.contains_key("name") {
        doc.insert("name".into(), Toml::String(ident.to_string()));
    }
    let base_name = base
        .as_ref()
        .and_then(|b| b.get("name"))
        .and_then(Toml::as_str)
        .unwrap_or("base")
        .to_string();
    let base_keys: Vec<String> = base.iter().flat_map(|b| b.keys().cloned()).collect();
    if let Some(b) = base {
        doc.insert("base".into(), Toml::Table(b));
    }
    doc.insert("joint".into(), Toml::Array(joints));
    if let Some(ee) = end_effector {
        doc.insert("end_effector".into(), Toml::Table(ee));
    }
    if !frames.is_empty() {
        doc.insert("frame".into(), Toml::Array(frames));
    }
    if errors.any() {
        for inv in &early {
            errors.push(spans.error(inv));
        }
    }
    let spans = Located {
        spans,
        base_name,
        base_keys,
    };
    if let Some(e) = errors.take() {
        return Err(e);
    }
    let text = toml::to_string(&Toml::Table(doc))
        .map_err(|e| syn::Error::new_spanned(ident, format!("internal error in robot!: {e}")))?;
    let file = format!("robot! {ident}");
    let robot = dynamics_model::toml_format::from_str(&text, &file)
        .map_err(|e| model_error(&spans, &e, &early, &text))?;
    if let Err(e) = robot.validate() {
        return Err(model_error(&spans, &e, &early, &text));
    }
    if let (Some(link), Some(tokens)) = (&generation.payload_link, &payload_tokens) {
        if !generation.runtime_parameters {
            return Err(syn::Error::new_spanned(
                runtime_tokens.as_ref().unwrap_or(tokens),
                "`payload_link` needs `runtime_parameters: true` (the payload is a run-time parameter)",
            ));
        }
        if !robot.links.iter().any(|l| l.name == *link) {
            let names: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
            return Err(syn::Error::new_spanned(
                tokens,
                format!(
                    "no moving link is called `{link}`: the payload link is one of {}",
                    names.join(", ")
                ),
            ));
        }
    }
    Ok((robot, generation))
}

/// The span map, and the base's name: the model names the base as a link without index,
/// whose fields are recorded under [`Part::Robot`] as `base.FIELD`.
struct Located {
    spans: SpanMap,
    base_name: String,
    /// The keys written in the base block.
    base_keys: Vec<String>,
}

impl Located {
    /// A compile error for `e`, on its field's tokens.
    fn error(&self, e: &Invalid) -> syn::Error {
        match self.base_place(e) {
            Some(tokens) => syn::Error::new_spanned(tokens, super::spans::message(e)),
            None => self.spans.error(e),
        }
    }

    /// The tokens an error about the base points at (`None` for other errors): the field,
    /// else (as for a link's `inertia` and `mass`) the keys it may have been written with,
    /// else the enclosing field, else the `base NAME` header.
    fn base_place(&self, e: &Invalid) -> Option<&TokenStream> {
        match &e.subject {
            Subject::Link { index: None, name } if *name == self.base_name => {}
            _ => return None,
        }
        let aliases: &[&str] = match e.field.as_str() {
            "inertia" => &["inertia", "spatial_inertia", "shape", "mass", "body"],
            "mass" => &["mass", "density", "shape", "inertia"],
            _ => &[],
        };
        let field = aliases
            .iter()
            .find(|a| self.base_keys.iter().any(|k| k == *a))
            .map_or_else(|| format!("{BASE}{}", e.field), |a| format!("{BASE}{a}"));
        Some(self.spans.locate(&Part::Robot, &field))
    }
}

/// A model error as compile errors on the fields it names, with the `early` checks (those
/// the model could not reach because of another error) added once.
fn model_error(spans: &Located, e: &ModelError, early: &[Invalid], text: &str) -> syn::Error {
    match e {
        ModelError::Invalid(list) => {
            let mut errors = Errors::default();
            let mut all: Vec<Invalid> = list
                .iter()
                .cloned()
                .map(|mut inv| {
                    inv.file = None;
                    inv.problem = macro_spelling(&inv.problem);
                    inv.fix = macro_spelling(&inv.fix);
                    inv
                })
                .collect();
            for inv in early {
                if !all.contains(inv) {
                    all.push(inv.clone());
                }
            }
            for inv in &all {
                errors.push(spans.error(inv));
            }
            errors
                .take()
                .unwrap_or_else(|| syn::Error::new_spanned(&spans.spans.fallback, e.to_string()))
        }
        other => syn::Error::new_spanned(
            &spans.spans.fallback,
            format!("internal error in robot! (please report): {other}\n{text}"),
        ),
    }
}

/// The TOML loader's advice about an undeclared parameter in `robot!`'s own spelling:
/// `parameters: { m2: VALUE }` where a file would write `[parameters]` and `m2 = VALUE`.
fn macro_spelling(message: &str) -> String {
    let message = message.replace(
        "declared in `[parameters]`",
        "declared in `parameters: { … }`",
    );
    let Some(end) = message.find(" = VALUE`") else {
        return message;
    };
    let name = &message[message[..end].rfind('`').map_or(0, |i| i + 1)..end];
    message
        .replace(
            &format!("add `[parameters]` with `{name} = VALUE`"),
            &format!("add `parameters: {{ {name}: VALUE }}`"),
        )
        .replace(
            &format!("add `{name} = VALUE` to `[parameters]`"),
            &format!("add `{name}: VALUE` to `parameters: {{ … }}`"),
        )
}

/// Splits a block body (or the top level) into items.
fn parse_items(tokens: TokenStream, errors: &mut Errors) -> Vec<Item> {
    let mut out = Vec::new();
    for item in split_commas(tokens) {
        let stream: TokenStream = item.iter().cloned().collect();
        match item.as_slice() {
            [TokenTree::Ident(_), TokenTree::Punct(p), ..] if p.as_char() == ':' => {
                out.extend(parse_entries(stream, errors).into_iter().map(Item::Entry));
            }
            [TokenTree::Ident(kw), args @ .., TokenTree::Group(g)]
                if g.delimiter() == Delimiter::Brace && BLOCKS.contains(&kw.to_string().as_str()) =>
            {
                let header: TokenStream = std::iter::once(TokenTree::Ident(kw.clone()))
                    .chain(args.iter().cloned())
                    .collect();
                out.push(Item::Block(Block {
                    keyword: kw.clone(),
                    args: args.to_vec(),
                    items: parse_items(g.stream(), errors),
                    header,
                }));
            }
            _ => errors.at(
                stream,
                "expected `key: value`, or a block `joint revolute NAME { … }`, `link NAME { … }`, `body NAME { … }`, `base NAME { … }` or `end_effector NAME { … }`",
            ),
        }
    }
    out
}

/// Checks an entry's key against `keys` (known, not repeated) and returns its type.
fn key_type(
    e: &Entry,
    keys: &[(&str, Type)],
    seen: &mut Vec<String>,
    place: &str,
    errors: &mut Errors,
) -> Option<Type> {
    let key = e.key.to_string();
    let Some(ty) = schema::lookup(keys, &key) else {
        errors.at(
            &e.key,
            format!(
                "unknown field `{key}` in {place}; the fields here are {}",
                schema::names(keys)
            ),
        );
        return None;
    };
    if seen.contains(&key) {
        errors.at(&e.key, format!("duplicate field `{key}` in {place}"));
        return None;
    }
    seen.push(key);
    Some(ty)
}

/// `NAME` after a block's keyword (an identifier or a string), if any.
fn block_name(args: &[TokenTree], what: &str, errors: &mut Errors) -> Option<String> {
    match args {
        [] => None,
        [one] => {
            let v = parse_value(std::slice::from_ref(one), errors);
            match v.kind {
                Kind::Word(id) => Some(id.to_string()),
                Kind::Str(s) => Some(s),
                Kind::Error => None,
                _ => {
                    errors.at(
                        one,
                        format!("expected the {what}'s name (an identifier or a string)"),
                    );
                    None
                }
            }
        }
        [_, extra, ..] => {
            errors.at(
                extra,
                format!("unexpected `{extra}`: a {what} has one name"),
            );
            None
        }
    }
}

/// One `joint KIND NAME { … }`: the joint's table, with its link.
fn joint(
    i: usize,
    b: Block,
    spans: &mut SpanMap,
    early: &mut Vec<Invalid>,
    errors: &mut Errors,
) -> Table {
    let part = Part::Joint(i);
    spans.insert(part.clone(), "", b.header.clone());
    let mut t = Table::new();
    let (kind, name_args) = match b.args.split_first() {
        Some((TokenTree::Ident(k), rest)) if k == "revolute" || k == "prismatic" => {
            (Some(k.to_string()), rest)
        }
        Some((other, _)) => {
            errors.at(
                other,
                format!("expected the joint type `revolute` or `prismatic`, found `{other}`; write `joint revolute NAME {{ … }}`"),
            );
            (None, &[][..])
        }
        None => {
            errors.at(
                &b.keyword,
                "missing joint type: write `joint revolute NAME { … }` or `joint prismatic NAME { … }`",
            );
            (None, &[][..])
        }
    };
    t.insert(
        "type".into(),
        Toml::String(kind.unwrap_or_else(|| "revolute".into())),
    );
    let name = block_name(name_args, "joint", errors).unwrap_or_else(|| format!("joint{}", i + 1));
    if let Some(n) = name_args.first() {
        spans.insert(part.clone(), "name", n.to_token_stream());
    }
    t.insert("name".into(), Toml::String(name));

    let link_part = Part::Link(i);
    let mut link = Table::new();
    let mut link_block: Option<Block> = None;
    let mut flat_bodies = Vec::new();
    let mut seen = Vec::new();
    let mut flat_link_tokens: Option<TokenStream> = None;
    for item in b.items {
        match item {
            Item::Entry(e) => {
                let key = e.key.to_string();
                let ty =
                    schema::lookup(JOINT_KEYS, &key).or_else(|| schema::lookup(&[PARENT], &key));
                if let Some(ty) = ty {
                    if seen.contains(&key) {
                        errors.at(
                            &e.key,
                            format!("duplicate field `{key}` in joint {}", i + 1),
                        );
                        continue;
                    }
                    seen.push(key.clone());
                    spans.insert(part.clone(), key.clone(), e.tokens.clone());
                    if let Some(v) = to_toml(&e.value, ty, errors) {
                        t.insert(key, v);
                    }
                } else if key == HOME.0 || schema::lookup(BODY_KEYS, &key).is_some() {
                    flat_link_tokens.get_or_insert_with(|| e.tokens.clone());
                    link_entry(
                        &link_part,
                        "",
                        e,
                        &mut link,
                        &mut seen,
                        "the joint's link",
                        spans,
                        errors,
                    );
                } else {
                    errors.at(
                        &e.key,
                        format!(
                            "unknown field `{key}` in a joint; a joint has `parent`, {}, a `link NAME {{ … }}`, or its link's keys `home`, {} and `body NAME {{ … }}` written in the joint",
                            schema::names(JOINT_KEYS),
                            schema::names(BODY_KEYS)
                        ),
                    );
                }
            }
            Item::Block(inner) => match inner.keyword.to_string().as_str() {
                "link" if link_block.is_none() => link_block = Some(inner),
                "link" => errors.at(&inner.header, "duplicate `link`: a joint moves one link"),
                "body" => flat_bodies.push(inner),
                _ => errors.at(
                    &inner.keyword,
                    format!(
                        "a `{}` block cannot be inside a joint; inside are `link` or `body` blocks",
                        inner.keyword
                    ),
                ),
            },
        }
    }
    match link_block {
        Some(lb) => {
            if let Some(flat) =
                flat_link_tokens.or_else(|| flat_bodies.first().map(|b| b.header.clone()))
            {
                errors.at(
                    flat,
                    "the joint has a `link { … }` block and also link keys written in the joint; write the link's keys in one place",
                );
            }
            spans.insert(link_part.clone(), "", lb.header.clone());
            let name = block_name(&lb.args, "link", errors);
            if let Some(n) = lb.args.first() {
                spans.insert(link_part.clone(), "name", n.to_token_stream());
            }
            if let Some(n) = name {
                link.insert("name".into(), Toml::String(n));
            }
            let mut seen = Vec::new();
            let mut bodies = Vec::new();
            for item in lb.items {
                match item {
                    Item::Entry(e) => link_entry(
                        &link_part, "", e, &mut link, &mut seen, "a link", spans, errors,
                    ),
                    Item::Block(inner) if inner.keyword == "body" => bodies.push(inner),
                    Item::Block(inner) => errors.at(
                        &inner.keyword,
                        format!(
                            "a `{}` block cannot be inside a link; inside are `body` blocks",
                            inner.keyword
                        ),
                    ),
                }
            }
            bodies_into(&link_part, "", bodies, &mut link, spans, errors);
        }
        None => bodies_into(&link_part, "", flat_bodies, &mut link, spans, errors),
    }
    if !link.contains_key("name") {
        link.insert("name".into(), Toml::String(format!("link{}", i + 1)));
    }
    if !link.contains_key("home") {
        errors.at(
            spans.locate(&link_part, "").clone(),
            format!(
                "link `{}`: missing field `home`; give `home: {{ xyz: [x, y, z], rpy: [r, p, y] }}` or a 4×4 matrix, the pose M_{{i−1,i}} of the link frame in the previous one",
                link.get("name").and_then(Toml::as_str).unwrap_or_default()
            ),
        );
    }
    if !t.contains_key("screw") && !t.contains_key("axis") {
        errors.at(
            &b.header,
            format!(
                "joint `{}`: missing field `screw`; give `screw: [ωx, ωy, ωz, vx, vy, vz]` in {{0}}, or `axis: [x, y, z]` (with `point: [x, y, z]` on it for a revolute joint)",
                t.get("name").and_then(Toml::as_str).unwrap_or_default()
            ),
        );
    }
    early_checks(i, &t, &link, early);
    t.insert("link".into(), Toml::Table(link));
    t
}

/// The model's checks of a written `screw` and 4×4 `home`, run on the numbers as written,
/// so that they are reported even when another error stops the robot from being built.
fn early_checks(i: usize, joint: &Table, link: &Table, early: &mut Vec<Invalid>) {
    let floats =
        |v: &Toml| -> Option<Vec<f64>> { v.as_array()?.iter().map(Toml::as_float).collect() };
    let name = |t: &Table| {
        t.get("name")
            .and_then(Toml::as_str)
            .unwrap_or("")
            .to_string()
    };
    let kind = match joint.get("type").and_then(Toml::as_str) {
        Some("prismatic") => JointKind::Prismatic,
        _ => JointKind::Revolute,
    };
    if let Some(s) = joint.get("screw").and_then(floats) {
        if let Ok(s) = <[f64; 6]>::try_from(s.as_slice()) {
            let subject = Subject::Joint {
                index: Some(i),
                name: name(joint),
            };
            early.extend(check_screw(subject, kind, &Vector6::from(s)));
        }
    }
    if let Some(rows) = link.get("home").and_then(Toml::as_array) {
        let rows: Option<Vec<Vec<f64>>> = rows.iter().map(floats).collect();
        if let Some(rows) = rows.filter(|r| r.len() == 4 && r.iter().all(|r| r.len() == 4)) {
            let t = Matrix4::from_fn(|r, c| rows[r][c]);
            let subject = Subject::Link {
                index: Some(i),
                name: name(link),
            };
            early.extend(check_home(subject, "home", &t));
        }
    }
}

/// A link key (`home` or an inertial key) into `table`; `prefix` is put before the field in
/// the span map: `""` for a link's own keys (which include `home`), `body[..].` for bodies,
/// `base.` and `base.body[..].` for the base's.
#[allow(clippy::too_many_arguments)]
fn link_entry(
    part: &Part,
    prefix: &str,
    e: Entry,
    table: &mut Table,
    seen: &mut Vec<String>,
    place: &str,
    spans: &mut SpanMap,
    errors: &mut Errors,
) {
    let mut keys: Vec<(&str, Type)> = BODY_KEYS.to_vec();
    if prefix.is_empty() {
        keys.insert(0, HOME);
    }
    let Some(ty) = key_type(&e, &keys, seen, place, errors) else {
        return;
    };
    let key = e.key.to_string();
    spans.insert(part.clone(), format!("{prefix}{key}"), e.tokens.clone());
    if let Kind::Table(entries) = &e.value.kind {
        for sub in entries {
            spans.insert(
                part.clone(),
                format!("{prefix}{key}.{}", sub.key),
                sub.tokens.clone(),
            );
        }
    }
    if let Some(v) = to_toml(&e.value, ty, errors) {
        table.insert(key, v);
    }
}

/// `body NAME { … }` blocks into `link.body` (or the base's `body`); `root` is put before
/// the fields in the span map (`base.` for the base).
fn bodies_into(
    part: &Part,
    root: &str,
    bodies: Vec<Block>,
    link: &mut Table,
    spans: &mut SpanMap,
    errors: &mut Errors,
) {
    if bodies.is_empty() {
        return;
    }
    spans.insert(
        part.clone(),
        format!("{root}body"),
        bodies[0].header.clone(),
    );
    let mut out = Vec::new();
    for (k, b) in bodies.into_iter().enumerate() {
        let name = block_name(&b.args, "body", errors);
        let prefix = match &name {
            Some(n) => format!("{root}body[{n}]."),
            None => format!("{root}body[{k}]."),
        };
        spans.insert(part.clone(), prefix.trim_end_matches('.'), b.header.clone());
        let mut t = Table::new();
        if let Some(n) = name {
            t.insert("name".into(), Toml::String(n));
        }
        let mut seen = Vec::new();
        for item in b.items {
            match item {
                Item::Entry(e) => {
                    link_entry(part, &prefix, e, &mut t, &mut seen, "a body", spans, errors)
                }
                Item::Block(inner) => {
                    errors.at(&inner.keyword, "a body holds keys only, no blocks")
                }
            }
        }
        out.push(Toml::Table(t));
    }
    link.insert("body".into(), Toml::Array(out));
}

/// `end_effector NAME { parent: LINK, home: … }`, or (`named`) a named frame
/// `frame NAME { parent: LINK, home: … }` (name and `parent` required).
fn frame_table(b: Block, named: bool, spans: &mut SpanMap, errors: &mut Errors) -> Table {
    let kind = if named { "frame" } else { "end effector" };
    let name = block_name(&b.args, kind, errors);
    let (part, what) = if named {
        if name.is_none() {
            errors.at(
                &b.header,
                "a frame needs a name: `frame NAME { parent: LINK, .. }`",
            );
        }
        (Part::Frame(name.clone().unwrap_or_default()), "a frame")
    } else {
        (Part::EndEffector, "the end effector")
    };
    spans.insert(part.clone(), "", b.header.clone());
    let mut t = Table::new();
    if let Some(n) = name {
        t.insert("name".into(), Toml::String(n));
    }
    let mut seen = Vec::new();
    for item in b.items {
        match item {
            Item::Entry(e) => {
                let Some(ty) = key_type(&e, &[PARENT, HOME], &mut seen, what, errors) else {
                    continue;
                };
                let key = e.key.to_string();
                spans.insert(part.clone(), key.clone(), e.tokens.clone());
                if let Kind::Table(entries) = &e.value.kind {
                    for sub in entries {
                        spans.insert(
                            part.clone(),
                            format!("{key}.{}", sub.key),
                            sub.tokens.clone(),
                        );
                    }
                }
                if let Some(v) = to_toml(&e.value, ty, errors) {
                    t.insert(key, v);
                }
            }
            Item::Block(inner) => errors.at(
                &inner.keyword,
                format!("{what} holds `parent` and `home` only"),
            ),
        }
    }
    if named && !t.contains_key("parent") {
        errors.at(
            &b.header,
            "a frame needs `parent: LINK` (the link it is attached to, or the base)",
        );
    }
    t
}

/// `base NAME { floating: true, mass: …, body NAME { … } }`: the TOML `[base]`, its fields
/// recorded under [`Part::Robot`] as `base.FIELD`.
fn base_table(b: Block, spans: &mut SpanMap, errors: &mut Errors) -> Table {
    spans.insert(Part::Robot, "base", b.header.clone());
    let mut t = Table::new();
    if let Some(n) = block_name(&b.args, "base", errors) {
        t.insert("name".into(), Toml::String(n));
    }
    if let Some(n) = b.args.first() {
        spans.insert(Part::Robot, format!("{BASE}name"), n.to_token_stream());
    }
    let mut seen = Vec::new();
    let mut bodies = Vec::new();
    for item in b.items {
        match item {
            Item::Entry(e) if e.key == "floating" => {
                if seen.iter().any(|k| k == "floating") {
                    errors.at(&e.key, "duplicate field `floating` in the base");
                    continue;
                }
                seen.push("floating".into());
                spans.insert(Part::Robot, format!("{BASE}floating"), e.tokens.clone());
                match &e.value.kind {
                    Kind::Word(w) if w == "true" || w == "false" => {
                        t.insert("floating".into(), Toml::Boolean(w == "true"));
                    }
                    Kind::Error => {}
                    _ => errors.at(
                        &e.value.tokens,
                        format!(
                            "expected `true` (a free 6-DoF joint between the world and the base) or `false`, found {}",
                            e.value.describe()
                        ),
                    ),
                }
            }
            Item::Entry(e) if schema::lookup(BODY_KEYS, &e.key.to_string()).is_none() => {
                errors.at(
                    &e.key,
                    format!(
                        "unknown field `{}` in the base; the base has `floating`, {} and `body NAME {{ … }}` blocks (its name is written after `base`)",
                        e.key,
                        schema::names(BODY_KEYS)
                    ),
                );
            }
            Item::Entry(e) => link_entry(
                &Part::Robot,
                BASE,
                e,
                &mut t,
                &mut seen,
                "the base",
                spans,
                errors,
            ),
            Item::Block(inner) if inner.keyword == "body" => bodies.push(inner),
            Item::Block(inner) => errors.at(
                &inner.keyword,
                format!(
                    "a `{}` block cannot be inside the base; inside are `body` blocks",
                    inner.keyword
                ),
            ),
        }
    }
    bodies_into(&Part::Robot, BASE, bodies, &mut t, spans, errors);
    t
}

/// A checked value of type `ty` as TOML (`None` after reporting an error).
fn to_toml(v: &Value, ty: Type, errors: &mut Errors) -> Option<Toml> {
    let floats = |xs: Vec<f64>| Toml::Array(xs.into_iter().map(Toml::Float).collect());
    // A string where a number goes is an expression over the `parameters`, which the TOML
    // loader evaluates (`dynamics_model::parameters`).
    let expression = |v: &Value| match &v.kind {
        Kind::Str(s) => Some(Toml::String(s.clone())),
        _ => None,
    };
    match ty {
        Type::Num => expression(v).or_else(|| v.number(errors).map(Toml::Float)),
        Type::Nums => match &v.kind {
            Kind::Array(items) if items.iter().any(|x| matches!(x.kind, Kind::Str(_))) => {
                let xs: Vec<Option<Toml>> = items
                    .iter()
                    .map(|x| expression(x).or_else(|| x.number(errors).map(Toml::Float)))
                    .collect();
                xs.into_iter().collect::<Option<Vec<_>>>().map(Toml::Array)
            }
            _ => v.numbers(errors).map(floats),
        },
        Type::Params => match &v.kind {
            Kind::Table(entries) => {
                let mut t = Table::new();
                for e in entries {
                    if let Some(x) = e.value.number(errors) {
                        t.insert(e.key.to_string(), Toml::Float(x));
                    }
                }
                Some(Toml::Table(t))
            }
            Kind::Error => None,
            _ => {
                errors.at(
                    &v.tokens,
                    format!("expected {}, found {}", ty.example(), v.describe()),
                );
                None
            }
        },
        Type::Matrix => v
            .matrix(errors)
            .map(|rows| Toml::Array(rows.into_iter().map(floats).collect())),
        Type::Name => v.name(errors).map(Toml::String),
        Type::About => match &v.kind {
            Kind::Word(w) if w == "com" || w == "origin" => Some(Toml::String(w.to_string())),
            Kind::Str(s) if s == "com" || s == "origin" => Some(Toml::String(s.clone())),
            Kind::Error => None,
            _ => {
                errors.at(&v.tokens, format!("expected {}", ty.example()));
                None
            }
        },
        Type::Pose | Type::Mimic => match &v.kind {
            Kind::Array(_) if ty == Type::Pose => to_toml(v, Type::Matrix, errors),
            Kind::Table(entries) => {
                let mut t = Table::new();
                let mut seen = Vec::new();
                let (keys, what) = if ty == Type::Pose {
                    (&[("xyz", Type::Nums), ("rpy", Type::Nums)][..], "a pose")
                } else {
                    (
                        &[
                            ("joint", Type::Name),
                            ("multiplier", Type::Num),
                            ("offset", Type::Num),
                        ][..],
                        "a mimic",
                    )
                };
                for e in entries {
                    let Some(ty) = key_type(e, keys, &mut seen, what, errors) else {
                        continue;
                    };
                    if let Some(x) = to_toml(&e.value, ty, errors) {
                        t.insert(e.key.to_string(), x);
                    }
                }
                if ty == Type::Mimic && !t.contains_key("joint") {
                    errors.at(
                        &v.tokens,
                        format!("a mimic needs the joint it follows: {}", ty.example()),
                    );
                    return None;
                }
                Some(Toml::Table(t))
            }
            Kind::Error => None,
            _ => {
                errors.at(
                    &v.tokens,
                    format!("expected {}, found {}", ty.example(), v.describe()),
                );
                None
            }
        },
        Type::Shape => {
            let entries = match &v.kind {
                Kind::Table(entries) if entries.len() == 1 => entries,
                Kind::Error => return None,
                _ => {
                    errors.at(&v.tokens, format!("expected {}", ty.example()));
                    return None;
                }
            };
            let e = &entries[0];
            let key = e.key.to_string();
            let Some((_, list)) = SHAPES.iter().find(|(s, _)| *s == key) else {
                errors.at(
                    &e.key,
                    format!("unknown shape `{key}`; expected {}", ty.example()),
                );
                return None;
            };
            let x = to_toml(&e.value, if *list { Type::Nums } else { Type::Num }, errors)?;
            let mut t = Table::new();
            t.insert(key, x);
            Some(Toml::Table(t))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    /// The tokens that model errors about the base's `fields` point at.
    fn base_places(block: TokenStream, fields: &[&str]) -> Vec<String> {
        let mut errors = Errors::default();
        let mut items = parse_items(block, &mut errors);
        let Some(Item::Block(b)) = items.pop() else {
            panic!("a block")
        };
        let mut spans = SpanMap::new(quote!(Fallback));
        let t = base_table(b, &mut spans, &mut errors);
        assert!(!errors.any());
        let located = Located {
            spans,
            base_name: "pelvis".into(),
            base_keys: t.keys().cloned().collect(),
        };
        fields
            .iter()
            .map(|f| {
                let subject = Subject::Link {
                    index: None,
                    name: "pelvis".into(),
                };
                let e = Invalid::new(subject, *f, "problem", "fix");
                located.base_place(&e).expect("about the base").to_string()
            })
            .collect()
    }

    #[test]
    fn errors_about_the_base_point_at_its_fields() {
        let places = base_places(
            quote! { base pelvis { floating: true, shape: { box: [1, 2, 3] }, density: 10,
            body hip { mass: 1, inertia: [1, 1, 1, 0, 0, 0] } } },
            &[
                "density",
                "inertia",
                "mass",
                "body[hip].inertia",
                "floating",
                "com",
            ],
        );
        assert_eq!(
            places,
            [
                "density : 10",
                "shape : { box : [1 , 2 , 3] }",
                "density : 10",
                "inertia : [1 , 1 , 1 , 0 , 0 , 0]",
                "floating : true",
                "base pelvis",
            ]
        );
    }
}
