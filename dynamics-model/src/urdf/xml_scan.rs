//! A small XML scanner that finds what `urdf-rs` would reject (or silently misread) and says
//! where: badly nested tags, a missing `name`, `<parent>` or `<mass>`, and numbers that do
//! not parse (`urdf-rs` drops the words of `xyz="1 2 x"` that are not numbers).
//!
//! Only what the loader reads is checked (see [`super::strip`]): visual, collision and
//! extension elements may hold anything.
//!
//! It builds a light element tree (names, attributes, byte offsets) and checks the parts of
//! the URDF schema the loader relies on; `urdf-rs` still does the real parsing afterwards.

use super::strip::kept;

/// An element: name, attributes, children, and the byte offset of its `<`.
#[derive(Debug)]
pub struct Element<'a> {
    /// The tag name.
    pub name: &'a str,
    /// Byte offset of the `<`.
    pub offset: usize,
    /// `(name, value, byte offset of the name)`.
    pub attrs: Vec<(&'a str, &'a str, usize)>,
    /// Child elements, in order.
    pub children: Vec<Element<'a>>,
    /// Byte offset just after the element (after `/>` or its closing tag's `>`).
    pub end: usize,
}

impl<'a> Element<'a> {
    fn attr(&self, name: &str) -> Option<&'a str> {
        self.attrs.iter().find(|a| a.0 == name).map(|a| a.1)
    }

    fn child(&self, name: &str) -> Option<&Element<'a>> {
        self.children.iter().find(|c| c.name == name)
    }
}

/// The deepest nesting accepted (URDF needs 5; deeper input would only risk the stack of
/// the recursive XML back ends).
pub const MAX_DEPTH: usize = 64;

/// A problem at a byte offset.
pub type Problem = (usize, String);

/// Scans `text` into its root element.
pub fn scan(text: &str) -> Result<Element<'_>, Problem> {
    let b = text.as_bytes();
    let mut stack: Vec<Element<'_>> = Vec::new();
    let mut root: Option<Element<'_>> = None;
    let mut i = 0;
    let find = |from: usize, pat: &str| text[from..].find(pat).map(|k| from + k);
    while let Some(k) = find(i, "<") {
        let rest = &text[k..];
        if rest.starts_with("<!--") {
            i = find(k + 4, "-->")
                .ok_or((k, "comment `<!--` is never closed by `-->`".to_string()))?
                + 3;
        } else if rest.starts_with("<![CDATA[") {
            i = find(k + 9, "]]>").ok_or((k, "CDATA section is never closed".to_string()))? + 3;
        } else if rest.starts_with("<?") {
            i = find(k + 2, "?>").ok_or((k, "`<?` is never closed by `?>`".to_string()))? + 2;
        } else if rest.starts_with("<!") {
            // <!DOCTYPE …>, possibly with an internal subset in brackets.
            let mut depth = 0i32;
            let mut end = None;
            for (off, c) in rest.char_indices().skip(2) {
                match c {
                    '[' => depth += 1,
                    ']' => depth -= 1,
                    '>' if depth <= 0 => {
                        end = Some(k + off);
                        break;
                    }
                    _ => {}
                }
            }
            i = end.ok_or((k, "`<!` declaration is never closed".to_string()))? + 1;
            if let Some(e) = text[k..i].find("<!ENTITY") {
                return Err((
                    k + e,
                    "entity declarations (`<!ENTITY`) are not supported; fix: write the values \
                     out in the file (xacro's output has none)"
                        .to_string(),
                ));
            }
        } else if let Some(after) = rest.strip_prefix("</") {
            let close =
                find(k, ">").ok_or((k, "closing tag is never closed by `>`".to_string()))?;
            let name = after[..close - k - 2].trim();
            match stack.pop() {
                Some(mut open) if open.name == name => {
                    open.end = close + 1;
                    attach(&mut stack, &mut root, open, k)?;
                }
                Some(open) => {
                    return Err((
                        k,
                        format!(
                            "closing tag </{name}> does not match the open element <{}> of line {}",
                            open.name,
                            text[..open.offset].matches('\n').count() + 1
                        ),
                    ))
                }
                None => return Err((k, format!("closing tag </{name}> without an opening tag"))),
            }
            i = close + 1;
        } else {
            let (mut element, end, self_closing) = start_tag(text, b, k)?;
            element.end = end;
            if self_closing {
                attach(&mut stack, &mut root, element, k)?;
            } else if stack.len() >= MAX_DEPTH {
                return Err((k, format!("elements nested more than {MAX_DEPTH} deep")));
            } else {
                stack.push(element);
            }
            i = end;
        }
    }
    if let Some(open) = stack.pop() {
        return Err((
            open.offset,
            format!("element <{}> is never closed", open.name),
        ));
    }
    root.ok_or((0, "no XML element found".to_string()))
}

