//! `eval`: the reference dynamics (dynamics-reference) on states read as JSON lines.

use super::args::EvalArgs;
use super::eval_line::eval_line;
use std::io::{BufRead, Write};

/// `dynamics-gen eval`: answers every line of stdin; stops at the first bad one unless
/// `--keep-going`.
pub fn run(args: &EvalArgs) -> Result<(), String> {
    let robot = args.model.load()?;
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut failed = 0usize;
    for (i, line) in stdin.lock().lines().enumerate() {
        let number = i + 1;
        let line = line.map_err(|e| format!("line {number}: cannot read standard input: {e}"))?;
        if line.trim().is_empty() {
            continue;
        }
        let json = match eval_line(&robot, &line).and_then(|answer| {
            serde_json::to_string(&answer).map_err(|e| format!("cannot write the result: {e}"))
        }) {
            Ok(json) => json,
            Err(e) if args.keep_going => {
                failed += 1;
                eprintln!("error: line {number}: {e}");
                serde_json::json!({ "line": number, "error": e }).to_string()
            }
            Err(e) => return Err(format!("line {number}: {e}")),
        };
        writeln!(out, "{json}")
            .and_then(|()| out.flush())
            .map_err(|e| format!("cannot write to standard output: {e}"))?;
    }
    if failed > 0 {
        return Err(format!(
            "{failed} line{} could not be evaluated (answered with \"error\")",
            if failed == 1 { "" } else { "s" }
        ));
    }
    Ok(())
}
