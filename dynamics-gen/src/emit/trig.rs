//! The `joint_sin_cos` helper of a generated impl: the sine and cosine of every joint angle at
//! once, with no call into the platform's or `libm`'s trigonometry on the normal path.
//!
//! The angles are padded with zeros to a whole number of the target's vector registers
//! (`sin_cos_lanes`, chosen by `cfg!(target_feature)` where the generated code is compiled:
//! a fixed padding to 4 f64 lanes had SSE2 compute 8 lanes for 5 angles). For each element x
//! (a loop over a fixed-size array with no branches, so that LLVM vectorises it across the
//! joints):
//!
//! 1. **Range reduction** (Cody–Waite): k = round(x · 2/π) by adding and subtracting
//!    1.5 · 2^p (p the mantissa width; the quadrant k mod 4 is then the low bits of the sum's
//!    representation), and r = x − k · π/2 in double-length arithmetic, with π/2 split into
//!    pieces short enough that k times each is exact (f64: three 32-bit pieces and a 53-bit
//!    one, exact for |k| < 2²¹; f32: four 11-bit pieces and a 24-bit one, exact for
//!    |k| < 2¹³). The first difference is exact (Sterbenz), the others are error-free
//!    transformations (Knuth's two-sum), so r = r_h + r_l carries about 100 (f64) or 60
//!    (f32) correct bits even where x is close to a multiple of π/2 and r cancels. r_h is
//!    the leading part as the subtractions leave it (not renormalised against r_l), so that
//!    the polynomials start while r_l is still being summed. Where the multiply-adds are
//!    fused (`std` code compiled with FMA, and the dispatched AVX-512 and AVX2 copies), π/2 is
//!    three full-precision pieces P₁ + P₂ + P₃ instead (π/2 to 3 × 53 bits for f64, 3 × 24
//!    for f32): x − k·P₁ is exact, and h = (x − k·P₁) − k·P₂ rounds once, relative to the
//!    reduced argument itself; the last term −k·P₃ (below 10⁻²⁷ for f64) is added to h only
//!    where r is the leading term of sin r, so that the polynomials start one multiply-add
//!    sooner (r within about an ulp of the exact reduced argument; 4 operations per element
//!    where the pieces above take 20 for f64, 28 for f32, and no correction in step 3).
//! 2. **Polynomials** on |r_h| ≤ π/4 (z = r_h²): for f64, minimax polynomials through r¹³
//!    (sin) and r¹⁴ (cos) whose relative errors there are below 0.04 ulp (`SIN_F64`); for
//!    f32, the Taylor series through r⁹ and r¹⁰ (below 0.05 ulp); sin as r + r·z·P(z); cos,
//!    fused, as 1 + z·T(z) with T = −1/2 + z·Q(z), otherwise as
//!    w + ((1 − w) − z/2 + z² Q(z)) with w = 1 − z/2, which keeps the rounding error of w
//!    where z·T and the sum would round apart. Evaluated by Estrin's scheme (pairs, then
//!    joined by z² and z⁴), with fused multiply-adds where the code has FMA: the sines and
//!    cosines head every function's longest dependency chain, and Estrin cuts their depth to
//!    three multiply-adds after z and one more for the result. (Fused, the reduction's third
//!    multiply-add off the path and cos no longer three operations after sin took 7 of the
//!    kernel's 43 cycles of latency, by the instructions' latencies; measured, 2026-12-04,
//!    in `docs/performance.md`.)
//! 3. **Correction and quadrant**: where r has a low part, sin r ≈ S + r_l C and
//!    cos r ≈ C − r_l S; then, by k mod 4,
//!    (sin x, cos x) = (S, C), (C, −S), (−S, −C) or (−C, S), by selects and sign-bit flips.
//!
//! Accuracy (tested against the platform's `sin` and `cos` in `tests/tests/trig.rs`): at
//! most 2 ulp for |x| ≤ 10⁶ (f64) and |x| ≤ 10⁴ (f32); measured worst, among the floats
//! nearest to multiples of π/2 and random ones: f64 1.0 ulp from the platform's values,
//! fused or not; f32 1.17 ulp from the exact ones, 1.46 fused. Beyond those bounds, where the
//! products k · π/2 stop being exact, and for infinities, the elements go to
//! `f64::sin_cos` (`std`) or `libm` (`no_std`): a branch that is never taken for the angles
//! of a robot's joints. NaN gives NaN.

