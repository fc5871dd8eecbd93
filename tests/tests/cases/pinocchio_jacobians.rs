//! The reference implementation (and the generated code) against Pinocchio 4.1.0's frame
//! Jacobians of the end effector on the UR5, Panda, rand7 and double-pendulum URDFs, and the
//! reference against Pinocchio's dynamics with armature on the Panda
//! (`data/reference/<robot>.jacobians.json`, made by `tools/jacobian_reference.py`).
//!
//! Pinocchio's Jacobian rows are `(v, ω)`, ours `(ω, v)`: rows 0..3 and 3..6 swap.
//! ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 for every quantity; the generated f32 cases at 1e-4·‖y‖∞,
//! as in `generated_vs_reference`.

use dynamics_model::{LoadOptions, Robot};
use dynamics_tests::{data_dir, reference_json, Spec, CASES};
use dynamics_tests::{row_major, rows, vecf};
use nalgebra::{Vector3, Vector6};
use serde_json::Value;

use crate::tolerance::{check, check_case};

const ROBOTS: [&str; 4] = ["ur5", "panda", "rand7", "double_pendulum"];

/// A Pinocchio Jacobian (rows `(v, ω)`, row-major) in our row order `(ω, v)`, row-major.
fn pin_jacobian(v: &Value) -> Vec<f64> {
    let r: Vec<Vec<f64>> = v.as_array().expect("rows").iter().map(vecf).collect();
    assert_eq!(r.len(), 6);
    (0..6).flat_map(|k| r[(k + 3) % 6].clone()).collect()
}

/// The robot of `<name>.urdf` with the file's end-effector frame, checked against its joints.
fn robot(name: &str, data: &Value) -> Robot {
    let tip = data["ee_frame"].as_str().expect("ee_frame");
    let path = data_dir().join(format!("robots/{name}.urdf"));
    let options = LoadOptions {
        tip: Some(tip.to_string()),
        ..Default::default()
    };
    let robot = dynamics_model::load_file(&path, &options).expect("loads");
    assert_eq!(robot.end_effector.name, tip);
    let names: Vec<&str> = data["joint_names"]
        .as_array()
        .expect("names")
        .iter()
        .map(|x| x.as_str().expect("name"))
        .collect();
    assert_eq!(robot.joint_names(), names, "{name}: joint order");
    robot
}

#[test]
fn reference_jacobians_reproduce_pinocchio() {
    for name in ROBOTS {
        let data = reference_json(&format!("{name}.jacobians.json"));
        assert_eq!(data["generator"]["pinocchio"].as_str(), Some("4.1.0"));
        let robot = robot(name, &data);
        let mut worst = [0.0f64; 2];
        let samples = data["samples"].as_array().expect("samples");
        assert_eq!(samples.len(), 25);
        for (k, s) in samples.iter().enumerate() {
            let q = vecf(&s["q"]);
            let js = dynamics_reference::jacobian_space(&robot, &q);
            let jb = dynamics_reference::jacobian_body(&robot, &q);
            worst[0] = worst[0].max(check(
                &format!("{name} sample {k}: J_s vs WORLD"),
                &row_major(&js),
                &pin_jacobian(&s["J_world"]),
            ));
            worst[1] = worst[1].max(check(
                &format!("{name} sample {k}: J_b vs LOCAL"),
                &row_major(&jb),
                &pin_jacobian(&s["J_local"]),
            ));
        }
        println!("{name}: reference J_s, J_b vs Pinocchio WORLD, LOCAL: worst relative {worst:?}");
    }
}

#[test]
fn generated_jacobians_reproduce_pinocchio() {
    let mut seen = Vec::new();
    for case in CASES {
        let Spec::Urdf(name, _) = case.spec else {
            continue;
        };
        if !ROBOTS.contains(&name) {
            continue;
        }
        let data = reference_json(&format!("{name}.jacobians.json"));
        assert_eq!(
            case.spec.robot().end_effector.name,
            data["ee_frame"].as_str().expect("ee_frame"),
            "{name}: the generated robot's end effector"
        );
        let mut worst = [0.0f64; 2];
        for (k, s) in data["samples"]
            .as_array()
            .expect("samples")
            .iter()
            .enumerate()
        {
            let q = vecf(&s["q"]);
            worst[0] = worst[0].max(check_case(
                case,
                &format!("generated {name} sample {k}: J_s vs WORLD"),
                &row_major(&case.imp.jacobian_space(&q)),
                &pin_jacobian(&s["J_world"]),
                1e-4,
            ));
            worst[1] = worst[1].max(check_case(
                case,
                &format!("generated {name} sample {k}: J_b vs LOCAL"),
                &row_major(&case.imp.jacobian_body(&q)),
                &pin_jacobian(&s["J_local"]),
                1e-4,
            ));
        }
        println!("generated {name}: J_s, J_b vs Pinocchio: worst relative {worst:?}");
        seen.push(name);
    }
    seen.sort_unstable();
    seen.dedup(); // a robot may be generated more than once (e.g. the portable copy of the Panda)
    assert_eq!(seen, ["double_pendulum", "panda", "rand7", "ur5"]);
}

