//! Text from a robot description never becomes code: hostile names (line breaks, comment
//! delimiters, quotes, backslashes, Unicode line separators, bidi controls, backticks) in
//! every name field, from every input format and every front end, give a generated file
//! that parses to exactly the expected items, with every name inert.

use dynamics_gen::{generate_file, Builder, Options};
use dynamics_model::load::{from_str, Format};
use dynamics_model::LoadOptions;
use quote::quote;
use std::path::PathBuf;
use std::process::Command;

/// Names that try to break out of a `//` comment, a `///` doc, a `/** */` block, a string
/// literal or a Markdown code span.
const HOSTILE: &[&str] = &[
    "x\nfn injected_newline() {}\n",
    "x\r\nfn injected_crlf() {}\r\n//",
    "*/ fn injected_block() {} /*",
    "\" ; fn injected_quote() {} ; \"",
    "back\\slash\\\" fn injected_backslash() {}",
    "x\u{2028}fn injected_line_separator() {}\u{2029}",
    "\u{202e}\u{2066}fn injected_bidi() {}\u{2069}",
    "`code` <script>fn injected_html() {}</script>",
    "\u{85}\u{0b}\u{0c}fn injected_controls() {}",
];

/// XML attribute escaping for the URDF files.
fn xml(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '<' => "&lt;".to_string(),
            '>' => "&gt;".to_string(),
            '&' => "&amp;".to_string(),
            '"' => "&quot;".to_string(),
            // XML 1.0 has no other C0 controls, not even as references.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => String::new(),
            c if c.is_control() || (c as u32) > 0x7e => format!("&#{};", c as u32),
            c => c.to_string(),
        })
        .collect()
}

/// `s` as it reads back from a URDF attribute written by [`xml`].
fn xml_read(s: &str) -> String {
    s.chars()
        .filter(|&c| (c as u32) >= 0x20 || matches!(c, '\t' | '\n' | '\r'))
        .collect()
}

