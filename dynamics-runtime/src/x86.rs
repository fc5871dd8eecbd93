//! [`Avx512`] and [`Avx2`]: the arithmetic of [`Lanes`] as AVX-512 or AVX2 instructions, for the
//! generated batch bodies' copies for those CPUs.
//!
//! The optimiser vectorises a batch body written with `Lanes` operators by rebuilding each
//! operation's `B` lanes from the unrolled lane loops (its SLP vectoriser). On bodies of a
//! few thousand operations it rebuilds part of them only: Solo-12's inverse dynamics with
//! `B` = 8 held 4,864 instructions, 482 of them scalar and 1,018 on half-width registers.
//! Written as one AVX-512 instruction per operation it held 2,742, and took 82 against 118 ns
//! per state (single calls: 163 ns). The generated AVX-512 and AVX2 copies of a large batch
//! body call the methods of a token instead of the operators.
//!
//! A token proves that the CPU has the features its instructions need (AVX-512 F and DQ and
//! FMA for [`Avx512`], AVX2 and FMA for [`Avx2`]): it is made only by its `unsafe`
//! `new_unchecked`, which the generated code calls in its copies for that CPU, after the
//! run-time check that chose them. Every method gives the bits of the operator it replaces
//! (IEEE operations are exactly rounded either way; `mul_add` rounds once, as `f64::mul_add`
//! does; `neg` flips the sign bit, as `-x` does). Lanes that do not fill whole registers (for
//! AVX-512, `B` not a multiple of 8 for `f64`, of 16 for `f32`; for AVX2, of 4 and 8) use the
//! operators (and a scalar fused multiply-add).
//!
//! The methods are written for the optimiser's sake as much as for the instructions': a plain
//! `if` on `B` (a constant) and, for one register, one straight-line instruction through
//! pointers into the arrays, so that its first passes turn every `Lanes` of the body into a
//! vector register value. Written first with an `Option` result (`None` for the operator
//! case) and a `step_by` loop over the registers, the AVX-512 body of Talos' forward dynamics
//! (5,501 operations, `B` = 8) took 155 s to compile in release, against 8 s now, and G1's
//! four batch functions 541 against 40 s; the instructions were the same.

// The crate's one unsafe module: intrinsics behind tokens whose constructors are `unsafe`.
#![allow(unsafe_code)]

use crate::Lanes;
use core::arch::x86_64::{
    __m256, __m256d, __m512, __m512d, _mm256_add_pd, _mm256_add_ps, _mm256_div_pd, _mm256_div_ps,
    _mm256_fmadd_pd, _mm256_fmadd_ps, _mm256_loadu_pd, _mm256_loadu_ps, _mm256_mul_pd,
    _mm256_mul_ps, _mm256_set1_pd, _mm256_set1_ps, _mm256_storeu_pd, _mm256_storeu_ps,
    _mm256_sub_pd, _mm256_sub_ps, _mm256_xor_pd, _mm256_xor_ps, _mm512_add_pd, _mm512_add_ps,
    _mm512_div_pd, _mm512_div_ps, _mm512_fmadd_pd, _mm512_fmadd_ps, _mm512_loadu_pd,
    _mm512_loadu_ps, _mm512_mul_pd, _mm512_mul_ps, _mm512_set1_pd, _mm512_set1_ps,
    _mm512_storeu_pd, _mm512_storeu_ps, _mm512_sub_pd, _mm512_sub_ps, _mm512_xor_pd, _mm512_xor_ps,
    _mm_cvtsd_f64, _mm_cvtss_f32, _mm_fmadd_sd, _mm_fmadd_ss, _mm_set_sd, _mm_set_ss,
};

/// Proof that the CPU has AVX-512 F and DQ and FMA: the [`Lanes`] arithmetic of the generated
/// batch bodies' AVX-512 copies (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Avx512(());

/// Proof that the CPU has AVX2 and FMA: the [`Lanes`] arithmetic of the generated batch
/// bodies' AVX2 copies (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

