//! The generated derivative functions of every compiled robot that has them
//! ([`DERIVATIVE_CASES`]: shipped, reference URDFs, random chains 1–12 joints, random trees
//! with fixed and floating bases, mimic joints, armature and friction in the dynamics; f64
//! and f32, std and `no_std`) at seeded random states:
//!
//! - against central differences of the *reference implementation* (not of the generated
//!   code): `∂τ/∂q`, `∂τ/∂q̇` of `inverse_dynamics` (+ friction where the case includes it),
//!   `∂q̈/∂q`, `∂q̈/∂q̇`, `∂q̈/∂τ` of `forward_dynamics`, `∂g/∂q` of the gravity forces; on
//!   a floating base along the tangent directions `q + h·q̇(e_j)` (the reference's
//!   `configuration_rate` of the unit velocity `e_j`), h = 1e-6 scaled by the coordinate;
//! - identities: `M⁻¹ M = I` (with the generated `mass_matrix`); the `_with_derivatives`
//!   forms equal the plain ones and `inverse_dynamics` / `forward_dynamics`; the third
//!   output of `forward_dynamics_derivatives` is `mass_matrix_inverse`.
//!
//! f64: ‖x − y‖∞ ≤ 1e-6·‖y‖∞ + 1e-8 against differences, 1e-10·‖y‖∞ + 1e-12 for the
//! identities; f32 (inputs rounded to f32, differences in f64): 2e-3 and 1e-4.

use dynamics_model::random::Rng;
use dynamics_model::Robot;
use dynamics_tests::{row_major, Case, Spec, CASES, DERIVATIVE_CASES};
use nalgebra::{DMatrix, DVector, Vector6};

fn check(
    module: &str,
    what: &str,
    x: &DMatrix<f64>,
    y: &DMatrix<f64>,
    rtol: f64,
    atol: f64,
) -> f64 {
    let what = format!("{module} {what}");
    let (err, scale) =
        dynamics_tests::assert_close(&what, &row_major(x), &row_major(y), rtol, atol);
    err / (rtol * scale + atol).max(1e-300)
}

fn col(v: DVector<f64>) -> DMatrix<f64> {
    let n = v.len();
    DMatrix::from_column_slice(n, 1, v.as_slice())
}

/// The reference's `τ = ID(q, q̇, q̈)` with the friction the case includes.
fn inverse(spec: &Spec, robot: &Robot, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64> {
    dynamics_reference::inverse_dynamics(robot, q, qd, qdd, &robot.gravity, &Vector6::zeros())
        + spec.friction_in_dynamics(robot, qd)
}

/// The reference's `q̈ = FD(q, q̇, τ)` with the friction the case includes.
fn forward(spec: &Spec, robot: &Robot, q: &[f64], qd: &[f64], tau: &[f64]) -> DVector<f64> {
    let tau = DVector::from_column_slice(tau) - spec.friction_in_dynamics(robot, qd);
    dynamics_reference::forward_dynamics(
        robot,
        q,
        qd,
        tau.as_slice(),
        &robot.gravity,
        &Vector6::zeros(),
    )
    .expect("M is positive definite")
}

/// Central differences of `f` (nv outputs) along the nv tangent directions of `q`: column
/// j is `(f(q + h r_j) − f(q − h r_j)) / 2h` with `r_j` the configuration rate of `ν = e_j`.
fn d_dq(robot: &Robot, q: &[f64], f: &dyn Fn(&[f64]) -> DVector<f64>) -> DMatrix<f64> {
    let nv = robot.nv();
    let h = 1e-6;
    let mut m = DMatrix::zeros(nv, nv);
    for j in 0..nv {
        let mut e = vec![0.0; nv];
        e[j] = 1.0;
        let r = dynamics_reference::configuration_rate(robot, q, &e);
        let plus: Vec<f64> = q.iter().zip(r.iter()).map(|(a, b)| a + h * b).collect();
        let minus: Vec<f64> = q.iter().zip(r.iter()).map(|(a, b)| a - h * b).collect();
        m.set_column(j, &((f(&plus) - f(&minus)) / (2.0 * h)));
    }
    m
}

/// Central differences of `f` along the unit vectors of its (velocity-sized) argument `x`.
fn d_dx(x: &[f64], f: &dyn Fn(&[f64]) -> DVector<f64>) -> DMatrix<f64> {
    let n = x.len();
    let h = 1e-6;
    let mut m = DMatrix::zeros(n, n);
    for j in 0..n {
        let mut plus = x.to_vec();
        let mut minus = x.to_vec();
        plus[j] += h;
        minus[j] -= h;
        m.set_column(j, &((f(&plus) - f(&minus)) / (2.0 * h)));
    }
    m
}

fn case(module: &str) -> &'static Case {
    CASES
        .iter()
        .find(|c| c.module == module)
        .unwrap_or_else(|| panic!("no compiled case {module}"))
}

