//! Numerical robustness of forward dynamics: badly scaled robots (link inertias from 1e-6 to
//! 1e3 times each other) and configurations at and near kinematic singularities, through
//! both routes (articulated-body algorithm and CRBA + LDLᵀ), against the same expressions
//! evaluated in double-double arithmetic (about 106 bits, `twofloat`).
//!
//! The expressions are the ones the generated code writes (the expansion's graph), evaluated
//! once in f64 and once in double-double. Sines and cosines are computed once, in f64, and
//! used by both evaluations: the comparison then measures the rounding of the recursions
//! themselves (a rounded sine is a relative perturbation of 1e-16 of a joint angle, which
//! the generated code's own `sin` makes anyway). For each case:
//!
//! * `κ`: the 2-norm condition number of `M(q)` (SVD);
//! * forward error `‖q̈ − q̈*‖ / ‖q̈*‖` of the f64 `q̈` against the double-double `q̈*`: a
//!   backward-stable method gives at most a small multiple of `κ ε`;
//! * the residual `‖M q̈ − (τ − c − g)‖ / (‖M‖ ‖q̈‖ + ‖τ − c − g‖)` of the f64 `q̈`, with `M`
//!   and `τ − c − g` in double-double: the normwise backward error, a small multiple of `ε`
//!   whatever `κ`.
//!
//! `τ = ID(q, q̇, q̈₀)` in double-double for a random `q̈₀`, so that `q̈* = q̈₀` too.
//! `cargo test -p dynamics-gen --test numerics -- --nocapture` prints the table
//! (`docs/numerics.md`).

use dynamics_gen::expand::{expand_with_route, Dynamics, ForwardRoute, Q, QD, QDD, TAU};
use dynamics_gen::expr::{ExprId, Input, Node};
use dynamics_model::random::{random_chain, ChainSpec, Rng};
use dynamics_model::{LoadOptions, Robot};
use nalgebra::{DMatrix, DVector};
use twofloat::TwoFloat;

/// Values of `roots` in f64 and in double-double (see the module docs for sines and
/// cosines).
fn eval_both(
    d: &Dynamics,
    roots: &[ExprId],
    x: &dyn Fn(Input) -> TwoFloat,
) -> (Vec<f64>, Vec<TwoFloat>) {
    let g = &d.graph;
    let live = g.live(roots);
    let mut lo = vec![f64::NAN; g.len()];
    let mut hi = vec![TwoFloat::from(f64::NAN); g.len()];
    for (i, node) in g.nodes().iter().enumerate() {
        if !live[i] {
            continue;
        }
        let (a, b) = match *node {
            Node::Const(c) => (c.value(), TwoFloat::from(c.value())),
            Node::Input(k) => (f64::from(x(k)), x(k)),
            Node::Neg(a) => (-lo[a.index()], -hi[a.index()]),
            Node::Add(a, b) => (lo[a.index()] + lo[b.index()], hi[a.index()] + hi[b.index()]),
            Node::Sub(a, b) => (lo[a.index()] - lo[b.index()], hi[a.index()] - hi[b.index()]),
            Node::Mul(a, b) => (lo[a.index()] * lo[b.index()], hi[a.index()] * hi[b.index()]),
            Node::Div(a, b) => (lo[a.index()] / lo[b.index()], hi[a.index()] / hi[b.index()]),
            Node::Sqrt(a) => (lo[a.index()].sqrt(), hi[a.index()].sqrt()),
            Node::Sin(a) => {
                let s = lo[a.index()].sin();
                (s, TwoFloat::from(s))
            }
            Node::Cos(a) => {
                let c = lo[a.index()].cos();
                (c, TwoFloat::from(c))
            }
        };
        lo[i] = a;
        hi[i] = b;
    }
    (
        roots.iter().map(|r| lo[r.index()]).collect(),
        roots.iter().map(|r| hi[r.index()]).collect(),
    )
}

/// One case's figures.
struct Figures {
    kappa: f64,
    forward: f64,
    residual: f64,
}

