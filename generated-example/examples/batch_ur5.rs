//! Batch against single-state calls on the generated UR5: `inverse_dynamics`,
//! `forward_dynamics`, `mass_matrix` and `gravity` for 1,024 random states, as `B` calls of the
//! single-state function and as one `*_batch` call of `B` states, interleaved in one run
//! (median of 15 rounds), in ns per state, with the gain per state.
//!
//! ```text
//! cargo run -p generated-example --example batch_ur5 --release                          # default x86-64 target (SSE2)
//! RUSTFLAGS="-C target-cpu=native" cargo run -p generated-example --example batch_ur5 --release
//! ```
//!
//! It also checks that every batch result equals the single-state call's bit for bit (this
//! crate's code is `no_std`, which fuses no multiply-adds).

use generated_example::ur5::Ur5;
use nalgebra::{SMatrix, SVector};
use std::hint::black_box;
use std::time::Instant;

type V = SVector<f64, 6>;
const STATES: usize = 1024;

/// Median ns per state of `f`, called on batches `0..STATES / b` of `b` states, over rounds.
fn time(rounds: usize, b: usize, mut f: impl FnMut(usize)) -> f64 {
    let mut t: Vec<f64> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            for k in 0..STATES / b {
                f(k);
            }
            start.elapsed().as_nanos() as f64 / STATES as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[rounds / 2]
}

fn compare<const B: usize>(q: &[V], qd: &[V], x: &[V]) {
    let robot = Ur5;
    let chunk = |s: &[V], k: usize| -> [V; B] { std::array::from_fn(|l| s[k * B + l]) };
    let qs: Vec<[V; B]> = (0..STATES / B).map(|k| chunk(q, k)).collect();
    let qds: Vec<[V; B]> = (0..STATES / B).map(|k| chunk(qd, k)).collect();
    let xs: Vec<[V; B]> = (0..STATES / B).map(|k| chunk(x, k)).collect();
    // Same bits, state by state.
    for k in 0..STATES / B {
        let (tau, qdd) = (
            robot.inverse_dynamics_batch(&qs[k], &qds[k], &xs[k]),
            robot.forward_dynamics_batch(&qs[k], &qds[k], &xs[k]),
        );
        let (m, g) = (robot.mass_matrix_batch(&qs[k]), robot.gravity_batch(&qs[k]));
        for l in 0..B {
            let (q, qd, x) = (&qs[k][l], &qds[k][l], &xs[k][l]);
            assert_eq!(tau[l], robot.inverse_dynamics(q, qd, x));
            assert_eq!(qdd[l], robot.forward_dynamics(q, qd, x));
            assert_eq!(m[l], robot.mass_matrix(q));
            assert_eq!(g[l], robot.gravity(q));
        }
    }
    let rounds = 15;
    let rows: [(&str, f64, f64); 4] = [
        (
            "inverse_dynamics",
            time(rounds, B, |k| {
                for l in 0..B {
                    black_box(robot.inverse_dynamics(&qs[k][l], &qds[k][l], black_box(&xs[k][l])));
                }
            }),
            time(rounds, B, |k| {
                black_box(robot.inverse_dynamics_batch(&qs[k], &qds[k], black_box(&xs[k])));
            }),
        ),
        (
            "forward_dynamics",
            time(rounds, B, |k| {
                for l in 0..B {
                    black_box(robot.forward_dynamics(&qs[k][l], &qds[k][l], black_box(&xs[k][l])));
                }
            }),
            time(rounds, B, |k| {
                black_box(robot.forward_dynamics_batch(&qs[k], &qds[k], black_box(&xs[k])));
            }),
        ),
        (
            "mass_matrix",
            time(rounds, B, |k| {
                for l in 0..B {
                    let m: SMatrix<f64, 6, 6> = robot.mass_matrix(black_box(&qs[k][l]));
                    black_box(m);
                }
            }),
            time(rounds, B, |k| {
                black_box(robot.mass_matrix_batch(black_box(&qs[k])));
            }),
        ),
        (
            "gravity",
            time(rounds, B, |k| {
                for l in 0..B {
                    black_box(robot.gravity(black_box(&qs[k][l])));
                }
            }),
            time(rounds, B, |k| {
                black_box(robot.gravity_batch(black_box(&qs[k])));
            }),
        ),
    ];
    for (name, single, batch) in rows {
        println!(
            "{name:<18} B = {B:<2} {single:8.1} {batch:8.1} {:6.2}x",
            single / batch
        );
    }
}

fn main() {
    // Uniform states from a fixed xorshift: angles in ±π, rates in ±2 rad/s, torques ±50 N·m.
    let mut s = 0x9e37_79b9_7f4a_7c15_u64;
    let mut r = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut states = |scale: f64| -> Vec<V> {
        (0..STATES)
            .map(|_| V::from_fn(|_, _| scale * r()))
            .collect()
    };
    let (q, qd, x) = (states(std::f64::consts::PI), states(2.0), states(50.0));
    println!(
        "UR5, {STATES} states; ns per state: {:<18} B    single    batch   gain",
        "function"
    );
    compare::<2>(&q, &qd, &x);
    compare::<4>(&q, &qd, &x);
    compare::<8>(&q, &qd, &x);
}
