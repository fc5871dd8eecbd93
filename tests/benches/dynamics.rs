//! Generated code against the generic recursive reference implementation, side by side in
//! one run: `cargo bench -p dynamics-tests --bench dynamics`.
//!
//! The reference allocates and loops (nalgebra `DMatrix`, one iteration per joint); the
//! generated functions are straight-line code over `SVector`s. Ratios measured in the same
//! run are what to compare, never absolute times from different runs.

use criterion::{criterion_group, criterion_main, Criterion};
use dynamics_model::LoadOptions;
use dynamics_tests::bench::{keep, states, STATES};
use nalgebra::{DMatrix, DVector, SMatrix, SVector, Vector6};
use std::hint::black_box;

/// Times `ours` and `reference` side by side, in alternating blocks of about a millisecond
/// each (the first of the two swapped every round), when the environment's `SIDE_BY_SIDE` is a
/// number of rounds and `SIDE_BY_SIDE_ROBOTS` lists `label` (`bench/run.sh` sets both): on a
/// shared machine whose speed drifts over seconds, two criterion rows measured a few seconds
/// apart can move by 2× against each other, while a ratio taken within one round of a few
/// milliseconds does not. Each closure gets the index of the state to use (cycling through
/// [`STATES`]). Prints one tab-separated line, `side-by-side`, the label, `name`, the medians
/// over the rounds of ours and the reference (ns per call), and the median, first and third
/// quartiles of the rounds' ratios (reference ÷ ours).
fn side_by_side<A, B>(
    label: &str,
    name: &str,
    mut ours: impl FnMut(usize) -> A,
    mut reference: impl FnMut(usize) -> B,
) {
    let rounds = std::env::var("SIDE_BY_SIDE")
        .ok()
        .and_then(|r| r.parse::<usize>().ok());
    let robots = std::env::var("SIDE_BY_SIDE_ROBOTS").unwrap_or_default();
    let Some(rounds) = rounds.filter(|&r| r > 0) else {
        return;
    };
    if !robots.split_whitespace().any(|r| r == label) {
        return;
    }
    // ns per call of `calls` calls, cycling through the states, after `warm` calls untimed
    // (the other side's block has just run).
    fn block<O>(warm: usize, calls: usize, f: &mut impl FnMut(usize) -> O) -> f64 {
        for i in 0..warm {
            keep(&f(i & (STATES - 1)));
        }
        let start = std::time::Instant::now();
        for i in 0..calls {
            keep(&f(i & (STATES - 1)));
        }
        start.elapsed().as_nanos() as f64 / calls as f64
    }
    // Calls per block: about a millisecond's worth (this also warms both up).
    fn calls<O>(f: &mut impl FnMut(usize) -> O) -> usize {
        let mut n = 1;
        while n < 1 << 20 && block(0, n, f) * (n as f64) < 1e6 {
            n *= 2;
        }
        n
    }
    let (n_ours, n_reference) = (calls(&mut ours), calls(&mut reference));
    let (mut t_ours, mut t_reference, mut ratios) = (vec![], vec![], vec![]);
    for round in 0..rounds {
        let (a, b) = if round % 2 == 0 {
            let a = block(n_ours / 4, n_ours, &mut ours);
            (a, block(n_reference / 4, n_reference, &mut reference))
        } else {
            let b = block(n_reference / 4, n_reference, &mut reference);
            (block(n_ours / 4, n_ours, &mut ours), b)
        };
        t_ours.push(a);
        t_reference.push(b);
        ratios.push(b / a);
    }
    for v in [&mut t_ours, &mut t_reference, &mut ratios] {
        v.sort_by(f64::total_cmp);
    }
    let median = |v: &[f64]| v[v.len() / 2];
    println!(
        "side-by-side\t{label}\t{name}\t{:.1}\t{:.1}\t{:.2}\t{:.2}\t{:.2}",
        median(&t_ours),
        median(&t_reference),
        median(&ratios),
        ratios[rounds / 4],
        ratios[(3 * rounds) / 4],
    );
}