fn norm(v: &[TwoFloat]) -> TwoFloat {
    v.iter().fold(TwoFloat::from(0.0), |s, &x| s + x * x).sqrt()
}

/// Forward dynamics of `d` at `q` (and random `q̇`, `q̈₀`), measured as the module docs say.
fn measure(d: &Dynamics, q: &[f64], rng: &mut Rng) -> Figures {
    let nv = d.nv;
    let qd: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let qdd0: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let state = |k: Input| -> TwoFloat {
        let v = match k.group {
            Q => q[k.index as usize],
            QD => qd[k.index as usize],
            QDD => qdd0[k.index as usize],
            _ => f64::NAN,
        };
        TwoFloat::from(v)
    };
    let (_, tau) = eval_both(d, &d.inverse_dynamics, &state);
    let (_, m) = eval_both(d, &d.mass_matrix, &state);
    let (_, bias) = eval_both(d, &d.bias, &state);
    let full = |k: Input| -> TwoFloat {
        if k.group == TAU {
            tau[k.index as usize]
        } else {
            state(k)
        }
    };
    // τ is rounded to f64 for the f64 evaluation and kept whole for the double-double one.
    let (qdd, qdd_star) = eval_both(d, &d.forward_dynamics, &full);
    let rhs: Vec<TwoFloat> = (0..nv).map(|i| tau[i] - bias[i]).collect();
    let diff: Vec<TwoFloat> = (0..nv)
        .map(|i| TwoFloat::from(qdd[i]) - qdd_star[i])
        .collect();
    let forward = f64::from(norm(&diff) / norm(&qdd_star));
    let mut r = Vec::with_capacity(nv);
    for i in 0..nv {
        let mut s = -rhs[i];
        for j in 0..nv {
            s += m[i * nv + j] * TwoFloat::from(qdd[j]);
        }
        r.push(s);
    }
    let m64 = DMatrix::from_fn(nv, nv, |i, j| f64::from(m[i * nv + j]));
    let sv = m64.clone().singular_values();
    let kappa = sv.max() / sv.min();
    let m_norm = sv.max();
    let qdd_norm = DVector::from_vec(qdd.clone()).norm();
    let residual = f64::from(norm(&r)) / (m_norm * qdd_norm + f64::from(norm(&rhs)));
    // The double-double q̈ is the q̈₀ that τ was made from, up to the constants that the
    // two expansions folded (and rounded to f64) differently: a relative change of ε in the
    // problem, so a difference of at most a few κε.
    let back: Vec<TwoFloat> = (0..nv)
        .map(|i| qdd_star[i] - TwoFloat::from(qdd0[i]))
        .collect();
    let back = f64::from(norm(&back) / norm(&qdd_star));
    assert!(
        back <= 100.0 * kappa * f64::EPSILON,
        "double-double FD(ID(q̈₀)) differs from q̈₀ by {back:e} (κ = {kappa:e})"
    );
    Figures {
        kappa,
        forward,
        residual,
    }
}

/// The robot with link `i`'s spatial inertia (mass and rotational inertia together)
/// multiplied by `scales[i]`.
fn scaled(mut robot: Robot, scales: &[f64]) -> Robot {
    for (link, s) in robot.links.iter_mut().zip(scales) {
        link.inertia.0 *= *s;
    }
    dynamics_gen::check_robot(&robot).expect("a scaled robot is valid");
    robot
}

/// The worst figures of a group of cases, checked against the bounds.
#[derive(Default)]
struct Worst {
    cases: usize,
    kappa: f64,
    ratio: f64,
    residual: f64,
}

impl Worst {
    fn add(&mut self, f: &Figures) {
        self.cases += 1;
        self.kappa = self.kappa.max(f.kappa);
        self.ratio = self.ratio.max(f.forward / (f.kappa * f64::EPSILON));
        self.residual = self.residual.max(f.residual / f64::EPSILON);
    }

