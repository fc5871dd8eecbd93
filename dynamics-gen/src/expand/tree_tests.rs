//! The expansion on kinematic trees and floating bases, checked for internal consistency on
//! seeded random trees: `τ = M ν̇ + c + g` (Newton–Euler against CRBA), both forward-dynamics
//! routes invert inverse dynamics, structural zeros of `M` are exact zeros of the graph,
//! and a floating base's quaternion is normalised. (Agreement with the independent
//! reference implementation and with Pinocchio is checked in the `dynamics-tests` crate.)

use super::*;
use dynamics_model::random::{random_tree, Rng, TreeSpec};

fn eval(d: &Dynamics, roots: &[ExprId], q: &[f64], v: &[f64], a: &[f64], tau: &[f64]) -> Vec<f64> {
    d.graph.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => v[i],
            QDD => a[i],
            _ => tau[i],
        }
    })
}

fn max_err(x: &[f64], y: &[f64]) -> f64 {
    x.iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, a| m.max(a.abs()))
}

fn spec(seed: u64) -> TreeSpec {
    TreeSpec {
        dof: 1 + (seed as usize * 7) % 16,
        prismatic: 0.25,
        branching: 0.4,
        floating: seed % 2 == 1,
    }
}

/// A random state: q (unit quaternion scaled by `quat_scale` on a floating base), ν, ν̇.
fn state(r: &dynamics_model::Robot, seed: u64, quat_scale: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed ^ 0xABCD);
    let mut q: Vec<f64> = (0..r.nq()).map(|_| rng.uniform(-2.0, 2.0)).collect();
    if r.base.floating {
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        for x in &mut q[3..7] {
            *x *= quat_scale / norm;
        }
    }
    let v = (0..r.nv()).map(|_| rng.uniform(-1.5, 1.5)).collect();
    let a = (0..r.nv()).map(|_| rng.uniform(-1.5, 1.5)).collect();
    (q, v, a)
}

/// `J̇_s`, `J̇_b` as the expansion keeps them (by the twists the columns move with, where
/// cheaper) equal the directional derivatives of `J_s`, `J_b` along the configuration rate,
/// on trees, floating bases and prismatic joints.
#[test]
fn jacobian_rates_equal_the_derivatives_of_the_jacobians() {
    for seed in 0..24u64 {
        let r = random_tree(seed, spec(seed));
        let (q, v, _) = state(&r, seed, 1.0);
        let k = kinematics::expand_kinematics(&r);
        let mut g = k.graph.clone();
        let rate = base::configuration_rate(&mut g, r.base.floating, r.n_coordinates());
        let jvp_s = g.jvp(&k.end_effector.jacobian_space, &rate);
        let jvp_b = g.jvp(&k.end_effector.jacobian_body, &rate);
        let at = |roots: &[ExprId]| {
            g.eval(roots, &|x: Input| match x.group {
                Q => q[x.index as usize],
                _ => v[x.index as usize],
            })
        };
        for (what, kept, derivative) in [
            ("J̇_s", &k.jacobian_space_dot, &jvp_s),
            ("J̇_b", &k.jacobian_body_dot, &jvp_b),
        ] {
            let (a, b) = (at(kept), at(derivative));
            let scale = max_abs(&b) + 1.0;
            assert!(
                max_err(&a, &b) <= 1e-12 * scale,
                "seed {seed} {what}: off by {:e}",
                max_err(&a, &b)
            );
        }
    }
}