/// Registers `generated/<name>` and `reference/<name>` with criterion, each cycling through
/// `states`, and times the two [`side_by_side`] too; with `elsewhere`, the generated row is
/// registered by another macro (`bench_robot!`, `bench_derivatives!`) and only the reference
/// row here.
macro_rules! pair_rows {
    ($group:ident, $states:ident, $label:expr, $name:literal, |$s:ident| $gen:expr, $reference:expr) => {
        $group.bench_function(concat!("generated/", $name), |b| {
            cycled(b, &$states, |$s| $gen)
        });
        pair_rows!(
            $group,
            $states,
            $label,
            $name,
            elsewhere,
            |$s| $gen,
            $reference
        );
    };
    ($group:ident, $states:ident, $label:expr, $name:literal, elsewhere, |$s:ident| $gen:expr, $reference:expr) => {
        $group.bench_function(concat!("reference/", $name), |b| {
            cycled(b, &$states, |$s| $reference)
        });
        side_by_side(
            $label,
            $name,
            |i| {
                let $s = black_box(&$states[i]);
                $gen
            },
            |i| {
                let $s = black_box(&$states[i]);
                $reference
            },
        );
    };
}

/// Times `f` on the states in turn, one per iteration (each through `black_box`, the result
/// through `keep`).
fn cycled<S, O>(b: &mut criterion::Bencher<'_>, states: &[S], mut f: impl FnMut(&S) -> O) {
    assert_eq!(states.len(), STATES);
    let mut k = 0;
    b.iter(|| {
        // `STATES` is a power of two: a mask, not a division, per iteration.
        k = (k + 1) & (STATES - 1);
        keep(&f(black_box(&states[k])))
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
        pair_rows!(
            group,
            states,
            $label,
            "inverse_dynamics",
            |s| Gen.inverse_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&s.qdd)),
            dynamics_reference::inverse_dynamics(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                black_box(s.qdd.as_slice()),
                &g,
                &z,
            )
        );
        pair_rows!(
            group,
            states,
            $label,
            "mass_matrix",
            |s| Gen.mass_matrix(black_box(&s.q)),
            dynamics_reference::mass_matrix(&robot, black_box(s.q.as_slice()))
        );
        // In place, into one matrix kept across the calls (its lower triangle).
        let mut lower = SMatrix::<f64, $nv, $nv>::zeros();
        pair_rows!(
            group,
            states,
            $label,
            "mass_matrix_lower_into",
            |s| {
                Gen.mass_matrix_lower_into(black_box(&s.q), &mut lower);
                keep(&lower);
            },
            dynamics_reference::mass_matrix(&robot, black_box(s.q.as_slice()))
        );
        pair_rows!(
            group,
            states,
            $label,
            "gravity",
            |s| Gen.gravity(black_box(&s.q)),
            dynamics_reference::gravity_forces(&robot, black_box(s.q.as_slice()), &g)
        );
        pair_rows!(
            group,
            states,
            $label,
            "coriolis",
            |s| Gen.coriolis(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::vel_quadratic_forces(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
            )
        );
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
        pair_rows!(
            group,
            states,
            $label,
            "forward_dynamics",
            |s| Gen.forward_dynamics(black_box(&s.q), black_box(&s.qd), black_box(&s.tau)),
            dynamics_reference::forward_dynamics(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                black_box(s.tau.as_slice()),
                &g,
                &z,
            )
        );
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

/// Central differences of `f` along the unit vectors of `x` (h = 1e-6), as
/// `tests/cases/generated_derivatives.rs` differentiates the reference (on a fixed base the tangent
/// directions of q are its unit vectors).
fn central(x: &[f64], f: impl Fn(&[f64]) -> DVector<f64>) -> DMatrix<f64> {
    let h = 1e-6;
    let mut m = DMatrix::zeros(x.len(), x.len());
    for j in 0..x.len() {
        let (mut plus, mut minus) = (x.to_vec(), x.to_vec());
        plus[j] += h;
        minus[j] -= h;
        m.set_column(j, &((f(&plus) - f(&minus)) / (2.0 * h)));
    }
    m
}

/// Every other public function of a fixed-base arm's generated code that has a counterpart in
/// the reference implementation, against it (the rows `bench_robot!` and `bench_derivatives!`
/// already time on the generated side get only their reference row here). The derivative
/// functions have no analytic counterpart in the reference: theirs is what the tests compare
/// them with, central differences of the reference (`2n` calls per Jacobian), with `M⁻¹`
/// from the reference's `M` by Cholesky.
macro_rules! bench_every {
    ($c:expr, $label:literal, $m:ident, $n:literal, $robot:expr) => {{
        use dynamics_tests::generated::$m::Robot as Gen;
        let robot = $robot;
        let states = states::<$n, $n>(|q, qd, qdd| Gen.inverse_dynamics(q, qd, qdd));
        let g = robot.gravity;
        let z = Vector6::zeros();
        let f_tip = Vector6::new(0.3, -0.2, 0.5, 4.0, -3.0, 6.0);
        // Two constraint rows on the joints, and their bias.
        let a =
            SMatrix::<f64, 2, $n>::from_fn(|i, j| if i == j { 1.0 } else { 0.1 * (i + j) as f64 });
        let a_dot_qd = SVector::<f64, 2>::new(0.2, -0.1);
        let (a_dyn, a_dot_qd_dyn) = (
            DMatrix::from_column_slice(2, $n, a.as_slice()),
            DVector::from_column_slice(a_dot_qd.as_slice()),
        );
        let id = |q: &[f64], qd: &[f64], qdd: &[f64]| {
            dynamics_reference::inverse_dynamics(&robot, q, qd, qdd, &g, &z)
        };
        let fd = |q: &[f64], qd: &[f64], tau: &[f64]| {
            dynamics_reference::forward_dynamics(&robot, q, qd, tau, &g, &z).expect("M > 0")
        };
        let minv = |q: &[f64]| {
            dynamics_reference::mass_matrix(&robot, q)
                .cholesky()
                .expect("M > 0")
                .inverse()
        };
        let mut group = $c.benchmark_group($label);
        macro_rules! pair {
            ($name:literal, |$s:ident| $gen:expr, $reference:expr) => {
                pair_rows!(group, states, $label, $name, |$s| $gen, $reference);
            };
            ($name:literal, elsewhere, |$s:ident| $gen:expr, $reference:expr) => {
                pair_rows!(
                    group,
                    states,
                    $label,
                    $name,
                    elsewhere,
                    |$s| $gen,
                    $reference
                );
            };
        }
        pair!(
            "kinetic_energy",
            |s| Gen.kinetic_energy(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::kinetic_energy(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice())
            )
        );
        pair!(
            "potential_energy",
            |s| Gen.potential_energy(black_box(&s.q)),
            dynamics_reference::potential_energy(&robot, black_box(s.q.as_slice()), &g)
        );
        pair!(
            "mass_matrix_dot",
            |s| Gen.mass_matrix_dot(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::mass_matrix_dot(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice())
            )
        );
        pair!(
            "coriolis_matrix",
            |s| Gen.coriolis_matrix(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::coriolis_matrix(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice())
            )
        );
        pair!(
            "friction",
            |s| Gen.friction(black_box(&s.qd)),
            dynamics_reference::friction_forces(&robot, black_box(s.qd.as_slice()), None)
        );
        pair!(
            "end_effector_pose",
            |s| Gen.end_effector_pose(black_box(&s.q)),
            dynamics_reference::end_effector_pose(&robot, black_box(s.q.as_slice()))
        );
        pair!(
            "jacobian_space",
            |s| Gen.jacobian_space(black_box(&s.q)),
            dynamics_reference::jacobian_space(&robot, black_box(s.q.as_slice()))
        );
        pair!(
            "jacobian_body",
            |s| Gen.jacobian_body(black_box(&s.q)),
            dynamics_reference::jacobian_body(&robot, black_box(s.q.as_slice()))
        );
        pair!(
            "jacobian_space_dot",
            |s| Gen.jacobian_space_dot(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::jacobian_space_dot(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice())
            )
        );
        pair!(
            "jacobian_body_dot",
            |s| Gen.jacobian_body_dot(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::jacobian_body_dot(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice())
            )
        );
        pair!(
            "end_effector_forces",
            |s| Gen.end_effector_forces(black_box(&s.q), black_box(&f_tip)),
            dynamics_reference::end_effector_forces(
                &robot,
                black_box(s.q.as_slice()),
                black_box(&f_tip)
            )
        );
        pair!(
            "inverse_dynamics_with_tip",
            |s| Gen.inverse_dynamics_with_tip(
                black_box(&s.q),
                black_box(&s.qd),
                black_box(&s.qdd),
                black_box(&f_tip)
            ),
            dynamics_reference::inverse_dynamics(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                black_box(s.qdd.as_slice()),
                &g,
                black_box(&f_tip)
            )
        );
        pair!(
            "forward_dynamics_with_tip",
            |s| Gen.forward_dynamics_with_tip(
                black_box(&s.q),
                black_box(&s.qd),
                black_box(&s.tau),
                black_box(&f_tip)
            ),
            dynamics_reference::forward_dynamics(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                black_box(s.tau.as_slice()),
                &g,
                black_box(&f_tip)
            )
        );
        pair!(
            "task_space_mass_matrix",
            |s| Gen.task_space_mass_matrix(black_box(&s.q)),
            dynamics_reference::task_space_mass_matrix(&robot, black_box(s.q.as_slice()))
        );
        pair!(
            "task_space_bias",
            |s| Gen.task_space_bias(black_box(&s.q), black_box(&s.qd)),
            dynamics_reference::task_space_bias(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                &g
            )
        );
        pair!(
            "constrained_forward_dynamics",
            |s| Gen.constrained_forward_dynamics(
                black_box(&s.q),
                black_box(&s.qd),
                black_box(&s.tau),
                black_box(&a),
                black_box(&a_dot_qd)
            ),
            dynamics_reference::constrained_forward_dynamics(
                &robot,
                black_box(s.q.as_slice()),
                black_box(s.qd.as_slice()),
                black_box(s.tau.as_slice()),
                black_box(&a_dyn),
                black_box(&a_dot_qd_dyn),
                &g
            )
        );
        pair!(
            "mass_matrix_and_bias",
            elsewhere,
            |s| Gen.mass_matrix_and_bias(black_box(&s.q), black_box(&s.qd)),
            {
                let (q, qd) = (black_box(s.q.as_slice()), black_box(s.qd.as_slice()));
                (
                    dynamics_reference::mass_matrix(&robot, q),
                    id(q, qd, &[0.0; $n]),
                )
            }
        );
        pair!(
            "mass_matrix_inverse",
            elsewhere,
            |s| Gen.mass_matrix_inverse(black_box(&s.q)),
            minv(black_box(s.q.as_slice()))
        );
        pair!(
            "gravity_derivative",
            elsewhere,
            |s| Gen.gravity_derivative(black_box(&s.q)),
            {
                central(black_box(s.q.as_slice()), |q| {
                    dynamics_reference::gravity_forces(&robot, q, &g)
                })
            }
        );
        let d_id = |q: &[f64], qd: &[f64], qdd: &[f64]| {
            (
                central(q, |q| id(q, qd, qdd)),
                central(qd, |qd| id(q, qd, qdd)),
            )
        };
        let d_fd = |q: &[f64], qd: &[f64], tau: &[f64]| {
            (
                central(q, |q| fd(q, qd, tau)),
                central(qd, |qd| fd(q, qd, tau)),
                minv(q),
            )
        };
        // The derivative functions of (q, q̇, x): ours against `$reference` of the three slices.
        macro_rules! of_three {
            ($name:literal, $gen:ident, $x:ident, |$q:ident, $qd:ident, $a:ident| $reference:expr) => {
                pair!(
                    $name,
                    elsewhere,
                    |s| Gen.$gen(black_box(&s.q), black_box(&s.qd), black_box(&s.$x)),
                    {
                        let ($q, $qd, $a) = (
                            black_box(s.q.as_slice()),
                            black_box(s.qd.as_slice()),
                            black_box(s.$x.as_slice()),
                        );
                        $reference
                    }
                );
            };
        }
        of_three!(
            "inverse_dynamics_derivatives",
            inverse_dynamics_derivatives,
            qdd,
            |q, qd, qdd| d_id(q, qd, qdd)
        );
        of_three!(
            "inverse_dynamics_with_derivatives",
            inverse_dynamics_with_derivatives,
            qdd,
            |q, qd, qdd| (id(q, qd, qdd), d_id(q, qd, qdd))
        );
        of_three!(
            "forward_dynamics_derivatives",
            forward_dynamics_derivatives,
            tau,
            |q, qd, tau| d_fd(q, qd, tau)
        );
        of_three!(
            "forward_dynamics_with_derivatives",
            forward_dynamics_with_derivatives,
            tau,
            |q, qd, tau| (fd(q, qd, tau), d_fd(q, qd, tau))
        );
        group.finish();
    }};
}

/// The same robot's code generated in f32 (`scalar = "f32"`), on the same states rounded to
/// f32, as `generated_f32/<function>` beside the f64 rows of `bench_robot!` and
/// `bench_every!`; with a fourth module, the f32 `no_std` code too (no CPU dispatch: the
/// portable copy, what an embedded target's code looks like on this machine), as
/// `generated_f32_no_std/<function>`. `bench/run.sh` prints them side by side.
macro_rules! bench_f32 {
    ($c:expr, $label:literal, $m64:ident, $m32:ident, $nq:literal, $nv:literal $(, $no_std:ident)?) => {{
        use dynamics_tests::generated::$m64::Robot as Gen64;
        let states: Vec<_> = states::<$nq, $nv>(|q, qd, qdd| Gen64.inverse_dynamics(q, qd, qdd))
            .iter()
            .map(|s| {
                (
                    s.q.cast::<f32>(),
                    s.qd.cast::<f32>(),
                    s.qdd.cast::<f32>(),
                    s.tau.cast::<f32>(),
                )
            })
            .collect();
        let mut group = $c.benchmark_group($label);
        macro_rules! rows {
            ($prefix:literal, $m:ident, $kinematics:literal) => {{
                use dynamics_tests::generated::$m::Robot as Gen;
                group.bench_function(concat!($prefix, "/inverse_dynamics"), |b| {
                    cycled(b, &states, |s| {
                        Gen.inverse_dynamics(black_box(&s.0), black_box(&s.1), black_box(&s.2))
                    })
                });
                group.bench_function(concat!($prefix, "/coriolis"), |b| {
                    cycled(b, &states, |s| Gen.coriolis(black_box(&s.0), black_box(&s.1)))
                });
                group.bench_function(concat!($prefix, "/gravity"), |b| {
                    cycled(b, &states, |s| Gen.gravity(black_box(&s.0)))
                });
                group.bench_function(concat!($prefix, "/mass_matrix"), |b| {
                    cycled(b, &states, |s| Gen.mass_matrix(black_box(&s.0)))
                });
                group.bench_function(concat!($prefix, "/forward_dynamics"), |b| {
                    cycled(b, &states, |s| {
                        Gen.forward_dynamics(black_box(&s.0), black_box(&s.1), black_box(&s.3))
                    })
                });
                if $kinematics {
                    group.bench_function(concat!($prefix, "/end_effector_pose"), |b| {
                        cycled(b, &states, |s| Gen.end_effector_pose(black_box(&s.0)))
                    });
                    group.bench_function(concat!($prefix, "/jacobian_space"), |b| {
                        cycled(b, &states, |s| Gen.jacobian_space(black_box(&s.0)))
                    });
                }
            }};
        }
        rows!("generated_f32", $m32, true);
        // The shipped robot's tip may differ from the benchmark's: dynamics only.
        $(rows!("generated_f32_no_std", $no_std, false);)?
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
        // `<name>_x8_batch` and `<name>_x8_single`, and the two [`side_by_side`] (the batch as
        // "ours", the single calls as "reference": the ratio is the batch's gain per state).
        macro_rules! rows {
            ($name:literal, $batch:expr, $single:expr) => {
                group.bench_function(concat!("generated/", $name, "_x8_batch"), |b| {
                    b.iter(|| keep(&$batch))
                });
                group.bench_function(concat!("generated/", $name, "_x8_single"), |b| {
                    b.iter(|| keep(&$single))
                });
                side_by_side($label, concat!($name, "_x8"), |_| $batch, |_| $single);
            };
        }
        rows!(
            "inverse_dynamics",
            Gen.inverse_dynamics_batch(black_box(&q), black_box(&qd), black_box(&qdd)),
            {
                let (q, qd, qdd) = (black_box(&q), black_box(&qd), black_box(&qdd));
                let out: [SVector<f64, $nv>; B] =
                    std::array::from_fn(|l| Gen.inverse_dynamics(&q[l], &qd[l], &qdd[l]));
                out
            }
        );
        rows!(
            "forward_dynamics",
            Gen.forward_dynamics_batch(black_box(&q), black_box(&qd), black_box(&tau)),
            {
                let (q, qd, tau) = (black_box(&q), black_box(&qd), black_box(&tau));
                let out: [SVector<f64, $nv>; B] =
                    std::array::from_fn(|l| Gen.forward_dynamics(&q[l], &qd[l], &tau[l]));
                out
            }
        );
        rows!("mass_matrix", Gen.mass_matrix_batch(black_box(&q)), {
            let q = black_box(&q);
            let out: [nalgebra::SMatrix<f64, $nv, $nv>; B] =
                std::array::from_fn(|l| Gen.mass_matrix(&q[l]));
            out
        });
        rows!("gravity", Gen.gravity_batch(black_box(&q)), {
            let q = black_box(&q);
            let out: [SVector<f64, $nv>; B] = std::array::from_fn(|l| Gen.gravity(&q[l]));
            out
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
    bench_every!(c, "ur5", urdf_ur5, 6, load("ur5", "tool0"));
    bench_every!(c, "panda", urdf_panda, 7, load("panda", "panda_hand_tcp"));
    bench_every!(c, "rand7", urdf_rand7, 7, load("rand7", "ee_link"));
    bench_f32!(
        c,
        "ur5",
        urdf_ur5,
        f32_urdf_ur5,
        6,
        6,
        shipped_ur5_f32_no_std
    );
    bench_f32!(c, "panda", urdf_panda, f32_urdf_panda, 7, 7);
    bench_f32!(c, "rand7", urdf_rand7, f32_urdf_rand7, 7, 7);
    bench_f32!(c, "solo12", tree_solo12, f32_tree_solo12, 19, 18);
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
