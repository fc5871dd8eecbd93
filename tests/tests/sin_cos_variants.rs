//! The `*_from_sin_cos` variants (`sin_cos_variants`, `dynamics-gen/src/emit/given_sin_cos.rs`)
//! fed `sin_cos(q)` equal the functions they vary: inverse dynamics, mass matrix, coriolis,
//! gravity, forward dynamics and kinetic energy of the Panda (with its derivative functions),
//! Solo-12 (a floating tree), an f32 `no_std` UR5 and a chain with mimic joints (whose angles
//! with a multiplier or an offset the variants compute from `q`), at 256 random states each.
//! Bit for bit: both take the same sines and cosines and run the same operations, and
//! `sin_cos`, the functions that have a variant and the variants are dispatched together or
//! not at all (the mimic chain's `sin_cos` takes two angles and its functions four: alone, the
//! helper would stay portable while they run their AVX-512 or AVX2 copy, whose fused
//! polynomial rounds some sines differently).

#![allow(missing_docs)]

use dynamics_tests::generated::{mimic_301_f64, shipped_ur5_f32_no_std, tree_solo12, urdf_panda};

#[test]
fn variants_fed_sin_cos_give_the_functions_bits() {
    type Differ = fn(&[f64], &[f64], &[f64]) -> (usize, usize, f64);
    // (name, helper, dimensions).
    let cases: [(&str, Differ, (usize, usize)); 4] = [
        (
            "urdf_panda",
            urdf_panda::sin_cos_variants_differ,
            urdf_panda::SIN_COS_DIMS,
        ),
        (
            "tree_solo12",
            tree_solo12::sin_cos_variants_differ,
            tree_solo12::SIN_COS_DIMS,
        ),
        (
            "shipped_ur5_f32_no_std",
            shipped_ur5_f32_no_std::sin_cos_variants_differ,
            shipped_ur5_f32_no_std::SIN_COS_DIMS,
        ),
        (
            "mimic_301_f64",
            mimic_301_f64::sin_cos_variants_differ,
            mimic_301_f64::SIN_COS_DIMS,
        ),
    ];
    // Seeded uniform numbers in [−1, 1).
    let mut s = 0x51c0_u64;
    let mut uniform = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for (name, differ, (nq, nv)) in cases {
        let (mut compared, mut differing, mut worst) = (0, 0, 0.0f64);
        for _ in 0..256 {
            let q: Vec<f64> = (0..nq).map(|_| 3.0 * uniform()).collect();
            let v: Vec<f64> = (0..nv).map(|_| 2.0 * uniform()).collect();
            let a: Vec<f64> = (0..nv).map(|_| 5.0 * uniform()).collect();
            let (c, d, w) = differ(&q, &v, &a);
            compared += c;
            differing += d;
            worst = worst.max(w);
        }
        println!("{name}: {differing} of {compared} values differ (largest relative difference {worst:e})");
        assert_eq!(
            differing, 0,
            "{name}: the variants fed sin_cos(q) differ from the functions (largest relative difference {worst:e})"
        );
    }
}
