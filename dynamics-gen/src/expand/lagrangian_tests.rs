//! The Lagrangian route against the Newton–Euler one, output by output, on the seed models,
//! the shipped robots, ≥ 100 seeded random chains of 1–7 joints (revolute and prismatic),
//! random trees with fixed and floating bases, mimic joints and armature: `M`, `c`, `g`, `τ`,
//! forward dynamics, `K`, `Ṁ` and `C` at random states, to ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12.
//! (The Newton–Euler expansion is itself checked against the reference implementation, the
//! exact seed cases and Pinocchio; the generated code of both routes in `dynamics-tests`.)

use super::*;
use dynamics_model::random::{random_chain, random_mimics, random_tree, ChainSpec, Rng, TreeSpec};
use dynamics_model::Robot;

fn eval(d: &Dynamics, roots: &[ExprId], s: &State) -> Vec<f64> {
    d.graph.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => s.q[i],
            QD => s.v[i],
            QDD => s.a[i],
            _ => s.tau[i],
        }
    })
}

struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    tau: Vec<f64>,
}

fn state(r: &Robot, seed: u64) -> State {
    let mut rng = Rng::new(seed ^ 0x1A6);
    let mut q: Vec<f64> = (0..r.nq()).map(|_| rng.uniform(-2.0, 2.0)).collect();
    if r.base.floating {
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= norm);
    }
    let mut draw = |n: usize| (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect::<Vec<f64>>();
    let (v, a, tau) = (draw(r.nv()), draw(r.nv()), draw(r.nv()));
    State { q, v, a, tau }
}

/// Every output of `l` equals `n`'s at three states.
fn same(what: &str, r: &Robot, l: &Dynamics, n: &Dynamics) {
    assert_eq!(l.method, Method::Lagrangian);
    assert_eq!((l.nq, l.nv, l.dof), (n.nq, n.nv, n.dof), "{what}");
    for k in 0..3u64 {
        let s = state(r, k);
        let outputs: [(&str, &[ExprId], &[ExprId]); 8] = [
            ("M", &l.mass_matrix, &n.mass_matrix),
            ("c", &l.coriolis, &n.coriolis),
            ("g", &l.gravity, &n.gravity),
            ("τ", &l.inverse_dynamics, &n.inverse_dynamics),
            ("q̈", &l.forward_dynamics, &n.forward_dynamics),
            ("K", &[l.kinetic_energy], &[n.kinetic_energy]),
            ("Ṁ", &l.mass_matrix_dot, &n.mass_matrix_dot),
            ("C", &l.coriolis_matrix, &n.coriolis_matrix),
        ];
        for (name, x, y) in outputs {
            let (x, y) = (eval(l, x, &s), eval(n, y, &s));
            let scale = y.iter().fold(0.0f64, |m, b| m.max(b.abs()));
            let err = x
                .iter()
                .zip(&y)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                x.len() == y.len() && err <= 1e-10 * scale + 1e-12,
                "{what}, state {k}: {name} differs by {err:e} (scale {scale:e})\n lagrangian {x:?}\n newton–euler {y:?}"
            );
        }
        // M reads q only (the second derivative of a quadratic form in ν), exactly symmetric.
        let mut s0 = state(r, k);
        s0.v.iter_mut().for_each(|x| *x = 0.0);
        let nv = l.nv;
        let (m, m0) = (eval(l, &l.mass_matrix, &s), eval(l, &l.mass_matrix, &s0));
        assert_eq!(m, m0, "{what}: M depends on ν");
        for i in 0..nv {
            for j in 0..nv {
                assert_eq!(m[i * nv + j], m[j * nv + i], "{what}: M not symmetric");
            }
        }
    }
}

fn check(what: &str, r: &Robot) {
    let l = expand_lagrangian(r, true);
    l.graph.verify().expect("graph invariants");
    same(what, r, &l, &expand(r));
}

#[test]
fn shipped_robots_agree_with_newton_euler() {
    for name in dynamics_model::shipped::NAMES {
        let r = dynamics_model::load::load(name, &Default::default()).expect("loads");
        check(name, &r);
    }
}

#[test]
fn random_chains_agree_with_newton_euler() {
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
        check(&format!("random chain {seed}"), &r);
    }
    assert!(prismatic > 50, "{prismatic} prismatic joints");
}

#[test]
fn trees_floating_bases_mimics_and_armature_agree_with_newton_euler() {
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

/// Exercise 8.4 as `tests/data/seed-cases.md` corrects it: `M(π/4, π/4) = [[11, √2], [√2, 6]]`.
#[test]
fn pendulum_mass_matrix_at_quarter_turns() {
    let r = dynamics_model::load::load("pendulum", &Default::default()).expect("loads");
    let l = expand_lagrangian(&r, true);
    let q = std::f64::consts::FRAC_PI_4;
    let s = State {
        q: vec![q, q],
        v: vec![0.0; 2],
        a: vec![0.0; 2],
        tau: vec![0.0; 2],
    };
    let m = eval(&l, &l.mass_matrix, &s);
    let want = [11.0, 2f64.sqrt(), 2f64.sqrt(), 6.0];
    for (x, y) in m.iter().zip(want) {
        assert!((x - y).abs() <= 1e-12 * y, "M = {m:?}");
    }
}
