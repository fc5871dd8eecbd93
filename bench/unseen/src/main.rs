//! Times the generated functions of the arms bench/unseen.sh generates into
//! `src/generated/` (1,024 seeded random states in ±2 rad and ±1, cycled through `black_box`;
//! median of 7 runs of 20,000 calls), one line per robot and function: `ROBOT FUNCTION NS`.
//! Results go to `black_box` by reference with the `by-ref` feature (`bench/unseen.sh`'s
//! default), as Pinocchio's benchmarks leave theirs in `Data`, or by value without it
//! (`BY_VALUE=1 bash bench/unseen.sh`).

use nalgebra::SVector;
use std::hint::black_box;
use std::time::Instant;

include!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/src/generated/arms.rs"
));

fn states<const N: usize>() -> Vec<(SVector<f64, N>, SVector<f64, N>, SVector<f64, N>)> {
    let mut r = uniform();
    (0..1024)
        .map(|_| {
            (
                SVector::from_fn(|_, _| 2.0 * r()),
                SVector::from_fn(|_, _| r()),
                SVector::from_fn(|_, _| r()),
            )
        })
        .collect()
}

include!(concat!(env!("CARGO_MANIFEST_DIR"), "/../harness.rs"));

fn time<F: FnMut(usize)>(mut f: F) -> f64 {
    let runs: Vec<f64> = (0..7)
        .map(|_| {
            let t = Instant::now();
            for i in 0..20_000 {
                f(i & 1023);
            }
            t.elapsed().as_nanos() as f64 / 20_000.0
        })
        .collect();
    median(runs)
}

macro_rules! bench {
    ($name:expr, $n:literal, $ty:path) => {{
        let st = states::<$n>();
        let r = <$ty>::default();
        let name = $name;
        let line = |f: &str, ns: f64| println!("{name} {f} {ns:.1}");
        line(
            "inverse_dynamics",
            time(|i| {
                let s = &st[i];
                consume!(r.inverse_dynamics(black_box(&s.0), &s.1, &s.2));
            }),
        );
        line(
            "coriolis",
            time(|i| {
                let s = &st[i];
                consume!(r.coriolis(black_box(&s.0), &s.1));
            }),
        );
        line(
            "mass_matrix",
            time(|i| {
                consume!(r.mass_matrix(black_box(&st[i].0)));
            }),
        );
        line(
            "gravity",
            time(|i| {
                consume!(r.gravity(black_box(&st[i].0)));
            }),
        );
        line(
            "forward_dynamics",
            time(|i| {
                let s = &st[i];
                consume!(r.forward_dynamics(black_box(&s.0), &s.1, &s.2));
            }),
        );
        line(
            "inverse_dynamics_derivatives",
            time(|i| {
                let s = &st[i];
                consume!(r.inverse_dynamics_derivatives(black_box(&s.0), &s.1, &s.2));
            }),
        );
        line(
            "forward_dynamics_with_derivatives",
            time(|i| {
                let s = &st[i];
                consume!(r.forward_dynamics_with_derivatives(black_box(&s.0), &s.1, &s.2));
            }),
        );
        line(
            "mass_matrix_inverse",
            time(|i| {
                consume!(r.mass_matrix_inverse(black_box(&st[i].0)));
            }),
        );
        line(
            "gravity_derivative",
            time(|i| {
                consume!(r.gravity_derivative(black_box(&st[i].0)));
            }),
        );
    }};
}

fn main() {
    bench!("xarm7", 7, xarm7::Xarm7);
    bench!("xarm7_snapped", 7, xarm7_snapped::Xarm7Snapped);
    bench!("baxter_left_arm", 7, baxter_left_arm::BaxterLeftArm);
}
