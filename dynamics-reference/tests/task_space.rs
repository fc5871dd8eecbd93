//! The task-space mass matrix Λ and bias η of the end effector (Modern Robotics §8.6) on
//! random chains (6–10 joints, redundant ones included), floating trees and mimic trees, with
//! armature: `Λ A = 1` for `A = J_b M⁻¹ J_bᵀ`, and `F = Λ V̇_b + η` with `V̇_b` from forward
//! dynamics; the singularity contract (nv < 6, wrist singularity, short paths).

mod common;

use common::random_chain::{random_robot, random_state, Rng};
use common::random_tree::trees_coupled;
use common::{check_tol, with_actuation, MaxErr};
use dynamics_model::{LoadOptions, Robot};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

struct Case {
    robot: Robot,
    q: Vec<f64>,
    qd: Vec<f64>,
}

/// Random chains of 6..=10 joints and random floating trees (nv ≥ 7), some with mimic joints,
/// all with random armature.
fn cases() -> Vec<Case> {
    let mut rng = Rng::new(806);
    let mut out = Vec::new();
    for n in [6, 7, 8, 9, 10, 6, 7] {
        let bare = random_robot(&mut rng, n);
        let robot = with_actuation(&mut rng, bare);
        let (q, qd, _) = random_state(&mut rng, &robot);
        out.push(Case { robot, q, qd });
    }
    for s in trees_coupled(807, 12, 8, 0.0)
        .into_iter()
        .chain(trees_coupled(808, 12, 8, 0.4))
        .filter(|s| s.robot.base.floating)
    {
        let robot = with_actuation(&mut rng, s.robot);
        out.push(Case {
            robot,
            q: s.q,
            qd: s.qd,
        });
    }
    out
}

fn dyn6(m: &Matrix6<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |r, c| m[(r, c)])
}

#[test]
fn lambda_inverts_j_minv_jt() {
    let mut max = MaxErr::default();
    let mut count = 0;
    for (k, c) in cases().iter().enumerate() {
        let robot = &c.robot;
        let m = dr::mass_matrix(robot, &c.q);
        let j_b = dr::jacobian_body(robot, &c.q);
        let a = &j_b * m.clone().try_inverse().expect("M invertible") * j_b.transpose();
        let Some(lambda) = dr::task_space_mass_matrix(robot, &c.q) else {
            panic!("case {k}: unexpected singularity");
        };
        count += 1;
        let lambda = dyn6(&lambda);
        assert_eq!(lambda, lambda.transpose(), "case {k}: Λ symmetric");
        let prod = &lambda * &a;
        // Conditioned by A: the residual of a backward-stable solve is ε·cond(A).
        let cond = {
            let e = a.clone().symmetric_eigenvalues();
            e.max() / e.min()
        };
        let err = (prod - DMatrix::identity(6, 6)).amax();
        assert!(
            err <= 1e-13 * cond.max(1.0),
            "case {k}: ‖ΛA − 1‖ = {err:e}, cond(A) = {cond:e}"
        );
        max.note("‖ΛA − 1‖∞ / cond(A)", err / cond.max(1.0));
        max.note("‖ΛA − 1‖∞", err);
    }
    assert!(count >= 15, "{count} cases");
    max.report("task-space mass matrix");
}

