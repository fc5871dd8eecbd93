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
