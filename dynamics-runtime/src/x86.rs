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
//! does; `neg` flips the sign bit, as `-x` does).
//!
//! The methods take one register of lanes (a [`Register`] of the token: 8 `f64` or 16 `f32`
//! for AVX-512, 4 and 8 for AVX2), so a generated body of instructions is written for one
//! register of states and its batch function runs it once per register. Each method is one
//! intrinsic on the register's bits, nothing else: no branch on `B`, no loop over registers,
//! no operator fallback. They are `#[inline(always)]` in release builds, and only `#[inline]`
//! where `debug_assertions` are on: an unoptimised build then calls them instead of pasting
//! thousands of them into a body (LLVM's always-inliner took 26 of the 49 s that G1's four
//! batch functions, `B` = 8, took to compile without debug info), and an optimised one with
//! debug assertions (opt-level 1, at which this project's tests compile the other crates)
//! still inlines them, as they are one instruction each. (The test crate's generated code is
//! compiled at opt-level 0, where they are calls.)
//!
//! Measured on G1's four batch functions with `B` = 8, in a crate of their own (before: the
//! methods generic over `B`, with a branch for lanes that fill no register and a loop for
//! several; after: this form): debug build 101.9 → 38 s, opt-level 1 without debug info
//! (the test crate's profile) over ten CPU-minutes → 96 s, release 111 → 48 s. Written first
//! with an `Option` result (`None` for the operator case) and a `step_by` loop over the
//! registers, the AVX-512 body of Talos' forward dynamics (5,501 operations, `B` = 8) had
//! taken 155 s to compile in release, and G1's four batch functions 541 s.

// The crate's unsafe module (besides `Lanes::scatter`'s writes into its uninitialised result):
// intrinsics behind tokens whose constructors are `unsafe`.
#![allow(unsafe_code)]

use crate::Lanes;
use core::arch::x86_64::{
    __m256, __m256d, __m512, __m512d, _mm256_add_pd, _mm256_add_ps, _mm256_div_pd, _mm256_div_ps,
    _mm256_fmadd_pd, _mm256_fmadd_ps, _mm256_mul_pd, _mm256_mul_ps, _mm256_set1_pd, _mm256_set1_ps,
    _mm256_sub_pd, _mm256_sub_ps, _mm256_xor_pd, _mm256_xor_ps, _mm512_add_pd, _mm512_add_ps,
    _mm512_div_pd, _mm512_div_ps, _mm512_fmadd_pd, _mm512_fmadd_ps, _mm512_mul_pd, _mm512_mul_ps,
    _mm512_set1_pd, _mm512_set1_ps, _mm512_sub_pd, _mm512_sub_ps, _mm512_xor_pd, _mm512_xor_ps,
};
use core::mem::transmute;

/// Proof that the CPU has AVX-512 F and DQ and FMA: the [`Lanes`] arithmetic of the generated
/// batch bodies' AVX-512 copies (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Avx512(());

/// Proof that the CPU has AVX2 and FMA: the [`Lanes`] arithmetic of the generated batch
/// bodies' AVX2 copies (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

/// One register of lanes of the token `K`'s instructions, with those instructions:
/// `Lanes<f64, 8>` and `Lanes<f32, 16>` for [`Avx512`], `Lanes<f64, 4>` and `Lanes<f32, 8>`
/// for [`Avx2`]. Sealed.
///
/// Each function is one instruction on the register, without a branch, a loop or a
/// fallback: a body of instructions is compiled for one register of states, and a debug
/// build (which neither folds constant branches nor prunes unused ones) compiles no more
/// than that instruction and its operands' moves.
pub trait Register<K>: Copy + sealed::Sealed {
    /// `a + b`.
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn add(a: Self, b: Self) -> Self;
    /// `a − b`.
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn sub(a: Self, b: Self) -> Self;
    /// `a · b`.
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn mul(a: Self, b: Self) -> Self;
    /// `a / b`.
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn div(a: Self, b: Self) -> Self;
    /// `a·b + c`, rounded once.
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn mul_add(a: Self, b: Self, c: Self) -> Self;
    /// `−a` (the sign bit flipped).
    ///
    /// # Safety
    ///
    /// The CPU has the features of `K`.
    unsafe fn neg(a: Self) -> Self;
}

mod sealed {
    pub trait Sealed {}
}

/// The function `$name` of a [`Register`] `Lanes<$t, $n>`, held as `$v`: the intrinsic `$f`
/// on the operands `$x` (see `register!`).
macro_rules! instruction {
    ($t:ty, $n:literal, $v:ty, $name:ident, $f:ident, $($x:ident),+) => {
        #[cfg_attr(debug_assertions, inline)]
        #[cfg_attr(not(debug_assertions), inline(always))]
        unsafe fn $name($($x: Self),+) -> Self {
            unsafe { Lanes(transmute::<$v, [$t; $n]>($f($(transmute::<[$t; $n], $v>($x.0)),+))) }
        }
    };
}

