//! The LaTeX of `dynamics-gen equations --format latex` compiles: each document is run through
//! `pdflatex` (Debian's `texlive-latex-base`, which `.ci/run` installs) and must give a PDF
//! with no error. Where no TeX engine is installed the test says so and checks only what the
//! unit test `latex_and_markdown_environments_are_balanced` checks, unless
//! `DYNAMICS_GEN_REQUIRE_TEX` is set, when a missing engine fails it.

use std::process::Command;

fn tex_engine() -> Option<&'static str> {
    let found = Command::new("pdflatex")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    found.then_some("pdflatex")
}

#[test]
fn latex_output_compiles_with_a_tex_engine() {
    let Some(engine) = tex_engine() else {
        assert!(
            std::env::var_os("DYNAMICS_GEN_REQUIRE_TEX").is_none(),
            "DYNAMICS_GEN_REQUIRE_TEX is set but pdflatex is not on PATH: install texlive-latex-base"
        );
        eprintln!(
            "no pdflatex on PATH: the LaTeX is only checked for balanced environments (unit tests)"
        );
        return;
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("latex");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let cases: [(&str, &[&str]); 4] = [
        ("pendulum_steps", &["pendulum", "--steps"]),
        (
            "planar2r_symbolic",
            &[
                "planar2r",
                "--steps",
                "--symbolic",
                "m1",
                "m2",
                "L1",
                "L2",
                "g",
            ],
        ),
        ("ur5_m_g", &["ur5", "--only", "M,g"]),
        ("mr_ur5_c", &["mr_ur5", "--only", "c"]),
    ];
    for (name, args) in cases {
        let out = Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
            .arg("equations")
            .args(args)
            .args(["--format", "latex"])
            .output()
            .expect("the binary runs");
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let tex = dir.join(format!("{name}.tex"));
        std::fs::write(&tex, &out.stdout).expect("written");
        let run = Command::new(engine)
            .args([
                "-interaction=nonstopmode",
                "-halt-on-error",
                "-output-directory",
            ])
            .arg(&dir)
            .arg(&tex)
            .output()
            .expect("pdflatex runs");
        let log = String::from_utf8_lossy(&run.stdout);
        let tail: Vec<&str> = log.lines().rev().take(30).collect();
        assert!(
            run.status.success(),
            "{name}: {engine} failed; the end of its log:\n{}",
            tail.into_iter().rev().collect::<Vec<_>>().join("\n")
        );
        let pdf = dir.join(format!("{name}.pdf"));
        let size = std::fs::metadata(&pdf).map(|m| m.len()).unwrap_or(0);
        assert!(size > 1000, "{name}: no PDF ({size} bytes)");
    }
}
