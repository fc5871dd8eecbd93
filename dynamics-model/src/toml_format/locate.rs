//! Which joint, link or body a byte offset of a TOML robot file falls in, so that a parse
//! error (an unknown key, a wrong type, a missing key) can name it as well as its line.
//!
//! A light scan of the text: table headers (`[[joint]]`, `[joint.link]`,
//! `[[joint.link.body]]`, `[end_effector]`, `[[frame]]`, `[base]`, `[[base.body]]`) on lines of their own, and each table's
//! `name = "…"`. It only adds context to a message, so a layout it does not recognise
//! (e.g. inline tables) simply gives none.

/// One table of the file: its header, where it starts and ends, and its `name`.
struct Section<'a> {
    header: &'a str,
    start: usize,
    name: Option<&'a str>,
}

/// A description of the table around byte `offset`, e.g.
/// ``link `forearm` of joint 2 `elbow` ``.
pub(crate) fn context(text: &str, offset: usize) -> Option<String> {
    let sections = sections(text);
    let here = sections.iter().rposition(|s| s.start <= offset)?;
    let joint_index = sections[..=here]
        .iter()
        .filter(|s| s.header == "[[joint]]")
        .count();
    let last = |header: &str| {
        sections[..=here]
            .iter()
            .rev()
            .find(|s| s.header == header)
            .and_then(|s| s.name)
    };
    let named = |what: String, name: Option<&str>| match name {
        Some(n) => format!("{what} `{n}`"),
        None => what,
    };
    let joint = || named(format!("joint {joint_index}"), last("[[joint]]"));
    let link = || named("link".into(), last("[joint.link]"));
    let s = &sections[here];
    match s.header {
        "[[joint]]" => Some(joint()),
        "[joint.link]" => Some(format!("{} of {}", link(), joint())),
        "[[joint.link.body]]" => {
            let body_index = sections[..=here]
                .iter()
                .rev()
                .take_while(|s| s.header != "[joint.link]" && s.header != "[[joint]]")
                .filter(|s| s.header == "[[joint.link.body]]")
                .count();
            Some(format!(
                "{} of the {} of {}",
                named(format!("body {body_index}"), s.name),
                link(),
                joint()
            ))
        }
        "[end_effector]" => Some("[end_effector]".into()),
        "[[frame]]" => Some(named("[[frame]]".into(), s.name)),
        "[base]" => Some(named("[base]".into(), s.name)),
        "[[base.body]]" => {
            let body_index = sections[..=here]
                .iter()
                .rev()
                .take_while(|s| s.header != "[base]")
                .filter(|s| s.header == "[[base.body]]")
                .count();
            Some(format!(
                "{} of {}",
                named(format!("body {body_index}"), s.name),
                named("[base]".into(), last("[base]"))
            ))
        }
        _ => None,
    }
}

/// The tables of `text`, in order, with a leading pseudo-section for the top level.
fn sections(text: &str) -> Vec<Section<'_>> {
    let mut out = vec![Section {
        header: "",
        start: 0,
        name: None,
    }];
    let mut start = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = strip_comment(line).trim();
        if is_header(trimmed) {
            out.push(Section {
                header: trimmed,
                start,
                name: None,
            });
        } else if let Some(name) = name_value(trimmed) {
            if let Some(last) = out.last_mut() {
                last.name.get_or_insert(name);
            }
        }
        start += line.len();
    }
    out
}

/// `line` without a trailing `# comment` (good enough for header and name lines).
fn strip_comment(line: &str) -> &str {
    match line.find('#') {
        Some(i) if !line[..i].contains('"') => &line[..i],
        _ => line,
    }
}

/// `[a.b]` or `[[a.b]]` with a plain dotted key.
fn is_header(line: &str) -> bool {
    let inner = line
        .strip_prefix("[[")
        .and_then(|l| l.strip_suffix("]]"))
        .or_else(|| line.strip_prefix('[').and_then(|l| l.strip_suffix(']')));
    inner.is_some_and(|k| {
        !k.is_empty()
            && k.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
            && k.chars().any(|c| c.is_ascii_alphabetic())
    })
}

/// The string of a `name = "…"` line.
fn name_value(line: &str) -> Option<&str> {
    let rest = line.strip_prefix("name")?.trim_start().strip_prefix('=')?;
    let rest = rest.trim_start().strip_prefix('"')?;
    rest.split('"').next()
}
