//! The reference against the Modern Robotics library's own outputs (`tests/data/reference/mr_*.json`,
//! generated with modern_robotics 1.1.1): every chapter-8 function on the docstring example, the
//! UR5 and a random 7-joint chain, and the explicit-Euler free falls.

mod common;

use common::{check, check_tol, dvec, load_json, mat4, mat_of, num, vec6, vec_of, MaxErr};
use dynamics_model::Robot;
use dynamics_reference as dr;
use nalgebra::{DMatrix, Vector3, Vector6};
use serde_json::Value;

fn mr_robot(file: &Value, checked: bool) -> Robot {
    let model = &file["model"];
    let robot = common::robot_from_lists(model, &model["screw_axes"], &model["g"], checked);
    // The 6×n `Slist` (columns = screws) must be the same axes as `screw_axes`.
    let slist = mat_of(&model["Slist"]);
    for (i, s) in robot.s_list().iter().enumerate() {
        assert_eq!(
            slist.column(i).into_owned(),
            nalgebra::DVector::from_column_slice(s.as_slice())
        );
    }
    robot
}

fn g_of(file: &Value) -> Vector3<f64> {
    common::vec3(&file["model"]["g"])
}

/// Checks the outputs of one set of inputs (the docstring example or one sample).
#[allow(clippy::too_many_arguments)]
fn check_outputs(
    robot: &Robot,
    label: &str,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &[f64],
    g: &Vector3<f64>,
    f_tip: &Vector6<f64>,
    out: &Value,
    max: &mut MaxErr,
) {
    let cmp = |name: &str, x: &[f64], max: &mut MaxErr| {
        let y = if out[name][0].is_array() {
            mat_of(&out[name]).as_slice().to_vec()
        } else {
            vec_of(&out[name])
        };
        max.note(name, check(&format!("{label} {name}"), x, &y));
    };
    cmp(
        "InverseDynamics",
        dr::inverse_dynamics(robot, q, qd, qdd, g, f_tip).as_slice(),
        max,
    );
    cmp("MassMatrix", dr::mass_matrix(robot, q).as_slice(), max);
    cmp(
        "VelQuadraticForces",
        dr::vel_quadratic_forces(robot, q, qd).as_slice(),
        max,
    );
    cmp(
        "GravityForces",
        dr::gravity_forces(robot, q, g).as_slice(),
        max,
    );
    cmp(
        "EndEffectorForces",
        dr::end_effector_forces(robot, q, f_tip).as_slice(),
        max,
    );
    let fd = dr::forward_dynamics(robot, q, qd, tau, g, f_tip).expect("M positive definite");
    cmp("ForwardDynamics", fd.as_slice(), max);
    if !out["FKinSpace"].is_null() {
        cmp(
            "FKinSpace",
            DMatrix::from_column_slice(4, 4, dr::end_effector_pose(robot, q).as_slice()).as_slice(),
            max,
        );
        cmp(
            "JacobianSpace",
            dr::jacobian_space(robot, q).as_slice(),
            max,
        );
    }
}

#[test]
fn docstring3_every_output() {
    let file = load_json("reference/mr_docstring3.json");
    // S₁ = (1,0,1, 0,1,0) has |ω| = √2: accepted as given, like the book's library.
    let robot = mr_robot(&file, false);
    let inp = &file["inputs"];
    let mut max = MaxErr::default();
    check_outputs(
        &robot,
        "docstring3",
        &vec_of(&inp["thetalist"]),
        &vec_of(&inp["dthetalist"]),
        &vec_of(&inp["ddthetalist"]),
        &vec_of(&inp["taulist"]),
        &common::vec3(&inp["g"]),
        &vec6(&inp["Ftip"]),
        &file["outputs"],
        &mut max,
    );
    max.report("docstring3");
}

