//! Compile-time diagnostics of `robot!` and `#[derive(Dynamics)]` (trybuild UI tests), and
//! the README examples as pass tests.
//!
//! trybuild builds the test crates in its own directory, so the robot files' relative paths
//! are resolved against the workspace root through `DYNAMICS_GEN_MANIFEST_DIR` (README paths
//! like `robots/ur5.urdf` read as in a user's crate, and no .stderr holds a machine path).

#[test]
fn ui() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    std::env::set_var("DYNAMICS_GEN_MANIFEST_DIR", root);
    let t = trybuild::TestCases::new();
    t.pass("tests/ui/pass/*.rs");
    t.compile_fail("tests/ui/fail/*.rs");
}
