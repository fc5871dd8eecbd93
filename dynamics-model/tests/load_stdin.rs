//! Reading a robot from standard input: `load("-")` goes through `load::from_reader`, which
//! sniffs the format (`<` first: URDF, else TOML) and names the input `<stdin>` in errors.

use dynamics_model::load::{from_reader, sniff, Format, STDIN_NAME};
use dynamics_model::LoadOptions;
use std::path::PathBuf;

fn workspace_file(rel: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(rel);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn the_format_is_sniffed() {
    assert_eq!(sniff("  \n\t<?xml version=\"1.0\"?><robot/>"), Format::Urdf);
    assert_eq!(sniff("<robot name=\"x\"/>"), Format::Urdf);
    assert_eq!(sniff("# a robot\nname = \"x\""), Format::Toml);
    assert_eq!(sniff(""), Format::Toml);
}

#[test]
fn urdf_and_toml_load_from_a_reader_like_from_their_files() {
    let opts = LoadOptions::default();
    let text = workspace_file("robots/ur5.urdf");
    let r = from_reader(format!("\n  {text}").as_bytes(), STDIN_NAME, &opts).expect("urdf");
    let file = dynamics_model::load("ur5", &opts).expect("shipped ur5");
    assert_eq!((r.joints, r.links), (file.joints, file.links));
    assert_eq!(r.source, "<stdin>");
    let text = workspace_file("robots/mr_ur5.toml");
    let r = from_reader(text.as_bytes(), STDIN_NAME, &opts).expect("toml");
    assert_eq!(r.dof(), 6);
    // Options apply as for a file.
    let lock = LoadOptions {
        lock: vec![("wrist_3_joint".into(), 0.5)],
        ..opts
    };
    let text = workspace_file("robots/ur5.urdf");
    let r = from_reader(text.as_bytes(), STDIN_NAME, &lock).expect("locked");
    assert_eq!(r.dof(), 5);
}

#[test]
fn errors_name_stdin() {
    let opts = LoadOptions::default();
    let bad = "<robot name=\"t\">\n<link name=\"a\">\n</robot>\n";
    let m = from_reader(bad.as_bytes(), STDIN_NAME, &opts)
        .unwrap_err()
        .to_string();
    assert!(m.starts_with("<stdin>:3:1: "), "{m}");
    let m = from_reader("name = 3".as_bytes(), STDIN_NAME, &opts)
        .unwrap_err()
        .to_string();
    assert!(m.starts_with("<stdin>"), "{m}");
    let m = from_reader(&[0xff, 0xfe, 0x3c][..], STDIN_NAME, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        m.starts_with("<stdin>:1:1: the file is not UTF-8 text (byte 0xff at offset 0)"),
        "{m}"
    );
}
