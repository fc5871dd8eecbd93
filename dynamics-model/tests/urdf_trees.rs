//! Kinematic trees and floating bases from URDF, against Pinocchio 4.1.0
//! (`tests/data/reference/trees/`, schema in its README): joint order, parents, body
//! inertias after merging fixed links, and the pose of every joint frame at 20 samples.
//!
//! Pinocchio's `oMi` is the pose of each joint frame (= the joint's child link frame) in the
//! world. Here it is the product of exponentials along the path from the base:
//! `T_{0i}(q) = Π_{k ∈ path(i)} e^{[S_k] q_k} · M_{0i}`, pre-multiplied on a floating base by
//! the base pose `(p, R(quat))` from `q[0..7]` (quaternion `(x, y, z, w)`, scalar last).

mod urdf_common;

use dynamics_model::lie::exp6;
use dynamics_model::{LoadOptions, Robot};
use nalgebra::{Matrix3, Matrix4, Quaternion, UnitQuaternion, Vector3};
use serde_json::Value;
use urdf_common::*;

const ROBOTS: [&str; 3] = ["talos_upper_body", "solo12", "g1_29dof"];

fn floating() -> LoadOptions {
    LoadOptions {
        floating_base: true,
        ..LoadOptions::default()
    }
}

/// The robot `name` of `robots/trees/`, floating when the reference is, and its reference.
fn load(name: &str) -> (Robot, Value) {
    let json = reference(&format!("trees/{name}.json"));
    let options = if json["floating"].as_bool().expect("floating") {
        floating()
    } else {
        LoadOptions::default()
    };
    let file = format!("{name}.urdf");
    let robot = load_text(&robot_text(&format!("trees/{file}")), &file, &options)
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    (robot, json)
}

/// The reference's joints without the free flyer (`root_joint`), and how many were left out.
fn movable(json: &Value) -> (Vec<&Value>, usize) {
    let all: Vec<&Value> = json["pinocchio_model"]
        .as_array()
        .expect("model")
        .iter()
        .collect();
    let skip = usize::from(json["floating"].as_bool().expect("floating"));
    (all[skip..].to_vec(), skip)
}

/// The base pose `T_{w,0}` from a floating q: position, then quaternion (x, y, z, w).
fn base_pose(q: &[f64]) -> Matrix4<f64> {
    let quat = UnitQuaternion::from_quaternion(Quaternion::new(q[6], q[3], q[4], q[5]));
    let mut t = Matrix4::identity();
    t.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(quat.to_rotation_matrix().matrix());
    t.fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&Vector3::new(q[0], q[1], q[2]));
    t
}

/// `T_{0i}(q)` for every link i, along `path_to(i)`.
fn link_poses(robot: &Robot, theta: &[f64]) -> Vec<Matrix4<f64>> {
    let home = robot.home_poses();
    (0..robot.dof())
        .map(|i| {
            let mut t: Matrix4<f64> = Matrix4::identity();
            for k in robot.path_to(i) {
                t *= exp6(&robot.joints[k].screw, theta[k]);
            }
            t * home[i + 1]
        })
        .collect()
}

#[test]
fn joint_order_and_parents_are_pinocchios() {
    for name in ROBOTS {
        let (robot, json) = load(name);
        let (joints, skip) = movable(&json);
        let names: Vec<&str> = joints
            .iter()
            .map(|j| j["name"].as_str().expect("name"))
            .collect();
        assert_eq!(robot.joint_names(), names, "{name}");
        let want: Vec<&str> = json["joint_names"].as_array().unwrap()[skip..]
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(robot.joint_names(), want, "{name}");
        // Pinocchio's parent p (0 = universe, the free flyer is joint 1) to λ(i).
        let parents: Vec<Option<usize>> = json["parents"].as_array().unwrap()[skip..]
            .iter()
            .map(|p| {
                let p = p.as_u64().unwrap() as usize;
                (p > skip).then(|| p - 1 - skip)
            })
            .collect();
        assert_eq!(robot.parents(), parents, "{name}");
        assert_eq!(robot.base.floating, skip == 1, "{name}");
        assert_eq!(
            robot.base.name,
            json["urdf_root_link"].as_str().unwrap(),
            "{name}"
        );
        assert_eq!(robot.nq(), json["nq"].as_u64().unwrap() as usize, "{name}");
        assert_eq!(robot.nv(), json["nv"].as_u64().unwrap() as usize, "{name}");
        assert!(!robot.is_serial(), "{name}");
    }
}

