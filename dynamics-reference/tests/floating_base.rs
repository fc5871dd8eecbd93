//! Identities of the floating base on seeded random trees (`common/random_tree.rs`): the base
//! block of M is the composite inertia, the base rows of τ are the rate of the total spatial
//! momentum less gravity's wrench, forward dynamics of an unactuated base without gravity
//! conserves that momentum, the joint block is the fixed-base tree's, and trajectories round
//! trip through inverse dynamics.

mod common;

use common::random_tree::{quaternion_of, trees, TreeSample};
use common::{check, check_tol, MaxErr};
use dynamics_model::lie::{adjoint, exp6, rotation, skew, trans_inv, translation};
use dynamics_model::Robot;
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Matrix4, Vector3, Vector4, Vector6};

/// 160 floating trees of 1–40 bodies.
fn floating_samples() -> Vec<TreeSample> {
    trees(0xF1_0A7, 240, 40)
        .into_iter()
        .filter(|s| s.robot.base.floating)
        .collect()
}

/// `h_0`: the total spatial momentum `(angular about the origin, linear)` in {0}, from the
/// base-frame momentum `M[0..6, ·] ν` moved as a wrench, `h_0 = [Ad_{T_{0b}⁻¹}]ᵀ h_b`.
fn momentum_in_world(r: &Robot, q: &[f64], qd: &[f64]) -> Vector6<f64> {
    let h_b = dr::mass_matrix(r, q).rows(0, 6) * DVector::from_column_slice(qd);
    let h_b = Vector6::from_column_slice(h_b.as_slice());
    adjoint(&trans_inv(&dr::base_pose(r, q))).transpose() * h_b
}

/// Gravity's wrench on the whole robot in {0}, about its origin: `Σ m (c × g, g)` over the
/// base and the links, `c` the centres of mass in {0}.
fn gravity_wrench_in_world(r: &Robot, q: &[f64], g: &Vector3<f64>) -> Vector6<f64> {
    let mut bodies: Vec<(Matrix4<f64>, _)> = vec![(dr::base_pose(r, q), r.base.inertia)];
    bodies.extend(
        dr::link_poses(r, q)
            .into_iter()
            .zip(r.links.iter().map(|l| l.inertia)),
    );
    bodies.iter().fold(Vector6::zeros(), |w, (t, inertia)| {
        let c = inertia.com();
        let c0 = (t * Vector4::new(c[0], c[1], c[2], 1.0)).xyz();
        let f = g * inertia.mass();
        w + dynamics_model::lie::twist(&c0.cross(&f), &f)
    })
}

/// M[0..6, 0..6] = `G_b + Σ_i [Ad_{T_{ib}}]ᵀ G_i [Ad_{T_{ib}}]`, with `T_{ib}` from the link poses
/// (products of exponentials, not the CRBA's recursion).
#[test]
fn base_block_is_the_composite_inertia() {
    let mut max = MaxErr::default();
    for (k, s) in floating_samples().iter().enumerate() {
        let r = &s.robot;
        let t_0b = dr::base_pose(r, &s.q);
        let composite = dr::link_poses(r, &s.q)
            .iter()
            .zip(&r.links)
            .fold(r.base.inertia, |sum, (t_0i, link)| {
                sum + link.inertia.transform_by(&(trans_inv(t_0i) * t_0b))
            });
        let m = dr::mass_matrix(r, &s.q);
        let block = m.view((0, 0), (6, 6)).into_owned();
        max.note(
            "M_bb − composite",
            check(
                &format!("tree {k} M_bb"),
                block.as_slice(),
                composite.0.as_slice(),
            ),
        );
    }
    max.report("floating trees");
}

/// `τ_b = [Ad_{T_{0b}}]ᵀ (ḣ_0 − W_g)`: the base rows of τ = ID(q, ν, ν̇) (no tip wrench) are
/// the rate of the total spatial momentum in {0} less gravity's wrench, moved into the base
/// frame. ḣ_0 by central differences (step 1e-5) along the motion with ν(t) = ν + ν̇ t:
/// `θ(t) = θ + θ̇ t + ½ θ̈ t²`, `T_{0b}(t) = T_{0b} e^{[ν_b t + ½ ν̇_b t²]}`.
#[test]
fn base_rows_are_the_momentum_rate() {
    let mut max = MaxErr::default();
    let h = 1e-5;
    for (k, s) in floating_samples().iter().enumerate() {
        let (r, g, n) = (&s.robot, s.robot.gravity, s.robot.dof());
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &Vector6::zeros());
        let t_0b = dr::base_pose(r, &s.q);
        let (nu_b, nud_b) = (
            Vector6::from_column_slice(&s.qd[..6]),
            Vector6::from_column_slice(&s.qdd[..6]),
        );
        let state_at = |t: f64| -> (Vec<f64>, Vec<f64>) {
            let pose = t_0b * exp6(&(nu_b * t + nud_b * (0.5 * t * t)), 1.0);
            let mut q: Vec<f64> = translation(&pose).iter().copied().collect();
            q.extend(quaternion_of(&rotation(&pose)));
            q.extend((0..n).map(|i| s.q[7 + i] + s.qd[6 + i] * t + 0.5 * s.qdd[6 + i] * t * t));
            let qd = s.qd.iter().zip(&s.qdd).map(|(v, a)| v + a * t).collect();
            (q, qd)
        };
        let ((qp, qdp), (qm, qdm)) = (state_at(h), state_at(-h));
        let h_dot = (momentum_in_world(r, &qp, &qdp) - momentum_in_world(r, &qm, &qdm)) / (2.0 * h);
        let w_g = gravity_wrench_in_world(r, &s.q, &g);
        let expected = adjoint(&t_0b).transpose() * (h_dot - w_g);
        let scale = h_dot.amax().max(w_g.amax()).max(1.0);
        let err = (Vector6::from_column_slice(&tau.as_slice()[..6]) - expected).amax() / scale;
        assert!(
            err <= 1e-6,
            "tree {k}: τ_b {:?} vs Adᵀ(ḣ − W_g) {expected:?}",
            &tau.as_slice()[..6]
        );
        max.note("τ_b − Adᵀ(ḣ − W_g), relative to max(|ḣ|, |W_g|)", err);
    }
    max.report("floating trees");
}

