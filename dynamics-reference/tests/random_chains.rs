//! Identities of rigid-body dynamics on 240 seeded random chains (1–12 joints, revolute and
//! prismatic, random axes, home frames and non-COM-frame inertias; see `common/random_chain.rs`).
//! None of these compares the reference with itself through the same formula: each identity
//! links two different algorithms (CRBA vs Newton–Euler, Cholesky solve vs Newton–Euler,
//! closed-form Ṁ vs finite differences, Christoffel C vs Newton–Euler c, …).

mod common;

use common::random_chain::{chains, Sample};
use common::{check, check_tol, MaxErr};
use dynamics_model::lie::{adjoint, trans_inv};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

const SEED: u64 = 0x5EED_D1CE;
const COUNT: usize = 240;

fn samples() -> Vec<Sample> {
    chains(SEED, COUNT)
}

fn unit(n: usize, j: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[j] = 1.0;
    e
}

fn amax(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// M is symmetric and positive definite (Cholesky succeeds, smallest eigenvalue > 0).
#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    let mut min_ratio = f64::INFINITY;
    for (k, s) in samples().iter().enumerate() {
        let m = dr::mass_matrix(&s.robot, &s.q);
        assert_eq!(m, m.transpose(), "chain {k}: M not symmetric");
        assert!(
            m.clone().cholesky().is_some(),
            "chain {k}: Cholesky of M fails"
        );
        let eig = m.symmetric_eigenvalues();
        assert!(eig.min() > 0.0, "chain {k}: eigenvalues {eig}");
        min_ratio = min_ratio.min(eig.min() / eig.max());
    }
    eprintln!("random chains: smallest eigenvalue ratio of M seen {min_ratio:.3e}");
}

/// Column j of M = ID(θ, θ̇, e_j) − ID(θ, θ̇, 0) (with gravity and a tip wrench on), and
/// = ID(θ, 0, e_j) with g = 0, F_tip = 0: the CRBA equals Newton–Euler.
#[test]
fn crba_equals_newton_euler_columns() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let (r, n) = (&s.robot, s.robot.dof());
        let g = r.gravity;
        let m = dr::crba(r, &s.q);
        let zero = vec![0.0; n];
        let bias = dr::rnea(r, &s.q, &s.qd, &zero, &g, &s.f_tip);
        for j in 0..n {
            let e_j = unit(n, j);
            let col = m.column(j).into_owned();
            let diff = dr::rnea(r, &s.q, &s.qd, &e_j, &g, &s.f_tip) - &bias;
            // The difference of two large torques: allow rounding relative to them too.
            let abs = 1e-13 * amax(bias.as_slice()).max(1.0);
            let e1 = check_tol(
                &format!("chain {k} column {j}: ID(e_j) − ID(0)"),
                diff.as_slice(),
                col.as_slice(),
                1e-9,
                abs,
            );
            let unit_acc = dr::rnea(r, &s.q, &zero, &e_j, &Vector3::zeros(), &Vector6::zeros());
            let e2 = check(
                &format!("chain {k} column {j}: ID(θ, 0, e_j)"),
                unit_acc.as_slice(),
                col.as_slice(),
            );
            max.note("ID(e_j) − ID(0)", e1);
            max.note("ID(θ, 0, e_j), g = 0", e2);
        }
    }
    max.report("random chains");
}

/// forward_dynamics(θ, θ̇, ID(θ, θ̇, θ̈)) = θ̈, with gravity and a tip wrench.
#[test]
fn forward_dynamics_inverts_inverse_dynamics() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let qdd = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &s.f_tip).unwrap();
        // Solving with M loses up to cond(M)·ε; scale the tolerance by cond(M) / 1e3.
        let eig = dr::mass_matrix(r, &s.q).symmetric_eigenvalues();
        let rel = 1e-9 * (eig.max() / eig.min() / 1e3).max(1.0);
        let e = check_tol(
            &format!("chain {k} FD(ID(θ̈))"),
            qdd.as_slice(),
            &s.qdd,
            rel,
            1e-12,
        );
        max.note("FD(ID(θ̈)) − θ̈", e);
    }
    max.report("random chains");
}

