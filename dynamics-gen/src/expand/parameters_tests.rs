//! Run-time parameters ([`super::parameters`]) on the expression graph: with their default
//! values every output equals the folded expansion of the same robot, and with another
//! gravity and a payload it equals the folded expansion of the changed robot (the payload's
//! spatial inertia added to its link's, numerically, in the model). The outputs: `M`, `c`,
//! `g`, `τ`, forward dynamics, `K`, `Ṁ`, `C`, the bias, `P`, the derivatives of τ and q̈, the
//! regressor `Y` and `inertial_parameters`; both derivation methods; chains with prismatic
//! joints, the shipped robots, fixed and floating trees, mimic joints and armature. Tolerance
//! ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12. (The folded expansion is itself checked against the
//! reference implementation and Pinocchio; the generated code with run-time parameters in
//! `dynamics-tests`.)

use super::derivatives::expand_derivatives;
use super::kinematics::expand_kinematics;
use super::parameters::{PARAM, PAYLOAD_COM, PAYLOAD_INERTIA, PAYLOAD_MASS};
use super::regressor::expand_regressor;
use super::*;
use crate::expr::ExprGraph;
use dynamics_model::random::{random_chain, random_mimics, random_tree, ChainSpec, Rng, TreeSpec};
use dynamics_model::Robot;
use nalgebra::{Matrix3, Vector3};

/// A payload and a gravity vector: the 13 parameter values.
fn changed(seed: u64) -> [f64; 13] {
    let mut rng = Rng::new(seed ^ 0x9A7);
    let mut v = [0.0; 13];
    for x in &mut v[..3] {
        *x = rng.uniform(-10.0, 10.0);
    }
    v[PAYLOAD_MASS as usize] = rng.uniform(0.5, 3.0);
    for x in &mut v[PAYLOAD_COM as usize..PAYLOAD_INERTIA as usize] {
        *x = rng.uniform(-0.3, 0.3);
    }
    // A physical inertia about the centre of mass: A Aᵀ + 0.01·1.
    let a = Matrix3::from_fn(|_, _| rng.uniform(-0.2, 0.2));
    let i = a * a.transpose() + Matrix3::identity() * 0.01;
    let k = PAYLOAD_INERTIA as usize;
    v[k..k + 6].copy_from_slice(&[
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)],
    ]);
    v
}

/// `robot` with the payload and gravity of `values` folded into the model.
fn folded(robot: &Robot, link: usize, values: &[f64; 13]) -> Robot {
    let at = |k: u16| values[k as usize];
    let mut r = robot.with_payload(
        link,
        at(PAYLOAD_MASS),
        [0, 1, 2].map(|j| at(PAYLOAD_COM + j)),
        [0, 1, 2, 3, 4, 5].map(|j| at(PAYLOAD_INERTIA + j)),
    );
    r.runtime = Default::default();
    r.gravity = Vector3::new(values[0], values[1], values[2]);
    r
}

struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    tau: Vec<f64>,
}

fn state(r: &Robot, seed: u64) -> State {
    let mut rng = Rng::new(seed ^ 0x7A7);
    let mut q: Vec<f64> = (0..r.nq()).map(|_| rng.uniform(-2.0, 2.0)).collect();
    if r.base.floating {
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= norm);
    }
    let mut draw = |n: usize| (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect::<Vec<f64>>();
    let (v, a, tau) = (draw(r.nv()), draw(r.nv()), draw(r.nv()));
    State { q, v, a, tau }
}

fn eval(g: &ExprGraph, roots: &[ExprId], s: &State, params: &[f64; 13]) -> Vec<f64> {
    g.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => s.q[i],
            QD => s.v[i],
            QDD => s.a[i],
            TAU => s.tau[i],
            PARAM => params[i],
            other => panic!("unexpected input group {other}"),
        }
    })
}

