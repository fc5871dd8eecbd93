//! Constrained forward dynamics (Modern Robotics §8.7, Exercise 8.10) on random trees, fixed
//! and floating, with and without mimic joints and armature: `A ν̇ + Ȧν = 0`,
//! `M ν̇ + h = τ + Aᵀλ`, the book's projection form, the end effector held still against the
//! task-space quantities, and `None` for dependent constraints.

mod common;

use common::random_chain::Rng;
use common::random_tree::trees_coupled;
use common::{check_tol, with_actuation, MaxErr};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Vector6};

#[test]
fn constraints_hold_and_the_equations_of_motion_balance() {
    let mut rng = Rng::new(810);
    let mut max = MaxErr::default();
    let mut samples = trees_coupled(8100, 15, 9, 0.0);
    samples.extend(trees_coupled(8101, 15, 9, 0.4));
    for (k, s) in samples.into_iter().enumerate() {
        let robot = with_actuation(&mut rng, s.robot);
        let nv = robot.nv();
        let g = robot.gravity;
        let label = format!(
            "tree {k} (nv {nv}, floating {}, mimic {})",
            robot.base.floating,
            robot.has_mimic()
        );
        let tau = DVector::from_vec(rng.vector(nv, -5.0, 5.0));
        let m = dr::mass_matrix(&robot, &s.q);
        let h = dr::inverse_dynamics(&robot, &s.q, &s.qd, &vec![0.0; nv], &g, &Vector6::zeros());
        for kc in 0..nv.min(4) {
            let a = DMatrix::from_fn(kc, nv, |_, _| rng.uniform(-1.0, 1.0));
            let a_dot_qd = DVector::from_vec(rng.vector(kc, -1.0, 1.0));
            let (qdd, lambda) = dr::constrained_forward_dynamics(
                &robot,
                &s.q,
                &s.qd,
                tau.as_slice(),
                &a,
                &a_dot_qd,
                &g,
            )
            .unwrap_or_else(|| panic!("{label}: {kc} random constraints are independent"));
            assert_eq!((qdd.len(), lambda.len()), (nv, kc));
            // A ν̇ + Ȧν = 0.
            let c = &a * &qdd + &a_dot_qd;
            let scale = 1.0 + (&a * &qdd).amax();
            max.note(
                "‖Aν̇ + Ȧν‖",
                check_tol(
                    &format!("{label} K={kc} constraint"),
                    c.as_slice(),
                    &vec![0.0; kc],
                    0.0,
                    1e-10 * scale,
                ) / scale,
            );
            // M ν̇ + h = τ + Aᵀλ.
            let lhs = &m * &qdd + &h;
            let rhs = &tau + a.transpose() * &lambda;
            let scale = 1.0 + rhs.amax();
            max.note(
                "‖Mν̇ + h − τ − Aᵀλ‖",
                check_tol(
                    &format!("{label} K={kc} motion"),
                    lhs.as_slice(),
                    rhs.as_slice(),
                    0.0,
                    1e-10 * scale,
                ) / scale,
            );
            // The book's projection (Exercise 8.10), with Ȧν: ν̇ = P_ν̇ M⁻¹(τ − h) − M⁻¹Aᵀ S⁻¹ Ȧν.
            let m_inv = m.clone().try_inverse().expect("M invertible");
            let s_inv = (&a * &m_inv * a.transpose())
                .try_inverse()
                .expect("S invertible");
            let p_qdd = DMatrix::identity(nv, nv) - &m_inv * a.transpose() * &s_inv * &a;
            let want = &p_qdd * &m_inv * (&tau - &h) - &m_inv * a.transpose() * &s_inv * &a_dot_qd;
            let scale = 1.0 + want.amax();
            max.note(
                "ν̇ vs projection",
                check_tol(
                    &format!("{label} K={kc} projection"),
                    qdd.as_slice(),
                    want.as_slice(),
                    0.0,
                    1e-9 * scale,
                ) / scale,
            );
            if kc == 0 {
                let fd = dr::forward_dynamics(
                    &robot,
                    &s.q,
                    &s.qd,
                    tau.as_slice(),
                    &g,
                    &Vector6::zeros(),
                )
                .unwrap();
                check_tol(
                    &format!("{label} K=0"),
                    qdd.as_slice(),
                    fd.as_slice(),
                    1e-12,
                    1e-12,
                );
            }
        }
    }
    max.report("constrained forward dynamics");
}

