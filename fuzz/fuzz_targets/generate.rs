//! Generation with arbitrary names and numbers: a robot file built from fuzzer-chosen names
//! (any Unicode: line breaks, comment and string delimiters, bidi controls) and geometry is
//! either refused or generates a file that parses with `syn` to exactly the items generated
//! for the same robot with plain names. No name ever becomes code.
#![no_main]

use arbitrary::Arbitrary;
use dynamics_gen::dynamics_model::{load, LoadOptions};
use dynamics_gen::{generate_file, Options, Provenance, Scalar};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Joint {
    name: String,
    link: String,
    prismatic: bool,
    /// Index into the six signed unit axes.
    axis: u8,
    /// Home offset of the link, in decimetres.
    offset: [i8; 3],
    /// Mass in tenths of a kilogram (0 is massless, without inertia).
    mass: u8,
    /// Parent: an earlier joint's link, modulo (0 = base).
    parent: u8,
}

#[derive(Arbitrary, Debug)]
struct Input {
    robot: String,
    base: String,
    frame: String,
    joints: Vec<Joint>,
    f32: bool,
}

/// A TOML basic string holding `s` exactly.
fn quoted(s: &str) -> String {
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

/// The robot file; `plain` replaces every name by a canonical one.
fn toml(input: &Input, plain: bool) -> String {
    let name = |s: &str, canonical: String| if plain { quoted(&canonical) } else { quoted(s) };
    let joints = &input.joints[..input.joints.len().min(4)];
    let mut t = format!(
        "name = {}\n\n[base]\nname = {}\n\n",
        name(&input.robot, "robot".into()),
        name(&input.base, "base".into())
    );
    for (i, j) in joints.iter().enumerate() {
        let axes = [
            [1, 0, 0],
            [0, 1, 0],
            [0, 0, 1],
            [-1, 0, 0],
            [0, -1, 0],
            [0, 0, -1],
        ];
        let a = axes[j.axis as usize % 6];
        let parent = match j.parent as usize % (i + 1) {
            0 => name(&input.base, "base".into()),
            p => name(&joints[p - 1].link, format!("link{}", p - 1)),
        };
        let m = f64::from(j.mass) / 10.0;
        let inertia = if j.mass == 0 { 0.0 } else { 0.01 * m };
        t += &format!(
            "[[joint]]\nname = {}\ntype = \"{}\"\nparent = {parent}\naxis = [{}, {}, {}]\n{}\n[joint.link]\nname = {}\nhome = {{ xyz = [{}, {}, {}] }}\nmass = {m}\ninertia = [{inertia}, {inertia}, {inertia}, 0, 0, 0]\n\n",
            name(&j.name, format!("joint{i}")),
            if j.prismatic { "prismatic" } else { "revolute" },
            a[0],
            a[1],
            a[2],
            if j.prismatic { "" } else { "point = [0, 0, 0]" },
            name(&j.link, format!("link{i}")),
            f64::from(j.offset[0]) / 10.0,
            f64::from(j.offset[1]) / 10.0,
            f64::from(j.offset[2]) / 10.0,
        );
    }
    if let Some(last) = joints.len().checked_sub(1) {
        t += &format!(
            "[[frame]]\nname = {}\nparent = {}\nhome = {{ xyz = [0, 0, 0.1] }}\n",
            name(&input.frame, "frame".into()),
            name(&joints[last].link, format!("link{last}"))
        );
    }
    t
}

/// Every item of a generated file, as its kind and identifier.
fn items(code: &str) -> Vec<String> {
    let file = syn::parse_file(code).unwrap_or_else(|e| panic!("not Rust ({e}):\n{code}"));
    let mut out = Vec::new();
    for item in file.items {
        match item {
            syn::Item::Struct(s) => out.push(format!("struct {}", s.ident)),
            syn::Item::Const(c) => out.push(format!("const {}", c.ident)),
            syn::Item::Impl(i) => {
                for item in i.items {
                    match item {
                        syn::ImplItem::Fn(f) => out.push(format!("fn {}", f.sig.ident)),
                        syn::ImplItem::Const(c) => out.push(format!("impl const {}", c.ident)),
                        other => out.push(format!("impl item {}", quote_tokens(&other))),
                    }
                }
            }
            other => out.push(format!("item {}", quote_tokens(&other))),
        }
    }
    out
}

fn quote_tokens(t: &impl quote::ToTokens) -> String {
    t.to_token_stream().to_string()
}

fuzz_target!(|input: Input| {
    let options = Options {
        name: Some("Fuzzed".into()),
        scalar: if input.f32 { Scalar::F32 } else { Scalar::F64 },
        functions: Some(vec![
            "inverse_dynamics".into(),
            "frame_poses".into(),
            "inertial_parameters".into(),
        ]),
        ..Options::default()
    };
    let generate = |plain: bool| {
        let text = toml(&input, plain);
        let robot = load::from_str(
            &text,
            load::Format::Toml,
            "fuzz.toml",
            &LoadOptions::default(),
        )
        .ok()?;
        Some(
            generate_file(&robot, &options, Provenance::new("fuzz.toml"))
                .map_err(|e| e.to_string()),
        )
    };
    // Refused with hostile names: the plain robot may still load (duplicate names, a link
    // named as the base); nothing to compare then.
    let Some(named) = generate(false) else {
        return;
    };
    let plain = generate(true).expect("the plain robot loads when the named one does");
    match (named, plain) {
        (Ok(code), Ok(plain)) => {
            assert_eq!(
                items(&code),
                items(&plain),
                "the names changed the items:\n{code}"
            )
        }
        // Refused for its geometry (a joint that moves no mass): so is the plain robot.
        (Err(_), Err(_)) => {}
        (named, plain) => panic!("the names changed the outcome: {named:?} / {plain:?}"),
    }
});
