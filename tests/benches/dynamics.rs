//! Generated code against the generic recursive reference implementation, side by side in
//! one run: `cargo bench -p dynamics-tests --bench dynamics`.
//!
//! The reference allocates and loops (nalgebra `DMatrix`, one iteration per joint); the
//! generated functions are straight-line code over `SVector`s. Ratios measured in the same
//! run are what to compare, never absolute times from different runs.

use criterion::{criterion_group, criterion_main, Criterion};
use dynamics_model::LoadOptions;
use dynamics_tests::bench::{states, STATES};
use nalgebra::{SVector, Vector6};
use std::hint::black_box;

/// Times `f` on the states in turn, one per iteration (each through `black_box`).
fn cycled<S, O>(b: &mut criterion::Bencher<'_>, states: &[S], mut f: impl FnMut(&S) -> O) {
    assert_eq!(states.len(), STATES);
    let mut k = 0;
    b.iter(|| {
        // `STATES` is a power of two: a mask, not a division, per iteration.
        k = (k + 1) & (STATES - 1);
        f(black_box(&states[k]))
    });
}

macro_rules! bench_robot {
    ($c:expr, $label:literal, $m:ident, $nq:literal, $nv:literal, $robot:expr) => {{
        use dynamics_tests::generated::$m::Robot as Gen;
        let robot = $robot;
        // (On a floating base q[3..7] is a quaternion: normalised inside, any length goes.)
        let states = states::<$nq, $nv>(|q, qd, qdd| Gen.inverse_dynamics(q, qd, qdd));
        let g = robot.gravity;
        let z = Vector6::zeros();
        let mut group = $c.benchmark_group($label);
        group.bench_function("generated/inverse_dynamics", |b| {
            cycled(b, &states, |s| {
                Gen.inverse_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&s.qdd))
            })
        });
        group.bench_function("reference/inverse_dynamics", |b| {
            cycled(b, &states, |s| {
                dynamics_reference::inverse_dynamics(
                    &robot,
                    black_box(s.q.as_slice()),
                    black_box(s.qd.as_slice()),
                    black_box(s.qdd.as_slice()),
                    &g,
                    &z,
                )
            })
        });
        group.bench_function("generated/mass_matrix", |b| {
            cycled(b, &states, |s| Gen.mass_matrix(black_box(&s.q)))
        });
        group.bench_function("reference/mass_matrix", |b| {
            cycled(b, &states, |s| {
                dynamics_reference::mass_matrix(&robot, black_box(s.q.as_slice()))
            })
        });
        group.bench_function("generated/gravity", |b| {
            cycled(b, &states, |s| Gen.gravity(black_box(&s.q)))
        });
        group.bench_function("generated/coriolis", |b| {
            cycled(b, &states, |s| {
                Gen.coriolis(black_box(&s.q), black_box(&s.qd))
            })
        });
        // One call for M and h = c + g, against two (M, then h as τ at q̈ = 0).
        let zero = SVector::<f64, $nv>::zeros();
        group.bench_function("generated/mass_matrix_and_bias", |b| {
            cycled(b, &states, |s| {
                Gen.mass_matrix_and_bias(black_box(&s.q), black_box(&s.qd))
            })
        });
        group.bench_function("generated/mass_matrix+bias_two_calls", |b| {
            cycled(b, &states, |s| {
                (
                    Gen.mass_matrix(black_box(&s.q)),
                    Gen.inverse_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&zero)),
                )
            })
        });
        group.bench_function("generated/forward_dynamics", |b| {
            cycled(b, &states, |s| {
                Gen.forward_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&s.tau))
            })
        });
        group.bench_function("reference/forward_dynamics", |b| {
            cycled(b, &states, |s| {
                dynamics_reference::forward_dynamics(
                    &robot,
                    black_box(s.q.as_slice()),
                    black_box(s.qd.as_slice()),
                    black_box(s.tau.as_slice()),
                    &g,
                    &z,
                )
            })
        });
        group.finish();
    }};
}

