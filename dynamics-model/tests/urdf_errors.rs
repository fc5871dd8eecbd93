//! Every refusal of the URDF loader names the file, the link or joint, and the field.

mod urdf_common;

use dynamics_model::LoadOptions;
use urdf_common::*;

const INERTIAL: &str = r#"<inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;

/// A robot from link names (each with a unit inertial) and raw joint XML.
fn robot(links: &[&str], joints: &str) -> String {
    let links: String = links
        .iter()
        .map(|l| format!("<link name=\"{l}\">{INERTIAL}</link>\n"))
        .collect();
    format!("<?xml version=\"1.0\"?>\n<robot name=\"t\">\n{links}{joints}\n</robot>\n")
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, extra: &str) -> String {
    format!(
        "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"0 0 0.2\" rpy=\"0 0 0\"/><axis xyz=\"0 0 1\"/>{extra}</joint>\n"
    )
}

#[track_caller]
fn assert_mentions(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(message.contains(p), "message lacks {p:?}:\n{message}");
    }
}

fn default() -> LoadOptions {
    LoadOptions::default()
}

#[test]
fn unknown_link() {
    let text = robot(&["a", "b"], &joint("j1", "revolute", "a", "nowhere", ""));
    let m = error_of(&text, "unknown.urdf", &default());
    assert_mentions(
        &m,
        &["unknown.urdf: ", "joint `j1`", "field `child`", "`nowhere`"],
    );
}

#[test]
fn link_with_two_parents() {
    let joints = joint("j1", "revolute", "a", "c", "") + &joint("j2", "revolute", "b", "c", "");
    let m = error_of(&robot(&["a", "b", "c"], &joints), "two.urdf", &default());
    assert_mentions(
        &m,
        &["two.urdf: ", "link `c`", "field `parent`", "`j1`", "`j2`"],
    );
}

#[test]
fn closed_loop() {
    // a is the root; b and c are each other's parent, unreachable from a.
    let joints = joint("j1", "revolute", "b", "c", "") + &joint("j2", "revolute", "c", "b", "");
    let m = error_of(&robot(&["a", "b", "c"], &joints), "loop.urdf", &default());
    assert_mentions(
        &m,
        &[
            "loop.urdf: ",
            "link `b`",
            "field `parent`",
            "closed loop",
            "`c`",
        ],
    );
}

#[test]
fn several_roots() {
    let joints = joint("j1", "revolute", "a", "b", "");
    let m = error_of(&robot(&["a", "b", "x"], &joints), "roots.urdf", &default());
    assert_mentions(&m, &["roots.urdf: ", "several root links", "`a`", "`x`"]);
}

#[test]
fn floating_and_planar_joints() {
    for kind in ["floating", "planar"] {
        let joints = joint("j1", kind, "a", "b", "");
        let m = error_of(&robot(&["a", "b"], &joints), "free.urdf", &default());
        assert_mentions(&m, &["free.urdf: ", "joint `j1`", "field `type`", kind]);
    }
}

#[test]
fn movable_mimic_joint_is_coupled_fixed_one_is_fine() {
    let mimic = r#"<mimic joint="j1" multiplier="1" offset="0"/>"#;
    let joints = joint("j1", "revolute", "a", "b", "") + &joint("j2", "prismatic", "b", "c", mimic);
    let r = load_text(&robot(&["a", "b", "c"], &joints), "mimic.urdf", &default())
        .expect("a coupled joint");
    assert_eq!(r.joint_names(), ["j1"]);
    assert_eq!((r.dof(), r.nq(), r.nv()), (2, 1, 1));
    assert_eq!(r.joints[1].mimic.map(|m| m.leader), Some(0));

    // The same joint fixed (as in panda.urdf) loads, with one joint.
    let fixed = joint("j1", "revolute", "a", "b", "") + &joint("j2", "fixed", "b", "c", mimic);
    let r =
        load_text(&robot(&["a", "b", "c"], &fixed), "mimic.urdf", &default()).expect("fixed mimic");
    assert_eq!(r.joint_names(), ["j1"]);
    assert_eq!(r.dof(), 1);
    // Locked alone, while its leader moves, it is refused: the lock to give is the leader's.
    let locked = LoadOptions {
        lock: vec![("j2".into(), 0.0)],
        ..default()
    };
    let m = error_of(&robot(&["a", "b", "c"], &joints), "mimic.urdf", &locked);
    assert_mentions(
        &m,
        &[
            "mimic.urdf: ",
            "joint `j2`",
            "field `lock`",
            "mimics `j1`",
            "--lock j1=0",
        ],
    );
    // Locking the leader welds both bodies: 2 kg.
    let locked = LoadOptions {
        lock: vec![("j1".into(), 0.0)],
        ..default()
    };
    let m = error_of(&robot(&["a", "b", "c"], &joints), "mimic.urdf", &locked);
    assert_mentions(&m, &["no movable joint"]);
}

