//! Runs of parallel joints in the kinematics ([`super::kinematics`]): the poses, Jacobians
//! and potential energy of arms whose consecutive axes are parallel (the same direction,
//! opposite directions, a prismatic joint along the axis inside the run, a mimic joint that
//! turns with its leader, a home offset) take the sines and cosines of the runs' sums, and
//! equal the reference implementation's.

use super::kinematics::expand_kinematics;
use super::*;
use crate::expr::Node;
use dynamics_model::random::Rng;
use dynamics_model::{LoadOptions, Robot};

/// A link with a mass off its joint's axis.
fn link(name: &str, mass: f64) -> String {
    format!(
        r#"<link name="{name}"><inertial><origin xyz="0.03 -0.02 0.05" rpy="0.1 0.2 0.3"/>
        <mass value="{mass}"/><inertia ixx="0.02" ixy="0.001" ixz="-0.002" iyy="0.03" iyz="0.0015" izz="0.025"/>
        </inertial></link>"#
    )
}

/// A joint of `kind` from `parent` to `child` at `origin` (`xyz`, `rpy`) about or along `axis`,
/// with `extra` tags (a mimic).
fn joint(
    name: &str,
    kind: &str,
    parent: &str,
    child: &str,
    origin: &str,
    axis: &str,
    extra: &str,
) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>
        <origin {origin}/><axis xyz="{axis}"/><limit lower="-3" upper="3" effort="10" velocity="2"/>{extra}</joint>"#
    )
}

/// The joints of an arm: name, kind, origin, axis, extra tags.
type Spec<'a> = [(&'a str, &'a str, &'a str, &'a str, &'a str)];

