//! The integrators on the harmonic oscillator `q̈ = −q` (E = ½(q² + q̇²)), whose exact
//! solution and whose discrete maps are known in closed form.

use generated_example::integrate::{explicit_euler, rk4, semi_implicit_euler, State};
use nalgebra::Vector1;

fn oscillator(q: &Vector1<f64>, _qd: &Vector1<f64>) -> Vector1<f64> {
    -q
}

fn energy((q, qd): &State<1>) -> f64 {
    0.5 * (q[0] * q[0] + qd[0] * qd[0])
}

fn start() -> State<1> {
    (Vector1::new(1.0), Vector1::new(0.0))
}

#[test]
fn explicit_euler_multiplies_the_energy_by_one_plus_h_squared() {
    let h = 0.01;
    let mut s = start();
    for k in 1..=1000 {
        s = explicit_euler(oscillator, s, h);
        let expected = 0.5 * (1.0 + h * h).powi(k);
        assert!((energy(&s) - expected).abs() <= 1e-13, "step {k}");
    }
}

#[test]
fn semi_implicit_euler_keeps_the_energy_bounded() {
    // It conserves the modified energy ½(q² + q̇²) − (h/2) q q̇ exactly (up to rounding), so
    // the energy itself oscillates within h/2 of its start and never drifts.
    let h = 0.01;
    let mut s = start();
    for _ in 0..100_000 {
        s = semi_implicit_euler(oscillator, s, h);
        let modified = energy(&s) - 0.5 * h * s.0[0] * s.1[0];
        assert!((modified - 0.5).abs() <= 1e-12, "{modified}");
        assert!((energy(&s) - 0.5).abs() <= 0.5 * h);
    }
}

#[test]
fn rk4_follows_the_cosine() {
    let h = 1e-3;
    let mut s = start();
    for k in 1..=10_000 {
        s = rk4(oscillator, s, h);
        let t = k as f64 * h;
        assert!((s.0[0] - t.cos()).abs() <= 1e-12, "t = {t}: {}", s.0[0]);
        assert!((s.1[0] + t.sin()).abs() <= 1e-12, "t = {t}: {}", s.1[0]);
    }
}
