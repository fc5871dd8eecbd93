//! Armature (rotor inertia through a gear, Modern Robotics §8.9.2) and joint friction on
//! random trees, fixed and floating, with and without mimic joints: M's diagonal shift, ID/FD
//! consistency, the identities that must survive it (Ṁ − 2C skew, c = Cν), friction values by
//! hand, and the power balance `d(K + P)/dt = νᵀ(τ − τ_friction)` along RK4 trajectories.
//! Pinocchio's armature numbers (`model.armature`) on the floating trees close the loop.

mod common;

use common::pinocchio::{matrix_to_ours, robot_from_pinocchio, to_ours};
use common::random_chain::Rng;
use common::random_tree::trees_coupled;
use common::{
    check, check_tol, coupling_matrix, load_json, mat_of, vec_of, with_actuation, MaxErr,
};
use dynamics_model::Robot;
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Matrix6, Vector3, Vector6};

/// Random trees (fixed and floating, 1..8 bodies) with and without mimic joints.
fn samples() -> Vec<common::random_tree::TreeSample> {
    let mut all = trees_coupled(810, 12, 8, 0.0);
    all.extend(trees_coupled(811, 12, 8, 0.4));
    all
}

/// `D = diag(0 for the base, G_i² I_rotor,i)` at the physical level, projected `Jᵀ D J`.
fn armature_matrix(robot: &Robot) -> DMatrix<f64> {
    let j = coupling_matrix(robot);
    let base = if robot.base.floating { 6 } else { 0 };
    let mut d = DMatrix::zeros(j.nrows(), j.nrows());
    for (i, joint) in robot.joints.iter().enumerate() {
        d[(base + i, base + i)] = joint.armature();
    }
    j.transpose() * d * j
}