fn attach<'a>(
    stack: &mut [Element<'a>],
    root: &mut Option<Element<'a>>,
    element: Element<'a>,
    at: usize,
) -> Result<(), Problem> {
    match stack.last_mut() {
        Some(parent) => parent.children.push(element),
        None if root.is_none() => *root = Some(element),
        None => {
            return Err((
                at,
                "a second top-level element after the root element".to_string(),
            ))
        }
    }
    Ok(())
}

/// Parses the start tag at `k`: the element, the offset after it, and whether it is `<…/>`.
fn start_tag<'a>(text: &'a str, b: &[u8], k: usize) -> Result<(Element<'a>, usize, bool), Problem> {
    let is_name =
        |c: u8| !(c.is_ascii_whitespace() || matches!(c, b'/' | b'>' | b'=' | b'<' | b'"' | b'\''));
    let mut j = k + 1;
    while j < b.len() && is_name(b[j]) {
        j += 1;
    }
    if j == k + 1 {
        return Err((k, "`<` not followed by an element name".to_string()));
    }
    let mut element = Element {
        name: &text[k + 1..j],
        offset: k,
        attrs: Vec::new(),
        children: Vec::new(),
        end: k,
    };
    let tag = element.name;
    let unclosed = || (k, format!("start tag <{tag}> is never closed by `>`"));
    loop {
        while j < b.len() && b[j].is_ascii_whitespace() {
            j += 1;
        }
        match b.get(j) {
            None => return Err(unclosed()),
            Some(b'>') => return Ok((element, j + 1, false)),
            Some(b'/') if b.get(j + 1) == Some(&b'>') => return Ok((element, j + 2, true)),
            Some(_) => {}
        }
        let name_start = j;
        while j < b.len() && is_name(b[j]) {
            j += 1;
        }
        if j == name_start {
            return Err((
                j,
                format!("unexpected character in start tag <{}>", element.name),
            ));
        }
        let name = &text[name_start..j];
        while j < b.len() && b[j].is_ascii_whitespace() {
            j += 1;
        }
        if b.get(j) != Some(&b'=') {
            return Err((
                name_start,
                format!("attribute `{name}` has no `=\"value\"`"),
            ));
        }
        j += 1;
        while j < b.len() && b[j].is_ascii_whitespace() {
            j += 1;
        }
        let quote = match b.get(j) {
            Some(&q @ (b'"' | b'\'')) => q,
            _ => {
                return Err((
                    name_start,
                    format!("the value of attribute `{name}` is not quoted"),
                ))
            }
        };
        let end = text[j + 1..]
            .find(quote as char)
            .map(|e| j + 1 + e)
            .ok_or((
                name_start,
                format!("the value of attribute `{name}` is never closed"),
            ))?;
        element.attrs.push((name, &text[j + 1..end], name_start));
        j = end + 1;
    }
}

/// How many numbers an attribute of an element the loader reads holds, if it is numeric.
fn numeric(element: &str, attr: &str) -> Option<usize> {
    match (element, attr) {
        ("origin", "xyz" | "rpy") | ("axis", "xyz") => Some(3),
        ("mass", "value")
        | ("inertia", "ixx" | "ixy" | "ixz" | "iyy" | "iyz" | "izz")
        | ("limit", "lower" | "upper" | "effort" | "velocity")
        | ("dynamics", "damping" | "friction")
        | ("mimic", "multiplier" | "offset") => Some(1),
        _ => None,
    }
}

