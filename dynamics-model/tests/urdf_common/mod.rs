//! Helpers shared by the URDF loader tests: test data, reference JSON, tolerances.
#![allow(dead_code)]

use dynamics_model::lie::exp6;
use dynamics_model::{Format, LoadOptions, ModelError, Robot};
use nalgebra::{DMatrix, Matrix3, Matrix4, Vector3};
use serde_json::Value;
use std::path::PathBuf;

/// `<workspace>/tests/data`.
pub fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("tests")
        .join("data")
}

/// The text of `tests/data/robots/<name>`.
pub fn robot_text(name: &str) -> String {
    let p = data_dir().join("robots").join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The reference JSON `tests/data/reference/<name>`.
pub fn reference(name: &str) -> Value {
    let p = data_dir().join("reference").join(name);
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).expect("reference JSON")
}

/// Loads URDF text through the public entry point (which validates the result).
pub fn load_text(text: &str, file: &str, options: &LoadOptions) -> Result<Robot, ModelError> {
    dynamics_model::load::from_str(text, Format::Urdf, file, options)
}

/// Loads an error case and returns its message (panics if it loads).
pub fn error_of(text: &str, file: &str, options: &LoadOptions) -> String {
    match load_text(text, file, options) {
        Ok(r) => panic!("{file} loaded ({} joints) but should fail", r.dof()),
        Err(e) => e.to_string(),
    }
}

/// Options with a tip link.
pub fn tip(name: &str) -> LoadOptions {
    LoadOptions {
        tip: Some(name.to_string()),
        ..LoadOptions::default()
    }
}

pub fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

pub fn vec3(v: &Value) -> Vector3<f64> {
    Vector3::new(f(&v[0]), f(&v[1]), f(&v[2]))
}

pub fn mat(v: &Value) -> DMatrix<f64> {
    let rows = v.as_array().expect("rows");
    let cols = rows[0].as_array().expect("cols").len();
    DMatrix::from_fn(rows.len(), cols, |i, j| f(&rows[i][j]))
}

pub fn mat3(v: &Value) -> Matrix3<f64> {
    let m = mat(v);
    Matrix3::from_fn(|i, j| m[(i, j)])
}

pub fn mat4(v: &Value) -> Matrix4<f64> {
    let m = mat(v);
    Matrix4::from_fn(|i, j| m[(i, j)])
}

/// `‖x − y‖∞ / (1e-9·‖y‖∞ + 1e-12)`: at most 1 when within the project tolerance. Also
/// returns the plain max error.
pub fn err_ratio(x: &[f64], y: &[f64]) -> (f64, f64) {
    assert_eq!(x.len(), y.len());
    let diff = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = y.iter().map(|b| b.abs()).fold(0.0, f64::max);
    (diff / (1e-9 * scale + 1e-12), diff)
}

/// Asserts `x ≈ y` within the project tolerance; returns the max abs error.
#[track_caller]
pub fn assert_close(what: &str, x: &[f64], y: &[f64]) -> f64 {
    let (ratio, diff) = err_ratio(x, y);
    assert!(
        ratio <= 1.0,
        "{what}: max error {diff:e}\n got  {x:?}\n want {y:?}"
    );
    diff
}

/// `T_{0,i}(q)` for i = 1..n (joint frames) and the end effector, by the product of
/// exponentials: `T_{0i}(q) = e^{[S1]q1} ⋯ e^{[Si]qi} M_{0i}`.
pub fn poses_at(robot: &Robot, q: &[f64]) -> (Vec<Matrix4<f64>>, Matrix4<f64>) {
    let home = robot.home_poses();
    let mut prod: Matrix4<f64> = Matrix4::identity();
    let mut frames = Vec::new();
    for (i, j) in robot.joints.iter().enumerate() {
        prod *= exp6(&j.screw, q[i]);
        frames.push(prod * home[i + 1]);
    }
    (frames, prod * home[robot.dof() + 1])
}
