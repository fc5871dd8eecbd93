//! The URDF loader on arbitrary text, with the load options a user can give: an error or a
//! valid robot, never a panic or a hang.
#![no_main]

use dynamics_gen::dynamics_model::{load, LoadOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let Ok(text) = std::str::from_utf8(rest) else {
        return;
    };
    let options = LoadOptions {
        floating_base: flags & 1 != 0,
        snap_angles: (flags & 2 != 0).then_some(1e-4),
        ..LoadOptions::default()
    };
    if let Ok(robot) = load::from_str(text, load::Format::Urdf, "fuzz.urdf", &options) {
        assert!(robot.validate().is_ok(), "a loaded robot must be valid");
    }
});
