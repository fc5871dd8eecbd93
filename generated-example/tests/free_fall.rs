//! The generated `no_std` code, integrated in time, against the trajectories of
//! `tests/data/reference/mr_ur5.json`: the Modern Robotics library's explicit-Euler free fall
//! (`free_fall`) and an RK4 free fall computed with Pinocchio (`free_fall_rk4`).

use generated_example::integrate::{explicit_euler, rk4, State};
use generated_example::mr_ur5::MrUr5;
use nalgebra::SVector;
use serde_json::Value;

type V6 = SVector<f64, 6>;

fn reference() -> Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/reference/mr_ur5.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).expect("reference data in the repo"))
        .unwrap()
}

fn rows(v: &Value) -> Vec<V6> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|row| V6::from_iterator(row.as_array().unwrap().iter().map(|x| x.as_f64().unwrap())))
        .collect()
}

/// `(max_k ‖x_k − y_k‖∞, max_k ‖y_k‖∞)` over the rows.
fn max_error(x: &[V6], y: &[V6]) -> (f64, f64) {
    assert_eq!(x.len(), y.len());
    let err = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    let scale = y.iter().map(|b| b.amax()).fold(0.0, f64::max);
    (err, scale)
}

/// Integrates from rest with `sub_steps` steps of `step` per stored row.
fn free_fall(
    rows: usize,
    dt: f64,
    sub_steps: usize,
    step: impl Fn(State<6>, f64) -> State<6>,
) -> (Vec<V6>, Vec<V6>) {
    let h = dt / sub_steps as f64;
    let mut state: State<6> = (V6::zeros(), V6::zeros());
    let (mut q, mut qd) = (vec![state.0], vec![state.1]);
    for _ in 1..rows {
        for _ in 0..sub_steps {
            state = step(state, h);
        }
        q.push(state.0);
        qd.push(state.1);
    }
    (q, qd)
}

fn accel(q: &V6, qd: &V6) -> V6 {
    MrUr5.forward_dynamics(q, qd, &V6::zeros())
}

#[test]
fn explicit_euler_reproduces_the_books_forward_dynamics_trajectory() {
    let data = reference();
    let ff = &data["free_fall"];
    let n = ff["N"].as_u64().unwrap() as usize;
    let dt = ff["dt"].as_f64().unwrap();
    let int_res = ff["intRes"].as_u64().unwrap() as usize;
    assert_eq!((n, int_res), (300, 8));
    let (q, qd) = free_fall(n, dt, int_res, |s, h| explicit_euler(accel, s, h));
    let (eq, sq) = max_error(&q, &rows(&ff["thetamat"]));
    let (ev, sv) = max_error(&qd, &rows(&ff["dthetamat"]));
    eprintln!(
        "explicit Euler vs the book: theta {eq:e} (rel {:e}), dtheta {ev:e} (rel {:e})",
        eq / sq,
        ev / sv
    );
    assert!(eq <= 1e-9 * sq + 1e-12, "theta error {eq:e}");
    assert!(ev <= 1e-9 * sv + 1e-12, "dtheta error {ev:e}");
}

#[test]
fn rk4_reproduces_the_accurate_free_fall() {
    let data = reference();
    let ff = &data["free_fall_rk4"];
    let n = ff["N"].as_u64().unwrap() as usize;
    let dt = ff["dt"].as_f64().unwrap();
    // h = dt/100 = 1e-4, as stored.
    let (q, qd) = free_fall(n, dt, 100, |s, h| rk4(accel, s, h));
    let (eq, sq) = max_error(&q, &rows(&ff["thetamat"]));
    let (ev, sv) = max_error(&qd, &rows(&ff["dthetamat"]));
    eprintln!(
        "RK4 vs Pinocchio RK4: theta {eq:e} (rel {:e}), dtheta {ev:e} (rel {:e})",
        eq / sq,
        ev / sv
    );
    assert!(eq <= 1e-9 * sq + 1e-12, "theta error {eq:e}");
    assert!(ev <= 1e-9 * sv + 1e-12, "dtheta error {ev:e}");
}
