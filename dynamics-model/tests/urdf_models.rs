//! The URDF loader on variants of known robots: the Modern Robotics UR5 written as a URDF
//! against the book's lists, continuous joints, locked finger joints, the shipped UR5.

mod urdf_common;

use dynamics_model::{LoadOptions, SpatialInertia};
use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};
use urdf_common::*;

/// mr_ur5.urdf puts its frames on the joint axes, MR's lists put them at the centres of
/// mass; the screw axes S_i (space frame) and the end effector's M = M_{0,n+1} do not depend
/// on the link frames, and G_i moves from the COM frame {c_i} to the joint frame {j_i} by
/// `G_j = [Ad_{T_cj}]ᵀ G_c [Ad_{T_cj}]` with `T_jc = M_{0j}⁻¹ M_{0c}`.
#[test]
fn mr_ur5_urdf_equals_the_book_lists() {
    let reference = reference("mr_ur5.json");
    let model = &reference["model"];
    let robot =
        load_text(&robot_text("mr_ur5.urdf"), "mr_ur5.urdf", &tip("ee_link")).expect("loads");
    assert_eq!(robot.dof(), 6);
    let mut max_err: f64 = 0.0;
    // M_{0c_i}: products of the MR home frames.
    let mut m0c: Vec<Matrix4<f64>> = Vec::new();
    let mut t = Matrix4::identity();
    for m in model["Mlist"].as_array().unwrap() {
        t *= mat4(m);
        m0c.push(t);
    }
    let ours = robot.home_poses();
    max_err = max_err.max(assert_close("M", ours[7].as_slice(), m0c[6].as_slice()));
    for i in 0..6 {
        let s = &model["screw_axes"][i];
        let want = Vector6::from_fn(|k, _| f(&s[k]));
        max_err = max_err.max(assert_close(
            &format!("S{}", i + 1),
            robot.joints[i].screw.as_slice(),
            want.as_slice(),
        ));
        let g_c = SpatialInertia(Matrix6::from_fn(|r, c| f(&model["Glist"][i][r][c])));
        let t_jc = dynamics_model::lie::trans_inv(&ours[i + 1]) * m0c[i];
        let want = g_c.expressed_in(&t_jc);
        max_err = max_err.max(assert_close(
            &format!("G{}", i + 1),
            robot.links[i].inertia.0.as_slice(),
            want.0.as_slice(),
        ));
    }
    eprintln!("mr_ur5: max error {max_err:e}");
}