    /// Forward error at most `ratio` κ ε, residual at most `residual` ε.
    fn check(&self, what: &str, ratio: f64, residual: f64) {
        eprintln!(
            "| {what} | {} | {:.1e} | {:.3} | {:.1} |",
            self.cases, self.kappa, self.ratio, self.residual
        );
        assert!(
            self.ratio <= ratio,
            "{what}: forward error {} κε",
            self.ratio
        );
        assert!(
            self.residual <= residual,
            "{what}: residual {} ε",
            self.residual
        );
    }
}

fn routes() -> [(ForwardRoute, &'static str); 2] {
    [
        (ForwardRoute::Aba, "ABA"),
        (ForwardRoute::Ldlt, "CRBA + LDLᵀ"),
    ]
}

#[test]
fn forward_dynamics_of_badly_scaled_robots_is_backward_stable() {
    eprintln!("| robots | cases | max κ(M) | max error / κε | max residual / ε |");
    eprintln!("|---|---|---|---|---|");
    for (route, route_name) in routes() {
        for dof in [3, 7, 12] {
            let mut worst = Worst::default();
            let mut rng = Rng::new(dof as u64);
            for seed in 0..12u64 {
                let robot = random_chain(
                    seed + 100 * dof as u64,
                    ChainSpec {
                        dof,
                        prismatic: 0.25,
                    },
                );
                let n = robot.links.len();
                // Random scales 10^[-6, 3], then the two monotone extremes.
                let scales: Vec<f64> = match seed {
                    10 => (0..n)
                        .map(|i| 10f64.powf(-6.0 + 9.0 * i as f64 / (n - 1) as f64))
                        .collect(),
                    11 => (0..n)
                        .map(|i| 10f64.powf(3.0 - 9.0 * i as f64 / (n - 1) as f64))
                        .collect(),
                    _ => (0..n).map(|_| 10f64.powf(rng.uniform(-6.0, 3.0))).collect(),
                };
                let robot = scaled(robot, &scales);
                let d = expand_with_route(&robot, route);
                for _ in 0..4 {
                    let q: Vec<f64> = (0..d.nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
                    worst.add(&measure(&d, &q, &mut rng));
                }
            }
            worst.check(
                &format!("{route_name}, random {dof}-joint chains, inertias 1e-6 to 1e3"),
                100.0,
                100.0,
            );
        }
    }
}

#[test]
fn forward_dynamics_at_kinematic_singularities_is_accurate() {
    use std::f64::consts::FRAC_PI_2;
    let ur5 = dynamics_model::load("ur5", &LoadOptions::default()).expect("shipped ur5");
    // UR5 joints: base, shoulder, elbow, wrist 1, wrist 2, wrist 3. Wrist singularity at
    // θ5 = 0 (axes 4 and 6 aligned), elbow singularity at θ3 = 0 (arm stretched),
    // shoulder singularity where the wrist centre is on the base axis.
    let singular: [(&str, [f64; 6]); 4] = [
        ("wrist", [0.3, -1.0, 1.2, 0.4, 0.0, 0.7]),
        ("elbow", [0.3, -1.0, 0.0, 0.4, 1.1, 0.7]),
        ("shoulder", [0.0, -FRAC_PI_2, 0.0, -FRAC_PI_2, 0.0, 0.0]),
        ("all zero", [0.0; 6]),
    ];
    eprintln!("| robot, configurations | cases | max κ(M) | max error / κε | max residual / ε |");
    eprintln!("|---|---|---|---|---|");
    for (route, route_name) in routes() {
        let d = expand_with_route(&ur5, route);
        let mut worst = Worst::default();
        let mut rng = Rng::new(7);
        for (_, q) in &singular {
            for delta in [0.0, 1e-12, 1e-9, 1e-6, 1e-3] {
                let q: Vec<f64> = q
                    .iter()
                    .map(|x| x + delta * rng.uniform(-1.0, 1.0))
                    .collect();
                worst.add(&measure(&d, &q, &mut rng));
            }
        }
        worst.check(
            &format!("{route_name}, UR5 at and near wrist, elbow and shoulder singularities"),
            100.0,
            100.0,
        );
    }
}
