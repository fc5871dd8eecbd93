//! Run-time CPU dispatch: on x86-64, two more copies of each numeric function, one compiled
//! for AVX-512 and one for AVX2, both with FMA, chosen at run time by what the CPU has.
//!
//! A crate built for the default x86-64 target (no `-C target-cpu`) may use only SSE2: 16 vector
//! registers of two `f64`s, no fused multiply-add. The unrolled dynamics keep dozens of values
//! live at once, so on SSE2 they spill to the stack, and the joints' sines and cosines take
//! two lanes at a time. So, for `std` code, every `&self` function whose body does
//! arithmetic (it calls `Self::mul_add` or `Self::joint_sin_cos`) becomes four: every public
//! one, and the private helpers without generic parameters (`mass_matrix_factor`, which
//! `constrained_forward_dynamics` calls: left to the portable code, that function took 392 ns
//! for rand7 against 171 ns for its forward dynamics, and an identical copy of it 187 or 641 ns
//! for the Panda depending on where the optimiser inlined it). A public function with const
//! generic parameters is one too: a batch function when its single-state function is, and
//! `constrained_forward_dynamics` on its own (its substitutions for `Y = M⁻¹ Aᵀ`, in the
//! caller's SSE2 code before, fused in its copies: rand7 5–8 % faster, the Panda 9 %). A
//! dispatched body that calls another dispatched single-state function (that one calls
//! `mass_matrix_factor`) calls its body in the copies and its portable copy otherwise
//! ([`with_bodies_called`]): no copy runs another function's CPU check. The wrapper keeps the
//! function's visibility:
//!
//! ```text
//! #[inline] pub fn f(&self, args) -> R {             // the public API, unchanged
//!     #[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f")))]
//!     {
//!         if Self::has_fast_avx512() { return unsafe { self.f_avx512(args) }; }
//!         #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
//!         { if Self::has_avx2() { return unsafe { self.f_avx2(args) }; } }
//!     }
//!     self.f_portable(args)
//! }
//! #[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f")))]
//! #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,fma")]
//! unsafe extern "C" fn f_avx512(&self, args) -> R { self.f_body::<true>(args) }
//! #[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f"),
//!           not(all(target_feature = "avx2", target_feature = "fma"))))]
//! #[target_feature(enable = "avx2,fma")]
//! unsafe extern "C" fn f_avx2(&self, args) -> R { self.f_body::<true>(args) }
//! #[cfg(the AVX2 copy's cfg)] #[inline(never)]
//! extern "C" fn f_portable(&self, args) -> R { self.f_body::<false>(args) }
//! #[cfg(not(the AVX2 copy's cfg))] #[inline(always)]
//! fn f_portable(&self, args) -> R { self.f_body::<{ cfg!(AVX2 and FMA) }>(args) }
//! #[inline(always)] fn f_body<const WIDE: bool>(&self, args) -> R { the body }
//! ```
//!
//! `f_portable` is what a CPU without AVX2 runs. Compiled for the default x86-64 target it is
//! out of line (and `extern "C"`, see below), so that the wrapper is a few instructions: a
//! crate that calls `f` from another crate compiles those and calls the copies, instead of
//! compiling the whole body again (the project's test binaries did, once for each). Where the
//! crate is compiled with AVX2 and FMA or for another architecture, `f_portable` is the code
//! that runs, and it is inlined into the wrapper as the body was before there was a dispatch.
//! Compiled with AVX2 and FMA (`-C target-cpu=native`, `x86-64-v3`, `x86-64-v4`), a
//! single-state function's `f_portable` is the copies' body, `WIDE` (its far angles left to
//! `f_far`, below, as in the copies): the `WIDE = false` body's packs of four are arrays of
//! scalars, which the optimiser left scalar there, and its sines' fallback is a call in line.
//! Measured old against new, one binary each (2026-12-06, Emerald Rapids): G1 (floating) built
//! native, mass matrix −26 and −34 %, forward dynamics −32 and −30 %, inverse dynamics −32 and
//! −18 %; built for `x86-64-v3`, −44 and −41 %, −31 and −31 %, −45 and −50 %; the same results
//! bit for bit (with FMA in the target, the `WIDE = false` body fuses the same operations).
//! A batch function's `f_portable` stays the vectoriser's body (its copies' bodies of
//! instructions run there, [`native_call`]).
//!
//! `f_body` is inlined into all three, so it is compiled once for the crate's target, once for
//! AVX-512 and once for AVX2: in the last two `Self::mul_add_with::<true>` is `f64::mul_add`,
//! one `vfmadd` instruction, and the sines and cosines take 8 `f64` lanes (16 `f32`) at a time
//! (one AVX-512 register, two AVX2 ones); AVX-512's 32 registers also hold what SSE2 spills.
//! The two copies run the same operations on the same values, so they give the same bits.
//! `has_fast_avx512`, `has_avx512` and `has_avx2` read one cached level (`cpu_level`, a
//! relaxed atomic load, inlined), which the standard library's `is_x86_feature_detected!` and
//! the vendor of CPUID leaf 0 give on the first call, in a cold `extern "C"` function, so that
//! callers know it cannot unwind. A single-state function runs its AVX-512 copy on AMD's
//! AVX-512 cores alone (`has_fast_avx512`) and its AVX2 copy on Intel's: the optimiser
//! vectorises the copies' sines and cosines on 512-bit registers, which on Intel's cores slow
//! down the code around them (twice as long, measured on a Xeon). A batch function, whose
//! lanes fill those registers, runs its AVX-512 copy on any AVX-512 core (`has_avx512`). The copies are
//! `extern "C"` for the same reason: they are
//! compiled where the generated file is (often another crate than the caller's), and a call to
//! a Rust function there counts as one that may unwind to `no_panic` and to the optimiser; an
//! `extern "C"` function cannot unwind (a panic in it would abort, which `#[no_panic]` cannot
//! see, so the `no_panic` test also reads the copies' machine code and follows their calls:
//! none reaches the panic machinery). The `unsafe` calls are sound because each callee needs
//! exactly the features just detected. They carry `#[allow(unsafe_code)]`, so that a crate that
//! denies unsafe code still compiles the generated file (a crate that forbids it cannot lift
//! that: it generates with `--no-cpu-dispatch`). Where the crate is already compiled with
//! AVX-512 (e.g. `-C target-cpu=native` on such a CPU), and on other architectures, the `cfg`
//! removes the dispatch and the code is what it was; where it is compiled with AVX2 and FMA
//! (`-C target-cpu=x86-64-v3`) there is no AVX2 copy, as the portable one has both. Except in
//! both, a batch function's copy with a body of instructions (below), AVX-512 or AVX2 as the
//! crate's features allow: it runs there without a check of the CPU, for `B` a multiple of
//! the register's lanes ([`native_call`]). On a CPU
//! with FMA the results can differ from the portable code's by the rounding of the fused
//! operations.
//!
//! The AVX2 copy serves the x86-64 CPUs without AVX-512 (most desktop and laptop processors,
//! AMD's before Zen 4). Measured on this project's AVX-512 machine with the AVX-512 check
//! forced false (so the AVX2 copy ran), against the portable copy that such a CPU ran before,
//! in one binary, medians of 9 interleaved rounds of 20,000 calls (2026-11-26): the Panda's
//! inverse dynamics −32 %, mass matrix −23 %, forward dynamics −25 %, gravity −45 %; rand7's
//! −27 %, −42 %, −74 % (its portable forward dynamics took 725 ns in that build, 233 ns in
//! another) and −41 %. An earlier measurement of the same scheme on the Panda, which predates
//! the sine–cosine kernel's padding and Estrin schedule, had found nothing (−4 % to +15 %);
//! why was not re-examined.
//!
//! The sines' far angles. The kernel's fallback for angles beyond its bound (10⁶ rad in `f64`,
//! 10⁴ in `f32`: the platform's `sin_cos`, lane by lane) is a call, and a call in line clobbers
//! every vector register: every value live across the kernel was spilled before it, though no
//! robot's angles take that branch (G1's inverse dynamics copied its 70 velocities and
//! accelerations to the stack). So a single-state body whose kernel takes several angles gets
//! a second `const`, `FAR`, and the copies run `f_body::<true, false>`, whose kernel
//! (`sin_cos_near`) returns `None` when an angle is beyond the bound; the body then returns
//! `f_far(args)` with the arguments as passed (kept aside at its top: a body may shadow them).
//! `f_far` is `f_body::<true, true>`, whose kernel keeps the fallback in line, compiled for
//! AVX2 and FMA, cold and out of line: the copies' fused operations, so the same bits as they
//! would have given, and a batch lane still equals the single call. Where no copy runs, `f_far`
//! is what the portable body calls where that is `WIDE` (compiled with AVX2 and FMA), and
//! elsewhere never called and `#[inline(always)]`, so never compiled. Measured on a Zen 4
//! (2026-12-03), old and new code in one binary: G1's inverse dynamics −10 and −12 %, the
//! UR5's and rand7's functions −1 to −11 %, mass matrices unchanged; the UR5's generated
//! library +21 % instructions (a fourth body per function).
//!
//! A batch body's kernel in a copy (`sin_cos_rows_near`) returns `None` the same way, and the
//! batch then calls its single-state function once per state ([`batch_far_call`]): each
//! state's result is the single call's bits by construction, and no fourth body is needed.
//! Measured (2026-12-03, Zen 4, `B` = 8, one binary): batched inverse dynamics −13 to −28 %
//! per state on the UR5, the Panda and rand7, with the bodies of instructions that this made
//! pay in the AVX-512 copy (`zmm::VECTOR_MIN_OPS`).
//!
//! A function with `const` generic parameters (the batch functions, `f<const B: usize>`) passes
//! them on: `f_avx512::<B>` and `f_body::<WIDE, B>`; its body's `Lanes` helpers
//! (`mul_add_lanes`, `joint_sin_cos_rows`) are fused as the scalar ones are. A batch function
//! `X_batch` is dispatched exactly when `X` is, so that a state's result is `X`'s bit for bit
//! on every CPU. A batch function comes `#[inline(never)]` (it holds the whole `B`-wide body
//! wherever it is not dispatched); its dispatching wrapper is `#[inline]`, and where no copy
//! runs it calls `f_portable::<B>`, out of line and `extern "C"` on every target, so that a
//! caller knows it cannot unwind (as [`super::batch::out_of_line`] does for the batch
//! functions the dispatch leaves alone). A large batch body ([`super::zmm::DOC_MARK`]) gets
//! bodies of its own in the AVX-512 and AVX2 copies, its lane arithmetic written as those
//! instructions, for `B` a multiple of a register's lanes. One too large for the optimiser's
//! vectoriser ([`super::zmm::ONLY_MARK`]) gets those two copies alone, and is otherwise the
//! single-state function once per state ([`zmm_only`]).
//!
//! Left alone: functions with type or lifetime parameters, bodies split into `extern "C"`
//! parts (the largest trees), whose nested functions cannot see `WIDE`, and bodies of fewer
//! than [`MIN_TOKENS`] tokens.

use crate::options::Scalar;
use proc_macro2::{Delimiter, Group, Ident, Literal, Span, TokenStream, TokenTree};
use quote::{format_ident, quote};
use std::collections::BTreeMap;

