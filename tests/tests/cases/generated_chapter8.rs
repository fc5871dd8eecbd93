//! The chapter-8 functions of every compiled robot (shipped, reference URDFs, seeded random
//! chains and trees with fixed and floating bases, mimic joints; f64 and f32) at seeded
//! random states:
//!
//! - against the reference implementation: `coriolis_matrix` (Christoffel symbols),
//!   `mass_matrix_and_bias` (`M` and `c + g`), `end_effector_forces` (`J_bᵀ F_tip`),
//!   `inverse_dynamics_with_tip` and `forward_dynamics_with_tip`;
//! - identities: `C q̇ = c`, `Ṁ − 2C` skew-symmetric; `Λ (J_b M⁻¹ J_bᵀ) = I` and
//!   `F = Λ V̇ + η` for the motion a tip wrench F produces through `τ = J_bᵀ F` (where
//!   `task_space_mass_matrix` is `Some`); `constrained_forward_dynamics` with K = 1, 2, 3
//!   random constraint rows: `A q̈ + Ȧ q̇ = 0` and `M q̈ + h = τ + Aᵀ λ`, and `None` for
//!   dependent rows.
//!
//! f64: ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12 (task space and constraints relative to the
//! conditioning of the matrix they invert); f32 (inputs rounded to f32): 1e-4, 1e-3 for
//! solves.

use dynamics_model::random::Rng;
use dynamics_tests::row_major;
use dynamics_tests::{Case, CASES};
use nalgebra::{DMatrix, DVector, Vector6};

fn check(case: &Case, what: &str, x: &[f64], y: &[f64], rtol: f64, atol: f64) -> f64 {
    let what = format!("{} {what}", case.module);
    let (err, scale) = dynamics_tests::assert_close(&what, x, y, rtol, atol);
    err / (rtol * scale + atol).max(1e-300)
}