/// [`Register<$token>`] for `Lanes<$t, $n>`, held as the vector type `$v`, with the register
/// width's intrinsics (add, sub, mul, div, fused multiply-add, xor, broadcast).
macro_rules! register {
    ($token:ident, $t:ty, $n:literal, $v:ty,
     $add:ident, $sub:ident, $mul:ident, $div:ident, $fma:ident, $xor:ident, $set1:ident) => {
        impl sealed::Sealed for Lanes<$t, $n> {}
        // SAFETY (every function): the caller's contract, the features; `$v` is the bytes of
        // `$n` `$t`s, and every bit pattern is valid for both. Inlined as the methods are.
        impl Register<$token> for Lanes<$t, $n> {
            instruction!($t, $n, $v, add, $add, a, b);
            instruction!($t, $n, $v, sub, $sub, a, b);
            instruction!($t, $n, $v, mul, $mul, a, b);
            instruction!($t, $n, $v, div, $div, a, b);
            instruction!($t, $n, $v, mul_add, $fma, a, b, c);
            #[cfg_attr(debug_assertions, inline)]
            #[cfg_attr(not(debug_assertions), inline(always))]
            unsafe fn neg(a: Self) -> Self {
                unsafe {
                    let r = $xor(transmute::<[$t; $n], $v>(a.0), $set1(-0.0));
                    Lanes(transmute::<$v, [$t; $n]>(r))
                }
            }
        }
    };
}

register!(
    Avx512,
    f64,
    8,
    __m512d,
    _mm512_add_pd,
    _mm512_sub_pd,
    _mm512_mul_pd,
    _mm512_div_pd,
    _mm512_fmadd_pd,
    _mm512_xor_pd,
    _mm512_set1_pd
);
register!(
    Avx512,
    f32,
    16,
    __m512,
    _mm512_add_ps,
    _mm512_sub_ps,
    _mm512_mul_ps,
    _mm512_div_ps,
    _mm512_fmadd_ps,
    _mm512_xor_ps,
    _mm512_set1_ps
);
register!(
    Avx2,
    f64,
    4,
    __m256d,
    _mm256_add_pd,
    _mm256_sub_pd,
    _mm256_mul_pd,
    _mm256_div_pd,
    _mm256_fmadd_pd,
    _mm256_xor_pd,
    _mm256_set1_pd
);
register!(
    Avx2,
    f32,
    8,
    __m256,
    _mm256_add_ps,
    _mm256_sub_ps,
    _mm256_mul_ps,
    _mm256_div_ps,
    _mm256_fmadd_ps,
    _mm256_xor_ps,
    _mm256_set1_ps
);

/// A method of a token: the register's instruction `$name` on the operands `$x` (inlined
/// always in release, called in debug builds: see the module docs).
macro_rules! method {
    ($(#[$doc:meta])* $name:ident($($x:ident),+)) => {
        $(#[$doc])*
        #[cfg_attr(debug_assertions, inline)]
        #[cfg_attr(not(debug_assertions), inline(always))]
        #[must_use]
        pub fn $name<V: Register<Self>>(self, $($x: V),+) -> V {
            // SAFETY: `self` proves the features.
            unsafe { V::$name($($x),+) }
        }
    };
}

/// The methods of the token `$token`; `$features` names what its constructor's caller
/// guarantees.
macro_rules! token {
    ($token:ident, $features:literal) => {
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

            method!(
                /// `a + b`, lane by lane.
                add(a, b)
            );
            method!(
                /// `a − b`, lane by lane.
                sub(a, b)
            );
            method!(
                /// `a · b`, lane by lane.
                mul(a, b)
            );
            method!(
                /// `a / b`, lane by lane.
                div(a, b)
            );
            method!(
                /// `−a`, lane by lane (the sign bit flipped, as `-x`).
                neg(a)
            );
            method!(
                /// `a·b + c`, lane by lane, rounded once (the fused multiply-add that the
                /// same copies' single-state code uses for the same products).
                mul_add(a, b, c)
            );
        }
    };
}

token!(
    Avx512,
    " The CPU this runs on has the `avx512f`, `avx512dq` and `fma` features (the generated \
     code's `has_avx512` checks them, with `avx512vl` and `avx512bw`)."
);
token!(
    Avx2,
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

    /// Every method of the token `$z` against its operator, bit for bit, on a register of
    /// `f64` lanes (`$d` wide) and one of `f32` lanes (`$s`).
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
            // SAFETY: the features are checked above.
            check!(unsafe { Avx512::new_unchecked() }, seed, f64: [8], f32: [16]);
        }
    }

    #[test]
    fn the_avx2_instructions_give_the_operators_bits() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            std::eprintln!("no AVX2 and FMA on this CPU: nothing to compare");
            return;
        }
        for seed in 0..50 {
            // SAFETY: the features are checked above.
            check!(unsafe { Avx2::new_unchecked() }, seed, f64: [4], f32: [8]);
        }
    }
}
