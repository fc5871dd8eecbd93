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

/// `case`'s five functions against the reference at one state `(q, q̇, q̈)` (rounded to the
/// case's scalar already), to `scale` times the usual relative tolerances, the worst relative
/// errors of each kept in `worst`.
fn compare_at(
    case: &Case,
    robot: &dynamics_model::Robot,
    [q, qd, qdd]: [&[f64]; 3],
    scale: f64,
    worst: &mut [f64; 5],
) {
    let f32 = case.scalar == "f32";
    let round = |x: f64| if f32 { x as f32 as f64 } else { x };
    let (rtol, rtol_fd, atol) = if f32 {
        (1e-4 * scale, 1e-3 * scale, 0.0)
    } else {
        (1e-10 * scale, 1e-10 * scale, 1e-12)
    };
    let g = robot.gravity;
    let zero6 = Vector6::zeros();
    let m_ref = dynamics_reference::mass_matrix(robot, q);
    let m = case.imp.mass_matrix(q);
    worst[0] = worst[0].max(check(case, "M", m.as_slice(), m_ref.as_slice(), rtol, atol));
    // In place: `M`'s lower triangle, the same bits, and nothing else written (the strict
    // upper triangle, and a tree's structural zeros, keep what `m` held).
    let held = -123.5;
    let nv = m.nrows();
    let lower = case
        .imp
        .mass_matrix_lower_into(q, &nalgebra::DMatrix::from_element(nv, nv, held));
    for c in 0..nv {
        for r in 0..nv {
            let (x, want) = (lower[(r, c)], m[(r, c)]);
            let ok = if r < c {
                x == held
            } else {
                x.to_bits() == want.to_bits() || (x == held && want == 0.0)
            };
            assert!(
                ok,
                "{} mass_matrix_lower_into ({r}, {c}): {x}, M has {want}",
                case.module
            );
        }
    }
    let c_ref = dynamics_reference::vel_quadratic_forces(robot, q, qd);
    let c = case.imp.coriolis(q, qd);
    worst[1] = worst[1].max(check(case, "c", c.as_slice(), c_ref.as_slice(), rtol, atol));
    let g_ref = dynamics_reference::gravity_forces(robot, q, &g);
    let gg = case.imp.gravity(q);
    worst[2] = worst[2].max(check(
        case,
        "g",
        gg.as_slice(),
        g_ref.as_slice(),
        rtol,
        atol,
    ));
    let friction = case.spec.friction_in_dynamics(robot, qd);
    let tau_ref = dynamics_reference::inverse_dynamics(robot, q, qd, qdd, &g, &zero6) + &friction;
    let tau = case.imp.inverse_dynamics(q, qd, qdd);
    worst[3] = worst[3].max(check(
        case,
        "τ",
        tau.as_slice(),
        tau_ref.as_slice(),
        rtol,
        atol,
    ));
    let tau_in: Vec<f64> = tau_ref.iter().map(|&x| round(x)).collect();
    let tau_eff: Vec<f64> = tau_in.iter().zip(&friction).map(|(t, f)| t - f).collect();
    let fd_ref = dynamics_reference::forward_dynamics(robot, q, qd, &tau_eff, &g, &zero6)
        .expect("M is positive definite");
    let fd: DVector<f64> = case.imp.forward_dynamics(q, qd, &tau_in);
    worst[4] = worst[4].max(check(
        case,
        "q̈",
        fd.as_slice(),
        fd_ref.as_slice(),
        rtol_fd,
        atol,
    ));
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
        let mut rng = Rng::new(7);
        for _ in 0..8 {
            // On a floating base q[3..7] is a quaternion of any non-zero length.
            let q: Vec<f64> = (0..nq).map(|_| round(rng.uniform(-3.0, 3.0))).collect();
            let qd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let qdd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            compare_at(case, &robot, [&q, &qd, &qdd], 1.0, worst);
        }
    }
    println!(
        "worst relative errors (M, c, g, τ, q̈) over {} cases: f64 {:?}, f32 {:?}",
        CASES.len(),
        worst_by_scalar[0],
        worst_by_scalar[1]
    );
}

