//! The URDF loader is as tolerant as urdfdom and Pinocchio: what a dynamics model does not
//! need (visual and collision content, materials, textures, `<gazebo>`, `<transmission>`,
//! extension geometry such as Pinocchio's `<capsule>`, unknown tags and attributes) is
//! skipped, and the errors that matter keep their line and column.

mod urdf_common;

use dynamics_model::LoadOptions;
use urdf_common::*;

/// A two-link arm whose links and joint carry `extra_link` / `extra_joint` and whose robot
/// carries `extra_top` after its links.
fn arm(extra_link: &str, extra_joint: &str, extra_top: &str) -> String {
    let inertial = r#"<inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    format!(
        r#"<?xml version="1.0"?>
<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">
<link name="a">{inertial}{extra_link}</link>
<link name="b">{inertial}{extra_link}</link>
{extra_top}
<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra_joint}</joint>
</robot>
"#
    )
}

fn loads(text: &str) {
    match load_text(text, "t.urdf", &LoadOptions::default()) {
        Ok(r) => assert_eq!(r.joint_names(), ["j1"]),
        Err(e) => panic!("refused: {e}\n{text}"),
    }
}

#[test]
fn texture_without_filename_is_skipped() {
    // icub.urdf, romeo_laas_small.urdf: <texture/> in a visual's material.
    let visual = r#"<visual><geometry><mesh filename="x.dae" scale="1 1 1"/></geometry>
        <material name="metal"><texture/><color rgba="0 0 0 1"/></material></visual>"#;
    loads(&arm(
        visual,
        "",
        r#"<material name="m"><texture/></material>"#,
    ));
}

#[test]
fn capsule_and_pinocchio_extensions_are_skipped() {
    // simple_humanoid.urdf: <collision_checking><capsule name="test"/></collision_checking>.
    let extension = r#"<collision><geometry><capsule radius="0.1" length="0.2"/></geometry></collision>
        <collision_checking><capsule name="test"/><convex name="box"/></collision_checking>"#;
    loads(&arm(extension, "", ""));
}

#[test]
fn bad_visual_and_collision_content_is_skipped() {
    // Missing or malformed geometry, colours and unknown geometry: not needed, not checked.
    let visual = r#"<visual><origin xyz="a b c"/><geometry><box/><sphere radius="-1"/></geometry>
        <material><color rgba="red"/></material></visual>
        <collision><geometry><cylinder length="x"/><heightfield/></geometry></collision>"#;
    loads(&arm(visual, "", ""));
}

#[test]
fn gazebo_transmission_and_unknown_tags_are_skipped() {
    let top = r#"<gazebo reference="a"><material>Gazebo/Grey</material><plugin name="p" filename="libp.so"><any/></plugin></gazebo>
<transmission name="t1"><type>transmission_interface/SimpleTransmission</type><joint name="j1"><hardwareInterface>x</hardwareInterface></joint><actuator name="m"/></transmission>
<xacro:property name="pi" value="3.14"/>
<sensor name="s"/>"#;
    let joint_extra =
        r#"<calibration rising="x"/><safety_controller soft_lower_limit="-1"/><unknown_tag/>"#;
    loads(&arm("<sensor name=\"cam\"/><unknown/>", joint_extra, top));
}

#[test]
fn unknown_attributes_are_ignored() {
    let text = arm("", "", "")
        .replace(
            "<link name=\"a\">",
            "<link name=\"a\" type=\"x\" color=\"red\">",
        )
        .replace(
            "<joint name=\"j1\" type=\"revolute\">",
            "<joint name=\"j1\" type=\"revolute\" extra=\"1\">",
        )
        .replace("<mass value=\"1\"/>", "<mass value=\"1\" unit=\"kg\"/>")
        .replace(r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 0 1" frame="x"/>"#);
    loads(&text);
}

#[test]
fn errors_that_matter_keep_their_line_and_column_after_skipped_elements() {
    // A multi-line visual with non-ASCII text before the error, on the same line and above.
    let visual = "<visual><!-- é --><geometry>\n<capsule/></geometry></visual>";
    let text = arm(visual, "", "").replace("0 0 0.2", "0 0 0.2x");
    let m = error_of(&text, "num.urdf", &LoadOptions::default());
    // Lines: 1 <?xml, 2 <robot, 3-4 link a, 5-6 link b, 7 empty, 8 the joint.
    assert!(m.starts_with("num.urdf:8:"), "{m}");
    assert!(m.contains("`0.2x` is not a number"), "{m}");
    // Malformed XML inside a skipped element is still malformed XML.
    let text = arm("<visual><geometry></visual>", "", "");
    let m = error_of(&text, "bad.urdf", &LoadOptions::default());
    assert!(m.starts_with("bad.urdf:3:"), "{m}");
    assert!(m.contains("</visual>"), "{m}");
    // A missing mass and a joint type urdf-rs does not know are still refused.
    let text = arm("", "", "").replacen("<mass value=\"1\"/>", "", 1);
    let m = error_of(&text, "mass.urdf", &LoadOptions::default());
    assert!(m.contains("link `a`: <inertial> has no <mass>"), "{m}");
    let text = arm("<visual/>", "", "").replace("type=\"revolute\"", "type=\"hinge\"");
    let m = error_of(&text, "type.urdf", &LoadOptions::default());
    assert!(m.starts_with("type.urdf:"), "{m}");
    assert!(m.contains("hinge"), "{m}");
}
