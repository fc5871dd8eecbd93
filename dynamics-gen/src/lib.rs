//! dynamics-gen: turns a robot arm's description into unrolled, allocation-free Rust
//! functions for its rigid-body dynamics.
//!
//! Pipeline: model ([`dynamics_model`]: robot, loaders, validation) → [`expand`] (symbolic
//! recursions over the [`expr`] graph, every constant of the robot folded in) → [`emit`]
//! (tokens, prettyplease, `@generated` header), with the front ends on top: the build.rs
//! [`Builder`], the `dynamics-gen` CLI and the `dynamics-macros` proc-macros.

pub mod builder;
pub mod check;
pub mod emit;
pub mod equations;
pub mod error;
pub mod expand;
pub mod expr;
pub mod macro_support;
pub mod manifest;
pub mod options;
pub mod stats;

pub use builder::{compile_robot, Builder};
pub use check::check_robot;
pub use dynamics_model;
pub use emit::{generate_file, generate_impl, Generated, Provenance};
pub use error::Error;
pub use options::{Method, Options, Scalar};
