//! One test per problem a TOML robot file can have: each is an error (never a panic) whose
//! message names the file, the joint or link, and the field.

use dynamics_model::load::{from_str, Format};
use dynamics_model::{toml_format, LoadOptions, ModelError};

const FILE: &str = "bad.toml";

/// A valid two-joint robot; tests replace one line of it.
const GOOD: &str = r#"name = "two"

[[joint]]
name = "j1"
type = "revolute"
screw = [0, 0, 1, 0, 0, 0]

[joint.link]
name = "l1"
home = { xyz = [0, 0, 0.5] }
mass = 1.0
inertia = [0.01, 0.01, 0.01, 0, 0, 0]

[[joint]]
name = "j2"
type = "revolute"
axis = [0, 1, 0]
point = [0, 0, 0.5]

[joint.link]
name = "l2"
home = { xyz = [0, 0, 0.4] }
mass = 2.0
inertia = [0.02, 0.02, 0.01, 0, 0, 0]
"#;

/// `GOOD` with the (unique) line `from` replaced by `to`.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(GOOD.matches(from).count(), 1, "{from}");
    GOOD.replace(from, to)
}

/// The error of loading `text` with validation.
fn error(text: &str) -> (ModelError, String) {
    let e = from_str(text, Format::Toml, FILE, &LoadOptions::default())
        .expect_err("the file must be refused");
    let msg = e.to_string();
    (e, msg)
}

/// The single validation error of `text`; checks it names the file, `who` and `field`.
fn invalid(text: &str, who: &str, field: &str, problem: &str) -> String {
    let (e, msg) = error(text);
    assert_eq!(e.errors().len(), 1, "{msg}");
    let inv = &e.errors()[0];
    assert_eq!(inv.file.as_deref(), Some(FILE), "{msg}");
    assert_eq!(inv.field, field, "{msg}");
    assert!(!inv.fix.is_empty(), "{msg}");
    for part in [FILE, who, &format!("field `{field}`"), problem] {
        assert!(msg.contains(part), "`{part}` missing from: {msg}");
    }
    msg
}

