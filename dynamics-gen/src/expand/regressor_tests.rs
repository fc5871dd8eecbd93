//! The regressor ([`regressor::expand_regressor`]) against the Newton–Euler expansion:
//! `Y π + diag(a) q̈ = τ` (a the rotors' armature) on the shipped robots, ≥ 100 seeded
//! random chains (revolute and prismatic), random trees with fixed and floating bases,
//! mimic joints and armature; the base parameters reproduce τ (`Y_b π_base = Y π`) and
//! `Y_b` stacked over fresh states has full column rank; ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12.
//! (Y against Pinocchio's `computeJointTorqueRegressor`: `dynamics-tests`,
//! tests/regressor_pinocchio.rs.)

use super::regressor::{expand_regressor, random_state, Regressor};
use super::*;
use dynamics_model::random::{random_chain, random_mimics, random_tree, ChainSpec, Rng, TreeSpec};
use dynamics_model::Robot;

fn eval(g: &ExprGraph, roots: &[ExprId], q: &[f64], v: &[f64], a: &[f64], pi: &[f64]) -> Vec<f64> {
    g.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => v[i],
            QDD => a[i],
            regressor::PI => pi[i],
            _ => 0.0,
        }
    })
}

fn close(what: &str, x: &[f64], y: &[f64]) {
    let scale = y.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        x.len() == y.len() && err <= 1e-10 * scale + 1e-12,
        "{what}: differs by {err:e} (scale {scale:e})\n got  {x:?}\n want {y:?}"
    );
}

/// `Y π + diag(a) q̈ = τ` and `Y_b π_base = τ − diag(a) q̈` at three states, `π_base` from
/// the generated map equal to the stored values, and `Y_b` of full column rank.
fn check(what: &str, r: &Robot) -> Regressor {
    let y = expand_regressor(r);
    y.graph.verify().expect("graph invariants");
    let (nv, p) = (y.nv, y.n_parameters());
    assert_eq!(y.y.len(), nv * p, "{what}");
    // The rigid bodies' forces: the robot without its rotors (armature).
    let mut rigid_robot = r.clone();
    rigid_robot
        .joints
        .iter_mut()
        .for_each(|j| j.rotor_inertia = 0.0);
    let d = expand(&rigid_robot);
    let map = eval(&y.graph, &y.base_map, &[], &[], &[], &y.parameters);
    close(&format!("{what}: π_base"), &map, &y.base_values);
    let yb = y.base_y();
    let nb = y.base_columns.len();
    let mut rng = Rng::new(0xC0FFEE);
    let mut stacked = Vec::new();
    for k in 0..3 {
        let (q, v, a) = random_state(&mut rng, r);
        let rigid = eval(&d.graph, &d.inverse_dynamics, &q, &v, &a, &[]);
        let ym = eval(&y.graph, &y.y, &q, &v, &a, &[]);
        let y_pi: Vec<f64> = (0..nv)
            .map(|i| (0..p).map(|j| ym[i * p + j] * y.parameters[j]).sum())
            .collect();
        close(&format!("{what}, state {k}: Y π"), &y_pi, &rigid);
        let ybm = eval(&y.graph, &yb, &q, &v, &a, &[]);
        let yb_pi: Vec<f64> = (0..nv)
            .map(|i| (0..nb).map(|j| ybm[i * nb + j] * y.base_values[j]).sum())
            .collect();
        close(&format!("{what}, state {k}: Y_b π_base"), &yb_pi, &rigid);
        stacked.push(ybm);
    }
    // Full column rank over more fresh states.
    for _ in 0..(nb / nv.max(1) + 5) {
        let (q, v, a) = random_state(&mut rng, r);
        stacked.push(eval(&y.graph, &yb, &q, &v, &a, &[]));
    }
    let rows: Vec<f64> = stacked.concat();
    if let Some(n_rows) = rows.len().checked_div(nb) {
        let mut w = nalgebra::DMatrix::from_row_slice(n_rows, nb, &rows);
        for mut c in w.column_iter_mut() {
            let n = c.norm();
            c /= n;
        }
        let sv = w.singular_values();
        let (hi, lo) = (sv.max(), sv.min());
        assert!(
            lo > 1e-9 * hi,
            "{what}: Y_b rank deficient ({lo:e} / {hi:e})"
        );
    }
    y
}

#[test]
fn shipped_robots() {
    for name in dynamics_model::shipped::NAMES {
        let r = dynamics_model::load::load(name, &Default::default()).expect("loads");
        let y = check(name, &r);
        eprintln!(
            "{name}: {} standard parameters, {} base, {} with no effect",
            y.n_parameters(),
            y.base_columns.len(),
            y.unidentifiable.len()
        );
    }
}

/// The textbook count for a chain of revolute joints with general geometry and a fixed
/// base whose first axis is vertical (gravity along it): 7 base parameters per link after
/// the first two links' reductions (Khalil and Dombre, §12.5); a 6-joint chain with
/// general geometry has at most 10·6 − (4 per revolute joint) − … parameters. We check
/// the reduction is strict and no larger than 7 per joint.
#[test]
fn random_chains() {
    let mut prismatic = 0;
    for seed in 0..105u64 {
        let spec = ChainSpec {
            dof: 1 + (seed as usize) % 7,
            prismatic: 0.3,
        };
        let r = random_chain(seed, spec);
        prismatic += r
            .joints
            .iter()
            .filter(|j| j.kind == dynamics_model::JointKind::Prismatic)
            .count();
        let y = check(&format!("random chain {seed}"), &r);
        let n = r.dof();
        assert!(
            y.base_columns.len() <= 7 * n,
            "chain {seed}: {}",
            y.base_columns.len()
        );
    }
    assert!(prismatic > 50, "{prismatic} prismatic joints");
}

#[test]
fn trees_floating_bases_mimics_and_armature() {
    for seed in 0..16u64 {
        let spec = TreeSpec {
            dof: 1 + (seed as usize * 5) % 12,
            prismatic: 0.25,
            branching: 0.4,
            floating: seed % 2 == 1,
        };
        let tree = random_tree(seed, spec);
        check(&format!("tree {seed}"), &tree);
        let mut geared = random_mimics(tree, seed, 0.4);
        for (i, j) in geared.joints.iter_mut().enumerate() {
            if i % 2 == 0 {
                j.rotor_inertia = 1e-4 * (1 + i) as f64;
                j.gear_ratio = 50.0;
            }
        }
        check(&format!("tree {seed} with mimics and armature"), &geared);
    }
}
