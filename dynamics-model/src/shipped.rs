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
    // The UR5 of the Modern Robotics course, link frames at the centres of mass.
    Shipped {
        name: "mr_ur5",
        file: "robots/mr_ur5.toml",
        format: Format::Toml,
        text: include_str!("../../robots/mr_ur5.toml"),
    },
    // The rotational pendulum of Exercise 8.4.
    Shipped {
        name: "pendulum",
        file: "robots/pendulum.toml",
        format: Format::Toml,
        text: include_str!("../../robots/pendulum.toml"),
    },
    // The random 7-joint chain of mr_random7.json, in every form the TOML format offers.
    Shipped {
        name: "rand7",
        file: "robots/rand7.toml",
        format: Format::Toml,
        text: include_str!("../../robots/rand7.toml"),
    },
    // The planar 2R arm of §8.1.1 with named parameters m1, m2, L1, L2, g.
    Shipped {
        name: "planar2r",
        file: "robots/planar2r.toml",
        format: Format::Toml,
        text: include_str!("../../robots/planar2r.toml"),
    },
];

/// The names of the shipped robots.
pub const NAMES: &[&str] = &["ur5", "mr_ur5", "pendulum", "rand7", "planar2r"];

/// The shipped robot called `name`.
pub fn get(name: &str) -> Option<Shipped> {
    ROBOTS.iter().copied().find(|r| r.name == name)
}
