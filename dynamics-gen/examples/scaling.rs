//! How generation, the generated code and its compilation grow with the number of joints.
//!
//! For each n, a seeded random revolute chain of n joints (`dynamics_model::random`) is
//! generated with the chosen functions, written as the `src/lib.rs` of a scratch crate
//! (`target/scaling/`, nalgebra its only dependency, built once beforehand), with the public
//! functions' `#[inline]` hints removed so that the library compiles them, and compiled in
//! the dev and release profiles. Printed per n, as a Markdown table: generation time, lines,
//! compile times and rustc's peak memory (GNU time's maximum resident set of the build's
//! largest process), then the operation counts per function.
//!
//! ```text
//! cargo run --release -p dynamics-gen --example scaling -- 2 4 8 16 30 60
//! cargo run --release -p dynamics-gen --example scaling -- --functions all 2 4 8
//! cargo run --release -p dynamics-gen --example scaling -- --generate-only 100
//! ```
//!
//! Default functions: `mass_matrix, coriolis, gravity, inverse_dynamics, forward_dynamics`.
//! Needs `/usr/bin/time` (GNU time) and network or a filled cargo cache for nalgebra.

use dynamics_gen::{generate_file, stats::robot_stats, Options};
use dynamics_model::random::{random_chain, ChainSpec};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const FIVE: &[&str] = &[
    "mass_matrix",
    "coriolis",
    "gravity",
    "inverse_dynamics",
    "forward_dynamics",
];

/// Seconds and peak resident memory (MiB) of `cargo build` in `dir`.
fn build(dir: &Path, release: bool) -> Result<(f64, f64), String> {
    let report = dir.join("time.txt");
    let mut cmd = Command::new("/usr/bin/time");
    cmd.arg("-f")
        .arg("%e %M")
        .arg("-o")
        .arg(&report)
        .arg("cargo")
        .arg("build")
        .arg("--quiet")
        .current_dir(dir)
        .env("CARGO_TARGET_DIR", dir.join("target"))
        .env("CARGO_INCREMENTAL", "0");
    if release {
        cmd.arg("--release");
    }
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run /usr/bin/time cargo: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build failed in {}", dir.display()));
    }
    let text = std::fs::read_to_string(&report).map_err(|e| e.to_string())?;
    let last = text.lines().last().unwrap_or_default();
    let mut parts = last.split_whitespace();
    let seconds: f64 = parts.next().and_then(|s| s.parse().ok()).ok_or(last)?;
    let kib: f64 = parts.next().and_then(|s| s.parse().ok()).ok_or(last)?;
    Ok((seconds, kib / 1024.0))
}

fn main() -> Result<(), String> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut functions: Option<Vec<String>> = Some(FIVE.iter().map(|s| s.to_string()).collect());
    if let Some(i) = args.iter().position(|a| a == "--functions") {
        let list = args.get(i + 1).cloned().ok_or("--functions needs a list")?;
        functions = (list != "all").then(|| list.split(',').map(str::to_string).collect());
        args.drain(i..=i + 1);
    }
    let generate_only = args.iter().any(|a| a == "--generate-only");
    args.retain(|a| a != "--generate-only");
    let sizes: Vec<usize> = if args.is_empty() {
        vec![2, 4, 8, 16, 30, 60]
    } else {
        args.iter()
            .map(|a| a.parse().map_err(|_| format!("not a joint count: {a}")))
            .collect::<Result<_, _>>()?
    };
    let dir: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/scaling");
    std::fs::create_dir_all(dir.join("src")).map_err(|e| e.to_string())?;
    std::fs::write(
        dir.join("Cargo.toml"),
        "[package]\nname = \"scaling\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n[dependencies]\nnalgebra = { version = \"0.35\", default-features = false, features = [\"std\"] }\n\n[workspace]\n",
    )
    .map_err(|e| e.to_string())?;
    // nalgebra once, in both profiles, so that the table times the generated code alone.
    std::fs::write(dir.join("src/lib.rs"), "").map_err(|e| e.to_string())?;
    if !generate_only {
        build(&dir, false)?;
        build(&dir, true)?;
    }

    println!("| n | generation (s) | lines | dev build (s) | release build (s) | rustc peak (MiB, release) |");
    println!("|---|---|---|---|---|---|");
    let mut ops = Vec::new();
    for &n in &sizes {
        let robot = random_chain(
            n as u64,
            ChainSpec {
                dof: n,
                prismatic: 0.0,
            },
        );
        let options = Options {
            functions: functions.clone(),
            // Only nalgebra in the scratch crate.
            runtime_path: None,
            ..Options::default()
        };
        let start = Instant::now();
        let code = generate_file(&robot, &options, format!("random chain of {n} joints"))
            .map_err(|e| e.to_string())?;
        let generation = start.elapsed().as_secs_f64();
        let stats = robot_stats(&robot, &options).map_err(|e| e.to_string())?;
        // The public functions are `#[inline]`: a library compiles them only where a caller
        // uses them. Without the hint they are compiled here, as in a user's binary.
        let compiled = code.replace("    #[inline]\n", "");
        std::fs::write(dir.join("src/lib.rs"), &compiled).map_err(|e| e.to_string())?;
        let (dev, _) = if generate_only {
            (f64::NAN, 0.0)
        } else {
            build(&dir, false)?
        };
        let (release, peak) = if generate_only {
            (f64::NAN, 0.0)
        } else {
            build(&dir, true)?
        };
        println!(
            "| {n} | {generation:.2} | {} | {dev:.1} | {release:.1} | {peak:.0} |",
            code.lines().count()
        );
        ops.push((n, stats));
    }
    println!("\nOperations (multiplications + additions, all kinds) per function:\n");
    let names: Vec<&str> = ops[0].1.functions.iter().map(|f| f.name).collect();
    println!("| n | {} |", names.join(" | "));
    println!("|---|{}", "---|".repeat(names.len()));
    for (n, stats) in &ops {
        let cells: Vec<String> = stats
            .functions
            .iter()
            .map(|f| f.ops.total().to_string())
            .collect();
        println!("| {n} | {} |", cells.join(" | "));
    }
    Ok(())
}
