//! The reference against the exact seed cases of `tests/data/seed-cases.json` (Lagrangian
//! derivations evaluated at 60 digits; see `tests/data/seed-cases.md`): the Exercise 8.4
//! pendulum with its closed forms, and the spatial 3R and RPR chains.

mod common;

use common::random_chain::Rng;
use common::{check, check_tol, load_json, mat_of, vec6, vec_of, MaxErr};
use dynamics_model::Robot;
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Vector6};
use serde_json::Value;

fn seed_model(name: &str) -> (Value, Robot) {
    let file = load_json("seed-cases.json");
    let model = file["models"][name].clone();
    let robot = common::robot_from_lists(&model, &model["Slist"], &model["gravity"], true);
    (model, robot)
}

fn dm(rows: &[&[f64]]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

/// Every expected quantity of every sample of a seed model.
fn samples_of(name: &str) {
    let (model, robot) = seed_model(name);
    let g = robot.gravity;
    let zero_tip = Vector6::zeros();
    let mut max = MaxErr::default();
    for (k, s) in model["samples"].as_array().unwrap().iter().enumerate() {
        let (q, qd, qdd) = (vec_of(&s["q"]), vec_of(&s["qd"]), vec_of(&s["qdd"]));
        let label = format!("{name} sample {k}");
        let mut cmp = |what: &str, x: &[f64], y: &[f64]| {
            max.note(what, check(&format!("{label} {what}"), x, y))
        };
        cmp(
            "M",
            dr::mass_matrix(&robot, &q).as_slice(),
            mat_of(&s["M"]).as_slice(),
        );
        cmp(
            "c",
            dr::vel_quadratic_forces(&robot, &q, &qd).as_slice(),
            &vec_of(&s["c"]),
        );
        cmp(
            "g",
            dr::gravity_forces(&robot, &q, &g).as_slice(),
            &vec_of(&s["g"]),
        );
        let tau = dr::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &zero_tip);
        cmp("tau", tau.as_slice(), &vec_of(&s["tau"]));
        cmp(
            "C",
            dr::coriolis_matrix(&robot, &q, &qd).as_slice(),
            mat_of(&s["C_christoffel"]).as_slice(),
        );
        cmp(
            "Mdot",
            dr::mass_matrix_dot(&robot, &q, &qd).as_slice(),
            mat_of(&s["Mdot"]).as_slice(),
        );
        let t_ee = DMatrix::from_column_slice(4, 4, dr::end_effector_pose(&robot, &q).as_slice());
        cmp("T_ee", t_ee.as_slice(), mat_of(&s["T_ee"]).as_slice());
        // Forward dynamics of τ returns θ̈.
        let qdd_fd = dr::forward_dynamics(&robot, &q, &qd, tau.as_slice(), &g, &zero_tip).unwrap();
        cmp("forward dynamics", qdd_fd.as_slice(), &qdd);
        if !s["Ftip"].is_null() {
            let f_tip = vec6(&s["Ftip"]);
            cmp(
                "tau_Ftip_only",
                dr::end_effector_forces(&robot, &q, &f_tip).as_slice(),
                &vec_of(&s["tau_Ftip_only"]),
            );
            let tau_f = dr::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &f_tip);
            cmp(
                "tau_with_Ftip",
                tau_f.as_slice(),
                &vec_of(&s["tau_with_Ftip"]),
            );
        }
    }
    max.report(name);
}

#[test]
fn pendulum_ex8_4_samples() {
    samples_of("rotational_pendulum_ex8_4");
}

#[test]
fn spatial_3r_samples() {
    samples_of("spatial_3R");
}

#[test]
fn spatial_rpr_samples() {
    samples_of("spatial_RPR");
}