use super::literal::float_tokens;
use crate::options::Scalar;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

/// The f64 polynomials: sin r = r + r·z·P(z) and cos r = 1 − z/2 + z²·Q(z), z = r², with the
/// coefficients of P and Q (lowest degree first) minimax for the relative error on
/// |r| ≤ π/4 by the Remez exchange in 60-digit arithmetic: 3.6·10⁻¹⁸ for sin, 2.0·10⁻¹⁹ for
/// cos (0.03 and 0.002 ulp), before rounding the coefficients to f64. One degree fewer gives
/// 45 and 2.9 ulp.
const SIN_F64: [f64; 6] = [
    -0.1666666666666663,
    0.008333333333322118,
    -0.00019841269829589542,
    2.75573136213867e-06,
    -2.5050747762987452e-08,
    1.589623016401917e-10,
];
/// See [`SIN_F64`].
const COS_F64: [f64; 6] = [
    0.04166666666666665,
    -0.0013888888888882846,
    2.480158729463356e-05,
    -2.7557315740699307e-07,
    2.0875898081312824e-09,
    -1.1368002341468553e-11,
];

/// 1/n!, rounded once (n! is exact in f64 up to 22!).
fn inverse_factorial(n: u32) -> f64 {
    1.0 / (1..=n).map(f64::from).product::<f64>()
}