#[test]
fn bias_gives_the_wrench_that_accelerates_the_end_effector() {
    let mut rng = Rng::new(8061);
    let mut max = MaxErr::default();
    for (k, c) in cases().iter().enumerate() {
        let robot = &c.robot;
        let g = robot.gravity;
        let nv = robot.nv();
        let lambda = dyn6(&dr::task_space_mass_matrix(robot, &c.q).expect("regular"));
        let eta = dr::task_space_bias(robot, &c.q, &c.qd, &g).expect("regular");
        let eta = DVector::from_column_slice(eta.as_slice());
        let m = dr::mass_matrix(robot, &c.q);
        let m_inv = m.clone().try_inverse().expect("M invertible");
        let j_b = dr::jacobian_body(robot, &c.q);
        let jd_qd = dr::jacobian_body_dot(robot, &c.q, &c.qd) * DVector::from_column_slice(&c.qd);
        let v_dot = |tau: &DVector<f64>| -> DVector<f64> {
            let qdd =
                dr::forward_dynamics(robot, &c.q, &c.qd, tau.as_slice(), &g, &Vector6::zeros())
                    .expect("M positive definite");
            &j_b * qdd + &jd_qd
        };
        // τ = J_bᵀ F + τ₀ with τ₀ in the dynamically consistent null space (J_b M⁻¹ τ₀ = 0).
        let f = DVector::from_vec(rng.vector(6, -5.0, 5.0));
        let z = DVector::from_vec(rng.vector(nv, -2.0, 2.0));
        let j_bar_t = &lambda * &j_b * &m_inv; // J̄ᵀ = Λ J_b M⁻¹
        let tau0 = &z - j_b.transpose() * (&j_bar_t * &z);
        let tau = j_b.transpose() * &f + tau0;
        let got = &lambda * v_dot(&tau) + &eta;
        let scale = 1.0 + f.amax();
        max.note(
            "ΛV̇ + η = F",
            check_tol(
                &format!("case {k}: F"),
                got.as_slice(),
                f.as_slice(),
                0.0,
                1e-9 * scale,
            ) / scale,
        );
        // Any τ: ΛV̇ + η = Λ J_b M⁻¹ τ.
        let tau = DVector::from_vec(rng.vector(nv, -5.0, 5.0));
        let got = &lambda * v_dot(&tau) + &eta;
        let want = &j_bar_t * &tau;
        let scale = 1.0 + want.amax();
        max.note(
            "ΛV̇ + η = ΛJ_bM⁻¹τ",
            check_tol(
                &format!("case {k}: any τ"),
                got.as_slice(),
                want.as_slice(),
                0.0,
                1e-9 * scale,
            ) / scale,
        );
        // At rest without gravity η = 0; at rest with gravity η = Λ J_b M⁻¹ g.
        let rest = vec![0.0; nv];
        let eta0 =
            dr::task_space_bias(robot, &c.q, &rest, &nalgebra::Vector3::zeros()).expect("regular");
        assert!(
            eta0.amax() == 0.0,
            "case {k}: η at rest without gravity = {eta0}"
        );
    }
    max.report("task-space bias");
}

#[test]
fn singularities_give_none() {
    let mut rng = Rng::new(8062);
    // nv < 6.
    for n in 1..6 {
        let robot = random_robot(&mut rng, n);
        let (q, qd, _) = random_state(&mut rng, &robot);
        assert!(dr::task_space_mass_matrix(&robot, &q).is_none(), "n = {n}");
        assert!(
            dr::task_space_bias(&robot, &q, &qd, &robot.gravity).is_none(),
            "n = {n}"
        );
    }
    // The UR5: regular at a generic q, wrist-singular at θ5 = 0 (and at home).
    let ur5 = dynamics_model::load("ur5", &LoadOptions::default()).expect("shipped");
    let q = [0.3, -1.1, 1.4, -0.7, 0.9, 0.2];
    assert!(dr::task_space_mass_matrix(&ur5, &q).is_some());
    let mut wrist = q;
    wrist[4] = 0.0;
    assert!(dr::task_space_mass_matrix(&ur5, &wrist).is_none());
    assert!(dr::task_space_bias(&ur5, &wrist, &[0.1; 6], &ur5.gravity).is_none());
    assert!(dr::task_space_mass_matrix(&ur5, &[0.0; 6]).is_none());
    // A fixed-base tree with more than six joints whose end effector sits behind fewer than
    // six of them: A has rank < 6.
    for s in trees_coupled(809, 30, 12, 0.0) {
        let r = &s.robot;
        if !r.base.floating && r.nv() >= 6 && r.frame_path(&r.end_effector).len() < 6 {
            assert!(dr::task_space_mass_matrix(r, &s.q).is_none());
        }
    }
}
