//! `dynamics-gen eval`'s line parser and evaluation (the CLI's own source file) on arbitrary
//! lines, for a chain, a chain with a tool and a floating-base tree: an answer whose numbers
//! are all finite, or an error; never a panic.
#![no_main]

#[path = "../../dynamics-gen/src/bin/cli/eval_line.rs"]
#[allow(dead_code)]
mod eval_line;

use dynamics_gen::dynamics_model::{load, shipped, LoadOptions, Robot};
use libfuzzer_sys::fuzz_target;
use std::sync::LazyLock;

static ROBOTS: LazyLock<Vec<Robot>> = LazyLock::new(|| {
    let floating = LoadOptions {
        floating_base: true,
        ..LoadOptions::default()
    };
    let mut robots: Vec<Robot> = ["pendulum", "ur5", "mr_ur5"]
        .iter()
        .map(|name| load::load(name, &LoadOptions::default()).expect("shipped"))
        .collect();
    let ur5 = shipped::get("ur5").expect("shipped");
    robots.push(load::from_str(ur5.text, ur5.format, ur5.file, &floating).expect("floats"));
    robots
});

fuzz_target!(|data: &[u8]| {
    let Some((&which, rest)) = data.split_first() else {
        return;
    };
    let Ok(line) = std::str::from_utf8(rest) else {
        return;
    };
    let robot = &ROBOTS[which as usize % ROBOTS.len()];
    if let Ok(answer) = eval_line::eval_line(robot, line) {
        let json = serde_json::to_string(&answer).expect("an answer serialises");
        // serde_json writes a non-finite number as null; only the two task-space entries
        // may be null (singular J_b M⁻¹ J_bᵀ).
        let rest = json
            .replace("\"task_space_mass_matrix\":null", "")
            .replace("\"task_space_bias\":null", "");
        assert!(!rest.contains("null"), "a non-finite number in {json}");
    }
});