#[test]
fn reference_with_armature_reproduces_pinocchio() {
    let data = reference_json("panda.jacobians.json");
    let case = &data["armature_case"];
    let mut robot = robot("panda", &data);
    let armature = vecf(&case["armature"]);
    assert_eq!(armature.len(), robot.dof());
    for (joint, a) in robot.joints.iter_mut().zip(&armature) {
        joint.rotor_inertia = *a;
        joint.gear_ratio = 1.0;
        assert_eq!(joint.armature(), *a);
    }
    let g = Vector3::from_vec(vecf(&reference_json("panda.json")["gravity"]));
    let zero6 = Vector6::zeros();
    let samples = case["samples"].as_array().expect("samples");
    assert_eq!(samples.len(), 10);
    let mut worst = [0.0f64; 3];
    for (k, s) in samples.iter().enumerate() {
        let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
        let tau = dynamics_reference::rnea(&robot, &q, &qd, &qdd, &g, &zero6);
        worst[0] = worst[0].max(check(
            &format!("panda armature sample {k}: rnea"),
            tau.as_slice(),
            &vecf(&s["tau"]),
        ));
        let m = dynamics_reference::crba(&robot, &q);
        worst[1] = worst[1].max(check(
            &format!("panda armature sample {k}: crba"),
            &row_major(&m),
            &rows(&s["M"]),
        ));
        let fd =
            dynamics_reference::forward_dynamics(&robot, &q, &qd, &vecf(&s["tau_in"]), &g, &zero6)
                .expect("M positive definite");
        worst[2] = worst[2].max(check(
            &format!("panda armature sample {k}: aba"),
            fd.as_slice(),
            &vecf(&s["qdd_fd"]),
        ));
    }
    println!("panda with armature: rnea, crba, aba worst relative {worst:?}");
}

/// The generated code of the Panda with the same armature (`Spec::PandaArmature`, compiled
/// by build.rs) against Pinocchio's `rnea`, `crba` and `aba` with `model.armature` set.
#[test]
fn generated_with_armature_reproduces_pinocchio() {
    let data = reference_json("panda.jacobians.json");
    let case = &data["armature_case"];
    let generated = dynamics_tests::CASES
        .iter()
        .find(|c| matches!(c.spec, dynamics_tests::Spec::PandaArmature))
        .expect("the Panda with armature is compiled");
    let robot = generated.spec.robot();
    let armature: Vec<f64> = robot.joints.iter().map(|j| j.armature()).collect();
    assert_eq!(
        armature,
        vecf(&case["armature"]),
        "same armature as Pinocchio's"
    );
    let mut worst = [0.0f64; 3];
    for (k, s) in case["samples"]
        .as_array()
        .expect("samples")
        .iter()
        .enumerate()
    {
        let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
        let imp = generated.imp;
        worst[0] = worst[0].max(check(
            &format!("generated panda armature sample {k}: rnea"),
            imp.inverse_dynamics(&q, &qd, &qdd).as_slice(),
            &vecf(&s["tau"]),
        ));
        worst[1] = worst[1].max(check(
            &format!("generated panda armature sample {k}: crba"),
            &row_major(&imp.mass_matrix(&q)),
            &rows(&s["M"]),
        ));
        worst[2] = worst[2].max(check(
            &format!("generated panda armature sample {k}: aba"),
            imp.forward_dynamics(&q, &qd, &vecf(&s["tau_in"]))
                .as_slice(),
            &vecf(&s["qdd_fd"]),
        ));
    }
    println!("generated panda with armature: rnea, crba, aba worst relative {worst:?}");
}
