//! The states the benchmarks (`benches/dynamics.rs`) and the instruction counts
//! (`examples/calls.rs`, `bench/run.sh` with `CALLGRIND=1`) cycle through, and how both keep a
//! result ([`keep`]).

use nalgebra::SVector;
use std::hint::black_box;

/// States cycled through by the benchmarks: 1,024, as in Pinocchio's benchmark (`bench/pinocchio_bench.cpp`).
pub const STATES: usize = 1024;

/// One state: q, q̇, q̈ and τ = ID(q, q̇, q̈) (the input of forward dynamics).
#[derive(Clone, Debug)]
pub struct State<const NQ: usize, const NV: usize> {
    /// Joint positions.
    pub q: SVector<f64, NQ>,
    /// Joint velocities.
    pub qd: SVector<f64, NV>,
    /// Joint accelerations.
    pub qdd: SVector<f64, NV>,
    /// The inverse dynamics of the above.
    pub tau: SVector<f64, NV>,
}

/// [`STATES`] random states drawn as Pinocchio's benchmark draws them: angles uniform in
/// [−π, π], velocities and accelerations in [−2, 2] (a fixed-seed SplitMix64, so every run
/// times the same states; on a floating base q[3..7], the quaternion, is normalised inside the
/// generated functions).
pub fn states<const NQ: usize, const NV: usize>(
    inverse_dynamics: impl Fn(
        &SVector<f64, NQ>,
        &SVector<f64, NV>,
        &SVector<f64, NV>,
    ) -> SVector<f64, NV>,
) -> Vec<State<NQ, NV>> {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = move |lo: f64, hi: f64| {
        seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..STATES)
        .map(|_| {
            let q = SVector::from_fn(|_, _| uniform(-std::f64::consts::PI, std::f64::consts::PI));
            let qd = SVector::from_fn(|_, _| uniform(-2.0, 2.0));
            let qdd = SVector::from_fn(|_, _| uniform(-2.0, 2.0));
            let tau = inverse_dynamics(&q, &qd, &qdd);
            State { q, qd, qdd, tau }
        })
        .collect()
}

/// A result through `black_box` by reference: computed and in memory where the callee wrote
/// it, and not copied again (with one entry read, the optimiser would compute that entry only:
/// the UR5's g₁ is a constant 0). By value (criterion's `iter`, `black_box(out)`) the harness
/// copied every result once more, a `memcpy` of up to 3 KB on the arms that Pinocchio's
/// benchmark (writing into its `Data`) and the reference's results (heap matrices, a pointer
/// and two lengths by value) never paid.
pub fn keep<O>(out: &O) {
    black_box(out);
}