#[test]
fn generated_chapter8_functions_equal_the_reference_and_satisfy_the_identities() {
    let mut worst = [0.0f64; 2];
    let (mut task, mut task_none, mut constrained) = (0, 0, 0);
    for case in CASES {
        let robot = case.spec.robot();
        let (nq, nv) = (robot.nq(), robot.nv());
        let f32 = case.scalar == "f32";
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let (rtol, rtol_solve, atol) = if f32 {
            (1e-4, 1e-3, 1e-5)
        } else {
            (1e-10, 1e-10, 1e-12)
        };
        let worst = &mut worst[usize::from(f32)];
        let mut rng = Rng::new(23);
        let g = robot.gravity;
        let zero6 = Vector6::zeros();
        for _ in 0..4 {
            let q: Vec<f64> = (0..nq).map(|_| round(rng.uniform(-3.0, 3.0))).collect();
            let qd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let qdd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let f: Vec<f64> = (0..6).map(|_| round(rng.uniform(-5.0, 5.0))).collect();
            let f_tip = Vector6::from_column_slice(&f);
            let cmp =
                |what: &str, x: &[f64], y: &[f64], rtol: f64| check(case, what, x, y, rtol, atol);
            let mut errs: Vec<f64> = Vec::new();
            // Against the reference.
            let c_ref = dynamics_reference::coriolis_matrix(&robot, &q, &qd);
            let c = case.imp.coriolis_matrix(&q, &qd);
            errs.push(cmp("C", &row_major(&c), &row_major(&c_ref), rtol));
            let m_ref = dynamics_reference::mass_matrix(&robot, &q);
            let zeros = vec![0.0; nv];
            let h_ref = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &zeros, &g, &zero6);
            let (m, h) = case.imp.mass_matrix_and_bias(&q, &qd);
            errs.push(cmp("M of (M, h)", &row_major(&m), &row_major(&m_ref), rtol));
            errs.push(cmp("h of (M, h)", h.as_slice(), h_ref.as_slice(), rtol));
            let ef = dynamics_reference::end_effector_forces(&robot, &q, &f_tip);
            errs.push(cmp(
                "J_bᵀF",
                case.imp.end_effector_forces(&q, &f).as_slice(),
                ef.as_slice(),
                rtol,
            ));
            // Friction, where the case generates it into the dynamics.
            let friction = case.spec.friction_in_dynamics(&robot, &qd);
            let ours = case.imp.friction(&qd);
            let reference = dynamics_reference::friction_forces(
                &robot,
                &qd,
                match case.spec {
                    dynamics_tests::Spec::Actuated(.., eps) => eps,
                    _ => None,
                },
            );
            errs.push(cmp("friction", ours.as_slice(), reference.as_slice(), rtol));
            let id =
                dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &f_tip) + &friction;
            let ours = case.imp.inverse_dynamics_with_tip(&q, &qd, &qdd, &f);
            errs.push(cmp("ID with tip", ours.as_slice(), id.as_slice(), rtol));
            let tau: Vec<f64> = id.iter().map(|&x| round(x)).collect();
            let tau_eff: Vec<f64> = tau.iter().zip(&friction).map(|(t, f)| t - f).collect();
            let fd = dynamics_reference::forward_dynamics(&robot, &q, &qd, &tau_eff, &g, &f_tip)
                .expect("M is positive definite");
            let ours = case.imp.forward_dynamics_with_tip(&q, &qd, &tau, &f);
            errs.push(cmp(
                "FD with tip",
                ours.as_slice(),
                fd.as_slice(),
                rtol_solve,
            ));

            // C q̇ = c and Ṁ − 2C skew-symmetric, on the generated functions alone.
            let qd_v = DVector::from_column_slice(&qd);
            let cq = &c * &qd_v;
            let c_vec = case.imp.coriolis(&q, &qd);
            errs.push(cmp("C q̇ = c", cq.as_slice(), c_vec.as_slice(), rtol));
            let n_mat = case.imp.mass_matrix_dot(&q, &qd) - 2.0 * &c;
            let skew = &n_mat + n_mat.transpose();
            let scale = n_mat.amax();
            errs.push(skew.amax() / (rtol * scale + atol));
            assert!(
                skew.amax() <= rtol * scale + atol,
                "{}: Ṁ − 2C not skew by {:e}",
                case.module,
                skew.amax()
            );

            // Task space: identities on the generated functions.
            let lambda = case.imp.task_space_mass_matrix(&q);
            let eta = case.imp.task_space_bias(&q, &qd);
            assert_eq!(lambda.is_some(), eta.is_some(), "{}", case.module);
            if nv < 6 {
                assert!(lambda.is_none(), "{}: Λ for nv < 6", case.module);
            }
            if let (Some(lambda), Some(eta)) = (lambda, eta) {
                task += 1;
                let jb = case.imp.jacobian_body(&q);
                let chol = m.clone().cholesky().expect("M positive definite");
                let a = &jb * chol.solve(&jb.transpose());
                let cond = a.norm() * lambda.norm();
                let prod = &lambda * &a;
                errs.push(cmp(
                    "ΛA = I",
                    &row_major(&prod),
                    &row_major(&DMatrix::identity(6, 6)),
                    rtol * cond.max(1.0),
                ));
                // (Plus the friction a case generates into forward dynamics, which η leaves
                // out.)
                let tau_f = case.imp.end_effector_forces(&q, &f) + &friction;
                let acc = case.imp.forward_dynamics(&q, &qd, tau_f.as_slice());
                let vdot = &jb * acc + case.imp.jacobian_body_dot(&q, &qd) * &qd_v;
                let back = &lambda * vdot + eta;
                errs.push(cmp(
                    "F = ΛV̇ + η",
                    back.as_slice(),
                    &f,
                    rtol_solve * cond.max(1.0),
                ));
            } else if nv >= 6 {
                task_none += 1;
            }

            // Constrained forward dynamics, K = 1..3 random rows.
            let k = 1 + (constrained % nv.min(3));
            let a = DMatrix::from_fn(k, nv, |_, _| round(rng.uniform(-1.0, 1.0)));
            let adq: Vec<f64> = (0..k).map(|_| round(rng.uniform(-1.0, 1.0))).collect();
            let (x, lambda) = case
                .imp
                .constrained_forward_dynamics(&q, &qd, &tau, &a, &adq)
                .unwrap_or_else(|| panic!("{}: independent constraints refused", case.module));
            constrained += 1;
            // Residuals, relative to the size of the terms (a backward-stable solve).
            let res = &a * &x + DVector::from_column_slice(&adq);
            let scale = (a.abs() * x.abs()).amax() + adq.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            errs.push(res.amax() / (rtol_solve * scale));
            assert!(
                res.amax() <= rtol_solve * scale,
                "{}: A q̈ + Ȧq̇ = {:e} (scale {scale:e})",
                case.module,
                res.amax()
            );
            let lhs = &m * &x + &h;
            let rhs = DVector::from_column_slice(&tau_eff) + a.transpose() * &lambda;
            errs.push(cmp(
                "M q̈ + h = τ + Aᵀλ",
                lhs.as_slice(),
                rhs.as_slice(),
                rtol_solve * 10.0,
            ));
            *worst = errs.iter().fold(*worst, |m, e| m.max(*e));
            // Dependent rows (a row repeated): None.
            if k == 1 {
                let twice = DMatrix::from_fn(2, nv, |_, j| a[(0, j)]);
                let none =
                    case.imp
                        .constrained_forward_dynamics(&q, &qd, &tau, &twice, &[adq[0], adq[0]]);
                assert!(
                    none.is_none(),
                    "{}: dependent constraints accepted",
                    case.module
                );
            }
        }
    }
    println!(
        "worst error / tolerance over {} cases: f64 {:.3}, f32 {:.3}; task space at {task} states ({task_none} None with nv ≥ 6); {constrained} constrained solves",
        CASES.len(),
        worst[0],
        worst[1]
    );
}

