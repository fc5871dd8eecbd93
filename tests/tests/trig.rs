//! The generated files' `joint_sin_cos` helper (dynamics-gen/src/emit/trig.rs) against the
//! platform's `sin` and `cos`: at most 2 ulp for |x| ≤ 10⁶ (f64) and |x| ≤ 10⁴ (f32), on
//! random arguments over the whole range, on small ones, and on the doubles closest to
//! multiples of π/2 (where the reduced argument cancels); beyond the range, and for NaN and
//! infinities, the platform's values. The polynomials are checked both as the portable code
//! evaluates them and fused, as the AVX-512 copy of a dispatched function does.

use dynamics_tests::trig_kernels::{F32NoStd, F32Std, F64NoStd, F64Std};

/// A kernel over 8 lanes.
type Kernel<T> = fn([T; 8]) -> ([T; 8], [T; 8]);

/// splitmix64: a seeded generator for the arguments.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [−a, a].
    fn uniform(&mut self, a: f64) -> f64 {
        ((self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * a
    }
}

/// |x − y| in units of the spacing of doubles at `y` (the exact value's neighbourhood).
fn ulps_f64(x: f64, y: f64) -> f64 {
    let spacing = if y == 0.0 {
        f64::from_bits(1)
    } else {
        let a = y.abs();
        f64::from_bits(a.to_bits() + 1) - a
    };
    (x - y).abs() / spacing
}

/// The same for f32, `y` computed in f64.
fn ulps_f32(x: f32, y: f64) -> f64 {
    let yf = y as f32;
    let spacing = if yf == 0.0 {
        f64::from(f32::from_bits(1))
    } else {
        let a = yf.abs();
        f64::from(f32::from_bits(a.to_bits() + 1) - a)
    };
    (f64::from(x) - y).abs() / spacing
}

/// The largest error (sin, cos, and the argument of each) over `xs`, by the f64 kernel `f`.
fn worst_f64(xs: &[f64], f: Kernel<f64>) -> (f64, f64, f64, f64) {
    let mut worst = (0.0, 0.0, 0.0, 0.0);
    for chunk in xs.chunks_exact(8) {
        let x: [f64; 8] = chunk.try_into().expect("8 elements");
        let (s, c) = f(x);
        for i in 0..8 {
            let es = ulps_f64(s[i], x[i].sin());
            let ec = ulps_f64(c[i], x[i].cos());
            if es > worst.0 {
                worst.0 = es;
                worst.1 = x[i];
            }
            if ec > worst.2 {
                worst.2 = ec;
                worst.3 = x[i];
            }
        }
    }
    worst
}

fn worst_f32(xs: &[f32], f: Kernel<f32>) -> (f64, f32, f64, f32) {
    let mut worst = (0.0, 0.0, 0.0, 0.0);
    for chunk in xs.chunks_exact(8) {
        let x: [f32; 8] = chunk.try_into().expect("8 elements");
        let (s, c) = f(x);
        for i in 0..8 {
            let es = ulps_f32(s[i], f64::from(x[i]).sin());
            let ec = ulps_f32(c[i], f64::from(x[i]).cos());
            if es > worst.0 {
                worst.0 = es;
                worst.1 = x[i];
            }
            if ec > worst.2 {
                worst.2 = ec;
                worst.3 = x[i];
            }
        }
    }
    worst
}

/// The doubles nearest to k·π/2 (and their neighbours) for k up to `max_k`, every `step`.
fn near_multiples(max_k: i64, step: usize) -> Vec<f64> {
    let mut xs = Vec::new();
    for k in (1..=max_k).step_by(step) {
        let x = k as f64 * std::f64::consts::FRAC_PI_2;
        for sign in [1.0, -1.0] {
            let b = x.to_bits();
            for d in [b - 2, b - 1, b, b + 1, b + 2] {
                xs.push(sign * f64::from_bits(d));
            }
        }
    }
    xs
}

fn f64_arguments() -> Vec<f64> {
    let mut rng = Rng(0x5eed);
    let mut xs: Vec<f64> = (0..800_000).map(|_| rng.uniform(1e4)).collect();
    xs.extend((0..200_000).map(|_| rng.uniform(10.0)));
    xs.extend((0..100_000).map(|_| rng.uniform(1e6)));
    // Small magnitudes, 1e-300 to 1, both signs.
    xs.extend((0..50_000).map(|_| {
        let e = rng.uniform(150.0) - 150.0;
        let x = 2f64.powf(e * 2.0);
        if rng.next() & 1 == 0 {
            x
        } else {
            -x
        }
    }));
    xs.extend(near_multiples(636_619, 7));
    xs.extend([0.0, -0.0, 1e-320, -1e-320, 1e6, -1e6, 1e4, -1e4]);
    while !xs.len().is_multiple_of(8) {
        xs.push(0.5);
    }
    xs
}

#[test]
fn f64_within_two_ulp() {
    let xs = f64_arguments();
    for (name, f) in [
        ("std", F64Std::sin_cos::<8> as fn(_) -> _),
        ("std, fused", F64Std::sin_cos_fused::<8>),
        ("no_std", F64NoStd::sin_cos::<8>),
    ] {
        let (es, xs_, ec, xc) = worst_f64(&xs, f);
        println!(
            "f64 {name}: {} arguments, worst sin {es:.3} ulp at {xs_:e}, worst cos {ec:.3} ulp at {xc:e}",
            xs.len()
        );
        assert!(es <= 2.0 && ec <= 2.0, "f64 {name}: {es} / {ec} ulp");
    }
}

#[test]
fn f32_within_two_ulp() {
    let mut rng = Rng(0xf32);
    let mut xs: Vec<f32> = (0..800_000).map(|_| rng.uniform(1e4) as f32).collect();
    xs.extend((0..200_000).map(|_| rng.uniform(10.0) as f32));
    xs.extend((0..50_000).map(|_| 2f64.powf(rng.uniform(60.0) - 60.0) as f32));
    // Every f32 nearest to k·π/2 and its neighbours, k ≤ 6366 (|x| ≤ 10⁴).
    for k in 1..=6366 {
        let x = (k as f64 * std::f64::consts::FRAC_PI_2) as f32;
        let b = x.to_bits();
        for d in [b - 1, b, b + 1] {
            xs.push(f32::from_bits(d));
            xs.push(-f32::from_bits(d));
        }
    }
    while !xs.len().is_multiple_of(8) {
        xs.push(0.5);
    }
    for (name, f) in [
        ("std", F32Std::sin_cos::<8> as fn(_) -> _),
        ("std, fused", F32Std::sin_cos_fused::<8>),
        ("no_std", F32NoStd::sin_cos::<8>),
    ] {
        let (es, xs_, ec, xc) = worst_f32(&xs, f);
        println!(
            "f32 {name}: {} arguments, worst sin {es:.3} ulp at {xs_:e}, worst cos {ec:.3} ulp at {xc:e}",
            xs.len()
        );
        assert!(es <= 2.0 && ec <= 2.0, "f32 {name}: {es} / {ec} ulp");
    }
}

#[test]
fn beyond_the_range_and_special_values() {
    let x = [
        1.5e6,
        -3e7,
        1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        0.0,
        -0.0,
    ];
    for (s, c) in [F64Std::sin_cos(x), F64NoStd::sin_cos(x)] {
        for i in 0..5 {
            assert!(ulps_f64(s[i], x[i].sin()) <= 1.0 || (s[i].is_nan() && x[i].is_infinite()));
            assert!(ulps_f64(c[i], x[i].cos()) <= 1.0 || (c[i].is_nan() && x[i].is_infinite()));
        }
        assert!(s[3].is_nan() && c[3].is_nan() && s[5].is_nan() && c[5].is_nan());
        assert_eq!((s[6], c[6]), (0.0, 1.0));
        assert_eq!(c[7], 1.0);
    }
    let x = [2e4f32, -1e9, f32::INFINITY, f32::NAN];
    for (s, c) in [F32Std::sin_cos(x), F32NoStd::sin_cos(x)] {
        for i in 0..2 {
            assert!(ulps_f32(s[i], f64::from(x[i]).sin()) <= 1.0);
            assert!(ulps_f32(c[i], f64::from(x[i]).cos()) <= 1.0);
        }
        assert!(s[2].is_nan() && c[2].is_nan() && s[3].is_nan() && c[3].is_nan());
    }
}

/// The generated functions call the helper with their angles padded to the target's vector
/// width (`sin_cos_lanes`): a whole number of registers, at most one register more than the
/// angles, and the first `K` results the same bits as unpadded.
#[test]
fn padding_to_the_target_width_changes_no_result() {
    let width = if cfg!(target_feature = "avx512f") {
        8
    } else if cfg!(target_feature = "avx") {
        4
    } else {
        2
    };
    for k in 1..=40 {
        let p = F64Std::lanes(k);
        assert!(
            p >= k && p.is_multiple_of(width) && p < k + width,
            "f64: {k} angles padded to {p}"
        );
        let p = F32Std::lanes(k);
        assert!(
            p >= k && p.is_multiple_of(2 * width) && p < k + 2 * width,
            "f32: {k} angles padded to {p}"
        );
    }
    let x = [0.3, -2.0, 1e5, 7.5, -0.001];
    let (s, c) = F64Std::sin_cos(x);
    let (sp, cp) = F64Std::sin_cos_padded::<5, { F64Std::lanes(5) }>(x);
    assert_eq!((&sp[..5], &cp[..5]), (&s[..], &c[..]));
    let (s, c) = F64NoStd::sin_cos(x);
    let (sp, cp) = F64NoStd::sin_cos_padded::<5, { F64NoStd::lanes(5) }>(x);
    assert_eq!((&sp[..5], &cp[..5]), (&s[..], &c[..]));
    let x = x.map(|v| v as f32);
    let (s, c) = F32Std::sin_cos(x);
    let (sp, cp) = F32Std::sin_cos_padded::<5, { F32Std::lanes(5) }>(x);
    assert_eq!((&sp[..5], &cp[..5]), (&s[..], &c[..]));
    let (s, c) = F32NoStd::sin_cos(x);
    let (sp, cp) = F32NoStd::sin_cos_padded::<5, { F32NoStd::lanes(5) }>(x);
    assert_eq!((&sp[..5], &cp[..5]), (&s[..], &c[..]));
}
