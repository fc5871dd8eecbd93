//! The subcommands of the `dynamics-gen` binary, each a thin layer over the library.

pub mod args;
pub mod eval;
pub mod generate;
pub mod joints;