#[test]
fn bodies_match_pinocchios_after_merging_fixed_links() {
    // The largest relative error of each quantity, for the record.
    let mut worst = std::collections::BTreeMap::<&str, f64>::new();
    for name in ROBOTS {
        let (robot, json) = load(name);
        let (joints, skip) = movable(&json);
        let mut check = |what: String, x: &[f64], y: &[f64]| {
            let scale = y.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
            let e = assert_close(&what, x, y) / scale;
            let kind = what.rsplit(' ').next().unwrap_or("");
            let w = worst
                .entry(
                    ["mass", "com", "com-inertia", "home"]
                        .into_iter()
                        .find(|k| *k == kind)
                        .unwrap_or("other"),
                )
                .or_default();
            *w = w.max(e);
        };
        let mut bodies: Vec<(String, dynamics_model::SpatialInertia, &Value)> = robot
            .links
            .iter()
            .zip(&joints)
            .map(|(l, j)| (l.name.clone(), l.inertia, *j))
            .collect();
        if skip == 1 {
            let root = &json["pinocchio_model"][0];
            bodies.push((robot.base.name.clone(), robot.base.inertia, root));
        }
        let mut total = 0.0;
        for (link, g, j) in &bodies {
            let at = format!("{name}: body `{link}`");
            check(format!("{at} mass"), &[g.mass()], &[f(&j["mass"])]);
            check(
                format!("{at} com"),
                g.com().as_slice(),
                vec3(&j["com"]).as_slice(),
            );
            let i: Matrix3<f64> = mat3(&j["inertia_about_com"]);
            check(
                format!("{at} com-inertia"),
                g.rotational_about_com().as_slice(),
                i.as_slice(),
            );
            total += g.mass();
        }
        let want: f64 = json["pinocchio_model"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| f(&j["mass"]))
            .sum();
        check(format!("{name}: total mass"), &[total], &[want]);
        // Pinocchio's placement: the joint frame in its parent joint's frame, fixed joints
        // folded in, = M_{λ(i),i}.
        for (l, j) in robot.links.iter().zip(&joints) {
            check(
                format!("{name}: `{}` home", l.name),
                l.home.as_slice(),
                mat4(&j["placement"]).as_slice(),
            );
        }
    }
    eprintln!("bodies: max relative error vs Pinocchio {worst:?}");
}

#[test]
fn joint_frames_match_pinocchios_omi_at_every_sample() {
    for name in ROBOTS {
        let (robot, json) = load(name);
        let skip = usize::from(robot.base.floating);
        let mut worst = 0f64;
        let samples = json["samples"].as_array().expect("samples");
        assert_eq!(samples.len(), 20);
        for (k, s) in samples.iter().enumerate() {
            let q: Vec<f64> = s["q"].as_array().unwrap().iter().map(f).collect();
            assert_eq!(q.len(), robot.nq());
            let (base, theta) = if robot.base.floating {
                (base_pose(&q), &q[7..])
            } else {
                (Matrix4::identity(), &q[..])
            };
            let omi = s["oMi"].as_array().expect("oMi");
            assert_eq!(omi.len(), robot.dof() + skip);
            if skip == 1 {
                let d = assert_close(
                    &format!("{name} sample {k}: base"),
                    base.as_slice(),
                    mat4(&omi[0]).as_slice(),
                );
                worst = worst.max(d);
            }
            for (i, t) in link_poses(&robot, theta).iter().enumerate() {
                let got = base * t;
                let d = assert_close(
                    &format!("{name} sample {k}: frame of `{}`", robot.joints[i].name),
                    got.as_slice(),
                    mat4(&omi[i + skip]).as_slice(),
                );
                worst = worst.max(d);
            }
        }
        eprintln!("{name}: oMi max abs error over 20 samples {worst:e}");
    }
}

