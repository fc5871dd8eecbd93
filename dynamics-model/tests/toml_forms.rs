//! Equivalent ways of writing the same robot give the same robot: a screw axis or its
//! direction and a point; a pose as xyz + rpy or as a 4×4 matrix. And the annotated example
//! of the format's documentation loads, with the values it documents.

use dynamics_model::load::{from_str, Format};
use dynamics_model::{LoadOptions, Robot};
use nalgebra::{Matrix3, Vector3, Vector6};

fn load(text: &str) -> Robot {
    from_str(text, Format::Toml, "test.toml", &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// A one-joint robot with the joint keys `joint` and the link's `home` and `frame`.
fn one(joint: &str, home: &str, frame: &str) -> String {
    format!(
        "name = \"one\"\n\n[[joint]]\nname = \"j\"\n{joint}\n\n[joint.link]\nname = \"l\"\nhome = {home}\nframe = {frame}\nmass = 1.5\ninertia = [0.03, 0.02, 0.04, 0.001, -0.002, 0.003]\ncom = [0.1, -0.05, 0.2]\n"
    )
}

#[test]
fn axis_and_point_give_the_screw_axis() {
    // Revolute: ω̂ = (1, 2, 2)/3 through q = (0.3, −0.7, 1.1); S = (ω̂, −ω̂ × q).
    let w = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let q = [0.3, -0.7, 1.1];
    // −ω̂ × q written out: −(w_y q_z − w_z q_y, w_z q_x − w_x q_z, w_x q_y − w_y q_x).
    let v = [
        -(w[1] * q[2] - w[2] * q[1]),
        -(w[2] * q[0] - w[0] * q[2]),
        -(w[0] * q[1] - w[1] * q[0]),
    ];
    let by_axis = load(&one(
        "type = \"revolute\"\naxis = [1, 2, 2]\npoint = [0.3, -0.7, 1.1]",
        "{ xyz = [0, 0, 0] }",
        "{ xyz = [0, 0, 0] }",
    ));
    let screw = format!(
        "type = \"revolute\"\nscrew = [{:?}, {:?}, {:?}, {:?}, {:?}, {:?}]",
        w[0], w[1], w[2], v[0], v[1], v[2]
    );
    let by_screw = load(&one(&screw, "{ xyz = [0, 0, 0] }", "{ xyz = [0, 0, 0] }"));
    let err = (by_axis.joints[0].screw - by_screw.joints[0].screw).amax();
    assert!(err < 1e-15, "{err:e}");
    // Any other point of the axis gives the same screw: q + 2.5 ω̂ = (0.3+2.5/3, …).
    let q2 = [q[0] + 2.5 * w[0], q[1] + 2.5 * w[1], q[2] + 2.5 * w[2]];
    let moved = load(&one(
        &format!(
            "type = \"revolute\"\naxis = [1, 2, 2]\npoint = [{:?}, {:?}, {:?}]",
            q2[0], q2[1], q2[2]
        ),
        "{ xyz = [0, 0, 0] }",
        "{ xyz = [0, 0, 0] }",
    ));
    assert!((moved.joints[0].screw - by_screw.joints[0].screw).amax() < 1e-15);
    // Prismatic: S = (0, v̂).
    let prismatic = load(&one(
        "type = \"prismatic\"\naxis = [0, -3, 4]",
        "{ xyz = [0, 0, 0] }",
        "{ xyz = [0, 0, 0] }",
    ));
    let want = Vector6::new(0.0, 0.0, 0.0, 0.0, -0.6, 0.8);
    assert!((prismatic.joints[0].screw - want).amax() < 1e-16);
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)`, multiplied out by hand.
fn rpy_matrix(r: f64, p: f64, y: f64) -> Matrix3<f64> {
    let (sr, cr) = r.sin_cos();
    let (sp, cp) = p.sin_cos();
    let (sy, cy) = y.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

fn matrix_text(r: &Matrix3<f64>, p: [f64; 3]) -> String {
    let row = |i: usize| {
        format!(
            "[{:?}, {:?}, {:?}, {:?}]",
            r[(i, 0)],
            r[(i, 1)],
            r[(i, 2)],
            p[i]
        )
    };
    format!("[{}, {}, {}, [0, 0, 0, 1]]", row(0), row(1), row(2))
}

#[test]
fn xyz_rpy_and_4x4_give_the_same_frames() {
    let joint = "type = \"revolute\"\nscrew = [0, 0, 1, 0, 0, 0]";
    let (home_xyz, home_rpy) = ([0.4, -0.1, 0.25], [0.3, -0.4, 1.2]);
    let (frame_xyz, frame_rpy) = ([-0.05, 0.02, 0.1], [-1.1, 0.7, 2.9]);
    let as_rpy = load(&one(
        joint,
        &format!("{{ xyz = {home_xyz:?}, rpy = {home_rpy:?} }}"),
        &format!("{{ xyz = {frame_xyz:?}, rpy = {frame_rpy:?} }}"),
    ));
    let home_r = rpy_matrix(home_rpy[0], home_rpy[1], home_rpy[2]);
    let frame_r = rpy_matrix(frame_rpy[0], frame_rpy[1], frame_rpy[2]);
    let as_matrix = load(&one(
        joint,
        &matrix_text(&home_r, home_xyz),
        &matrix_text(&frame_r, frame_xyz),
    ));
    let home_err = (as_rpy.links[0].home - as_matrix.links[0].home).amax();
    let g_err = (as_rpy.links[0].inertia.0 - as_matrix.links[0].inertia.0).amax();
    assert!(home_err < 1e-15 && g_err < 1e-15, "{home_err:e} {g_err:e}");
    // The translation is the xyz, and a missing rpy is no rotation.
    let xyz_only = load(&one(joint, "{ xyz = [1, 2, 3] }", "{ rpy = [0, 0, 0] }"));
    let h = xyz_only.links[0].home;
    assert_eq!(
        h.fixed_view::<3, 1>(0, 3).into_owned(),
        Vector3::new(1.0, 2.0, 3.0)
    );
    assert_eq!(h.fixed_view::<3, 3>(0, 0).into_owned(), Matrix3::identity());
}

/// The ```toml block of the format's module documentation (the user manual).
fn manual_example() -> String {
    let path = format!("{}/src/toml_format/mod.rs", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    let mut inside = false;
    for line in src.lines() {
        let Some(doc) = line.strip_prefix("//!") else {
            continue;
        };
        let doc = doc.strip_prefix(' ').unwrap_or(doc);
        if doc.starts_with("```toml") {
            inside = true;
        } else if inside && doc.starts_with("```") {
            break;
        } else if inside {
            out.push_str(doc);
            out.push('\n');
        }
    }
    assert!(out.contains("[[joint]]"));
    out
}

#[test]
fn the_documented_example_loads_with_its_values() {
    let robot = load(&manual_example());
    assert_eq!(robot.name, "demo");
    assert_eq!(robot.joint_names(), ["shoulder", "elbow", "camera_pan"]);
    // A tree: the camera hangs from the upper arm, the tool from the forearm.
    assert_eq!(robot.parents(), [None, Some(0), Some(0)]);
    assert_eq!(robot.end_effector.name, "tool");
    assert_eq!(robot.end_effector.parent, Some(1));
    assert_eq!(robot.base.name, "pedestal");
    assert!(!robot.base.floating);
    assert_eq!(robot.base.inertia.mass(), 10.0);
    assert!((robot.base.inertia.com() - Vector3::new(0.0, 0.0, -0.05)).amax() < 1e-16);
    // The camera's axis passes through its link's origin at home.
    let camera = robot.home_poses()[3];
    assert!((camera.fixed_view::<3, 1>(0, 3) - Vector3::new(0.1, 0.0, 0.3)).amax() < 1e-16);
    let shoulder = &robot.joints[0];
    assert_eq!(shoulder.limits.unwrap().effort, Some(150.0));
    assert_eq!(shoulder.gear_ratio, 1.0);
    // Elbow: axis y through (0, 0, 0.5): S = (0, 1, 0, −(y × 0.5 z)) = (0, 1, 0, −0.5, 0, 0).
    let want = Vector6::new(0.0, 1.0, 0.0, -0.5, 0.0, 0.0);
    assert!((robot.joints[1].screw - want).amax() < 1e-16);
    // Upper arm: COM 0.1 above {1}: G's off-diagonal block is m[c].
    let g1 = robot.links[0].inertia;
    assert_eq!(g1.mass(), 2.0);
    assert!((g1.com() - Vector3::new(0.0, 0.0, 0.1)).amax() < 1e-16);
    // Forearm: aluminium tube ρπr²h plus a 0.5 kg gripper.
    let pi = std::f64::consts::PI;
    let tube = 2700.0 * pi * 0.03 * 0.03 * 0.4;
    let g2 = robot.links[1].inertia;
    assert!((g2.mass() - (tube + 0.5)).abs() < 1e-12);
    let com_z = (tube * 0.2 + 0.5 * 0.4) / (tube + 0.5);
    assert!((g2.com() - Vector3::new(0.0, 0.0, com_z)).amax() < 1e-15);
    // I_zz about {2}'s z axis: the tube's m r²/2 plus the gripper's 0.001 (its rotated
    // x axis lies along z, and its centre is on the axis).
    assert!((g2.0[(2, 2)] - (tube * 0.03 * 0.03 / 2.0 + 0.001)).abs() < 1e-15);
    assert_eq!(robot.end_effector.home[(2, 3)], 0.45);
}