/// Power balance with friction along a simulated trajectory: on the compiled random trees
/// with armature and smoothed friction in the dynamics (fixed base), the generated
/// `forward_dynamics` integrated by RK4 (1 ms, 0.5 s) under a constant joint torque, with
/// the work `W = ∫ q̇ᵀ(τ − τ_f(q̇)) dt` integrated alongside: `K + P` (the generated energies)
/// changes by W, to 1e-6 of the energy that flowed (`∫ |q̇ᵀτ| + |q̇ᵀτ_f| dt`).
#[test]
fn generated_energy_balance_with_friction_along_a_trajectory() {
    let mut checked = 0;
    for case in CASES {
        let dynamics_tests::Spec::Actuated(_, _, false, Some(_)) = case.spec else {
            continue;
        };
        let robot = case.spec.robot();
        let n = robot.nv();
        let tau: Vec<f64> = (0..n).map(|i| 0.8 * ((i as f64) * 1.3).sin()).collect();
        // State (q, q̇, W, F): W the work, F the energy that flowed.
        let rate = |x: &[f64]| -> Vec<f64> {
            let (q, qd) = (&x[..n], &x[n..2 * n]);
            let qdd = case.imp.forward_dynamics(q, qd, &tau);
            let tf = case.imp.friction(qd);
            let p_in: f64 = (0..n).map(|i| qd[i] * tau[i]).sum();
            let p_f: f64 = (0..n).map(|i| qd[i] * tf[i]).sum();
            let mut d: Vec<f64> = qd.to_vec();
            d.extend(qdd.iter());
            d.push(p_in - p_f);
            d.push(p_in.abs() + p_f.abs());
            d
        };
        let energy = |x: &[f64]| {
            case.imp.kinetic_energy(&x[..n], &x[n..2 * n]) + case.imp.potential_energy(&x[..n])
        };
        let mut x: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64).cos()).collect();
        x.extend((0..n).map(|i| 0.5 - 0.1 * i as f64));
        x.extend([0.0, 0.0]);
        let e0 = energy(&x);
        let h = 1e-3;
        for _ in 0..500 {
            let k1 = rate(&x);
            let at = |k: &[f64], s: f64| -> Vec<f64> {
                x.iter().zip(k).map(|(a, b)| a + s * b).collect()
            };
            let k2 = rate(&at(&k1, h / 2.0));
            let k3 = rate(&at(&k2, h / 2.0));
            let k4 = rate(&at(&k3, h));
            for i in 0..x.len() {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        let (work, flow) = (x[2 * n], x[2 * n + 1]);
        let change = energy(&x) - e0;
        let err = (change - work).abs();
        println!(
            "{}: ΔE = {change:.6e}, ∫q̇ᵀ(τ − τ_f) = {work:.6e}, flow {flow:.3e}, error {:.2e} of the flow",
            case.module,
            err / flow
        );
        assert!(
            err <= 1e-6 * flow,
            "{}: energy balance off by {err:e}",
            case.module
        );
        checked += 1;
    }
    assert!(checked >= 1);
}