#[test]
fn armature_shifts_the_diagonal_and_id_fd_stay_consistent() {
    let mut rng = Rng::new(8092);
    let mut max = MaxErr::default();
    for (k, s) in samples().into_iter().enumerate() {
        let bare = s.robot.clone();
        let robot = with_actuation(&mut rng, s.robot);
        let label = format!(
            "tree {k} (floating {}, mimic {})",
            robot.base.floating,
            robot.has_mimic()
        );
        let g = robot.gravity;
        let nv = robot.nv();
        let d = armature_matrix(&robot);
        if !robot.has_mimic() {
            // Exactly diagonal, zero on the base's six entries.
            for r in 0..nv {
                for c in 0..nv {
                    if r != c || (robot.base.floating && r < 6) {
                        assert_eq!(d[(r, c)], 0.0);
                    }
                }
            }
        }
        let m = dr::mass_matrix(&robot, &s.q);
        let m0 = dr::mass_matrix(&bare, &s.q);
        max.note(
            "M − M_bare − JᵀDJ",
            check(&format!("{label} M"), (&m - &m0).as_slice(), d.as_slice()),
        );
        // ID adds D ν̇; FD inverts it.
        let tau = dr::inverse_dynamics(&robot, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let tau0 = dr::inverse_dynamics(&bare, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let d_qdd = &d * DVector::from_column_slice(&s.qdd);
        max.note(
            "τ − τ_bare − Dν̇",
            check(
                &format!("{label} τ"),
                (&tau - &tau0).as_slice(),
                d_qdd.as_slice(),
            ),
        );
        let id_m = &m * DVector::from_column_slice(&s.qdd)
            + dr::inverse_dynamics(&robot, &s.q, &s.qd, &vec![0.0; nv], &g, &s.f_tip);
        max.note(
            "τ = Mν̇ + bias",
            check(
                &format!("{label} Mν̇ + bias"),
                tau.as_slice(),
                id_m.as_slice(),
            ),
        );
        let qdd = dr::forward_dynamics(&robot, &s.q, &s.qd, tau.as_slice(), &g, &s.f_tip)
            .expect("M positive definite");
        max.note(
            "FD(ID(ν̇)) = ν̇",
            check(&format!("{label} FD∘ID"), qdd.as_slice(), &s.qdd),
        );
        // K = ½ νᵀMν includes ½ νᵀDν.
        let v = DVector::from_column_slice(&s.qd);
        let dk = dr::kinetic_energy(&robot, &s.q, &s.qd) - dr::kinetic_energy(&bare, &s.q, &s.qd);
        max.note(
            "K − K_bare = ½νᵀDν",
            check(&format!("{label} K"), &[dk], &[0.5 * v.dot(&(&d * &v))]),
        );
        // The constant armature leaves Ṁ and C alone, and the identities hold.
        let mdot = dr::mass_matrix_dot(&robot, &s.q, &s.qd);
        let mdot0 = dr::mass_matrix_dot(&bare, &s.q, &s.qd);
        assert_eq!(mdot, mdot0, "{label}: Ṁ changed");
        let c = dr::coriolis_matrix(&robot, &s.q, &s.qd);
        let cv = &c * &v;
        let c_vec = dr::vel_quadratic_forces(&robot, &s.q, &s.qd);
        max.note(
            "Cν = c",
            check(&format!("{label} Cν"), cv.as_slice(), c_vec.as_slice()),
        );
        let skew = &mdot - &c * 2.0;
        let sym = &skew + skew.transpose();
        max.note(
            "Ṁ − 2C skew",
            check_tol(
                &format!("{label} skew"),
                sym.as_slice(),
                &vec![0.0; nv * nv],
                0.0,
                1e-10 * (1.0 + mdot.amax() + c.amax()),
            ),
        );
    }
    max.report("armature");
}

/// One revolute joint about z with a link of inertia `i_link` about it (unit mass at the axis).
fn single_joint(i_link: f64) -> Robot {
    let g1 = Matrix6::from_diagonal(&Vector6::new(i_link, i_link, i_link, 1.0, 1.0, 1.0));
    let s1 = Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
    Robot::from_mr_lists(
        &[Matrix4::identity(), Matrix4::identity()],
        &[g1],
        &[s1],
        Vector3::zeros(),
    )
    .expect("valid")
}

#[test]
fn armature_by_hand_on_one_joint() {
    // I_link = 0.5, I_rotor = 2e-4, G = 50: M = 0.5 + 2500·2e-4 = 1; τ = 1·θ̈.
    let mut robot = single_joint(0.5);
    robot.joints[0].rotor_inertia = 2e-4;
    robot.joints[0].gear_ratio = 50.0;
    assert!((robot.joints[0].armature() - 0.5).abs() < 1e-15);
    let m = dr::mass_matrix(&robot, &[0.3]);
    assert!((m[(0, 0)] - 1.0).abs() < 1e-15, "{m}");
    let tau = dr::inverse_dynamics(
        &robot,
        &[0.3],
        &[2.0],
        &[1.5],
        &Vector3::zeros(),
        &Vector6::zeros(),
    );
    assert!((tau[0] - 1.5).abs() < 1e-15, "{tau}");
    // G* = √(0.5/2e-4) = 50 maximises θ̈ = G τ_m / (I_link + G² I_rotor).
    assert!((dynamics_model::optimal_gear_ratio(0.5, 2e-4) - 50.0).abs() < 1e-12);
}

#[test]
fn friction_forces_by_hand() {
    // Three joints: b = (0.5, 0, 2), μ = (0.1, 0.3, 0).
    let mut robot = dynamics_model::random::random_chain(
        7,
        dynamics_model::random::ChainSpec {
            dof: 3,
            prismatic: 0.0,
        },
    );
    for (j, (b, mu)) in robot
        .joints
        .iter_mut()
        .zip([(0.5, 0.1), (0.0, 0.3), (2.0, 0.0)])
    {
        j.damping = b;
        j.friction = mu;
    }
    let qd = [2.0, -1.0, 0.0];
    let f = dr::friction_forces(&robot, &qd, None);
    assert_eq!(f.as_slice(), &[0.5 * 2.0 + 0.1, -0.3, 0.0]);
    let f = dr::friction_forces(&robot, &qd, Some(0.5));
    let want = [1.0 + 0.1 * 4.0f64.tanh(), -0.3 * 2.0f64.tanh(), 0.0];
    check("smooth friction", f.as_slice(), &want);
    // sgn(0) = 0, also for −0.0; the smooth form is 0 at rest too.
    let rest = dr::friction_forces(&robot, &[0.0, -0.0, 0.0], None);
    assert_eq!(rest.as_slice(), &[0.0, 0.0, 0.0]);
    // Dissipative: νᵀ τ_friction ≥ 0 for every ν.
    let mut rng = Rng::new(5);
    for _ in 0..20 {
        let v = rng.vector(3, -2.0, 2.0);
        for smooth in [None, Some(0.1)] {
            let f = dr::friction_forces(&robot, &v, smooth);
            assert!(DVector::from_vec(v.clone()).dot(&f) >= 0.0);
        }
    }

    // Floating base: zero on the base's six entries.
    let mut floating = robot.clone();
    floating.base.floating = true;
    floating.base.inertia = dynamics_model::SpatialInertia::at_com(1.0, Matrix3::identity() * 0.01);
    let f = dr::friction_forces(
        &floating,
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 2.0, -1.0, 0.0],
        None,
    );
    assert_eq!(
        f.as_slice(),
        &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.1, -0.3, 0.0]
    );

    // Mimic: joint 3 follows joint 2 with m = −2: θ̇₃ = −2θ̇₂. With b₃ = 2, μ₃ = 0.4 its
    // friction 2·(−2θ̇₂) + 0.4·sgn(−2θ̇₂) acts on joint 2 times m = −2.
    let mut mimic = robot.clone();
    mimic.joints[2].friction = 0.4;
    mimic.joints[2].mimic = Some(dynamics_model::Mimic {
        leader: 1,
        multiplier: -2.0,
        offset: 0.1,
    });
    mimic.validate().expect("valid mimic");
    let f = dr::friction_forces(&mimic, &[2.0, -1.0], None);
    let follower = 2.0 * 2.0 + 0.4; // θ̇₃ = 2
    assert_eq!(f.as_slice(), &[1.1, -0.3 + (-2.0) * follower]);
}