#[test]
#[allow(clippy::approx_constant)] // the decimals the UR5 file writes for 2π and π
fn continuous_joints_give_the_same_model_without_position_limits() {
    let text = robot_text("ur5.urdf");
    let revolute = load_text(&text, "ur5.urdf", &LoadOptions::default()).expect("revolute");
    let continuous_text = text.replace(r#"type="revolute""#, r#"type="continuous""#);
    assert_ne!(text, continuous_text);
    let continuous =
        load_text(&continuous_text, "ur5.urdf", &LoadOptions::default()).expect("continuous");
    assert_eq!(continuous.links, revolute.links);
    assert_eq!(continuous.end_effector, revolute.end_effector);
    for (c, r) in continuous.joints.iter().zip(&revolute.joints) {
        assert_eq!(
            (c.kind, c.screw, c.damping, c.friction),
            (r.kind, r.screw, r.damping, r.friction)
        );
        // The UR5's revolute joints have limits (±2π, elbow ±π) and damping 0.0 friction 0.0.
        let l = r.limits.expect("revolute limits");
        assert!(l.lower < 0.0 && l.upper > 0.0 && l.lower == -l.upper);
        // A continuous joint has no position limits but keeps the velocity and effort limits.
        let lc = c.limits.expect("velocity and effort limits");
        assert_eq!((lc.lower, lc.upper), (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!((lc.velocity, lc.effort), (l.velocity, l.effort));
    }
    assert_eq!(revolute.joints[0].limits.unwrap().upper, 6.28318530718);
    assert_eq!(revolute.joints[2].limits.unwrap().upper, 3.14159265359);
    assert_eq!(revolute.joints[0].limits.unwrap().velocity, Some(3.15));
}

/// Panda with its finger joints movable again (prismatic along ±y of the hand, the second
/// mimicking the first, as in example-robot-data's source file): one coordinate for both
/// fingers; locking the first at 0
/// (which locks the second with it) gives the model of the file where they are fixed;
/// locking it at 2 cm opens both fingers by 2 cm, in opposite directions: the body's first
/// mass moment m·c is unchanged (equal finger masses), where the left finger alone would
/// move it by m_finger · 0.02 · R_{7,hand} e_y.
#[test]
fn locked_fingers_merge_into_the_hand() {
    let fixed_text = robot_text("panda.urdf");
    let fixed =
        load_text(&fixed_text, "panda.urdf", &LoadOptions::default()).expect("fixed fingers");
    let movable = fixed_text
        .replace(
            r#"<joint name="panda_finger_joint1" type="fixed">"#,
            r#"<joint name="panda_finger_joint1" type="prismatic"><axis xyz="0 1 0"/><limit effort="100" lower="0.0" upper="0.04" velocity="0.2"/>"#,
        )
        .replace(
            r#"<joint name="panda_finger_joint2" type="fixed">"#,
            r#"<joint name="panda_finger_joint2" type="prismatic"><axis xyz="0 -1 0"/><limit effort="100" lower="0.0" upper="0.04" velocity="0.2"/><mimic joint="panda_finger_joint1"/>"#,
        );
    assert_ne!(movable, fixed_text);
    // Unlocked, the fingers are one coordinate: finger 2 follows finger 1.
    let coupled =
        load_text(&movable, "panda.urdf", &LoadOptions::default()).expect("coupled fingers");
    let mut names = fixed.joint_names();
    names.push("panda_finger_joint1");
    assert_eq!(coupled.joint_names(), names);
    assert_eq!((coupled.dof(), coupled.nq()), (9, 8));
    assert_eq!(coupled.joints[8].mimic.map(|m| m.leader), Some(7));
    let lock = |v1: f64| LoadOptions {
        lock: vec![("panda_finger_joint1".into(), v1)],
        ..LoadOptions::default()
    };
    let at_zero = load_text(&movable, "panda.urdf", &lock(0.0)).expect("locked at 0");
    assert_eq!(at_zero.joint_names(), fixed.joint_names());
    for (a, b) in at_zero.links.iter().zip(&fixed.links) {
        assert_close("home", a.home.as_slice(), b.home.as_slice());
        assert_close("G", a.inertia.0.as_slice(), b.inertia.0.as_slice());
    }
    let open = load_text(&movable, "panda.urdf", &lock(0.02)).expect("locked at 2 cm");
    let first_moment = |g: &SpatialInertia| g.com() * g.mass();
    let shift = first_moment(&open.links[6].inertia) - first_moment(&fixed.links[6].inertia);
    // panda_link8 is at z = 0.107 without rotation; the hand is turned by −π/4 about z.
    let (s, c) = (-std::f64::consts::FRAC_PI_4).sin_cos();
    let left_alone = Vector3::new(-s, c, 0.0) * (0.015 * 0.02);
    assert!(
        (shift - left_alone).amax() > 1e-4,
        "the right finger did not follow"
    );
    let err = assert_close("m·c shift", shift.as_slice(), &[0.0; 3]);
    eprintln!("finger lock: m·c shift error {err:e}");
    assert_eq!(open.links[6].inertia.mass(), fixed.links[6].inertia.mass());
}

#[test]
fn shipped_ur5_is_the_test_file() {
    let shipped = dynamics_model::load("ur5", &LoadOptions::default()).expect("shipped ur5");
    let file =
        load_text(&robot_text("ur5.urdf"), "ur5.urdf", &LoadOptions::default()).expect("file");
    assert_eq!(shipped.joints, file.joints);
    assert_eq!(shipped.links, file.links);
    assert_eq!(shipped.end_effector.name, "wrist_3_link");
    assert_eq!(shipped.end_effector.home, Matrix4::identity());
    assert_eq!(shipped.gravity, Vector3::new(0.0, 0.0, -9.81));
    // Right angles are exact: shoulder_lift_joint's origin rpy (0, 1.57079632679, 0).
    let r = shipped.links[1].home;
    assert_eq!((r[(0, 0)], r[(0, 2)], r[(2, 0)]), (0.0, 1.0, -1.0));
    // The tool flange as tip: tool0 = wrist_3_link · (0 0.0823 0, rpy −π/2 0 0).
    let tool = dynamics_model::load("ur5", &tip("tool0")).expect("tool0");
    let want = Matrix4::new(
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 1.0, 0.0823, //
        0.0, -1.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    );
    assert_eq!(tool.end_effector.home, want);
    assert_eq!(tool.end_effector.name, "tool0");
}

/// `snap_angles`: a Panda that writes 1.5708 for π/2 (3.7e-6 rad off) is, with
/// `snap_angles = 1e-5`, exactly the Panda that writes π/2 to full precision; without it, it
/// keeps the file's angles. TOML files and tolerances above 1e-2 are refused.
#[test]
fn snap_angles_makes_near_right_angles_exact() {
    let exact_text = robot_text("panda.urdf");
    let rounded_text = exact_text.replace("1.5707963267948966", "1.5708");
    assert!(rounded_text.matches("1.5708").count() >= 6);
    let exact = load_text(&exact_text, "panda.urdf", &LoadOptions::default()).expect("loads");
    let as_written = load_text(&rounded_text, "p.urdf", &LoadOptions::default()).expect("loads");
    let snapped = load_text(
        &rounded_text,
        "p.urdf",
        &LoadOptions {
            snap_angles: Some(1e-5),
            ..Default::default()
        },
    )
    .expect("loads");
    let frames = |r: &dynamics_model::Robot| -> Vec<f64> {
        r.home_poses()
            .iter()
            .flat_map(|m| m.iter().copied())
            .chain(r.joints.iter().flat_map(|j| j.screw.iter().copied()))
            .collect()
    };
    let (e, w, s) = (frames(&exact), frames(&as_written), frames(&snapped));
    let diff = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    assert_eq!(diff(&e, &s), 0.0, "snapped = exact, bit for bit");
    assert!(
        diff(&e, &w) > 1e-7,
        "as written, the frames are 3.7e-6 rad off"
    );
    for (a, b) in exact.links.iter().zip(&snapped.links) {
        assert_eq!(a.inertia.0, b.inertia.0);
    }
    // Only the distances in (1e-9, 1e-4] are listed.
    let near = dynamics_model::urdf::near_right_angles(&rounded_text, "p.urdf", 1e-9, 1e-4)
        .expect("parses");
    assert_eq!(near.len(), 6, "{near:?}");
    assert!(near
        .iter()
        .all(|a| a.element.starts_with("joint `panda_joint") && a.index == 0));
    assert!(
        dynamics_model::urdf::near_right_angles(&exact_text, "panda.urdf", 1e-9, 1e-4)
            .expect("parses")
            .is_empty()
    );
    // Refusals.
    let too_wide = error_of(
        &rounded_text,
        "p.urdf",
        &LoadOptions {
            snap_angles: Some(0.5),
            ..Default::default()
        },
    );
    assert!(
        too_wide.contains("snap_angles must be between 0 and 1e-2 rad, found 5e-1"),
        "{too_wide}"
    );
    let toml = dynamics_model::load::from_str(
        "",
        dynamics_model::Format::Toml,
        "arm.toml",
        &LoadOptions {
            snap_angles: Some(1e-5),
            ..Default::default()
        },
    )
    .expect_err("refused");
    assert_eq!(
        toml.to_string(),
        "arm.toml: `snap_angles` applies to URDF files only; write exact angles (1.5707963267948966) or 4×4 matrices in a TOML file"
    );
}
