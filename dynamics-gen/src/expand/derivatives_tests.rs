//! [`derivatives`] checked on seeded random trees and chains (fixed and floating, revolute
//! and prismatic) against central differences of the dynamics graph, the configuration
//! perturbed along the tangent space on a floating base.

use super::derivatives::{
    analytical, expand_derivatives, partials, tangent_jacobian, tangent_seeds, Derivatives,
};
use super::rnea_derivatives::PairFrame;
use super::*;
use dynamics_model::random::{random_chain, random_mimics, random_tree, ChainSpec, Rng, TreeSpec};
use dynamics_model::Robot;

/// Central-difference step.
const H: f64 = 1e-6;

fn eval_at(
    g: &ExprGraph,
    roots: &[ExprId],
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tau: &[f64],
) -> Vec<f64> {
    g.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => v[i],
            QDD => a[i],
            TAU => tau[i],
            _ => panic!("unexpected input {x}"),
        }
    })
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, a| m.max(a.abs()))
}

/// The robots: 30 seeds, trees and chains, fixed and floating, a quarter prismatic; seeds
/// 30.. with mimic joints.
fn robot(seed: u64) -> Robot {
    let dof = 1 + (seed as usize * 5) % 9;
    if seed >= 30 {
        let spec = TreeSpec {
            dof: dof + 2,
            prismatic: 0.25,
            branching: 0.4,
            floating: seed % 2 == 1,
        };
        random_mimics(random_tree(seed, spec), seed, 0.4)
    } else if seed % 5 == 4 {
        random_chain(
            seed,
            ChainSpec {
                dof,
                prismatic: 0.25,
            },
        )
    } else {
        random_tree(
            seed,
            TreeSpec {
                dof,
                prismatic: 0.25,
                branching: 0.4,
                floating: seed % 2 == 1,
            },
        )
    }
}

/// q, ν, ν̇, τ; the quaternion scaled to length `quat_scale` (the dynamics normalise it).
fn state(r: &Robot, seed: u64, quat_scale: f64) -> [Vec<f64>; 4] {
    let mut rng = Rng::new(seed ^ 0xD1FF);
    let mut q: Vec<f64> = (0..r.nq()).map(|_| rng.uniform(-2.0, 2.0)).collect();
    if r.base.floating {
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        for x in &mut q[3..7] {
            *x *= quat_scale / norm;
        }
    }
    let mut vec = || {
        (0..r.nv())
            .map(|_| rng.uniform(-1.5, 1.5))
            .collect::<Vec<f64>>()
    };
    [q, vec(), vec(), vec()]
}

/// `a ⊗ b` for quaternions `(x, y, z, w)`.
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + bw * ax + ay * bz - az * by,
        aw * by + bw * ay + az * bx - ax * bz,
        aw * bz + bw * az + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// `q ⊕ t e_j` (tangent direction j of nv): the configuration moved by `t` along tangent direction `j` (on a floating
/// base `ω_b = e_j` turns the quaternion by `exp(½ t e_j)` on the right, `v_b = e_{j−3}`
/// moves `p` by `t R e_{j−3}`).
fn retract(q: &[f64], floating: bool, j: usize, t: f64) -> Vec<f64> {
    let mut q = q.to_vec();
    if !floating {
        q[j] += t;
        return q;
    }
    let u = [q[3], q[4], q[5], q[6]];
    if j < 3 {
        let mut e = [0.0, 0.0, 0.0, (t / 2.0).cos()];
        e[j] = (t / 2.0).sin();
        q[3..7].copy_from_slice(&quat_mul(u, e));
    } else if j < 6 {
        // R e_c = the rotation of e_c by quat/|quat|: u ⊗ (e_c, 0) ⊗ u* / |u|².
        let mut e = [0.0; 4];
        e[j - 3] = 1.0;
        let conj = [-u[0], -u[1], -u[2], u[3]];
        let r = quat_mul(quat_mul(u, e), conj);
        let s: f64 = u.iter().map(|x| x * x).sum();
        for i in 0..3 {
            q[i] += t * r[i] / s;
        }
    } else {
        q[j + 1] += t;
    }
    q
}