/// The parse error of `text`: file, 1-based line and column, and message parts.
fn parse_error(text: &str, line: usize, column: usize, parts: &[&str]) -> String {
    let (e, msg) = error(text);
    match &e {
        ModelError::Parse {
            file,
            line: l,
            column: c,
            ..
        } => {
            assert_eq!(file, FILE);
            assert_eq!((*l, *c), (line, column), "{msg}");
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
    assert!(
        msg.starts_with(&format!("{FILE}:{line}:{column}: ")),
        "{msg}"
    );
    for part in parts {
        assert!(msg.contains(part), "`{part}` missing from: {msg}");
    }
    msg
}

#[test]
fn the_base_file_is_valid() {
    let robot = from_str(GOOD, Format::Toml, FILE, &LoadOptions::default()).unwrap();
    assert_eq!(robot.dof(), 2);
}

#[test]
fn unknown_key_is_a_parse_error_at_the_key() {
    let text = edit("mass = 2.0", "masss = 2.0");
    // `masss` is on line 23, column 1, in link `l2` of joint 2 `j2`.
    parse_error(
        &text,
        23,
        1,
        &["unknown field `masss`", "link `l2` of joint 2 `j2`"],
    );
}

#[test]
fn unknown_key_in_a_joint_is_named() {
    let text = edit("point = [0, 0, 0.5]", "pointt = [0, 0, 0.5]");
    parse_error(&text, 18, 1, &["unknown field `pointt`", "joint 2 `j2`"]);
}

#[test]
fn missing_field_is_a_parse_error_naming_the_link() {
    let text = edit("home = { xyz = [0, 0, 0.4] }\n", "");
    let (_, msg) = error(&text);
    assert!(msg.starts_with("bad.toml:"), "{msg}");
    assert!(msg.contains("missing field `home`"), "{msg}");
    assert!(msg.contains("link `l2`"), "{msg}");
}

#[test]
fn toml_syntax_error_has_line_and_column() {
    let text = edit("mass = 1.0", "mass = 1.0.0");
    // Column 11 is the second `.` of `1.0.0`.
    parse_error(
        &text,
        11,
        11,
        &["invalid float", "link `l1` of joint 1 `j1`"],
    );
}

#[test]
fn wrong_type_is_a_parse_error() {
    let text = edit("mass = 1.0", "mass = true");
    parse_error(&text, 11, 8, &["boolean", "link `l1`"]);
}

#[test]
fn a_string_where_a_number_goes_is_an_expression_over_the_parameters() {
    let text = edit("mass = 1.0", "mass = \"heavy\"");
    let err = dynamics_model::toml_format::from_str(&text, "bad.toml")
        .unwrap_err()
        .to_string();
    for part in [
        "bad.toml: link `l1`: field `mass`",
        "`heavy` is not a declared parameter",
        "add `[parameters]` with `heavy = VALUE`",
    ] {
        assert!(err.contains(part), "{err}");
    }
    // Declared, it is the number.
    let text = edit("mass = 1.0", "mass = \"heavy / 2\"").replacen(
        "\n[[joint]]",
        "\n[parameters]\nheavy = 3.0\n\n[[joint]]",
        1,
    );
    let robot = dynamics_model::toml_format::from_str(&text, "ok.toml").expect("evaluated");
    assert_eq!(robot.links[0].inertia.mass(), 1.5);
    assert_eq!(robot.parameters.names, ["heavy"]);
}

#[test]
fn unknown_joint_type_lists_the_choices() {
    let text = edit("type = \"revolute\"\naxis", "type = \"spherical\"\naxis");
    parse_error(
        &text,
        16,
        8,
        &["spherical", "revolute", "prismatic", "joint 2"],
    );
}

#[test]
fn wrong_array_length_names_field_and_length() {
    let msg = invalid(
        &edit(
            "inertia = [0.01, 0.01, 0.01, 0, 0, 0]",
            "inertia = [0.01, 0.01, 0.01]",
        ),
        "link `l1`",
        "inertia",
        "expected 6 numbers, found 3",
    );
    assert!(msg.contains("[ixx, iyy, izz, ixy, ixz, iyz]"), "{msg}");
    invalid(
        &edit("screw = [0, 0, 1, 0, 0, 0]", "screw = [0, 0, 1, 0, 0]"),
        "joint `j1`",
        "screw",
        "expected 6 numbers, found 5",
    );
    invalid(
        &edit("point = [0, 0, 0.5]", "point = [0, 0.5]"),
        "joint `j2`",
        "point",
        "expected 3 numbers, found 2",
    );
    invalid(
        &edit(
            "home = { xyz = [0, 0, 0.5] }",
            "home = { xyz = [0, 0, 0.5], rpy = [0, 0] }",
        ),
        "link `l1`",
        "home.rpy",
        "expected 3 numbers, found 2",
    );
    invalid(
        &edit(
            "home = { xyz = [0, 0, 0.5] }",
            "home = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.5]]",
        ),
        "link `l1`",
        "home",
        "4 rows, found 3",
    );
    invalid(
        &format!("gravity = [0, -9.81]\n{GOOD}"),
        "robot",
        "gravity",
        "expected 3 numbers, found 2",
    );
}

#[test]
fn unknown_key_in_a_pose() {
    invalid(
        &edit(
            "home = { xyz = [0, 0, 0.5] }",
            "home = { xzy = [0, 0, 0.5] }",
        ),
        "link `l1`",
        "home",
        "unknown field `xzy`",
    );
}

#[test]
fn negative_mass() {
    invalid(
        &edit("mass = 1.0", "mass = -1.0"),
        "link `l1`",
        "mass",
        "-1",
    );
}

#[test]
fn inertia_not_positive_semidefinite() {
    invalid(
        &edit(
            "inertia = [0.01, 0.01, 0.01, 0, 0, 0]",
            "inertia = [0.01, 0.01, 0.01, 0.02, 0, 0]",
        ),
        "link `l1`",
        "inertia",
        "not positive semidefinite",
    );
}

#[test]
fn triangle_inequality_broken() {
    invalid(
        &edit(
            "inertia = [0.01, 0.01, 0.01, 0, 0, 0]",
            "inertia = [0.01, 0.01, 0.03, 0, 0, 0]",
        ),
        "link `l1`",
        "inertia",
        "triangle inequality",
    );
}

#[test]
fn massless_link_with_inertia() {
    invalid(
        &edit("mass = 1.0", "mass = 0.0"),
        "link `l1`",
        "inertia",
        "massless",
    );
}

#[test]
fn massless_link_alone_is_valid() {
    let text = edit(
        "mass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]",
        "mass = 0",
    );
    let robot = from_str(&text, Format::Toml, FILE, &LoadOptions::default()).unwrap();
    assert_eq!(robot.links[0].inertia.0, nalgebra::Matrix6::zeros());
}

#[test]
fn mass_without_inertia() {
    invalid(
        &edit(
            "mass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]",
            "mass = 1.0",
        ),
        "link `l1`",
        "inertia",
        "without its rotational inertia",
    );
}

#[test]
fn inertia_without_mass() {
    invalid(
        &edit("mass = 1.0\n", ""),
        "link `l1`",
        "mass",
        "without a `mass`",
    );
}

#[test]
fn no_inertial_data_at_all() {
    invalid(
        &edit("mass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]\n", ""),
        "link `l1`",
        "mass",
        "no inertial data",
    );
}

#[test]
fn non_unit_screw_axis() {
    invalid(
        &edit("screw = [0, 0, 1, 0, 0, 0]", "screw = [0, 0, 2, 0, 0, 0]"),
        "joint `j1`",
        "screw",
        "|ω| = 2",
    );
    // The unchecked path keeps it as written.
    let robot = toml_format::from_str(
        &edit("screw = [0, 0, 1, 0, 0, 0]", "screw = [0, 0, 2, 0, 0, 0]"),
        FILE,
    )
    .unwrap();
    assert_eq!(robot.joints[0].screw[2], 2.0);
}

#[test]
fn prismatic_with_rotation() {
    invalid(
        &edit("type = \"revolute\"\nscrew", "type = \"prismatic\"\nscrew"),
        "joint `j1`",
        "screw",
        "prismatic joint needs ω = 0",
    );
}

#[test]
fn prismatic_axis_with_point() {
    invalid(
        &edit("type = \"revolute\"\naxis", "type = \"prismatic\"\naxis"),
        "joint `j2`",
        "point",
        "prismatic",
    );
}

#[test]
fn revolute_axis_without_point() {
    invalid(
        &edit("point = [0, 0, 0.5]\n", ""),
        "joint `j2`",
        "point",
        "without a `point`",
    );
}

#[test]
fn screw_and_axis_both() {
    invalid(
        &edit(
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0, 0, 0]\naxis = [0, 0, 1]",
        ),
        "joint `j1`",
        "axis",
        "both `screw` and `axis`",
    );
}

#[test]
fn zero_axis() {
    invalid(
        &edit("axis = [0, 1, 0]", "axis = [0, 0, 0]"),
        "joint `j2`",
        "axis",
        "no direction",
    );
}

#[test]
fn non_rigid_home_matrix() {
    invalid(
        &edit(
            "home = { xyz = [0, 0, 0.4] }",
            "home = [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.4], [0, 0, 0, 1]]",
        ),
        "link `l2`",
        "home",
        "not a rigid transform",
    );
    invalid(
        &edit(
            "home = { xyz = [0, 0, 0.4] }",
            "home = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.4], [0, 0, 1, 1]]",
        ),
        "link `l2`",
        "home",
        "last row",
    );
}

#[test]
fn non_rigid_body_frame() {
    invalid(
        &edit(
            "mass = 2.0",
            "frame = [[1, 0, 0, 0], [0, 1, 0.5, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\nmass = 2.0",
        ),
        "link `l2`",
        "frame",
        "not a rigid transform",
    );
}

#[test]
fn mass_and_density_both() {
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "mass = 2.0\ndensity = 1000.0\nshape = { sphere = 0.1 }",
        ),
        "link `l2`",
        "density",
        "both `mass` and `density`",
    );
}