/// The `cfg` under which the dispatch exists.
fn dispatch_cfg() -> TokenStream {
    let cond = dispatch_cond();
    quote!(#[cfg(#cond)])
}

/// Its predicate: x86-64 code not already compiled for AVX-512.
fn dispatch_cond() -> TokenStream {
    quote!(all(target_arch = "x86_64", not(target_feature = "avx512f")))
}

/// The predicate of x86-64 code compiled with AVX2 and FMA (`-C target-cpu=native` on most
/// x86-64 CPUs of the last decade, `x86-64-v3`, `x86-64-v4`): there the portable body of a
/// single-state function is the copies' fused body (`WIDE`), its far angles left to `X_far`
/// as in the copies.
fn wide_native_cond() -> TokenStream {
    quote!(all(
        target_arch = "x86_64",
        target_feature = "avx2",
        target_feature = "fma"
    ))
}

/// The predicate of the code that may run a `WIDE` body, and so of the intrinsics in the
/// vector helpers and of the `X_far` functions: the dispatch's (the copies) and
/// [`wide_native_cond`]'s (the portable body).
fn wide_cond() -> TokenStream {
    let (dispatch, native) = (dispatch_cond(), wide_native_cond());
    quote!(any(#dispatch, #native))
}

/// The predicate of code compiled with the features of the AVX-512 copy (`-C
/// target-cpu=native` on such a CPU, `x86-64-v4`): no dispatch there, but a batch function
/// with an AVX-512 body of instructions runs it ([`native_call`]).
fn native_avx512_cond() -> TokenStream {
    quote!(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512vl",
        target_feature = "avx512dq",
        target_feature = "avx512bw",
        target_feature = "fma"
    ))
}

/// Within the dispatch, the predicate of the AVX2 copy: code not already compiled with AVX2
/// and FMA (e.g. `-C target-cpu=x86-64-v3`, whose portable copy has both).
fn avx2_cond() -> TokenStream {
    quote!(not(all(target_feature = "avx2", target_feature = "fma")))
}

/// The `cfg` of the AVX2 copies and of their CPU check: the dispatch's and [`avx2_cond`].
fn avx2_cfg() -> TokenStream {
    let cond = avx2_copy_cond();
    quote!(#[cfg(#cond)])
}

/// Its predicate.
fn avx2_copy_cond() -> TokenStream {
    let avx2 = avx2_cond();
    quote!(all(target_arch = "x86_64", not(target_feature = "avx512f"), #avx2))
}

/// The two copies whose batch bodies can run on the runtime's tokens ([`super::zmm`]).
#[derive(Clone, Copy, PartialEq)]
enum Isa {
    Avx512,
    Avx2,
}

impl Isa {
    /// The suffix of the copy's name (`f_avx512`).
    fn suffix(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512",
            Isa::Avx2 => "avx2",
        }
    }

    /// Its name in prose.
    fn prose(self) -> &'static str {
        match self {
            Isa::Avx512 => "AVX-512",
            Isa::Avx2 => "AVX2",
        }
    }

    /// The `cfg` of a copy with a body of instructions, and of that body: wherever the
    /// dispatch is, and where the crate is compiled with the copy's features (`-C
    /// target-cpu=native`; `x86-64-v3` for AVX2, `x86-64-v4` for AVX-512), where it runs
    /// without a check of the CPU ([`native_call`]). A copy without such a body is not
    /// compiled there, as it would be the portable code again. (The AVX2 one needs no second
    /// predicate: a crate compiled with AVX2 and FMA but not AVX-512 has the dispatch.)
    fn cfg(self) -> TokenStream {
        match self {
            Isa::Avx512 => {
                let (dispatch, native) = (dispatch_cond(), native_avx512_cond());
                quote!(#[cfg(any(#dispatch, #native))])
            }
            Isa::Avx2 => dispatch_cfg(),
        }
    }

    /// The predicate of code compiled with the copy's features, under which a batch function
    /// calls its copy with a body of instructions without a check ([`native_call`]).
    fn native_cond(self) -> TokenStream {
        match self {
            Isa::Avx512 => native_avx512_cond(),
            Isa::Avx2 => quote!(all(target_feature = "avx2", target_feature = "fma")),
        }
    }

    /// The attributes of a function compiled for it: [`Self::cfg`] and its `target_feature`s.
    fn attrs(self) -> TokenStream {
        let (cfg, features) = (self.cfg(), self.features());
        quote!(#cfg #[target_feature(enable = #features)])
    }

    /// Its `target_feature`s.
    fn features(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512f,avx512vl,avx512dq,avx512bw,fma",
            Isa::Avx2 => "avx2,fma",
        }
    }

    /// The runtime's token of its instructions.
    fn token(self) -> &'static str {
        match self {
            Isa::Avx512 => "Avx512",
            Isa::Avx2 => "Avx2",
        }
    }

    /// The lanes of the scalar in one of its registers.
    fn lanes(self, scalar: Scalar) -> proc_macro2::Literal {
        let per_zmm = match scalar {
            Scalar::F64 => 8,
            Scalar::F32 => 16,
        };
        proc_macro2::Literal::usize_unsuffixed(match self {
            Isa::Avx512 => per_zmm,
            Isa::Avx2 => per_zmm / 2,
        })
    }
}

/// What the rewritten bodies use, so that only those helpers are added.
#[derive(Default)]
struct Used {
    any: bool,
    mul_add: bool,
    sin_cos: bool,
    /// Kernels whose far angles return the caller's far call ([`wide_tokens`]): the `*_far`
    /// function's result, or a batch's single-state calls.
    far: usize,
    /// Whether a batch body's kernel became `sin_cos_rows_near`: the helper (which
    /// `super::batch` emits wherever batch bodies may be dispatched) is kept only then.
    rows_near: bool,
    /// The vector helpers of packed bodies that the bodies call ([`super::pack`]).
    vector: std::collections::BTreeSet<String>,
    /// Whether a copy aligns its frame (`align_frame`, [`aligns_frame`]).
    align_frame: bool,
    /// The dispatched single-state functions' names and whether their bodies have `FAR`
    /// ([`with_bodies_called`]).
    bodies: BTreeMap<String, bool>,
    /// The dispatched functions whose copies return their result in the struct's `Written`
    /// union ([`written_result`]): a caller of a copy or body reads its `value`.
    written: std::collections::BTreeSet<String>,
}

/// The impl block (`attrs impl Name { items }`) with every eligible function dispatched, and
/// the two helpers when any was; unchanged when none is.
pub fn apply(impl_block: TokenStream, scalar: Scalar) -> TokenStream {
    with_impl_items(impl_block, |body| {
        let mut used = Used::default();
        let items = dispatch_items(body, &mut used, scalar);
        used.any.then(|| {
            let helpers = helpers(scalar, &used);
            quote!(#items #helpers)
        })
    })
}

/// `impl_block` (`attrs impl Name { items }`) with its items replaced by `f(items)`;
/// unchanged where `f` gives `None`, or without a body.
pub(crate) fn with_impl_items(
    impl_block: TokenStream,
    f: impl FnOnce(TokenStream) -> Option<TokenStream>,
) -> TokenStream {
    let mut tokens: Vec<TokenTree> = impl_block.into_iter().collect();
    let Some((pos, body)) = tokens.iter().enumerate().find_map(|(k, t)| match t {
        TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => Some((k, g.clone())),
        _ => None,
    }) else {
        return tokens.into_iter().collect();
    };
    let Some(items) = f(body.stream()) else {
        return tokens.into_iter().collect();
    };
    let mut group = Group::new(Delimiter::Brace, items);
    group.set_span(body.span());
    tokens[pos] = TokenTree::Group(group);
    tokens.into_iter().collect()
}

/// The index of `fn` and the name of the public function `item` (`… pub fn name …`), or
/// `None` when it is not one.
pub(crate) fn public_fn(item: &[TokenTree]) -> Option<(usize, Ident)> {
    let (f, name) = fn_name(item)?;
    matches!(item.get(f.checked_sub(1)?), Some(TokenTree::Ident(i)) if i == "pub")
        .then_some((f, name))
}

/// The private helpers the dispatched functions call.
fn helpers(scalar: Scalar, used: &Used) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let cfg = dispatch_cfg();
    let avx2_cfg = avx2_cfg();
    let lanes = Isa::Avx512.lanes(scalar);
    let mul_add = used.mul_add.then(|| {
        quote! {
            /// `a·b + c`: fused when `WIDE` (code compiled for AVX-512, which has FMA: one
            /// instruction), otherwise [`Self::mul_add`].
            #[inline(always)]
            fn mul_add_with<const WIDE: bool>(a: #t, b: #t, c: #t) -> #t {
                if WIDE {
                    a.mul_add(b, c)
                } else {
                    Self::mul_add(a, b, c)
                }
            }
        }
    });
    let sin_cos = used.sin_cos.then(|| {
        quote! {
            /// `k` rounded up to a whole number of AVX-512 registers: the padded length of the
            /// sines and cosines in dispatched code (computed on all of them when `WIDE`, on
            /// [`Self::sin_cos_lanes`] otherwise).
            #[inline(always)]
            const fn wide_lanes(k: usize) -> usize {
                k.div_ceil(#lanes) * #lanes
            }

            /// The sines and cosines of a dispatched body's angles `angles(q)`, inline: when
            /// `WIDE` (the AVX-512 and AVX2 copies) on all `P` lanes, fused, otherwise on
            /// [`Self::sin_cos_lanes`]. In the AVX-512 copies the optimiser vectorises the
            /// kernel on 512-bit registers, which slow down the code around them on Intel's
            /// AVX-512 cores; the single-state functions run those copies on AMD's alone (see
            /// [`Self::cpu_level`]).
            #[inline(always)]
            fn sin_cos_with<const K: usize, const P: usize, const WIDE: bool, Q, F>(
                q: Q,
                angles: F,
            ) -> ([#t; P], [#t; P])
            where
                F: FnOnce(Q) -> [#t; K],
            {
                Self::sin_cos_n::<K, P, WIDE>(
                    angles(q),
                    if WIDE { P } else { Self::sin_cos_lanes(K) },
                )
            }

            /// [`Self::sin_cos_with`] in a single-state body, where the angles beyond the
            /// kernel's bound are the caller's: when `WIDE`, `None` if any is (the body then
            /// returns what its `*_far` function computes), the same sines and cosines
            /// otherwise; when not `WIDE`, [`Self::sin_cos_with`]'s, its fallback included.
            /// That fallback calls the platform's `sin_cos` lane by lane: in line in a copy, the
            /// call clobbers every vector register, so that every value live across the kernel
            /// was spilled before it (G1's inverse dynamics copied its 70 velocities and
            /// accelerations to the stack) and the sines and cosines went through memory.
            #[inline(always)]
            fn sin_cos_near<const K: usize, const P: usize, const WIDE: bool, const FAR: bool, Q, F>(
                q: Q,
                angles: F,
            ) -> ::core::option::Option<([#t; P], [#t; P])>
            where
                F: FnOnce(Q) -> [#t; K],
            {
                if !WIDE || FAR {
                    return ::core::option::Option::Some(Self::sin_cos_with::<K, P, WIDE, Q, F>(
                        q, angles,
                    ));
                }
                let mut x = [0.0; P];
                for (p, a) in x.iter_mut().zip(angles(q)) {
                    *p = a;
                }
                let (mut sin, mut cos) = ([0.0; P], [0.0; P]);
                if Self::sin_cos_poly::<WIDE>(&x, &mut sin, &mut cos, P) {
                    ::core::option::Option::None
                } else {
                    ::core::option::Option::Some((sin, cos))
                }
            }
        }
    });
    let wide = wide_cond();
    let vector = vector_helpers(&quote!(#[cfg(#wide)]), &used.vector, scalar);
    let align_frame = align_frame_helper(used);
    quote! {
        #mul_add
        #sin_cos
        #vector

        /// The copies this CPU can run: 3 where it has the AVX-512 features the `*_avx512`
        /// copies are compiled for and is AMD's, 2 where it has them and is not, 1 where it has
        /// AVX2 and FMA, 0 otherwise. Detected once, then one relaxed atomic load, inlined into
        /// every dispatching wrapper (before, two calls of the standard library's cached
        /// detection per call: the UR5's `J_s` took 26–27 % longer and its gravity 16–19 %,
        /// measured side by side on a Zen 3).
        #cfg
        #[inline(always)]
        fn cpu_level() -> u8 {
            // The level plus one; 0 until detected.
            static LEVEL: ::core::sync::atomic::AtomicU8 = ::core::sync::atomic::AtomicU8::new(0);
            match LEVEL.load(::core::sync::atomic::Ordering::Relaxed) {
                0 => Self::detect_cpu_level(&LEVEL),
                stored => stored - 1,
            }
        }

        /// [`Self::cpu_level`] from the standard library's detection, stored in `level` (plus
        /// one). `extern "C"`, cold and never inlined: its callers know it cannot unwind.
        #cfg
        #[cold]
        #[inline(never)]
        extern "C" fn detect_cpu_level(level: &::core::sync::atomic::AtomicU8) -> u8 {
            let avx2 =
                ::std::is_x86_feature_detected!("avx2") && ::std::is_x86_feature_detected!("fma");
            let avx512 = avx2
                && ::std::is_x86_feature_detected!("avx512f")
                && ::std::is_x86_feature_detected!("avx512vl")
                && ::std::is_x86_feature_detected!("avx512dq")
                && ::std::is_x86_feature_detected!("avx512bw");
            // The vendor "AuthenticAMD" (EBX, EDX, ECX of leaf 0).
            // (`__cpuid` is safe in recent Rust, `unsafe` in older releases.)
            #[allow(unsafe_code, unused_unsafe)]
            // SAFETY: every x86-64 CPU has CPUID and its leaf 0.
            let vendor = unsafe { ::core::arch::x86_64::__cpuid(0) };
            let amd =
                (vendor.ebx, vendor.edx, vendor.ecx) == (0x6874_7541, 0x6974_6e65, 0x444d_4163);
            let found = if avx512 && amd {
                3
            } else if avx512 {
                2
            } else if avx2 {
                1
            } else {
                0
            };
            level.store(found + 1, ::core::sync::atomic::Ordering::Relaxed);
            found
        }

        /// Whether this CPU has the AVX-512 features the dispatched functions are compiled for
        /// (and AVX2 and FMA).
        #cfg
        #[inline(always)]
        fn has_avx512() -> bool {
            Self::cpu_level() >= 2
        }

        /// Whether the single-state functions run their AVX-512 copies here: on AMD's
        /// AVX-512 cores (Zen 4 and later), which run 512-bit instructions at full speed.
        /// Their copies' sines and cosines are vectorised on 512-bit registers, and on Intel's
        /// AVX-512 cores those slow down the code around them: a 6-joint arm's inverse
        /// dynamics took twice as long, measured on a Xeon (Emerald Rapids), where the AVX2
        /// copies were within ±5 % of the AVX-512 ones without them. Those cores run the AVX2
        /// copies (the batch functions, whose lanes fill the 512-bit registers, their AVX-512
        /// ones).
        #cfg
        #[inline(always)]
        fn has_fast_avx512() -> bool {
            Self::cpu_level() == 3
        }

        /// Whether this CPU has AVX2 and FMA, which the `*_avx2` copies are compiled for.
        #avx2_cfg
        #[inline(always)]
        fn has_avx2() -> bool {
            Self::cpu_level() >= 1
        }

        #align_frame
    }
}

/// [`Used::align_frame`]'s helper, when a copy calls it.
fn align_frame_helper(used: &Used) -> Option<TokenStream> {
    used.align_frame.then(|| {
        quote! {
        /// The first statement of the AVX-512 and AVX2 copies of the batch functions and of
        /// the longer packed bodies (alike limbs in lanes): 64 bytes of the copy's stack
        /// frame, aligned to 64, whose address leaves the function (`black_box`; nothing is
        /// written), so that the compiler aligns the whole frame to 64 bytes. The copies'
        /// vector spills (`ymm`, `zmm`) then never straddle a cache line. Without it the frame
        /// is aligned to 16 only, and which spills straddled one depended on where the
        /// process's stack began: measured, the same code of G1's mass matrix ran from 0.6 %
        /// to 12.5 % faster than the code it replaced in five processes, 16–19 % in each with
        /// the frame aligned.
        #[cfg(target_arch = "x86_64")]
        #[inline(always)]
        fn align_frame() {
            #[repr(C, align(64))]
            struct CacheLine([u8; 64]);
            let line = ::core::mem::MaybeUninit::<CacheLine>::uninit();
            ::core::hint::black_box(&line);
        }
        }
    })
}

/// The items of an impl body, each eligible function dispatched (noted in `used`). A batch
/// function (`X_batch`) is dispatched exactly when its single-state function `X` is, so
/// that the two fuse alike and give the same bits.
fn dispatch_items(stream: TokenStream, used: &mut Used, scalar: Scalar) -> TokenStream {
    let items = impl_items(stream);
    let mut sigs: Vec<Option<Signature>> = items.iter().map(|i| signature(i, scalar)).collect();
    // With the variants, `sin_cos`, the functions that have one and the variants are
    // dispatched together or not at all, so that a variant fed `sin_cos(q)` gives its
    // function's bits on every CPU (a sine is fused in a dispatched copy, not in the
    // portable one).
    let names: Vec<Option<String>> = items
        .iter()
        .map(|i| fn_name(i).map(|(_, n)| n.to_string()))
        .collect();
    let bases: Vec<&str> = names
        .iter()
        .flatten()
        .filter_map(|n| n.strip_suffix(super::given_sin_cos::SUFFIX))
        .collect();
    if !bases.is_empty() {
        let in_group = |n: &Option<String>| {
            n.as_deref().is_some_and(|n| {
                n == "sin_cos" || n.ends_with(super::given_sin_cos::SUFFIX) || bases.contains(&n)
            })
        };
        let any = names
            .iter()
            .zip(&sigs)
            .any(|(n, s)| in_group(n) && s.is_some());
        if any {
            for ((item, n), sig) in items.iter().zip(&names).zip(sigs.iter_mut()) {
                if in_group(n) && sig.is_none() {
                    *sig = signature_of(item, scalar, true);
                }
            }
        }
    }
    let singles: Vec<String> = sigs
        .iter()
        .flatten()
        .filter(|s| s.generic_names.is_empty())
        .map(|s| s.name.to_string())
        .collect();
    // A body that calls another dispatched single-state function is dispatched after it, so
    // that its copies call that function's body ([`with_bodies_called`]); the items keep their
    // order.
    let calls_single = |sig: &Option<Signature>| {
        sig.as_ref()
            .is_some_and(|s| calls_any(&s.body, &singles, &s.name.to_string()))
    };
    let is_caller: Vec<bool> = sigs.iter().map(calls_single).collect();
    let (callers, others): (Vec<usize>, Vec<usize>) = (0..items.len()).partition(|&k| is_caller[k]);
    let mut slots: Vec<Option<(Vec<TokenTree>, Option<Signature>)>> =
        items.into_iter().zip(sigs).map(Some).collect();
    let mut outs: Vec<TokenStream> = vec![TokenStream::new(); slots.len()];
    // The batch kernel for the copies, held back until it is known whether a body calls it.
    let mut rows_near = None;
    for k in others.into_iter().chain(callers) {
        let Some((item, mut sig)) = slots[k].take() else {
            continue;
        };
        if fn_name(&item).is_some_and(|(_, n)| n == "sin_cos_rows_near") {
            rows_near = Some(item);
            continue;
        }
        if let Some(sig) = sig.as_mut().filter(|_| is_caller[k]) {
            let body = std::mem::take(&mut sig.body);
            sig.body = with_bodies_called(body, &used.bodies, &used.written);
        }
        let out = &mut outs[k];
        // A batch function follows its single-state function; another generic function
        // (`constrained_forward_dynamics`, whose `K` sizes the caller's constraints and whose
        // substitutions are unrolled in its body) is dispatched on its own.
        let follows = |s: &Signature| {
            let name = s.name.to_string();
            s.generic_names.is_empty()
                || match name.strip_suffix("_batch") {
                    Some(single) => singles.iter().any(|n| n == single),
                    None => true,
                }
        };
        match sig.filter(follows) {
            Some(sig) => {
                out.extend(dispatched(&item, sig, used, scalar));
                used.any = true;
            }
            // Not dispatched (so its function is not: it cannot happen for a body this
            // large), a batch body only the AVX-512 copy may run goes state by state.
            None if has_mark(&item, super::zmm::ONLY_MARK) => {
                match signature_of(&item, scalar, true) {
                    Some(sig) => out.extend(zmm_only(&item, sig, None, scalar)),
                    None => out.extend(item),
                }
            }
            None => out.extend(item),
        }
    }
    let mut out: TokenStream = outs.into_iter().collect();
    if used.rows_near {
        out.extend(rows_near.into_iter().flatten());
    }
    out
}

/// The items of an impl body: each function (attributes to body) or other item (to its
/// `;`), and what follows the last one.
pub(crate) fn impl_items(stream: TokenStream) -> Vec<Vec<TokenTree>> {
    let mut items: Vec<Vec<TokenTree>> = Vec::new();
    let mut item: Vec<TokenTree> = Vec::new();
    let mut seen_fn = false;
    for tt in stream {
        let end = match &tt {
            TokenTree::Punct(p) if p.as_char() == ';' && !seen_fn => true,
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace && seen_fn => true,
            TokenTree::Ident(i) if i == "fn" => {
                seen_fn = true;
                false
            }
            _ => false,
        };
        item.push(tt);
        if end {
            items.push(std::mem::take(&mut item));
            seen_fn = false;
        }
    }
    if !item.is_empty() {
        items.push(item);
    }
    items
}

/// The index of `fn` and the name of the function `item`, if it is one.
fn fn_name(item: &[TokenTree]) -> Option<(usize, Ident)> {
    let f = item
        .iter()
        .position(|t| matches!(t, TokenTree::Ident(i) if i == "fn"))?;
    match item.get(f + 1)? {
        TokenTree::Ident(name) => Some((f, name.clone())),
        _ => None,
    }
}

/// What [`dispatched`] needs of an eligible function.
struct Signature {
    /// The index of `pub` (of `fn` for a private function) in the item.
    p: usize,
    /// Whether the function is `pub` (its wrapper is too).
    public: bool,
    name: Ident,
    /// The generic parameters without the brackets, and their names (`const` ones only).
    generics: TokenStream,
    generic_names: Vec<Ident>,
    args: TokenStream,
    arg_names: Vec<Ident>,
    ret: TokenStream,
    body: TokenStream,
}

/// The signature of `item` (attributes, `pub fn name(&self, …) -> R { body }`) when it is
/// eligible, otherwise `None`.
fn signature(item: &[TokenTree], scalar: Scalar) -> Option<Signature> {
    signature_of(item, scalar, false)
}

/// [`signature`], with `forced`: whatever the body's size and arithmetic.
fn signature_of(item: &[TokenTree], scalar: Scalar, forced: bool) -> Option<Signature> {
    let is_ident = |t: &TokenTree, s: &str| matches!(t, TokenTree::Ident(i) if i == s);
    // `pub fn`, or a private `fn` (a helper such as `mass_matrix_factor`, which a public
    // function without arithmetic of its own calls): not `pub const fn`, `unsafe fn`,
    // `extern "C" fn`, `pub(crate) fn`, …
    let f = item.iter().position(|t| is_ident(t, "fn"))?;
    let public = f > 0 && is_ident(&item[f - 1], "pub");
    let p = if public { f - 1 } else { f };
    let plain_start = p == 0
        || matches!(&item[p - 1], TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket);
    if !plain_start {
        return None;
    }
    let TokenTree::Ident(name) = item.get(f + 1)? else {
        return None;
    };
    // `<const B: usize, …>`: const parameters only, passed on by name; none on a private one.
    let (generics, generic_names, after) = const_generics(&item[f + 2..])?;
    if !public && !generic_names.is_empty() {
        return None;
    }
    let after = f + 2 + after;
    let TokenTree::Group(args) = item.get(after)? else {
        return None;
    };
    if args.delimiter() != Delimiter::Parenthesis {
        return None;
    }
    let TokenTree::Group(body) = item.last()? else {
        return None;
    };
    let ret: TokenStream = item[after + 1..item.len() - 1].iter().cloned().collect();
    let arg_names = receiver_and_names(args.stream())?;
    let body = body.stream();
    if contains_ident(&body, "extern")
        || (!forced
            && (!calls_arithmetic(&body)
                || (size(&body) < MIN_TOKENS && !several_angles(&body, scalar))))
    {
        return None;
    }
    Some(Signature {
        p,
        public,
        name: name.clone(),
        generics,
        generic_names,
        args: args.stream(),
        arg_names,
        ret,
        body,
    })
}

/// Whether the attributes of `item` (its doc comment) hold `mark`.
fn has_mark(item: &[TokenTree], mark: &str) -> bool {
    let f = fn_name(item).map_or(item.len(), |(f, _)| f);
    item[..f].iter().any(|t| t.to_string().contains(mark))
}

/// Packed bodies of fewer `let` statements than this leave their copies' frames as they are.
const ALIGN_FRAME_LETS: usize = 128;

/// Whether the copies of `body` align their stack frames to 64 bytes (`align_frame`): a
/// batch body's, and a packed one's (it calls the `v4_*` helpers of
/// [`super::function::VECTOR_HELPERS`]) of [`ALIGN_FRAME_LETS`] statements or more. Counted in
/// the benchmark binary's AVX-512 copies, the packed tree bodies keep hundreds of `ymm` and
/// `zmm` values on their stack (TALOS' inverse dynamics 396 accesses, its forward dynamics
/// 1,203), the batch bodies tens to hundreds; the arms' single-state bodies (no packs) and the
/// short packed ones (the Panda's and rand7's poses, 58 and 69 statements) none or a few, for
/// which the alignment's prologue would be all they got.
fn aligns_frame(body: &TokenStream, is_batch: bool) -> bool {
    /// The `let` statements of `stream` and whether it calls a vector helper.
    fn scan(stream: &TokenStream) -> (usize, bool) {
        stream
            .clone()
            .into_iter()
            .fold((0, false), |(lets, packed), t| match t {
                TokenTree::Ident(i) if i == "let" => (lets + 1, packed),
                TokenTree::Ident(i) => (
                    lets,
                    packed || super::function::VECTOR_HELPERS.iter().any(|h| i == h),
                ),
                TokenTree::Group(g) => {
                    let (l, p) = scan(&g.stream());
                    (lets + l, packed || p)
                }
                _ => (lets, packed),
            })
    }
    let (lets, packed) = scan(body);
    is_batch || (packed && lets >= ALIGN_FRAME_LETS)
}

/// The three functions for the eligible `item`.
fn dispatched(item: &[TokenTree], sig: Signature, used: &mut Used, scalar: Scalar) -> TokenStream {
    if has_mark(item, super::zmm::ONLY_MARK) {
        let far = batch_far_call(&sig.name, &sig.arg_names, &sig.ret, &used.written);
        let before = used.far;
        let fused = wide_body(sig.body.clone(), used, far.as_ref());
        let fused = with_far_args(fused, &sig.arg_names, used.far > before);
        let z_body = super::zmm::token_body(&fused);
        used.align_frame = true;
        return zmm_only(item, sig, z_body, scalar);
    }
    let Signature {
        p,
        public,
        name,
        generics,
        generic_names,
        args,
        arg_names,
        ret,
        body,
    } = sig;
    // A result written into the struct's union: the copies and the body return the union,
    // the wrapper reads its `value`.
    let (body, copy_ret, value) = match written_result(&body) {
        Some((union, body)) => {
            used.written.insert(name.to_string());
            (body, quote!(-> #union), quote!(.value))
        }
        None => (body, ret.clone(), quote!()),
    };
    let (attrs, out_of_line) = without_inline_never(&item[..p]);
    let fast = format_ident!("{}_avx512", name);
    let mid = format_ident!("{}_avx2", name);
    let body_fn = format_ident!("{}_body", name);
    // An angle beyond the kernel's bound: the copy returns `X_far`'s result ([`wide_tokens`]).
    let far = format_ident!("{}_far", name);
    // `::<B, …>` after a generic function's name (the batch functions'), nothing otherwise.
    let turbofish = (!generic_names.is_empty()).then(|| quote!(::<#(#generic_names),*>));
    // SAFETY (in the generated code): reached only from the AVX-512 and AVX2 copies, which run
    // only on CPUs with AVX2 and FMA, and from code compiled with both: the features `X_far` is
    // compiled for.
    // The arguments as passed, kept aside at the body's top (`far_args`): bodies shadow them
    // (an actuated robot's forward dynamics takes `tau − friction(q̇)` as its `tau`), and
    // `X_far` must get the originals.
    // An output argument (`m: &mut …`, `mass_matrix_lower_into`) is not kept aside: the body
    // writes through it before the angles are known, so `X_far` gets it as it is.
    let kept = by_value_names(&args);
    let batch_far = batch_far_call(&name, &arg_names, &ret, &used.written);
    let is_batch = batch_far.is_some();
    let far_call = batch_far.unwrap_or_else(|| {
        quote!({
            let (#(#kept,)*) = far_args;
            unsafe { self.#far #turbofish (#(#arg_names),*) }
        })
    });
    let align = aligns_frame(&body, is_batch).then(|| quote!(Self::align_frame();));
    used.align_frame |= align.is_some();
    let far_before = used.far;
    let fused = wide_body(body, used, Some(&far_call));
    let exits = used.far > far_before;
    let fused = with_far_args(fused, &kept, exits);
    // A single-state body's exits need `FAR` and `X_far`; a batch's call its single-state
    // function instead.
    let has_far = exits && !is_batch;
    if generic_names.is_empty() {
        used.bodies.insert(name.to_string(), has_far);
    }
    // A large batch body's AVX-512 and AVX2 copies (and a mid-sized one's with a vector
    // result): their lane arithmetic as instructions.
    let z_body = has_mark(item, super::zmm::DOC_MARK)
        .then(|| super::zmm::token_body(&fused))
        .flatten();
    let cfg = dispatch_cfg();
    let avx2 = avx2_cond();
    let avx2_cfg = avx2_cfg();
    let fast_doc = format!(
        " [`Self::{name}`] compiled for AVX-512: call it only on a CPU that has the features \
         [`Self::has_avx512`] checks."
    );
    let mid_doc = format!(
        " [`Self::{name}`] compiled for AVX2 with FMA, the same fused body as \
         [`Self::{fast}`] (the same bits): call it only on a CPU that has the features \
         [`Self::has_avx2`] checks."
    );
    let body_doc = format!(
        " The body of [`Self::{name}`]; `WIDE`: fused multiply-adds, and the sines and cosines \
         on the whole of the copy's registers (the AVX-512 and AVX2 copies, and the portable \
         body where the target has AVX2 and FMA)."
    );
    let fast_generics = (!generic_names.is_empty()).then(|| quote!(<#generics>));
    let const_generics = generics.clone();
    let generics = if generic_names.is_empty() {
        quote!()
    } else {
        quote!(, #generics)
    };
    let vis = public.then(|| quote!(pub));
    // Where no copy runs: the body compiled for the target, `X_portable`. Where the dispatch
    // exists and the target lacks AVX2 or FMA (the default x86-64 target), only a CPU without
    // AVX2 runs it: it is out of line there, so that a crate calling `X` from another crate
    // (the test binaries, a user's crate over a generated library) compiles the small wrapper
    // and not the whole body again. A batch function's (which holds a `B`-wide body) is out
    // of line everywhere. Out of line means `extern "C"`, so that a caller knows it cannot
    // unwind without seeing it (see `batch::out_of_line`). Elsewhere (`-C target-cpu` with
    // AVX2 and FMA or AVX-512, other architectures) a single-state body is inlined into the
    // wrapper, as it was before there was a dispatch.
    let portable = format_ident!("{}_portable", name);
    // A body whose kernel leaves the far angles to `X_far` has a second `const`, `FAR`: true in
    // `X_far` alone, whose kernel keeps the fallback in line.
    let far_generic = has_far.then(|| quote!(, const FAR: bool));
    // A call of the body with `WIDE` = `wide` (and `FAR` = `far`, where it has one).
    let call_body = |wide: TokenStream, far: bool| {
        let far = has_far.then(|| quote!(, #far));
        quote!(self.#body_fn::<#wide #far #(, #generic_names)*>(#(#arg_names),*))
    };
    // Compiled with AVX2 and FMA, a single-state function's portable body is the copies'
    // (`WIDE`: packs as vector instructions, the sines on all lanes, far angles out of line);
    // a batch function's stays the vectoriser's body, its lanes run as `native_call` says.
    let wide_native = wide_native_cond();
    let portable_wide = if is_batch {
        quote!(false)
    } else {
        quote!({ cfg!(#wide_native) })
    };
    let portable_body = call_body(portable_wide, false);
    // The default x86-64 target's (no AVX2 there).
    let sse2_body = call_body(quote!(false), false);
    let fallback = quote!(self.#portable #turbofish (#(#arg_names),*));
    let wrapper_fallback = if value.is_empty() {
        fallback.clone()
    } else {
        quote!(unsafe { #fallback #value })
    };
    let far_item = has_far.then(|| {
        let doc = format!(
            " [`Self::{name}`] where an angle lies beyond the sines' bound (10⁶ rad for `f64`, \
             10⁴ for `f32`), which the AVX-512 and AVX2 copies (and the portable body, where \
             the crate is compiled with AVX2 and FMA) leave to it: the same fused body with \
             the kernel's fallback (the platform's sines and cosines for those angles) in \
             line, compiled for AVX2 and FMA, so the same bits as the copies. Cold and out of \
             line, so that the copies make no call of their own."
        );
        // Where no `WIDE` body runs, nothing calls it: `#[inline(always)]`, so that it is
        // compiled only where called (nowhere), not as one more portable body (a
        // `#[inline(never)]` one was: 22,920 of the UR5's 23,463 instructions in a library
        // built for `x86-64-v4`, before such a library's portable body became `WIDE`).
        let other = " Where no copy runs and the crate lacks AVX2 or FMA: never called (the \
                     portable body keeps its fallback), and so never compiled.";
        let wide = wide_cond();
        let far_body = call_body(quote!(true), true);
        quote! {
            #[doc = #doc]
            #[cfg(#wide)]
            #[target_feature(enable = "avx2,fma")]
            #[cold]
            #[allow(unsafe_code, improper_ctypes_definitions)]
            unsafe extern "C" fn #far #fast_generics (#args) #copy_ret {
                #far_body
            }
            #[doc = #other]
            #[cfg(not(#wide))]
            #[inline(always)]
            #[allow(unsafe_code, improper_ctypes_definitions)]
            unsafe extern "C" fn #far #fast_generics (#args) #copy_ret {
                #fallback
            }
        }
    });
    let doc = format!(" [`Self::{name}`] where no copy runs: the body compiled for the target.");
    let wide_doc = if is_batch {
        doc.clone()
    } else {
        format!(
            " [`Self::{name}`] where no copy runs: the body compiled for the target, the \
             copies' fused one (`WIDE`) where the target has AVX2 and FMA."
        )
    };
    let out_of_line_portable = |body: &TokenStream| {
        quote! {
            #[inline(never)]
            #[allow(improper_ctypes_definitions)]
            extern "C" fn #portable #fast_generics (#args) #copy_ret {
                #body
            }
        }
    };
    let portable = if out_of_line {
        let item = out_of_line_portable(&portable_body);
        quote! {
            #[doc = #wide_doc]
            #item
        }
    } else {
        let cond = avx2_copy_cond();
        let item = out_of_line_portable(&sse2_body);
        quote! {
            #[doc = #doc]
            #[cfg(#cond)]
            #item
            #[doc = #wide_doc]
            #[cfg(not(#cond))]
            #[inline(always)]
            fn #portable #fast_generics (#args) #copy_ret {
                #portable_body
            }
        }
    };
    // The call of the body in a copy for `isa`, and the item of its body of instructions
    // where it has one. For `B` that do not fill its registers, the vectoriser's body: the
    // same bits, and the body of instructions is not generated for them (see `zmm_only`).
    let plain = call_body(quote!(true), false);
    let copy = |isa: Isa, copy: &Ident| -> (TokenStream, TokenStream) {
        let Some(z_body) = z_body.as_ref() else {
            return (plain.clone(), quote!());
        };
        let body_z = format_ident!("{}_body_{}", name, isa.suffix());
        let doc = format!(
            " The body of [`Self::{copy}`]: [`Self::{body_fn}`] with its lane arithmetic \
             as {} instructions (the runtime's `{}`).",
            isa.prose(),
            isa.token()
        );
        let lanes = isa.lanes(scalar);
        let (Some(b), Some(elem)) = (generic_names.first(), array_elem(&ret)) else {
            return (plain.clone(), quote!());
        };
        let Some((per_register, fill_item)) = super::batch::per_register(
            copy,
            &body_z,
            &arg_names,
            &elem,
            &lanes,
            b,
            &const_generics,
            &args,
            &isa.attrs(),
        ) else {
            return (plain.clone(), quote!());
        };
        let call = quote! {
            if const { #b % #lanes == 0 } {
                #per_register
            } else {
                #plain
            }
        };
        let item = token_body_item(isa, &body_z, b, &lanes, &args, &ret, z_body, &doc);
        (call, quote!(#item #fill_item))
    };
    let (fast_call, fast_body) = copy(Isa::Avx512, &fast);
    let (mid_call, mid_body) = copy(Isa::Avx2, &mid);
    // With a body of instructions, a copy is also what a crate compiled with its features
    // runs (for `B` that fill its registers); without one it would be the portable code.
    let native = |isa: Isa, copy: &Ident, body: &TokenStream, cfg: TokenStream| match (
        body.is_empty(),
        generic_names.first(),
    ) {
        (false, Some(b)) => (isa.cfg(), native_call(isa, copy, b, scalar, &arg_names)),
        _ => (cfg, quote!()),
    };
    let (fast_cfg, native_fast) = native(Isa::Avx512, &fast, &fast_body, cfg.clone());
    // The single-state functions' AVX-512 copies run on AMD's cores alone (see
    // `has_fast_avx512`); the batch functions' (`X_batch`) wherever the features are.
    let has_fast = if !name.to_string().ends_with("_batch") {
        format_ident!("has_fast_avx512")
    } else {
        format_ident!("has_avx512")
    };
    let (mid_cfg, native_mid) = native(Isa::Avx2, &mid, &mid_body, avx2_cfg);
    quote! {
        #attrs
        #[allow(unsafe_code)]
        #vis fn #name #fast_generics (#args) #ret {
            #cfg
            {
                if Self::#has_fast() {
                    return unsafe { self.#fast #turbofish (#(#arg_names),*) #value };
                }
                #[cfg(#avx2)]
                {
                    if Self::has_avx2() {
                        return unsafe { self.#mid #turbofish (#(#arg_names),*) #value };
                    }
                }
                #native_mid
            }
            #native_fast
            #wrapper_fallback
        }

        #portable

        #far_item

        #[doc = #fast_doc]
        #fast_cfg
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,fma")]
        #[allow(unsafe_code, improper_ctypes_definitions)]
        unsafe extern "C" fn #fast #fast_generics (#args) #copy_ret {
            #align
            #fast_call
        }

        #fast_body

        #[doc = #mid_doc]
        #mid_cfg
        #[target_feature(enable = "avx2,fma")]
        #[allow(unsafe_code, improper_ctypes_definitions)]
        unsafe extern "C" fn #mid #fast_generics (#args) #copy_ret {
            #align
            #mid_call
        }

        #mid_body

        #[doc = #body_doc]
        #[inline(always)]
        #[allow(unsafe_code)]
        fn #body_fn<const WIDE: bool #far_generic #generics>(#args) #copy_ret {
            #fused
        }
    }
}

/// A batch function's far angles (`name` ends in `_batch`, `ret` its `-> [R; B]`): its
/// single-state function once per state, whose copies give the same bits as the batch's. A
/// batch is dispatched only with its single-state function, so both of these exist: where the
/// AVX2 copies do, `f_avx2` (every CPU that runs a batch copy has AVX2 and FMA), not the
/// wrapper `f`, whose CPU check an `extern "C"` copy must not reach (its first call detects
/// the CPU, a call that may unwind); elsewhere `f_portable`, there compiled with FMA or for
/// another architecture, where the batch's copies fuse alike or do not exist. A `while` loop
/// writing the results in place: in this cold branch the optimiser left `from_fn`'s closure
/// out of line, a call that may unwind (and so an abort path in the `extern "C"` copy).
///
/// ```text
/// { let (q, qd, qdd) = far_args; let mut out = MaybeUninit::<[R; B]>::uninit(); let mut l = 0;
///   while l < B { out.as_mut_ptr().cast::<R>().add(l).write(f_avx2(&q[l], &qd[l], &qdd[l])); l += 1; }
///   out.assume_init() }
/// ```
fn batch_far_call(
    name: &Ident,
    arg_names: &[Ident],
    ret: &TokenStream,
    written: &std::collections::BTreeSet<String>,
) -> Option<TokenStream> {
    let single = name.to_string();
    let single = single.strip_suffix("_batch")?;
    let elem = array_elem(ret)?;
    // The single-state copies' result in the struct's union ([`written_result`]): its value.
    let value = written.contains(single).then(|| quote!(.value));
    let (avx2, portable) = (
        format_ident!("{}_avx2", single),
        format_ident!("{}_portable", single),
    );
    let portable_call = match &value {
        Some(value) => quote!(unsafe { self.#portable(#(&#arg_names[l]),*) #value }),
        None => quote!(self.#portable(#(&#arg_names[l]),*)),
    };
    let cond = avx2_copy_cond();
    Some(quote!({
        let (#(#arg_names,)*) = far_args;
        let mut out = ::core::mem::MaybeUninit::<[#elem; B]>::uninit();
        let mut l = 0;
        while l < B {
            #[cfg(#cond)]
            let v = unsafe { self.#avx2(#(&#arg_names[l]),*) #value };
            #[cfg(not(#cond))]
            let v = #portable_call;
            // SAFETY: `l < B`, within `out`.
            unsafe { out.as_mut_ptr().cast::<#elem>().add(l).write(v) };
            l += 1;
        }
        // SAFETY: the loop wrote all `B` results.
        unsafe { out.assume_init() }
    }))
}

/// Whether `body` calls (`self.f(…)`) one of the functions `names` other than `own`.
fn calls_any(body: &TokenStream, names: &[String], own: &str) -> bool {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    tokens.iter().enumerate().any(|(k, t)| match t {
        TokenTree::Group(g) => calls_any(&g.stream(), names, own),
        _ => {
            method_call(&tokens[k..]).is_some_and(|(f, _)| f != own && names.iter().any(|n| f == n))
        }
    })
}

/// The name and arguments of the call `self.f(args)` at the start of `tokens`.
fn method_call(tokens: &[TokenTree]) -> Option<(&Ident, &Group)> {
    match tokens {
        [TokenTree::Ident(s), TokenTree::Punct(dot), TokenTree::Ident(f), TokenTree::Group(args), ..]
            if s == "self"
                && dot.as_char() == '.'
                && args.delimiter() == Delimiter::Parenthesis =>
        {
            Some((f, args))
        }
        _ => None,
    }
}

/// `body` with each call of a dispatched single-state function `f` (in `bodies`, with
/// whether its body has `FAR`) made a call of its body in the copies, and of its portable
/// copy otherwise: `self.f(args)` becomes
///
/// ```text
/// { if WIDE { self.f_body::<true, false>(args) } else { self.f_portable(args) } }
/// ```
///
/// (`, false` only for a body with `FAR`). Calling `f` itself, the copies would run its
/// wrapper's CPU check, whose first call detects the CPU (a call that may unwind, so an abort
/// path in an `extern "C"` copy, which the `no_panic` test rejects), and then its copy out of
/// line; its body is fused into theirs instead, with its far angles left to `f_far` as in its
/// own copies. `constrained_forward_dynamics` calls `mass_matrix_factor` so.
fn with_bodies_called(
    body: TokenStream,
    bodies: &BTreeMap<String, bool>,
    written: &std::collections::BTreeSet<String>,
) -> TokenStream {
    let tokens: Vec<TokenTree> = body.into_iter().collect();
    let mut out = TokenStream::new();
    let mut k = 0;
    while k < tokens.len() {
        if let Some((f, args)) = method_call(&tokens[k..]) {
            if let Some(&far) = bodies.get(&f.to_string()) {
                let args = with_bodies_called(args.stream(), bodies, written);
                let body_fn = format_ident!("{}_body", f);
                let portable = format_ident!("{}_portable", f);
                let not_far = far.then(|| quote!(, false));
                out.extend(if written.contains(&f.to_string()) {
                    // Its result in the struct's union ([`written_result`]): its value.
                    quote!({
                        if WIDE {
                            unsafe { self.#body_fn::<true #not_far>(#args).value }
                        } else {
                            unsafe { self.#portable(#args).value }
                        }
                    })
                } else {
                    quote!({
                        if WIDE {
                            self.#body_fn::<true #not_far>(#args)
                        } else {
                            self.#portable(#args)
                        }
                    })
                });
                k += 4;
                continue;
            }
        }
        match &tokens[k] {
            TokenTree::Group(g) => {
                let mut new = Group::new(
                    g.delimiter(),
                    with_bodies_called(g.stream(), bodies, written),
                );
                new.set_span(g.span());
                out.extend([TokenTree::Group(new)]);
            }
            t => out.extend([t.clone()]),
        }
        k += 1;
    }
    out
}

/// A body that writes its result into the struct's union (`Written`,
/// [`super::function::written_union_item`]): it declares `let mut m: W<R> = W { uninit: () };`
/// at its top level and ends `unsafe { m.value }`. Then the union's type `W<R>` and the body
/// ending `m` instead, so that the copies return the union through the caller's memory and
/// the wrapper reads its `value`; `None` for any other body.
fn written_result(body: &TokenStream) -> Option<(TokenStream, TokenStream)> {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    let is = |t: &TokenTree, s: &str| match t {
        TokenTree::Ident(i) => i == s,
        TokenTree::Punct(p) => s.len() == 1 && s.starts_with(p.as_char()),
        TokenTree::Group(_) | TokenTree::Literal(_) => false,
    };
    let [.., TokenTree::Ident(unsafe_kw), TokenTree::Group(tail)] = &tokens[..] else {
        return None;
    };
    let tail: Vec<TokenTree> = tail.stream().into_iter().collect();
    if unsafe_kw != "unsafe"
        || tail.len() != 3
        || !(is(&tail[0], "m") && is(&tail[1], ".") && is(&tail[2], "value"))
    {
        return None;
    }
    // `let mut m : W < R > = W { uninit : () } ;` at the top level.
    let union = tokens.windows(4).enumerate().find_map(|(k, w)| {
        (is(&w[0], "let") && is(&w[1], "mut") && is(&w[2], "m") && is(&w[3], ":")).then(|| {
            let eq = tokens[k + 4..]
                .iter()
                .position(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == '='))?;
            let init = &tokens[k + 4 + eq + 1..];
            match init {
                [TokenTree::Ident(_), TokenTree::Group(g), ..]
                    if contains_ident(&g.stream(), "uninit") =>
                {
                    Some(
                        tokens[k + 4..k + 4 + eq]
                            .iter()
                            .cloned()
                            .collect::<TokenStream>(),
                    )
                }
                _ => None,
            }
        })?
    })?;
    let mut body: TokenStream = tokens[..tokens.len() - 2].iter().cloned().collect();
    body.extend(quote!(m));
    Some((union, body))
}

/// `body` with the arguments as passed kept aside at its top (`far_args`) when `far` (its
/// kernel's far angles return through them).
fn with_far_args(body: TokenStream, arg_names: &[Ident], far: bool) -> TokenStream {
    if far {
        quote!(let far_args = (#(#arg_names,)*); #body)
    } else {
        body
    }
}

/// A batch function whose body is too large for the optimiser's vectoriser
/// ([`super::zmm::ONLY_MARK`]): its body of instructions `z_body` where the CPU has AVX-512
/// or AVX2 and `B` fills whole registers of it, and otherwise the single-state function once
/// per state (which is dispatched itself, so a state's result is its bits on every CPU):
///
/// ```text
/// #[inline] pub fn f_batch<const B: usize>(&self, args) -> [R; B] {
///     #[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f")))]
///     {
///         if const { B % 8 == 0 } && Self::has_avx512() { return unsafe { self.f_batch_avx512::<B>(args) }; }
///         #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
///         { if const { B % 4 == 0 } && Self::has_avx2() { return unsafe { self.f_batch_avx2::<B>(args) }; } }
///         #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
///         { if const { B % 4 == 0 } { return unsafe { self.f_batch_avx2::<B>(args) }; } }
///     }
///     #[cfg(all(target_arch = "x86_64", target_feature = "avx512f", …, target_feature = "fma"))]
///     { if const { B % 8 == 0 } { return unsafe { self.f_batch_avx512::<B>(args) }; } }
///     (f once per state)
/// }
/// unsafe extern "C" fn f_batch_avx512<const B: usize>(&self, args) -> [R; B]  // AVX-512
/// unsafe extern "C" fn f_batch_avx512_fill<const B: usize>(&self, args, out)  // its loop
/// unsafe fn f_batch_body_avx512(&self, args of 8 states) -> [R; 8]            // z_body, `Avx512`
/// unsafe extern "C" fn f_batch_avx2<const B: usize>(&self, args) -> [R; B]    // AVX2 and FMA
/// unsafe extern "C" fn f_batch_avx2_fill<const B: usize>(&self, args, out)    // its loop
/// unsafe fn f_batch_body_avx2(&self, args of 4 states) -> [R; 4]              // z_body, `Avx2`
/// ```
///
/// (The lanes of `f64`; `f32` has twice as many.) The tests of `B` are inline `const`s, so
/// that for other `B` the compiler does not even generate the copy: there its token methods
/// would be the operators' lane loops, and Talos' forward dynamics batch with `B` = 3 took
/// 379 s to compile in release with a plain `if`, 2.8 s with the `const` one. On a CPU with
/// AVX-512, a `B` that fills AVX2 registers but not AVX-512 ones (4 `f64`) runs the AVX2
/// copy: the same bits, as the two copies fuse alike.
///
/// Without `z_body` (the body did not parse), only the per-state loop.
fn zmm_only(
    item: &[TokenTree],
    sig: Signature,
    z_body: Option<TokenStream>,
    scalar: Scalar,
) -> TokenStream {
    let (name, generics, args, arg_names, ret) = (
        &sig.name,
        &sig.generics,
        &sig.args,
        &sig.arg_names,
        &sig.ret,
    );
    let (attrs, _) = without_inline_never(&item[..sig.p]);
    let vis = sig.public.then(|| quote!(pub));
    // `-> [R; B]`: the single-state function's result `R`, and the name of `B`.
    let elem = array_elem(ret);
    let single = name
        .to_string()
        .strip_suffix("_batch")
        .map(|s| Ident::new(s, name.span()));
    let (Some(elem), Some(single), [b]) = (elem, single, sig.generic_names.as_slice()) else {
        return item.iter().cloned().collect();
    };
    let per_state = super::batch::per_state(&single, arg_names, &quote!(<#elem>));
    let Some(z_body) = z_body else {
        return quote! {
            #attrs
            #vis fn #name<#generics>(#args) #ret {
                #per_state
            }
        };
    };
    // A copy for `isa`: its call in the wrapper (after its `const` test of `B` and its CPU
    // check), the copy and its body of instructions, and its unchecked call where the crate
    // has its features (`native_call`).
    let copy = |isa: Isa| -> (TokenStream, TokenStream, TokenStream) {
        let lanes = isa.lanes(scalar);
        let (fast, body_z) = (
            format_ident!("{}_{}", name, isa.suffix()),
            format_ident!("{}_body_{}", name, isa.suffix()),
        );
        let has = format_ident!("has_{}", isa.suffix());
        let prose = isa.prose();
        let fast_doc = format!(
            " [`Self::{name}`] compiled for {prose}, for `B` a multiple of {lanes}: call it \
             only on a CPU that has the features [`Self::{has}`] checks."
        );
        let body_doc = format!(
            " The body of [`Self::{fast}`]: the unrolled code of [`Self::{single}`] on lanes, \
             its arithmetic as {prose} instructions (the runtime's `{}`).",
            isa.token()
        );
        let body_item = token_body_item(isa, &body_z, b, &lanes, args, ret, &z_body, &body_doc);
        // (`None` for a function without states, which no batch function is.)
        let attrs = isa.attrs();
        let (per_register, fill_item) = super::batch::per_register(
            &fast, &body_z, arg_names, &elem, &lanes, b, generics, args, &attrs,
        )
        .unwrap_or_else(|| (per_state.clone(), quote!()));
        let call = quote! {
            if const { #b % #lanes == 0 } && Self::#has() {
                return unsafe { self.#fast::<#b>(#(#arg_names),*) };
            }
        };
        let items = quote! {
            #[doc = #fast_doc]
            #attrs
            #[allow(unsafe_code, improper_ctypes_definitions)]
            unsafe extern "C" fn #fast<#generics>(#args) #ret {
                Self::align_frame();
                if const { #b % #lanes == 0 } {
                    #per_register
                } else {
                    #per_state
                }
            }

            #fill_item

            #body_item
        };
        let native = native_call(isa, &fast, b, scalar, arg_names);
        (call, items, native)
    };
    let (fast_call, fast_items, native_fast) = copy(Isa::Avx512);
    let (mid_call, mid_items, native_mid) = copy(Isa::Avx2);
    let cfg = dispatch_cfg();
    let avx2 = avx2_cond();
    quote! {
        #attrs
        #[allow(unsafe_code)]
        #vis fn #name<#generics>(#args) #ret {
            #cfg
            {
                #fast_call
                #[cfg(#avx2)]
                {
                    #mid_call
                }
                #native_mid
            }
            #native_fast
            #per_state
        }

        #fast_items

        #mid_items
    }
}

/// In a batch function's wrapper, where the crate is compiled with the features of `isa`'s
/// copy `copy`, which holds the body of instructions: that copy, for `B` (`b`) a multiple of
/// the register's lanes, without a check of the CPU. Otherwise such a build ran the
/// vectoriser's `B`-wide body, or for the largest bodies the single-state function once per
/// state. The AVX2 call sits in the dispatch's block (a crate with AVX-512 has no such call),
/// the AVX-512 one outside it (such a crate has no dispatch).
fn native_call(
    isa: Isa,
    copy: &Ident,
    b: &Ident,
    scalar: Scalar,
    arg_names: &[Ident],
) -> TokenStream {
    let (cond, lanes) = (isa.native_cond(), isa.lanes(scalar));
    quote! {
        #[cfg(#cond)]
        {
            if const { #b % #lanes == 0 } {
                // SAFETY: the crate is compiled with the copy's features.
                return unsafe { self.#copy::<#b>(#(#arg_names),*) };
            }
        }
    }
}

/// `R` of the return type `-> [R; B]`.
fn array_elem(ret: &TokenStream) -> Option<TokenStream> {
    match syn::parse2::<syn::ReturnType>(ret.clone()) {
        Ok(syn::ReturnType::Type(_, ty)) => match *ty {
            syn::Type::Array(a) => {
                let elem = a.elem;
                Some(quote!(#elem))
            }
            _ => None,
        },
        _ => None,
    }
}

/// The `unsafe fn name` that runs `z_body`, a body of the runtime's token methods
/// ([`super::zmm::token_body`]), with `isa`'s token made at its top: for one register of
/// states, `lanes` of them, so not generic. The batch function's `B` (`b`) is that number
/// in the signature and a `const` inside, so that every `Lanes` of the body is a whole
/// register, whose token methods are one instruction each (the runtime's `Register`).
#[allow(clippy::too_many_arguments)]
fn token_body_item(
    isa: Isa,
    name: &Ident,
    b: &Ident,
    lanes: &proc_macro2::Literal,
    args: &TokenStream,
    ret: &TokenStream,
    z_body: &TokenStream,
    doc: &str,
) -> TokenStream {
    let cfg = isa.cfg();
    let safety = format!(
        " The CPU has the features [`Self::has_{}`] checks.",
        isa.suffix()
    );
    let token = format_ident!("lanes_{}", isa.suffix());
    let wide = contains_ident(z_body, "WIDE").then(|| {
        quote!(
            const WIDE: bool = true;
        )
    });
    let (args, ret) = (with_literal(args, b, lanes), with_literal(ret, b, lanes));
    let z_body = &if isa == Isa::Avx2 {
        scatter_columns(z_body)
    } else {
        z_body.clone()
    };
    quote! {
        #[doc = #doc]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = ""]
        #[doc = #safety]
        #cfg
        #[inline(always)]
        #[allow(unsafe_code)]
        unsafe fn #name(#args) #ret {
            const #b: usize = #lanes;
            #wide
            // SAFETY: the function's contract: the copy's features.
            let z = unsafe { Self::#token() };
            #z_body
        }
    }
}

/// `body` with each `scatter(&[[…]])` of a single column (a vector result) calling the
/// runtime's `scatter_column` instead, which is inlined: the AVX2 bodies of instructions'
/// results are whole registers, which the optimiser then writes to each state's vector by
/// shuffles, where the out-of-line `scatter` has them stored, read back a lane at a time and
/// copied again (the UR5's inverse dynamics, `B` = 8, 264 → 254 instructions and about 30 →
/// 28.5 ns per state on a Zen 3; `dynamics_runtime::Lanes::scatter_column`). The AVX-512
/// bodies keep `scatter`: not measured (no AVX-512 machine at hand when this was written).
fn scatter_columns(body: &TokenStream) -> TokenStream {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    let single_column = |t: Option<&TokenTree>| {
        // `(&[[…]])`: a reference to an array of one array.
        let Some(TokenTree::Group(args)) = t else {
            return false;
        };
        let inner: Vec<TokenTree> = args.stream().into_iter().collect();
        match inner.as_slice() {
            [TokenTree::Punct(amp), TokenTree::Group(cols)]
                if amp.as_char() == '&' && cols.delimiter() == Delimiter::Bracket =>
            {
                let cols: Vec<TokenTree> = cols.stream().into_iter().collect();
                matches!(cols.as_slice(), [TokenTree::Group(c)] if c.delimiter() == Delimiter::Bracket)
            }
            _ => false,
        }
    };
    tokens
        .iter()
        .enumerate()
        .map(|(k, t)| match t {
            TokenTree::Ident(i) if i == "scatter" && single_column(tokens.get(k + 1)) => {
                TokenTree::Ident(Ident::new("scatter_column", i.span()))
            }
            TokenTree::Group(g) => {
                let mut out = Group::new(g.delimiter(), scatter_columns(&g.stream()));
                out.set_span(g.span());
                TokenTree::Group(out)
            }
            t => t.clone(),
        })
        .collect()
}

/// `stream` with every identifier `name` replaced by the literal `lit`.
fn with_literal(stream: &TokenStream, name: &Ident, lit: &proc_macro2::Literal) -> TokenStream {
    stream
        .clone()
        .into_iter()
        .map(|t| match t {
            TokenTree::Ident(i) if i == *name => TokenTree::Literal(lit.clone()),
            TokenTree::Group(g) => {
                let mut out = Group::new(g.delimiter(), with_literal(&g.stream(), name, lit));
                out.set_span(g.span());
                TokenTree::Group(out)
            }
            t => t,
        })
        .collect()
}

/// The attributes `attrs` with `#[inline(never)]` (a batch function's, see
/// [`super::batch`]) made `#[inline]`, and whether there was one: the dispatching wrapper is
/// small, and the body stays out of line in the copies and in `X_portable` ([`dispatched`]).
pub(super) fn without_inline_never(attrs: &[TokenTree]) -> (TokenStream, bool) {
    let never = quote!(inline(never)).to_string();
    let mut out = TokenStream::new();
    let mut found = false;
    let mut k = 0;
    while k < attrs.len() {
        let is_never = matches!(&attrs[k], TokenTree::Punct(p) if p.as_char() == '#')
            && matches!(attrs.get(k + 1), Some(TokenTree::Group(g))
                if g.delimiter() == Delimiter::Bracket && g.stream().to_string() == never);
        if is_never {
            out.extend(quote!(#[inline]));
            found = true;
            k += 2;
        } else {
            out.extend([attrs[k].clone()]);
            k += 1;
        }
    }
    (out, found)
}

/// The generic parameters at the start of `tokens` (`<const B: usize, …>`, without the
/// brackets), their names, and the index of the token after them: all empty and 0 without
/// any; `None` unless every parameter is a `const` one.
pub(super) fn const_generics(tokens: &[TokenTree]) -> Option<(TokenStream, Vec<Ident>, usize)> {
    let is_punct = |t: &TokenTree, c: char| matches!(t, TokenTree::Punct(p) if p.as_char() == c);
    if !tokens.first().is_some_and(|t| is_punct(t, '<')) {
        return Some((TokenStream::new(), Vec::new(), 0));
    }
    let close = tokens.iter().position(|t| is_punct(t, '>'))?;
    let inner = &tokens[1..close];
    let mut names = Vec::new();
    for param in inner.split(|t| is_punct(t, ',')).filter(|p| !p.is_empty()) {
        match param {
            [TokenTree::Ident(c), TokenTree::Ident(n), TokenTree::Punct(colon), ..]
                if c == "const" && colon.as_char() == ':' =>
            {
                names.push(n.clone());
            }
            _ => return None, // a type or lifetime parameter
        }
    }
    Some((inner.iter().cloned().collect(), names, close + 1))
}

/// The argument names after a `&self` receiver (`None` without one, or for a pattern
/// argument).
pub(super) fn receiver_and_names(args: TokenStream) -> Option<Vec<Ident>> {
    let mut parts = split_commas(args).into_iter();
    let receiver = parts.next()?;
    let is_self = matches!(receiver.as_slice(), [TokenTree::Punct(a), TokenTree::Ident(s)] if a.as_char() == '&' && s == "self");
    if !is_self {
        return None;
    }
    parts
        .map(|p| match (p.first(), p.get(1)) {
            (Some(TokenTree::Ident(i)), Some(TokenTree::Punct(c))) if c.as_char() == ':' => {
                Some(i.clone())
            }
            _ => None,
        })
        .collect()
}

/// The names of the arguments `args` after `&self` that are not mutable references
/// (`m: &mut T`).
fn by_value_names(args: &TokenStream) -> Vec<Ident> {
    split_commas(args.clone())
        .into_iter()
        .skip(1)
        .filter_map(|p| match p.as_slice() {
            [TokenTree::Ident(name), TokenTree::Punct(colon), ty @ ..]
                if colon.as_char() == ':' =>
            {
                let mut_ref = matches!(ty, [TokenTree::Punct(amp), TokenTree::Ident(m), ..]
                    if amp.as_char() == '&' && m == "mut");
                (!mut_ref).then(|| name.clone())
            }
            _ => None,
        })
        .collect()
}

/// The non-empty runs of `tokens` between commas outside angle brackets (`SVector<f64, 7>`
/// is one): a function's arguments, or an array's elements.
pub(crate) fn split_commas(tokens: TokenStream) -> Vec<Vec<TokenTree>> {
    let mut parts: Vec<Vec<TokenTree>> = vec![Vec::new()];
    let mut depth = 0i32;
    for t in tokens {
        match &t {
            TokenTree::Punct(p) if p.as_char() == '<' => depth += 1,
            TokenTree::Punct(p) if p.as_char() == '>' => depth -= 1,
            TokenTree::Punct(p) if p.as_char() == ',' && depth == 0 => {
                parts.push(Vec::new());
                continue;
            }
            _ => {}
        }
        if let Some(last) = parts.last_mut() {
            last.push(t);
        }
    }
    parts.retain(|p| !p.is_empty());
    parts
}

/// The smallest body (in tokens) worth a second copy unless it takes several sines and
/// cosines at once ([`several_angles`]): below it (a pendulum's functions, a few dozen
/// operations) the check of the CPU would cost a noticeable part of the call.
const MIN_TOKENS: usize = 400;

/// Whether `body` takes the sines and cosines of more angles at once than one SSE2 register
/// holds (`Self::joint_sin_cos::<K, …>` with `K` above 2 `f64`s or 4 `f32`s): then the
/// AVX-512 copy computes them in one 8-lane (16-lane) pass where the portable copy takes
/// several, which pays for the CPU check even in a short body (the UR5's `gravity`: three
/// angles and a dozen operations, 18 ns portable, 8 ns compiled for the CPU).
fn several_angles(body: &TokenStream, scalar: Scalar) -> bool {
    let narrow = match scalar {
        Scalar::F64 => 2,
        Scalar::F32 => 4,
    };
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    tokens.iter().enumerate().any(|(k, t)| match t {
        TokenTree::Ident(i) if i == "joint_sin_cos" => matches!(
            tokens.get(k + 4),
            Some(TokenTree::Literal(l)) if l.to_string().parse::<usize>().is_ok_and(|k| k > narrow)
        ),
        TokenTree::Group(g) => several_angles(&g.stream(), scalar),
        _ => false,
    })
}

/// The number of tokens of `stream`, groups' contents included.
fn size(stream: &TokenStream) -> usize {
    stream
        .clone()
        .into_iter()
        .map(|t| match t {
            TokenTree::Group(g) => 1 + size(&g.stream()),
            _ => 1,
        })
        .sum()
}

/// Whether `stream` has the identifier `name` anywhere, groups' contents included.
pub(crate) fn contains_ident(stream: &TokenStream, name: &str) -> bool {
    stream.clone().into_iter().any(|t| match t {
        TokenTree::Ident(i) => i == name,
        TokenTree::Group(g) => contains_ident(&g.stream(), name),
        _ => false,
    })
}

/// Whether a body calls the arithmetic helpers (so that it is worth a second copy).
fn calls_arithmetic(body: &TokenStream) -> bool {
    [
        "mul_add",
        "joint_sin_cos",
        "mul_add_lanes",
        "joint_sin_cos_rows",
    ]
    .iter()
    .chain(&super::function::VECTOR_HELPERS)
    .any(|f| contains_ident(body, f))
}

/// The `_with::<WIDE>` forms of the vector helpers ([`super::function::vector_helpers`]):
/// when `WIDE` (the AVX-512 and AVX2 copies, compiled with AVX2 and FMA), one AVX2
/// instruction on the four lanes (`vfmadd…pd`, `vmulpd`, `vaddpd`, `vsubpd`, `vxorpd` on a
/// 256-bit register; for `f32` the `…ps` forms on a 128-bit one), and the `v2_…` helpers'
/// on the first two lanes of an `f64` pack (a 128-bit register; the other two lanes 0); the
/// same operations on the same values as the lanes' scalar forms, so the same bits.
fn vector_helpers(
    cfg: &TokenStream,
    used: &std::collections::BTreeSet<String>,
    scalar: Scalar,
) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let reg = match scalar {
        Scalar::F64 => quote!(__m256d),
        Scalar::F32 => quote!(__m128),
    };
    let one = |name: &str, args: &[&str], op: TokenStream| {
        let with = format_ident!("{}_with", name);
        let plain = format_ident!("{}", name);
        let args: Vec<Ident> = args.iter().map(|a| format_ident!("{}", a)).collect();
        quote! {
            #[inline(always)]
            #[allow(unsafe_code)]
            fn #with<const WIDE: bool>(#(#args: [#t; 4]),*) -> [#t; 4] {
                #cfg
                {
                    if WIDE {
                        use ::core::arch::x86_64::*;
                        use ::core::mem::transmute;
                        // SAFETY: `WIDE` is true only in the `*_avx512` and `*_avx2` copies,
                        // which run only where `has_avx512` or `has_avx2` found AVX2 and FMA,
                        // and in code compiled with both; `[T; 4]` and the register type are
                        // the same 32 (`f64`) or 16 (`f32`) bytes, as `[f64; 2]` and `__m128d`.
                        return unsafe { #op };
                    }
                }
                Self::#plain(#(#args),*)
            }
        }
    };
    let v = |a: &str| {
        let a = format_ident!("{}", a);
        quote!(transmute::<[#t; 4], #reg>(#a))
    };
    let (a, b, c) = (v("a"), v("b"), v("c"));
    let [fma, mul, add, sub, xor, set1] = match scalar {
        Scalar::F64 => [
            "_mm256_fmadd_pd",
            "_mm256_mul_pd",
            "_mm256_add_pd",
            "_mm256_sub_pd",
            "_mm256_xor_pd",
            "_mm256_set1_pd",
        ],
        Scalar::F32 => [
            "_mm_fmadd_ps",
            "_mm_mul_ps",
            "_mm_add_ps",
            "_mm_sub_ps",
            "_mm_xor_ps",
            "_mm_set1_ps",
        ],
    }
    .map(|f| format_ident!("{}", f));
    let four = |name: &'static str, args: &[&str], op: TokenStream| {
        (
            name,
            one(name, args, quote!(transmute::<#reg, [#t; 4]>(#op))),
        )
    };
    let mut helpers = vec![
        four("v4_fma", &["a", "b", "c"], quote!(#fma(#a, #b, #c))),
        four("v4_mul", &["a", "b"], quote!(#mul(#a, #b))),
        four("v4_add", &["a", "b"], quote!(#add(#a, #b))),
        four("v4_sub", &["a", "b"], quote!(#sub(#a, #b))),
        four("v4_neg", &["a"], quote!(#xor(#a, #set1(-0.0)))),
    ];
    // Packs of two lanes, which the emitter writes for `f64` only (`f32`'s four lanes are one
    // 128-bit register already): the 128-bit operation on the first two lanes, the other two 0.
    if scalar == Scalar::F64 {
        let two = |name: &'static str, op: &str, args: &[&str]| {
            let op = format_ident!("{}", op);
            let mut operands: Vec<TokenStream> = args
                .iter()
                .map(|a| {
                    let a = format_ident!("{}", a);
                    quote!(transmute::<[f64; 2], __m128d>([#a[0], #a[1]]))
                })
                .collect();
            if name == "v2_neg" {
                operands.push(quote!(_mm_set1_pd(-0.0)));
            }
            let op = quote! {
                let [r0, r1] = transmute::<__m128d, [f64; 2]>(#op(#(#operands),*));
                [r0, r1, 0.0, 0.0]
            };
            (name, one(name, args, op))
        };
        helpers.extend([
            two("v2_fma", "_mm_fmadd_pd", &["a", "b", "c"]),
            two("v2_mul", "_mm_mul_pd", &["a", "b"]),
            two("v2_add", "_mm_add_pd", &["a", "b"]),
            two("v2_neg", "_mm_xor_pd", &["a"]),
        ]);
    }
    let used = helpers
        .into_iter()
        .filter(|(name, _)| used.contains(*name))
        .map(|(_, helper)| helper);
    quote!(#(#used)*)
}

/// `body` with every `Self::mul_add(` turned into `Self::mul_add_with::<WIDE>(` (and
/// `Self::mul_add_lanes(` into `Self::mul_add_lanes_with::<_, WIDE>(`, `Self::joint_sin_cos_rows(`
/// into `Self::sin_cos_rows_with::<_, _, WIDE>(`), and every
/// `Self::joint_sin_cos::<K, P>([angles])` into
/// `Self::sin_cos_with::<K, { Self::wide_lanes(K) }, WIDE, _, _>(&q.data.0[0], |joints| [angles])`,
/// the angles' inputs `q7`, … read as `joints[7]`, …: the wide lanes when `WIDE` (the
/// polynomials fused), [`sin_cos_lanes`](super::trig) otherwise. (The angles were computed
/// inside an out-of-line kernel compiled for AVX2, so that the AVX-512 copies had no 512-bit
/// additions, until the single-state functions stopped running those copies on Intel's cores;
/// see `cpu_level`.) Angles that read anything else go through a copy,
/// `((), move |()| [angles])`.
fn wide_body(body: TokenStream, used: &mut Used, far: Option<&TokenStream>) -> TokenStream {
    let inputs = input_names(&body);
    let out = wide_tokens(body, used, &inputs, far);
    // Inputs now read by a kernel's `joints[i]` alone: `_` in the pattern (the only
    // place left that names them), or the compiler warns of an unused variable.
    let mut uses: BTreeMap<String, usize> = inputs.keys().map(|n| (n.clone(), 0)).collect();
    count_uses(&out, &mut uses);
    if uses.values().all(|&n| n > 1) {
        return out;
    }
    let unbound = super::function::map_idents(out, &|i| {
        (uses.get(&i.to_string()) == Some(&1)).then(|| Ident::new("_", i.span()))
    });
    without_empty_patterns(unbound)
}

/// Adds to `uses` the occurrences in `stream` (groups' contents included) of the
/// identifiers it has.
fn count_uses(stream: &TokenStream, uses: &mut BTreeMap<String, usize>) {
    for t in stream.clone() {
        match t {
            TokenTree::Ident(i) => {
                if let Some(n) = uses.get_mut(&i.to_string()) {
                    *n += 1;
                }
            }
            TokenTree::Group(g) => count_uses(&g.stream(), uses),
            _ => {}
        }
    }
}

/// The inputs a body takes apart (`let [[q0, q1, _, …]] = q.data.0;`, at its top level or
/// in a block, as `let tau = { … };` of an actuated robot): each name with its argument and
/// index.
fn input_names(body: &TokenStream) -> BTreeMap<String, (Ident, usize)> {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    let mut names = BTreeMap::new();
    for t in &tokens {
        if let TokenTree::Group(g) = t {
            if g.delimiter() == Delimiter::Brace {
                names.extend(input_names(&g.stream()));
            }
        }
    }
    for w in tokens.windows(9) {
        let Some((arg, elements)) = taken_apart(w) else {
            continue;
        };
        for (i, name) in elements.into_iter().enumerate() {
            if let Some(name) = name {
                names.insert(name, (arg.clone(), i));
            }
        }
    }
    names
}

/// The argument and the bound names (`None` for `_`) of the nine tokens
/// `let [[q0, _, …]] = q.data.0;`, if `w` is such a statement.
fn taken_apart(w: &[TokenTree]) -> Option<(Ident, Vec<Option<String>>)> {
    let [TokenTree::Ident(l), TokenTree::Group(outer), TokenTree::Punct(eq), TokenTree::Ident(arg), TokenTree::Punct(d1), TokenTree::Ident(data), TokenTree::Punct(d2), TokenTree::Literal(zero), TokenTree::Punct(semi)] =
        w
    else {
        return None;
    };
    if l != "let"
        || outer.delimiter() != Delimiter::Bracket
        || eq.as_char() != '='
        || d1.as_char() != '.'
        || data != "data"
        || d2.as_char() != '.'
        || zero.to_string() != "0"
        || semi.as_char() != ';'
    {
        return None;
    }
    let inner: Vec<TokenTree> = outer.stream().into_iter().collect();
    let [TokenTree::Group(inner)] = inner.as_slice() else {
        return None;
    };
    let elements = inner
        .stream()
        .into_iter()
        .filter(|t| !matches!(t, TokenTree::Punct(p) if p.as_char() == ','))
        .map(|t| match t {
            TokenTree::Ident(name) if name != "_" => Some(name.to_string()),
            _ => None,
        })
        .collect();
    Some((arg.clone(), elements))
}

/// `stream` without the statements that take an input apart and bind none of it
/// (`let [[_, _, _]] = q.data.0;`, left where the kernel reads every input the body used).
fn without_empty_patterns(stream: TokenStream) -> TokenStream {
    let tokens: Vec<TokenTree> = stream.into_iter().collect();
    let mut out = Vec::with_capacity(tokens.len());
    let mut k = 0;
    while k < tokens.len() {
        let empty = tokens
            .get(k..k + 9)
            .and_then(taken_apart)
            .is_some_and(|(_, names)| names.iter().all(Option::is_none));
        if empty {
            k += 9;
            continue;
        }
        out.push(match &tokens[k] {
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => {
                let mut new = Group::new(g.delimiter(), without_empty_patterns(g.stream()));
                new.set_span(g.span());
                TokenTree::Group(new)
            }
            other => other.clone(),
        });
        k += 1;
    }
    out.into_iter().collect()
}

/// `args` (the angles of a `joint_sin_cos` call) with every input of the argument they read
/// replaced by `joints[i]`, and that argument; `None` where they read anything but one
/// argument's inputs, constants and `Self::mul_add_with::<WIDE>`.
fn angles_of_input(
    args: &TokenStream,
    inputs: &BTreeMap<String, (Ident, usize)>,
    arg: &mut Option<Ident>,
) -> Option<TokenStream> {
    let mut out = TokenStream::new();
    for t in args.clone() {
        match t {
            TokenTree::Ident(i) => match inputs.get(&i.to_string()) {
                Some((from, k)) => {
                    if arg.get_or_insert_with(|| from.clone()) != from {
                        return None;
                    }
                    let k = Literal::usize_unsuffixed(*k);
                    out.extend(quote!(joints[#k]));
                }
                None if ["Self", "mul_add_with", "WIDE"].iter().any(|n| i == n) => {
                    out.extend([TokenTree::Ident(i)]);
                }
                None => return None,
            },
            TokenTree::Group(g) => {
                let mut new = Group::new(g.delimiter(), angles_of_input(&g.stream(), inputs, arg)?);
                new.set_span(g.span());
                out.extend([TokenTree::Group(new)]);
            }
            other => out.extend([other]),
        }
    }
    Some(out)
}

/// [`wide_body`] of `body`, a part of a body whose inputs are `inputs`.
fn wide_tokens(
    body: TokenStream,
    used: &mut Used,
    inputs: &BTreeMap<String, (Ident, usize)>,
    far: Option<&TokenStream>,
) -> TokenStream {
    let mut out: Vec<TokenTree> = Vec::new();
    let mut tokens = body.into_iter().peekable();
    while let Some(tt) = tokens.next() {
        match tt {
            TokenTree::Ident(i) if i == "mul_add" && after_self_path(&out) => {
                used.mul_add = true;
                let call = quote!(mul_add_with::<WIDE>);
                out.extend(call);
            }
            // The vector helpers of packed bodies: their AVX2 instructions when `WIDE`.
            TokenTree::Ident(i)
                if super::function::VECTOR_HELPERS.iter().any(|h| i == h)
                    && after_self_path(&out) =>
            {
                used.vector.insert(i.to_string());
                let with = format_ident!("{}_with", i);
                out.extend(quote!(#with::<WIDE>));
            }
            // The batch bodies' helpers (on `Lanes`), as the two above.
            TokenTree::Ident(i) if i == "mul_add_lanes" && after_self_path(&out) => {
                out.extend(quote!(mul_add_lanes_with::<_, WIDE>));
            }
            // A batch body's: where the caller takes the far angles (`far`), `match
            // Self::sin_cos_rows_near::<…>(x) { Some(v) => v, None => return far }`.
            TokenTree::Ident(i) if i == "joint_sin_cos_rows" && after_self_path(&out) => {
                match (far, tokens.peek()) {
                    (Some(far), Some(TokenTree::Group(g)))
                        if g.delimiter() == Delimiter::Parenthesis =>
                    {
                        let x = wide_tokens(g.stream(), used, inputs, None);
                        tokens.next();
                        used.far += 1;
                        used.rows_near = true;
                        out.truncate(out.len() - 3);
                        out.extend(quote! {
                            match Self::sin_cos_rows_near::<_, _, WIDE>(#x) {
                                ::core::option::Option::Some(v) => v,
                                ::core::option::Option::None => return #far,
                            }
                        });
                    }
                    _ => out.extend(quote!(sin_cos_rows_with::<_, _, WIDE>)),
                }
            }
            TokenTree::Ident(i) if i == "joint_sin_cos" && after_self_path(&out) => {
                // `::<K, P>(args)`: K a literal, P a literal or a `{ … }` block.
                let rest: Vec<TokenTree> = tokens.by_ref().take(7).collect();
                let k = match rest.as_slice() {
                    [TokenTree::Punct(c1), TokenTree::Punct(c2), TokenTree::Punct(lt), k @ TokenTree::Literal(_), TokenTree::Punct(comma), _p, TokenTree::Punct(gt)]
                        if c1.as_char() == ':'
                            && c2.as_char() == ':'
                            && lt.as_char() == '<'
                            && comma.as_char() == ','
                            && gt.as_char() == '>' =>
                    {
                        Some(k.clone())
                    }
                    _ => None,
                };
                // The angles themselves widened too: a mimic joint's `m·q + o` is a
                // `mul_add`, fused in the copies as it is in the batch bodies' angles (left
                // as written, the single call and its batch lane differed in the last bits).
                let args = match (k.is_some(), tokens.peek()) {
                    (true, Some(TokenTree::Group(g)))
                        if g.delimiter() == Delimiter::Parenthesis =>
                    {
                        Some(wide_tokens(g.stream(), used, inputs, far))
                    }
                    _ => None,
                };
                match (k, args) {
                    // One angle: nothing to widen (and its pattern has no `..`), but fused
                    // when `WIDE`, as the angles of every other batch are there (and those of
                    // the batch functions), so that an angle's sine is the same bits
                    // whichever call computes it.
                    (Some(k), Some(args)) if k.to_string() == "1" => {
                        tokens.next();
                        out.extend(quote!(sin_cos_n::<1, 1, WIDE>(#args, 1)));
                    }
                    // Several: computed in the kernel from the input itself where the
                    // angles read one argument's inputs only, from a copy of them otherwise.
                    (Some(k), Some(args)) => {
                        tokens.next();
                        used.sin_cos = true;
                        let mut arg = None;
                        let (kernel, far_flag) = if far.is_some() {
                            (quote!(sin_cos_near), quote!(FAR,))
                        } else {
                            (quote!(sin_cos_with), quote!())
                        };
                        let call = match angles_of_input(&args, inputs, &mut arg).zip(arg) {
                            Some((angles, arg)) => quote! {
                                #kernel::<#k, { Self::wide_lanes(#k) }, WIDE, #far_flag _, _>(
                                    &#arg.data.0[0],
                                    |joints| #angles,
                                )
                            },
                            None => quote! {
                                #kernel::<#k, { Self::wide_lanes(#k) }, WIDE, #far_flag _, _>(
                                    (),
                                    move |()| #args,
                                )
                            },
                        };
                        match far {
                            // `match Self::sin_cos_near::<…>(…) { Some(v) => v, None => return
                            // self.f_far(args) }`: the `Self ::` already written goes inside.
                            Some(far) => {
                                used.far += 1;
                                out.truncate(out.len() - 3);
                                out.extend(quote! {
                                    match Self::#call {
                                        ::core::option::Option::Some(v) => v,
                                        ::core::option::Option::None => return #far,
                                    }
                                });
                            }
                            None => out.extend(call),
                        }
                    }
                    _ => {
                        out.push(TokenTree::Ident(i));
                        out.extend(rest);
                    }
                }
            }
            TokenTree::Group(g) => {
                let mut new = Group::new(g.delimiter(), wide_tokens(g.stream(), used, inputs, far));
                new.set_span(g.span());
                out.push(TokenTree::Group(new));
            }
            other => out.push(other),
        }
    }
    out.into_iter().collect()
}

/// Whether `out` ends in `Self ::`.
fn after_self_path(out: &[TokenTree]) -> bool {
    matches!(
        out,
        [.., TokenTree::Ident(s), TokenTree::Punct(a), TokenTree::Punct(b)]
            if s == "Self" && a.as_char() == ':' && b.as_char() == ':'
    )
}

#[cfg(test)]
mod tests {
    /// `sin_cos`, every function with a `_from_sin_cos` variant and the variants: all
    /// dispatched or none, on a robot whose functions are (the UR5) and on a small one (the
    /// pendulum: two angles, so that `sin_cos` alone would not be).
    #[test]
    fn sin_cos_and_the_variants_are_dispatched_with_their_functions() {
        for robot in ["ur5", "pendulum"] {
            let code = crate::Builder::new(robot)
                .sin_cos_variants(true)
                .generate()
                .expect("generates");
            let mut group = vec!["sin_cos".to_string()];
            for (k, _) in code.match_indices("_from_sin_cos(") {
                let before = &code[..k];
                let start = before
                    .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .map_or(0, |s| s + 1);
                if before[..start].ends_with("fn ") {
                    group.push(before[start..].to_string());
                    group.push(format!("{}_from_sin_cos", &before[start..]));
                }
            }
            assert!(group.len() >= 11, "{robot}: {group:?}");
            let dispatched = code.contains("fn sin_cos_avx512(");
            assert!(dispatched || robot == "pendulum");
            for name in &group {
                assert_eq!(
                    code.contains(&format!("fn {name}_avx512(")),
                    dispatched,
                    "{robot}: {name}"
                );
            }
            println!(
                "{robot}: {} functions, dispatched: {dispatched}",
                group.len()
            );
        }
    }

    #[test]
    fn copies_that_spill_vectors_align_their_frames() {
        // The text of the copy `name` (from its `fn` to the next item), without whitespace.
        fn copy(code: &str, name: &str) -> String {
            let k = code
                .find(&format!("fn {name}("))
                .or_else(|| code.find(&format!("fn {name}<")))
                .unwrap_or_else(|| panic!("{name}"));
            let end = code[k..].find("\n    }\n").expect("its end");
            code[k..k + end].split_whitespace().collect()
        }
        let talos = crate::Builder::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/talos_upper_body.urdf"
        ))
        .generate()
        .expect("generates");
        let ur5 = crate::Builder::new("ur5").generate().expect("generates");
        let aligned = "Self::align_frame();";
        // TALOS' packed inverse dynamics (both arms in lanes) and every batch copy: aligned.
        for isa in ["avx512", "avx2"] {
            assert!(copy(&talos, &format!("inverse_dynamics_{isa}")).contains(aligned));
            assert!(copy(&ur5, &format!("inverse_dynamics_batch_{isa}")).contains(aligned));
            // A chain's single-state bodies have no packs: their copies are as they were.
            for f in ["inverse_dynamics", "jacobian_space", "gravity"] {
                assert!(!copy(&ur5, &format!("{f}_{isa}")).contains(aligned), "{f}");
            }
        }
        assert!(!copy(&talos, "inverse_dynamics_portable").contains(aligned));
        let helper = copy(&talos, "align_frame");
        assert!(helper.contains("#[repr(C,align(64))]"));
        assert!(helper.contains("::core::hint::black_box(&line);"));
        // The helper exists only where a copy calls it.
        let pendulum = crate::Builder::new("pendulum")
            .generate()
            .expect("generates");
        assert!(!pendulum.contains("fn align_frame("));
    }

    #[test]
    fn large_batch_bodies_get_avx512_and_avx2_bodies_of_instructions() {
        let solo = crate::Builder::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/solo12.urdf"
        ))
        .floating_base(true)
        .generate()
        .expect("generates");
        // Solo-12's inverse dynamics batch (1,310 operations): its AVX-512 and AVX2 copies run
        // a body of token methods each, made `unsafe` and given the token at its top.
        for isa in ["avx512", "avx2"] {
            let k = solo
                .find(&format!("unsafe fn inverse_dynamics_batch_body_{isa}("))
                .expect("the body of instructions");
            let body = &solo[k..k + solo[k..].find("\n    }\n").expect("its end")];
            // prettyplease breaks method chains over lines: compare without whitespace.
            let body: String = body.split_whitespace().collect();
            assert!(body.contains(&format!("letz=unsafe{{Self::lanes_{isa}()}};")));
            for method in ["z.mul_add(", "z.add(", "z.sub(", "z.mul(", "z.neg("] {
                assert!(body.contains(method), "{method}");
            }
            assert!(body.matches("lett").count() > 100);
            // (The far angles' loop counts states: `l += 1`, a `usize`.)
            let body = body.replacen("l+=1;", "", 1);
            assert!(
                !body.contains('+') && !body.contains('*'),
                "an operator left"
            );
            // Compiled for one register of states and called once per register.
            let flat: String = solo.split_whitespace().collect();
            let lanes = if isa == "avx512" { 8 } else { 4 };
            assert!(!flat.contains(&format!("batch_body_{isa}::<")));
            // The loop in `_fill`, writing each register's results into the copy's result,
            // which the copy hands it uninitialised and returns (no local copied out).
            assert!(flat.contains(&format!(
                "results.add(k).write(self.inverse_dynamics_batch_body_{isa}(q,qd,qdd))"
            )));
            assert!(flat.contains(&format!(
                "unsafe{{self.inverse_dynamics_batch_{isa}_fill::<B>(q,qd,qdd,&mutout)}};unsafe{{out.assume_init()}}"
            )));
            assert!(flat.contains(&format!(
                "#[inline(never)]#[allow(unsafe_code,improper_ctypes_definitions)]unsafeextern\"C\"fninverse_dynamics_batch_{isa}_fill<constB:usize>(&self,"
            )));
            // For one register: not generic, its `B` that register's lanes.
            assert!(flat.contains(&format!(
                "unsafefninverse_dynamics_batch_body_{isa}(&self,q:&[::nalgebra::SVector<f64,19>;{lanes}],"
            )));
            assert!(flat.contains(&format!("{{constB:usize={lanes};")));
            assert!(solo.contains(&format!("unsafe fn lanes_{isa}()")));
            // Its vector result back to one per state: in line in the AVX2 body, out of line
            // (`scatter`) in the AVX-512 one.
            let (inline, out_of_line) = (
                body.contains(">::scatter_column(&[["),
                body.contains(">::scatter(&[["),
            );
            assert_eq!((inline, out_of_line), (isa == "avx2", isa == "avx512"));
        }
        // Only for whole registers: for other `B` the copy runs the vectoriser's body, and the
        // body of instructions is not generated.
        assert!(solo.contains("if const { B % 8 == 0 } {"));
        assert!(solo.contains("if const { B % 4 == 0 } {"));
        // Its forward dynamics (2,966 operations) is too large for the vectoriser: lanes in
        // the AVX-512 and AVX2 copies alone, for `B` a multiple of 8 and 4, and otherwise its
        // single-state function once per state, with no portable copy of the lanes.
        let k = solo
            .find("pub fn forward_dynamics_batch<const B: usize>(")
            .expect("the batch function");
        let wrapper = &solo[k..k + solo[k..].find("\n    }\n").expect("its end")];
        assert!(wrapper.contains("if const { B % 8 == 0 } && Self::has_avx512() {"));
        assert!(wrapper
            .contains("return unsafe { self.forward_dynamics_batch_avx512::<B>(q, qd, tau) };"));
        assert!(wrapper.contains("if const { B % 4 == 0 } && Self::has_avx2() {"));
        assert!(wrapper
            .contains("return unsafe { self.forward_dynamics_batch_avx2::<B>(q, qd, tau) };"));
        assert!(wrapper.contains("*o = single(q, qd, tau);"));
        // Where the crate is compiled with AVX2 and FMA (no AVX2 check, no copy of the
        // portable code), the AVX2 copy of a body of instructions runs without a check; only
        // those copies exist there.
        let native = "#[cfg(all(target_feature = \"avx2\", target_feature = \"fma\"))]";
        let flat_wrapper: String = wrapper.split_whitespace().collect();
        assert!(flat_wrapper.contains(
            "#[cfg(all(target_feature=\"avx2\",target_feature=\"fma\"))]{ifconst{B%4==0}{returnunsafe{self.forward_dynamics_batch_avx2::<B>(q,qd,tau)};}}"
        ));
        let k = solo
            .find("pub fn inverse_dynamics_batch<const B: usize>(")
            .expect("the batch function");
        assert!(solo[k..k + solo[k..].find("\n    }\n").expect("its end")].contains(native));
        let k = solo
            .find("unsafe extern \"C\" fn inverse_dynamics_batch_avx2<")
            .expect("the AVX2 copy");
        let attrs = &solo[solo[..k].rfind("///").expect("its doc")..k];
        assert!(attrs
            .contains("#[cfg(all(target_arch = \"x86_64\", not(target_feature = \"avx512f\")))]"));
        // Where it is compiled with AVX-512 (no dispatch), the AVX-512 copy, unchecked.
        assert!(flat_wrapper.contains(
            "target_feature=\"avx512bw\",target_feature=\"fma\"))]{ifconst{B%8==0}{returnunsafe{self.forward_dynamics_batch_avx512::<B>(q,qd,tau)};}}"
        ));
        let k = solo
            .find("unsafe extern \"C\" fn inverse_dynamics_batch_avx512<")
            .expect("the AVX-512 copy");
        let attrs: String = solo[solo[..k].rfind("///").expect("its doc")..k]
            .split_whitespace()
            .collect();
        assert!(attrs.contains("#[cfg(any(all(target_arch=\"x86_64\",not(target_feature=\"avx512f\")),all(target_arch=\"x86_64\",target_feature=\"avx512f\","));
        let k = solo
            .find("pub fn gravity_batch<")
            .expect("a batch without such a body");
        assert!(!solo[k..k + solo[k..].find("\n    }\n").expect("its end")].contains(native));
        assert!(solo.contains("unsafe fn forward_dynamics_batch_body_avx512("));
        assert!(solo.contains("unsafe fn forward_dynamics_batch_body_avx2("));
        for absent in ["_batch_body<", "_batch_portable"].map(|s| format!("forward_dynamics{s}")) {
            assert!(!solo.contains(&absent), "{absent}");
        }
        assert!(solo.contains("on other CPUs and targets and for other `B` it calls `forward_dynamics` once per state"));
        // Without the dispatch, state by state on every CPU.
        let plain = crate::Builder::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/solo12.urdf"
        ))
        .floating_base(true)
        .cpu_dispatch(false)
        .generate()
        .expect("generates");
        assert!(!plain.contains("_avx512") && !plain.contains("_avx2"));
        assert!(plain.contains(
            "The code of `forward_dynamics` called once per state: its body (2970 operations)"
        ));
        // Its gravity batch is below both bounds: the vectoriser's code, and no token.
        assert!(!solo.contains("gravity_batch_body_avx"));
        // The UR5's inverse dynamics (272 operations, a vector) is above `VECTOR_MIN_OPS` and
        // below `MIN_OPS`: bodies of instructions in both copies. Its gravity (too small) and
        // mass matrix (a matrix) keep the vectoriser's code in both copies.
        let ur5 = crate::Builder::new("ur5").generate().expect("generates");
        assert!(ur5.contains("unsafe fn inverse_dynamics_batch_body_avx2("));
        assert!(ur5.contains("unsafe fn inverse_dynamics_batch_body_avx512("));
        assert!(ur5.contains("For a body of 272 operations with a vector result"));
        assert!(!ur5.contains("mass_matrix_batch_body_avx"));
        assert!(!ur5.contains("gravity_batch_body_avx"));
        // Their kernels leave the far angles to the single-state function.
        for isa in ["avx2", "avx512"] {
            let k = ur5
                .find(&format!("unsafe fn inverse_dynamics_batch_body_{isa}("))
                .expect("the body");
            let body: String = ur5[k..k + ur5[k..].find("\n    }\n").expect("its end")]
                .split_whitespace()
                .collect();
            assert!(body.contains("letfar_args=(q,qd,qdd);"), "{body}");
            assert!(body.contains("matchSelf::sin_cos_rows_near::<"), "{body}");
            // Where the AVX2 copies exist, the single-state function's; its portable body
            // elsewhere (not the wrapper, whose CPU detection may unwind).
            assert!(
                body.contains("letv=unsafe{self.inverse_dynamics_avx2(&q[l],&qd[l],&qdd[l])};"),
                "{body}"
            );
            assert!(body.contains("letv=self.inverse_dynamics_portable(&q[l],&qd[l],&qdd[l]);"));
        }
        // Not for `f32`, whose AVX2 register holds 8 lanes.
        let f32 = crate::Builder::new("ur5")
            .scalar(crate::options::Scalar::F32)
            .generate()
            .expect("generates");
        assert!(!f32.contains("_batch_body_avx"));
    }

    #[test]
    fn only_single_columns_are_scattered_in_line() {
        let body = quote::quote! {
            let v = L::scatter(&[[a, z.add(b, c)]]);
            let m = L::scatter(&[[a, b], [c, d]]);
            { L::scatter(&[[e]]) }
        };
        let out = super::scatter_columns(&body).to_string();
        assert_eq!(out.matches("scatter_column").count(), 2, "{out}");
        assert!(
            out.contains("L :: scatter (& [[a , b] , [c , d]])"),
            "{out}"
        );
    }

    /// The angles are computed in the kernel from the input (mimic joints and offsets
    /// included), and the pattern no longer binds the inputs only they read.
    #[test]
    fn the_kernel_computes_the_angles_from_the_input() {
        let talos = crate::Builder::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/talos_upper_body_mimic.urdf"
        ))
        .generate()
        .expect("generates");
        let flat: String = talos.split_whitespace().collect();
        let body = &flat[flat.find("fninverse_dynamics_body<").expect("a body")..];
        let body = &body[..body.find("fnforward_dynamics").unwrap_or(body.len())];
        let call = &body[body.find("Self::sin_cos_near::<").expect("the kernel")..];
        let call = &call[..call.find(';').expect("the statement's end")];
        // An angle beyond the kernel's bound: the same fused body with its fallback, out of
        // line (`FAR`), compiled for AVX2 and FMA.
        assert!(
            call.contains("::core::option::Option::None=>{return{let(q,qd,qdd)=far_args"),
            "{call}"
        );
        // The arguments as passed (the body may shadow them), kept aside at its top.
        assert!(body.contains("{letfar_args=(q,qd,qdd);"), "{body}");
        assert!(body.contains("unsafe{self.inverse_dynamics_far(q,qd,qdd)}"));
        assert!(call.contains(",WIDE,FAR,_,_,>"), "{call}");
        assert!(flat.contains(
            "#[target_feature(enable=\"avx2,fma\")]#[cold]#[allow(unsafe_code,improper_ctypes_definitions)]unsafeextern\"C\"fninverse_dynamics_far("
        ));
        assert!(flat.contains("self.inverse_dynamics_body::<true,true>(q,qd,qdd)"));
        // Where no `WIDE` body runs nothing calls it: inlined (nowhere), so never compiled.
        let wide = "any(all(target_arch=\"x86_64\",not(target_feature=\"avx512f\")),all(target_arch=\"x86_64\",target_feature=\"avx2\",target_feature=\"fma\"))";
        assert!(flat.contains(&format!(
            "#[cfg(not({wide}))]#[inline(always)]#[allow(unsafe_code,improper_ctypes_definitions)]unsafeextern\"C\"fninverse_dynamics_far("
        )));
        assert!(flat.contains(&format!(
            "#[cfg({wide})]#[target_feature(enable=\"avx2,fma\")]#[cold]"
        )));
        // Compiled with AVX2 and FMA, the portable body is the copies' (`WIDE`), its far
        // angles left to the same `inverse_dynamics_far`; on the default target, not.
        assert!(
            flat.contains("{self.inverse_dynamics_body::<false,false>(q,qd,qdd)}"),
            "the default target's portable body"
        );
        assert!(flat.contains(
            "self.inverse_dynamics_body::<{cfg!(all(target_arch=\"x86_64\",target_feature=\"avx2\",target_feature=\"fma\"))},false,>(q,qd,qdd)"
        ), "the portable body compiled with AVX2 and FMA");
        let call = &call[..call.find("{::core::option").expect("the match")];
        assert!(
            call.contains(">(&q.data.0[0],|joints|[joints[1],"),
            "{call}"
        );
        // Each mimic finger reads its driver's input (a finger that turns with it, at no
        // offset, shares its angle).
        assert!(call.contains("joints[9],"), "{call}");
        assert!(!call.contains(",q") && !call.contains("[q"), "{call}");
        assert!(!flat.contains("|()|"), "no angle goes through a copy");
        // The pattern: no input bound that nothing reads (the compiler would warn).
        let words: Vec<&str> = body
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .collect();
        for (at, _) in body.match_indices("let[[") {
            let pattern = &body[at + 5..];
            let pattern = &pattern[..pattern.find("]]").expect("its end")];
            for name in pattern.split(',').filter(|n| *n != "_") {
                let reads = words.iter().filter(|w| *w == &name).count();
                assert!(reads > 1, "{name} unread: {pattern}");
            }
        }
        // A joint's home offset is added to its input in the kernel's argument.
        let rand7 = crate::Builder::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/rand7.urdf"
        ))
        .generate()
        .expect("generates");
        let flat: String = rand7.split_whitespace().collect();
        assert!(flat.contains("joints[1]+-2.189006490495273,"), "an offset");
        // Where the kernel reads every input the body used, no pattern is left.
        let ur5 = crate::Builder::new("ur5").generate().expect("generates");
        let flat: String = ur5.split_whitespace().collect();
        let body = &flat[flat.find("fnjacobian_space_body<").expect("a body")..];
        let body = &body[..body.find("fnjacobian_body").unwrap_or(body.len())];
        assert!(body.contains("(&q.data.0[0],|joints|"), "{body}");
        assert!(!body.contains("=q.data.0;"), "{body}");
    }

    /// The batch kernel for the copies is kept where a dispatched batch body calls it, and
    /// left out where none does (the pendulum's batch bodies are too small to dispatch).
    #[test]
    fn the_batch_kernel_for_the_copies_only_where_called() {
        for (robot, kept) in [("ur5", true), ("pendulum", false)] {
            let code = crate::Builder::new(robot).generate().expect("generates");
            let flat: String = code.split_whitespace().collect();
            assert_eq!(flat.contains("fnsin_cos_rows_near<"), kept, "{robot}");
            assert_eq!(flat.contains("Self::sin_cos_rows_near::<"), kept, "{robot}");
            assert!(flat.contains("fninverse_dynamics_batch<"), "{robot}");
        }
    }

    /// Angles that read anything but one argument's inputs go through a copy, and the
    /// inputs they read stay bound.
    #[test]
    fn other_angles_go_through_a_copy() {
        let body = quote::quote! {
            let [[q0, q1]] = q.data.0;
            let t0 = q0 * 2.0;
            let ([s0, s1, ..], [c0, c1, ..]) =
                Self::joint_sin_cos::<2, { Self::sin_cos_lanes(2) }>([t0, q1 + 0.5]);
        };
        let out: String = super::wide_body(body, &mut super::Used::default(), None)
            .to_string()
            .split_whitespace()
            .collect();
        assert!(out.contains("let[[q0,q1]]=q.data.0;"), "{out}");
        assert!(out.contains("WIDE,_,_>((),move|()|[t0,q1+0.5],)"), "{out}");
    }

    #[test]
    fn std_code_has_an_avx512_copy_and_no_std_code_none() {
        let std = crate::Builder::new("ur5").generate().expect("generates");
        assert!(std.contains("fn inverse_dynamics_avx512("));
        assert!(std.contains("fn has_avx512() -> bool"));
        // The AVX2 copy runs the same fused body, behind its own check.
        assert!(std.contains("fn inverse_dynamics_avx2("));
        assert!(std.contains("fn has_avx2() -> bool"));
        assert!(std.contains("#[target_feature(enable = \"avx2,fma\")]"));
        assert!(std.contains("return unsafe { self.inverse_dynamics_avx2(q, qd, qdd) };"));
        assert_eq!(
            std.matches("self.inverse_dynamics_body::<true, false>(")
                .count(),
            2,
            "the AVX-512 and the AVX2 copy"
        );
        assert_eq!(
            std.matches("self.inverse_dynamics_body::<true, true>(")
                .count(),
            1,
            "the far angles' copy"
        );
        assert!(std.contains("Self::mul_add_with::<WIDE>"));
        // A single-state function runs its AVX-512 copy on AMD's AVX-512 cores alone, a
        // batch function on any AVX-512 core; AMD's found by the vendor of CPUID leaf 0.
        let wrapper = |name: &str| {
            let w = &std[std.find(&format!("pub fn {name}")).expect("a wrapper")..];
            w[..w.find("\n    }\n").expect("its end")].to_string()
        };
        assert!(wrapper("inverse_dynamics(").contains("if Self::has_fast_avx512() {"));
        assert!(wrapper("inverse_dynamics_batch<").contains("if Self::has_avx512() {"));
        assert!(std.contains("Self::cpu_level() == 3"));
        assert!(std.contains("(0x6874_7541, 0x6974_6e65, 0x444d_4163)"));
        // Every `mul_add` of a dispatched body goes through `mul_add_with`.
        let body = &std[std.find("fn inverse_dynamics_body").expect("a body")..];
        let body = &body[..body.find("\n    }\n").expect("its end")];
        assert!(!body.contains("Self::mul_add("));
        assert!(body.contains("Self::sin_cos_near::<"));
        // The batch functions pass their `B` on, and their `Lanes` helpers get `WIDE`.
        assert!(std.contains("pub fn inverse_dynamics_batch<const B: usize>("));
        assert!(std.contains("fn inverse_dynamics_batch_avx512<const B: usize>("));
        assert!(std.contains("fn inverse_dynamics_batch_body<const WIDE: bool, const B: usize>("));
        assert!(std.contains("self.inverse_dynamics_batch_avx512::<B>("));
        assert!(std.contains("fn inverse_dynamics_batch_avx2<const B: usize>("));
        assert!(std.contains("self.inverse_dynamics_batch_avx2::<B>("));
        assert!(std.contains("self.inverse_dynamics_batch_body::<false, B>("));
        let batch = &std[std
            .find("fn inverse_dynamics_batch_body<")
            .expect("a batch body")..];
        let batch: String = batch[..batch.find("\n    }\n").expect("its end")]
            .split_whitespace()
            .collect();
        assert!(batch.contains("Self::mul_add_lanes_with::<_,WIDE,>("));
        assert!(batch.contains("matchSelf::sin_cos_rows_near::<_,_,WIDE,>("));
        assert!(
            batch.contains("None=>{return{let(q,qd,qdd)=far_args;"),
            "{batch}"
        );
        assert!(!batch.contains("Self::mul_add_lanes("));
        // Its wrapper is inlined; where no copy runs it calls `_portable`, an out-of-line
        // `extern "C"` function everywhere. A single-state function stays `#[inline]`; its
        // `_portable` is out of line where the dispatch exists and the target has no AVX2
        // (the default x86-64 target), and inlined elsewhere.
        let before = &std[..std
            .find("pub fn inverse_dynamics_batch<")
            .expect("a batch wrapper")];
        let attrs = &before[before.rfind("///").expect("its doc")..];
        assert!(
            attrs.contains("#[inline]\n") && !attrs.contains("never"),
            "{attrs}"
        );
        assert!(std.contains("self.inverse_dynamics_batch_portable::<B>(q, qd, qdd)"));
        assert_eq!(
            std.matches("fn inverse_dynamics_batch_portable<").count(),
            1
        );
        // The attributes before the item at `k`, without whitespace.
        let attrs_before = |k: usize| -> String { std[k - 300..k].split_whitespace().collect() };
        let out_of_line = r#"#[inline(never)]#[allow(improper_ctypes_definitions)]"#;
        let k = std
            .find("extern \"C\" fn inverse_dynamics_batch_portable<")
            .expect("the out-of-line fallback");
        let attrs = attrs_before(k);
        assert!(
            attrs.ends_with(&format!(
                "wherenocopyruns:thebodycompiledforthetarget.{out_of_line}"
            )),
            "{attrs}"
        );
        let before = &std[..std.find("pub fn inverse_dynamics(").expect("a function")];
        let attrs = &before[before.rfind("///").expect("its doc")..];
        assert!(
            attrs.contains("#[inline]\n") && !attrs.contains("never"),
            "{attrs}"
        );
        assert_eq!(std.matches("fn inverse_dynamics_portable(").count(), 2);
        let avx2_copy = r#"all(target_arch="x86_64",not(target_feature="avx512f"),not(all(target_feature="avx2",target_feature="fma")))"#;
        let k = std
            .find("extern \"C\" fn inverse_dynamics_portable(")
            .expect("the out-of-line fallback");
        let attrs = attrs_before(k);
        assert!(
            attrs.ends_with(&format!("#[cfg({avx2_copy})]{out_of_line}")),
            "{attrs}"
        );
        let k = std
            .rfind("fn inverse_dynamics_portable(")
            .expect("the inlined fallback");
        let attrs = attrs_before(k);
        assert!(
            attrs.ends_with(&format!("#[cfg(not({avx2_copy}))]#[inline(always)]")),
            "{attrs}"
        );
        // A short body with several angles is dispatched (the UR5's gravity).
        assert!(std.contains("fn gravity_avx512("));
        // So is a private helper, and its wrapper stays private: `mass_matrix_factor`, which
        // `constrained_forward_dynamics` calls. The generic private helpers are left alone.
        assert!(std.contains("\n    fn mass_matrix_factor(\n"));
        assert!(std.contains("fn mass_matrix_factor_avx512("));
        assert!(std.contains("fn mass_matrix_factor_avx2("));
        assert!(!std.contains("pub fn mass_matrix_factor"));
        assert!(!std.contains("joint_sin_cos_avx512"));
        assert!(!std.contains("fn isometry_avx512"));
        // A generic function that is not a batch function is dispatched on its own:
        // `constrained_forward_dynamics`, whose substitutions for `Y = M⁻¹ Aᵀ` are then
        // fused, in its copies, instead of compiled where the caller is (SSE2 by default).
        assert!(std.contains("fn constrained_forward_dynamics_avx2<const K: usize>("));
        assert!(
            std.contains("fn constrained_forward_dynamics_body<const WIDE: bool, const K: usize>(")
        );
        let body = &std[std
            .find("fn constrained_forward_dynamics_body<")
            .expect("its body")..];
        let body = &body[..body.find("\n    }\n").expect("its end")];
        assert!(body.contains("Self::mul_add_with::<WIDE>"));
        // Its copies run the factor's body, not its wrapper (whose CPU check an `extern "C"`
        // copy must not reach), and its portable copy the factor's portable copy.
        assert!(body.contains("self.mass_matrix_factor_body::<true, false>(q, qd, tau)"));
        assert!(body.contains("self.mass_matrix_factor_portable(q, qd, tau)"));
        assert!(!body.contains("self.mass_matrix_factor("));
        // A batch function follows its single-state function: the pendulum's bodies are too
        // small to dispatch, and so are its batch functions, whatever their size.
        let pendulum = crate::Builder::new("pendulum")
            .generate()
            .expect("generates");
        assert!(!pendulum.contains("fn inverse_dynamics_avx512("));
        assert!(!pendulum.contains("fn inverse_dynamics_batch_avx512"));
        for builder in [
            crate::Builder::new("ur5").no_std(true),
            crate::Builder::new("ur5").cpu_dispatch(false),
        ] {
            let code = builder.generate().expect("generates");
            assert!(!code.contains("has_avx512"), "{}", builder.options().no_std);
            assert!(!code.contains("target_feature(enable"));
            assert!(!code.contains("unsafe"));
            // Not dispatched: the batch function's body stays out of line, in an `extern "C"`
            // part (see `batch::out_of_line`).
            let before = &code[..code
                .find("extern \"C\" fn inverse_dynamics_batch_out_of_line<")
                .expect("a batch function's body")];
            let attrs = &before[before.rfind("///").expect("its doc")..];
            assert!(attrs.contains("#[inline(never)]") && !attrs.contains("cfg_attr"));
            assert!(code.contains("self.inverse_dynamics_batch_out_of_line::<B>(q, qd, qdd)"));
        }
    }

    /// A dispatched body's calls of other dispatched single-state functions: their bodies in
    /// the copies, their portable copies otherwise; `, false` for a body with `FAR`; calls in
    /// the arguments too; other calls left alone.
    #[test]
    fn calls_of_dispatched_functions_become_calls_of_their_bodies() {
        use super::{calls_any, with_bodies_called};
        use quote::quote;
        use std::collections::BTreeMap;
        let bodies: BTreeMap<String, bool> =
            [("g".to_string(), true), ("h".to_string(), false)].into();
        let body = quote!(let x = self.g(a, self.h(b)); let y = (self.k(x), self.h(c)); y);
        let out = with_bodies_called(body.clone(), &bodies, &Default::default()).to_string();
        assert!(
            out.contains("self . g_body :: < true , false > (a , {"),
            "{out}"
        );
        assert!(out.contains("self . h_body :: < true > (b)"), "{out}");
        assert!(out.contains("self . g_portable (a , {"), "{out}");
        assert!(out.contains("self . h_portable (c)"), "{out}");
        assert!(out.contains("self . k (x)"), "{out}");
        assert!(
            !out.contains("self . g (") && !out.contains("self . h ("),
            "{out}"
        );
        // A function whose copies return the struct's union: its value is read.
        let written = ["h".to_string()].into();
        let out = with_bodies_called(body.clone(), &bodies, &written).to_string();
        assert!(
            out.contains("unsafe { self . h_body :: < true > (b) . value }"),
            "{out}"
        );
        assert!(
            out.contains("unsafe { self . h_portable (c) . value }"),
            "{out}"
        );
        assert!(out.contains("self . g_portable (a , {"), "{out}");
        assert!(calls_any(&body, &["h".to_string()], "g"));
        assert!(!calls_any(&body, &["h".to_string()], "h"));
        assert!(!calls_any(&body, &["m".to_string()], "g"));
    }
}
