//! `dynamics-gen`: the command-line front end of the generator.
//!
//! ```text
//! dynamics-gen generate ROBOT [--name NAME] [--scalar f64|f32] [--no-std] [-o FILE] [model options]
//! dynamics-gen stats    ROBOT [model options]
//! dynamics-gen eval     ROBOT [model options]  < states.jsonl
//! dynamics-gen joints   ROBOT [--tip LINK] [--lock JOINT=VALUE ...]
//! dynamics-gen robots
//! ```
//!
//! ROBOT is a `.urdf`/`.toml` file or the name of a shipped robot. Every error is printed as
//! `error: <message>` with exit code 1.

mod cli;

use clap::{CommandFactory, FromArgMatches};
use cli::args::{Cli, Command};
use std::process::ExitCode;

fn main() -> ExitCode {
    let shipped = format!(
        "Shipped robots (usable as ROBOT from any directory): {}.",
        dynamics_gen::dynamics_model::shipped::NAMES.join(", ")
    );
    let mut command = Cli::command().after_help(shipped.clone());
    for sub in ["generate", "stats", "equations", "eval", "joints"] {
        command = command.mut_subcommand(sub, |c| c.after_help(shipped.clone()));
    }
    let cli = match command
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m))
    {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // Usage errors: clap's message already starts with `error:`.
            eprint!("{}", e.render());
            return ExitCode::from(1);
        }
        Err(e) => {
            // --help and --version.
            // A reader that stops early (`| head`) is no error.
            let _ = cli::print(&e.render().to_string());
            return ExitCode::SUCCESS;
        }
    };
    let result = match cli.command {
        Command::Generate(args) => cli::generate::run(&args),
        Command::Stats(args) => cli::generate::stats(&args),
        Command::Equations(args) => cli::generate::equations(&args),
        Command::Eval(args) => cli::eval::run(&args),
        Command::Joints(args) => cli::joints::run(&args),
        Command::Robots => cli::joints::robots(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
    }
}