#[test]
fn density_without_shape() {
    invalid(
        &edit("mass = 2.0", "density = 1000.0"),
        "link `l2`",
        "density",
        "without a `shape`",
    );
}

#[test]
fn shape_with_inertia() {
    invalid(
        &edit("mass = 2.0", "mass = 2.0\nshape = { sphere = 0.1 }"),
        "link `l2`",
        "inertia",
        "together with `shape`",
    );
}

#[test]
fn shape_with_bad_size() {
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "mass = 2.0\nshape = { box = [0.1, -0.2, 0.3] }",
        ),
        "link `l2`",
        "shape.box",
        "positive length",
    );
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "mass = 2.0\nshape = { cylinder = [0.1] }",
        ),
        "link `l2`",
        "shape.cylinder",
        "expected 2 numbers, found 1",
    );
}

#[test]
fn thin_shape_with_density() {
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "density = 2.0\nshape = { disc = 0.1 }",
        ),
        "link `l2`",
        "density",
        "no volume",
    );
}

#[test]
fn unknown_shape_is_a_parse_error() {
    let text = edit("mass = 2.0", "mass = 2.0\nshape = { cube = 0.1 }");
    let (_, msg) = error(&text);
    assert!(msg.starts_with("bad.toml:24:"), "{msg}");
    assert!(msg.contains("cube") && msg.contains("ellipsoid"), "{msg}");
}