/// end_effector_forces = J_bᵀ F_tip = ID(θ, 0, 0, g = 0, F_tip), and J_b = [Ad_{T⁻¹}] J_s with
/// T the end-effector pose; the last link pose times M_{n,n+1} is the end-effector pose.
#[test]
fn jacobians_and_tip_wrench() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let (r, n) = (&s.robot, s.robot.dof());
        let zero = vec![0.0; n];
        let via_id = dr::inverse_dynamics(r, &s.q, &zero, &zero, &Vector3::zeros(), &s.f_tip);
        let via_j = dr::end_effector_forces(r, &s.q, &s.f_tip);
        max.note(
            "J_bᵀF − ID(0,0,0,F)",
            check(
                &format!("chain {k} J_bᵀ F_tip"),
                via_j.as_slice(),
                via_id.as_slice(),
            ),
        );

        let t = dr::end_effector_pose(r, &s.q);
        let j_s = dr::jacobian_space(r, &s.q);
        let j_b = dr::jacobian_body(r, &s.q);
        let ad_inv = adjoint(&trans_inv(&t));
        let from_s = DMatrix::from_fn(6, n, |i, j| {
            (0..6).map(|l| ad_inv[(i, l)] * j_s[(l, j)]).sum()
        });
        max.note(
            "J_b − Ad_{T⁻¹} J_s",
            check(&format!("chain {k} J_b"), j_b.as_slice(), from_s.as_slice()),
        );

        let last = dr::link_poses(r, &s.q)[n - 1] * r.end_effector.home;
        max.note(
            "T_0n M_{n,n+1} − T",
            check(
                &format!("chain {k} link poses"),
                last.as_slice(),
                t.as_slice(),
            ),
        );
    }
    max.report("random chains");
}

/// `[V_s] = Ṫ T⁻¹` with `V_s = J_s θ̇`, Ṫ by central differences along θ̇ (step 1e-6).
#[test]
fn space_jacobian_matches_pose_derivative() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let r = &s.robot;
        let shift = |sign: f64| -> Vec<f64> {
            s.q.iter()
                .zip(&s.qd)
                .map(|(a, b)| a + sign * h * b)
                .collect()
        };
        let t_dot = (dr::end_effector_pose(r, &shift(1.0))
            - dr::end_effector_pose(r, &shift(-1.0)))
            / (2.0 * h);
        let vs = t_dot * trans_inv(&dr::end_effector_pose(r, &s.q));
        let fd = [
            vs[(2, 1)],
            vs[(0, 2)],
            vs[(1, 0)],
            vs[(0, 3)],
            vs[(1, 3)],
            vs[(2, 3)],
        ];
        let j = dr::jacobian_space(r, &s.q) * DVector::from_column_slice(&s.qd);
        for (x, y) in fd.iter().zip(j.iter()) {
            assert!(
                (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                "chain {k}: J_s θ̇ {y} vs difference {x}"
            );
            max.note("J_s θ̇ − central difference", (x - y).abs());
        }
    }
    max.report("random chains");
}

/// `c = C θ̇` (Christoffel C from exact ∂M/∂θ_k vs Newton–Euler c), `Ṁ − 2C` skew, and the
/// closed-form Ṁ against central differences of M along θ̇ (step 1e-6, ≤ 1e-7·max(1, |x|)).
#[test]
fn coriolis_matrix_and_mass_matrix_dot() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let r = &s.robot;
        let qd = DVector::from_column_slice(&s.qd);
        let c_mat = dr::coriolis_matrix(r, &s.q, &s.qd);
        let c = dr::vel_quadratic_forces(r, &s.q, &s.qd);
        max.note(
            "C θ̇ − c",
            check(
                &format!("chain {k} C θ̇"),
                (&c_mat * &qd).as_slice(),
                c.as_slice(),
            ),
        );

        let mdot = dr::mass_matrix_dot(r, &s.q, &s.qd);
        let n_mat = &mdot - &c_mat * 2.0;
        let skew = (&n_mat + n_mat.transpose()).amax();
        let scale = mdot.amax().max(c_mat.amax()).max(1.0);
        assert!(
            skew <= 1e-12 * scale,
            "chain {k}: Ṁ − 2C not skew: {skew:e} (scale {scale:e})"
        );
        max.note("skew(Ṁ − 2C) / scale", skew / scale);

        let shift = |sign: f64| -> Vec<f64> {
            s.q.iter()
                .zip(&s.qd)
                .map(|(a, b)| a + sign * h * b)
                .collect()
        };
        let fd = (dr::mass_matrix(r, &shift(1.0)) - dr::mass_matrix(r, &shift(-1.0))) / (2.0 * h);
        for (x, y) in fd.iter().zip(mdot.iter()) {
            assert!(
                (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                "chain {k}: Ṁ {y} vs central difference {x}"
            );
            max.note("Ṁ − central difference", (x - y).abs() / y.abs().max(1.0));
        }
    }
    max.report("random chains");
}

