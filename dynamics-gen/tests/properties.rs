//! Properties of random valid robots (proptest): chains and trees of 1–30 joints, revolute
//! and prismatic, arbitrary axes, frames and inertias, on a fixed or floating base.
//!
//! - The symbolic expansion, evaluated through the expression graph, equals the reference
//!   implementation (M, c, g, τ), relative 1e-9.
//! - M is symmetric positive definite.
//! - Forward dynamics inverts inverse dynamics: `M (FD(ID(q̈)) − q̈) ≈ 0`, relative 1e-9
//!   (the residual, so that the check does not depend on M's conditioning).
//! - Energy balance: the power of the velocity-product forces is the rate of change of the
//!   kinetic energy they cause, `q̇ᵀ c(q, q̇) = ½ q̇ᵀ Ṁ(q, q̇) q̇` (Ṁ from the reference).
//! - Generation is deterministic: the same robot gives byte-identical files.
//!
//! A failing case is kept in `properties.proptest-regressions` beside this file (commit it)
//! and replayed first on every run.

use dynamics_gen::expand::{expand, Q, QD, QDD, TAU};
use dynamics_gen::expr::{ExprGraph, ExprId, Input};
use dynamics_gen::{generate_file, Options};
use dynamics_model::random::{random_tree, Rng, TreeSpec};
use dynamics_model::Robot;
use nalgebra::{DMatrix, DVector, Vector6};
use proptest::prelude::*;

/// A random valid robot: (seed, dof, prismatic share, branching, floating base).
fn robots(max_dof: usize) -> impl Strategy<Value = Robot> {
    (
        any::<u64>(),
        1..=max_dof,
        0.0..0.5f64,
        prop_oneof![Just(0.0), 0.0..0.6f64],
        any::<bool>(),
    )
        .prop_map(|(seed, dof, prismatic, branching, floating)| {
            random_tree(
                seed,
                TreeSpec {
                    dof,
                    prismatic,
                    branching,
                    floating,
                },
            )
        })
}

fn eval(graph: &ExprGraph, roots: &[ExprId], state: [&[f64]; 4]) -> Vec<f64> {
    let [q, qd, qdd, tau] = state;
    graph.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => qd[i],
            QDD => qdd[i],
            TAU => tau[i],
            _ => f64::NAN,
        }
    })
}

fn close(what: &str, x: &[f64], y: &[f64], rel: f64) -> Result<(), TestCaseError> {
    prop_assert_eq!(x.len(), y.len());
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    prop_assert!(
        err <= rel * scale + 1e-12,
        "{}: error {:e}, scale {:e}",
        what,
        err,
        scale
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn expansion_equals_reference_and_respects_the_physics(robot in robots(30), state in any::<u64>()) {
        let (nq, nv) = (robot.nq(), robot.nv());
        let d = expand(&robot);
        let mut rng = Rng::new(state);
        let q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let qdd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let g = robot.gravity;
        let z = Vector6::zeros();
        let tau = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &z);
        let at = |roots: &[ExprId]| eval(&d.graph, roots, [&q, &qd, &qdd, tau.as_slice()]);

        // Graph = reference.
        let m_ref = dynamics_reference::mass_matrix(&robot, &q);
        let m_rows: Vec<f64> = m_ref.transpose().as_slice().to_vec();
        let m = at(&d.mass_matrix);
        close("M", &m, &m_rows, 1e-9)?;
        let c = at(&d.coriolis);
        close("c", &c, dynamics_reference::vel_quadratic_forces(&robot, &q, &qd).as_slice(), 1e-9)?;
        let grav = at(&d.gravity);
        close("g", &grav, dynamics_reference::gravity_forces(&robot, &q, &g).as_slice(), 1e-9)?;
        close("τ", &at(&d.inverse_dynamics), tau.as_slice(), 1e-9)?;

        // M symmetric positive definite.
        let m = DMatrix::from_row_slice(nv, nv, &m);
        close("M − Mᵀ", m.as_slice(), m.transpose().as_slice(), 1e-12)?;
        prop_assert!(m.clone().cholesky().is_some(), "M is not positive definite");

        // FD(ID(q̈)) = q̈, as a residual in torque units.
        let fd = DVector::from_vec(at(&d.forward_dynamics));
        let residual = &m * (fd - DVector::from_column_slice(&qdd));
        let scale = tau.amax() + (&m * DVector::from_column_slice(&qdd)).amax();
        prop_assert!(
            residual.amax() <= 1e-9 * scale + 1e-12,
            "M (FD(ID(q̈)) − q̈) = {:e}, scale {:e}",
            residual.amax(),
            scale
        );

        // Energy balance of the velocity-product forces.
        let qd_v = DVector::from_column_slice(&qd);
        let m_dot = dynamics_reference::mass_matrix_dot(&robot, &q, &qd);
        let power = qd_v.dot(&DVector::from_vec(c));
        let rate = 0.5 * qd_v.dot(&(&m_dot * &qd_v));
        let scale = m_dot.amax() * qd_v.amax() * qd_v.amax() * nv as f64;
        prop_assert!(
            (power - rate).abs() <= 1e-9 * scale + 1e-12,
            "q̇ᵀc = {:e} but ½q̇ᵀṀq̇ = {:e}",
            power,
            rate
        );
    }

    #[test]
    fn generation_is_byte_identical(robot in robots(6)) {
        let options = Options {
            functions: Some(vec![
                "inverse_dynamics".into(),
                "mass_matrix".into(),
                "forward_dynamics".into(),
                "inertial_parameters".into(),
            ]),
            ..Options::default()
        };
        let a = generate_file(&robot, &options, "random.toml");
        let b = generate_file(&robot.clone(), &options, "random.toml");
        match (a, b) {
            (Ok(a), Ok(b)) => prop_assert!(a == b, "two generations differ"),
            (Err(a), Err(b)) => prop_assert_eq!(a.to_string(), b.to_string()),
            (a, b) => prop_assert!(false, "one generation failed: {:?} / {:?}", a.err(), b.err()),
        }
    }
}