#[test]
fn spatial_inertia_with_mass_or_wrong_size() {
    invalid(
        &edit(
            "inertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "spatial_inertia = [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,2,0,0],[0,0,0,0,2,0],[0,0,0,0,0,2]]",
        ),
        "link `l2`",
        "mass",
        "together with `spatial_inertia`",
    );
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "spatial_inertia = [[1,0,0,0,0,0],[0,1,0,0,0,0]]",
        ),
        "link `l2`",
        "spatial_inertia",
        "6×6",
    );
    invalid(
        &edit(
            "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "spatial_inertia = [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,2,0,0],[0,0,0,0,3,0],[0,0,0,0,0,2]]",
        ),
        "link `l2`",
        "spatial_inertia",
        "m·1₃",
    );
}

#[test]
fn bodies_and_own_keys_both() {
    let text =
        format!("{GOOD}\n[[joint.link.body]]\nmass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]\n");
    invalid(&text, "link `l2`", "body", "both its own inertial keys");
}

#[test]
fn a_bad_body_is_named() {
    let text = edit(
        "mass = 2.0\ninertia = [0.02, 0.02, 0.01, 0, 0, 0]",
        "[[joint.link.body]]\nmass = 1.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]\n\n[[joint.link.body]]\nname = \"tip\"\nmass = -2.0\ninertia = [0.01, 0.01, 0.01, 0, 0, 0]",
    );
    invalid(&text, "link `l2`", "body[tip].mass", "-2");
}

#[test]
fn velocity_limit_must_be_positive() {
    // Without position limits too: a velocity or effort limit is kept with −∞ and +∞.
    invalid(
        &edit(
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nvelocity_limit = -2.0",
        ),
        "joint `j2`",
        "velocity_limit",
        "must be a positive number",
    );
}

#[test]
fn duplicate_names() {
    invalid(
        &edit("name = \"j2\"", "name = \"j1\""),
        "joint `j1`",
        "name",
        "both called `j1`",
    );
}

#[test]
fn no_joints() {
    invalid("name = \"empty\"\n", "robot", "joint", "no movable joint");
}

