//! The reference implementation, and the generated code, against numbers nobody here wrote:
//! Pinocchio 4.1.0 on the UR5, Panda, double-pendulum and rand7 URDFs, and the Modern
//! Robotics library on the TOML versions of its UR5 and random 7-joint chain.
//!
//! ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 for every quantity; the generated f32 cases at 1e-4·‖y‖∞
//! (q̈ 1e-3·‖y‖∞), as in `generated_vs_reference`.

use dynamics_model::LoadOptions;
use dynamics_tests::{data_dir, reference_json, Spec, CASES};
use dynamics_tests::{row_major, rows, vecf};
use nalgebra::{Vector3, Vector6};
use serde_json::Value;

use crate::tolerance::{check, check_case};

#[test]
fn reference_implementation_reproduces_pinocchio() {
    for (file, urdf) in [
        ("ur5.json", "ur5"),
        ("panda.json", "panda"),
        ("double_pendulum.json", "double_pendulum"),
        ("rand7.json", "rand7"),
    ] {
        let data = reference_json(file);
        let tip = data["ee_frame"].as_str().expect("ee_frame");
        let path = data_dir().join(format!("robots/{urdf}.urdf"));
        let options = LoadOptions {
            tip: Some(tip.to_string()),
            ..Default::default()
        };
        let robot = dynamics_model::load_file(&path, &options).expect("loads");
        let names: Vec<String> = data["joint_names"]
            .as_array()
            .expect("names")
            .iter()
            .map(|x| x.as_str().expect("name").to_string())
            .collect();
        assert_eq!(robot.joint_names(), names, "{urdf}: joint order");
        let g = Vector3::from_vec(vecf(&data["gravity"]));
        let zero6 = Vector6::zeros();
        let mut worst = [0.0f64; 7];
        for s in data["samples"].as_array().expect("samples") {
            let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
            let m = dynamics_reference::mass_matrix(&robot, &q);
            worst[0] = worst[0].max(check("M", &row_major(&m), &rows(&s["M"])));
            let c = dynamics_reference::vel_quadratic_forces(&robot, &q, &qd);
            worst[1] = worst[1].max(check("c", c.as_slice(), &vecf(&s["c"])));
            let gq = dynamics_reference::gravity_forces(&robot, &q, &g);
            worst[2] = worst[2].max(check("g", gq.as_slice(), &vecf(&s["g"])));
            let tau = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &zero6);
            worst[3] = worst[3].max(check("τ", tau.as_slice(), &vecf(&s["tau"])));
            let fd = dynamics_reference::forward_dynamics(
                &robot,
                &q,
                &qd,
                &vecf(&s["tau_rand"]),
                &g,
                &zero6,
            )
            .expect("M positive definite");
            worst[4] = worst[4].max(check("q̈", fd.as_slice(), &vecf(&s["qdd_fd"])));
            // Coriolis matrices are not unique; ours (Christoffel) and Pinocchio's both give
            // c = C q̇, and both make Ṁ − 2C skew. Where they are equal, compare them.
            let cm = dynamics_reference::coriolis_matrix(&robot, &q, &qd);
            let cq = &cm * nalgebra::DVector::from_vec(qd.clone());
            worst[5] = worst[5].max(check("C q̇", cq.as_slice(), &vecf(&s["c"])));
            let pose = dynamics_reference::end_effector_pose(&robot, &q);
            let pose: Vec<f64> = (0..4)
                .flat_map(|i| (0..4).map(move |j| (i, j)))
                .map(|(i, j)| pose[(i, j)])
                .collect();
            worst[6] = worst[6].max(check("oMf", &pose, &rows(&s["oMf"])));
        }
        println!("{urdf}: worst relative errors M, c, g, τ, q̈, Cq̇, pose = {worst:?}");
    }
}

#[test]
fn christoffel_coriolis_matrix_equals_pinocchios() {
    // Pinocchio's computeCoriolisMatrix is built from the same Christoffel-symbol identity
    // for these serial chains; the test documents that the two agree.
    for (file, urdf) in [
        ("ur5.json", "ur5"),
        ("panda.json", "panda"),
        ("rand7.json", "rand7"),
    ] {
        let data = reference_json(file);
        let path = data_dir().join(format!("robots/{urdf}.urdf"));
        let robot = dynamics_model::load_file(&path, &LoadOptions::default()).expect("loads");
        let mut worst = 0.0f64;
        for s in data["samples"].as_array().expect("samples") {
            let (q, qd) = (vecf(&s["q"]), vecf(&s["qd"]));
            let cm = dynamics_reference::coriolis_matrix(&robot, &q, &qd);
            worst = worst.max(check("C", &row_major(&cm), &rows(&s["C"])));
        }
        println!("{urdf}: Christoffel C vs Pinocchio C: {worst:e}");
    }
}