/// A random URDF tree: per joint, (parent link, type, xyz, rpy, axis, mass, principal moments).
type UrdfJoint = (usize, u8, [f64; 3], [f64; 3], [f64; 3], f64, [f64; 3]);

fn urdf_joints() -> impl Strategy<Value = Vec<UrdfJoint>> {
    prop::collection::vec(
        (
            any::<usize>(),
            0u8..3,
            [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64],
            [-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64],
            [-1.0..1.0f64, -1.0..1.0f64, 0.2..1.0f64],
            0.1..5.0f64,
            // Moments in [0.05, 0.1] always meet the triangle inequality.
            [0.05..0.1f64, 0.05..0.1f64, 0.05..0.1f64],
        ),
        1..8,
    )
}

/// The URDF of `joints` with its links and joints written in the orders given.
fn urdf_text(joints: &[UrdfJoint], link_order: &[usize], joint_order: &[usize]) -> String {
    let v = |a: &[f64; 3]| format!("{} {} {}", a[0], a[1], a[2]);
    let link = |i: usize| -> String {
        if i == 0 {
            return "  <link name=\"base\"/>\n".into();
        }
        let (.., mass, moments) = &joints[i - 1];
        format!(
            "  <link name=\"link{i}\"><inertial><origin xyz=\"0.01 0.02 0.03\" rpy=\"0.1 0.2 0.3\"/><mass value=\"{mass}\"/><inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/></inertial></link>\n",
            moments[0], moments[1], moments[2]
        )
    };
    let joint = |i: usize| -> String {
        let (parent, kind, xyz, rpy, axis, ..) = &joints[i];
        let kind = ["revolute", "continuous", "prismatic"][*kind as usize];
        let limit = if kind == "continuous" {
            ""
        } else {
            "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/>"
        };
        format!(
            "  <joint name=\"joint{}\" type=\"{kind}\"><parent link=\"{}\"/><child link=\"link{}\"/><origin xyz=\"{}\" rpy=\"{}\"/><axis xyz=\"{}\"/>{limit}</joint>\n",
            i + 1,
            if parent % (i + 1) == 0 { "base".to_string() } else { format!("link{}", parent % (i + 1)) },
            i + 1,
            v(xyz),
            v(rpy),
            v(axis)
        )
    };
    let mut text = String::from("<?xml version=\"1.0\"?>\n<robot name=\"random\">\n");
    link_order.iter().for_each(|&i| text += &link(i));
    joint_order.iter().for_each(|&i| text += &joint(i));
    text + "</robot>\n"
}

/// A permutation of `0..n` from sort keys.
fn permutation(keys: &[u64], n: usize) -> Vec<usize> {
    let mut p: Vec<usize> = (0..n).collect();
    p.sort_by_key(|&i| (keys.get(i).copied().unwrap_or(0), i));
    p
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Links may come in any order; joints in any order that keeps the order of joints
    /// sharing a parent (siblings are numbered in file order, as in urdfdom and Pinocchio).
    /// The robot and its generated file do not change.
    #[test]
    fn urdf_element_order_changes_nothing(
        joints in urdf_joints(),
        link_keys in prop::collection::vec(any::<u64>(), 9),
        joint_keys in prop::collection::vec(any::<u64>(), 8),
    ) {
        let n = joints.len();
        let parent = |i: usize| joints[i].0 % (i + 1);
        let in_order: Vec<usize> = (0..n).collect();
        let links_in_order: Vec<usize> = (0..=n).collect();
        // Shuffle, then put each parent's joints back in their own relative order.
        let shuffled = permutation(&joint_keys, n);
        let mut joint_order = shuffled.clone();
        for p in 0..=n {
            let slots: Vec<usize> = (0..n).filter(|&k| parent(shuffled[k]) == p).collect();
            let mut own: Vec<usize> = (0..n).filter(|&i| parent(i) == p).collect();
            own.sort();
            for (slot, i) in slots.into_iter().zip(own) {
                joint_order[slot] = i;
            }
        }
        let a = urdf_text(&joints, &links_in_order, &in_order);
        let b = urdf_text(&joints, &permutation(&link_keys, n + 1), &joint_order);
        let load = |text: &str| dynamics_model::load::from_str(
            text,
            dynamics_model::Format::Urdf,
            "random.urdf",
            &dynamics_model::LoadOptions::default(),
        );
        let (ra, rb) = (load(&a), load(&b));
        match (&ra, &rb) {
            (Ok(ra), Ok(rb)) => {
                prop_assert!(ra == rb, "the robots differ:\n{}\n{}", a, b);
                let options = Options {
                    functions: Some(vec!["inverse_dynamics".into(), "frame_poses".into()]),
                    ..Options::default()
                };
                let ga = generate_file(ra, &options, "random.urdf").map_err(|e| e.to_string());
                let gb = generate_file(rb, &options, "random.urdf").map_err(|e| e.to_string());
                prop_assert!(ga == gb, "the generated files differ");
            }
            (Err(ea), Err(eb)) => prop_assert_eq!(ea.to_string(), eb.to_string()),
            _ => prop_assert!(false, "one order loads, the other not: {:?} / {:?}", ra.err(), rb.err()),
        }
    }
}
