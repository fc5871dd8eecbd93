//! The TOML loader on arbitrary bytes: an error or a valid robot, never a panic or a hang.
#![no_main]

use dynamics_gen::dynamics_model::{load, LoadOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Bytes, as a file is read: UTF-8 decoding and the byte-order mark included.
    if let Ok(robot) = load::from_reader(data, "fuzz.toml", &LoadOptions::default()) {
        // What loads is valid: it passes validation again, unchanged.
        assert!(robot.validate().is_ok(), "a loaded robot must be valid");
    }
});
