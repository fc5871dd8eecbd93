//! Links welded to the fixed base never move, so their inertias do not enter the dynamics and
//! are not checked (real files carry meaningless ones there, e.g. Unitree's B1-Z1 or TIAGo's
//! antennas); the same inertia on a moving link is an error naming that link.

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
