//! The checks of the tests against Pinocchio's files (`reference_files.rs`,
//! `pinocchio_jacobians.rs`): f64 at ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12; the generated f32 cases,
//! whose code rounds the f64 inputs to f32, at the f32 tolerance of `generated_vs_reference`.

/// `‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12`, naming `what` on failure; the relative error.
pub fn check(what: &str, x: &[f64], y: &[f64]) -> f64 {
    let (err, scale) = dynamics_tests::assert_close(what, x, y, 1e-9, 1e-12);
    err / scale.max(1e-300)
}

/// [`check`] for a generated case; an f32 case at `‖x − y‖∞ ≤ rtol_f32·‖y‖∞` (1e-4, and
/// 1e-3 for forward dynamics, as in `generated_vs_reference`).
pub fn check_case(
    case: &dynamics_tests::Case,
    what: &str,
    x: &[f64],
    y: &[f64],
    rtol_f32: f64,
) -> f64 {
    if case.scalar == "f32" {
        let what = format!("{} (f32): {what}", case.module);
        let (err, scale) = dynamics_tests::assert_close(&what, x, y, rtol_f32, 0.0);
        err / scale.max(1e-300)
    } else {
        check(what, x, y)
    }
}
