//! Mimic joints in the TOML format: `mimic = { joint, multiplier, offset }`, chains resolved
//! to the root leader, the same robot as the URDF `<mimic>`, and the errors (each naming the
//! file, the joint, the field `mimic` and the fix).

use dynamics_model::load::{from_str, Format};
use dynamics_model::{LoadOptions, Mimic};

const FILE: &str = "gripper.toml";

/// A wrist and three fingers on it: `f2` follows `f1` (×−1), `f3` follows `f2` (×2 + 0.1).
fn gripper(mimic2: &str, mimic3: &str) -> String {
    let joint = |name: &str, parent: &str, mimic: &str, y: f64| {
        format!(
            "[[joint]]\nname = \"{name}\"\ntype = \"revolute\"\nparent = \"{parent}\"\naxis = [1, 0, 0]\npoint = [0, {y}, 0.3]\n{mimic}\n\n[joint.link]\nname = \"{name}_link\"\nhome = {{ xyz = [0, {y}, 0.1] }}\nmass = 0.1\ninertia = [0.001, 0.001, 0.001, 0, 0, 0]\ncom = [0, 0, 0.02]\n\n"
        )
    };
    let mut text = String::from(
        "name = \"gripper\"\n\n[[joint]]\nname = \"wrist\"\ntype = \"revolute\"\naxis = [0, 0, 1]\npoint = [0, 0, 0]\n\n[joint.link]\nname = \"palm\"\nhome = { xyz = [0, 0, 0.2] }\nmass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]\n\n",
    );
    text += &joint("f1", "palm", "", 0.05);
    text += &joint("f2", "palm", mimic2, -0.05);
    text += &joint("f3", "palm", mimic3, 0.0);
    text
}

fn load(text: &str) -> Result<dynamics_model::Robot, String> {
    from_str(text, Format::Toml, FILE, &LoadOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn mimic_keys_couple_joints_and_chains_compose() {
    let r = load(&gripper(
        r#"mimic = { joint = "f1", multiplier = -1 }"#,
        r#"mimic = { joint = "f2", multiplier = 2, offset = 0.1 }"#,
    ))
    .expect("a coupled gripper");
    assert_eq!(r.joint_names(), ["wrist", "f1"]);
    assert_eq!((r.dof(), r.nq(), r.nv()), (4, 2, 2));
    assert_eq!(
        r.joints[2].mimic,
        Some(Mimic {
            leader: 1,
            multiplier: -1.0,
            offset: 0.0
        })
    );
    // θ_f3 = 2 θ_f2 + 0.1 = −2 θ_f1 + 0.1.
    assert_eq!(
        r.joints[3].mimic,
        Some(Mimic {
            leader: 1,
            multiplier: -2.0,
            offset: 0.1
        })
    );
    // A leader after its follower is fine too.
    let r = load(&gripper("", r#"mimic = { joint = "f2" }"#).replace(
        "name = \"f1\"\ntype = \"revolute\"\nparent = \"palm\"\naxis = [1, 0, 0]\npoint = [0, 0.05, 0.3]\n",
        "name = \"f1\"\ntype = \"revolute\"\nparent = \"palm\"\naxis = [1, 0, 0]\npoint = [0, 0.05, 0.3]\nmimic = { joint = \"f3\" }\n",
    ))
    .expect("f1 follows f3, which follows f2");
    assert_eq!(r.joint_names(), ["wrist", "f2"]);
    assert_eq!(r.joints[1].mimic.map(|m| m.leader), Some(2));
}

#[test]
fn impossible_mimics_name_the_joint_and_the_fix() {
    for (m2, m3, parts) in [
        (
            r#"mimic = { joint = "thumb" }"#,
            "",
            &["joint `f2`", "names no joint", "`f1`"][..],
        ),
        (
            r#"mimic = { joint = "f2" }"#,
            "",
            &["joint `f2`", "follows itself"][..],
        ),
        (
            r#"mimic = { joint = "f3" }"#,
            r#"mimic = { joint = "f2" }"#,
            &["joint `f2`", "cycle (f2 → f3 → f2)", "remove `mimic`"][..],
        ),
        (
            r#"mimic = { joint = "f1", multiplier = 0 }"#,
            "",
            &["joint `f2`", "multiplier is 0", "non-zero"][..],
        ),
    ] {
        let m = load(&gripper(m2, m3)).expect_err("refused");
        for p in parts.iter().chain(&["gripper.toml: ", "field `mimic`"]) {
            assert!(m.contains(p), "lacks {p:?}: {m}");
        }
    }
    // An unknown key of the table is a parse error with its position.
    let m = load(&gripper(r#"mimic = { joint = "f1", ratio = 2 }"#, "")).expect_err("ratio");
    assert!(m.contains("unknown field `ratio`"), "{m}");
}

/// The same gripper as a URDF with `<mimic>`: the same coupling.
#[test]
fn toml_and_urdf_mimics_agree() {
    let urdf = r#"<robot name="g">
<link name="base"/>
<link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<link name="b"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
<link name="c"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
<joint name="wrist" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
<joint name="f1" type="continuous"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/></joint>
<joint name="f2" type="continuous"><parent link="a"/><child link="c"/><axis xyz="1 0 0"/><mimic joint="f1" multiplier="-1.5" offset="0.2"/></joint>
</robot>"#;
    let r = from_str(urdf, Format::Urdf, "g.urdf", &LoadOptions::default()).expect("urdf");
    assert_eq!(
        r.joints[2].mimic,
        Some(Mimic {
            leader: 1,
            multiplier: -1.5,
            offset: 0.2
        })
    );
    let t = load(&gripper(
        r#"mimic = { joint = "f1", multiplier = -1.5, offset = 0.2 }"#,
        "",
    ))
    .expect("toml");
    assert_eq!(t.joints[2].mimic, r.joints[2].mimic);
}
