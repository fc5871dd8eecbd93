//! The batch functions: `inverse_dynamics_batch`, `forward_dynamics_batch`, `mass_matrix_batch`
//! and `gravity_batch`, each the single-state function's unrolled code evaluated on `B`
//! states at once, in structure-of-arrays form.
//!
//! Every value of the body is a `Lanes<scalar, B>` of the runtime crate: `B` values side by
//! side, one per state, each operation applied lane by lane on a fixed-size array, which
//! the compiler turns into vector instructions (4 `f64` lanes per AVX2 register, 2 per SSE2
//! register). The expression graph and its order of operations are those of the single-state
//! function, and so are its fused multiply-adds (`mul_add_lanes`, fused where the
//! single-state `mul_add` is), so that a lane is the single-state result bit for bit. The
//! joints' sines and cosines come from the single-state kernel's loop (`sin_cos_into`) run
//! once over all `K·B` angles (`joint_sin_cos_rows`), inlined into the body.
//!
//! Under run-time CPU dispatch ([`super::dispatch`]) a batch function gets its AVX-512 and AVX2
//! copies as the single-state ones do: there the lanes' multiply-adds are fused and the
//! kernel's polynomials too, as in the single-state copies.
//!
//! Where the lanes do not pay, the batch function calls the single-state function once per
//! state instead: for a result of more than [`MAX_LANES_OUTPUTS`] entries (a tree's mass
//! matrix), whose transpose out of the lanes costs more than the lanes gain, and for a body of
//! more than [`MAX_LANES_OPS`] operations (a tree's forward dynamics, a humanoid's inverse
//! dynamics), which the optimiser's vectoriser leaves largely scalar. Under the CPU dispatch
//! such a body still runs on lanes in the AVX-512 and AVX2 copies, whose arithmetic is vector
//! instructions written out ([`super::zmm`]), for `B` a multiple of a register's lanes; only
//! elsewhere does it go state by state.
//!
//! A vectorised body the dispatch does not copy (a small function, `no_std`, no dispatch) is
//! kept out of line, and there [`out_of_line`] moves it into a private `extern "C"` function
//! that the public one calls: see there why.

use super::function::{Arg, FunctionBody, Output, ALIKE_PACKS, MAX_UNSPLIT_LETS};
use crate::expr::{ExprGraph, ExprId};
use crate::options::Options;
use proc_macro2::{Ident, Span, TokenStream, TokenTree};
use quote::{format_ident, quote};

/// The most entries of a vectorised batch function's result: up to 8 × 8 the runtime's
/// `Lanes::scatter` is straight-line copies. Measured (`*_batch::<8>` against 8 single calls
/// per state, default profile, AVX-512 copies; the transpose alone in ns per state):
/// mass matrices of 6 × 6 and 7 × 7, 1.6–2.8× faster (transpose 5.0 and 6.7 ns); 12 × 12
/// (Solo-12), 20 × 20 (Talos' upper body) and 29 × 29 (G1, fixed base), 0.54×, 0.74× and 0.50×
/// (transpose 40, 90 and 206 ns).
pub const MAX_LANES_OUTPUTS: usize = 64;

/// The most operations of a vectorised batch body. Measured as above, inverse dynamics:
/// Talos' upper body (2,451 operations) 1.47× with `B` = 8 and 1.19× with 4, G1 (3,409)
/// 1.02× and 0.82×. Solo-12's forward dynamics on its floating base (2,966 operations) was
/// 0.64–0.71× with `B` = 8 (1.45–1.52× with 4, 1.38–1.76× with 2; a scratch harness, medians
/// of 11 interleaved rounds, 2026-11-27): its AVX-512 copy held 20,827 instructions against
/// 7,156 for `B` = 4, most of them scalar (`vmulsd`, `vfmadd231sd`), as the optimiser's
/// vectoriser, which has to rebuild each operation's `B` lanes from the unrolled lane loops,
/// left most of the 8-wide body unvectorised. The bound is an operation count, a crude proxy
/// for that: it sits between the two measured bodies. It binds the vectoriser's copies only:
/// the AVX-512 and AVX2 copies of a larger body run its lanes as vector instructions ([`super::zmm`]),
/// at 2.0–2.8× of single calls for these bodies.
pub const MAX_LANES_OPS: usize = 2500;

