//! `robot! { … }`: the inline robot, read into the TOML format's document and built by the
//! TOML loader, so that both front ends share one meaning of every key.
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
    /// The robot as written and the span of every field.
    pub robot: Result<Robot, syn::Error>,
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

const BLOCKS: &[&str] = &["joint", "link", "body", "end_effector"];

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
fn build(ident: &Ident, rest: TokenStream) -> Result<Robot, syn::Error> {
    let mut errors = Errors::default();
    let mut spans = SpanMap::new(ident.to_token_stream());
    let items = parse_items(rest, &mut errors);
    let mut doc = Table::new();
    let mut joints = Vec::new();
    let mut end_effector: Option<Table> = None;
    let mut seen = Vec::new();
    let mut early = Vec::new();
    for item in items {
        match item {
            Item::Entry(e) => {
                let Some(ty) = key_type(&e, ROBOT_KEYS, &mut seen, "the robot", &mut errors)
                else {
                    continue;
                };
                spans.insert(Part::Robot, e.key.to_string(), e.tokens.clone());
                if let Some(v) = to_toml(&e.value, ty, &mut errors) {
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
                    end_effector = Some(end_effector_table(b, &mut spans, &mut errors));
                }
                _ => errors.at(
                    &b.keyword,
                    format!(
                        "a `{}` block goes inside a joint; at the top level are `joint`, `end_effector` and the keys {}",
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
    doc.insert("joint".into(), Toml::Array(joints));
    if let Some(ee) = end_effector {
        doc.insert("end_effector".into(), Toml::Table(ee));
    }
    if errors.any() {
        for inv in &early {
            errors.push(spans.error(inv));
        }
    }
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
    Ok(robot)
}

/// A model error as compile errors on the fields it names, with the `early` checks (those
/// the model could not reach because of another error) added once.
fn model_error(spans: &SpanMap, e: &ModelError, early: &[Invalid], text: &str) -> syn::Error {
    match e {
        ModelError::Invalid(list) => {
            let mut errors = Errors::default();
            let mut all: Vec<Invalid> = list
                .iter()
                .cloned()
                .map(|mut inv| {
                    inv.file = None;
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
                .unwrap_or_else(|| syn::Error::new_spanned(&spans.fallback, e.to_string()))
        }
        other => syn::Error::new_spanned(
            &spans.fallback,
            format!("internal error in robot! (please report): {other}\n{text}"),
        ),
    }
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
                "expected `key: value`, or a block `joint revolute NAME { … }`, `link NAME { … }`, `body NAME { … }` or `end_effector NAME { … }`",
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
                if let Some(ty) = schema::lookup(JOINT_KEYS, &key) {
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
                            "unknown field `{key}` in a joint; a joint has {}, a `link NAME {{ … }}`, or its link's keys `home`, {} and `body NAME {{ … }}` written in the joint",
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
            bodies_into(&link_part, bodies, &mut link, spans, errors);
        }
        None => bodies_into(&link_part, flat_bodies, &mut link, spans, errors),
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

/// A link key (`home` or an inertial key) into `table`; `prefix` is `body[..].` for bodies.
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

/// `body NAME { … }` blocks into `link.body`.
fn bodies_into(
    part: &Part,
    bodies: Vec<Block>,
    link: &mut Table,
    spans: &mut SpanMap,
    errors: &mut Errors,
) {
    if bodies.is_empty() {
        return;
    }
    spans.insert(part.clone(), "body", bodies[0].header.clone());
    let mut out = Vec::new();
    for (k, b) in bodies.into_iter().enumerate() {
        let name = block_name(&b.args, "body", errors);
        let prefix = match &name {
            Some(n) => format!("body[{n}]."),
            None => format!("body[{k}]."),
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

/// `end_effector NAME { home: … }`.
fn end_effector_table(b: Block, spans: &mut SpanMap, errors: &mut Errors) -> Table {
    spans.insert(Part::EndEffector, "", b.header.clone());
    let mut t = Table::new();
    if let Some(n) = block_name(&b.args, "end effector", errors) {
        t.insert("name".into(), Toml::String(n));
    }
    let mut seen = Vec::new();
    for item in b.items {
        match item {
            Item::Entry(e) => {
                let Some(ty) = key_type(&e, &[HOME], &mut seen, "the end effector", errors) else {
                    continue;
                };
                spans.insert(Part::EndEffector, "home", e.tokens.clone());
                if let Kind::Table(entries) = &e.value.kind {
                    for sub in entries {
                        spans.insert(
                            Part::EndEffector,
                            format!("home.{}", sub.key),
                            sub.tokens.clone(),
                        );
                    }
                }
                if let Some(v) = to_toml(&e.value, ty, errors) {
                    t.insert("home".into(), v);
                }
            }
            Item::Block(inner) => errors.at(&inner.keyword, "the end effector holds `home` only"),
        }
    }
    t
}

/// A checked value of type `ty` as TOML (`None` after reporting an error).
fn to_toml(v: &Value, ty: Type, errors: &mut Errors) -> Option<Toml> {
    let floats = |xs: Vec<f64>| Toml::Array(xs.into_iter().map(Toml::Float).collect());
    match ty {
        Type::Num => v.number(errors).map(Toml::Float),
        Type::Nums => v.numbers(errors).map(floats),
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
        Type::Pose => match &v.kind {
            Kind::Array(_) => to_toml(v, Type::Matrix, errors),
            Kind::Table(entries) => {
                let mut t = Table::new();
                let mut seen = Vec::new();
                let keys = [("xyz", Type::Nums), ("rpy", Type::Nums)];
                for e in entries {
                    let Some(ty) = key_type(e, &keys, &mut seen, "a pose", errors) else {
                        continue;
                    };
                    if let Some(x) = to_toml(&e.value, ty, errors) {
                        t.insert(e.key.to_string(), x);
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
