//! The pose and Jacobians of frames, expanded symbolically and evaluated through the
//! expression graph, against the reference implementation (`frame_pose`,
//! `frame_jacobian_space`, `frame_jacobian_body`): 120 seeded random trees (1–30 bodies,
//! revolute and prismatic, every other one on a floating base) with a frame at a random pose
//! on every link and one on the base, the end effector included; and the shipped serial arms.
//! ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 per quantity. Unit quaternions are not assumed: q's
//! quaternion is scaled by 0.3 to 3.

use dynamics_gen::expand::kinematics::{expand_kinematics, FrameKinematics};
use dynamics_gen::expand::Q;
use dynamics_gen::expr::Input;
use dynamics_model::lie::{exp6, xyz_rpy};
use dynamics_model::random::{random_tree, Rng, TreeSpec};
use dynamics_model::{Frame, Robot};
use dynamics_tests::row_major;
use nalgebra::{Matrix4, Vector6};

fn check(what: &str, x: &[f64], y: &[f64]) -> f64 {
    let (err, scale) = dynamics_tests::assert_close(what, x, y, 1e-9, 1e-12);
    err / (1e-9 * scale + 1e-12)
}

fn pose_entries(t: &Matrix4<f64>) -> Vec<f64> {
    let mut out: Vec<f64> = (0..3)
        .flat_map(|i| (0..3).map(move |j| t[(i, j)]))
        .collect();
    out.extend((0..3).map(|i| t[(i, 3)]));
    out
}

/// Every quantity of one frame at `q`: graph against reference; the worst error as a
/// fraction of the tolerance.
fn compare(
    what: &str,
    robot: &Robot,
    frame: &Frame,
    k: &FrameKinematics,
    eval: &dyn Fn(&[dynamics_gen::expr::ExprId]) -> Vec<f64>,
    q: &[f64],
) -> f64 {
    let pose = dynamics_reference::frame_pose(robot, frame, q);
    let j_s = dynamics_reference::frame_jacobian_space(robot, frame, q);
    let j_b = dynamics_reference::frame_jacobian_body(robot, frame, q);
    let mut worst = check(
        &format!("{what} pose"),
        &eval(&k.pose),
        &pose_entries(&pose),
    );
    worst = worst.max(check(
        &format!("{what} J_s"),
        &eval(&k.jacobian_space),
        &row_major(&j_s),
    ));
    worst.max(check(
        &format!("{what} J_b"),
        &eval(&k.jacobian_body),
        &row_major(&j_b),
    ))
}

fn check_robot(name: &str, robot: &Robot, rng: &mut Rng) -> (f64, usize) {
    let kin = expand_kinematics(robot);
    assert_eq!(kin.frames.len(), robot.frames.len());
    let mut q: Vec<f64> = (0..robot.nq()).map(|_| rng.uniform(-3.0, 3.0)).collect();
    if robot.base.floating {
        let scale = rng.uniform(0.3, 3.0);
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        for x in &mut q[3..7] {
            *x *= scale / norm;
        }
    }
    let eval = |roots: &[dynamics_gen::expr::ExprId]| {
        kin.graph.eval(roots, &|x: Input| {
            assert_eq!(x.group, Q, "kinematics read only q");
            q[x.index as usize]
        })
    };
    let mut worst = compare(
        &format!("{name} end effector"),
        robot,
        &robot.end_effector,
        &kin.end_effector,
        &eval,
        &q,
    );
    for (f, k) in robot.frames.iter().zip(&kin.frames) {
        let what = format!("{name} frame {}", f.name);
        worst = worst.max(compare(&what, robot, f, k, &eval, &q));
    }
    (worst, robot.frames.len() + 1)
}

/// A random rigid transform (a screw motion of up to ~1 rad and 0.5 m).
fn random_pose(rng: &mut Rng) -> Matrix4<f64> {
    let w = Vector6::from_fn(|_, _| rng.uniform(-1.0, 1.0));
    let t = xyz_rpy(
        [
            rng.uniform(-0.5, 0.5),
            rng.uniform(-0.5, 0.5),
            rng.uniform(-0.5, 0.5),
        ],
        [0.0; 3],
    );
    t * exp6(&w, rng.uniform(-1.0, 1.0))
}

#[test]
fn frames_of_random_trees_through_the_graph_equal_the_reference() {
    let (mut worst, mut frames, mut floating) = (0.0f64, 0, 0);
    for seed in 0..120u64 {
        let mut robot = random_tree(
            seed,
            TreeSpec {
                dof: 1 + (seed as usize * 7) % 30,
                prismatic: 0.25,
                branching: 0.3,
                floating: seed % 2 == 1,
            },
        );
        floating += usize::from(robot.base.floating);
        let mut rng = Rng::new(seed ^ 0xF2A);
        robot.frames = (0..robot.dof())
            .map(Some)
            .chain([None])
            .map(|parent| Frame {
                name: format!("f{parent:?}"),
                parent,
                home: random_pose(&mut rng),
            })
            .collect();
        robot.end_effector.home = random_pose(&mut rng);
        robot.validate().expect("valid");
        let (w, n) = check_robot(&format!("tree {seed}"), &robot, &mut rng);
        worst = worst.max(w);
        frames += n;
    }
    assert_eq!(floating, 60);
    println!("120 trees, {frames} frames: worst error {worst:.3e} of the tolerance");
}

#[test]
fn end_effector_of_the_shipped_arms_through_the_graph_equals_the_reference() {
    let mut rng = Rng::new(7);
    for name in dynamics_model::shipped::NAMES {
        let robot =
            dynamics_model::load(name, &dynamics_model::LoadOptions::default()).expect("shipped");
        let (w, _) = check_robot(name, &robot, &mut rng);
        println!("{name}: worst error {w:.3e} of the tolerance");
    }
}