/// The derivative functions (the robots generated with them), beside `inverse_dynamics`.
macro_rules! bench_derivatives {
    ($c:expr, $label:literal, $m:ident, $nq:literal, $nv:literal) => {{
        use dynamics_tests::generated::$m::Robot as Gen;
        let states = states::<$nq, $nv>(|q, qd, qdd| Gen.inverse_dynamics(q, qd, qdd));
        let mut group = $c.benchmark_group($label);
        group.bench_function("generated/inverse_dynamics_derivatives", |b| {
            cycled(b, &states, |s| {
                Gen.inverse_dynamics_derivatives(
                    black_box(&s.q),
                    black_box(&s.qd),
                    black_box(&s.qdd),
                )
            })
        });
        group.bench_function("generated/inverse_dynamics_with_derivatives", |b| {
            cycled(b, &states, |s| {
                Gen.inverse_dynamics_with_derivatives(
                    black_box(&s.q),
                    black_box(&s.qd),
                    black_box(&s.qdd),
                )
            })
        });
        group.bench_function("generated/inverse_dynamics+derivatives_two_calls", |b| {
            cycled(b, &states, |s| {
                (
                    Gen.inverse_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&s.qdd)),
                    Gen.inverse_dynamics_derivatives(
                        black_box(&s.q),
                        black_box(&s.qd),
                        black_box(&s.qdd),
                    ),
                )
            })
        });
        group.bench_function("generated/forward_dynamics_derivatives", |b| {
            cycled(b, &states, |s| {
                Gen.forward_dynamics_derivatives(
                    black_box(&s.q),
                    black_box(&s.qd),
                    black_box(&s.tau),
                )
            })
        });
        group.bench_function("generated/forward_dynamics_with_derivatives", |b| {
            cycled(b, &states, |s| {
                Gen.forward_dynamics_with_derivatives(
                    black_box(&s.q),
                    black_box(&s.qd),
                    black_box(&s.tau),
                )
            })
        });
        group.bench_function("generated/mass_matrix_inverse", |b| {
            cycled(b, &states, |s| Gen.mass_matrix_inverse(black_box(&s.q)))
        });
        group.bench_function("generated/gravity_derivative", |b| {
            cycled(b, &states, |s| Gen.gravity_derivative(black_box(&s.q)))
        });
        group.finish();
    }};
}