/// One batch function: its name, the single-state function it batches, its arguments, its
/// outputs on `graph` and their columns (1: a vector).
pub struct Batched<'a> {
    /// `inverse_dynamics_batch`, …
    pub name: &'static str,
    /// `inverse_dynamics`, …
    pub single: &'static str,
    /// The arguments, as in the single-state function.
    pub args: &'a [Arg],
    /// The outputs (row-major).
    pub outputs: &'a [ExprId],
    /// Columns of the result.
    pub cols: usize,
    /// The doc comment's first lines.
    pub doc: &'static str,
}

/// How a vectorised batch body gets the joints' friction, as the single-state function does
/// ([`super::friction`]), by the name of the single-state function.
pub type Wrap<'a> = &'a dyn Fn(&str, TokenStream) -> TokenStream;

/// The batch functions of `fns`, over `graph`: vectorised in the runtime crate's `Lanes`
/// (`runtime`), or, without the runtime crate or for a body too large to unroll `B` wide,
/// the single-state function called once per state (a selected batch function brings its
/// single-state function into the selection).
pub fn batch_functions(
    graph: &ExprGraph,
    fns: &[Batched<'_>],
    rows: usize,
    options: &Options,
    nalgebra: &TokenStream,
    runtime: Option<&TokenStream>,
    emitted: impl Fn(&str) -> bool,
    wrap: Wrap<'_>,
) -> TokenStream {
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    // As in `body_tokens`: the struct, which a split body's parts call helpers through.
    let self_ty = options
        .name
        .as_deref()
        .and_then(|n| syn::parse_str::<Ident>(n).ok());
    let mut out = TokenStream::new();
    // Which `Lanes` helpers the vectorised bodies call (`any_token`: the runtime's tokens).
    let (mut fuses, mut trig, mut any_token) = (false, false, false);
    for f in fns {
        if !emitted(f.name) {
            continue;
        }
        let name = Ident::new(f.name, Span::call_site());
        let vec_of = |len: usize| {
            let len = proc_macro2::Literal::usize_unsuffixed(len);
            quote!(#nalgebra::SVector<#scalar, #len>)
        };
        let names: Vec<Ident> = f
            .args
            .iter()
            .map(|a| Ident::new(a.name, Span::call_site()))
            .collect();
        let params = f.args.iter().zip(&names).map(|(a, n)| {
            let ty = vec_of(a.len);
            quote!(#n: &[#ty; B])
        });
        let rows_lit = proc_macro2::Literal::usize_unsuffixed(rows);
        let cols_lit = proc_macro2::Literal::usize_unsuffixed(f.cols);
        let (result, result_path) = if f.cols == 1 {
            (
                vec_of(rows),
                quote!(#nalgebra::SVector::<#scalar, #rows_lit>),
            )
        } else {
            (
                quote!(#nalgebra::SMatrix<#scalar, #rows_lit, #cols_lit>),
                quote!(#nalgebra::SMatrix::<#scalar, #rows_lit, #cols_lit>),
            )
        };
        let body = |lanes: Option<&TokenStream>| {
            FunctionBody {
                graph,
                args: f.args,
                outputs: f.outputs,
                rows,
                cols: f.cols,
                output: Output::Matrix,
                scalar: options.scalar,
                no_std: options.no_std,
                nalgebra,
                self_ty: self_ty.as_ref(),
                lanes,
                ready: &[],
                pack: ALIKE_PACKS,
                park: false,
                order: super::schedule::Order::Demand,
                written: None,
                plan: None,
                reads_jacobian: &[],
            }
            .tokens()
        };
        let ops = graph.op_counts(f.outputs).total();
        let too_many_outputs = rows * f.cols > MAX_LANES_OUTPUTS;
        let dispatched = !options.no_std && options.cpu_dispatch;
        // Too large for the optimiser's vectoriser, not for the AVX-512 instructions
        // (`zmm`): lanes in the AVX-512 and AVX2 copies alone, state by state elsewhere. The dispatch
        // makes it so only where the single-state function has its copies (its body is not
        // split), and goes state by state otherwise.
        let too_large = ops > MAX_LANES_OPS
            || graph.live(f.outputs).iter().filter(|&&l| l).count() > MAX_UNSPLIT_LETS;
        let zmm_only = too_large && dispatched;
        let large = too_many_outputs || (too_large && !zmm_only);
        let (body, how, inline) = match runtime {
            Some(runtime) if !large => {
                let body = body(Some(runtime));
                let text = body.to_string();
                fuses |= text.contains("mul_add_lanes");
                trig |= text.contains("joint_sin_cos_rows");
                let (avx2, avx512) = match options.scalar {
                    crate::options::Scalar::F64 => (4, 8),
                    crate::options::Scalar::F32 => (8, 16),
                };
                let single = f.single;
                let wide = if !dispatched {
                    "where the target's vectors are wide (`-C target-cpu=native`)".to_string()
                } else {
                    format!("where the CPU's vectors are wide (on x86-64 with AVX-512 or AVX2 this function runs a copy compiled for it wherever `{single}` does; elsewhere compile with `-C target-cpu=native`)")
                };
                // The dispatch gives a body of this size copies of instructions (`zmm`).
                let large = if zmm_only {
                    any_token = true;
                    format!(" It runs so only where the CPU has AVX-512 and `B` is a multiple of {avx512}, or AVX2 with FMA and `B` a multiple of {avx2}: {} (the runtime's `Avx512` and `Avx2`); {} `{single}` once per state, as its body ({ops} operations) is too large for the optimiser to vectorise `B` wide (more than {MAX_LANES_OPS}).", super::zmm::DOC_MARK, super::zmm::ONLY_MARK)
                } else if dispatched && ops >= super::zmm::MIN_OPS {
                    any_token = true;
                    format!(" A body this large ({ops} operations) is only partly vectorised by the optimiser, so {} (the runtime's `Avx512` and `Avx2`) where `B` is a multiple of a register's lanes ({avx512} and {avx2}).", super::zmm::DOC_MARK)
                } else if dispatched
                    && options.scalar == crate::options::Scalar::F64
                    && f.cols == 1
                    && ops >= super::zmm::VECTOR_MIN_OPS
                {
                    any_token = true;
                    format!(" For a body of {ops} operations with a vector result, {} (the runtime's `Avx512` and `Avx2`) where `B` is a multiple of a register's lanes ({avx512} and {avx2}): faster than the vectoriser's.", super::zmm::DOC_MARK)
                } else {
                    String::new()
                };
                let t = options.scalar.as_str();
                // Where the vectoriser's copies run too, when they pay.
                let pays = if zmm_only {
                    String::new()
                } else {
                    format!(": per state it is cheaper than `B` calls {wide}, with `B` a multiple of the vector width (AVX2 holds {avx2} `{t}`s, AVX-512 {avx512})")
                };
                let how = format!(
                    " The unrolled code of `{single}` with every value a `Lanes<{t}, B>` of the runtime crate (structure of arrays), so that each operation runs on all `B` states at once in vector registers{pays}.{large} Multiply-adds are fused where `{single}`'s are: a state's result is `{single}`'s bit for bit."
                );
                // Never inlined: where it is not dispatched (`-C target-cpu=native`, other
                // architectures, `no_std`) this function holds the whole `B`-wide body, and
                // inlined into a caller's loop it ran 1.1–1.4× slower (UR5 and Panda, B = 8,
                // native); where it is, `dispatch` makes the small wrapper `#[inline]` again,
                // and where it is not, `out_of_line` moves the body into an `extern "C"` part.
                (wrap(f.single, body), how, quote!(#[inline(never)]))
            }
            _ => {
                let single = Ident::new(f.single, Span::call_site());
                let why = if runtime.is_none() {
                    "it is generated without the runtime crate, whose `Lanes` type vectorised batches need".to_string()
                } else if too_many_outputs {
                    format!("its result has {} entries, and transposing that many out of `B`-wide lanes costs more than computing them lane-wise gains (more than {MAX_LANES_OUTPUTS} entries)", rows * f.cols)
                } else {
                    format!("its body ({ops} operations) is too large to unroll `B` wide (more than {MAX_LANES_OPS}: the optimiser leaves such bodies largely unvectorised, and their `B`-wide values spill)")
                };
                (
                    per_state(&single, &names, &result_path),
                    format!(" The code of `{}` called once per state: {why}.", f.single),
                    quote!(#[inline]),
                )
            }
        };
        let doc = f.doc;
        out.extend(quote! {
            #[doc = #doc]
            #[doc = ""]
            #[doc = #how]
            #inline
            #[must_use]
            pub fn #name<const B: usize>(&self, #(#params),*) -> [#result; B] {
                #body
            }
        });
    }
    if let Some(runtime) = runtime {
        out.extend(lanes_helpers(
            options.scalar,
            runtime,
            fuses,
            trig,
            trig && !options.no_std && options.cpu_dispatch,
            any_token,
        ));
    }
    out
}

/// A batch body that calls `single` once per state, by iterators (no indexing, so no bounds
/// checks), on the arguments `names`, into an array of `result` (a type path that has
/// `zeros()`). The single-state function is generated with its batch form (`generate_impl`).
pub(super) fn per_state(single: &Ident, names: &[Ident], result: &TokenStream) -> TokenStream {
    let call = quote!(|#(#names),*| self.#single(#(#names),*));
    let Some((pattern, states)) = zipped(names) else {
        return quote!([self.#single(); B]);
    };
    quote! {
        let single = #call;
        let mut out = [#result::zeros(); B];
        for (o, #pattern) in out.iter_mut().zip(#states) {
            *o = single(#(#names),*);
        }
        out
    }
}

/// The pattern `((a, b), c)` and the iterator `a.iter().zip(b.iter()).zip(c.iter())` over the
/// arrays `names` of states, or `None` for none.
fn zipped(names: &[Ident]) -> Option<(TokenStream, TokenStream)> {
    let (first, rest) = names.split_first()?;
    let (mut pattern, mut states) = (quote!(#first), quote!(#first.iter()));
    for n in rest {
        pattern = quote!((#pattern, #n));
        states = quote!(#states.zip(#n.iter()));
    }
    Some((pattern, states))
}

/// A copy's batch function that runs `body`, a body of instructions for one register of
/// lanes (`L` = `lanes` states, not generic: [`super::dispatch`]'s `token_body_item`), on the
/// `B` states `L` at a time (`B` a multiple of `L`; [`super::zmm`]): the statements of the
/// copy `copy`, and the item they call, `copy_fill`. `elem`: `R` of `-> [R; B]`, `b` the name of
/// `B`, `generics` and `args` the copy's; `attrs` its `cfg` and `target_feature`. `None` for a
/// function without states.
///
/// `copy_fill` (`#[inline(never)]`, `extern "C"`) writes each register's results into the copy's
/// uninitialised result through a pointer, and the copy returns it: the optimiser then hands
/// `copy_fill` the copy's return slot itself (LLVM's call-slot optimisation), so the `B` results are
/// written once, where the caller wants them. Built in the copy's frame instead (a zeroed
/// array, filled, returned), they were zeroed by a `memset` and copied out by a `memcpy`
/// (Solo-12's inverse dynamics batch of 8: 1,152 bytes; G1's 2,240, which glibc copies with
/// `rep movsb`, placement-dependent on a Zen 3: see the runtime's `Lanes::scatter`).
///
/// Written for one register, the body is compiled once whatever `B` is; with `B` = 2`L`, its
/// values in two registers each, G1's AVX2 bodies took 189 s to compile in release against
/// 58 s, and ran slower (Solo-12's inverse dynamics in the AVX2 copy: 1.37× of single calls
/// with `B` = 8 as one body, 1.89× with 4). The body is never named with `B`, not even in a
/// branch for `B` = `L`: a debug build, which does not prune `if const` branches before it
/// generates code, then also compiled the bodies `B` wide (G1's four batch functions with
/// `B` = 8: 119 s in debug).
#[allow(clippy::too_many_arguments)]
pub(super) fn per_register(
    copy: &Ident,
    body: &Ident,
    names: &[Ident],
    elem: &TokenStream,
    lanes: &proc_macro2::Literal,
    b: &Ident,
    generics: &TokenStream,
    args: &TokenStream,
    attrs: &TokenStream,
) -> Option<(TokenStream, TokenStream)> {
    let (pattern, states) = zipped(names)?;
    let fill = format_ident!("{}_fill", copy);
    let statements = quote! {
        let mut out = ::core::mem::MaybeUninit::<[#elem; #b]>::uninit();
        // SAFETY: the function's contract: the copy's features.
        unsafe { self.#fill::<#b>(#(#names,)* &mut out) };
        // SAFETY: `B` is a multiple of the register's lanes here, so `fill` wrote every one of
        // the `B` results.
        unsafe { out.assume_init() }
    };
    let doc = format!(
        " The loop of [`Self::{copy}`]: [`Self::{body}`] on each register of {lanes} states, its results written into `out` (all `B` of them, `B` a multiple of {lanes})."
    );
    let item = quote! {
        #[doc = #doc]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = ""]
        #[doc = " The CPU has the copy's features, and `B` is a multiple of the register's lanes."]
        #attrs
        #[inline(never)]
        #[allow(unsafe_code, improper_ctypes_definitions)]
        unsafe extern "C" fn #fill<#generics>(#args, out: &mut ::core::mem::MaybeUninit<[#elem; #b]>) {
            let results = out.as_mut_ptr().cast::<[#elem; #lanes]>();
            #(let (#names, _) = #names.as_chunks::<#lanes>();)*
            for (k, #pattern) in #states.enumerate() {
                // SAFETY: `k` < `B` / `L`, so register `k`'s `L` results lie within `out`; the
                // function's contract: the copy's features.
                unsafe { results.add(k).write(self.#body(#(#names),*)) };
            }
        }
    };
    Some((statements, item))
}

/// The impl block with each public `X_batch<const B: usize>` marked `#[inline(never)]` (a
/// vectorised body the dispatch left alone) split in two: `X_batch`, `#[inline]`, which only
/// calls `X_batch_out_of_line`, the body, `#[inline(never)]` and `extern "C"`.
///
/// Why: a caller cannot know that a Rust-ABI function it does not see cannot unwind, so a
/// `#[no_panic]` wrapper around `mass_matrix_batch` failed to link whenever the optimiser
/// placed the two in different codegen units (the release `no_panic` test on a mimic chain,
/// after unrelated changes had moved the partition). An `extern "C"` function cannot unwind
/// by its ABI, and its callers know it from its declaration alone, as for the dispatched
/// copies and the runtime's `Lanes::scatter`. Where the dispatch copies a batch function, its
/// wrapper is `#[inline]` already and calls `extern "C"` functions: the copies, or where none
/// runs `X_batch_portable` ([`super::dispatch`]).
pub(super) fn out_of_line(impl_block: TokenStream) -> TokenStream {
    super::dispatch::with_impl_items(impl_block, |body| {
        let mut items = TokenStream::new();
        for item in super::dispatch::impl_items(body) {
            match split_out_of_line(&item) {
                Some(split) => items.extend(split),
                None => items.extend(item),
            }
        }
        Some(items)
    })
}

/// The two functions of [`out_of_line`] for `item`, when it is an out-of-line batch function.
fn split_out_of_line(item: &[TokenTree]) -> Option<TokenStream> {
    let (f, name) = super::dispatch::public_fn(item)?;
    if !name.to_string().ends_with("_batch") {
        return None;
    }
    // The attributes stay on the public function, `#[inline(never)]` made `#[inline]`.
    let (attrs, never_found) = super::dispatch::without_inline_never(&item[..f - 1]);
    if !never_found {
        return None;
    }
    let (generics, generic_names, after) = super::dispatch::const_generics(&item[f + 2..])?;
    let after = f + 2 + after;
    let TokenTree::Group(args) = item.get(after)? else {
        return None;
    };
    let TokenTree::Group(body) = item.last()? else {
        return None;
    };
    let names = super::dispatch::receiver_and_names(args.stream())?;
    let ret: TokenStream = item[after + 1..item.len() - 1].iter().cloned().collect();
    let inner = format_ident!("{}_out_of_line", name);
    let doc = format!(
        " The body of [`Self::{name}`], out of line; `extern \"C\"`, so that its callers know it cannot unwind without seeing it."
    );
    let (args, body) = (args.stream(), body.stream());
    Some(quote! {
        #attrs
        pub fn #name<#generics>(#args) #ret {
            self.#inner::<#(#generic_names),*>(#(#names),*)
        }
        #[doc = #doc]
        #[inline(never)]
        #[allow(improper_ctypes_definitions)]
        extern "C" fn #inner<#generics>(#args) #ret {
            #body
        }
    })
}

/// The helpers of the vectorised bodies: `mul_add_lanes` (where they fuse) and
/// `joint_sin_cos_rows` (where they take sines and cosines), each with a `_with` form whose
/// `F` the CPU dispatch sets ([`super::dispatch`]).
fn lanes_helpers(
    scalar: crate::options::Scalar,
    runtime: &TokenStream,
    fuses: bool,
    trig: bool,
    dispatched: bool,
    tokens: bool,
) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let lanes = quote!(#runtime::Lanes<#t, B>);
    let mul_add = fuses.then(|| {
        quote! {
            /// `a·b + c` lane by lane, fused (rounded once) where [`Self::mul_add`] is: the
            /// batch bodies' multiply-adds, the same products as the single-state bodies'.
            #[inline(always)]
            fn mul_add_lanes<const B: usize>(a: #lanes, b: #lanes, c: #lanes) -> #lanes {
                Self::mul_add_lanes_with::<B, false>(a, b, c)
            }

            /// [`Self::mul_add_lanes`], fused also when `F` (the AVX-512 and AVX2 copies of a
            /// dispatched batch function).
            #[inline(always)]
            fn mul_add_lanes_with<const B: usize, const F: bool>(
                a: #lanes,
                b: #lanes,
                c: #lanes,
            ) -> #lanes {
                if F || cfg!(any(target_feature = "fma", target_arch = "aarch64")) {
                    let mut out = c.0;
                    for ((o, a), b) in out.iter_mut().zip(a.0).zip(b.0) {
                        *o = a.mul_add(b, *o);
                    }
                    #runtime::Lanes(out)
                } else {
                    a * b + c
                }
            }
        }
    });
    let sin_cos = trig.then(|| {
        quote! {
            /// The sines and cosines of `K` joint angles of `B` states each: the
            /// `joint_sin_cos` kernel on all `K·B` angles, inlined into the batch body.
            #[inline(always)]
            fn joint_sin_cos_rows<const K: usize, const B: usize>(
                x: [#lanes; K],
            ) -> ([#lanes; K], [#lanes; K]) {
                Self::sin_cos_rows_with::<K, B, false>(x)
            }

            /// [`Self::joint_sin_cos_rows`], the polynomials fused when `F` (see
            /// `sin_cos_n`). One loop over all `K·B` elements, so that it vectorises across
            /// rows when `B` is narrower than the target's vectors.
            #[inline(always)]
            fn sin_cos_rows_with<const K: usize, const B: usize, const F: bool>(
                x: [#lanes; K],
            ) -> ([#lanes; K], [#lanes; K]) {
                let ((), sin, cos) = Self::sin_cos_rows_by::<K, B, _, _>(x, |x, s, c, n| {
                    Self::sin_cos_into::<F>(x, s, c, n)
                });
                (sin, cos)
            }

            /// `kernel(angles, sines, cosines, n)` on the `K·B` elements of `x` as one
            /// array, and the sines and cosines back in rows.
            #[inline(always)]
            fn sin_cos_rows_by<const K: usize, const B: usize, R, G>(
                x: [#lanes; K],
                kernel: G,
            ) -> (R, [#lanes; K], [#lanes; K])
            where
                G: FnOnce(&[#t], &mut [#t], &mut [#t], usize) -> R,
            {
                let mut xs = [[0.0; B]; K];
                for (d, x) in xs.iter_mut().zip(&x) {
                    *d = x.0;
                }
                let (mut s, mut c) = ([[0.0; B]; K], [[0.0; B]; K]);
                let r = kernel(
                    xs.as_flattened(),
                    s.as_flattened_mut(),
                    c.as_flattened_mut(),
                    K * B,
                );
                let (mut sin, mut cos) = (x, x);
                for (((s, c), sin), cos) in s.iter().zip(&c).zip(&mut sin).zip(&mut cos) {
                    (sin.0, cos.0) = (*s, *c);
                }
                (r, sin, cos)
            }
        }
    });
    // The dispatched bodies' kernel: the far angles are the caller's (`super::dispatch`, which
    // keeps it only where a batch body calls it: a pendulum's bodies are too small to be
    // dispatched; `allow(dead_code)` for a block where nothing is dispatched at all).
    let near = (trig && dispatched).then(|| {
        quote! {
            /// [`Self::sin_cos_rows_with`] in a dispatched batch body, where the angles
            /// beyond the kernel's bound are the caller's: when `F` (the AVX-512 and AVX2
            /// copies), `None` if any is (the body then calls the single-state function once
            /// per state), the same sines and cosines otherwise; when not `F`, those of
            /// [`Self::sin_cos_rows_with`], its fallback included. In line in a copy, that
            /// fallback's calls of the platform's `sin_cos` clobber every vector register, so
            /// that the values live across the kernel are spilled before it.
            #[inline(always)]
            #[allow(dead_code)]
            fn sin_cos_rows_near<const K: usize, const B: usize, const F: bool>(
                x: [#lanes; K],
            ) -> ::core::option::Option<([#lanes; K], [#lanes; K])> {
                if !F {
                    return ::core::option::Option::Some(Self::sin_cos_rows_with::<K, B, F>(x));
                }
                match Self::sin_cos_rows_by::<K, B, _, _>(x, |x, s, c, n| {
                    Self::sin_cos_poly::<F>(x, s, c, n)
                }) {
                    (false, sin, cos) => ::core::option::Option::Some((sin, cos)),
                    (true, ..) => ::core::option::Option::None,
                }
            }
        }
    });
    // The operands and the tokens of the AVX-512 and AVX2 copies of large batch bodies
    // (`super::zmm`) and the AVX2 copies of mid-sized ones, which exist only where the dispatch
    // made them.
    let tokens = tokens.then(|| {
        quote! {
            /// The lanes of `x`: `x` itself, or a scalar on every lane (the operands of the
            /// AVX-512 batch bodies' instructions).
            #[inline(always)]
            #[allow(dead_code)]
            fn lanes<const B: usize>(x: impl Into<#lanes>) -> #lanes {
                x.into()
            }

            /// The runtime's `Avx512` token, for the AVX-512 batch bodies.
            ///
            /// # Safety
            ///
            /// The CPU has AVX-512 F and DQ and FMA (which `has_avx512` checks, where the
            /// functions are dispatched).
            #[cfg(target_arch = "x86_64")]
            #[inline(always)]
            #[allow(dead_code, unsafe_code)]
            unsafe fn lanes_avx512() -> #runtime::Avx512 {
                // SAFETY: the function's contract.
                unsafe { #runtime::Avx512::new_unchecked() }
            }

            /// The runtime's `Avx2` token, for the AVX2 batch bodies.
            ///
            /// # Safety
            ///
            /// The CPU has AVX2 and FMA (which `has_avx2` checks, where the functions are
            /// dispatched).
            #[cfg(target_arch = "x86_64")]
            #[inline(always)]
            #[allow(dead_code, unsafe_code)]
            unsafe fn lanes_avx2() -> #runtime::Avx2 {
                // SAFETY: the function's contract.
                unsafe { #runtime::Avx2::new_unchecked() }
            }
        }
    });
    quote!(#mul_add #sin_cos #near #tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_line_batch_bodies_move_into_extern_c_parts() {
        let block = quote! {
            impl Robot {
                /// The mass matrix for a batch.
                #[inline(never)]
                #[must_use]
                pub fn mass_matrix_batch<const B: usize>(&self, q: &[V; B]) -> [M; B] {
                    let x = q;
                    body(x)
                }
                #[inline]
                pub fn gravity_batch<const B: usize>(&self, q: &[V; B]) -> [V; B] {
                    per_state(q)
                }
                #[inline(never)]
                fn helper(&self) {}
            }
        };
        let out = out_of_line(block).to_string().replace(' ', "");
        assert!(out.contains(
            "Themassmatrixforabatch.\"]#[inline]#[must_use]pubfnmass_matrix_batch<constB:usize>(&self,q:&[V;B])->[M;B]{self.mass_matrix_batch_out_of_line::<B>(q)}"
        ), "{out}");
        assert!(out.contains(
            "#[inline(never)]#[allow(improper_ctypes_definitions)]extern\"C\"fnmass_matrix_batch_out_of_line<constB:usize>(&self,q:&[V;B])->[M;B]{letx=q;body(x)}"
        ), "{out}");
        // Not out of line, not a batch function: unchanged.
        assert!(out.contains(
            "#[inline]pubfngravity_batch<constB:usize>(&self,q:&[V;B])->[V;B]{per_state(q)}"
        ));
        assert!(out.contains("#[inline(never)]fnhelper(&self){}"));
        assert_eq!(out.matches("out_of_line").count(), 2);
    }
}
