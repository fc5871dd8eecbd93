//! Locks: joints frozen at a value (branches of a tree merged into their parent body), mimic
//! joints following a locked leader, and lock values checked against the joint's limits.

mod urdf_common;

use dynamics_model::LoadOptions;
use urdf_common::*;

const INERTIAL: &str = r#"<inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;

/// A robot from joints `(name, type, parent, child, extra XML)`; links are made from the
/// names the joints use.
fn robot(joints: &[(&str, &str, &str, &str, &str)]) -> String {
    let mut links: Vec<&str> = Vec::new();
    for (_, _, p, c, _) in joints {
        for l in [p, c] {
            if !links.contains(l) {
                links.push(l);
            }
        }
    }
    let mut out = String::from("<robot name=\"t\">\n");
    for l in links {
        out += &format!("<link name=\"{l}\">{INERTIAL}</link>\n");
    }
    for (name, kind, parent, child, extra) in joints {
        out += &format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"0 0.1 0.2\"/><axis xyz=\"0 0 1\"/>{extra}</joint>\n"
        );
    }
    out + "</robot>\n"
}

fn locks(pairs: &[(&str, f64)]) -> LoadOptions {
    LoadOptions {
        lock: pairs.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
        ..LoadOptions::default()
    }
}

/// The locks of a `--lock A=0,B=0` suggestion: the last one in the first error line.
fn suggested(message: &str) -> LoadOptions {
    let first = message.lines().next().expect("a message");
    let list = first.rsplit("--lock ").next().expect("a --lock suggestion");
    let list = list.split([' ', '`', ';']).next().unwrap_or("");
    let pairs: Vec<(String, f64)> = list
        .split(',')
        .map(|p| {
            let (n, v) = p.split_once('=').expect("JOINT=VALUE");
            (n.to_string(), v.parse().expect("a number"))
        })
        .collect();
    LoadOptions {
        lock: pairs,
        ..LoadOptions::default()
    }
}

const LIMIT: &str = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;

/// TIAGo's shape: wheels and a torso on the base, head and arm on the torso, two fingers on
/// the gripper (the second mimicking the first).
fn tiago_like() -> String {
    robot(&[
        ("wheel_l", "continuous", "base", "wl", ""),
        ("wheel_r", "continuous", "base", "wr", ""),
        ("torso", "prismatic", "base", "torso_link", LIMIT),
        ("head_1", "revolute", "torso_link", "h1", LIMIT),
        ("head_2", "revolute", "h1", "h2", LIMIT),
        ("arm_1", "revolute", "torso_link", "a1", LIMIT),
        ("arm_2", "revolute", "a1", "a2", LIMIT),
        ("arm_3", "revolute", "a2", "gripper", LIMIT),
        (
            "finger_1",
            "prismatic",
            "gripper",
            "f1",
            r#"<limit lower="0.01" upper="0.04" effort="1" velocity="1"/>"#,
        ),
        (
            "finger_2",
            "prismatic",
            "gripper",
            "f2",
            r#"<limit lower="0.01" upper="0.04" effort="1" velocity="1"/><mimic joint="finger_1"/>"#,
        ),
    ])
}

