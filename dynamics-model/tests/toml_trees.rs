//! Trees and the base in the TOML format: `parent` of a joint and of the end effector, the
//! `[base]` table, and their errors (each naming the file, the joint or link, the field and
//! the fix).

use dynamics_model::load::{from_str, Format};
use dynamics_model::{LoadOptions, ModelError, Robot};
use nalgebra::Vector3;

const FILE: &str = "tree.toml";

/// Two arms on a torso, on a floating pelvis; the tool hangs from the left forearm.
const TWO_ARMS: &str = r#"name = "two_arms"

[base]
name = "pelvis"
floating = true
mass = 5.0
inertia = [0.05, 0.04, 0.03, 0, 0, 0]
com = [0, 0, 0.05]

[[joint]]
name = "torso_yaw"
type = "revolute"
axis = [0, 0, 1]
point = [0, 0, 0]

[joint.link]
name = "torso"
home = { xyz = [0, 0, 0.3] }
mass = 10.0
inertia = [0.3, 0.3, 0.1, 0, 0, 0]
com = [0, 0, 0.1]

[[joint]]
name = "left_shoulder"
type = "revolute"
parent = "torso"
axis = [0, 1, 0]
point = [0, 0.2, 0.5]

[joint.link]
name = "left_arm"
home = { xyz = [0, 0.2, 0.2] }
mass = 1.0
inertia = [0.01, 0.01, 0.002, 0, 0, 0]
com = [0, 0, -0.15]

[[joint]]
name = "left_elbow"
type = "revolute"
axis = [0, 1, 0]
point = [0, 0.2, 0.2]

[joint.link]
name = "left_forearm"
home = { xyz = [0, 0, -0.3] }
mass = 0.8
inertia = [0.008, 0.008, 0.001, 0, 0, 0]
com = [0, 0, -0.12]

[[joint]]
name = "right_shoulder"
type = "revolute"
parent = "torso"
axis = [0, 1, 0]
point = [0, -0.2, 0.5]

[joint.link]
name = "right_arm"
home = { xyz = [0, -0.2, 0.2] }
mass = 1.0
inertia = [0.01, 0.01, 0.002, 0, 0, 0]
com = [0, 0, -0.15]

[[joint]]
name = "right_elbow"
type = "revolute"
axis = [0, 1, 0]
point = [0, -0.2, 0.2]

[joint.link]
name = "right_forearm"
home = { xyz = [0, 0, -0.3] }
mass = 0.8
inertia = [0.008, 0.008, 0.001, 0, 0, 0]
com = [0, 0, -0.12]

[end_effector]
name = "left_hand"
parent = "left_forearm"
home = { xyz = [0, 0, -0.25] }
"#;

/// The same robot in URDF (the tool as a link welded to the left forearm).
const TWO_ARMS_URDF: &str = r#"<robot name="two_arms">
  <link name="pelvis"><inertial><origin xyz="0 0 0.05"/><mass value="5"/><inertia ixx="0.05" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.03"/></inertial></link>
  <link name="torso"><inertial><origin xyz="0 0 0.1"/><mass value="10"/><inertia ixx="0.3" ixy="0" ixz="0" iyy="0.3" iyz="0" izz="0.1"/></inertial></link>
  <link name="left_arm"><inertial><origin xyz="0 0 -0.15"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial></link>
  <link name="left_forearm"><inertial><origin xyz="0 0 -0.12"/><mass value="0.8"/><inertia ixx="0.008" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.001"/></inertial></link>
  <link name="right_arm"><inertial><origin xyz="0 0 -0.15"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial></link>
  <link name="right_forearm"><inertial><origin xyz="0 0 -0.12"/><mass value="0.8"/><inertia ixx="0.008" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.001"/></inertial></link>
  <link name="left_hand"/>
  <joint name="torso_yaw" type="continuous"><parent link="pelvis"/><child link="torso"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/></joint>
  <joint name="right_shoulder" type="continuous"><parent link="torso"/><child link="right_arm"/><origin xyz="0 -0.2 0.2"/><axis xyz="0 1 0"/></joint>
  <joint name="right_elbow" type="continuous"><parent link="right_arm"/><child link="right_forearm"/><origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/></joint>
  <joint name="left_shoulder" type="continuous"><parent link="torso"/><child link="left_arm"/><origin xyz="0 0.2 0.2"/><axis xyz="0 1 0"/></joint>
  <joint name="left_elbow" type="continuous"><parent link="left_arm"/><child link="left_forearm"/><origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/></joint>
  <joint name="left_hand_joint" type="fixed"><parent link="left_forearm"/><child link="left_hand"/><origin xyz="0 0 -0.25"/></joint>
</robot>"#;

fn load(text: &str) -> Result<Robot, ModelError> {
    from_str(text, Format::Toml, FILE, &LoadOptions::default())
}

/// `TWO_ARMS` with the (unique) text `from` replaced by `to`.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(TWO_ARMS.matches(from).count(), 1, "{from}");
    TWO_ARMS.replace(from, to)
}