/// A follower's `<mimic>` that cannot be a coupling: a leader the file does not have, a fixed
/// leader, a cycle, a zero multiplier. Each error names the joint, the field `mimic` and the
/// lock that would do instead.
#[test]
fn impossible_mimics_are_refused_by_name() {
    let base = joint("j1", "revolute", "a", "b", "");
    let cases = [
        (
            joint("j2", "revolute", "b", "c", r#"<mimic joint="nope"/>"#),
            "which the file does not have",
        ),
        (
            joint("j2", "revolute", "b", "c", r#"<mimic joint="fx"/>"#)
                + &joint("fx", "fixed", "c", "d", ""),
            "which is fixed",
        ),
        (
            joint("j2", "revolute", "b", "c", r#"<mimic joint="j3"/>"#)
                + &joint("j3", "revolute", "c", "d", r#"<mimic joint="j2"/>"#),
            "cycle (j2 → j3 → j2)",
        ),
        (
            joint(
                "j2",
                "revolute",
                "b",
                "c",
                r#"<mimic joint="j1" multiplier="0"/>"#,
            ),
            "multiplier 0",
        ),
    ];
    for (extra, problem) in cases {
        let links: &[&str] = if extra.contains("\"d\"") {
            &["a", "b", "c", "d"]
        } else {
            &["a", "b", "c"]
        };
        let text = robot(links, &(base.clone() + &extra));
        let m = error_of(&text, "mimic.urdf", &default());
        assert_mentions(
            &m,
            &[
                "mimic.urdf: ",
                "joint `j2`",
                "field `mimic`",
                problem,
                "--lock j2=",
            ],
        );
    }
}

#[test]
fn movable_branches_make_a_tree_and_locks_still_merge_them() {
    // a -j1-> b, then b branches: -ja-> c -jc-> e and -jb-> d.
    let joints = joint("j1", "revolute", "a", "b", "")
        + &joint("ja", "revolute", "b", "c", "")
        + &joint("jc", "revolute", "c", "e", "")
        + &joint("jb", "prismatic", "b", "d", "");
    let text = robot(&["a", "b", "c", "d", "e"], &joints);
    let r = load_text(&text, "y.urdf", &default()).expect("a tree");
    // Depth first, b's children by joint name: ja (then jc below it), jb.
    assert_eq!(r.joint_names(), ["j1", "ja", "jc", "jb"]);
    assert_eq!(r.parents(), [None, Some(0), Some(1), Some(0)]);
    // The tip is the last joint's child, d.
    assert_eq!(r.end_effector.name, "d");
    assert_eq!(r.end_effector.parent, Some(3));
    // Locking one branch merges it into its parent body: lock ja and jc (ja at a quarter turn).
    let lock = LoadOptions {
        lock: vec![
            ("ja".into(), std::f64::consts::FRAC_PI_2),
            ("jc".into(), 0.0),
        ],
        ..default()
    };
    let r = load_text(&text, "y.urdf", &lock).expect("locked");
    assert_eq!(r.joint_names(), ["j1", "jb"]);
    assert!(r.is_serial());
    // Body of j1 = b + c + e: 3 kg; c and e turn about z, which moves nothing off the z axis.
    assert!((r.links[0].inertia.mass() - 3.0).abs() < 1e-15);
    // COM of b, c, e in b's frame: z = 0.1, 0.3, 0.5 → mean 0.3.
    assert!((r.links[0].inertia.com() - nalgebra::Vector3::new(0.0, 0.0, 0.3)).amax() < 1e-15);
}

#[test]
fn lock_of_unknown_joint_lists_the_movable_joints() {
    let joints = joint("j1", "revolute", "a", "b", "") + &joint("j2", "prismatic", "b", "c", "");
    let lock = LoadOptions {
        lock: vec![("j9".into(), 0.0)],
        ..default()
    };
    let m = error_of(&robot(&["a", "b", "c"], &joints), "lock.urdf", &lock);
    assert_mentions(&m, &["lock.urdf: ", "joint `j9`", "field `lock`", "j1, j2"]);
}

#[test]
fn tip_is_any_link_and_an_unknown_one_is_refused() {
    let text = robot_text("ur5.urdf");
    // A link before the last joint: the end effector hangs from its body.
    let r = load_text(&text, "ur5.urdf", &tip("wrist_2_link")).expect("wrist_2_link");
    assert_eq!(r.end_effector.name, "wrist_2_link");
    assert_eq!(r.end_effector.parent, Some(4));
    // The fixed base's root link: attached to the base.
    let r = load_text(&text, "ur5.urdf", &tip("base_link")).expect("base_link");
    assert_eq!(r.end_effector.parent, None);
    let m = error_of(&text, "ur5.urdf", &tip("no_such_link"));
    assert_mentions(&m, &["link `no_such_link`", "field `tip`", "tool0"]);
}

#[test]
fn negative_mass() {
    let text = robot(&["a", "b"], &joint("j1", "revolute", "a", "b", "")).replacen(
        r#"<mass value="1"/>"#,
        r#"<mass value="-2"/>"#,
        2,
    );
    let m = error_of(&text, "mass.urdf", &default());
    assert_mentions(
        &m,
        &["mass.urdf: ", "link `b`", "field `inertial.mass`", "-2"],
    );
}

#[test]
fn impossible_inertia_names_the_urdf_link_even_when_merged() {
    // ee_link is welded to wrist_3_link: the merged body would hide it.
    let text = robot_text("ur5.urdf").replacen(
        r#"<mass value="0"/>
      <origin rpy="0 0 0" xyz="0 0 0"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#,
        r#"<mass value="1"/>
      <origin rpy="0 0 0" xyz="0 0 0"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/>"#,
        1,
    );
    let m = error_of(&text, "ur5.urdf", &default());
    assert_mentions(
        &m,
        &[
            "ur5.urdf: ",
            "link `ee_link`",
            "field `inertial.inertia`",
            "triangle inequality",
        ],
    );
}

#[test]
fn zero_axis() {
    let joints = joint("j1", "revolute", "a", "b", "").replace(r#"xyz="0 0 1""#, r#"xyz="0 0 0""#);
    let m = error_of(&robot(&["a", "b"], &joints), "axis.urdf", &default());
    assert_mentions(&m, &["axis.urdf: ", "joint `j1`", "field `axis`", "zero"]);
}

#[test]
fn non_finite_numbers() {
    let joints =
        joint("j1", "revolute", "a", "b", "").replace(r#"rpy="0 0 0""#, r#"rpy="0 nan 0""#);
    let m = error_of(&robot(&["a", "b"], &joints), "nan.urdf", &default());
    assert_mentions(
        &m,
        &[
            "nan.urdf: ",
            "joint `j1`",
            "field `origin.rpy`",
            "not finite",
        ],
    );
}

#[test]
fn no_movable_joint() {
    let m = error_of(
        &robot(&["a", "b"], &joint("j1", "fixed", "a", "b", "")),
        "fixed.urdf",
        &default(),
    );
    assert_mentions(&m, &["fixed.urdf: ", "no movable joint"]);
}

#[test]
fn malformed_xml_gives_file_line_and_column() {
    // Line 4 closes <joint> where <child> is still open.
    let text = "<robot name=\"t\">\n<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\">\n</joint>\n</robot>\n";
    let m = error_of(text, "bad.urdf", &default());
    assert_mentions(&m, &["bad.urdf:4:1: ", "</joint>", "<child>"]);
    // A number that is not one, located.
    let text =
        robot(&["a", "b"], &joint("j1", "revolute", "a", "b", "")).replace("0 0 0.2", "0 0 0.2x");
    let m = error_of(&text, "num.urdf", &default());
    assert!(m.starts_with("num.urdf:5:"), "{m}");
    assert_mentions(&m, &["joint `j1`", "xyz", "`0.2x` is not a number"]);
    // Not a URDF at all.
    let m = error_of("<sdf version=\"1.6\"/>", "x.urdf", &default());
    assert_mentions(&m, &["x.urdf:1:1: ", "not <robot>"]);
}
