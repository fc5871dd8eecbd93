//! Every compiled robot (shipped, reference URDFs, seeded random chains and trees with fixed
//! and floating bases, random trees and TALOS with mimic joints; f64 and f32) against
//! the reference implementation at seeded random states, for all five functions.
//!
//! f64: ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12. f32 (inputs rounded to f32 for both): ≤ 1e-4·‖y‖∞ for
//! M, c, g, τ and ≤ 1e-3·‖y‖∞ for forward dynamics.

use dynamics_model::random::Rng;
use dynamics_tests::{Case, CASES};
use nalgebra::{DVector, Vector6};

fn check(case: &Case, what: &str, x: &[f64], y: &[f64], rtol: f64, atol: f64) -> f64 {
    let what = format!("{} {what}", case.module);
    let (err, scale) = dynamics_tests::assert_close(&what, x, y, rtol, atol);
    err / scale.max(1e-300)
}

#[test]
fn generated_code_equals_the_reference_implementation() {
    let mut worst_by_scalar = [[0.0f64; 5]; 2];
    for case in CASES {
        let robot = case.spec.robot();
        let (n, nq, nv) = (robot.n_coordinates(), robot.nq(), robot.nv());
        assert_eq!(case.imp.dof(), n, "{}", case.module);
        assert_eq!((case.imp.nq(), case.imp.nv()), (nq, nv), "{}", case.module);
        assert_eq!(
            case.imp.joint_names(),
            robot.joint_names(),
            "{}",
            case.module
        );
        let f32 = case.scalar == "f32";
        let worst = &mut worst_by_scalar[usize::from(f32)];
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let (rtol, rtol_fd, atol) = if f32 {
            (1e-4, 1e-3, 0.0)
        } else {
            (1e-10, 1e-10, 1e-12)
        };
        let mut rng = Rng::new(7);
        let g = robot.gravity;
        let zero6 = Vector6::zeros();
        for _ in 0..8 {
            // On a floating base q[3..7] is a quaternion of any non-zero length.
            let q: Vec<f64> = (0..nq).map(|_| round(rng.uniform(-3.0, 3.0))).collect();
            let qd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let qdd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let m_ref = dynamics_reference::mass_matrix(&robot, &q);
            let m = case.imp.mass_matrix(&q);
            worst[0] = worst[0].max(check(case, "M", m.as_slice(), m_ref.as_slice(), rtol, atol));
            let c_ref = dynamics_reference::vel_quadratic_forces(&robot, &q, &qd);
            let c = case.imp.coriolis(&q, &qd);
            worst[1] = worst[1].max(check(case, "c", c.as_slice(), c_ref.as_slice(), rtol, atol));
            let g_ref = dynamics_reference::gravity_forces(&robot, &q, &g);
            let gg = case.imp.gravity(&q);
            worst[2] = worst[2].max(check(
                case,
                "g",
                gg.as_slice(),
                g_ref.as_slice(),
                rtol,
                atol,
            ));
            let tau_ref = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &zero6);
            let tau = case.imp.inverse_dynamics(&q, &qd, &qdd);
            worst[3] = worst[3].max(check(
                case,
                "τ",
                tau.as_slice(),
                tau_ref.as_slice(),
                rtol,
                atol,
            ));
            let tau_in: Vec<f64> = tau_ref.iter().map(|&x| round(x)).collect();
            let fd_ref = dynamics_reference::forward_dynamics(&robot, &q, &qd, &tau_in, &g, &zero6)
                .expect("M is positive definite");
            let fd: DVector<f64> = case.imp.forward_dynamics(&q, &qd, &tau_in);
            worst[4] = worst[4].max(check(
                case,
                "q̈",
                fd.as_slice(),
                fd_ref.as_slice(),
                rtol_fd,
                atol,
            ));
        }
    }
    println!(
        "worst relative errors (M, c, g, τ, q̈) over {} cases: f64 {:?}, f32 {:?}",
        CASES.len(),
        worst_by_scalar[0],
        worst_by_scalar[1]
    );
}