/// Asserts `got` ≈ `want` entry by entry, relative to `want`'s largest entry (+1); returns
/// the largest relative error.
fn assert_close(what: &str, seed: u64, got: &[f64], want: &[f64], tol: f64) -> f64 {
    let scale = max_abs(want) + 1.0;
    let mut worst = 0.0f64;
    for (k, (x, y)) in got.iter().zip(want).enumerate() {
        assert!(
            (x - y).abs() <= tol * scale,
            "seed {seed} {what}[{k}]: {x} vs {y} (scale {scale})"
        );
        worst = worst.max((x - y).abs() / scale);
    }
    worst
}

/// Central differences of `roots` (length nv) along the nv tangent directions of q or along
/// ν, as an nv×nv row-major matrix.
fn central(
    d: &Dynamics,
    roots: &[ExprId],
    s: &[Vec<f64>; 4],
    floating: bool,
    along_v: bool,
) -> Vec<f64> {
    let nv = d.nv;
    let [q, v, a, tau] = s;
    let mut out = vec![0.0; nv * nv];
    for j in 0..nv {
        let f = |t: f64| {
            if along_v {
                let mut v = v.clone();
                v[j] += t;
                eval_at(&d.graph, roots, q, &v, a, tau)
            } else {
                eval_at(&d.graph, roots, &retract(q, floating, j, t), v, a, tau)
            }
        };
        let (p, m) = (f(H), f(-H));
        for i in 0..nv {
            out[i * nv + j] = (p[i] - m[i]) / (2.0 * H);
        }
    }
    out
}

