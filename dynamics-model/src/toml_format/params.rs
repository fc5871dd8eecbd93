//! `[parameters]` and expressions in a TOML robot file ([`crate::parameters`]): every string
//! where the format takes a number is an expression over the declared parameters, replaced
//! by its value before the file is read, in place (the lines of the file do not move, so
//! later errors still point at the right line). The expressions of the fields that can stay
//! symbols are kept in a [`Parameters`].

use crate::error::{Invalid, Subject};
use crate::parameters::{Expr, InertialSpec, Parameters, ScrewSpec};
use std::collections::{BTreeMap, BTreeSet};
use toml_edit::{DocumentMut, Item, Value};

/// Keys whose values are numbers (or lists, matrices or tables of them): a string there is
/// an expression. Anywhere else a string is left for the schema (text, or a type error with
/// its line).
const NUMBER_KEYS: [&str; 29] = [
    "gravity",
    "screw",
    "axis",
    "point",
    "limits",
    "velocity_limit",
    "effort_limit",
    "damping",
    "friction",
    "rotor_inertia",
    "gear_ratio",
    "multiplier",
    "offset",
    "home",
    "frame",
    "xyz",
    "rpy",
    "mass",
    "density",
    "com",
    "inertia",
    "spatial_inertia",
    "box",
    "cylinder",
    "sphere",
    "ellipsoid",
    "plate",
    "disc",
    "shape",
];

/// One step of a path into the file.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Seg {
    Key(String),
    Index(usize),
}

type Path = Vec<Seg>;

