//! Generates the dynamics of three shipped robots into `OUT_DIR` (f64, `no_std`).

use dynamics_gen::Builder;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let robots = [
        // The UR5 of example-robot-data (URDF), with its forearm as a named frame (for the
        // elbow: `forearm_link_pose`, `forearm_link_jacobian_space`, …).
        Builder::new("ur5").no_std(true).frames(["forearm_link"]),
        // The rotational pendulum of Modern Robotics Exercise 8.4.
        Builder::new("pendulum").no_std(true),
        // The UR5 of the Modern Robotics course, with the gravity of its reference data.
        Builder::new("mr_ur5")
            .no_std(true)
            .gravity([0.0, 0.0, -9.81]),
    ];
    for builder in &robots {
        // On error: a Cargo error under this crate's name, no panic backtrace.
        builder.compile_or_report();
    }
}
