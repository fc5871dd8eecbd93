//! The subcommands of the `dynamics-gen` binary, each a thin layer over the library.

pub mod args;
pub mod eval;
pub mod eval_line;
pub mod generate;
pub mod joints;

/// Writes `text` to standard output. A reader that stops early (`| head`) is not an error:
/// the rest is dropped quietly instead of panicking as `print!` does.
pub fn print(text: &str) -> Result<(), String> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write to standard output: {e}"))
        }
        _ => Ok(()),
    }
}
