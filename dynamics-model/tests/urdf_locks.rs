//! Locks: joints frozen at a value (branches of a tree merged into their parent body), mimic
//! joints following a locked leader (or coupled to a free one), and lock values checked
//! against the joint's limits.

mod urdf_common;

use dynamics_model::{LoadOptions, Mimic};
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
fn a_tree_loads_whole_with_a_coupled_mimic_finger() {
    let text = tiago_like();
    let r = load_text(&text, "tiago.urdf", &LoadOptions::default()).expect("a coupled finger");
    // Depth first, children by joint name: base → torso, wheel_l, wheel_r; torso_link →
    // arm_1, head_1; gripper → finger_1, finger_2. finger_2 follows finger_1: no coordinate.
    assert_eq!(
        r.joint_names(),
        [
            "torso", "arm_1", "arm_2", "arm_3", "finger_1", "head_1", "head_2", "wheel_l",
            "wheel_r"
        ]
    );
    assert_eq!((r.dof(), r.nq()), (10, 9));
    assert_eq!(r.joints[5].name, "finger_2");
    assert_eq!(
        r.joints[5].mimic,
        Some(Mimic {
            leader: 4,
            multiplier: 1.0,
            offset: 0.0
        })
    );
    assert_eq!(r.links[5].parent, Some(3));
    // Locking the follower alone is refused with the leader's lock; the suggestion loads.
    let m = error_of(&text, "tiago.urdf", &locks(&[("finger_2", 0.02)]));
    assert_eq!(m.lines().count(), 1, "{m}");
    for part in [
        "tiago.urdf: ",
        "joint `finger_2`",
        "field `lock`",
        "mimics `finger_1`",
        "`--lock finger_1=0.02`",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    let r = load_text(&text, "tiago.urdf", &suggested(&m)).expect("the suggested lock");
    assert_eq!(r.dof(), 8);
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
    assert_eq!(r.dof(), 6);
    assert_eq!(r.end_effector.name, "h2");
}

#[test]
fn a_mimic_follower_in_its_own_branch_is_coupled_or_locked_with_its_leader() {
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
    let r = load_text(&text, "m.urdf", &LoadOptions::default()).expect("coupled");
    assert_eq!(r.joint_names(), ["a1", "lead"]);
    // Children by joint name: a1, follow, lead; the follower comes before its leader.
    assert_eq!(r.joints[1].name, "follow");
    assert_eq!(
        r.joints[1].mimic.map(|m| (m.leader, m.multiplier)),
        Some((2, -1.0))
    );
    // θ_follow = −θ_lead: locking it at 0.5 alone means locking the leader at −0.5.
    let m = error_of(&text, "m.urdf", &locks(&[("follow", 0.5)]));
    assert!(
        m.contains("--lock lead=-0.5") && m.contains("joint `follow`"),
        "{m}"
    );
    let r = load_text(&text, "m.urdf", &suggested(&m)).expect("leader locked");
    assert_eq!(r.joint_names(), ["a1"]);
    let r = load_text(&text, "m.urdf", &locks(&[("lead", -0.5), ("follow", 0.5)]))
        .expect("both, consistent");
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
    // Without locks the followers are coupled, f2 through f1 to the root leader:
    // θ_f2 = θ_f1 = 2 θ_lead + 0.1.
    let r = load_text(&text, "m.urdf", &LoadOptions::default()).expect("coupled");
    assert_eq!(r.joint_names(), ["j1", "lead"]);
    for f in [2, 3] {
        assert_eq!(
            r.joints[f].mimic,
            Some(Mimic {
                leader: 1,
                multiplier: 2.0,
                offset: 0.1
            })
        );
    }
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
    // A follower locked on its own, its leader free, is refused (it would break the
    // coupling); the error gives the root leader's lock, up the chain: f2 = 0.5 needs
    // lead = (0.5 − 0.1)/2 = 0.2.
    let m = error_of(&text, "m.urdf", &locks(&[("f2", 0.5)]));
    for part in [
        "joint `f2`",
        "field `lock`",
        "mimics `f1`",
        "--lock lead=0.2",
    ] {
        assert!(m.contains(part), "lacks {part:?}: {m}");
    }
    let r = load_text(&text, "m.urdf", &suggested(&m)).expect("the suggested lock");
    assert_eq!(r.joint_names(), ["j1"]);
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
