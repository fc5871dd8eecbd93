//! Helpers shared by the integration tests: reading the reference JSON files of the repository
//! and comparing numbers with the project's tolerance.
#![allow(dead_code)]

pub mod pinocchio;
pub mod random_chain;
pub mod random_tree;

use dynamics_model::Robot;
use nalgebra::{DMatrix, DVector, Matrix4, Matrix6, Vector3, Vector6};
use serde_json::Value;

/// The repository's test data folder (`tests/data` at the workspace root).
pub const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/");

/// Reads and parses `tests/data/<rel>`.
pub fn load_json(rel: &str) -> Value {
    let path = format!("{DATA}{rel}");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("cannot parse {path}: {e}"))
}

/// A JSON number.
pub fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A JSON list of numbers.
pub fn vec_of(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not a list: {v}"))
        .iter()
        .map(num)
        .collect()
}

/// A JSON row-major nested list as a matrix.
pub fn mat_of(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v
        .as_array()
        .expect("list of rows")
        .iter()
        .map(vec_of)
        .collect();
    let ncols = rows.first().map_or(0, Vec::len);
    assert!(rows.iter().all(|r| r.len() == ncols), "ragged matrix");
    DMatrix::from_fn(rows.len(), ncols, |i, j| rows[i][j])
}

/// A 4×4 transform.
pub fn mat4(v: &Value) -> Matrix4<f64> {
    let m = mat_of(v);
    assert_eq!(m.shape(), (4, 4));
    Matrix4::from_fn(|i, j| m[(i, j)])
}

/// A 6×6 matrix.
pub fn mat6(v: &Value) -> Matrix6<f64> {
    let m = mat_of(v);
    assert_eq!(m.shape(), (6, 6));
    Matrix6::from_fn(|i, j| m[(i, j)])
}

/// A 6-vector.
pub fn vec6(v: &Value) -> Vector6<f64> {
    Vector6::from_column_slice(&vec_of(v))
}

/// A 3-vector.
pub fn vec3(v: &Value) -> Vector3<f64> {
    Vector3::from_column_slice(&vec_of(v))
}

/// A column vector from a JSON list.
pub fn dvec(v: &Value) -> DVector<f64> {
    DVector::from_vec(vec_of(v))
}

/// The robot of a model in the book's list form: `Mlist`, `Glist`, screw axes as a list of
/// 6-vectors (`screws`), and the gravity vector.
pub fn robot_from_lists(model: &Value, screws: &Value, gravity: &Value, checked: bool) -> Robot {
    let m_list: Vec<_> = model["Mlist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat4)
        .collect();
    let g_list: Vec<_> = model["Glist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat6)
        .collect();
    let s_list: Vec<_> = screws.as_array().unwrap().iter().map(vec6).collect();
    let g = vec3(gravity);
    if checked {
        Robot::from_mr_lists(&m_list, &g_list, &s_list, g).expect("valid model")
    } else {
        Robot::from_mr_lists_unchecked(&m_list, &g_list, &s_list, g).expect("lists fit")
    }
}

/// Asserts the project tolerance `‖x − y‖∞ ≤ rel·‖y‖∞ + abs` (rel = 1e-9, abs = 1e-12 by
/// default) and returns `‖x − y‖∞ / max(‖y‖∞, 1)` for reporting. `x` and `y` must be laid out
/// alike (e.g. both column-major matrices of the same shape).
pub fn check_tol(what: &str, x: &[f64], y: &[f64], rel: f64, abs: f64) -> f64 {
    assert_eq!(
        x.len(),
        y.len(),
        "{what}: sizes differ ({} vs {})",
        x.len(),
        y.len()
    );
    let diff = x
        .iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    let scale = y.iter().fold(0.0_f64, |m, b| m.max(b.abs()));
    assert!(
        diff <= rel * scale + abs && x.iter().all(|v| v.is_finite()),
        "{what}: ‖x − y‖∞ = {diff:e} exceeds {rel:e}·{scale:e} + {abs:e}\n x = {x:?}\n y = {y:?}"
    );
    diff / scale.max(1.0)
}

/// [`check_tol`] with the project tolerance 1e-9 relative, 1e-12 absolute.
pub fn check(what: &str, x: &[f64], y: &[f64]) -> f64 {
    check_tol(what, x, y, 1e-9, 1e-12)
}

/// The largest error seen in a group of checks, printed at the end of a test (run with
/// `--nocapture` to see it).
#[derive(Default)]
pub struct MaxErr(pub Vec<(String, f64)>);

impl MaxErr {
    /// Records `err` under `name`, keeping the maximum.
    pub fn note(&mut self, name: &str, err: f64) {
        match self.0.iter_mut().find(|(n, _)| n == name) {
            Some((_, e)) => *e = e.max(err),
            None => self.0.push((name.to_string(), err)),
        }
    }

    /// Prints every maximum.
    pub fn report(&self, title: &str) {
        for (n, e) in &self.0 {
            eprintln!("{title}: max error {n} = {e:.3e}");
        }
    }
}

/// `J`, nv_phys × nv: how the physical joint velocities follow the coordinates (the floating
/// base's 6×6 identity first; the identity without mimic joints).
pub fn coupling_matrix(robot: &Robot) -> DMatrix<f64> {
    let base = if robot.base.floating { 6 } else { 0 };
    let mut j = DMatrix::zeros(base + robot.dof(), robot.nv());
    for b in 0..base {
        j[(b, b)] = 1.0;
    }
    for (i, c) in robot.couplings().iter().enumerate() {
        j[(base + i, base + c.coordinate)] = c.multiplier;
    }
    j
}

/// `robot` with a random motor and friction on every joint: rotor inertia in [0, 1e-3)
/// kg·m², gear ratio ±[1, 100), damping in [0, 2), Coulomb friction in [0, 1).
pub fn with_actuation(rng: &mut random_chain::Rng, mut robot: Robot) -> Robot {
    for j in &mut robot.joints {
        j.rotor_inertia = rng.uniform(0.0, 1e-3);
        let g = rng.uniform(1.0, 100.0);
        j.gear_ratio = if rng.unit() < 0.5 { -g } else { g };
        j.damping = rng.uniform(0.0, 2.0);
        j.friction = rng.uniform(0.0, 1.0);
    }
    robot
}

/// `‖x − y‖∞ / max(‖y‖∞, 1e-300)`.
pub fn rel_err(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "sizes differ");
    let diff = x
        .iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    let scale = y.iter().fold(0.0_f64, |m, b| m.max(b.abs()));
    diff / scale.max(1e-300)
}