/// The attributes `urdf-rs` requires on an element the loader reads (`velocity` of
/// `<limit>` only before URDF 1.2, which defaults it).
fn required(element: &str, attr_defaults: bool) -> &'static [&'static str] {
    match element {
        "limit" if !attr_defaults => &["velocity"],
        "axis" => &["xyz"],
        "mimic" => &["joint"],
        _ => &[],
    }
}

/// Checks the URDF schema parts the loader relies on, below the `<robot>` root; the elements
/// it does not read ([`kept`]) are not checked.
pub fn check_urdf(robot: &Element<'_>) -> Result<(), Problem> {
    // URDF 1.2 and later give <limit> defaults.
    let v12 = robot.attr("version").is_some_and(|v| {
        let mut it = v.trim().split('.').map(|p| p.parse::<u32>().unwrap_or(0));
        (it.next().unwrap_or(1), it.next().unwrap_or(0)) >= (1, 2)
    });
    for e in &robot.children {
        match e.name {
            "link" => {
                let name = e
                    .attr("name")
                    .ok_or((e.offset, "<link> has no `name` attribute".to_string()))?;
                if let Some(inertial) = e.child("inertial") {
                    for (tag, attrs) in [
                        ("mass", &["value"][..]),
                        ("inertia", &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"][..]),
                    ] {
                        let c = inertial.child(tag).ok_or((
                            inertial.offset,
                            format!("link `{name}`: <inertial> has no <{tag}>"),
                        ))?;
                        if let Some(a) = attrs.iter().find(|a| c.attr(a).is_none()) {
                            return Err((
                                c.offset,
                                format!(
                                    "link `{name}`: <{tag}> has no `{a}` attribute; fix: URDF requires all of {}",
                                    attrs.join(", ")
                                ),
                            ));
                        }
                    }
                }
                check_numbers(e, name, "link", v12)?;
            }
            "joint" => {
                let name = e
                    .attr("name")
                    .ok_or((e.offset, "<joint> has no `name` attribute".to_string()))?;
                if e.attr("type").is_none() {
                    return Err((e.offset, format!("joint `{name}` has no `type` attribute")));
                }
                for tag in ["parent", "child"] {
                    let c = e.child(tag).ok_or((
                        e.offset,
                        format!("joint `{name}` has no <{tag} link=\"…\"/>"),
                    ))?;
                    if c.attr("link").is_none() {
                        return Err((
                            c.offset,
                            format!("joint `{name}`: <{tag}> has no `link` attribute"),
                        ));
                    }
                }
                check_numbers(e, name, "joint", v12)?;
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every element below `e` that the loader reads ([`kept`]) has its required attributes, and
/// every numeric attribute holds the right count of numbers.
fn check_numbers(e: &Element<'_>, owner: &str, kind: &str, v12: bool) -> Result<(), Problem> {
    for c in e.children.iter().filter(|c| kept(e.name, c.name)) {
        if let Some(a) = required(c.name, v12).iter().find(|a| c.attr(a).is_none()) {
            return Err((
                c.offset,
                format!(
                    "{kind} `{owner}`: <{}> has no `{a}` attribute; fix: add `{a}` (URDF requires it)",
                    c.name
                ),
            ));
        }
        for &(attr, value, offset) in &c.attrs {
            let Some(count) = numeric(c.name, attr) else {
                continue;
            };
            let words: Vec<&str> = value.split_whitespace().collect();
            let bad = words.iter().find(|w| w.parse::<f64>().is_err());
            if bad.is_some() || words.len() != count {
                let what = if count == 1 {
                    "one number".to_string()
                } else {
                    format!("{count} numbers")
                };
                return Err((
                    offset,
                    format!(
                        "{kind} `{owner}`: <{} {attr}=\"{value}\">: expected {what}{}",
                        c.name,
                        bad.map_or(String::new(), |w| format!(", and `{w}` is not a number"))
                    ),
                ));
            }
        }
        check_numbers(c, owner, kind, v12)?;
    }
    Ok(())
}
