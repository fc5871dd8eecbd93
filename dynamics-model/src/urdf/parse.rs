//! Reading the XML with `urdf-rs`, and turning its errors into [`ModelError::Parse`] with a
//! line and column in the user's file.
//!
//! `urdf-rs` reads in two stages: an XML parser (whose errors carry `Line: L, Column: C` of
//! the original text) and a serde pass over a re-serialised copy (whose positions mean
//! nothing to the user). For the second kind the position is found by searching the user's
//! text for the value or element the message quotes; when nothing is found, line and column
//! are 0 and the message stands alone.

use super::{strip, xml_scan};
use crate::error::ModelError;

/// Parses `text` with `urdf_rs::read_from_string`; errors name `file` and, where they can
/// be found, the line and column.
pub fn read(text: &str, file: &str) -> Result<urdf_rs::Robot, ModelError> {
    let parse_error = |line, column, message: String| ModelError::Parse {
        file: file.to_string(),
        line,
        column,
        message,
    };
    let root = xml_scan::scan(text).map_err(|(offset, message)| {
        let (line, column) = line_column(text, offset);
        parse_error(line, column, format!("malformed XML: {message}"))
    })?;
    if root.name != "robot" {
        let (line, column) = line_column(text, root.offset);
        return Err(parse_error(
            line,
            column,
            format!(
                "the root element is <{}>, not <robot>: this is not a URDF file",
                root.name
            ),
        ));
    }
    xml_scan::check_urdf(&root).map_err(|(offset, message)| {
        let (line, column) = line_column(text, offset);
        parse_error(line, column, message)
    })?;
    // urdf-rs and its XML back ends are not known to panic on malformed input, but they were
    // not written with hostile input in mind; a panic must not take down a build script or
    // the CLI, so it is caught here as a last resort and reported as a parse error.
    // The elements the loader does not read are blanked out first (lines and columns kept).
    let text = &strip::dynamics_only(text, &root);
    let result = std::panic::catch_unwind(|| urdf_rs::read_from_string(text));
    match result {
        Ok(Ok(robot)) => Ok(robot),
        Ok(Err(e)) => {
            let message = e.to_string();
            let (line, column) = position(text, &message).unwrap_or((0, 0));
            Err(parse_error(line, column, tidy(&message)))
        }
        Err(_) => Err(parse_error(
            0,
            0,
            "the URDF parser (urdf-rs) failed on this file; check that it is well-formed XML"
                .into(),
        )),
    }
}

/// The 1-based (line, column) of byte `offset` in `text` (column in characters).
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

/// The position an error message points at: `Line: L, Column: C` from the XML parser, else
/// the only occurrence in `text` of a value the message quotes (`[..]`, `(..)` or
/// backticks) or of the element it names.
fn position(text: &str, message: &str) -> Option<(usize, usize)> {
    if let Some(p) = xml_parser_position(message) {
        return Some(p);
    }
    for (open, close) in [('[', ']'), ('(', ')'), ('`', '`'), ('"', '"')] {
        for quoted in quoted_parts(message, open, close) {
            let quoted = quoted.trim();
            if quoted.is_empty() {
                continue;
            }
            for needle in [
                format!("\"{quoted}\""),
                format!("'{quoted}'"),
                format!("<{quoted}"),
            ] {
                // Only a value found once says where the problem is.
                if let (Some(i), 1) = (text.find(&needle), text.matches(&needle).count()) {
                    return Some(line_column(text, i));
                }
            }
        }
    }
    None
}

/// `Line: 12, Column: 7` in a RustyXML message.
fn xml_parser_position(message: &str) -> Option<(usize, usize)> {
    let number_after = |key: &str| -> Option<usize> {
        let i = message.find(key)? + key.len();
        let digits: String = message[i..]
            .trim_start()
            .chars()
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse().ok()
    };
    Some((number_after("Line:")?, number_after("Column:")?))
}

/// The parts of `message` between `open` and `close`.
fn quoted_parts(message: &str, open: char, close: char) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = message;
    while let Some(i) = rest.find(open) {
        let after = &rest[i + open.len_utf8()..];
        let Some(j) = after.find(close) else { break };
        out.push(&after[..j]);
        rest = &after[j + close.len_utf8()..];
    }
    out
}

/// Drops the XML parser's own position prefix (the position is in the error's fields).
fn tidy(message: &str) -> String {
    let m = message.trim();
    if let (Some(_), Some(i)) = (xml_parser_position(m), m.find("Reason:")) {
        return format!("malformed XML: {}", m[i + "Reason:".len()..].trim());
    }
    m.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_one_based() {
        assert_eq!(line_column("ab\ncd<x>", 5), (2, 3));
        assert_eq!(line_column("é<x>", 2), (1, 2));
    }

    #[test]
    fn root_must_be_robot() {
        let e = read("<?xml version=\"1.0\"?>\n<sdf/>", "f.sdf").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("f.sdf:2:1: the root element is <sdf>"),
            "{e}"
        );
    }
}