/// The tokens of the helper for `scalar`; `no_std` picks `libm` for the out-of-range
/// elements.
pub fn sin_cos_helper(scalar: Scalar, no_std: bool) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let lit = |x: f64| float_tokens(x, scalar);
    // π/2 split into pieces (see the module doc), computed from 100 digits of π.
    let (pieces, round, limit, sign_shift): (&[f64], f64, f64, u32) = match scalar {
        Scalar::F64 => (
            &[
                1.5707963267341256,
                6.077100506303966e-11,
                2.0222662487111665e-21,
                8.4784276603689e-32,
            ],
            6755399441055744.0, // 1.5 · 2⁵²
            1e6,
            62,
        ),
        Scalar::F32 => (
            &[
                1.5703125,
                0.0004837512969970703,
                7.549533620476723e-8,
                2.5632829192545614e-12,
                6.123234262925839e-17,
            ],
            12582912.0, // 1.5 · 2²³
            1e4,
            30,
        ),
    };
    let (sin_c, cos_c): (Vec<f64>, Vec<f64>) = match scalar {
        Scalar::F64 => (SIN_F64.to_vec(), COS_F64.to_vec()),
        // Taylor: sin r = r + r·z·(−1/3! + z·(1/5! − …)) through r⁹, cos r = 1 − z/2 +
        // z²·(1/4! − z·(1/6! − …)) through r¹⁰.
        Scalar::F32 => (
            (1..=4)
                .map(|i| if i % 2 == 1 { -1.0 } else { 1.0 } * inverse_factorial(2 * i + 1))
                .collect(),
            (2..=5)
                .map(|i| if i % 2 == 1 { -1.0 } else { 1.0 } * inverse_factorial(2 * i))
                .collect(),
        ),
    };
    // Estrin's scheme: the pairs c₂ᵢ + z·c₂ᵢ₊₁ side by side, then adjacent terms joined by
    // z², then by z⁴: (c₀ + z c₁) + z²·(c₂ + z c₃) + z⁴·(c₄ + z c₅), three dependent
    // multiply-adds after z for six or seven coefficients, where Horner's scheme chains six.
    // The sines and cosines head every function's longest chain of dependent operations.
    // Also returns whether the polynomial reads z⁴ (more than two pairs).
    let estrin = |c: &[f64]| {
        let mut terms: Vec<TokenStream> = c
            .chunks(2)
            .map(|p| match *p {
                [a, b] => {
                    let (a, b) = (lit(a), lit(b));
                    quote!(fma(z, #b, #a))
                }
                [a] => lit(a),
                _ => unreachable!("chunks of two"),
            })
            .collect();
        let reads_z4 = terms.len() > 2;
        for power in [quote!(z2), quote!(z4)] {
            terms = terms
                .chunks(2)
                .map(|p| match p {
                    [a, b] => quote!(fma(#power, #b, #a)),
                    [a] => a.clone(),
                    _ => unreachable!("chunks of two"),
                })
                .collect();
        }
        assert_eq!(terms.len(), 1, "one to eight coefficients");
        (terms.pop().expect("one term"), reads_z4)
    };
    // cos r = 1 − z/2 + z²·Q(z). Fused, as 1 + z·T(z) with T = −1/2 + z·Q(z): one
    // multiply-add after T, rounded once. Unfused, z·T and the sum would round apart (2.0 ulp
    // measured), so there it is w + ((1 − w) − z/2 + z²·Q(z)) with w = 1 − z/2, which keeps
    // the rounding error of w (1.0 ulp), three operations later.
    let cos_t: Vec<f64> = std::iter::once(-0.5).chain(cos_c.iter().copied()).collect();
    let ((sin_poly, sin_z4), (cos_poly, cos_z4), (cos_q, cos_q_z4)) =
        (estrin(&sin_c), estrin(&cos_t), estrin(&cos_c));
    let (hz_w, compensated) = (
        quote! {
            let hz = 0.5 * z;
            let w = 1.0 - hz;
        },
        quote!(w + fma(z2, #cos_q, (1.0 - w) - hz)),
    );
    // z⁴ where an emitted polynomial reads it (`cos_poly` only in `std` code).
    let z4 = (sin_z4 || cos_q_z4 || (!no_std && cos_z4)).then(|| quote!(let z4 = z2 * z2;));
    let cosine = if no_std {
        quote!(#hz_w let c = #compensated;)
    } else {
        quote! {
            let c = if fused {
                fma(z, #cos_poly, 1.0)
            } else {
                #hz_w
                #compensated
            };
        }
    };
    // `a·b + c`: one rounding where the code is compiled with FMA (or in the AVX-512 and AVX2
    // copies of a dispatched function, `F`), two otherwise; `core` has no `mul_add`. `fused`
    // also picks the reduction and whether the correction of step 3 runs.
    let fma = if no_std {
        quote!(let fma = |a: #t, b: #t, c: #t| a * b + c;)
    } else {
        quote! {
            let fused = F || cfg!(target_feature = "fma");
            let fma = |a: #t, b: #t, c: #t| if fused { a.mul_add(b, c) } else { a * b + c };
        }
    };
    let sign_shift = proc_macro2::Literal::u32_unsuffixed(sign_shift);
    let frac_2_pi = lit(std::f64::consts::FRAC_2_PI);
    let round = lit(round);
    let limit = lit(limit);
    let p: Vec<TokenStream> = pieces.iter().map(|&x| lit(x)).collect();
    let p1 = &p[0];
    let last = &p[p.len() - 1];
    // Two-sums subtracting k·p for the middle pieces; their errors add up in `l`.
    let middle = p[1..p.len() - 1].iter().enumerate().map(|(i, piece)| {
        let e = quote::format_ident!("e{}", i);
        quote! {
            let b = k * #piece;
            let s = h - b;
            let v = s - h;
            let #e = (h - (s - v)) - (b + v);
            let h = s;
        }
    });
    let errors = (0..p.len() - 2).map(|i| quote::format_ident!("e{}", i));
    let unfused = quote! {
        let h = fma(-k, #p1, x);
        #(#middle)*
        let l = (#(#errors)+*) - k * #last;
    };
    // With a fused multiply-add, x − k·P₁ is exact for π/2's leading piece P₁ rounded to the
    // full precision (both are multiples of P₁'s ulp, the difference below 2 in magnitude);
    // r = (x − k·P₁) − k·P₂ − k·P₃ by two more fused multiply-adds, each rounded once. Where
    // r cancels (x near a multiple of π/2) both roundings are relative to r itself, so r stays
    // within about an ulp of x − k·π/2; P₁ + P₂ + P₃ is π/2 to 3 × 53 (f64) or 3 × 24 (f32)
    // bits. Up to 2026-12-02 this path split k·P₂ exactly and kept a low part r_l by a
    // two-sum, with the correction of step 3: 10 more operations per element for about
    // half an ulp. Measured (the AVX2 copies of dispatched functions, old and new code in
    // one binary, medians of 15 interleaved rounds, three runs): `sin_cos` of 7 angles
    // 18.4–20.3 → 15.8–16.3 ns; the UR5's, the Panda's and rand7's poses −9 to −15 %,
    // `J_s` −5 to −14 %, gravity 0 to −11 %.
    //
    // The last term, k·P₃, is below 10⁻²⁷ (f64; 2·10⁻¹¹ for f32) for every k of the range:
    // it changes z = h² by at most 2·10⁻²⁷, far below z's own rounding, and matters only
    // where r itself is added, the leading term of sin r. So the fused path returns
    // h = (x − k·P₁) − k·P₂ and l = −k·P₃; the polynomials start from h (one multiply-add
    // sooner) and sin adds r = h + l (rounded once, as the third multiply-add rounded it).
    let reduce = if no_std {
        unfused
    } else {
        let [q1, q2, q3] = match scalar {
            Scalar::F64 => [
                std::f64::consts::FRAC_PI_2,
                6.123233995736766e-17,
                -1.4973849048591698e-33,
            ],
            Scalar::F32 => [
                f64::from(std::f32::consts::FRAC_PI_2),
                -4.371138828673793e-08,
                -1.7151245100058819e-15,
            ],
        }
        .map(lit);
        quote! {
            // Fused: r = h + l with l = −k·P₃ (step 3 is skipped).
            let (h, l) = if fused {
                let h = fma(-k, #q1, x);
                let h = fma(-k, #q2, h);
                (h, -k * #q3)
            } else {
                #unfused
                (h, l)
            };
        }
    };
    // sin's leading term: r = h + l where l is k·P₃'s (fused), h where l is a low part that
    // step 3 adds.
    let (leading, r) = if no_std {
        (quote!(), quote!(h))
    } else {
        (quote!(let r = if fused { h + l } else { h };), quote!(r))
    };
    // The first-order correction by the reduced argument's low part, where there is one.
    let correct = if no_std {
        quote!(let (s, c) = (fma(l, c, s), fma(-l, s, c));)
    } else {
        quote! {
            let (s, c) = if fused {
                (s, c)
            } else {
                (fma(l, c, s), fma(-l, s, c))
            };
        }
    };
    // Through `black_box`: the optimiser takes the call for a pure operation and, in a loop
    // it vectorises (a batch's row of lanes), would call it on every element and select
    // afterwards; measured, 54 % of a UR5 batch's time went into `sin_cos` of angles of 0.3.
    let fallback = if no_std {
        match scalar {
            Scalar::F64 => quote!({
                let x = ::core::hint::black_box(x);
                (::libm::sin(x), ::libm::cos(x))
            }),
            Scalar::F32 => quote!({
                let x = ::core::hint::black_box(x);
                (::libm::sinf(x), ::libm::cosf(x))
            }),
        }
    } else {
        quote!(::core::hint::black_box(x).sin_cos())
    };
    let doc_bound = match scalar {
        Scalar::F64 => " at most 2 ulp from the exact values for |x| ≤ 10⁶;",
        Scalar::F32 => " at most 2 ulp from the exact values for |x| ≤ 10⁴;",
    };
    let doc_fallback = if no_std {
        " beyond that bound, and for infinities, `libm`'s `sin` and `cos`."
    } else {
        " beyond that bound, and for infinities, the platform's `sin_cos`."
    };
    // Lanes of AVX-512, AVX and 128-bit vectors (SSE2, the x86-64 default; NEON).
    let (wide, mid, narrow) = match scalar {
        Scalar::F64 => (8usize, 4usize, 2usize),
        Scalar::F32 => (16, 8, 4),
    };
    let lanes_doc = format!(
        " `k` rounded up to a whole number of vector registers of the compilation target ({wide} \
         `{t}` lanes with AVX-512, {mid} with AVX, {narrow} otherwise: SSE2, the x86-64 default, or \
         NEON): the length [`Self::joint_sin_cos`] computes `k` angles on, so that its loop \
         vectorises with no scalar tail and no more padding than the target needs."
    );
    quote! {
        /// `(sin x_i, cos x_i)` of every element: Cody–Waite reduction by π/2 in double-length
        /// arithmetic, polynomials on [−π/4, π/4], and the quadrant by selects, one
        /// branch-free loop that vectorises across the elements;
        #[doc = #doc_bound]
        #[doc = #doc_fallback]
        /// The `K` elements are padded with zeros to `P` (`P ≥ K`; `sin_cos_lanes(K)`, a whole
        /// number of the target's vector registers), and `P` results returned.
        #[inline(always)]
        fn joint_sin_cos<const K: usize, const P: usize>(x: [#t; K]) -> ([#t; P], [#t; P]) {
            Self::sin_cos_n::<K, P, false>(x, P)
        }

        /// [`Self::joint_sin_cos`] on the first `n` of the `P` padded elements only (the
        /// others stay 0): `n` a constant once inlined, the loop's trip count. `F`: the
        /// polynomials' multiply-adds are fused (`mul_add`; with `std` only), as they also are
        /// where the code is compiled with FMA.
        #[inline(always)]
        fn sin_cos_n<const K: usize, const P: usize, const F: bool>(
            x: [#t; K],
            n: usize,
        ) -> ([#t; P], [#t; P]) {
            let x = {
                let mut padded = [0.0; P];
                for (p, x) in padded.iter_mut().zip(x) {
                    *p = x;
                }
                padded
            };
            let mut sin = [0.0; P];
            let mut cos = [0.0; P];
            Self::sin_cos_into::<F>(&x, &mut sin, &mut cos, n);
            (sin, cos)
        }

        /// The loops of [`Self::sin_cos_n`]: the sines and cosines of the first `n` elements
        /// of `x` into `sin` and `cos` (a fixed-size array's elements once inlined, `n` the
        /// trip count).
        #[inline(always)]
        fn sin_cos_into<const F: bool>(x: &[#t], sin: &mut [#t], cos: &mut [#t], n: usize) {
            if Self::sin_cos_poly::<F>(x, sin, cos, n) {
                for ((sin, cos), &x) in sin.iter_mut().zip(cos.iter_mut()).zip(x.iter()).take(n) {
                    if x > #limit || x < -#limit {
                        (*sin, *cos) = #fallback;
                    }
                }
            }
        }

        /// The first loop of [`Self::sin_cos_into`], the reduction and the polynomials, and
        /// whether any element lies beyond the bound (whose results are then not its sine and
        /// cosine: [`Self::sin_cos_into`] replaces them).
        #[inline(always)]
        fn sin_cos_poly<const F: bool>(x: &[#t], sin: &mut [#t], cos: &mut [#t], n: usize) -> bool {
            #fma
            // Whether any element is beyond the bound: an or of comparisons, which vectorises
            // with the loop (a loop of compares and branches over the elements, which the
            // fallback alone needs, took 30 instructions per state of a UR5 batch of 8).
            let mut far = false;
            for ((sin, cos), &x) in sin.iter_mut().zip(cos.iter_mut()).zip(x.iter()).take(n) {
                far |= (x > #limit) | (x < -#limit);
                let y = fma(x, #frac_2_pi, #round);
                let k = y - #round;
                let n = y.to_bits();
                #reduce
                // x − k·π/2 = h + l. sin h = h + h·z·P(z), cos h = 1 + z·T(z) (or its
                // compensated form), z = h², the polynomials by Estrin, start as soon as h is
                // known, beside the sum of l.
                let z = h * h;
                let z2 = z * z;
                #z4
                #leading
                let s = fma(h * z, #sin_poly, #r);
                #cosine
                #correct
                let (s, c) = if n & 1 == 0 { (s, c) } else { (c, s) };
                *sin = #t::from_bits(s.to_bits() ^ ((n & 2) << #sign_shift));
                *cos = #t::from_bits(c.to_bits() ^ ((n.wrapping_add(1) & 2) << #sign_shift));
            }
            far
        }

        #[doc = #lanes_doc]
        #[inline(always)]
        const fn sin_cos_lanes(k: usize) -> usize {
            let lanes = if cfg!(target_feature = "avx512f") {
                #wide
            } else if cfg!(target_feature = "avx") {
                #mid
            } else {
                #narrow
            };
            k.div_ceil(lanes) * lanes
        }
    }
}