/// The kinetic energy the expansion keeps (the bodies' twists where that is cheaper) is
/// `½ νᵀ M ν`, on trees, floating bases and prismatic joints.
#[test]
fn kinetic_energy_is_half_v_m_v() {
    for seed in 0..24u64 {
        let r = random_tree(seed, spec(seed));
        let nv = r.nv();
        let (q, v, a) = state(&r, seed, 1.0);
        let zeros = vec![0.0; nv];
        let d = expand_with_route(&r, ForwardRoute::Ldlt);
        let m = eval(&d, &d.mass_matrix, &q, &v, &a, &zeros);
        let k = eval(&d, &[d.kinetic_energy], &q, &v, &a, &zeros)[0];
        let expected = 0.5
            * (0..nv)
                .map(|i| v[i] * (0..nv).map(|j| m[i * nv + j] * v[j]).sum::<f64>())
                .sum::<f64>();
        assert!(
            (k - expected).abs() <= 1e-12 * (expected.abs() + 1.0),
            "seed {seed}: K = {k}, ½ νᵀ M ν = {expected}"
        );
    }
}

#[test]
fn trees_are_consistent_on_both_routes() {
    for seed in 0..24u64 {
        let r = random_tree(seed, spec(seed));
        assert!(r.validate().is_ok());
        let nv = r.nv();
        let (q, v, a) = state(&r, seed, 1.0);
        let zeros = vec![0.0; nv];
        for route in [ForwardRoute::Ldlt, ForwardRoute::Aba] {
            let d = expand_with_route(&r, route);
            assert_eq!((d.nq, d.nv), (r.nq(), nv));
            let m = eval(&d, &d.mass_matrix, &q, &v, &a, &zeros);
            let c = eval(&d, &d.coriolis, &q, &v, &a, &zeros);
            let gr = eval(&d, &d.gravity, &q, &v, &a, &zeros);
            let tau = eval(&d, &d.inverse_dynamics, &q, &v, &a, &zeros);
            let expected: Vec<f64> = (0..nv)
                .map(|i| (0..nv).map(|j| m[i * nv + j] * a[j]).sum::<f64>() + c[i] + gr[i])
                .collect();
            let scale = max_abs(&tau) + 1.0;
            assert!(
                max_err(&tau, &expected) < 1e-10 * scale,
                "seed {seed} {route:?}: τ ≠ M a + c + g by {:e}",
                max_err(&tau, &expected)
            );
            for i in 0..nv {
                for j in 0..nv {
                    assert_eq!(m[i * nv + j], m[j * nv + i], "seed {seed}: M not symmetric");
                }
            }
            let back = eval(&d, &d.forward_dynamics, &q, &v, &zeros, &tau);
            assert!(
                max_err(&back, &a) < 1e-8 * (max_abs(&a) + 1.0),
                "seed {seed} {route:?}: forward(inverse(a)) ≠ a by {:e}",
                max_err(&back, &a)
            );
        }
    }
}

#[test]
fn entries_between_branches_are_never_built() {
    for seed in 0..24u64 {
        let r = random_tree(seed, spec(seed));
        let d = expand(&r);
        let (n, nv) = (r.dof(), r.nv());
        let off = nv - n;
        let mut zeros = 0;
        for i in 0..n {
            for j in 0..n {
                let related = r.path_to(i).contains(&j) || r.path_to(j).contains(&i);
                let id = d.mass_matrix[(off + i) * nv + off + j];
                if !related {
                    assert!(d.graph.is_zero(id), "seed {seed}: M[{i}][{j}] is built");
                    zeros += 1;
                }
            }
        }
        if !r.is_serial() {
            assert!(
                zeros > 0 || n < 3,
                "seed {seed}: a branched tree without zeros"
            );
        }
    }
}

#[test]
fn the_quaternion_is_normalised() {
    for seed in (1..24u64).step_by(2) {
        let r = random_tree(seed, spec(seed));
        assert!(r.base.floating);
        let d = expand(&r);
        let nv = r.nv();
        let (q, v, a) = state(&r, seed, 1.0);
        let (q2, _, _) = state(&r, seed, 3.7);
        let tau: Vec<f64> = (0..nv).map(|i| i as f64 - 2.0).collect();
        for roots in [&d.gravity, &d.inverse_dynamics, &d.forward_dynamics] {
            let x = eval(&d, roots, &q, &v, &a, &tau);
            let y = eval(&d, roots, &q2, &v, &a, &tau);
            assert!(max_err(&x, &y) < 1e-10 * (max_abs(&x) + 1.0), "seed {seed}");
        }
    }
}