/// TOML basic-string escaping.
fn toml_str(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn urdf(h: &str) -> String {
    let (robot, j1, j2, base, l1, l2) = (
        xml(&format!("robot{h}")),
        xml(&format!("j1{h}")),
        xml(&format!("j2{h}")),
        xml(&format!("base{h}")),
        xml(&format!("l1{h}")),
        xml(&format!("l2{h}")),
    );
    format!(
        r#"<?xml version="1.0"?>
<robot name="{robot}">
  <link name="{base}"/>
  <link name="{l1}"><inertial><origin xyz="0 0 0.2"/><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="{l2}"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{j1}" type="revolute"><parent link="{base}"/><child link="{l1}"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <joint name="{j2}" type="revolute"><parent link="{l1}"/><child link="{l2}"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>
"#
    )
}

fn toml(h: &str) -> String {
    format!(
        r#"name = {robot}
[[joint]]
name = {j1}
type = "revolute"
screw = [0, 0, 1, 0, 0, 0]
[joint.link]
name = {l1}
home = {{ xyz = [0, 0, 0.2] }}
mass = 1.0
inertia = [0.01, 0.01, 0.01, 0, 0, 0]
[[joint]]
name = {j2}
type = "revolute"
axis = [0, 1, 0]
point = [0, 0, 0.4]
[joint.link]
name = {l2}
home = {{ xyz = [0.1, 0, 0.2] }}
mass = 2.0
inertia = [0.02, 0.02, 0.01, 0, 0, 0]
[end_effector]
name = {ee}
home = {{ xyz = [0, 0, 0] }}
"#,
        robot = toml_str(&format!("robot{h}")),
        j1 = toml_str(&format!("j1{h}")),
        j2 = toml_str(&format!("j2{h}")),
        l1 = toml_str(&format!("l1{h}")),
        l2 = toml_str(&format!("l2{h}")),
        ee = toml_str(&format!("ee{h}")),
    )
}

/// The items of a generated file, by kind and name; panics if it does not parse.
fn items(code: &str) -> Vec<String> {
    let file = syn::parse_file(code).unwrap_or_else(|e| panic!("{e}\n{code}"));
    assert!(file.attrs.is_empty(), "inner attributes:\n{code}");
    file.items
        .iter()
        .map(|item| match item {
            syn::Item::Struct(s) => format!("struct {}", s.ident),
            syn::Item::Impl(i) => {
                let self_ty = &i.self_ty;
                let of = i.trait_.as_ref().map(|(p, _for)| {
                    let p = quote!(#p).to_string();
                    format!("{p} for ")
                });
                format!("impl {}{}", of.unwrap_or_default(), quote!(#self_ty))
            }
            syn::Item::Const(_) => "const".to_string(),
            other => panic!("unexpected item {}\n{code}", quote!(#other)),
        })
        .collect()
}

/// The whole file is inert: exactly the expected items, each method once, no injected
/// function anywhere, and every header line a comment.
fn check_file(code: &str, struct_name: &str, context: &str) {
    let got = items(code);
    assert_eq!(
        got[..2],
        [
            format!("struct {struct_name}"),
            format!("impl {struct_name}")
        ],
        "{context}\n{code}"
    );
    // Then trait impls, and the struct's own `impl` of its `DEFAULT` constant.
    assert!(
        got[2..]
            .iter()
            .all(|i| (i.starts_with("impl ") && i.contains(" for "))
                || *i == format!("impl {struct_name}")),
        "{context}: {got:?}"
    );
    check_tokens(code, context);
    for line in code
        .lines()
        .take_while(|l| !l.starts_with("///") && !l.is_empty())
    {
        assert!(line.starts_with("// "), "{context}: header line {line:?}");
    }
}

/// No injected function survives anywhere in the parsed tokens (outside string literals
/// and doc strings, where it is inert text).
fn check_tokens(code: &str, context: &str) {
    let file: syn::File = syn::parse_file(code).unwrap_or_else(|e| panic!("{e}\n{code}"));
    let tokens = quote!(#file).to_string();
    let fns = tokens.matches("fn injected").count();
    // Doc attributes and string literals are `"…"` tokens; count the injected names that
    // occur inside them and compare.
    let inert: usize = literals(&tokens)
        .iter()
        .map(|l| l.matches("fn injected").count())
        .sum();
    assert_eq!(
        fns, inert,
        "{context}: injected code outside literals\n{code}"
    );
    for l in literals(&tokens) {
        for bad in ['\n', '\r', '\u{2028}', '\u{2029}', '\u{202e}', '\u{85}'] {
            assert!(!l.contains(bad), "{context}: raw {bad:?} in {l}");
        }
    }
}

/// The string literals of a token string, as written (escapes not decoded).
fn literals(tokens: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut chars = tokens.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '"' {
            let mut lit = String::new();
            while let Some(c) = chars.next() {
                match c {
                    '\\' => {
                        lit.push(c);
                        if let Some(n) = chars.next() {
                            lit.push(n);
                        }
                    }
                    '"' => break,
                    c => lit.push(c),
                }
            }
            out.push(lit);
        }
    }
    out
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("dynamics-gen-hostile-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn hostile_names_in_urdf_and_toml_through_generate_file() {
    for (k, h) in HOSTILE.iter().enumerate() {
        for (format, text) in [(Format::Urdf, urdf(h)), (Format::Toml, toml(h))] {
            let file = format!("robots/arm{h}.{format:?}");
            let robot = from_str(&text, format, &file, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{k} {format:?}: {e}"));
            let written = match format {
                Format::Urdf => xml_read(h),
                Format::Toml => h.to_string(),
            };
            assert_eq!(
                robot.joints[0].name,
                format!("j1{written}"),
                "names kept as written"
            );
            let code = generate_file(&robot, &Options::default(), file.as_str()).unwrap();
            let derived = dynamics_gen::options::upper_camel(&robot.name);
            assert!(
                derived.chars().all(|c| c.is_ascii_alphanumeric()),
                "{derived}"
            );
            check_file(&code, &derived, &format!("{k} {format:?}"));
            // Tip, frame and lock option values reach the header (and the frames the code).
            if format == Format::Urdf {
                let options = Options {
                    load: LoadOptions {
                        tip: Some(format!("l2{written}")),
                        frames: Some(vec![format!("l2{written}"), format!("l1{written}")]),
                        ..Default::default()
                    },
                    ..Default::default()
                };
                let robot = from_str(&text, format, &file, &options.load).unwrap();
                let code = generate_file(&robot, &options, file.as_str()).unwrap();
                check_file(&code, &derived, &format!("{k} tip"));
            }
        }
    }
}

#[test]
fn hostile_names_in_modern_robotics_lists() {
    let robot = dynamics_model::load("pendulum", &LoadOptions::default()).unwrap();
    for (k, h) in HOSTILE.iter().enumerate() {
        let mut r = robot.clone();
        r.name = h.to_string();
        r.source = format!("/abs/{h}/lists");
        for j in &mut r.joints {
            j.name = format!("{}{h}", j.name);
        }
        for l in &mut r.links {
            l.name = format!("{}{h}", l.name);
        }
        r.end_effector.name = h.to_string();
        r.frames = vec![dynamics_model::Frame {
            name: format!("f{h}"),
            parent: Some(0),
            home: nalgebra::Matrix4::identity(),
        }];
        let options = Options {
            name: Some("Arm".into()),
            ..Default::default()
        };
        let code = generate_file(&r, &options, *h).unwrap();
        check_file(&code, "Arm", &format!("lists {k}"));
    }
}

#[test]
fn hostile_names_and_paths_through_the_builder() {
    let dir = temp_dir("builder");
    for (k, h) in HOSTILE.iter().enumerate() {
        // The file name itself is hostile where the file system allows it.
        let stem = if h.contains('/') {
            "arm".to_string()
        } else {
            format!("arm{h}")
        };
        let path = dir.join(format!("{stem}.urdf"));
        std::fs::write(&path, urdf(h)).unwrap();
        let code = Builder::new(path.to_string_lossy().into_owned())
            .lock(format!("j2{}", xml_read(h)), 0.5)
            .name("Arm")
            .generate()
            .unwrap_or_else(|e| panic!("{k}: {e}"));
        check_file(&code, "Arm", &format!("builder {k}"));
        assert!(
            !code.contains(dir.to_str().unwrap()),
            "absolute path in\n{code}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn hostile_names_through_the_cli() {
    let dir = temp_dir("cli");
    for (k, h) in HOSTILE.iter().enumerate() {
        let path = dir.join(format!("arm{k}.toml"));
        std::fs::write(&path, toml(h)).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
            .arg("generate")
            .arg(&path)
            .args(["--name", "Arm"])
            .output()
            .unwrap();
        let code = String::from_utf8(out.stdout).unwrap();
        assert!(
            out.status.success(),
            "{k}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        check_file(&code, "Arm", &format!("cli {k}"));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn hostile_names_through_the_macros() {
    let dir = temp_dir("macros");
    for (k, h) in HOSTILE.iter().enumerate() {
        let (robot, j1, l1) = (format!("robot{h}"), format!("j1{h}"), format!("l1{h}"));
        let tokens = dynamics_gen::macro_support::robot(quote! {
            pub struct Arm;
            name: #robot,
            joint revolute #j1 {
                screw: [0, 0, 1, 0, 0, 0],
                link #l1 { home: { xyz: [0, 0, 0.2] }, mass: 1, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
            },
        });
        let code = tokens.to_string();
        assert!(!code.contains("compile_error"), "{k}: {code}");
        let file: syn::File = syn::parse2(tokens).unwrap();
        let formatted = prettyplease::unparse(&file);
        let got = items(&formatted);
        assert_eq!(got[..2], ["struct Arm", "impl Arm"], "robot! {k}");
        check_tokens(&formatted, &format!("robot! {k}"));

        let path = dir.join(format!("arm{k}.urdf"));
        std::fs::write(&path, urdf(h)).unwrap();
        let path = path.to_string_lossy().into_owned();
        let tokens = dynamics_gen::macro_support::derive_dynamics(quote! {
            #[dynamics(file = #path)]
            pub struct Arm;
        });
        let code = tokens.to_string();
        assert!(!code.contains("compile_error"), "{k}: {code}");
        let file: syn::File = syn::parse2(tokens).unwrap();
        let formatted = prettyplease::unparse(&file);
        let got = items(&formatted);
        assert_eq!(got[..2], ["const", "impl Arm"], "derive {k}");
        check_tokens(&formatted, &format!("derive {k}"));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
