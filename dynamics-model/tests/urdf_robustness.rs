//! The URDF loader never panics and always names the file: every test URDF, mutated at
//! seeded random places (truncated, a byte deleted, a markup character inserted, a span cut
//! out), loads or fails with an error that starts with the file name. A panic inside
//! urdf-rs would surface as the loader's "urdf-rs failed on this file" message, which must
//! not appear either (our own scanner should catch malformed input first).

mod urdf_common;

use dynamics_model::LoadOptions;
use urdf_common::*;

#[test]
fn mutated_files_never_panic() {
    let dir = data_dir().join("robots");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/data/robots")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "urdf"))
        .collect();
    files.sort();
    assert!(
        files.len() >= 5,
        "test URDFs missing from {}",
        dir.display()
    );
    // xorshift64, seeded: the same mutations on every run.
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed as usize
    };
    let (mut ok, mut failed) = (0, 0);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        for _ in 0..150 {
            let mut b = text.as_bytes().to_vec();
            let pos = rnd() % b.len();
            match rnd() % 4 {
                0 => b.truncate(pos),
                1 => {
                    b.remove(pos);
                }
                2 => {
                    let chars = b"<>/\"'= x0-.";
                    b.insert(pos, chars[rnd() % chars.len()]);
                }
                _ => {
                    let len = (rnd() % 40).min(b.len() - pos);
                    b.drain(pos..pos + len);
                }
            }
            let Ok(t) = String::from_utf8(b) else {
                continue;
            };
            match load_text(&t, "mutated.urdf", &LoadOptions::default()) {
                Ok(r) => {
                    assert!(r.dof() > 0);
                    ok += 1;
                }
                Err(e) => {
                    let m = e.to_string();
                    assert!(m.starts_with("mutated.urdf"), "{m}");
                    assert!(!m.contains("failed on this file"), "urdf-rs panicked: {m}");
                    failed += 1;
                }
            }
        }
    }
    eprintln!("{ok} mutated files loaded, {failed} refused with a message");
    assert!(failed > 100 && ok > 50);
}

/// Found by the `urdf_loader` fuzz target: a namespace declaration binding the prefix
/// `xmlns` made urdf-rs's XML back end (RustyXML) panic while formatting the robot. The
/// loader now blanks namespace attributes of the elements it reads; the file loads.
#[test]
fn namespace_declarations_on_kept_elements_are_ignored() {
    let text = std::fs::read_to_string(data_dir().join("robots/ur5.urdf")).unwrap();
    let plain = load_text(&text, "ur5.urdf", &LoadOptions::default()).unwrap();
    for attrs in [
        r#"xmlns:xmlns="http://wiki.ros.org/xacro""#,
        r#"xmlns="http://example.org/robot" xmlns:xacro="http://wiki.ros.org/xacro""#,
        r#"xacro:extra="1" xmlns:p="""#,
    ] {
        let odd = text.replacen(
            r#"<robot name="ur5""#,
            &format!(r#"<robot name="ur5" {attrs}"#),
            1,
        );
        assert_ne!(odd, text);
        let odd = odd.replacen(
            r#"<link name="base_link""#,
            &format!(r#"<link name="base_link" {attrs}"#),
            1,
        );
        let robot = load_text(&odd, "ur5.urdf", &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{attrs}: {e}"));
        assert_eq!(robot, plain, "{attrs}");
    }
}
