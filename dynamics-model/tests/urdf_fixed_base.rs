//! Links welded to the fixed base never move, so their inertias do not enter the dynamics and
//! are not checked (real files carry meaningless ones there, e.g. Unitree's B1-Z1 or TIAGo's
//! antennas); the same inertia on a moving link is an error naming that link, and on a
//! floating base the merged base body must be physical.

use dynamics_model::{load::from_str, Format, LoadOptions};

const URDF: &str = r#"<robot name="base_inertia">
  <link name="base">
    <inertial><mass value="1e-6"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="3e-6"/></inertial>
  </link>
  <link name="l1">
    <inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;

#[test]
fn an_impossible_inertia_on_the_fixed_base_is_ignored() {
    let robot = from_str(URDF, Format::Urdf, "base.urdf", &LoadOptions::default())
        .expect("the base link's inertia does not matter");
    assert_eq!(robot.dof(), 1);
    assert!((robot.links[0].inertia.mass() - 1.0).abs() < 1e-15);
    // Kept as the base's inertia, which counts only on a floating base.
    assert_eq!(robot.base.inertia.mass(), 1e-6);
    assert!(!robot.base.floating);
}

#[test]
fn the_same_inertia_on_a_moving_link_is_an_error_naming_it() {
    let moving = URDF.replace(
        r#"<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>"#,
        r#"<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="3e-6"/>"#,
    );
    let e = from_str(
        &moving,
        Format::Urdf,
        "moving.urdf",
        &LoadOptions::default(),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("moving.urdf") && msg.contains("link `l1`"),
        "{msg}"
    );
    assert!(
        msg.contains("inertial.inertia") && msg.contains("triangle"),
        "{msg}"
    );
}

#[test]
fn the_same_inertia_on_a_floating_base_is_an_error_naming_it() {
    let floating = LoadOptions {
        floating_base: true,
        ..LoadOptions::default()
    };
    let msg = from_str(URDF, Format::Urdf, "float.urdf", &floating)
        .unwrap_err()
        .to_string();
    // The base is checked as one merged body (here: this link alone).
    assert!(
        msg.contains("float.urdf") && msg.contains("link `base`"),
        "{msg}"
    );
    assert!(msg.contains("inertia") && msg.contains("triangle"), "{msg}");
    // The same dummy link welded to a physical trunk (as ANYmal, Go1 and B1 have it): the
    // merged base is physical, and loads.
    let with_trunk = URDF.replace(
        r#"<link name="l1">"#,
        r#"<link name="trunk"><inertial><mass value="5"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/></inertial></link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="trunk"/></joint>
  <link name="l1">"#,
    );
    let robot = from_str(&with_trunk, Format::Urdf, "trunk.urdf", &floating).expect("merged base");
    assert!((robot.base.inertia.mass() - (5.0 + 1e-6)).abs() < 1e-12);
    // A physical inertia on the same base loads, and floats.
    let fine = URDF.replace(
        r#"<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="3e-6"/>"#,
        r#"<inertia ixx="2e-6" ixy="0" ixz="0" iyy="2e-6" iyz="0" izz="3e-6"/>"#,
    );
    let robot = from_str(&fine, Format::Urdf, "float.urdf", &floating).expect("floating");
    assert!(robot.base.floating);
    assert_eq!(robot.base.name, "base");
    assert_eq!(robot.base.inertia.mass(), 1e-6);
}