/// Power balance `θ̇ᵀ(M θ̈ + ½ Ṁ θ̇ + g) = θ̇ᵀ τ` with θ̈ from forward dynamics of a random τ
/// (no tip wrench): `d/dt(K + P) = θ̇ᵀ τ`, which holds because `c = C θ̇` and `Ṁ − 2C` is skew.
#[test]
fn power_balance() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let tau = DVector::from_column_slice(&s.qdd) * 3.0; // any torque
        let tip = Vector6::zeros();
        let qdd = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &tip).unwrap();
        let qd = DVector::from_column_slice(&s.qd);
        let m = dr::mass_matrix(r, &s.q);
        let mdot = dr::mass_matrix_dot(r, &s.q, &s.qd);
        let grav = dr::gravity_forces(r, &s.q, &g);
        let terms = [&m * &qdd, &mdot * &qd * 0.5, grav];
        let lhs: f64 = terms.iter().map(|t| qd.dot(t)).sum();
        let rhs = qd.dot(&tau);
        let scale: f64 =
            terms.iter().map(|t| qd.abs().dot(&t.abs())).sum::<f64>() + qd.abs().dot(&tau.abs());
        assert!(
            (lhs - rhs).abs() <= 1e-11 * scale.max(1.0),
            "chain {k}: power {lhs} vs {rhs}"
        );
        max.note("power balance / scale", (lhs - rhs).abs() / scale.max(1.0));
    }
    max.report("random chains");
}

/// `g(θ) = ∂P/∂θ` with P from the link centres of mass, by central differences (step 1e-6).
#[test]
fn gravity_forces_are_the_potential_gradient() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let grav = dr::gravity_forces(r, &s.q, &g);
        for i in 0..r.dof() {
            let mut qp = s.q.clone();
            let mut qm = s.q.clone();
            qp[i] += h;
            qm[i] -= h;
            let fd =
                (dr::potential_energy(r, &qp, &g) - dr::potential_energy(r, &qm, &g)) / (2.0 * h);
            assert!(
                (fd - grav[i]).abs() <= 1e-7 * grav[i].abs().max(1.0),
                "chain {k} joint {i}: g {} vs ∂P/∂θ {fd}",
                grav[i]
            );
            max.note(
                "g − ∂P/∂θ (central difference)",
                (fd - grav[i]).abs() / grav[i].abs().max(1.0),
            );
        }
    }
    max.report("random chains");
}

/// With intRes = 1, an Euler trajectory's accelerations are `(θ̇_{k+1} − θ̇_k)/dt`, and
/// inverse dynamics along the trajectory returns the applied torques.
#[test]
fn trajectories_round_trip() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().take(36).enumerate() {
        let (r, n, g) = (&s.robot, s.robot.dof(), s.robot.gravity);
        let steps = 20;
        let dt = 0.01;
        let taumat = DMatrix::from_fn(steps, n, |i, j| (0.3 * i as f64 + j as f64).sin());
        let ftipmat = DMatrix::from_fn(steps, 6, |i, j| s.f_tip[j] * (0.1 * i as f64).cos());
        let (thetamat, dthetamat) =
            dr::forward_dynamics_trajectory(r, &s.q, &s.qd, &taumat, &g, &ftipmat, dt, 1).unwrap();
        let rows = steps - 1;
        let ddthetamat = DMatrix::from_fn(rows, n, |i, j| {
            (dthetamat[(i + 1, j)] - dthetamat[(i, j)]) / dt
        });
        let tau_back = dr::inverse_dynamics_trajectory(
            r,
            &thetamat.rows(0, rows).into_owned(),
            &dthetamat.rows(0, rows).into_owned(),
            &ddthetamat,
            &g,
            &ftipmat.rows(0, rows).into_owned(),
        );
        // (θ̇_{k+1} − θ̇_k)/dt loses about |θ̇|·ε/dt; allow for it through M.
        let scale = dr::mass_matrix(r, &s.q).amax() * dthetamat.amax() * 1e-13 / dt;
        let e = check_tol(
            &format!("chain {k} ID along FD trajectory"),
            tau_back.as_slice(),
            taumat.rows(0, rows).into_owned().as_slice(),
            1e-9,
            scale,
        );
        max.note("ID(trajectory) − τ", e);
        // Euler steps of the trajectory, one by one.
        let (q1, qd1) = dr::euler_step(
            &s.q,
            &s.qd,
            &ddthetamat.row(0).iter().copied().collect::<Vec<_>>(),
            dt,
        );
        check(
            &format!("chain {k} euler θ"),
            q1.as_slice(),
            &thetamat.row(1).iter().copied().collect::<Vec<_>>(),
        );
        check(
            &format!("chain {k} euler θ̇"),
            qd1.as_slice(),
            &dthetamat.row(1).iter().copied().collect::<Vec<_>>(),
        );
    }
    max.report("random chains");
}