/// The arm of `joints`, one after the other from the base.
fn arm(joints: &Spec<'_>) -> Robot {
    let mut text = String::from(r#"<robot name="runs">"#);
    text += &link("base", 1.0);
    let mut parent = "base".to_string();
    for (k, (name, kind, origin, axis, extra)) in joints.iter().enumerate() {
        let child = format!("l{}", k + 1);
        text += &link(&child, 1.0 + k as f64 * 0.1);
        text += &joint(name, kind, &parent, &child, origin, axis, extra);
        parent = child;
    }
    text += "</robot>";
    dynamics_model::urdf::from_str(&text, "runs.urdf", &LoadOptions::default()).expect("loads")
}

const Y: &str = r#"xyz="0.1 0.05 0.3" rpy="0 0 0""#;
const SHOULDER: &str = r#"xyz="0 0.13 0.08" rpy="1.5707963267948966 0 0""#;
const ELBOW: &str = r#"xyz="0.42 0 0.02" rpy="0 0 1.5707963267948966""#;
const MIMIC: &str = r#"<mimic joint="j2" multiplier="1" offset="0.3"/>"#;

/// An arm of 9 joints: a base yaw, then a run about one axis (shoulder, elbow, a joint about
/// the opposite direction, a prismatic joint along the axis, a wrist joint turned about it by
/// a constant 0.7 rad, a mimic of the shoulder), then a run of two joints about another axis
/// (the second's frame turned by π about x, so that its axis is the first's reversed).
fn runs_arm() -> Robot {
    arm(&[
        ("j1", "revolute", YAW, "0 0 1", ""),
        ("j2", "revolute", SHOULDER, "0 0 1", ""),
        ("j3", "revolute", ELBOW, "0 0 1", ""),
        ("j4", "revolute", Y, "0 0 -1", ""),
        ("j5", "prismatic", Y, "0 0 1", ""),
        (
            "j6",
            "revolute",
            r#"xyz="0.2 -0.1 0" rpy="0 0 0.7""#,
            "0 0 1",
            "",
        ),
        ("j7", "revolute", Y, "0 0 1", MIMIC),
        (
            "j8",
            "revolute",
            r#"xyz="0 0 0.1" rpy="0 1.5707963267948966 0""#,
            "0 0 1",
            "",
        ),
        (
            "j9",
            "revolute",
            r#"xyz="0 0.1 0" rpy="3.141592653589793 0 0""#,
            "0 0 1",
            "",
        ),
    ])
}

/// Whether a live `sin` or `cos` of `roots` takes an argument that reads two or more inputs.
fn has_sum_angle(g: &ExprGraph, roots: &[ExprId]) -> bool {
    fn inputs(g: &ExprGraph, id: ExprId, out: &mut Vec<u16>) {
        match *g.node(id) {
            Node::Input(x) => out.push(x.index),
            ref n => n.operands().for_each(|o| inputs(g, o, out)),
        }
    }
    let live = g.live(roots);
    g.nodes().iter().zip(&live).any(|(n, &l)| {
        let (Node::Sin(a) | Node::Cos(a)) = *n else {
            return false;
        };
        let mut read = Vec::new();
        inputs(g, a, &mut read);
        read.sort_unstable();
        read.dedup();
        l && read.len() >= 2
    })
}

fn close(what: &str, x: &[f64], y: &[f64]) {
    let scale = y.iter().fold(1.0f64, |m, b| m.max(b.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        x.len() == y.len() && err <= 1e-12 * scale,
        "{what}: error {err:e} (scale {scale:e})"
    );
}

fn row_major(m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect()
}

/// The end effector's pose, `J_s`, `J_b` and the potential energy of `k` (expanded from
/// `robot`) equal the reference's at 20 random configurations drawn from `seed`.
fn equal_the_reference(robot: &Robot, k: &super::kinematics::Kinematics, seed: u64) {
    let ee = &k.end_effector;
    let mut rng = Rng::new(seed);
    for _ in 0..20 {
        let q: Vec<f64> = (0..robot.n_coordinates())
            .map(|_| rng.uniform(-3.0, 3.0))
            .collect();
        let eval = |roots: &[ExprId]| k.graph.eval(roots, &|x: Input| q[x.index as usize]);
        let t = dynamics_reference::end_effector_pose(robot, &q);
        let pose: Vec<f64> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .chain((0..3).map(|i| (i, 3)))
            .map(|(i, j)| t[(i, j)])
            .collect();
        close("pose", &eval(&ee.pose), &pose);
        let j_s = dynamics_reference::jacobian_space(robot, &q);
        close("J_s", &eval(&ee.jacobian_space), &row_major(&j_s));
        let j_b = dynamics_reference::jacobian_body(robot, &q);
        close("J_b", &eval(&ee.jacobian_body), &row_major(&j_b));
        let p = dynamics_reference::potential_energy(robot, &q, &robot.gravity);
        close("P", &eval(&[k.potential_energy]), &[p]);
    }
}

#[test]
fn runs_of_parallel_joints_take_the_sums_and_equal_the_reference() {
    let robot = runs_arm();
    let k = expand_kinematics(&robot);
    let ee = &k.end_effector;
    for (what, roots) in [
        ("pose", &ee.pose),
        ("J_s", &ee.jacobian_space),
        ("J_b", &ee.jacobian_body),
    ] {
        assert!(has_sum_angle(&k.graph, roots), "{what} takes no run's sum");
    }
    equal_the_reference(&robot, &k, 0x5_a17);
}

/// The UR5's shoulder, elbow and first wrist joint are a run (its pose takes their sums); the
/// Panda has no two consecutive parallel axes, so its kinematics take no sum.
#[test]
fn the_ur5_takes_sums_and_the_panda_none() {
    let ur5 = dynamics_model::load("ur5", &LoadOptions::default()).expect("shipped");
    let k = expand_kinematics(&ur5);
    assert!(has_sum_angle(&k.graph, &k.end_effector.pose));
    let panda = dynamics_model::urdf::from_str(
        include_str!("../../../tests/data/robots/panda.urdf"),
        "panda.urdf",
        &LoadOptions::default(),
    )
    .expect("panda");
    let k = expand_kinematics(&panda);
    let ee = &k.end_effector;
    for roots in [&ee.pose, &ee.jacobian_space, &ee.jacobian_body] {
        assert!(!has_sum_angle(&k.graph, roots));
    }
}

/// `M` and `g` of the closed-form equations (`dynamics-gen equations`; with the derivation's
/// steps, which print the potential energy) at 5 random states against the reference's.
fn check_closed_form(robot: &Robot) {
    use crate::equations::{poly::Var, quantities, Select};
    let select = Select {
        mass_matrix: true,
        coriolis: false,
        coriolis_matrix: false,
        gravity: true,
    };
    let out = quantities(robot, true, select, &[]).expect("closed form");
    let find = |text: &str| {
        out.iter()
            .find(|q| q.text == text)
            .unwrap_or_else(|| panic!("no {text}"))
    };
    let (m, g) = (find("M"), find("g"));
    let mut rng = Rng::new(0xe9);
    for _ in 0..5 {
        let q: Vec<f64> = (0..robot.n_coordinates())
            .map(|_| rng.uniform(-3.0, 3.0))
            .collect();
        let at = |p: &crate::equations::poly::Poly| {
            p.eval(&|v| match v {
                Var::Q(i) => q[i as usize],
                Var::Sin(i) => q[i as usize].sin(),
                Var::Cos(i) => q[i as usize].cos(),
                other => panic!("{other:?} in M or g"),
            })
        };
        let gravity = dynamics_reference::gravity_forces(robot, &q, &robot.gravity);
        let got: Vec<f64> = g.entries.iter().map(at).collect();
        close("g", &got, gravity.as_slice());
        let mass = dynamics_reference::mass_matrix(robot, &q);
        let got: Vec<f64> = m.entries.iter().map(at).collect();
        close("M", &got, &row_major(&mass));
    }
}

const YAW: &str = r#"xyz="0 0 0.1" rpy="0 0 0""#;

/// The closed form expands a run's sines and cosines by the angle addition formulas, a mimic
/// joint's twice-counted leader included.
#[test]
fn equations_of_runs_expand_the_sums() {
    // A run small enough for the closed form: a base yaw, shoulder, elbow, a joint about the
    // opposite direction and a mimic of the shoulder.
    check_closed_form(&arm(&[
        ("j1", "revolute", YAW, "0 0 1", ""),
        ("j2", "revolute", SHOULDER, "0 0 1", ""),
        ("j3", "revolute", ELBOW, "0 0 1", ""),
        ("j4", "revolute", Y, "0 0 -1", ""),
        ("j7", "revolute", Y, "0 0 1", MIMIC),
    ]));
}

/// A mimic joint with a whole multiplier has a closed form (its sine expanded by angle
/// addition, `sin 2θ = 2 sin θ cos θ`), equal to the reference; a multiplier of 0.5 is refused
/// with what to do.
#[test]
fn equations_of_whole_and_fractional_mimic_multipliers() {
    let with = |multiplier: &str| {
        let mimic = format!(r#"<mimic joint="j2" multiplier="{multiplier}" offset="0.2"/>"#);
        let across = r#"xyz="0.3 0 0" rpy="0 1.5707963267948966 0""#;
        arm(&[
            ("j1", "revolute", YAW, "0 0 1", ""),
            ("j2", "revolute", SHOULDER, "0 0 1", ""),
            ("j3", "revolute", across, "0 0 1", &mimic),
        ])
    };
    check_closed_form(&with("2"));
    let select = crate::equations::Select::default();
    let err = crate::equations::quantities(&with("0.5"), false, select, &[])
        .expect_err("a multiplier of 0.5 has no closed form in sines of θ")
        .to_string();
    assert!(err.contains("multiplier such as 0.5"), "{err}");
    assert!(err.contains("whole numbers up to 8"), "{err}");
}

/// The Jacobian's point on a joint's axis: the Panda's third joint sits 0.316 m along its own
/// axis from the second joint's origin, which is on the base's z axis at `(0, 0, 0.333)`; its
/// column's `v = (0, 0, 0.333) × ω` then has an exact zero for `v_z` (from the joint's own
/// origin it would be a sum of products that cancel only numerically).
#[test]
fn the_jacobian_takes_a_cheaper_point_of_the_axis() {
    let panda = dynamics_model::urdf::from_str(
        include_str!("../../../tests/data/robots/panda.urdf"),
        "panda.urdf",
        &LoadOptions::default(),
    )
    .expect("panda");
    let k = expand_kinematics(&panda);
    let nv = panda.dof();
    let j_s = &k.end_effector.jacobian_space;
    assert!(k.graph.is_zero(j_s[5 * nv + 2]), "v_z of the third column");
    assert!(!k.graph.is_zero(j_s[3 * nv + 2]), "v_x of the third column");
}

/// Twisted joints (the axes neither parallel nor at right angles: `a x_λ + d z` from the foot
/// of the common normal instead of three columns of `R_λ`), offsets along and across the axes,
/// a prismatic joint among them: the pose, both Jacobians and the potential energy equal the
/// reference's.
#[test]
fn twisted_joints_equal_the_reference() {
    let robot = arm(&[
        ("j1", "revolute", YAW, "0 0 1", ""),
        (
            "j2",
            "revolute",
            r#"xyz="0.05 0.1 0.2" rpy="0.4 0 0""#,
            "0 0 1",
            "",
        ),
        (
            "j3",
            "revolute",
            r#"xyz="0.3 -0.07 0.11" rpy="-0.9 0.3 0.2""#,
            "0 0 1",
            "",
        ),
        (
            "j4",
            "prismatic",
            r#"xyz="0.1 0.02 0.05" rpy="0.7 0 0""#,
            "0 0 1",
            "",
        ),
        (
            "j5",
            "revolute",
            r#"xyz="0 0.15 0.25" rpy="1.2 0 0""#,
            "0 0 1",
            "",
        ),
        (
            "j6",
            "revolute",
            r#"xyz="0.12 0 0" rpy="0 0.6 0""#,
            "0 1 0",
            "",
        ),
    ]);
    let k = expand_kinematics(&robot);
    equal_the_reference(&robot, &k, 0x7_157);
}