/// solo12 behind a `world` link and a floating joint (with an origin, which is ignored).
fn solo12_on_a_floating_joint(world_inertial: &str) -> String {
    robot_text("trees/solo12.urdf").replacen(
        "<link name=\"base_link\">",
        &format!(
            "<link name=\"world\">{world_inertial}</link>\n  <joint name=\"root\" type=\"floating\"><parent link=\"world\"/><child link=\"base_link\"/><origin xyz=\"1 2 3\" rpy=\"0.1 0.2 0.3\"/></joint>\n  <link name=\"base_link\">"
        ),
        1,
    )
}

#[test]
fn a_floating_root_joint_floats_the_base() {
    let text = solo12_on_a_floating_joint("");
    let auto = load_text(&text, "solo12_world.urdf", &LoadOptions::default()).expect("floating");
    let (forced, _) = load("solo12");
    assert!(auto.base.floating);
    assert_eq!(auto.base.name, "base_link");
    assert_eq!(
        Robot {
            source: forced.source.clone(),
            ..auto.clone()
        },
        forced
    );
    // Asking for it as well changes nothing; a zero <inertial> is no inertia either.
    let both = load_text(&text, "solo12_world.urdf", &floating()).expect("floating");
    assert_eq!(both, auto);
    let zero = r#"<inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>"#;
    let r = load_text(
        &solo12_on_a_floating_joint(zero),
        "solo12_world.urdf",
        &LoadOptions::default(),
    )
    .expect("zero inertial");
    assert!(r.base.floating);
    // The world is not part of the robot.
    let m = error_of(&text, "solo12_world.urdf", &tip("world"));
    assert!(
        m.contains("link `world`") && m.contains("field `tip`") && m.contains("`base_link`"),
        "{m}"
    );
}