/// The closed forms of Exercise 8.4 at 50 seeded random states.
#[test]
fn pendulum_closed_forms_at_random_states() {
    let (_, robot) = seed_model("rotational_pendulum_ex8_4");
    let g = robot.gravity;
    let mut rng = Rng::new(84);
    let mut max = MaxErr::default();
    for k in 0..50 {
        let q = rng.vector(2, -std::f64::consts::PI, std::f64::consts::PI);
        let qd = rng.vector(2, -2.0, 2.0);
        let qdd = rng.vector(2, -2.0, 2.0);
        let (s2, c2) = q[1].sin_cos();
        let (qd1, qd2) = (qd[0], qd[1]);
        let label = format!("pendulum state {k}");
        let mut cmp = |what: &str, x: &[f64], y: &[f64]| {
            max.note(what, check(&format!("{label} {what}"), x, y))
        };

        let m = dm(&[&[8.0 + 6.0 * s2 * s2, 2.0 * c2], &[2.0 * c2, 6.0]]);
        let c = DVector::from_vec(vec![
            12.0 * s2 * c2 * qd1 * qd2 - 2.0 * s2 * qd2 * qd2,
            -6.0 * s2 * c2 * qd1 * qd1,
        ]);
        let grav = DVector::from_vec(vec![0.0, 20.0 * s2]);
        let tau = &m * DVector::from_column_slice(&qdd) + &c + &grav;
        let cor = dm(&[
            &[6.0 * s2 * c2 * qd2, 6.0 * s2 * c2 * qd1 - 2.0 * s2 * qd2],
            &[-6.0 * s2 * c2 * qd1, 0.0],
        ]);
        let mdot = dm(&[
            &[12.0 * s2 * c2 * qd2, -2.0 * s2 * qd2],
            &[-2.0 * s2 * qd2, 0.0],
        ]);
        let j_b = dm(&[
            &[0.0, 1.0],
            &[s2, 0.0],
            &[c2, 0.0],
            &[-s2, 0.0],
            &[c2, 1.0],
            &[-s2, 0.0],
        ]);
        let kinetic =
            4.0 * qd1 * qd1 + 3.0 * qd2 * qd2 + 3.0 * s2 * s2 * qd1 * qd1 + 2.0 * c2 * qd1 * qd2;

        cmp("M", dr::mass_matrix(&robot, &q).as_slice(), m.as_slice());
        cmp(
            "c",
            dr::vel_quadratic_forces(&robot, &q, &qd).as_slice(),
            c.as_slice(),
        );
        cmp(
            "g",
            dr::gravity_forces(&robot, &q, &g).as_slice(),
            grav.as_slice(),
        );
        let zero_tip = Vector6::zeros();
        cmp(
            "tau",
            dr::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &zero_tip).as_slice(),
            tau.as_slice(),
        );
        cmp(
            "C",
            dr::coriolis_matrix(&robot, &q, &qd).as_slice(),
            cor.as_slice(),
        );
        cmp(
            "Mdot",
            dr::mass_matrix_dot(&robot, &q, &qd).as_slice(),
            mdot.as_slice(),
        );
        cmp(
            "J_b",
            dr::jacobian_body(&robot, &q).as_slice(),
            j_b.as_slice(),
        );
        cmp("K", &[dr::kinetic_energy(&robot, &q, &qd)], &[kinetic]);
        // P = −20 c2 with the model's gravity (0, 0, −10): the pendulum hangs at q = 0.
        cmp("P", &[dr::potential_energy(&robot, &q, &g)], &[-20.0 * c2]);
    }
    max.report("pendulum closed forms");
}

/// `M(π/4, π/4) = [[11, √2], [√2, 6]]`, eigenvalues `(17 ∓ √33)/2`, static torque `(0, 10√2)`.
#[test]
fn pendulum_at_pi_over_4() {
    let (_, robot) = seed_model("rotational_pendulum_ex8_4");
    let q = [std::f64::consts::FRAC_PI_4; 2];
    let m = dr::mass_matrix(&robot, &q);
    let r2 = std::f64::consts::SQRT_2;
    check(
        "M(π/4, π/4)",
        m.as_slice(),
        dm(&[&[11.0, r2], &[r2, 6.0]]).as_slice(),
    );
    let mut eig: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
    eig.sort_by(f64::total_cmp);
    let s33 = 33f64.sqrt();
    check(
        "eigenvalues",
        &eig,
        &[(17.0 - s33) / 2.0, (17.0 + s33) / 2.0],
    );
    check(
        "static torque",
        dr::gravity_forces(&robot, &q, &robot.gravity).as_slice(),
        &[0.0, 10.0 * r2],
    );
}