#[test]
fn a_tree_loads_whole_and_a_free_mimic_finger_is_refused_with_its_lock() {
    let text = tiago_like();
    let m = error_of(&text, "tiago.urdf", &LoadOptions::default());
    // Only the follower is refused; its limits exclude 0, so the suggestion is the nearest one.
    assert_eq!(m.lines().count(), 1, "{m}");
    for part in [
        "tiago.urdf: ",
        "joint `finger_2`",
        "field `mimic`",
        "`--lock finger_2=0.01`",
        "lock `finger_1`",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    let r = load_text(&text, "tiago.urdf", &suggested(&m)).expect("the suggested lock");
    // Depth first, children by joint name: base → torso, wheel_l, wheel_r; torso_link →
    // arm_1, head_1; gripper → finger_1.
    assert_eq!(
        r.joint_names(),
        [
            "torso", "arm_1", "arm_2", "arm_3", "finger_1", "head_1", "head_2", "wheel_l",
            "wheel_r"
        ]
    );
    assert_eq!(
        r.parents(),
        [
            None,
            Some(0),
            Some(1),
            Some(2),
            Some(3),
            Some(0),
            Some(5),
            None,
            None
        ]
    );
    // Locking the leader locks the follower with it; locking the wheels leaves one branch
    // fewer at the base.
    let r = load_text(
        &text,
        "tiago.urdf",
        &locks(&[("finger_1", 0.02), ("wheel_l", 0.0), ("wheel_r", 1.0)]),
    )
    .expect("fingers and wheels locked");
    assert_eq!(
        r.joint_names(),
        ["torso", "arm_1", "arm_2", "arm_3", "head_1", "head_2"]
    );
    assert_eq!(r.end_effector.name, "h2");
}

#[test]
fn a_mimic_follower_in_its_own_branch_is_refused_until_it_or_its_leader_is_locked() {
    let text = robot(&[
        ("a1", "revolute", "base", "a", ""),
        ("lead", "revolute", "base", "l", ""),
        (
            "follow",
            "revolute",
            "base",
            "f",
            r#"<mimic joint="lead" multiplier="-1"/>"#,
        ),
    ]);
    let m = error_of(&text, "m.urdf", &LoadOptions::default());
    assert!(
        m.contains("--lock follow=0") && m.contains("joint `follow`"),
        "{m}"
    );
    let r = load_text(&text, "m.urdf", &suggested(&m)).expect("follower locked");
    assert_eq!(r.joint_names(), ["a1", "lead"]);
    let r = load_text(&text, "m.urdf", &locks(&[("lead", 0.5)])).expect("leader locked");
    assert_eq!(r.joint_names(), ["a1"]);
}

#[test]
fn locking_a_mimic_leader_locks_its_followers() {
    let text = robot(&[
        ("j1", "revolute", "base", "a", ""),
        ("lead", "revolute", "a", "b", ""),
        (
            "f1",
            "revolute",
            "b",
            "c",
            r#"<mimic joint="lead" multiplier="2" offset="0.1"/>"#,
        ),
        ("f2", "prismatic", "c", "d", r#"<mimic joint="f1"/>"#),
    ]);
    // Without locks the followers are refused (they are not independent joints).
    let m = error_of(&text, "m.urdf", &LoadOptions::default());
    assert!(
        m.contains("joint `f1`: field `mimic`") && m.contains("lock `lead`"),
        "{m}"
    );
    let by_leader = load_text(&text, "m.urdf", &locks(&[("lead", 0.3)])).expect("leader");
    let explicit = load_text(
        &text,
        "m.urdf",
        &locks(&[("lead", 0.3), ("f1", 0.7), ("f2", 0.7)]),
    )
    .expect("all three, consistent");
    assert_eq!(by_leader.joint_names(), ["j1"]);
    assert_eq!(by_leader.links, explicit.links);
    assert_eq!(by_leader.end_effector, explicit.end_effector);
    // Different from the followers left at 0.
    let at_zero = load_text(&text, "m.urdf", &locks(&[("lead", 0.3), ("f1", 0.0)]));
    let m = at_zero.expect_err("inconsistent explicit lock").to_string();
    for part in [
        "joint `f1`",
        "field `lock`",
        "locked at 0",
        "mimics `lead`",
        "0.7",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    // A follower locked on its own, its leader free, is still allowed.
    let r = load_text(&text, "m.urdf", &locks(&[("f1", 0.0), ("f2", 0.0)])).expect("followers");
    assert_eq!(r.joint_names(), ["j1", "lead"]);
}

#[test]
fn lock_values_outside_the_limits_are_refused() {
    let text = robot(&[
        ("j1", "revolute", "base", "a", LIMIT),
        ("j2", "revolute", "a", "b", LIMIT),
        ("j3", "continuous", "b", "c", LIMIT),
    ]);
    let m = error_of(&text, "lim.urdf", &locks(&[("j2", 2.0)]));
    for part in [
        "lim.urdf: ",
        "joint `j2`",
        "field `lock`",
        "2 rad",
        "outside the joint's limits [-1, 1]",
        "--lock j2=0",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    // At a limit is fine; a continuous joint has no limits.
    load_text(&text, "lim.urdf", &locks(&[("j2", 1.0)])).expect("at the upper limit");
    load_text(&text, "lim.urdf", &locks(&[("j3", 5.0)])).expect("continuous");
}

#[test]
fn absurd_lock_values_are_blamed_on_the_lock() {
    // Unlimited (lower = upper = 0) prismatic and continuous joints: only the magnitude
    // bound catches 1e308, which used to give a non-finite pose blamed on the URDF.
    let text = robot(&[
        ("j1", "revolute", "base", "a", ""),
        ("p", "prismatic", "a", "b", ""),
        ("c", "continuous", "b", "d", ""),
    ]);
    for (joint, value) in [
        ("p", 1e308),
        ("c", 1e308),
        ("p", f64::NAN),
        ("c", f64::INFINITY),
    ] {
        let m = error_of(&text, "big.urdf", &locks(&[(joint, value)]));
        assert!(m.contains(&format!("joint `{joint}`: field `lock`")), "{m}");
        assert!(!m.contains("origin") && !m.contains("inertia"), "{m}");
    }
}