/// The outputs compared, each as (name, graph, roots).
fn outputs(r: &Robot, method: Method) -> Vec<(String, ExprGraph, Vec<ExprId>)> {
    let d = expand_method(r, method);
    let mut out = Vec::new();
    let dynamics: [(&str, &[ExprId]); 9] = [
        ("M", &d.mass_matrix),
        ("c", &d.coriolis),
        ("g", &d.gravity),
        ("τ", &d.inverse_dynamics),
        ("q̈", &d.forward_dynamics),
        ("K", &[d.kinetic_energy]),
        ("Ṁ", &d.mass_matrix_dot),
        ("C", &d.coriolis_matrix),
        ("h", &d.bias),
    ];
    for (name, roots) in dynamics {
        out.push((name.to_string(), d.graph.clone(), roots.to_vec()));
    }
    let k = expand_kinematics(r);
    out.push(("P".into(), k.graph.clone(), vec![k.potential_energy]));
    let x = expand_derivatives(&d, r);
    let derivatives: [(&str, &[ExprId]); 5] = [
        ("∂τ/∂q", &x.d_tau_dq),
        ("∂τ/∂q̇", &x.d_tau_dqd),
        ("∂g/∂q", &x.gravity_derivative),
        ("∂q̈/∂q", &x.d_qdd_dq),
        ("∂q̈/∂q̇", &x.d_qdd_dqd),
    ];
    for (name, roots) in derivatives {
        out.push((name.to_string(), x.graph.clone(), roots.to_vec()));
    }
    let y = expand_regressor(r);
    out.push(("Y".into(), y.graph.clone(), y.y.clone()));
    out.push(("π".into(), y.graph.clone(), y.parameter_nodes.clone()));
    out
}

fn assert_same(what: &str, x: &[f64], y: &[f64]) {
    let scale = y.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        x.len() == y.len() && err <= 1e-10 * scale + 1e-12,
        "{what} differs by {err:e} (scale {scale:e})\n run-time {x:?}\n folded   {y:?}"
    );
}

/// With run-time parameters on the link `link` of `robot`: defaults = folded, and a changed
/// payload and gravity = the folded changed robot, at two states each.
fn check(what: &str, robot: &Robot, link: usize, method: Method) {
    let mut rt = robot.clone();
    rt.runtime = dynamics_model::RuntimeParameters {
        gravity: true,
        payload: Some(link),
    };
    let defaults = parameters::defaults(&rt);
    let values = changed(link as u64 + robot.dof() as u64);
    let ours = outputs(&rt, method);
    for (params, reference) in [
        (defaults, outputs(robot, method)),
        (values, outputs(&folded(robot, link, &values), method)),
    ] {
        for ((name, g, roots), (_, g_ref, roots_ref)) in ours.iter().zip(&reference) {
            for k in 0..2u64 {
                let s = state(robot, k);
                let x = eval(g, roots, &s, &params);
                let y = eval(g_ref, roots_ref, &s, &defaults);
                let label = if params == defaults {
                    "defaults"
                } else {
                    "changed"
                };
                assert_same(
                    &format!("{what} ({method:?}), {label}, state {k}: {name}"),
                    &x,
                    &y,
                );
            }
        }
    }
}

#[test]
fn shipped_robots_with_a_payload_on_the_tip() {
    for name in dynamics_model::shipped::NAMES {
        let r = dynamics_model::load::load(name, &Default::default()).expect("loads");
        let tip = r
            .end_effector
            .parent
            .expect("a link carries the end effector");
        check(name, &r, tip, Method::NewtonEuler);
    }
    let ur5 = dynamics_model::load::load("ur5", &Default::default()).expect("loads");
    check("ur5", &ur5, 5, Method::Lagrangian);
    // A payload on a link in the middle of the chain.
    check("ur5, link 2", &ur5, 2, Method::NewtonEuler);
}

#[test]
fn random_chains_with_prismatic_joints() {
    for seed in 0..12u64 {
        let spec = ChainSpec {
            dof: 1 + (seed as usize) % 7,
            prismatic: 0.4,
        };
        let r = random_chain(seed + 500, spec);
        let link = (seed as usize * 3) % r.dof();
        let method = if seed % 3 == 0 {
            Method::Lagrangian
        } else {
            Method::NewtonEuler
        };
        check(&format!("random chain {seed}"), &r, link, method);
    }
}

#[test]
fn trees_floating_bases_mimics_and_armature() {
    for seed in 0..6u64 {
        let spec = TreeSpec {
            dof: 2 + (seed as usize * 5) % 9,
            prismatic: 0.25,
            branching: 0.4,
            floating: seed % 2 == 1,
        };
        let tree = random_tree(seed + 600, spec);
        let link = tree.dof() - 1 - (seed as usize) % tree.dof();
        check(&format!("tree {seed}"), &tree, link, Method::NewtonEuler);
        let mut geared = random_mimics(tree, seed, 0.4);
        for (i, j) in geared.joints.iter_mut().enumerate() {
            if i % 2 == 0 {
                j.rotor_inertia = 1e-4 * (1 + i) as f64;
                j.gear_ratio = 50.0;
            }
        }
        check(
            &format!("tree {seed} with mimics and armature"),
            &geared,
            link,
            Method::NewtonEuler,
        );
    }
}