/// The pendulum's `equivalent_Glists` (inertias that differ only where no joint-space quantity
/// sees them) give the same M, c, g and τ.
#[test]
fn pendulum_equivalent_glists() {
    let (model, robot) = seed_model("rotational_pendulum_ex8_4");
    let g = robot.gravity;
    let mut rng = Rng::new(841);
    let states: Vec<_> = (0..10)
        .map(|_| {
            (
                rng.vector(2, -3.0, 3.0),
                rng.vector(2, -2.0, 2.0),
                rng.vector(2, -2.0, 2.0),
            )
        })
        .collect();
    let equivalents = model["equivalent_Glists"].as_array().unwrap();
    assert_eq!(equivalents.len(), 2);
    for (e, eq) in equivalents.iter().enumerate() {
        let mut alt_model = model.clone();
        alt_model["Glist"] = eq["Glist"].clone();
        let alt = common::robot_from_lists(&alt_model, &model["Slist"], &model["gravity"], true);
        assert_ne!(alt.g_list(), robot.g_list());
        for (q, qd, qdd) in &states {
            let f_tip = Vector6::zeros();
            let what = format!("equivalent Glist {e}");
            check(
                &format!("{what} M"),
                dr::mass_matrix(&alt, q).as_slice(),
                dr::mass_matrix(&robot, q).as_slice(),
            );
            check(
                &format!("{what} tau"),
                dr::inverse_dynamics(&alt, q, qd, qdd, &g, &f_tip).as_slice(),
                dr::inverse_dynamics(&robot, q, qd, qdd, &g, &f_tip).as_slice(),
            );
        }
    }
}

/// On every seed model and sample: `Ṁ − 2C` is skew-symmetric, `C θ̇ = c`, and the closed
/// form of Ṁ matches central differences of M along θ̇ (step 1e-6, ≤ 1e-7·max(1, |x|)).
#[test]
fn seed_models_mdot_identities() {
    for name in ["rotational_pendulum_ex8_4", "spatial_3R", "spatial_RPR"] {
        let (model, robot) = seed_model(name);
        let mut max = MaxErr::default();
        for s in model["samples"].as_array().unwrap() {
            let (q, qd) = (vec_of(&s["q"]), vec_of(&s["qd"]));
            let mdot = dr::mass_matrix_dot(&robot, &q, &qd);
            let c_mat = dr::coriolis_matrix(&robot, &q, &qd);
            let n_mat = &mdot - &c_mat * 2.0;
            let skew = (&n_mat + n_mat.transpose()).amax();
            assert!(
                skew <= 1e-12 * mdot.amax().max(1.0),
                "{name}: Ṁ − 2C not skew: {skew:e}"
            );
            max.note("skew(Ṁ − 2C)", skew);
            let c = dr::vel_quadratic_forces(&robot, &q, &qd);
            max.note(
                "C θ̇ − c",
                check(
                    &format!("{name} C θ̇"),
                    (&c_mat * DVector::from_column_slice(&qd)).as_slice(),
                    c.as_slice(),
                ),
            );
            let h = 1e-6;
            let shift = |sign: f64| -> Vec<f64> {
                q.iter().zip(&qd).map(|(a, b)| a + sign * h * b).collect()
            };
            let fd = (dr::mass_matrix(&robot, &shift(1.0)) - dr::mass_matrix(&robot, &shift(-1.0)))
                / (2.0 * h);
            for (x, y) in fd.iter().zip(mdot.iter()) {
                assert!(
                    (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                    "{name}: Ṁ {y} vs central difference {x}"
                );
                max.note("Ṁ − central difference", (x - y).abs());
            }
        }
        max.report(name);
    }
}

#[test]
fn seed_check_tolerance_helper_rejects_a_wrong_value() {
    let r = std::panic::catch_unwind(|| check_tol("x", &[1.0 + 1e-6], &[1.0], 1e-9, 1e-12));
    assert!(r.is_err());
}
