//! What of a URDF file the loader reads, and the file with everything else blanked out.
//!
//! A dynamics model needs, below `<robot>`, the `<link>`s with their `<inertial>` (`<origin>`,
//! `<mass>`, `<inertia>`) and the `<joint>`s with their `<origin>`, `<parent>`, `<child>`,
//! `<axis>`, `<limit>`, `<dynamics>` and `<mimic>`. Everything else — `<visual>`,
//! `<collision>` and their geometry, materials and textures, `<gazebo>`, `<transmission>`,
//! `<calibration>`, `<safety_controller>`, extensions such as Pinocchio's `<capsule>` or
//! `<collision_checking>`, and unknown tags — is skipped, as urdfdom and Pinocchio skip what
//! they do not use. Unknown attributes are ignored.
//!
//! `urdf-rs` checks all of it (a `<texture/>` without `filename` is an error there), so the
//! text it gets has the skipped elements replaced by spaces, character for character, with
//! line breaks kept: line and column of everything that remains are those of the user's file.
//! Namespace declarations and prefixed attributes (`xmlns:xacro="…"`, `xacro:foo="…"`) on the
//! kept elements go the same way: the loader reads none, and the XML back end of `urdf-rs`
//! panics on some of them (`xmlns:xmlns="…"`, found by fuzzing).

use super::xml_scan::Element;

/// Whether a child element `child` of `parent` is read (`parent` is `robot` for the
/// top-level elements). Children of the leaf elements (`<origin>`, `<mass>`, …) are not.
pub fn kept(parent: &str, child: &str) -> bool {
    matches!(
        (parent, child),
        ("robot", "link" | "joint")
            | ("link", "inertial")
            | ("inertial", "origin" | "mass" | "inertia")
            | (
                "joint",
                "origin" | "parent" | "child" | "axis" | "limit" | "dynamics" | "mimic"
            )
    )
}

/// `text` with every element below `root` that [`kept`] refuses replaced by spaces (line
/// breaks kept, one space per character, so lines and columns do not move).
pub fn dynamics_only(text: &str, root: &Element<'_>) -> String {
    let mut ranges = Vec::new();
    namespaced(text, root, &mut ranges);
    skipped(text, root, &mut ranges);
    if ranges.is_empty() {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for (start, end) in ranges {
        out.push_str(&text[at..start]);
        out.extend(
            text[start..end]
                .chars()
                .map(|c| if c == '\n' || c == '\r' { c } else { ' ' }),
        );
        at = end;
    }
    out.push_str(&text[at..]);
    out
}

/// The byte ranges of the skipped elements below `e`, and of the namespace attributes of
/// the kept ones, in file order.
fn skipped(text: &str, e: &Element<'_>, ranges: &mut Vec<(usize, usize)>) {
    for c in &e.children {
        if kept(e.name, c.name) {
            namespaced(text, c, ranges);
            skipped(text, c, ranges);
        } else {
            ranges.push((c.offset, c.end));
        }
    }
}

/// The byte ranges of `e`'s attributes `xmlns`, `xmlns:…` and `prefix:…`, from the name to
/// the closing quote of the value.
fn namespaced(text: &str, e: &Element<'_>, ranges: &mut Vec<(usize, usize)>) {
    for &(name, value, offset) in &e.attrs {
        if name == "xmlns" || name.contains(':') {
            // The value is a slice of `text`; its closing quote follows it.
            let value_start = value.as_ptr() as usize - text.as_ptr() as usize;
            ranges.push((offset, value_start + value.len() + 1));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::urdf::xml_scan::scan;

    #[test]
    fn skipped_elements_become_spaces_and_lines_stay() {
        let text = "<robot>\n<link name=\"a\"><visual>é\n<x/></visual><inertial/></link>\n<gazebo/></robot>";
        let root = scan(text).unwrap();
        let expected = format!(
            "<robot>\n<link name=\"a\">{}\n{}<inertial/></link>\n{}</robot>",
            " ".repeat(9),
            " ".repeat(13),
            " ".repeat(9)
        );
        assert_eq!(dynamics_only(text, &root), expected);
    }
}