#[test]
fn floating_joints_elsewhere_are_refused_by_name() {
    // The world link has mass: it is a body, and the floating joint is not the root joint.
    let heavy = r#"<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>"#;
    let m = error_of(
        &solo12_on_a_floating_joint(heavy),
        "heavy.urdf",
        &LoadOptions::default(),
    );
    for part in [
        "heavy.urdf: ",
        "joint `root`",
        "field `type`",
        "`floating`",
        "root joint",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    // Below a movable joint.
    let text = robot_text("trees/solo12.urdf").replacen("type=\"fixed\"", "type=\"floating\"", 1);
    let m = error_of(&text, "deep.urdf", &LoadOptions::default());
    assert!(
        m.contains("joint `FL_ANKLE`") && m.contains("field `type`"),
        "{m}"
    );
    // Planar joints, anywhere.
    let text = robot_text("trees/solo12.urdf").replacen("type=\"fixed\"", "type=\"planar\"", 1);
    let m = error_of(&text, "planar.urdf", &LoadOptions::default());
    assert!(
        m.contains("joint `FL_ANKLE`") && m.contains("`planar`"),
        "{m}"
    );
}

#[test]
fn the_tip_is_any_link_of_the_tree() {
    let text = robot_text("trees/talos_upper_body.urdf");
    let file = "talos_upper_body.urdf";
    // Default: the child of the last movable joint in the order (head_2_joint).
    let r = load_text(&text, file, &LoadOptions::default()).expect("talos");
    assert_eq!(r.end_effector.name, "head_2_link");
    assert_eq!(r.end_effector.parent, Some(r.dof() - 1));
    // A link of another branch.
    let r = load_text(&text, file, &tip("arm_left_4_link")).expect("arm");
    let i = r
        .joint_names()
        .iter()
        .position(|&n| n == "arm_left_4_joint");
    assert_eq!(r.end_effector.parent, i);
    assert_eq!(r.end_effector.home, Matrix4::identity());
    // A link welded to a body (the left gripper's tool frame) gets its pose in that body.
    let r = load_text(&text, file, &tip("wrist_left_ft_tool_link")).expect("tool");
    let i = r
        .joint_names()
        .iter()
        .position(|&n| n == "arm_left_7_joint");
    assert_eq!(r.end_effector.parent, i);
    assert_ne!(r.end_effector.home, Matrix4::identity());
    // The base itself, and a link welded to the fixed base (a leg, locked in this file).
    let r = load_text(&text, file, &tip("base_link")).expect("base");
    assert_eq!(r.end_effector.parent, None);
    assert_eq!(r.end_effector.home, Matrix4::identity());
    let r = load_text(&text, file, &tip("leg_left_6_link")).expect("leg");
    assert_eq!(r.end_effector.parent, None);
    assert_ne!(r.end_effector.home, Matrix4::identity());
}

#[test]
fn locks_freeze_branches_into_their_parent_body() {
    // talos with both grippers locked: 18 joints, the fingers' links merged into the wrists.
    let text = robot_text("trees/talos_upper_body.urdf");
    let file = "talos_upper_body.urdf";
    let free = load_text(&text, file, &LoadOptions::default()).expect("talos");
    let locked = LoadOptions {
        lock: vec![
            ("gripper_left_joint".into(), 0.0),
            ("gripper_right_joint".into(), 0.0),
        ],
        ..LoadOptions::default()
    };
    let r = load_text(&text, file, &locked).expect("locked grippers");
    assert_eq!(r.dof(), free.dof() - 2);
    assert!(!r.joint_names().contains(&"gripper_left_joint"));
    let mass = |r: &Robot| r.links.iter().map(|l| l.inertia.mass()).sum::<f64>();
    assert!((mass(&r) - mass(&free)).abs() < 1e-12 * mass(&free));
    // The parents still point at the right bodies: head_1 hangs from torso_2.
    let head = r
        .joint_names()
        .iter()
        .position(|&n| n == "head_1_joint")
        .unwrap();
    let torso = r.joint_names().iter().position(|&n| n == "torso_2_joint");
    assert_eq!(r.links[head].parent, torso);
}

#[test]
fn children_are_ordered_by_joint_name_bytes_not_file_order() {
    // Upper case sorts before lower case (byte order), and file order is reversed.
    const I: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    let joint = |name: &str, parent: &str, child: &str, kind: &str| {
        format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"0 0.1 0\"/><axis xyz=\"0 0 1\"/></joint>\n"
        )
    };
    let links: String = ["base", "a", "b", "c", "d", "e"]
        .iter()
        .map(|l| format!("<link name=\"{l}\">{I}</link>\n"))
        .collect();
    let text = format!(
        "<robot name=\"order\">{links}{}{}{}{}{}</robot>",
        joint("zeta", "base", "a", "revolute"),
        joint("b_fixed", "base", "b", "fixed"),
        joint("Zulu", "b", "c", "revolute"),
        joint("alpha", "base", "d", "revolute"),
        joint("alpha2", "d", "e", "prismatic"),
    );
    let r = load_text(&text, "order.urdf", &LoadOptions::default()).expect("order");
    // base's children by name: alpha, b_fixed (→ Zulu), zeta.
    assert_eq!(r.joint_names(), ["alpha", "alpha2", "Zulu", "zeta"]);
    assert_eq!(r.parents(), [None, Some(0), None, None]);
    // The base holds `base` and `b` (welded): 2 kg, not counted on a fixed base.
    assert!(!r.base.floating);
    assert!((r.base.inertia.mass() - 2.0).abs() < 1e-15);
    assert_eq!(r.end_effector.name, "a");
}