/// The single validation error of `text`; checks it names the file, `who`, `field` and
/// `problem`, and has a fix.
fn invalid(text: &str, who: &str, field: &str, problem: &str) -> String {
    let e = load(text).expect_err("the file must be refused");
    let msg = e.to_string();
    assert_eq!(e.errors().len(), 1, "{msg}");
    let inv = &e.errors()[0];
    assert_eq!(inv.field, field, "{msg}");
    assert!(!inv.fix.is_empty(), "{msg}");
    for part in [FILE, who, &format!("field `{field}`"), problem] {
        assert!(msg.contains(part), "`{part}` missing from: {msg}");
    }
    msg
}

#[test]
fn two_arms_on_a_torso() {
    let r = load(TWO_ARMS).expect("two arms");
    assert_eq!(
        r.joint_names(),
        [
            "torso_yaw",
            "left_shoulder",
            "left_elbow",
            "right_shoulder",
            "right_elbow"
        ]
    );
    assert_eq!(r.parents(), [None, Some(0), Some(1), Some(0), Some(3)]);
    assert_eq!(r.path_to(4), [0, 3, 4]);
    assert!(r.base.floating);
    assert_eq!(r.base.name, "pelvis");
    assert_eq!(r.base.inertia.mass(), 5.0);
    assert_eq!(r.nq(), 12);
    assert_eq!(r.end_effector.parent, Some(2));
    // Homes are relative to the parent: the right forearm is at (0, −0.2, 0.2) in {0}, the
    // hand 0.25 below the left forearm.
    let home = r.home_poses();
    let at = |i: usize| home[i].fixed_view::<3, 1>(0, 3).into_owned();
    assert!((at(5) - Vector3::new(0.0, -0.2, 0.2)).amax() < 1e-15);
    assert!((at(6) - Vector3::new(0.0, 0.2, -0.05)).amax() < 1e-15);
}

#[test]
fn the_toml_tree_is_the_urdf_tree() {
    let toml = load(TWO_ARMS).expect("toml");
    let options = LoadOptions {
        floating_base: true,
        tip: Some("left_hand".into()),
        ..LoadOptions::default()
    };
    let urdf = from_str(TWO_ARMS_URDF, Format::Urdf, "two_arms.urdf", &options).expect("urdf");
    // URDF lists children by joint name, as the TOML file does here.
    assert_eq!(toml.joint_names(), urdf.joint_names());
    assert_eq!(toml.parents(), urdf.parents());
    assert_eq!(toml.base.floating, urdf.base.floating);
    assert_eq!(toml.base.name, urdf.base.name);
    assert!((toml.base.inertia.0 - urdf.base.inertia.0).amax() < 1e-15);
    for (a, b) in toml.joints.iter().zip(&urdf.joints) {
        assert!((a.screw - b.screw).amax() < 1e-15, "{}", a.name);
    }
    for (a, b) in toml.links.iter().zip(&urdf.links) {
        assert_eq!(a.name, b.name);
        assert!((a.home - b.home).amax() < 1e-15, "{}", a.name);
        assert!((a.inertia.0 - b.inertia.0).amax() < 1e-15, "{}", a.name);
    }
    assert_eq!(toml.end_effector.parent, urdf.end_effector.parent);
    assert!((toml.end_effector.home - urdf.end_effector.home).amax() < 1e-15);
}

#[test]
fn defaults_make_a_fixed_massless_base_and_a_chain() {
    // Without `[base]` and `parent`: a serial chain on a fixed base called `base`.
    let text = TWO_ARMS
        .replace("parent = \"torso\"\n", "")
        .replace("parent = \"left_forearm\"\n", "");
    let text = text[text.find("[[joint]]").unwrap()..].to_string();
    let r = load(&format!("name = \"chain\"\n{text}")).expect("chain");
    assert!(r.is_serial());
    assert_eq!(r.base.name, "base");
    assert!(!r.base.floating);
    assert_eq!(r.base.inertia.mass(), 0.0);
    assert_eq!(r.end_effector.parent, Some(4));
    // A `[base]` with a name only is massless and fixed; `parent` may name it.
    let r = load(
        &edit(
            "mass = 5.0\ninertia = [0.05, 0.04, 0.03, 0, 0, 0]\ncom = [0, 0, 0.05]\n",
            "",
        )
        .replace("floating = true\n", "")
        .replace(
            "name = \"right_shoulder\"\ntype = \"revolute\"\nparent = \"torso\"",
            "name = \"right_shoulder\"\ntype = \"revolute\"\nparent = \"pelvis\"",
        ),
    )
    .expect("named base");
    assert!(!r.base.floating);
    assert_eq!(r.base.inertia.mass(), 0.0);
    assert_eq!(r.parents()[3], None);
    // The loader's floating_base floats a TOML base too.
    let floating = LoadOptions {
        floating_base: true,
        ..LoadOptions::default()
    };
    let r = from_str(
        &format!("name = \"chain\"\n{text}"),
        Format::Toml,
        FILE,
        &floating,
    )
    .expect("floating");
    assert!(r.base.floating);
}