/// The file's text with every expression replaced by its value, and the parameters.
/// `None` when the file has neither `[parameters]` nor an expression (the text is used as
/// it is); a file that is not TOML is left to the schema's parser, which reports it.
pub(crate) fn substitute(text: &str) -> Result<Option<(String, Parameters)>, Vec<Invalid>> {
    let Ok(mut doc) = text.parse::<DocumentMut>() else {
        return Ok(None);
    };
    let mut errors = Vec::new();
    let mut names = Vec::new();
    let mut values = Vec::new();
    if let Some(item) = doc.get("parameters") {
        match item.as_table_like() {
            None => errors.push(Invalid::new(
                Subject::Robot,
                "parameters",
                "`parameters` is not a table",
                "declare parameters as a table: `[parameters]` with lines `m1 = 2.0`",
            )),
            Some(t) => {
                for (name, v) in t.iter() {
                    let value = v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .filter(|x| x.is_finite());
                    let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                        && name != "pi";
                    if !valid_name {
                        errors.push(Invalid::new(
                            Subject::Robot,
                            format!("parameters.{name}"),
                            format!("`{name}` cannot name a parameter"),
                            "use an ASCII letter followed by ASCII letters, digits or `_` (not `pi`, which is π)",
                        ));
                    } else if let Some(x) = value {
                        names.push(name.to_string());
                        values.push(x);
                    } else {
                        errors.push(Invalid::new(
                            Subject::Robot,
                            format!("parameters.{name}"),
                            "a parameter's value must be a finite number",
                            format!("write `{name} = 1.0` (a number, not an expression)"),
                        ));
                    }
                }
            }
        }
    }
    let mut exprs: BTreeMap<Path, Expr> = BTreeMap::new();
    let mut bad: Vec<(Path, String, String)> = Vec::new();
    for (key, item) in doc.as_table_mut().iter_mut() {
        if key.get() == "parameters" {
            continue;
        }
        let mut path = vec![Seg::Key(key.get().to_string())];
        walk_item(item, &mut path, &names, &values, &mut exprs, &mut bad);
    }
    for (path, problem, fix) in bad {
        let (subject, field) = subject_of(&doc, &path);
        errors.push(Invalid::new(subject, field, problem, fix));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    if names.is_empty() && exprs.is_empty() {
        return Ok(None);
    }
    let mut params = Parameters {
        names,
        values,
        ..Parameters::default()
    };
    classify(&doc, &exprs, &mut params);
    Ok(Some((doc.to_string(), params)))
}

fn walk_item(
    item: &mut Item,
    path: &mut Path,
    names: &[String],
    values: &[f64],
    exprs: &mut BTreeMap<Path, Expr>,
    errors: &mut Vec<(Path, String, String)>,
) {
    match item {
        Item::Value(v) => walk_value(v, path, names, values, exprs, errors),
        Item::Table(t) => {
            for (k, item) in t.iter_mut() {
                path.push(Seg::Key(k.get().to_string()));
                walk_item(item, path, names, values, exprs, errors);
                path.pop();
            }
        }
        Item::ArrayOfTables(a) => {
            for (i, t) in a.iter_mut().enumerate() {
                path.push(Seg::Index(i));
                for (k, item) in t.iter_mut() {
                    path.push(Seg::Key(k.get().to_string()));
                    walk_item(item, path, names, values, exprs, errors);
                    path.pop();
                }
                path.pop();
            }
        }
        Item::None => {}
    }
}

fn walk_value(
    v: &mut Value,
    path: &mut Path,
    names: &[String],
    values: &[f64],
    exprs: &mut BTreeMap<Path, Expr>,
    errors: &mut Vec<(Path, String, String)>,
) {
    match v {
        Value::String(s) => {
            let key = path.iter().rev().find_map(|s| match s {
                Seg::Key(k) => Some(k.as_str()),
                Seg::Index(_) => None,
            });
            if !key.is_some_and(|k| NUMBER_KEYS.contains(&k)) {
                return;
            }
            let text = s.value().clone();
            match Expr::parse(&text, names) {
                Ok(e) => {
                    let x = e.eval(values);
                    let decor = v.decor().clone();
                    *v = Value::from(x);
                    *v.decor_mut() = decor;
                    exprs.insert(path.clone(), e);
                }
                Err(why) => errors.push((
                    path.clone(),
                    format!("`\"{text}\"` is not a number or an expression over the parameters: {why}"),
                    "write a number, or an expression such as \"L1/2\" or \"m1*L1^2/12\" over the parameters declared in `[parameters]`".into(),
                )),
            }
        }
        Value::Array(a) => {
            for (i, v) in a.iter_mut().enumerate() {
                path.push(Seg::Index(i));
                walk_value(v, path, names, values, exprs, errors);
                path.pop();
            }
        }
        Value::InlineTable(t) => {
            for (k, v) in t.iter_mut() {
                path.push(Seg::Key(k.get().to_string()));
                walk_value(v, path, names, values, exprs, errors);
                path.pop();
            }
        }
        _ => {}
    }
}

/// `joint[1].link.home.xyz[0]`.
fn display(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// The link, joint or frame a path is in, and the field's path inside it.
fn subject_of(doc: &DocumentMut, path: &[Seg]) -> (Subject, String) {
    let name = |p: &[Seg]| -> Option<String> {
        let mut p = p.to_vec();
        p.push(key("name"));
        match lookup(doc, &p)? {
            ItemRef::Item(Item::Value(v)) | ItemRef::Value(v) => v.as_str().map(str::to_string),
            _ => None,
        }
    };
    let unnamed = || "(unnamed)".to_string();
    match path {
        [Seg::Key(j), Seg::Index(i), Seg::Key(l), rest @ ..] if j == "joint" && l == "link" => (
            Subject::Link {
                index: Some(*i),
                name: name(&path[..3]).unwrap_or_else(unnamed),
            },
            display(rest),
        ),
        [Seg::Key(j), Seg::Index(i), rest @ ..] if j == "joint" => (
            Subject::Joint {
                index: Some(*i),
                name: name(&path[..2]).unwrap_or_else(unnamed),
            },
            display(rest),
        ),
        [Seg::Key(f), Seg::Index(_), rest @ ..] if f == "frame" => (
            Subject::Frame(name(&path[..2]).unwrap_or_else(unnamed)),
            display(rest),
        ),
        [Seg::Key(e), rest @ ..] if e == "end_effector" => (Subject::EndEffector, display(rest)),
        _ => (Subject::Robot, display(path)),
    }
}

fn key(k: &str) -> Seg {
    Seg::Key(k.to_string())
}

/// The item at `path`, tables and inline tables alike.
fn lookup<'a>(doc: &'a DocumentMut, path: &[Seg]) -> Option<ItemRef<'a>> {
    let mut at = ItemRef::Item(doc.as_item());
    for seg in path {
        at = match (at, seg) {
            (ItemRef::Item(item), Seg::Key(k)) => match item {
                Item::Table(t) => ItemRef::Item(t.get(k)?),
                Item::Value(Value::InlineTable(t)) => ItemRef::Value(t.get(k)?),
                _ => return None,
            },
            (ItemRef::Item(item), Seg::Index(i)) => match item {
                Item::ArrayOfTables(a) => ItemRef::Table(a.get(*i)?),
                Item::Value(Value::Array(a)) => ItemRef::Value(a.get(*i)?),
                _ => return None,
            },
            (ItemRef::Table(t), Seg::Key(k)) => ItemRef::Item(t.get(k)?),
            (ItemRef::Value(Value::InlineTable(t)), Seg::Key(k)) => ItemRef::Value(t.get(k)?),
            (ItemRef::Value(Value::Array(a)), Seg::Index(i)) => ItemRef::Value(a.get(*i)?),
            _ => return None,
        };
    }
    Some(at)
}

