//! The one place where text from a robot description (robot, joint, link and frame names,
//! file names, option values) is made inert before it reaches generated code.
//!
//! Robot files come from strangers. Generated code holds such text in two contexts only:
//!
//! * comments and doc comments — through [`inert`], always inside a Markdown code span;
//! * string literals (`JOINT_NAMES`) — through [`proc_macro2::Literal::string`], which escapes
//!   quotes, backslashes and control characters itself.
//!
//! Identifiers are never taken from a robot file as they are: the struct name is built from
//! ASCII alphanumerics ([`crate::options::upper_camel`]) and checked, and the named frames'
//! methods from [`method_stems`] (ASCII alphanumerics and `_`, lower case).

use std::fmt::Write;

/// `text` as a Markdown code span (`` `…` ``) that is inert in a `//` comment, a `///` doc
/// comment and a `/** */` block: every character that could end the comment or the span,
/// start a new line, or change how the line reads is written as a visible escape.
///
/// Escaped: control characters (`\n`, `\r`, `\t`, …, as `\u{a}`), Unicode line and paragraph
/// separators, bidirectional and other format characters (`\u{202e}`, `\u{200b}`, …), the
/// backtick (`\u{60}`), the backslash (`\\`) and the comment delimiters `*/` and `/*`
/// (`*\/`, `/\*`). Everything else, including non-ASCII letters, is kept as is, so
/// `Schulter_gelenk_ü` reads as itself.
pub fn inert(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('`');
    let mut previous = '\0';
    for ch in text.chars() {
        match ch {
            '\\' => out.push_str("\\\\"),
            '`' => out.push_str("\\u{60}"),
            '/' if previous == '*' => out.push_str("\\/"),
            '*' if previous == '/' => out.push_str("\\*"),
            c if needs_escape(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
        previous = ch;
    }
    out.push('`');
    out
}

/// Characters that are not plain visible text: control characters (Cc), line and paragraph
/// separators, and the format characters (Cf) that reorder or hide text.
fn needs_escape(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{00ad}'
                | '\u{061c}'
                | '\u{180e}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2060}'..='\u{206f}'
                | '\u{feff}'
                | '\u{fff9}'..='\u{fffb}'
                | '\u{e0000}'..='\u{e007f}'
        )
}

/// The stems of the named frames' methods (`{stem}_pose`, `{stem}_jacobian_space`,
/// `{stem}_jacobian_body`), one per name: the name in lower case with every character but
/// ASCII letters and digits replaced by `_` (runs of `_` merged, none at either end), `frame`
/// when that is empty, prefixed `frame_` when it starts with a digit; then suffixed `_frame` (and a
/// number) until its three methods collide neither with `taken` (the other generated
/// methods) nor with an earlier frame's. Deterministic: the same names give the same stems.
pub fn method_stems(names: &[&str], taken: &[&str]) -> Vec<String> {
    let mut used: Vec<String> = Vec::new();
    let methods = |stem: &str| {
        [
            format!("{stem}_pose"),
            format!("{stem}_jacobian_space"),
            format!("{stem}_jacobian_body"),
        ]
    };
    names
        .iter()
        .map(|name| {
            let mut base = String::new();
            for c in name.chars() {
                if c.is_ascii_alphanumeric() {
                    base.push(c.to_ascii_lowercase());
                } else if !base.ends_with('_') && !base.is_empty() {
                    base.push('_');
                }
            }
            let mut base = base.trim_end_matches('_').to_string();
            if base.is_empty() {
                base.push_str("frame");
            } else if base.starts_with(|c: char| c.is_ascii_digit()) {
                base.insert_str(0, "frame_");
            }
            let free = |stem: &str| {
                methods(stem)
                    .iter()
                    .all(|m| !taken.contains(&m.as_str()) && !used.contains(m))
            };
            let mut stem = base.clone();
            let mut k = 1;
            while !free(&stem) {
                stem = if k == 1 {
                    format!("{base}_frame")
                } else {
                    format!("{base}_frame_{k}")
                };
                k += 1;
            }
            used.extend(methods(&stem));
            stem
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{inert, method_stems};

    #[test]
    fn frame_method_stems_are_snake_case_identifiers_without_collisions() {
        let names = [
            "LF_FOOT",
            "camera link",
            "end-effector",
            "3d_cam",
            "",
            "a-b",
            "a_b",
            "Ünïcode",
        ];
        let taken = ["end_effector_pose", "jacobian_space"];
        let stems = method_stems(&names, &taken);
        assert_eq!(
            stems,
            [
                "lf_foot",
                "camera_link",
                "end_effector_frame",
                "frame_3d_cam",
                "frame",
                "a_b",
                "a_b_frame",
                "n_code",
            ]
        );
        for s in &stems {
            let ident = format!("{s}_jacobian_body");
            assert!(syn::parse_str::<syn::Ident>(&ident).is_ok(), "{ident}");
        }
    }

    #[test]
    fn plain_names_read_as_themselves() {
        assert_eq!(inert("shoulder_pan_joint"), "`shoulder_pan_joint`");
        assert_eq!(inert("Gelenk ü 1"), "`Gelenk ü 1`");
    }

    #[test]
    fn everything_that_could_end_a_comment_or_a_span_is_escaped() {
        assert_eq!(inert("a\nfn x() {}"), "`a\\u{a}fn x() {}`");
        assert_eq!(inert("a\r\n"), "`a\\u{d}\\u{a}`");
        assert_eq!(inert("*/ x /* y"), "`*\\/ x /\\* y`");
        assert_eq!(inert("a`b"), "`a\\u{60}b`");
        assert_eq!(inert("a\\b"), "`a\\\\b`");
        assert_eq!(inert("a\u{2028}b\u{2029}"), "`a\\u{2028}b\\u{2029}`");
        assert_eq!(inert("\u{202e}evil\u{2066}"), "`\\u{202e}evil\\u{2066}`");
        assert_eq!(
            inert("\u{85}\u{feff}\u{200b}"),
            "`\\u{85}\\u{feff}\\u{200b}`"
        );
        // The escapes themselves hold none of the dangerous characters.
        for s in ["\n", "*/", "`", "\u{2028}", "\u{202e}"] {
            let out = inert(s);
            let inner = &out[1..out.len() - 1];
            assert!(!inner.contains(['\n', '`', '\u{2028}', '\u{202e}']));
            assert!(!inner.contains("*/"));
        }
    }
}