/// One RK4 step of `(q̇, ν̇) = (q̇(q, ν), FD(q, ν, τ))` without gravity.
fn rk4_step(
    r: &Robot,
    q: &DVector<f64>,
    qd: &DVector<f64>,
    tau: &[f64],
    h: f64,
) -> (DVector<f64>, DVector<f64>) {
    let f = |q: &DVector<f64>, qd: &DVector<f64>| {
        let g0 = Vector3::zeros();
        let qdd = dr::forward_dynamics(r, q.as_slice(), qd.as_slice(), tau, &g0, &Vector6::zeros())
            .unwrap();
        (dr::configuration_rate(r, q.as_slice(), qd.as_slice()), qdd)
    };
    let (k1q, k1v) = f(q, qd);
    let (k2q, k2v) = f(&(q + &k1q * (h / 2.0)), &(qd + &k1v * (h / 2.0)));
    let (k3q, k3v) = f(&(q + &k2q * (h / 2.0)), &(qd + &k2v * (h / 2.0)));
    let (k4q, k4v) = f(&(q + &k3q * h), &(qd + &k3v * h));
    (
        q + (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (h / 6.0),
        qd + (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (h / 6.0),
    )
}

/// With no gravity, no tip wrench and no wrench on the base (any joint forces: they are
/// internal), forward dynamics conserves the total spatial momentum in {0}. Integrated by
/// RK4 over 0.2 s, the drift is the integration error: it falls by about 2⁴ when the step
/// halves, and is below 1e-7 of the momentum at the smaller step.
#[test]
fn unactuated_base_conserves_momentum() {
    let mut max = MaxErr::default();
    let samples: Vec<_> = trees(0xC0_5E7, 24, 8)
        .into_iter()
        .filter(|s| s.robot.base.floating)
        .take(6)
        .collect();
    for (k, s) in samples.iter().enumerate() {
        let r = &s.robot;
        let mut tau = s.qdd.clone();
        tau[..6].fill(0.0);
        let h0 = momentum_in_world(r, &s.q, &s.qd);
        let drift = |steps: usize| -> f64 {
            let h = 0.2 / steps as f64;
            let (mut q, mut qd) = (
                DVector::from_column_slice(&s.q),
                DVector::from_column_slice(&s.qd),
            );
            for _ in 0..steps {
                (q, qd) = rk4_step(r, &q, &qd, &tau, h);
            }
            (momentum_in_world(r, q.as_slice(), qd.as_slice()) - h0).amax() / h0.amax().max(1.0)
        };
        let (coarse, fine) = (drift(40), drift(80));
        eprintln!(
            "tree {k} ({} joints): momentum drift {coarse:.2e} (h = 5 ms), {fine:.2e} (h = 2.5 ms)",
            r.dof()
        );
        assert!(fine <= 1e-7, "tree {k}: drift {fine:e}");
        assert!(
            fine <= coarse / 8.0 || fine <= 1e-12,
            "tree {k}: drift {coarse:e} → {fine:e} is not the integration error"
        );
        max.note("momentum drift (h = 2.5 ms)", fine);
    }
    max.report("floating trees");
}

/// The joint block of a floating robot is the fixed-base tree's: with the base at rest
/// (ν_b = ν̇_b = 0), `M[6.., 6..]` and `τ[6..]` equal M and τ of the same tree on a fixed base
/// with gravity `Rᵀ g` (gravity seen from the base).
#[test]
fn joint_block_is_the_fixed_base_tree() {
    let mut max = MaxErr::default();
    for (k, s) in floating_samples().iter().enumerate() {
        let r = &s.robot;
        let mut fixed = r.clone();
        fixed.base.floating = false;
        let g_b = rotation(&dr::base_pose(r, &s.q)).transpose() * r.gravity;
        let theta = &s.q[7..];
        let (mut qd, mut qdd) = (s.qd.clone(), s.qdd.clone());
        qd[..6].fill(0.0);
        qdd[..6].fill(0.0);
        let m = dr::mass_matrix(r, &s.q);
        let m_fixed = dr::mass_matrix(&fixed, theta);
        let block = m.view((6, 6), (r.dof(), r.dof())).into_owned();
        max.note(
            "M_θθ − M_fixed",
            check(
                &format!("tree {k} M_θθ"),
                block.as_slice(),
                m_fixed.as_slice(),
            ),
        );
        let tau = dr::inverse_dynamics(r, &s.q, &qd, &qdd, &r.gravity, &s.f_tip);
        let tau_fixed =
            dr::inverse_dynamics(&fixed, theta, &s.qd[6..], &s.qdd[6..], &g_b, &s.f_tip);
        max.note(
            "τ_θ − τ_fixed",
            check(
                &format!("tree {k} τ_θ"),
                &tau.as_slice()[6..],
                tau_fixed.as_slice(),
            ),
        );
    }
    max.report("floating trees");
}

/// `q̇(q, ν)` moves the base as its body twist says: `Ṫ_{0b} = T_{0b} [ν_b]` by central
/// differences of the base pose (step 1e-6), for quaternions of any norm.
#[test]
fn configuration_rate_follows_the_body_twist() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in floating_samples().iter().enumerate() {
        let r = &s.robot;
        let q_dot = dr::configuration_rate(r, &s.q, &s.qd);
        let at = |sign: f64| -> Vec<f64> {
            s.q.iter()
                .zip(q_dot.iter())
                .map(|(a, b)| a + sign * h * b)
                .collect()
        };
        let t_dot = (dr::base_pose(r, &at(1.0)) - dr::base_pose(r, &at(-1.0))) / (2.0 * h);
        let t = dr::base_pose(r, &s.q);
        let (w, v) = (
            Vector3::new(s.qd[0], s.qd[1], s.qd[2]),
            Vector3::new(s.qd[3], s.qd[4], s.qd[5]),
        );
        let mut bracket = Matrix4::zeros();
        bracket.fixed_view_mut::<3, 3>(0, 0).copy_from(&skew(&w));
        bracket.fixed_view_mut::<3, 1>(0, 3).copy_from(&v);
        let expected = t * bracket;
        max.note(
            "Ṫ − T[ν_b]",
            check_tol(
                &format!("tree {k} Ṫ"),
                t_dot.as_slice(),
                expected.as_slice(),
                1e-7,
                1e-8,
            ),
        );
        // |quat| is constant along q̇.
        let quat = &s.q[3..7];
        let d_norm: f64 = quat
            .iter()
            .zip(&q_dot.as_slice()[3..7])
            .map(|(a, b)| a * b)
            .sum();
        assert!(
            d_norm.abs() <= 1e-14 * q_dot.amax().max(1.0),
            "tree {k}: d|quat|²/dt = {d_norm:e}"
        );
    }
    max.report("floating trees");
}

/// With intRes = 1 a floating trajectory's accelerations are `(ν_{k+1} − ν_k)/dt` and its
/// configurations `q_{k+1} = q_k + dt q̇(q_k, ν_k)`; inverse dynamics along it returns τ.
#[test]
fn trajectories_round_trip() {
    let mut max = MaxErr::default();
    for (k, s) in floating_samples().iter().take(30).enumerate() {
        let (r, nv, g) = (&s.robot, s.robot.nv(), s.robot.gravity);
        let (steps, dt) = (12, 0.01);
        let taumat = DMatrix::from_fn(steps, nv, |i, j| 3.0 * (0.3 * i as f64 + j as f64).sin());
        let ftipmat = DMatrix::from_fn(steps, 6, |i, j| s.f_tip[j] * (0.1 * i as f64).cos());
        let (qmat, vmat) =
            dr::forward_dynamics_trajectory(r, &s.q, &s.qd, &taumat, &g, &ftipmat, dt, 1).unwrap();
        let rows = steps - 1;
        let amat = DMatrix::from_fn(rows, nv, |i, j| (vmat[(i + 1, j)] - vmat[(i, j)]) / dt);
        let tau_back = dr::inverse_dynamics_trajectory(
            r,
            &qmat.rows(0, rows).into_owned(),
            &vmat.rows(0, rows).into_owned(),
            &amat,
            &g,
            &ftipmat.rows(0, rows).into_owned(),
        );
        let scale = dr::mass_matrix(r, &s.q).amax() * vmat.amax() * 1e-13 / dt;
        let e = check_tol(
            &format!("tree {k} ID along the trajectory"),
            tau_back.as_slice(),
            taumat.rows(0, rows).into_owned().as_slice(),
            1e-9,
            scale,
        );
        max.note("ID(trajectory) − τ", e);
        for i in 0..rows {
            let q_i: Vec<f64> = qmat.row(i).iter().copied().collect();
            let v_i: Vec<f64> = vmat.row(i).iter().copied().collect();
            let next =
                DVector::from_column_slice(&q_i) + dr::configuration_rate(r, &q_i, &v_i) * dt;
            let row: Vec<f64> = qmat.row(i + 1).iter().copied().collect();
            check(&format!("tree {k} row {}", i + 1), next.as_slice(), &row);
        }
    }
    max.report("floating trees");
}