#[test]
fn docstring3_forward_dynamics_trajectory_example() {
    let file = load_json("reference/mr_docstring3.json");
    let robot = mr_robot(&file, false);
    let inp = &file["inputs"];
    let ex = &file["ForwardDynamicsTrajectory_example"];
    let (thetamat, dthetamat) = dr::forward_dynamics_trajectory(
        &robot,
        &vec_of(&inp["thetalist"]),
        &vec_of(&inp["dthetalist"]),
        &mat_of(&ex["taumat"]),
        &common::vec3(&inp["g"]),
        &mat_of(&ex["Ftipmat"]),
        num(&ex["dt"]),
        ex["intRes"].as_u64().unwrap() as usize,
    )
    .expect("M positive definite");
    let e1 = check(
        "thetamat",
        thetamat.as_slice(),
        mat_of(&ex["thetamat"]).as_slice(),
    );
    let e2 = check(
        "dthetamat",
        dthetamat.as_slice(),
        mat_of(&ex["dthetamat"]).as_slice(),
    );
    eprintln!("docstring3 trajectory: max error thetamat {e1:.3e}, dthetamat {e2:.3e}");
}

fn samples_of(name: &str) {
    let file = load_json(&format!("reference/{name}.json"));
    let robot = mr_robot(&file, true);
    let g = g_of(&file);
    let samples = file["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 25);
    let mut max = MaxErr::default();
    for (k, s) in samples.iter().enumerate() {
        check_outputs(
            &robot,
            &format!("{name} sample {k}"),
            &vec_of(&s["thetalist"]),
            &vec_of(&s["dthetalist"]),
            &vec_of(&s["ddthetalist"]),
            &vec_of(&s["taulist"]),
            &g,
            &vec6(&s["Ftip"]),
            &s["outputs"],
            &mut max,
        );
        // FKinSpace is also given as a 4×4 transform: the same numbers as a Matrix4.
        let t = dr::end_effector_pose(&robot, &vec_of(&s["thetalist"]));
        check(
            "FKinSpace as Matrix4",
            t.as_slice(),
            mat4(&s["outputs"]["FKinSpace"]).as_slice(),
        );
    }
    max.report(name);
}

#[test]
fn ur5_every_output_of_every_sample() {
    samples_of("mr_ur5");
}

#[test]
fn random7_every_output_of_every_sample() {
    samples_of("mr_random7");
}

/// The potential energy as the book's library computes it: its `MatrixExp6` treats a joint
/// with `|ω θ| < 1e-6` (`NearZero`) as a pure translation `v θ`, dropping the rotation. The
/// reference energies of the UR5 free fall's rows 1–2 (a joint at θ = −4e-8) carry that
/// approximation (about 2e-8 J), so those rows are checked against this emulation, and
/// against the exact [`dr::potential_energy`] with a tolerance of 1e-7 relative.
fn potential_energy_mr_near_zero(robot: &Robot, q: &[f64], g: &Vector3<f64>) -> f64 {
    let mut emulated = robot.clone();
    for (j, &theta) in emulated.joints.iter_mut().zip(q) {
        if (j.screw.fixed_rows::<3>(0) * theta).norm() < 1e-6 {
            j.screw.fixed_rows_mut::<3>(0).fill(0.0);
        }
    }
    dr::potential_energy(&emulated, q, g)
}

/// The book's explicit-Euler free fall (θ_0 = 0, θ̇_0 = 0, τ = 0, F_tip = 0, dt = 0.01,
/// intRes = 8, 300 rows), row by row, and the energy K + P of every reference row.
///
/// Rows before `late_row` are held to 1e-9 relative, later rows to `late_tol`: the random
/// chain spins chaotically, so rounding-level differences (the book inverts M, we use Cholesky)
/// grow with time.
fn free_fall(name: &str, late_row: usize, late_tol: f64) {
    let file = load_json(&format!("reference/{name}.json"));
    let robot = mr_robot(&file, true);
    let g = g_of(&file);
    let ff = &file["free_fall"];
    let steps = ff["N"].as_u64().unwrap() as usize;
    let n = robot.dof();
    let (thetamat, dthetamat) = dr::forward_dynamics_trajectory(
        &robot,
        &vec![0.0; n],
        &vec![0.0; n],
        &DMatrix::zeros(steps, n),
        &g,
        &DMatrix::zeros(steps, 6),
        num(&ff["dt"]),
        ff["intRes"].as_u64().unwrap() as usize,
    )
    .expect("M positive definite");
    let want_theta = mat_of(&ff["thetamat"]);
    let want_dtheta = mat_of(&ff["dthetamat"]);
    let energy = dvec(&ff["energy"]);
    assert_eq!(want_theta.shape(), (steps, n));
    assert_eq!(thetamat.shape(), (steps, n));

    let row = |m: &DMatrix<f64>, k: usize| -> Vec<f64> { m.row(k).iter().copied().collect() };
    let mut worst = (0.0_f64, 0.0_f64, 0.0_f64);
    for k in 0..steps {
        let tol = if k < late_row { 1e-9 } else { late_tol };
        let what = format!("{name} free fall row {k}");
        let et = check_tol(
            &format!("{what} theta"),
            &row(&thetamat, k),
            &row(&want_theta, k),
            tol,
            1e-12,
        );
        let ed = check_tol(
            &format!("{what} dtheta"),
            &row(&dthetamat, k),
            &row(&want_dtheta, k),
            tol,
            1e-12,
        );
        worst = (worst.0.max(et), worst.1.max(ed), worst.2);
        if k % 50 == 49 || k == steps - 1 {
            eprintln!(
                "{name} free fall: rows ≤ {k}: max error theta {:.3e}, dtheta {:.3e}",
                worst.0, worst.1
            );
        }

        // The energy of the reference's own rows, with the reference functions.
        let (q, qd) = (row(&want_theta, k), row(&want_dtheta, k));
        let kinetic = dr::kinetic_energy(&robot, &q, &qd);
        let e = kinetic + dr::potential_energy(&robot, &q, &g);
        let near_zero = robot
            .joints
            .iter()
            .zip(&q)
            .any(|(j, &t)| t != 0.0 && (j.screw.fixed_rows::<3>(0) * t).norm() < 1e-6);
        if near_zero {
            let e_mr = kinetic + potential_energy_mr_near_zero(&robot, &q, &g);
            check(
                &format!("{what} energy (book's NearZero)"),
                &[e_mr],
                &[energy[k]],
            );
            check_tol(&format!("{what} energy"), &[e], &[energy[k]], 1e-7, 0.0);
            eprintln!("{name} free fall row {k}: the book's NearZero exp applies; exact energy differs by {:.3e} J", e - energy[k]);
        } else {
            let err = check(&format!("{what} energy"), &[e], &[energy[k]]);
            worst.2 = worst.2.max(err);
        }
    }
    eprintln!("{name} free fall: max energy error {:.3e}", worst.2);
    // The energy drift of the book's Euler integrator (+2.70 J for the UR5, +4.68 J for random7).
    let last = steps - 1;
    let e_end = dr::kinetic_energy(&robot, &row(&thetamat, last), &row(&dthetamat, last))
        + dr::potential_energy(&robot, &row(&thetamat, last), &g);
    let drift = e_end - energy[0];
    check_tol(
        &format!("{name} energy drift"),
        &[drift],
        &[num(&ff["energy_drift"])],
        late_tol,
        1e-12,
    );
    eprintln!(
        "{name} free fall: energy drift {drift:.9} J (reference {})",
        num(&ff["energy_drift"])
    );
}

#[test]
fn ur5_free_fall_explicit_euler() {
    // Measured: ≤ 3e-14 relative on every row.
    free_fall("mr_ur5", 300, 1e-9);
}

#[test]
fn random7_free_fall_explicit_euler() {
    // Measured: ≤ 6e-11 up to row 200, growing chaotically to ≈ 4e-9 at row 299.
    free_fall("mr_random7", 200, 1e-8);
}