/// A joint angle beyond the sines' bound (10⁶ rad in f64, 10⁴ in f32), where the dispatched
/// copies return what their `*_far` function computes (the same fused body with the kernel's
/// fallback in line): every case's five functions still equal the reference, with its last
/// revolute joint's coordinate moved by ±1.5·10⁶ (f32: ±1.2·10⁴), to 1,000 times the usual
/// tolerances (a case without one is skipped). An angle
/// that large is known to its last bit only, 2.3·10⁻¹⁰ rad (f32: 10⁻³), a home offset added to
/// it (`q + θ₀`, rounded) moves it by as much, and forward dynamics magnifies it (q̈ 6.4·10⁻⁸
/// at worst over the test robots, 2026-12-03).
#[test]
fn angles_beyond_the_sines_bound_equal_the_reference() {
    let mut worst_by_scalar = [[0.0f64; 5]; 2];
    for case in CASES {
        let robot = case.spec.robot();
        let (nq, nv) = (robot.nq(), robot.nv());
        let f32 = case.scalar == "f32";
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let far = if f32 { 1.2e4 } else { 1.5e6 };
        // The last revolute joint's coordinate: a prismatic one has no sine (and moved by
        // kilometres, its links' lever arms leave f32 no digits).
        let base = if robot.base.floating { 7 } else { 0 };
        let Some(k) = robot
            .joints
            .iter()
            .filter(|j| j.mimic.is_none())
            .enumerate()
            .filter(|(_, j)| j.kind == dynamics_model::JointKind::Revolute)
            .map(|(k, _)| base + k)
            .last()
        else {
            continue;
        };
        let mut rng = Rng::new(11);
        for sign in [1.0, -1.0] {
            let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
            q[k] += sign * far;
            let q: Vec<f64> = q.into_iter().map(round).collect();
            let qd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            let qdd: Vec<f64> = (0..nv).map(|_| round(rng.uniform(-2.0, 2.0))).collect();
            compare_at(
                case,
                &robot,
                [&q, &qd, &qdd],
                1000.0,
                &mut worst_by_scalar[usize::from(f32)],
            );
        }
    }
    println!(
        "worst relative errors (M, c, g, τ, q̈) beyond the bound: f64 {:?}, f32 {:?}",
        worst_by_scalar[0], worst_by_scalar[1]
    );
}

/// The kinetic and potential energies, the end effector's pose and Jacobians, and those of
/// every named frame, against the reference implementation (`kinetic_energy`,
/// `potential_energy`, `frame_pose`, `frame_jacobian_space`, `frame_jacobian_body`); same
/// tolerances as M (P relative to its own size plus that of g, since P can be near zero at
/// the origin of {0}).
#[test]
fn generated_kinematics_equals_the_reference_implementation() {
    let mut worst_by_scalar = [0.0f64; 2];
    let mut frames = 0;
    for case in CASES {
        let robot = case.spec.robot();
        let names: Vec<&str> = robot.frames.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(case.imp.frame_names(), names, "{}", case.module);
        frames += names.len();
        let f32 = case.scalar == "f32";
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let (rtol, atol) = if f32 { (1e-4, 0.0) } else { (1e-10, 1e-12) };
        let worst = &mut worst_by_scalar[usize::from(f32)];
        let mut rng = Rng::new(11);
        for _ in 0..4 {
            let q: Vec<f64> = (0..robot.nq())
                .map(|_| round(rng.uniform(-3.0, 3.0)))
                .collect();
            let p = dynamics_reference::potential_energy(&robot, &q, &robot.gravity);
            // P is measured from the origin of {0}: its scale is that of m g · height.
            let scale = dynamics_reference::gravity_forces(&robot, &q, &robot.gravity).amax();
            let (x, y) = (case.imp.potential_energy(&q), p);
            *worst = worst.max((x - y).abs() / (scale + y.abs()));
            assert!(
                (x - y).abs() <= rtol * (scale + y.abs()) + atol,
                "{} P: {x} vs {y}",
                case.module
            );
            let mut compare = |what: &str, x: &[f64], y: &[f64]| {
                *worst = worst.max(check(case, what, x, y, rtol, atol));
            };
            let qd: Vec<f64> = (0..robot.nv())
                .map(|_| round(rng.uniform(-2.0, 2.0)))
                .collect();
            let k = dynamics_reference::kinetic_energy(&robot, &q, &qd);
            compare("K", &[case.imp.kinetic_energy(&q, &qd)], &[k]);
            let ee = &robot.end_effector;
            let pose = dynamics_reference::frame_pose(&robot, ee, &q);
            compare(
                "pose",
                case.imp.end_effector_pose(&q).as_slice(),
                pose.as_slice(),
            );
            let j_s = dynamics_reference::frame_jacobian_space(&robot, ee, &q);
            compare(
                "J_s",
                case.imp.jacobian_space(&q).as_slice(),
                j_s.as_slice(),
            );
            let j_b = dynamics_reference::frame_jacobian_body(&robot, ee, &q);
            compare("J_b", case.imp.jacobian_body(&q).as_slice(), j_b.as_slice());
            let poses = case.imp.frame_poses(&q);
            let spaces = case.imp.frame_jacobians_space(&q);
            let bodies = case.imp.frame_jacobians_body(&q);
            assert_eq!(poses.len(), robot.frames.len());
            for (k, f) in robot.frames.iter().enumerate() {
                let what = |w: &str| format!("frame {} {w}", f.name);
                let pose = dynamics_reference::frame_pose(&robot, f, &q);
                compare(&what("pose"), poses[k].as_slice(), pose.as_slice());
                let j_s = dynamics_reference::frame_jacobian_space(&robot, f, &q);
                compare(&what("J_s"), spaces[k].as_slice(), j_s.as_slice());
                let j_b = dynamics_reference::frame_jacobian_body(&robot, f, &q);
                compare(&what("J_b"), bodies[k].as_slice(), j_b.as_slice());
            }
        }
    }
    assert!(frames > 30, "{frames} named frames");
    println!(
        "worst relative errors of poses and Jacobians over {} cases ({frames} named frames): f64 {:e}, f32 {:e}",
        CASES.len(),
        worst_by_scalar[0],
        worst_by_scalar[1]
    );
}

