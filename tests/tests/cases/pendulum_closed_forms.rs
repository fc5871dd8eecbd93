//! The generated pendulum (Exercise 8.4, `robots/pendulum.toml`) against the closed forms of
//! the seed cases: M = [[8 + 6 s2², 2 c2], [2 c2, 6]], c = (12 s2 c2 q̇1 q̇2 − 2 s2 q̇2², −6 s2 c2 q̇1²),
//! g = (0, 20 s2), and M(π/4, π/4) = [[11, √2], [√2, 6]].

use dynamics_model::random::Rng;
use dynamics_tests::{Spec, CASES};

fn close(x: &[f64], y: &[f64], what: &str) {
    for (a, b) in x.iter().zip(y) {
        assert!(
            (a - b).abs() <= 1e-12 * b.abs().max(1.0),
            "{what}: {x:?} vs {y:?}"
        );
    }
}

#[test]
fn generated_pendulum_matches_the_closed_forms() {
    let case = CASES
        .iter()
        .find(|c| matches!(c.spec, Spec::Shipped("pendulum")) && c.scalar == "f64")
        .expect("pendulum compiled");
    let p = case.imp;
    let m = p.mass_matrix(&[std::f64::consts::FRAC_PI_4; 2]);
    close(
        m.as_slice(),
        &[11.0, 2f64.sqrt(), 2f64.sqrt(), 6.0],
        "M(π/4)",
    );
    let mut rng = Rng::new(84);
    for _ in 0..200 {
        let q = [rng.uniform(-4.0, 4.0), rng.uniform(-4.0, 4.0)];
        let qd = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let qdd = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let (s2, c2) = q[1].sin_cos();
        let m_cf = [8.0 + 6.0 * s2 * s2, 2.0 * c2, 2.0 * c2, 6.0];
        let c_cf = [
            12.0 * s2 * c2 * qd[0] * qd[1] - 2.0 * s2 * qd[1] * qd[1],
            -6.0 * s2 * c2 * qd[0] * qd[0],
        ];
        let g_cf = [0.0, 20.0 * s2];
        let tau_cf = [
            m_cf[0] * qdd[0] + m_cf[1] * qdd[1] + c_cf[0] + g_cf[0],
            m_cf[2] * qdd[0] + m_cf[3] * qdd[1] + c_cf[1] + g_cf[1],
        ];
        close(p.mass_matrix(&q).as_slice(), &m_cf, "M");
        close(p.coriolis(&q, &qd).as_slice(), &c_cf, "c");
        close(p.gravity(&q).as_slice(), &g_cf, "g");
        close(p.inverse_dynamics(&q, &qd, &qdd).as_slice(), &tau_cf, "τ");
        close(p.forward_dynamics(&q, &qd, &tau_cf).as_slice(), &qdd, "q̈");
    }
}