/// The scalars of [`Lanes`] (`f64`, `f32`), with their AVX-512 and AVX2 operations. Sealed.
pub trait Element: Copy + sealed::Sealed {
    /// The lanes of one 512-bit register.
    const PER_ZMM: usize;
    /// The lanes of one 256-bit register.
    const PER_YMM: usize;
    /// `a + b`, `a − b`, `a · b`, `a / b`, `a·b + c` (rounded once), `−a` on the 512 bits
    /// at `a`, `b`, `c`, written to `out`.
    ///
    /// # Safety
    ///
    /// AVX-512 F and DQ are available; each pointer reads or writes 64 bytes.
    unsafe fn op_zmm(op: Op, a: *const Self, b: *const Self, c: *const Self, out: *mut Self);
    /// The same on the 256 bits at `a`, `b`, `c`.
    ///
    /// # Safety
    ///
    /// AVX2 and FMA are available; each pointer reads or writes 32 bytes.
    unsafe fn op_ymm(op: Op, a: *const Self, b: *const Self, c: *const Self, out: *mut Self);
    /// `a·b + c` rounded once, on one scalar.
    ///
    /// # Safety
    ///
    /// FMA is available.
    unsafe fn fma(a: Self, b: Self, c: Self) -> Self;
}

/// An arithmetic operation of [`Element::op_zmm`] and [`Element::op_ymm`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `a + b`.
    Add,
    /// `a − b`.
    Sub,
    /// `a · b`.
    Mul,
    /// `a / b`.
    Div,
    /// `a·b + c`, rounded once.
    MulAdd,
    /// `−a`.
    Neg,
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f64 {}
    impl Sealed for f32 {}
}

/// `Op` on one register of type `$v` at the pointers, with the register width's intrinsics
/// (load, store, add, sub, mul, div, fused multiply-add, xor, broadcast).
macro_rules! register_op {
    ($op:ident, $a:ident, $b:ident, $c:ident, $out:ident, $v:ty, $load:ident, $store:ident,
     $add:ident, $sub:ident, $mul:ident, $div:ident, $fma:ident, $xor:ident, $set1:ident) => {{
        let x: $v = $load($a);
        let r = match $op {
            Op::Add => $add(x, $load($b)),
            Op::Sub => $sub(x, $load($b)),
            Op::Mul => $mul(x, $load($b)),
            Op::Div => $div(x, $load($b)),
            Op::MulAdd => $fma(x, $load($b), $load($c)),
            Op::Neg => $xor(x, $set1(-0.0)),
        };
        $store($out, r);
    }};
}

macro_rules! element {
    ($t:ty, $zmm_lanes:literal, $ymm_lanes:literal, zmm: [$($z:tt)*], ymm: [$($y:tt)*],
     scalar: [$fma1:ident, $set:ident, $get:ident]) => {
        impl Element for $t {
            const PER_ZMM: usize = $zmm_lanes;
            const PER_YMM: usize = $ymm_lanes;
            #[inline(always)]
            unsafe fn fma(a: Self, b: Self, c: Self) -> Self {
                // SAFETY: the caller's contract: FMA.
                unsafe { $get($fma1($set(a), $set(b), $set(c))) }
            }
            #[inline(always)]
            unsafe fn op_zmm(op: Op, a: *const Self, b: *const Self, c: *const Self, out: *mut Self) {
                // SAFETY: the caller's contract: the features, and 64 bytes at each pointer.
                unsafe { register_op!(op, a, b, c, out, $($z)*) }
            }
            #[inline(always)]
            unsafe fn op_ymm(op: Op, a: *const Self, b: *const Self, c: *const Self, out: *mut Self) {
                // SAFETY: the caller's contract: the features, and 32 bytes at each pointer.
                unsafe { register_op!(op, a, b, c, out, $($y)*) }
            }
        }
    };
}

element!(
    f64, 8, 4,
    zmm: [__m512d, _mm512_loadu_pd, _mm512_storeu_pd, _mm512_add_pd, _mm512_sub_pd,
          _mm512_mul_pd, _mm512_div_pd, _mm512_fmadd_pd, _mm512_xor_pd, _mm512_set1_pd],
    ymm: [__m256d, _mm256_loadu_pd, _mm256_storeu_pd, _mm256_add_pd, _mm256_sub_pd,
          _mm256_mul_pd, _mm256_div_pd, _mm256_fmadd_pd, _mm256_xor_pd, _mm256_set1_pd],
    scalar: [_mm_fmadd_sd, _mm_set_sd, _mm_cvtsd_f64]
);
element!(
    f32, 16, 8,
    zmm: [__m512, _mm512_loadu_ps, _mm512_storeu_ps, _mm512_add_ps, _mm512_sub_ps,
          _mm512_mul_ps, _mm512_div_ps, _mm512_fmadd_ps, _mm512_xor_ps, _mm512_set1_ps],
    ymm: [__m256, _mm256_loadu_ps, _mm256_storeu_ps, _mm256_add_ps, _mm256_sub_ps,
          _mm256_mul_ps, _mm256_div_ps, _mm256_fmadd_ps, _mm256_xor_ps, _mm256_set1_ps],
    scalar: [_mm_fmadd_ss, _mm_set_ss, _mm_cvtss_f32]
);