#[derive(Clone, Copy)]
enum ItemRef<'a> {
    Item(&'a Item),
    Table(&'a toml_edit::Table),
    Value(&'a Value),
}

impl ItemRef<'_> {
    fn number(self) -> Option<f64> {
        let v = match self {
            ItemRef::Item(Item::Value(v)) | ItemRef::Value(v) => v,
            _ => return None,
        };
        v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
    }

    fn has(self, k: &str) -> bool {
        match self {
            ItemRef::Item(Item::Table(t)) | ItemRef::Table(t) => t.contains_key(k),
            ItemRef::Item(Item::Value(Value::InlineTable(t)))
            | ItemRef::Value(Value::InlineTable(t)) => t.contains_key(k),
            _ => false,
        }
    }
}

/// The expressions of the `n` entries of the array at `path` (numbers as constants); `None`
/// when it is missing or not an array of numbers.
fn entries<const N: usize>(
    doc: &DocumentMut,
    exprs: &BTreeMap<Path, Expr>,
    path: &[Seg],
) -> Option<[Expr; N]> {
    let mut out: Vec<Expr> = Vec::with_capacity(N);
    for i in 0..N {
        let mut p = path.to_vec();
        p.push(Seg::Index(i));
        out.push(match exprs.get(&p) {
            Some(e) => e.clone(),
            None => Expr::Num(lookup(doc, &p)?.number()?),
        });
    }
    lookup(doc, &[path.to_vec(), vec![Seg::Index(N)]].concat())
        .is_none()
        .then(|| out.try_into().ok())
        .flatten()
}

/// Sorts the expressions that use parameters into the fields that can stay symbols and the
/// rest.
fn classify(doc: &DocumentMut, exprs: &BTreeMap<Path, Expr>, params: &mut Parameters) {
    let mut elsewhere: BTreeMap<String, (BTreeSet<usize>, String)> = BTreeMap::new();
    let mut not_symbolic = |path: &[Seg], e: &Expr, why: &str| {
        let entry = elsewhere
            .entry(display(path))
            .or_insert_with(|| (BTreeSet::new(), why.to_string()));
        e.params(&mut entry.0);
    };
    for (path, e) in exprs {
        if e.is_constant() {
            continue;
        }
        let s: Vec<&Seg> = path.iter().collect();
        match s.as_slice() {
            [Seg::Key(g), Seg::Index(_)] if g == "gravity" => {
                match entries::<3>(doc, exprs, &[key("gravity")]) {
                    Some(g) => params.gravity = Some(g),
                    None => not_symbolic(path, e, "`gravity` is not three entries"),
                }
            }
            [Seg::Key(j), Seg::Index(i), Seg::Key(f), Seg::Index(_)]
                if j == "joint" && (f == "screw" || f == "point") =>
            {
                let joint = [key("joint"), Seg::Index(*i)];
                let spec = if f == "screw" {
                    entries::<6>(doc, exprs, &[&joint[..], &[key("screw")]].concat())
                        .map(ScrewSpec::Screw)
                } else {
                    let axis = entries::<3>(doc, exprs, &[&joint[..], &[key("axis")]].concat());
                    let point = entries::<3>(doc, exprs, &[&joint[..], &[key("point")]].concat());
                    match (axis, point) {
                        (Some(a), Some(point)) if a.iter().all(Expr::is_constant) => {
                            let a = a.map(|x| x.eval(&[]));
                            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                            (n > 0.0).then(|| ScrewSpec::Point {
                                axis: a.map(|x| x / n),
                                point,
                            })
                        }
                        _ => None,
                    }
                };
                match spec {
                    Some(spec) => {
                        params.screws.insert(*i, spec);
                    }
                    None => not_symbolic(path, e, "the joint's axis is not three numbers"),
                }
            }
            [Seg::Key(j), Seg::Index(i), Seg::Key(l), Seg::Key(h), Seg::Key(x), Seg::Index(_)]
                if j == "joint" && l == "link" && h == "home" && x == "xyz" =>
            {
                let p = [key("joint"), Seg::Index(*i), key("link"), key("home"), key("xyz")];
                match entries::<3>(doc, exprs, &p) {
                    Some(xyz) => {
                        params.homes.insert(*i, xyz);
                    }
                    None => not_symbolic(path, e, "`xyz` is not three entries"),
                }
            }
            [Seg::Key(j), Seg::Index(i), Seg::Key(l), Seg::Key(f), ..]
                if j == "joint" && l == "link" && ["mass", "com", "inertia"].contains(&f.as_str()) =>
            {
                let link = [key("joint"), Seg::Index(*i), key("link")];
                let spec = lookup(doc, &link).and_then(|t| {
                    let plain = !["frame", "density", "shape", "spatial_inertia", "body"]
                        .iter()
                        .any(|k| t.has(k));
                    let at = |k: &str| [&link[..], &[key(k)]].concat();
                    let mass = match exprs.get(&at("mass")) {
                        Some(m) => m.clone(),
                        None => Expr::Num(lookup(doc, &at("mass"))?.number()?),
                    };
                    let com = if t.has("com") {
                        entries::<3>(doc, exprs, &at("com"))?
                    } else {
                        [0.0; 3].map(Expr::Num)
                    };
                    let inertia = entries::<6>(doc, exprs, &at("inertia"))?;
                    let about_origin = matches!(
                        lookup(doc, &at("inertia_about")),
                        Some(ItemRef::Item(Item::Value(v))) | Some(ItemRef::Value(v))
                            if v.as_str() == Some("origin")
                    );
                    plain.then_some(InertialSpec {
                        mass,
                        com,
                        inertia,
                        about_origin,
                    })
                });
                match spec {
                    Some(spec) => {
                        params.inertias.insert(*i, spec);
                    }
                    None => not_symbolic(
                        path,
                        e,
                        "a link keeps its inertia symbolic only when it is given by `mass`, `inertia` and optionally `com` alone (no `frame`, `shape`, `density`, `spatial_inertia` or bodies)",
                    ),
                }
            }
            [Seg::Key(j), Seg::Index(_), Seg::Key(l), Seg::Key(h), ..]
                if j == "joint" && l == "link" && h == "home" =>
            {
                not_symbolic(
                    path,
                    e,
                    "only the translation of a home can stay symbolic: write it as `{ xyz = [..], rpy = [..] }` with numbers in `rpy`",
                )
            }
            _ => not_symbolic(
                path,
                e,
                "the closed-form equations keep parameters symbolic only in gravity, a joint's `screw` or `point`, a link's `home.xyz`, `mass`, `com` and `inertia`",
            ),
        }
    }
    params.elsewhere = elsewhere
        .into_iter()
        .map(|(path, (set, why))| (path, set, why))
        .collect();
}