/// `∂P/∂q = g(q)` and `K = ½ q̇ᵀ M q̇` on the generated code itself: central differences of
/// `potential_energy` against `gravity` (fixed bases, f64; on a floating base g is taken along
/// the base's body twist, not along q), to 1e-6 relative.
#[test]
fn generated_energies_satisfy_the_identities() {
    let mut worst = 0.0f64;
    for case in CASES.iter().filter(|c| c.scalar == "f64") {
        let robot = case.spec.robot();
        let mut rng = Rng::new(5);
        for _ in 0..3 {
            let q: Vec<f64> = (0..robot.nq()).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let qd: Vec<f64> = (0..robot.nv()).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let m = case.imp.mass_matrix(&q);
            let v = DVector::from_column_slice(&qd);
            let k = 0.5 * v.dot(&(&m * &v));
            worst = worst.max(check(
                case,
                "K",
                &[case.imp.kinetic_energy(&q, &qd)],
                &[k],
                1e-12,
                0.0,
            ));
            if robot.base.floating {
                continue;
            }
            let g = case.imp.gravity(&q);
            let h = 1e-6;
            let dp: Vec<f64> = (0..q.len())
                .map(|i| {
                    let (mut a, mut b) = (q.clone(), q.clone());
                    a[i] += h;
                    b[i] -= h;
                    (case.imp.potential_energy(&a) - case.imp.potential_energy(&b)) / (2.0 * h)
                })
                .collect();
            worst = worst.max(check(case, "∂P/∂q", &dp, g.as_slice(), 1e-6, 1e-9));
        }
    }
    println!("energy identities: worst relative error {worst:e}");
}

/// `Ṁ` against the reference's `mass_matrix_dot` (same tolerances as M), and `J̇_s`, `J̇_b`
/// against central differences of the generated `jacobian_space`, `jacobian_body` along the
/// configuration rate (`q ± h q̇`, q̇ from `configuration_rate`, so quaternions included; f64,
/// 1e-6 relative).
#[test]
fn generated_time_derivatives_are_the_derivatives() {
    let (mut worst_m, mut worst_j) = ([0.0f64; 2], 0.0f64);
    for case in CASES {
        let robot = case.spec.robot();
        let f32 = case.scalar == "f32";
        let round = |x: f64| if f32 { x as f32 as f64 } else { x };
        let (rtol, atol) = if f32 { (1e-4, 0.0) } else { (1e-10, 1e-12) };
        let mut rng = Rng::new(13);
        for _ in 0..3 {
            let q: Vec<f64> = (0..robot.nq())
                .map(|_| round(rng.uniform(-3.0, 3.0)))
                .collect();
            let qd: Vec<f64> = (0..robot.nv())
                .map(|_| round(rng.uniform(-2.0, 2.0)))
                .collect();
            let m_dot = dynamics_reference::mass_matrix_dot(&robot, &q, &qd);
            let ours = case.imp.mass_matrix_dot(&q, &qd);
            let err = check(case, "Ṁ", ours.as_slice(), m_dot.as_slice(), rtol, atol);
            worst_m[usize::from(f32)] = worst_m[usize::from(f32)].max(err);
            if f32 {
                continue;
            }
            let rate = dynamics_reference::configuration_rate(&robot, &q, &qd);
            let h = 1e-6;
            let at = |s: f64| -> Vec<f64> {
                q.iter().zip(rate.iter()).map(|(x, r)| x + s * r).collect()
            };
            let (a, b) = (at(h), at(-h));
            let fd = |f: &dyn Fn(&[f64]) -> nalgebra::DMatrix<f64>| (f(&a) - f(&b)) / (2.0 * h);
            let js = fd(&|x| case.imp.jacobian_space(x));
            let jb = fd(&|x| case.imp.jacobian_body(x));
            let scale = |j: &nalgebra::DMatrix<f64>| j.amax() + case.imp.jacobian_space(&q).amax();
            let ours = case.imp.jacobian_space_dot(&q, &qd);
            let err = (&ours - &js).amax() / scale(&js);
            assert!(err < 1e-6, "{} J̇_s: {err:e}", case.module);
            worst_j = worst_j.max(err);
            let ours = case.imp.jacobian_body_dot(&q, &qd);
            let err = (&ours - &jb).amax() / scale(&jb);
            assert!(err < 1e-6, "{} J̇_b: {err:e}", case.module);
            worst_j = worst_j.max(err);
        }
    }
    println!(
        "Ṁ vs reference: worst relative f64 {:e}, f32 {:e}; J̇ (f64) vs central differences: worst relative {worst_j:e}",
        worst_m[0], worst_m[1]
    );
}