#[test]
#[should_panic(expected = "smoothing width")]
fn friction_forces_refuses_a_zero_width() {
    let robot = single_joint(1.0);
    dr::friction_forces(&robot, &[1.0], Some(0.0));
}

/// `(q̇, ν̇)` of the robot driven by `tau` with smooth friction.
fn rate(
    robot: &Robot,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    eps: f64,
) -> (DVector<f64>, DVector<f64>, f64) {
    let f = dr::friction_forces(robot, v, Some(eps));
    let net = DVector::from_column_slice(tau) - f;
    let vd = dr::forward_dynamics(
        robot,
        q,
        v,
        net.as_slice(),
        &robot.gravity,
        &Vector6::zeros(),
    )
    .expect("M positive definite");
    let power = DVector::from_column_slice(v).dot(&net);
    (dr::configuration_rate(robot, q, v), vd, power)
}

fn energy(robot: &Robot, q: &[f64], v: &[f64]) -> f64 {
    dr::kinetic_energy(robot, q, v) + dr::potential_energy(robot, q, &robot.gravity)
}

/// `d(K + P)/dt = νᵀ(τ − τ_friction)`: the work of the net joint force, integrated with the
/// state by RK4, equals the change of energy.
#[test]
fn power_balance_with_friction_and_armature_along_rk4() {
    let mut rng = Rng::new(4242);
    let (dt, steps, eps) = (1e-3, 300, 0.05);
    let mut worst = 0.0f64;
    for (k, s) in samples().into_iter().enumerate() {
        let robot = with_actuation(&mut rng, s.robot);
        let tau = rng.vector(robot.nv(), -1.0, 1.0);
        let (mut q, mut v, mut work) = (
            DVector::from_vec(s.q.clone()),
            DVector::from_vec(s.qd.clone()),
            0.0,
        );
        let e0 = energy(&robot, q.as_slice(), v.as_slice());
        for _ in 0..steps {
            let (k1q, k1v, k1w) = rate(&robot, q.as_slice(), v.as_slice(), &tau, eps);
            let (q2, v2) = (&q + &k1q * (dt / 2.0), &v + &k1v * (dt / 2.0));
            let (k2q, k2v, k2w) = rate(&robot, q2.as_slice(), v2.as_slice(), &tau, eps);
            let (q3, v3) = (&q + &k2q * (dt / 2.0), &v + &k2v * (dt / 2.0));
            let (k3q, k3v, k3w) = rate(&robot, q3.as_slice(), v3.as_slice(), &tau, eps);
            let (q4, v4) = (&q + &k3q * dt, &v + &k3v * dt);
            let (k4q, k4v, k4w) = rate(&robot, q4.as_slice(), v4.as_slice(), &tau, eps);
            q += (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (dt / 6.0);
            v += (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (dt / 6.0);
            work += (k1w + 2.0 * k2w + 2.0 * k3w + k4w) * (dt / 6.0);
        }
        let e1 = energy(&robot, q.as_slice(), v.as_slice());
        let scale = e0.abs().max(e1.abs()).max(work.abs()).max(1.0);
        let err = (e1 - e0 - work).abs() / scale;
        eprintln!(
            "tree {k} (floating {}, mimic {}): ΔE = {:.6}, ∫νᵀ(τ − τ_f) = {:.6}, rel. error {err:.1e}",
            robot.base.floating,
            robot.has_mimic(),
            e1 - e0,
            work
        );
        assert!(err < 1e-8, "tree {k}: power balance off by {err:e}");
        worst = worst.max(err);
    }
    eprintln!("power balance: worst relative error {worst:.1e}");
}

/// Pinocchio 4.1.0 with `model.armature` = 0.1 on every joint of the floating trees
/// (`armature_samples` of `reference/trees/*.json`): M, τ = rnea(q, v, a), aba(q, v, τ_rand).
#[test]
fn pinocchio_armature_on_floating_trees() {
    for name in ["solo12", "g1_29dof"] {
        let file = load_json(&format!("reference/trees/{name}.json"));
        let mut robot = robot_from_pinocchio(&file);
        let floating = robot.base.floating;
        assert!(floating);
        let arm = to_ours(floating, &vec_of(&file["armature"]));
        for (i, j) in robot.joints.iter_mut().enumerate() {
            j.rotor_inertia = arm[6 + i];
            j.gear_ratio = 1.0;
        }
        let g = robot.gravity;
        let mut max = MaxErr::default();
        let samples = file["armature_samples"]
            .as_array()
            .expect("armature samples");
        assert!(!samples.is_empty());
        for (k, s) in samples.iter().enumerate() {
            let label = format!("{name} armature sample {k}");
            let q = vec_of(&s["q"]);
            let v = to_ours(floating, &vec_of(&s["v"]));
            let a = to_ours(floating, &vec_of(&s["a"]));
            let m = dr::mass_matrix(&robot, &q);
            let m_pin = matrix_to_ours(floating, &mat_of(&s["M"]));
            max.note(
                "M",
                check(&format!("{label} M"), m.as_slice(), m_pin.as_slice()),
            );
            let tau = dr::inverse_dynamics(&robot, &q, &v, &a, &g, &Vector6::zeros());
            max.note(
                "τ",
                check(
                    &format!("{label} τ"),
                    tau.as_slice(),
                    &to_ours(floating, &vec_of(&s["tau"])),
                ),
            );
            let tau_rand = to_ours(floating, &vec_of(&s["tau_rand"]));
            let a_fd = dr::forward_dynamics(&robot, &q, &v, &tau_rand, &g, &Vector6::zeros())
                .expect("M positive definite");
            max.note(
                "a_fd",
                check(
                    &format!("{label} a_fd"),
                    a_fd.as_slice(),
                    &to_ours(floating, &vec_of(&s["a_fd"])),
                ),
            );
        }
        max.report(&format!("Pinocchio armature {name}"));
    }
}
