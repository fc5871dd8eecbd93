//! Robots shipped with dynamics-gen, embedded in the binary so that their names work from
//! any directory.

use crate::load::Format;

/// A shipped robot description.
#[derive(Clone, Copy, Debug)]
pub struct Shipped {
    /// Its name (what the CLI and the Builder accept).
    pub name: &'static str,
    /// Its file name under `robots/` (used in error messages and generated headers).
    pub file: &'static str,
    /// The format.
    pub format: Format,
    /// The file's text.
    pub text: &'static str,
}

/// Every shipped robot.
pub const ROBOTS: &[Shipped] = &[
    // Universal Robots UR5 (example-robot-data, BSD-3-Clause; see robots/README.md).
    Shipped {
        name: "ur5",
        file: "robots/ur5.urdf",
        format: Format::Urdf,
        text: include_str!("../../robots/ur5.urdf"),
    },
];

/// The names of the shipped robots.
pub const NAMES: &[&str] = &["ur5"];

/// The shipped robot called `name`.
pub fn get(name: &str) -> Option<Shipped> {
    ROBOTS.iter().copied().find(|r| r.name == name)
}
