//! The batch functions (`inverse_dynamics_batch`, `forward_dynamics_batch`,
//! `mass_matrix_batch`, `gravity_batch`) against the single-state functions, state by state,
//! on the robots of `with_batch_cases!`: chains and trees, fixed and floating base, mimic
//! joints, friction, run-time parameters, both derivation routes, f64 and f32, std and no_std,
//! and a quadruped whose largest body runs on lanes in the AVX-512 and AVX2 copies alone (a
//! whole register of states, on a CPU with either) and state by state otherwise
//! (`tests/dispatched_copies.rs` also calls the AVX2 bodies directly).
//!
//! A batch lane is the single-state code's arithmetic on that state, its multiply-adds fused
//! where the single-state code's are, and the run-time CPU dispatch picks copies that fuse
//! alike (portable, or AVX-512 and AVX2) for both: the results are the same bits, on every target and CPU.

use nalgebra::SVector;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The robots checked.
static CHECKED: AtomicUsize = AtomicUsize::new(0);

/// The largest entry of `a − b` over the largest of `b` (plus one, for zero results).
fn rel<const R: usize, const C: usize>(
    a: &nalgebra::SMatrix<f64, R, C>,
    b: &nalgebra::SMatrix<f64, R, C>,
) -> f64 {
    (a - b).amax() / (b.amax() + 1.0)
}

macro_rules! batch {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {{
        // Four states, and a whole 512-bit register of them (8 `f64`, 16 `f32`): there the
        // AVX-512 copy of a large batch body computes with AVX-512 instructions of its own.
        // Four `f64` states fill an AVX2 register but not an AVX-512 one: on a CPU with
        // AVX-512, a body too large for the vectoriser runs its AVX2 copy's instructions, the
        // others their AVX-512 copy's vectoriser body; four `f32` states fill neither.
        // Each with every angle within the polynomial kernel's range (10⁶ in f64, 10⁴ in
        // f32), and with one beyond it (a dispatched copy's kernel then leaves the batch to
        // single-state calls; a portable body's takes that lane's fallback in line).
        for far in [false, true] {
            check::<4>(far);
            check::<{ 64 / std::mem::size_of::<$s>() }>(far);
        }
        CHECKED.fetch_add(1, Ordering::SeqCst);
        fn check<const B: usize>(far: bool) {
            use dynamics_tests::generated::$m::Robot;
            let r = Robot::DEFAULT;
            let mut q: [SVector<$s, $nq>; B] = std::array::from_fn(|l| {
                SVector::from_fn(|i, _| 0.3 + 0.1 * i as $s - 0.45 * l as $s)
            });
            if far {
                q[2][$nq - 1] = 2.0e6;
            }
            let qd: [SVector<$s, $nv>; B] = std::array::from_fn(|l| {
                SVector::from_fn(|i, _| 0.5 - 0.2 * i as $s + 0.3 * l as $s)
            });
            let x: [SVector<$s, $nv>; B] =
                std::array::from_fn(|l| SVector::from_fn(|i, _| 0.7 * i as $s - 1.0 + l as $s));
            let tau = r.inverse_dynamics_batch(&q, &qd, &x);
            let qdd = r.forward_dynamics_batch(&q, &qd, &x);
            let m = r.mass_matrix_batch(&q);
            let g = r.gravity_batch(&q);
            for l in 0..B {
                let pairs = [
                    (
                        "inverse_dynamics",
                        tau[l].map(f64::from),
                        r.inverse_dynamics(&q[l], &qd[l], &x[l]).map(f64::from),
                    ),
                    (
                        "forward_dynamics",
                        qdd[l].map(f64::from),
                        r.forward_dynamics(&q[l], &qd[l], &x[l]).map(f64::from),
                    ),
                    (
                        "gravity",
                        g[l].map(f64::from),
                        r.gravity(&q[l]).map(f64::from),
                    ),
                ];
                for (name, a, b) in pairs {
                    assert!(
                        a == b,
                        "{}: {name}_batch lane {l}: {a} against {b} (relative difference {:e})",
                        stringify!($m),
                        rel(&a, &b)
                    );
                }
                let (a, b) = (m[l].map(f64::from), r.mass_matrix(&q[l]).map(f64::from));
                assert!(
                    a == b,
                    "{}: mass_matrix_batch lane {l}: {a} against {b} (relative difference {:e})",
                    stringify!($m),
                    rel(&a, &b)
                );
            }
            // Not vacuous: the states differ, and so do the results.
            assert!(tau[0] != tau[1] && qdd[0] != qdd[2], "{}", stringify!($m));
        }
    }};
}

#[test]
fn batch_functions_equal_single_state_calls() {
    dynamics_tests::with_batch_cases!(batch);
    let checked = CHECKED.load(Ordering::SeqCst);
    assert!(checked >= 12, "only {checked} robots");
}