#[test]
fn generated_code_reproduces_pinocchio() {
    for case in CASES {
        let Spec::Urdf(urdf, _) = case.spec else {
            continue;
        };
        let Ok(text) = std::fs::read_to_string(data_dir().join(format!("reference/{urdf}.json")))
        else {
            continue; // mr_ur5.urdf has Modern Robotics numbers instead (below).
        };
        let data: Value = serde_json::from_str(&text).expect("json");
        if data["schema"].as_str() != Some("robot-dynamics-reference/1") {
            continue; // mr_ur5.json holds Modern Robotics numbers (checked below).
        }
        for s in data["samples"].as_array().expect("samples") {
            let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
            let m = case.imp.mass_matrix(&q);
            check_case(case, "M", &row_major(&m), &rows(&s["M"]), 1e-4);
            let c = case.imp.coriolis(&q, &qd);
            check_case(case, "c", c.as_slice(), &vecf(&s["c"]), 1e-4);
            let g = case.imp.gravity(&q);
            check_case(case, "g", g.as_slice(), &vecf(&s["g"]), 1e-4);
            let tau = case.imp.inverse_dynamics(&q, &qd, &qdd);
            check_case(case, "τ", tau.as_slice(), &vecf(&s["tau"]), 1e-4);
            let fd = case.imp.forward_dynamics(&q, &qd, &vecf(&s["tau_rand"]));
            check_case(case, "q̈", fd.as_slice(), &vecf(&s["qdd_fd"]), 1e-3);
        }
    }
}

#[test]
fn toml_robots_and_their_code_reproduce_the_modern_robotics_library() {
    for (name, file) in [("mr_ur5", "mr_ur5.json"), ("rand7", "mr_random7.json")] {
        let robot = dynamics_model::load(name, &LoadOptions::default()).expect("shipped");
        let generated = CASES
            .iter()
            .find(|c| matches!(c.spec, Spec::Shipped(n) if n == name) && c.scalar == "f64")
            .expect("compiled");
        let data = reference_json(file);
        let g = Vector3::from_vec(vecf(&data["model"]["g"]));
        for s in data["samples"].as_array().expect("samples") {
            let q = vecf(&s["thetalist"]);
            let qd = vecf(&s["dthetalist"]);
            let qdd = vecf(&s["ddthetalist"]);
            let f_tip = Vector6::from_vec(vecf(&s["Ftip"]));
            let tau_in = vecf(&s["taulist"]);
            let out = &s["outputs"];
            let tau = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &f_tip);
            check("ID", tau.as_slice(), &vecf(&out["InverseDynamics"]));
            let m = dynamics_reference::mass_matrix(&robot, &q);
            check("M", &row_major(&m), &rows(&out["MassMatrix"]));
            let fd = dynamics_reference::forward_dynamics(&robot, &q, &qd, &tau_in, &g, &f_tip)
                .expect("pd");
            check("FD", fd.as_slice(), &vecf(&out["ForwardDynamics"]));
            // Generated code (no F_tip): τ_ID − J_bᵀF_tip.
            let ee = dynamics_reference::end_effector_forces(&robot, &q, &f_tip);
            let want: Vec<f64> = vecf(&out["InverseDynamics"])
                .iter()
                .zip(ee.iter())
                .map(|(a, b)| a - b)
                .collect();
            check(
                "generated τ",
                generated.imp.inverse_dynamics(&q, &qd, &qdd).as_slice(),
                &want,
            );
            check(
                "generated M",
                &row_major(&generated.imp.mass_matrix(&q)),
                &rows(&out["MassMatrix"]),
            );
            check(
                "generated c",
                generated.imp.coriolis(&q, &qd).as_slice(),
                &vecf(&out["VelQuadraticForces"]),
            );
            check(
                "generated g",
                generated.imp.gravity(&q).as_slice(),
                &vecf(&out["GravityForces"]),
            );
        }
    }
}

#[test]
fn ur5_with_continuous_joints_has_the_same_dynamics() {
    let text = std::fs::read_to_string(data_dir().join("robots/ur5.urdf")).expect("ur5");
    let continuous = text.replace("type=\"revolute\"", "type=\"continuous\"");
    assert_ne!(text, continuous);
    let opts = LoadOptions::default();
    let a = dynamics_model::load::from_str(&text, dynamics_model::Format::Urdf, "ur5.urdf", &opts)
        .expect("ur5");
    let b = dynamics_model::load::from_str(
        &continuous,
        dynamics_model::Format::Urdf,
        "ur5c.urdf",
        &opts,
    )
    .expect("continuous ur5");
    // No position limits; the velocity and effort limits the file gives are kept.
    for (ja, jb) in a.joints.iter().zip(&b.joints) {
        let (la, lb) = (
            ja.limits.expect("ur5 limits"),
            jb.limits.expect("velocity, effort"),
        );
        assert_eq!((lb.lower, lb.upper), (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!((lb.velocity, lb.effort), (la.velocity, la.effort));
        assert!(lb.velocity.is_some() && lb.effort.is_some());
    }
    let data = reference_json("ur5.json");
    let g = Vector3::new(0.0, 0.0, -9.81);
    for s in data["samples"].as_array().expect("samples") {
        let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
        let ta = dynamics_reference::inverse_dynamics(&a, &q, &qd, &qdd, &g, &Vector6::zeros());
        let tb = dynamics_reference::inverse_dynamics(&b, &q, &qd, &qdd, &g, &Vector6::zeros());
        assert_eq!(ta, tb);
        check("τ continuous", tb.as_slice(), &vecf(&s["tau"]));
    }
}