/// The end effector held still, `J_b ν̇ + J̇_b ν = 0`, needs the constraint force
/// `λ = η − Λ J_b M⁻¹ τ` (from `F = Λ V̇_b + η` with `V̇_b = 0` and `τ + J_bᵀλ` as the joint force).
#[test]
fn holding_the_end_effector_matches_the_task_space() {
    let mut rng = Rng::new(811);
    let mut count = 0;
    for s in trees_coupled(8110, 24, 9, 0.3) {
        let robot = with_actuation(&mut rng, s.robot);
        if !robot.base.floating {
            continue;
        }
        let nv = robot.nv();
        let g = robot.gravity;
        let tau = DVector::from_vec(rng.vector(nv, -5.0, 5.0));
        let j_b = dr::jacobian_body(&robot, &s.q);
        let jd_qd = dr::jacobian_body_dot(&robot, &s.q, &s.qd) * DVector::from_column_slice(&s.qd);
        let (qdd, lambda) =
            dr::constrained_forward_dynamics(&robot, &s.q, &s.qd, tau.as_slice(), &j_b, &jd_qd, &g)
                .expect("a floating base can always hold its end effector");
        let v_dot = &j_b * &qdd + &jd_qd;
        assert!(v_dot.amax() < 1e-9 * (1.0 + qdd.amax()), "V̇_b = {v_dot}");
        let lambda_ts = dr::task_space_mass_matrix(&robot, &s.q).unwrap();
        let eta = dr::task_space_bias(&robot, &s.q, &s.qd, &g).unwrap();
        let m_inv = dr::mass_matrix(&robot, &s.q).try_inverse().unwrap();
        let lam = DMatrix::from_fn(6, 6, |r, c| lambda_ts[(r, c)]);
        let want = DVector::from_column_slice(eta.as_slice()) - &lam * &j_b * &m_inv * &tau;
        let scale = 1.0 + want.amax();
        check_tol(
            "λ vs task space",
            lambda.as_slice(),
            want.as_slice(),
            0.0,
            1e-9 * scale,
        );
        count += 1;
    }
    assert!(count > 5);
}

#[test]
fn dependent_constraints_give_none() {
    let mut rng = Rng::new(812);
    for s in trees_coupled(8120, 12, 8, 0.0)
        .into_iter()
        .filter(|s| s.robot.nv() >= 3)
    {
        let robot = &s.robot;
        let nv = robot.nv();
        let tau = rng.vector(nv, -1.0, 1.0);
        let row = DMatrix::from_fn(1, nv, |_, _| rng.uniform(-1.0, 1.0));
        // The same row twice, and one row a multiple of another.
        for a in [
            DMatrix::from_fn(2, nv, |_, c| row[(0, c)]),
            DMatrix::from_fn(2, nv, |r, c| row[(0, c)] * if r == 0 { 1.0 } else { -3.0 }),
            DMatrix::zeros(1, nv),
        ] {
            let k = a.nrows();
            let out = dr::constrained_forward_dynamics(
                robot,
                &s.q,
                &s.qd,
                &tau,
                &a,
                &DVector::zeros(k),
                &robot.gravity,
            );
            assert!(out.is_none(), "dependent constraints {a}");
        }
        // More constraints than velocities.
        let a = DMatrix::from_fn(nv + 1, nv, |_, _| rng.uniform(-1.0, 1.0));
        let out = dr::constrained_forward_dynamics(
            robot,
            &s.q,
            &s.qd,
            &tau,
            &a,
            &DVector::zeros(nv + 1),
            &robot.gravity,
        );
        assert!(out.is_none());
    }
}

#[test]
#[should_panic(expected = "`a` has 2 columns")]
fn a_with_the_wrong_width_panics() {
    let s = &trees_coupled(813, 3, 3, 0.0)[2];
    let robot = &s.robot;
    dr::constrained_forward_dynamics(
        robot,
        &s.q,
        &s.qd,
        &vec![0.0; robot.nv()],
        &DMatrix::zeros(1, 2),
        &DVector::zeros(1),
        &robot.gravity,
    );
}