/// The batch functions on 8 states against 8 single-state calls on the same states: both
/// rows time 8 states, so their ratio is the batch's gain per state.
macro_rules! bench_batch {
    ($c:expr, $label:literal, $m:ident, $nq:literal, $nv:literal) => {{
        use dynamics_tests::generated::$m::Robot as Gen;
        const B: usize = 8;
        let q: [SVector<f64, $nq>; B] =
            std::array::from_fn(|l| SVector::from_fn(|i, _| 0.3 + 0.2 * i as f64 - 0.1 * l as f64));
        let qd: [SVector<f64, $nv>; B] = std::array::from_fn(|l| {
            SVector::from_fn(|i, _| 0.5 - 0.1 * i as f64 + 0.05 * l as f64)
        });
        let qdd: [SVector<f64, $nv>; B] = std::array::from_fn(|l| {
            SVector::from_fn(|i, _| -0.4 + 0.15 * i as f64 + 0.1 * l as f64)
        });
        let tau = Gen.inverse_dynamics_batch(&q, &qd, &qdd);
        let mut group = $c.benchmark_group($label);
        group.bench_function("generated/inverse_dynamics_x8_batch", |b| {
            b.iter(|| Gen.inverse_dynamics_batch(black_box(&q), black_box(&qd), black_box(&qdd)))
        });
        group.bench_function("generated/inverse_dynamics_x8_single", |b| {
            b.iter(|| {
                let (q, qd, qdd) = (black_box(&q), black_box(&qd), black_box(&qdd));
                let out: [SVector<f64, $nv>; B] =
                    std::array::from_fn(|l| Gen.inverse_dynamics(&q[l], &qd[l], &qdd[l]));
                out
            })
        });
        group.bench_function("generated/forward_dynamics_x8_batch", |b| {
            b.iter(|| Gen.forward_dynamics_batch(black_box(&q), black_box(&qd), black_box(&tau)))
        });
        group.bench_function("generated/forward_dynamics_x8_single", |b| {
            b.iter(|| {
                let (q, qd, tau) = (black_box(&q), black_box(&qd), black_box(&tau));
                let out: [SVector<f64, $nv>; B] =
                    std::array::from_fn(|l| Gen.forward_dynamics(&q[l], &qd[l], &tau[l]));
                out
            })
        });
        group.bench_function("generated/mass_matrix_x8_batch", |b| {
            b.iter(|| Gen.mass_matrix_batch(black_box(&q)))
        });
        group.bench_function("generated/mass_matrix_x8_single", |b| {
            b.iter(|| {
                let q = black_box(&q);
                let out: [nalgebra::SMatrix<f64, $nv, $nv>; B] =
                    std::array::from_fn(|l| Gen.mass_matrix(&q[l]));
                out
            })
        });
        group.bench_function("generated/gravity_x8_batch", |b| {
            b.iter(|| Gen.gravity_batch(black_box(&q)))
        });
        group.bench_function("generated/gravity_x8_single", |b| {
            b.iter(|| {
                let q = black_box(&q);
                let out: [SVector<f64, $nv>; B] = std::array::from_fn(|l| Gen.gravity(&q[l]));
                out
            })
        });
        group.finish();
    }};
}

fn benches(c: &mut Criterion) {
    let data = dynamics_tests::data_dir().join("robots");
    let load = |name: &str, tip: &str| {
        let options = LoadOptions {
            tip: Some(tip.to_string()),
            ..Default::default()
        };
        dynamics_model::load_file(&data.join(format!("{name}.urdf")), &options).expect("loads")
    };
    bench_robot!(c, "ur5", urdf_ur5, 6, 6, load("ur5", "tool0"));
    bench_robot!(
        c,
        "panda",
        urdf_panda,
        7,
        7,
        load("panda", "panda_hand_tcp")
    );
    bench_robot!(c, "rand7", urdf_rand7, 7, 7, load("rand7", "ee_link"));
    bench_batch!(c, "ur5", urdf_ur5, 6, 6);
    bench_batch!(c, "panda", urdf_panda, 7, 7);
    bench_batch!(c, "rand7", urdf_rand7, 7, 7);
    bench_batch!(c, "solo12", tree_solo12, 19, 18);
    bench_derivatives!(c, "ur5", urdf_ur5, 6, 6);
    bench_derivatives!(c, "panda", urdf_panda, 7, 7);
    bench_derivatives!(c, "rand7", urdf_rand7, 7, 7);
    bench_derivatives!(c, "double_pendulum", urdf_double_pendulum, 2, 2);
    let tree = |name: &str, floating: bool| {
        let options = LoadOptions {
            floating_base: floating,
            ..Default::default()
        };
        let path = data.join(format!("trees/{name}.urdf"));
        dynamics_model::load_file(&path, &options).expect("loads")
    };
    let talos = tree("talos_upper_body", false);
    bench_robot!(c, "talos_upper_body", tree_talos_upper_body, 20, 20, talos);
    bench_robot!(c, "solo12", tree_solo12, 19, 18, tree("solo12", true));
    bench_derivatives!(c, "solo12", tree_solo12, 19, 18);
    bench_robot!(c, "g1_29dof", tree_g1_29dof, 36, 35, tree("g1_29dof", true));
}

criterion_group! {
    name = dynamics;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(1));
    targets = benches
}
criterion_main!(dynamics);