#[test]
fn every_problem_is_reported_at_once() {
    let text = edit("mass = 1.0", "mass = -1.0").replace("point = [0, 0, 0.5]", "point = [0, 0.5]");
    let (e, msg) = error(&text);
    assert_eq!(e.errors().len(), 2, "{msg}");
    assert!(
        msg.contains("link `l1`") && msg.contains("joint `j2`"),
        "{msg}"
    );
}

/// Deterministic xorshift for the no-panic test.
fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

#[test]
fn never_panics_on_truncated_or_mangled_files() {
    let text = dynamics_model::shipped::get("rand7").unwrap().text;
    // Every prefix ending on a line boundary, and every 37th character boundary.
    for (i, _) in text
        .char_indices()
        .filter(|(i, c)| *c == '\n' || i % 37 == 0)
    {
        let _ = toml_format::from_str(&text[..i], FILE);
    }
    // Random single-character replacements by characters that matter to TOML and numbers.
    let alphabet: Vec<char> = "[]{}=\",.-+e0 9#\nabxyz_".chars().collect();
    let chars: Vec<char> = GOOD.chars().collect();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for _ in 0..3000 {
        let mut c = chars.clone();
        for _ in 0..1 + next(&mut state) % 3 {
            let at = (next(&mut state) % c.len() as u64) as usize;
            c[at] = alphabet[(next(&mut state) % alphabet.len() as u64) as usize];
        }
        let s: String = c.into_iter().collect();
        let _ = from_str(&s, Format::Toml, FILE, &LoadOptions::default());
    }
}

#[test]
fn revolute_screw_with_pitch_is_refused() {
    let msg = invalid(
        &edit("screw = [0, 0, 1, 0, 0, 0]", "screw = [0, 0, 1, 0, 0, 1]"),
        "joint `j1`",
        "screw",
        "ω · v = 1",
    );
    assert!(msg.contains("v = −ω × q"), "{msg}");
    // A screw through a point off the origin has v = −ω × q ≠ 0 and no pitch: accepted.
    from_str(
        &edit(
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0.3, -0.2, 0]",
        ),
        Format::Toml,
        FILE,
        &LoadOptions::default(),
    )
    .expect("a pitch-free screw off the origin is valid");
}

#[test]
fn actuation_and_friction_fields_load_onto_the_joint() {
    let text = edit(
        "screw = [0, 0, 1, 0, 0, 0]",
        "screw = [0, 0, 1, 0, 0, 0]\ndamping = 0.5\nfriction = 0.1\nrotor_inertia = 1e-4\ngear_ratio = -100",
    );
    let robot = from_str(&text, Format::Toml, FILE, &LoadOptions::default()).expect("loads");
    let j1 = &robot.joints[0];
    assert_eq!(
        (j1.damping, j1.friction, j1.rotor_inertia, j1.gear_ratio),
        (0.5, 0.1, 1e-4, -100.0)
    );
    // The armature G²·I_rotor: the sign of G does not matter.
    assert!((j1.armature() - 1.0).abs() < 1e-15, "{}", j1.armature());
    // Left out: no friction, no rotor.
    let j2 = &robot.joints[1];
    assert_eq!(
        (j2.damping, j2.friction, j2.rotor_inertia, j2.gear_ratio),
        (0.0, 0.0, 0.0, 1.0)
    );
    assert_eq!(j2.armature(), 0.0);
}

#[test]
fn actuation_and_friction_fields_are_validated() {
    for (key, value, problem) in [
        ("damping", "-0.5", "finite and ≥ 0"),
        ("friction", "nan", "finite and ≥ 0"),
        ("rotor_inertia", "-1e-4", "finite and ≥ 0"),
        ("rotor_inertia", "inf", "finite and ≥ 0"),
        ("gear_ratio", "0", "finite and non-zero"),
        ("gear_ratio", "inf", "finite and non-zero"),
    ] {
        let text = edit(
            "screw = [0, 0, 1, 0, 0, 0]",
            &format!("screw = [0, 0, 1, 0, 0, 0]\n{key} = {value}"),
        );
        invalid(&text, "joint `j1`", key, problem);
    }
}
