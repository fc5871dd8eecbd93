//! The URDF loader against Pinocchio 4.1.0 (`tests/data/reference/*.json`): per joint, the
//! placement `M_{i−1,i}`, mass, centre of mass, inertia about the centre of mass, the axis
//! in the joint frame; the joint order; and the joint and end-effector poses at every
//! sample's q, computed by the product of exponentials from `S_i` and `M_{0i}`.

mod urdf_common;

use dynamics_model::lie::{adjoint, trans_inv};
use dynamics_model::{JointKind, LoadOptions};
use nalgebra::Vector6;
use urdf_common::*;

/// Compares the robot loaded from `urdf` with the reference `json`; returns the largest
/// absolute error seen (model, poses).
fn compare(urdf: &str, json: &str) -> (f64, f64) {
    let reference = reference(json);
    let text = robot_text(urdf);
    let options = LoadOptions {
        frames: None,
        tip: Some(
            reference["ee_frame"]
                .as_str()
                .expect("ee_frame")
                .to_string(),
        ),
        lock: Vec::new(),
        floating_base: false,
        gravity: None,
        armature: Vec::new(),
        snap_angles: None,
    };
    let robot = load_text(&text, urdf, &options).expect("loads");

    let names: Vec<&str> = reference["joint_names"]
        .as_array()
        .expect("names")
        .iter()
        .map(|v| v.as_str().expect("name"))
        .collect();
    assert_eq!(robot.joint_names(), names, "{urdf}: joint order");
    assert_eq!(
        robot.end_effector.name,
        reference["ee_frame"].as_str().unwrap()
    );

    let mut model_err: f64 = 0.0;
    let poses = robot.home_poses();
    for (i, pj) in reference["pinocchio_model"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let what = |w: &str| format!("{urdf}: joint {i} `{}`: {w}", robot.joints[i].name);
        let link = &robot.links[i];
        let m = link.inertia.mass();
        model_err = model_err
            .max(assert_close(
                &what("placement"),
                link.home.as_slice(),
                mat4(&pj["placement"]).as_slice(),
            ))
            .max(assert_close(&what("mass"), &[m], &[f(&pj["mass"])]));
        if m > 0.0 {
            model_err = model_err
                .max(assert_close(
                    &what("com"),
                    link.inertia.com().as_slice(),
                    vec3(&pj["com"]).as_slice(),
                ))
                .max(assert_close(
                    &what("inertia_about_com"),
                    link.inertia.rotational_about_com().as_slice(),
                    mat3(&pj["inertia_about_com"]).as_slice(),
                ));
        }
        // Ad_{M_{0i}⁻¹} S_i is the joint's motion in its own frame: (axis, 0) or (0, axis).
        let local = adjoint(&trans_inv(&poses[i + 1])) * robot.joints[i].screw;
        let axis = vec3(&pj["axis"]);
        let want = match robot.joints[i].kind {
            JointKind::Revolute => Vector6::new(axis[0], axis[1], axis[2], 0.0, 0.0, 0.0),
            JointKind::Prismatic => Vector6::new(0.0, 0.0, 0.0, axis[0], axis[1], axis[2]),
        };
        assert_eq!(
            robot.joints[i].kind.as_str(),
            if pj["kind"] == "prismatic" {
                "prismatic"
            } else {
                "revolute"
            }
        );
        model_err = model_err.max(assert_close(
            &what("axis"),
            local.as_slice(),
            want.as_slice(),
        ));
    }

    let mut pose_err: f64 = 0.0;
    for (k, s) in reference["samples"].as_array().unwrap().iter().enumerate() {
        let q: Vec<f64> = s["q"].as_array().unwrap().iter().map(f).collect();
        let (frames, ee) = poses_at(&robot, &q);
        pose_err = pose_err.max(assert_close(
            &format!("{urdf}: sample {k}: oMf"),
            ee.as_slice(),
            mat4(&s["oMf"]).as_slice(),
        ));
        for (i, t) in frames.iter().enumerate() {
            pose_err = pose_err.max(assert_close(
                &format!("{urdf}: sample {k}: oMi[{i}]"),
                t.as_slice(),
                mat4(&s["oMi"][i]).as_slice(),
            ));
        }
    }
    eprintln!("{urdf}: max model error {model_err:e}, max pose error {pose_err:e}");
    (model_err, pose_err)
}

#[test]
fn ur5_matches_pinocchio() {
    compare("ur5.urdf", "ur5.json");
}

#[test]
fn panda_matches_pinocchio() {
    // The fingers are already fixed in the test file (the JSON's `locked_joints`), so no lock.
    compare("panda.urdf", "panda.json");
}

#[test]
fn double_pendulum_matches_pinocchio() {
    compare("double_pendulum.urdf", "double_pendulum.json");
}

#[test]
fn rand7_matches_pinocchio() {
    compare("rand7.urdf", "rand7.json");
}
