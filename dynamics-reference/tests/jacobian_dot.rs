//! `J̇_s`, `J̇_b` (Exercise 8.6) of the end effector and of extra frames on random trees, fixed
//! and floating, with and without mimic joints, against central differences of the Jacobians
//! along the configuration rate, and against each other through `J_b = [Ad_{T⁻¹}] J_s`.

mod common;

use common::random_chain::Rng;
use common::random_tree::trees_coupled;
use common::{check_tol, MaxErr};
use dynamics_model::lie::{ad, adjoint, trans_inv};
use dynamics_model::{Frame, Robot};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Vector6};

/// The end effector and one random frame on a random link (or on the base for a one-link tree
/// half of the time).
fn frames(rng: &mut Rng, robot: &Robot) -> Vec<Frame> {
    let n = robot.dof();
    let parent = if rng.unit() < 0.1 {
        None
    } else {
        Some((rng.unit() * n as f64) as usize % n)
    };
    vec![
        robot.end_effector.clone(),
        Frame {
            name: "extra".into(),
            parent,
            home: rng.transform(0.4),
        },
    ]
}

/// `(J(q + h q̇) − J(q − h q̇)) / 2h` with `q̇` the configuration rate.
fn central(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    j: impl Fn(&[f64]) -> DMatrix<f64>,
) -> DMatrix<f64> {
    let h = 1e-6;
    let rate = dr::configuration_rate(robot, q, qd);
    let qp: Vec<f64> = q.iter().zip(rate.iter()).map(|(a, b)| a + h * b).collect();
    let qm: Vec<f64> = q.iter().zip(rate.iter()).map(|(a, b)| a - h * b).collect();
    (j(&qp) - j(&qm)) / (2.0 * h)
}

#[test]
fn jacobian_rates_match_central_differences() {
    let mut rng = Rng::new(86);
    let mut max = MaxErr::default();
    let mut samples = trees_coupled(860, 18, 9, 0.0);
    samples.extend(trees_coupled(861, 18, 9, 0.4));
    for (k, s) in samples.iter().enumerate() {
        let robot = &s.robot;
        let label = format!(
            "tree {k} (floating {}, mimic {})",
            robot.base.floating,
            robot.has_mimic()
        );
        for (f, frame) in frames(&mut rng, robot).iter().enumerate() {
            let js_dot = dr::frame_jacobian_space_dot(robot, frame, &s.q, &s.qd);
            let jb_dot = dr::frame_jacobian_body_dot(robot, frame, &s.q, &s.qd);
            let fd_s = central(robot, &s.q, &s.qd, |q| {
                dr::frame_jacobian_space(robot, frame, q)
            });
            let fd_b = central(robot, &s.q, &s.qd, |q| {
                dr::frame_jacobian_body(robot, frame, q)
            });
            let scale_s = 1.0 + fd_s.amax();
            let scale_b = 1.0 + fd_b.amax();
            max.note(
                "J̇_s vs central differences",
                check_tol(
                    &format!("{label} frame {f} J̇_s"),
                    js_dot.as_slice(),
                    fd_s.as_slice(),
                    0.0,
                    1e-6 * scale_s,
                ) / scale_s,
            );
            max.note(
                "J̇_b vs central differences",
                check_tol(
                    &format!("{label} frame {f} J̇_b"),
                    jb_dot.as_slice(),
                    fd_b.as_slice(),
                    0.0,
                    1e-6 * scale_b,
                ) / scale_b,
            );
            // Columns off the frame's path stay exactly zero.
            let js = dr::frame_jacobian_space(robot, frame, &s.q);
            for c in 0..robot.nv() {
                if js.column(c).iter().all(|x| *x == 0.0) {
                    assert!(
                        js_dot.column(c).iter().all(|x| *x == 0.0),
                        "{label}: column {c}"
                    );
                    assert!(
                        jb_dot.column(c).iter().all(|x| *x == 0.0),
                        "{label}: column {c}"
                    );
                }
            }
            // J_b = [Ad_{T⁻¹}] J_s, so J̇_b = [Ad_{T⁻¹}] (J̇_s − [ad_{V_s}] J_s), V_s = J_s ν.
            let t = dr::frame_pose(robot, frame, &s.q);
            let v_s: Vector6<f64> =
                Vector6::from_iterator((&js * DVector::from_column_slice(&s.qd)).iter().copied());
            let ad_inv = adjoint(&trans_inv(&t));
            let want = DMatrix::from_fn(6, 6, |r, c| ad_inv[(r, c)])
                * (&js_dot - DMatrix::from_fn(6, 6, |r, c| ad(&v_s)[(r, c)]) * &js);
            let scale = 1.0 + want.amax();
            max.note(
                "J̇_b = Ad(J̇_s − ad J_s)",
                check_tol(
                    &format!("{label} frame {f} J̇_b from J̇_s"),
                    jb_dot.as_slice(),
                    want.as_slice(),
                    0.0,
                    1e-12 * scale,
                ) / scale,
            );
        }
        // The end-effector forms are the frame forms of the end effector.
        assert_eq!(
            dr::jacobian_space_dot(robot, &s.q, &s.qd),
            dr::frame_jacobian_space_dot(robot, &robot.end_effector, &s.q, &s.qd)
        );
        assert_eq!(
            dr::jacobian_body_dot(robot, &s.q, &s.qd),
            dr::frame_jacobian_body_dot(robot, &robot.end_effector, &s.q, &s.qd)
        );
    }
    max.report("Jacobian rates");
}

/// J̇ is linear in ν: `J̇(q, ν) = Σ_k J̇(q, e_k) ν_k`.
#[test]
fn jacobian_rates_are_linear_in_the_velocity() {
    for s in trees_coupled(870, 9, 7, 0.3) {
        let robot = &s.robot;
        let nv = robot.nv();
        let mut sum_s = DMatrix::zeros(6, nv);
        let mut sum_b = DMatrix::zeros(6, nv);
        for k in 0..nv {
            let mut e = vec![0.0; nv];
            e[k] = 1.0;
            sum_s += dr::jacobian_space_dot(robot, &s.q, &e) * s.qd[k];
            sum_b += dr::jacobian_body_dot(robot, &s.q, &e) * s.qd[k];
        }
        let js = dr::jacobian_space_dot(robot, &s.q, &s.qd);
        let jb = dr::jacobian_body_dot(robot, &s.q, &s.qd);
        check_tol("J̇_s linear", js.as_slice(), sum_s.as_slice(), 1e-12, 1e-13);
        check_tol("J̇_b linear", jb.as_slice(), sum_b.as_slice(), 1e-12, 1e-13);
    }
}
