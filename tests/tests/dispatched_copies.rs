//! The AVX2 copy of a dispatched function runs the same fused body as its AVX-512 copy
//! (`dynamics-gen/src/emit/dispatch.rs`), so the two must give the same bits. A machine with
//! AVX-512 runs only the AVX-512 copy through the public functions, and a machine without it
//! only the AVX2 one; here both are called directly, on the UR5, the Panda, Solo-12 (a floating
//! tree, in f64 and in f32: its legs in `[f32; 4]` packs), the TALOS upper body (its arms in
//! packs of two `f64` lanes, 128-bit operations) and an f32 chain, at 256 random states each. Where the CPU lacks either instruction set, or the binary is compiled with
//! AVX-512 or with AVX2 and FMA (no such pair of copies), the test says so and checks nothing.
//!
//! The batch functions' AVX2 bodies of instructions (the runtime's `Avx2` token) run through
//! the public functions on a machine with AVX-512 only where `B` fills AVX2 registers but not
//! AVX-512 ones, and for the largest bodies only; here the Panda's forward dynamics (a smaller
//! body) is called directly too, against the single-state AVX2 copy state by state.

#![allow(missing_docs)]

/// A module's comparison at one state `(q, q̇, q̈ or τ)`: (entries compared, entries whose
/// bits differ), or `None` where the CPU lacks the features.
#[allow(dead_code)]
type Differ = fn(&[f64], &[f64], &[f64]) -> Option<(usize, usize)>;

/// Each case's `differ` at `states` seeded random states (`seed`): no entry may differ
/// between `what`; `lacks` is said, and nothing checked, where the CPU lacks the features.
#[cfg(all(
    target_arch = "x86_64",
    not(target_feature = "avx512f"),
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
fn compare(
    cases: &[(&str, Differ, (usize, usize))],
    seed: u64,
    states: usize,
    what: &str,
    lacks: &str,
) {
    // Seeded uniform numbers in [−1, 1).
    let mut s = seed;
    let mut uniform = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for &(name, differ, (nq, nv)) in cases {
        let (mut compared, mut differing) = (0, 0);
        for _ in 0..states {
            let q: Vec<f64> = (0..nq).map(|_| 3.0 * uniform()).collect();
            let v: Vec<f64> = (0..nv).map(|_| 2.0 * uniform()).collect();
            let a: Vec<f64> = (0..nv).map(|_| 5.0 * uniform()).collect();
            let Some((c, d)) = differ(&q, &v, &a) else {
                eprintln!("{lacks}");
                return;
            };
            compared += c;
            differing += d;
        }
        assert!(compared > 0, "{name}: nothing compared");
        assert_eq!(
            differing, 0,
            "{name}: {differing} of {compared} entries differ between {what}"
        );
        eprintln!("{name}: {compared} entries, the same bits in {what}");
    }
}

#[cfg(all(
    target_arch = "x86_64",
    not(target_feature = "avx512f"),
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[test]
fn avx2_copies_give_the_avx512_copies_bits() {
    let cases: [(&str, Differ, (usize, usize)); 6] = [
        (
            "shipped_ur5",
            dynamics_tests::generated::shipped_ur5::dispatched_copies_differ,
            dynamics_tests::generated::shipped_ur5::COPIES_DIMS,
        ),
        (
            "urdf_panda",
            dynamics_tests::generated::urdf_panda::dispatched_copies_differ,
            dynamics_tests::generated::urdf_panda::COPIES_DIMS,
        ),
        (
            "tree_solo12",
            dynamics_tests::generated::tree_solo12::dispatched_copies_differ,
            dynamics_tests::generated::tree_solo12::COPIES_DIMS,
        ),
        (
            "tree_talos_upper_body",
            dynamics_tests::generated::tree_talos_upper_body::dispatched_copies_differ,
            dynamics_tests::generated::tree_talos_upper_body::COPIES_DIMS,
        ),
        (
            "random_104_f32",
            dynamics_tests::generated::random_104_f32::dispatched_copies_differ,
            dynamics_tests::generated::random_104_f32::COPIES_DIMS,
        ),
        (
            "f32_tree_solo12",
            dynamics_tests::generated::f32_tree_solo12::dispatched_copies_differ,
            dynamics_tests::generated::f32_tree_solo12::COPIES_DIMS,
        ),
    ];
    compare(
        &cases,
        0x5eed,
        256,
        "the AVX-512 and the AVX2 copy",
        "this CPU lacks AVX-512 or AVX2 and FMA: the copies are not compared",
    );
}

#[cfg(all(
    target_arch = "x86_64",
    not(target_feature = "avx512f"),
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[test]
fn avx2_batch_bodies_give_the_single_calls_bits() {
    let cases: [(&str, Differ, (usize, usize)); 1] = [(
        "urdf_panda",
        dynamics_tests::generated::urdf_panda::batch_copies_differ,
        dynamics_tests::generated::urdf_panda::BATCH_COPIES_DIMS,
    )];
    compare(
        &cases,
        0xba7c,
        16,
        "the AVX2 batch body and single calls",
        "this CPU lacks AVX2 and FMA: the batch bodies are not compared",
    );
}
