//! Reading the XML with `urdf-rs`, and turning its errors into [`ModelError::Parse`] with a
//! line and column in the user's file.
//!
//! `urdf-rs` reads in two stages: an XML parser (whose errors carry `Line: L, Column: C` of
//! the original text) and a serde pass over a re-serialised copy (whose positions mean
//! nothing to the user). For the second kind the position is found by searching the user's
//! text for the value or element the message quotes; when nothing is found, line and column
//! are 0 and the message stands alone.

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
    if text.trim().is_empty() {
        return Err(parse_error(
            1,
            1,
            "the file is empty; a URDF file holds one <robot> element".into(),
        ));
    }
    if !has_robot_root(text) {
        let (line, column) = first_element(text).unwrap_or((1, 1));
        return Err(parse_error(
            line,
            column,
            "the root element is not <robot>: this is not a URDF file".into(),
        ));
    }
    // urdf-rs and its XML back ends are not known to panic on malformed input, but they were
    // not written with hostile input in mind; a panic must not take down a build script or
    // the CLI, so it is caught here as a last resort and reported as a parse error.
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

/// Whether the first element of `text` (after the prolog and comments) is `<robot`.
fn has_robot_root(text: &str) -> bool {
    match first_element(text) {
        Some((line, column)) => {
            let offset = offset_of(text, line, column);
            let rest = &text[offset..];
            rest.starts_with("<robot")
                && rest[6..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_whitespace() || c == '>' || c == '/')
        }
        // No element at all: let the XML parser say what is wrong.
        None => true,
    }
}

/// The 1-based line and column of the first start tag (skipping `<?…?>`, `<!…>`).
fn first_element(text: &str) -> Option<(usize, usize)> {
    let mut rest = text;
    let mut offset = 0;
    loop {
        let i = rest.find('<')?;
        let after = &rest[i + 1..];
        let skip = if after.starts_with("!--") {
            after.find("-->").map(|e| e + 3)
        } else if after.starts_with('?') || after.starts_with('!') {
            after.find('>').map(|e| e + 1)
        } else {
            return Some(line_column(text, offset + i));
        };
        let skip = skip?;
        offset += i + 1 + skip;
        rest = &text[offset..];
    }
}

/// The 1-based (line, column) of byte `offset` in `text` (column in characters).
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

/// The byte offset of the 1-based (line, column) found by [`line_column`].
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let line_start = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum::<usize>();
    let in_line = text[line_start..]
        .char_indices()
        .nth(column.saturating_sub(1))
        .map_or(text.len() - line_start, |(i, _)| i);
    line_start + in_line
}

/// The position an error message points at: `Line: L, Column: C` from the XML parser, else
/// the first occurrence in `text` of a value the message quotes (`[..]`, `(..)` or
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
                if let Some(i) = text.find(&needle) {
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
        let text = "ab\ncd<x>";
        assert_eq!(line_column(text, 5), (2, 3));
        assert_eq!(offset_of(text, 2, 3), 5);
        assert_eq!(
            first_element("<?xml version='1.0'?>\n<!-- c -->\n <robot/>"),
            Some((3, 2))
        );
    }

    #[test]
    fn root_must_be_robot() {
        assert!(has_robot_root("<?xml version=\"1.0\"?><robot name=\"r\"/>"));
        assert!(!has_robot_root("<robots/>"));
        assert!(!has_robot_root("<sdf/>"));
    }
}