#[test]
fn base_bodies_add_up() {
    let r = load(&edit(
        "mass = 5.0\ninertia = [0.05, 0.04, 0.03, 0, 0, 0]\ncom = [0, 0, 0.05]\n",
        "\n[[base.body]]\nname = \"hip\"\nshape = { box = [0.2, 0.3, 0.1] }\nmass = 4.0\n\n[[base.body]]\nname = \"battery\"\nmass = 1.0\ninertia = [0, 0, 0, 0, 0, 0]\nframe = { xyz = [0, 0, 0.1] }\n",
    ))
    .expect("base bodies");
    assert_eq!(r.base.inertia.mass(), 5.0);
    assert!((r.base.inertia.com() - Vector3::new(0.0, 0.0, 0.02)).amax() < 1e-16);
}

#[test]
fn unknown_parent() {
    let msg = invalid(
        &edit("parent = \"left_forearm\"", "parent = \"left_foot\""),
        "end effector",
        "parent",
        "`left_foot` is neither the base nor a link",
    );
    assert!(msg.contains("`pelvis` (the base)"), "{msg}");
    let msg = invalid(
        &edit(
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"torso\"",
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"torsoo\"",
        ),
        "joint `left_shoulder`",
        "parent",
        "`torsoo` is neither the base nor a link",
    );
    // The fix lists the links it may hang from: the base and earlier links only.
    assert!(msg.contains("`pelvis` (the base), `torso`"), "{msg}");
    assert!(!msg.contains("`right_arm`"), "{msg}");
}

#[test]
fn parent_after_the_joint() {
    let msg = invalid(
        &edit(
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"torso\"",
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"right_arm\"",
        ),
        "joint `left_shoulder`",
        "parent",
        "`right_arm` is the link of joint 4 `right_shoulder`, which comes after this joint",
    );
    assert!(
        msg.contains("move this `[[joint]]` after joint `right_shoulder`"),
        "{msg}"
    );
    invalid(
        &edit(
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"torso\"",
            "name = \"left_shoulder\"\ntype = \"revolute\"\nparent = \"left_arm\"",
        ),
        "joint `left_shoulder`",
        "parent",
        "this joint's own link",
    );
}

#[test]
fn a_link_may_not_take_the_bases_name() {
    invalid(
        &edit("name = \"right_arm\"", "name = \"pelvis\""),
        "link `pelvis`",
        "name",
        "the base's name",
    );
}

#[test]
fn base_inertial_errors_name_the_base_and_the_field() {
    invalid(
        &edit("mass = 5.0", "mass = -5.0"),
        "link `pelvis`",
        "mass",
        "≥ 0",
    );
    invalid(
        &edit(
            "inertia = [0.05, 0.04, 0.03, 0, 0, 0]",
            "inertia = [0.01, 0.01, 0.03, 0, 0, 0]",
        ),
        "link `pelvis`",
        "inertia",
        "triangle inequality",
    );
    invalid(
        &edit(
            "com = [0, 0, 0.05]\n",
            "com = [0, 0, 0.05]\ndensity = 1000.0\n",
        ),
        "link `pelvis`",
        "density",
        "without a `shape`",
    );
    let msg = invalid(
        &edit(
            "com = [0, 0, 0.05]\n",
            "com = [0, 0, 0.05]\n\n[[base.body]]\nmass = 1.0\ninertia = [0, 0, 0, 0, 0, 0]\n",
        ),
        "link `pelvis`",
        "body",
        "the base has both its own inertial keys",
    );
    assert!(msg.contains("`[[base.body]]`"), "{msg}");
    invalid(
        &edit(
            "mass = 5.0\ninertia = [0.05, 0.04, 0.03, 0, 0, 0]\ncom = [0, 0, 0.05]\n",
            "\n[[base.body]]\nname = \"hip\"\nshape = { box = [0.2, -0.3, 0.1] }\nmass = 4.0\n",
        ),
        "link `pelvis`",
        "body[hip].shape.box",
        "positive length",
    );
}

#[test]
fn base_schema_errors_are_parse_errors_in_the_base() {
    for (from, to, parts) in [
        (
            "floating = true",
            "floating = \"yes\"",
            &["invalid type", "[base] `pelvis`"][..],
        ),
        (
            "mass = 5.0",
            "mas = 5.0",
            &["unknown field `mas`", "[base] `pelvis`"][..],
        ),
        (
            "parent = \"left_forearm\"",
            "parent = 3",
            &["invalid type", "[end_effector]"][..],
        ),
    ] {
        let e = load(&edit(from, to)).expect_err(to);
        assert!(matches!(e, ModelError::Parse { .. }), "{e}");
        let msg = e.to_string();
        for part in parts {
            assert!(msg.contains(part), "`{part}` missing from: {msg}");
        }
    }
}