#[test]
fn generated_derivatives_equal_central_differences_of_the_reference() {
    let mut worst = [0.0f64; 2];
    let mut floating = 0;
    for &(module, gen) in DERIVATIVE_CASES {
        let case = case(module);
        let spec = case.spec;
        let robot = spec.robot();
        let (nq, nv) = (robot.nq(), robot.nv());
        floating += usize::from(robot.base.floating);
        let f32 = case.scalar == "f32";
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let (rtol, atol, rtol_id, atol_id) = if f32 {
            (2e-3, 1e-4, 1e-4, 1e-5)
        } else {
            (1e-6, 1e-8, 1e-10, 1e-12)
        };
        let worst = &mut worst[usize::from(f32)];
        let mut rng = Rng::new(0xDE21);
        for _ in 0..2 {
            let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform(-2.5, 2.5)).collect();
            if robot.base.floating {
                let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
                q[3..7].iter_mut().for_each(|x| *x /= norm);
            }
            let q: Vec<f64> = q.into_iter().map(round).collect();
            // Velocities away from zero (a Coulomb term is not differentiable at rest).
            let qd: Vec<f64> = (0..nv)
                .map(|_| {
                    let x = rng.uniform(0.3, 1.5);
                    round(if rng.uniform(0.0, 1.0) < 0.5 { -x } else { x })
                })
                .collect();
            let qdd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let tau: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-5.0, 5.0))).collect();
            let mut errs = Vec::new();
            let mut cmp = |what: &str, x: &DMatrix<f64>, y: &DMatrix<f64>, r: f64, a: f64| {
                errs.push(check(module, what, x, y, r, a));
            };

            // Against central differences of the reference.
            let (d_q, d_qd) = gen.inverse_dynamics_derivatives(&q, &qd, &qdd);
            let want_q = d_dq(&robot, &q, &|x| inverse(&spec, &robot, x, &qd, &qdd));
            let want_qd = d_dx(&qd, &|x| inverse(&spec, &robot, &q, x, &qdd));
            cmp("∂τ/∂q", &d_q, &want_q, rtol, atol);
            cmp("∂τ/∂q̇", &d_qd, &want_qd, rtol, atol);
            let (fd_q, fd_qd, m_inv) = gen.forward_dynamics_derivatives(&q, &qd, &tau);
            let want_q = d_dq(&robot, &q, &|x| forward(&spec, &robot, x, &qd, &tau));
            let want_qd = d_dx(&qd, &|x| forward(&spec, &robot, &q, x, &tau));
            let want_tau = d_dx(&tau, &|x| forward(&spec, &robot, &q, &qd, x));
            cmp("∂q̈/∂q", &fd_q, &want_q, rtol, atol);
            cmp("∂q̈/∂q̇", &fd_qd, &want_qd, rtol, atol);
            cmp("∂q̈/∂τ", &m_inv, &want_tau, rtol, atol);
            let dg = gen.gravity_derivative(&q);
            let want_g = d_dq(&robot, &q, &|x| {
                dynamics_reference::gravity_forces(&robot, x, &robot.gravity)
            });
            cmp("∂g/∂q", &dg, &want_g, rtol, atol);

            // Identities.
            let m = case.imp.mass_matrix(&q);
            let m_inv_alone = gen.mass_matrix_inverse(&q);
            cmp(
                "M⁻¹ M",
                &(&m_inv_alone * &m),
                &DMatrix::identity(nv, nv),
                rtol_id * 10.0,
                atol_id,
            );
            cmp("fd third = M⁻¹", &m_inv, &m_inv_alone, rtol_id, atol_id);
            let (t, w_q, w_qd) = gen.inverse_dynamics_with_derivatives(&q, &qd, &qdd);
            cmp(
                "with τ",
                &col(t),
                &col(case.imp.inverse_dynamics(&q, &qd, &qdd)),
                rtol_id,
                atol_id,
            );
            cmp("with ∂τ/∂q", &w_q, &d_q, rtol_id, atol_id);
            cmp("with ∂τ/∂q̇", &w_qd, &d_qd, rtol_id, atol_id);
            let (x, w_q, w_qd, w_inv) = gen.forward_dynamics_with_derivatives(&q, &qd, &tau);
            cmp(
                "with q̈",
                &col(x),
                &col(case.imp.forward_dynamics(&q, &qd, &tau)),
                rtol_id,
                atol_id,
            );
            cmp("with ∂q̈/∂q", &w_q, &fd_q, rtol_id, atol_id);
            cmp("with ∂q̈/∂q̇", &w_qd, &fd_qd, rtol_id, atol_id);
            cmp("with M⁻¹", &w_inv, &m_inv, rtol_id, atol_id);
            *worst = errs.iter().fold(*worst, |a, &b| a.max(b));
        }
    }
    assert!(
        DERIVATIVE_CASES.len() >= 30,
        "{} cases",
        DERIVATIVE_CASES.len()
    );
    assert!(floating >= 3, "{floating} floating-base cases");
    println!(
        "{} compiled cases ({floating} on a floating base); worst error / tolerance: f64 {:.3}, f32 {:.3}",
        DERIVATIVE_CASES.len(),
        worst[0],
        worst[1]
    );
}