/// A method of a token for the binary operator `$op` of trait `$tr`: one instruction per
/// whole register (`apply`), the operator otherwise.
macro_rules! binary {
    ($(#[$doc:meta])* $name:ident, $tr:ident, $op:tt) => {
        $(#[$doc])*
        #[inline(always)]
        #[must_use]
        pub fn $name<T: Element, const B: usize>(self, a: Lanes<T, B>, b: Lanes<T, B>) -> Lanes<T, B>
        where
            Lanes<T, B>: core::ops::$tr<Output = Lanes<T, B>>,
        {
            if Self::whole::<T, B>() {
                self.apply(Op::$tr, &a, &b, &b)
            } else {
                a $op b
            }
        }
    };
}

/// The methods of the token `$token`, whose registers hold `T::$per` lanes and whose
/// instructions are `T::$op`; `$features` names what its constructor's caller guarantees.
macro_rules! token {
    ($token:ident, $per:ident, $op:ident, $features:literal) => {
        impl $token {
            /// The token.
            ///
            /// # Safety
            ///
            #[doc = $features]
            #[inline(always)]
            #[must_use]
            pub const unsafe fn new_unchecked() -> Self {
                Self(())
            }

            /// Whether `B` lanes fill a whole number of registers (the instructions' case).
            #[inline(always)]
            const fn whole<T: Element, const B: usize>() -> bool {
                B != 0 && B.is_multiple_of(T::$per)
            }

            /// `op` on whole registers of lanes: only where [`Self::whole`].
            #[inline(always)]
            fn apply<T: Element, const B: usize>(
                self,
                op: Op,
                a: &Lanes<T, B>,
                b: &Lanes<T, B>,
                c: &Lanes<T, B>,
            ) -> Lanes<T, B> {
                let mut out = *a;
                let (pa, pb, pc, po) = (a.0.as_ptr(), b.0.as_ptr(), c.0.as_ptr(), out.0.as_mut_ptr());
                if B == T::$per {
                    // SAFETY: `self` proves the features; each array is one register's bytes.
                    unsafe { T::$op(op, pa, pb, pc, po) };
                } else {
                    let mut k = 0;
                    while k < B {
                        // SAFETY: `self` proves the features; lanes `k..k + $per` (one
                        // register) are within the `B` of each array, as `B` is a multiple
                        // of `$per`.
                        unsafe { T::$op(op, pa.add(k), pb.add(k), pc.add(k), po.add(k)) };
                        k += T::$per;
                    }
                }
                out
            }

            binary!(
                /// `a + b`, lane by lane.
                add, Add, +
            );
            binary!(
                /// `a − b`, lane by lane.
                sub, Sub, -
            );
            binary!(
                /// `a · b`, lane by lane.
                mul, Mul, *
            );
            binary!(
                /// `a / b`, lane by lane.
                div, Div, /
            );

            /// `−a`, lane by lane (the sign bit flipped, as `-x`).
            #[inline(always)]
            #[must_use]
            pub fn neg<T: Element, const B: usize>(self, a: Lanes<T, B>) -> Lanes<T, B>
            where
                Lanes<T, B>: core::ops::Neg<Output = Lanes<T, B>>,
            {
                if Self::whole::<T, B>() {
                    self.apply(Op::Neg, &a, &a, &a)
                } else {
                    -a
                }
            }

            /// `a·b + c`, lane by lane, rounded once (the fused multiply-add that the same
            /// copies' single-state code uses for the same products).
            #[inline(always)]
            #[must_use]
            pub fn mul_add<T: Element, const B: usize>(
                self,
                a: Lanes<T, B>,
                b: Lanes<T, B>,
                c: Lanes<T, B>,
            ) -> Lanes<T, B> {
                if Self::whole::<T, B>() {
                    return self.apply(Op::MulAdd, &a, &b, &c);
                }
                let mut out = c.0;
                for ((o, a), b) in out.iter_mut().zip(a.0).zip(b.0) {
                    // SAFETY: `self` proves FMA.
                    *o = unsafe { T::fma(a, b, *o) };
                }
                Lanes(out)
            }
        }
    };
}

token!(
    Avx512,
    PER_ZMM,
    op_zmm,
    " The CPU this runs on has the `avx512f`, `avx512dq` and `fma` features (the generated \
     code's `has_avx512` checks them, with `avx512vl` and `avx512bw`)."
);
token!(
    Avx2,
    PER_YMM,
    op_ymm,
    " The CPU this runs on has the `avx2` and `fma` features (the generated code's `has_avx2` \
     checks them)."
);

#[cfg(test)]
mod tests {
    extern crate std;
    use super::{Avx2, Avx512, Lanes};

    /// Values with every kind of rounding: products and quotients that are inexact, a
    /// negative zero, a subnormal, an infinity.
    fn values<const B: usize>(seed: u64) -> [f64; B] {
        let mut s = seed;
        core::array::from_fn(|i| match (i + seed as usize) % 11 {
            3 => -0.0,
            7 => 1e-310,
            9 => f64::INFINITY,
            _ => {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e3
            }
        })
    }

    fn same<T: Copy + Into<f64>, const B: usize>(a: Lanes<T, B>, b: Lanes<T, B>) -> bool {
        a.0.iter().zip(b.0).all(|(&x, y)| {
            let (x, y): (f64, f64) = (x.into(), y.into());
            x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan())
        })
    }

    fn lanes<const B: usize>(seed: u64) -> [Lanes<f64, B>; 3] {
        [0, 100, 200].map(|d| Lanes(values::<B>(seed + d)))
    }

    fn narrow<const B: usize>(seed: u64) -> [Lanes<f32, B>; 3] {
        lanes::<B>(seed).map(|l| Lanes(l.0.map(|v| v as f32)))
    }

    /// Every method of the token `$z` against its operator on the lanes `[a, b, c]`.
    macro_rules! ops {
        ($z:expr, $abc:expr) => {{
            let (z, [a, b, c]) = ($z, $abc);
            assert!(same(z.add(a, b), a + b));
            assert!(same(z.sub(a, b), a - b));
            assert!(same(z.mul(a, b), a * b));
            assert!(same(z.div(a, b), a / b));
            assert!(same(z.neg(a), -a));
            let want = Lanes(core::array::from_fn(|l| a.0[l].mul_add(b.0[l], c.0[l])));
            assert!(same(z.mul_add(a, b, c), want));
        }};
    }

    /// Every method of the token `$z` against its operator, bit for bit, on `f64` lanes
    /// `$d` wide and `f32` lanes `$s` wide.
    macro_rules! check {
        ($z:expr, $seed:expr, f64: [$($d:literal),*], f32: [$($s:literal),*]) => {{
            let z = $z;
            $(
                ops!(z, lanes::<$d>($seed));
            )*
            $(
                ops!(z, narrow::<$s>($seed));
            )*
        }};
    }

    #[test]
    fn the_avx512_instructions_give_the_operators_bits() {
        let has = std::is_x86_feature_detected!("avx512f")
            && std::is_x86_feature_detected!("avx512dq")
            && std::is_x86_feature_detected!("fma");
        if !has {
            std::eprintln!("no AVX-512 on this CPU: nothing to compare");
            return;
        }
        for seed in 0..50 {
            // One register (8 `f64`, 16 `f32`), two, and lanes that do not fill one (the
            // operators, and the scalar FMA).
            // SAFETY: the features are checked above.
            check!(unsafe { Avx512::new_unchecked() }, seed, f64: [8, 16, 4], f32: [16, 32, 4]);
        }
    }

    #[test]
    fn the_avx2_instructions_give_the_operators_bits() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            std::eprintln!("no AVX2 and FMA on this CPU: nothing to compare");
            return;
        }
        for seed in 0..50 {
            // One register (4 `f64`, 8 `f32`), two, and lanes that do not fill one.
            // SAFETY: the features are checked above.
            check!(unsafe { Avx2::new_unchecked() }, seed, f64: [4, 8, 3], f32: [8, 16, 4]);
        }
    }
}
