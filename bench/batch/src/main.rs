//! Batch against single calls, as a user crate gets the code (bench/batch.sh generates the
//! robots into `src/generated/`): for each robot, function and `B` (8, then 4), `B`
//! consecutive states of 1,024 seeded random ones (angles in ±π, velocities and accelerations
//! in ±2, as the other harnesses draw them) through `B` single-state calls and through one
//! `*_batch::<B>` call, every argument and result through `black_box` (`consume!`); median of 7 runs of
//! 40,000 states each, the two interleaved run by run. One line per robot, function and `B`:
//! `ROBOT FUNCTION B SINGLE_NS_PER_STATE BATCH_NS_PER_STATE GAIN`.

#![allow(dead_code)]

use nalgebra::SVector;
use std::hint::black_box;
use std::time::Instant;

include!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/src/generated/robots.rs"
));

/// States per run.
const STATES: usize = 40_000;

/// 1,024 states, as arrays of `B` consecutive states each (128 of them).
#[allow(clippy::type_complexity)]
fn states<const N: usize, const B: usize>() -> Vec<(
    [SVector<f64, N>; B],
    [SVector<f64, N>; B],
    [SVector<f64, N>; B],
)> {
    let mut r = uniform();
    (0..1024 / B)
        .map(|_| {
            let mut q = [SVector::zeros(); B];
            let mut v = [SVector::zeros(); B];
            let mut a = [SVector::zeros(); B];
            for l in 0..B {
                q[l] = SVector::from_fn(|_, _| std::f64::consts::PI * r());
                v[l] = SVector::from_fn(|_, _| 2.0 * r());
                a[l] = SVector::from_fn(|_, _| 2.0 * r());
            }
            (q, v, a)
        })
        .collect()
}

include!(concat!(env!("CARGO_MANIFEST_DIR"), "/../harness.rs"));

/// ns per state of `single` and `batch` (each called with a round's index), interleaved.
fn pair<const B: usize>(mut single: impl FnMut(usize), mut batch: impl FnMut(usize)) -> (f64, f64) {
    let run = |f: &mut dyn FnMut(usize)| {
        let t = Instant::now();
        for i in 0..STATES / B {
            f(i & (1024 / B - 1));
        }
        t.elapsed().as_nanos() as f64 / STATES as f64
    };
    let (mut s, mut b) = (Vec::new(), Vec::new());
    for _ in 0..7 {
        s.push(run(&mut single));
        b.push(run(&mut batch));
    }
    (median(s), median(b))
}

/// One line: `$single` on each of `B` states against `$batch` on all of them, the state's
/// `(q, q̇, x)` bound to `$pat` (a pattern naming the arguments `$arg`).
macro_rules! row {
    ($line:ident, $r:ident, $st:ident, $single:ident, $batch:ident, $pat:pat, $($arg:ident),+) => {
        $line(
            stringify!($single),
            pair::<B>(
                |i| {
                    let $pat = black_box(&$st[i]);
                    for l in 0..B {
                        consume!($r.$single($(&$arg[l]),+));
                    }
                },
                |i| {
                    let $pat = black_box(&$st[i]);
                    consume!($r.$batch($($arg),+));
                },
            ),
        )
    };
}

macro_rules! bench {
    ($name:expr, $n:literal, $ty:path, $b:literal) => {{
        const B: usize = $b;
        let st = states::<$n, B>();
        let r = <$ty>::default();
        let line =
            |f: &str, (s, b): (f64, f64)| println!("{} {f} {B} {s:.1} {b:.1} {:.2}", $name, s / b);
        row!(
            line,
            r,
            st,
            inverse_dynamics,
            inverse_dynamics_batch,
            (q, v, a),
            q,
            v,
            a
        );
        row!(
            line,
            r,
            st,
            forward_dynamics,
            forward_dynamics_batch,
            (q, v, a),
            q,
            v,
            a
        );
        row!(line, r, st, mass_matrix, mass_matrix_batch, (q, _, _), q);
        row!(line, r, st, gravity, gravity_batch, (q, _, _), q);
    }};
}

fn main() {
    bench!("ur5", 6, ur5::Ur5, 8);
    bench!("panda", 7, panda::Panda, 8);
    bench!("ur5", 6, ur5::Ur5, 4);
    bench!("panda", 7, panda::Panda, 4);
}