/// A floating tree with a 15-body branch: the rounding bound that decides which sums are
/// zero over-estimates its articulated-body algorithm's errors so much that the default
/// tolerance pruned genuinely non-zero sums (ν̇ of a whole branch came out 0). The checked
/// pruning must keep every route exact.
#[test]
fn pruning_is_checked_on_a_deep_tree() {
    let spec = TreeSpec {
        dof: 31,
        prismatic: 0.25,
        branching: 0.3,
        floating: true,
    };
    let r = random_tree(3, spec);
    let nv = r.nv();
    let (q, v, a) = state(&r, 3, 1.0);
    let zeros = vec![0.0; nv];
    for route in [ForwardRoute::Ldlt, ForwardRoute::Aba] {
        let d = expand_with_route(&r, route);
        let tau = eval(&d, &d.inverse_dynamics, &q, &v, &a, &zeros);
        let back = eval(&d, &d.forward_dynamics, &q, &v, &zeros, &tau);
        assert!(
            max_err(&back, &a) < 1e-9,
            "{route:?}: {:e}",
            max_err(&back, &a)
        );
    }
}

/// Every Newton–Euler form (the link wrench spatial or classical; classical accelerations
/// with cross products or through the tensor `W`) gives the same forces, on trees, floating
/// bases and prismatic joints, with gravity and a wrench at the end effector.
#[test]
fn every_newton_euler_form_gives_the_same_forces() {
    use rnea::LinkForce;
    use rnea_classical::Euler;
    for seed in 0..24u64 {
        let r = random_tree(seed, spec(seed));
        let (q, v, a) = state(&r, seed, 1.0);
        let mut rng = Rng::new(seed ^ 0x5EED);
        let wrench: Vec<f64> = (0..6).map(|_| rng.uniform(-5.0, 5.0)).collect();
        let Inputs {
            frames,
            coupling,
            ov,
            mut g,
            x,
            xd,
            xdd,
            ..
        } = Inputs::new(&r);
        let qs = coupling.positions(&mut g, &x);
        let (qd, qdd) = (coupling.rates(&mut g, &xd), coupling.rates(&mut g, &xdd));
        let motions = joint_motions(&mut g, &frames, &qs);
        let gravity = parameters::gravity(&mut g, &frames);
        let floating = frames.base.is_some();
        let base = base::base_motion(&mut g, floating, &qd[..ov], &qdd[..ov], gravity);
        let tip = tip_wrench(&mut g, &r, &frames);
        let bi = frames.base.as_ref();
        let (v_j, a_j) = (&qd[ov..], &qdd[ov..]);
        let tip = Some(&tip);
        let mut forms: Vec<Vec<ExprId>> = [LinkForce::Spatial, LinkForce::Classical]
            .map(|f| rnea::rnea(&mut g, &motions, &base, bi, v_j, a_j, f, tip))
            .into();
        forms.extend([Euler::Vector, Euler::Tensor].map(|e| {
            rnea_classical::rnea_classical(&mut g, &motions, &base, bi, v_j, a_j, tip, e)
        }));
        let at = |roots: &[ExprId]| {
            g.eval(roots, &|x: Input| {
                let i = x.index as usize;
                match x.group {
                    Q => q[i],
                    QD => v[i],
                    QDD => a[i],
                    _ => wrench[i],
                }
            })
        };
        let want = at(&forms[0]);
        let scale = max_abs(&want) + 1.0;
        for (k, form) in forms.iter().enumerate().skip(1) {
            let got = at(form);
            assert!(
                max_err(&got, &want) <= 1e-12 * scale,
                "seed {seed}, form {k}: off by {:e} (scale {scale:e})",
                max_err(&got, &want)
            );
        }
    }
}