#[test]
fn derivatives_match_central_differences() {
    let (mut worst, mut mimics) = (0.0f64, 0);
    for seed in 0..36u64 {
        let r = robot(seed);
        mimics += r.dof() - r.n_coordinates();
        let floating = r.base.floating;
        // Both forward-dynamics routes feed ν̇ := FD.
        let d = if seed % 3 == 0 {
            expand_with_route(&r, ForwardRoute::Aba)
        } else {
            expand(&r)
        };
        let x = expand_derivatives(&d, &r);
        x.graph.verify().unwrap();
        let nv = d.nv;
        assert_eq!(x.nv, nv);
        let s = state(&r, seed, if seed % 4 == 3 { 1.7 } else { 1.0 });
        let ev = |roots: &[ExprId]| eval_at(&x.graph, roots, &s[0], &s[1], &s[2], &s[3]);
        let tol = 1e-6;
        let id = &d.inverse_dynamics;
        let fd = &d.forward_dynamics;
        worst = worst.max(assert_close(
            "∂τ/∂q",
            seed,
            &ev(&x.d_tau_dq),
            &central(&d, id, &s, floating, false),
            tol,
        ));
        worst = worst.max(assert_close(
            "∂τ/∂ν",
            seed,
            &ev(&x.d_tau_dqd),
            &central(&d, id, &s, floating, true),
            tol,
        ));
        let dg = central(&d, &d.gravity, &s, floating, false);
        worst = worst.max(assert_close(
            "∂g/∂q",
            seed,
            &ev(&x.gravity_derivative),
            &dg,
            tol,
        ));
        worst = worst.max(assert_close(
            "∂ν̇/∂q",
            seed,
            &ev(&x.d_qdd_dq),
            &central(&d, fd, &s, floating, false),
            tol,
        ));
        worst = worst.max(assert_close(
            "∂ν̇/∂ν",
            seed,
            &ev(&x.d_qdd_dqd),
            &central(&d, fd, &s, floating, true),
            tol,
        ));
        // M⁻¹ M = I, M⁻¹ symmetric.
        let m = eval_at(&d.graph, &d.mass_matrix, &s[0], &s[1], &s[2], &s[3]);
        let mi = ev(&x.mass_matrix_inverse);
        for i in 0..nv {
            for j in 0..nv {
                let p: f64 = (0..nv).map(|k| mi[i * nv + k] * m[k * nv + j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (p - want).abs() < 1e-10,
                    "seed {seed}: (M⁻¹M)[{i}][{j}] = {p}"
                );
                assert_eq!(mi[i * nv + j], mi[j * nv + i]);
            }
        }
        // ∂ν̇/∂τ = M⁻¹: central differences of forward dynamics in τ.
        let [q, v, a, tau] = &s;
        for j in 0..nv {
            let f = |t: f64| {
                let mut tau = tau.clone();
                tau[j] += t;
                eval_at(&d.graph, fd, q, v, a, &tau)
            };
            let (p, mm) = (f(H), f(-H));
            for i in 0..nv {
                let fdiff = (p[i] - mm[i]) / (2.0 * H);
                let scale = max_abs(&mi) + 1.0;
                assert!(
                    (fdiff - mi[i * nv + j]).abs() < tol * scale,
                    "seed {seed}: ∂ν̇/∂τ"
                );
            }
        }
    }
    assert!(mimics > 0, "no mimic joints drawn");
    eprintln!("worst relative error against central differences: {worst:e}");
}

/// On a fixed base the tangent derivative is the plain partial, and the gravity derivative
/// is that of inverse dynamics at ν = 0, ν̇ = 0.
#[test]
fn gravity_derivative_is_that_of_inverse_dynamics_at_rest() {
    for seed in [0u64, 1, 2, 3] {
        let r = robot(seed);
        let d = expand(&r);
        let x = expand_derivatives(&d, &r);
        let [q, _, _, tau] = state(&r, seed, 1.0);
        let zeros = vec![0.0; d.nv];
        let a = eval_at(&x.graph, &x.d_tau_dq, &q, &zeros, &zeros, &tau);
        let b = eval_at(&x.graph, &x.gravity_derivative, &q, &zeros, &zeros, &tau);
        assert_close("∂g/∂q", seed, &a, &b, 1e-12);
    }
}

fn counts(x: &Derivatives, d: &Dynamics) -> String {
    let t = |r: &[ExprId]| x.graph.op_counts(r).total();
    format!(
        "ID {} g {} | dτ/dq {} dτ/dν {} dg/dq {} M⁻¹ {} dν̇/dq {} dν̇/dν {} | all {}",
        d.graph.op_counts(&d.inverse_dynamics).total(),
        d.graph.op_counts(&d.gravity).total(),
        t(&x.d_tau_dq),
        t(&x.d_tau_dqd),
        t(&x.gravity_derivative),
        t(&x.mass_matrix_inverse),
        t(&x.d_qdd_dq),
        t(&x.d_qdd_dqd),
        t(&[
            x.d_tau_dq.clone(),
            x.d_tau_dqd.clone(),
            x.gravity_derivative.clone(),
            x.mass_matrix_inverse.clone(),
            x.d_qdd_dq.clone(),
            x.d_qdd_dqd.clone(),
        ]
        .concat()),
    )
}

/// Op counts of the outputs (`cargo test -p dynamics-gen --lib derivative_op_counts --
/// --ignored --nocapture`).
#[test]
#[ignore]
fn derivative_op_counts() {
    let mut robots: Vec<Robot> = ["pendulum", "ur5", "rand7"]
        .iter()
        .map(|n| dynamics_model::load(n, &Default::default()).unwrap())
        .collect();
    // More robots by path (`+ff`: on a floating base), e.g.
    // DERIVATIVE_ROBOTS="../tests/data/robots/panda.urdf ../tests/data/robots/trees/solo12.urdf+ff".
    for spec in std::env::var("DERIVATIVE_ROBOTS")
        .unwrap_or_default()
        .split_whitespace()
    {
        let (path, floating_base) = match spec.strip_suffix("+ff") {
            Some(p) => (p, true),
            None => (spec, false),
        };
        let options = dynamics_model::LoadOptions {
            floating_base,
            ..Default::default()
        };
        robots.push(dynamics_model::load(path, &options).unwrap());
    }
    robots.push(random_tree(
        20,
        TreeSpec {
            dof: 20,
            prismatic: 0.25,
            branching: 0.4,
            floating: true,
        },
    ));
    for r in robots {
        let t = std::time::Instant::now();
        let d = expand(&r);
        let x = expand_derivatives(&d, &r);
        println!(
            "{} (nv {}): {} [{:?}]",
            r.name,
            d.nv,
            counts(&x, &d),
            t.elapsed()
        );
        // What the checked zero pruning of `expand` would remove.
        let roots: Vec<&[ExprId]> = vec![
            &x.d_tau_dq,
            &x.d_tau_dqd,
            &x.gravity_derivative,
            &x.mass_matrix_inverse,
            &x.d_qdd_dq,
            &x.d_qdd_dqd,
        ];
        let (pg, pruned) = prune_checked(x.graph.clone(), &roots);
        let pruned: Vec<String> = pruned
            .iter()
            .map(|r| pg.op_counts(r).total().to_string())
            .collect();
        println!("  pruned: {}", pruned.join(" "));
    }
}

/// The analytical recursion ([`super::rnea_derivatives`]) equals forward-mode
/// differentiation of inverse dynamics on every fixed-base robot without mimic joints:
/// random trees and chains (a quarter prismatic), with an armature on some, at random
/// states, to 1e-10 relative.
#[test]
fn analytical_derivatives_equal_forward_mode() {
    let mut checked = 0;
    for seed in 0..60u64 {
        let mut r = robot(seed % 30 + 100 * (seed / 30));
        if r.base.floating || r.dof() != r.n_coordinates() {
            r = random_chain(
                seed,
                ChainSpec {
                    dof: 1 + seed as usize % 8,
                    prismatic: 0.25,
                },
            );
        }
        if seed % 3 == 0 {
            for (k, j) in r.joints.iter_mut().enumerate() {
                j.rotor_inertia = 0.01 * (k + 1) as f64;
                j.gear_ratio = 3.0;
            }
        }
        let d = expand(&r);
        let mut g = ExprGraph::new();
        let id = g.import(&d.graph, &d.inverse_dynamics);
        let seeds = tangent_seeds(&mut g, false, d.dof);
        let dq = tangent_jacobian(&mut g, &id, &seeds);
        let dqd = partials(&mut g, &id, QD, d.nv);
        let gravity = g.import(&d.graph, &d.gravity);
        let dg = tangent_jacobian(&mut g, &gravity, &seeds);
        for frame in [PairFrame::Deeper, PairFrame::Ancestor] {
            let x = analytical(&mut g, &r, &[frame]).expect("a fixed base without mimic joints");
            let (a_dq, a_dqd, a_dg) = (x.d_tau_dq, x.d_tau_dqd, x.gravity_derivative);
            let a_tau = x.inverse_dynamics;
            for k in 0..3u64 {
                let [q, v, a, tau] = state(&r, seed * 7 + k, 1.0);
                for (what, x, y) in [
                    ("dτ/dq", &a_dq, &dq),
                    ("dτ/dν", &a_dqd, &dqd),
                    ("dg/dq", &a_dg, &dg),
                    ("τ", &a_tau, &id),
                ] {
                    let x = eval_at(&g, x, &q, &v, &a, &tau);
                    let y = eval_at(&g, y, &q, &v, &a, &tau);
                    let diff: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a - b).collect();
                    assert!(
                        max_abs(&diff) <= 1e-10 * max_abs(&y).max(1.0),
                        "{} seed {seed} ({frame:?}): {what} differs by {:e} (scale {:e})",
                        r.name,
                        max_abs(&diff),
                        max_abs(&y)
                    );
                }
            }
        }
        checked += 1;
    }
    assert_eq!(checked, 60);
}
