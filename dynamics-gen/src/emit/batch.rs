//! The batch functions: `inverse_dynamics_batch`, `forward_dynamics_batch`, `mass_matrix_batch`
//! and `gravity_batch`, each the single-state function's unrolled code evaluated on `B`
//! states at once, in structure-of-arrays form.
//!
//! Every value of the body is a `Lanes<scalar, B>` of the runtime crate: `B` values side by
//! side, one per state, each operation applied lane by lane on a fixed-size array, which
//! the compiler turns into vector instructions (4 `f64` lanes per AVX2 register, 2 per SSE2
//! register). The expression graph and its order of operations are those of the single-state
//! function; only fused multiply-adds are left out (lanes have none), so a lane differs from
//! the single-state result by rounding only where that one fuses. The joints' sines and
//! cosines come from the single-state `joint_sin_cos`, called once per state.
//!
//! A body larger than the splitting threshold of single-state functions (a large tree) is
//! not unrolled `B` wide: the batch function then calls the single-state function per state.

use super::function::{Arg, FunctionBody, Output, MAX_UNSPLIT_LETS};
use crate::expr::{ExprGraph, ExprId};
use crate::options::Options;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

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
            }
            .tokens()
        };
        let large = graph.live(f.outputs).iter().filter(|&&l| l).count() > MAX_UNSPLIT_LETS;
        let (body, how) = match runtime {
            Some(runtime) if !large => (
                wrap(f.single, body(Some(runtime))),
                format!(
                    " The unrolled code of `{0}` with every value a `Lanes<{1}, B>` of the runtime crate (structure of arrays), so that each operation runs on all `B` states at once in vector registers: per state it is cheaper than `B` calls where the target's vectors are wide (`-C target-cpu=native`; AVX2 holds 4 `{1}`s, AVX-512 8), with `B` a multiple of that width. No fused multiply-adds: a state's result may differ from `{0}`'s by rounding where that one fuses.",
                    f.single,
                    options.scalar.as_str()
                ),
            ),
            _ => {
                // Per state, by iterators (no indexing, so no bounds checks): a call of the
                // single-state function (generated with its batch form, see `generate_impl`).
                let single = Ident::new(f.single, Span::call_site());
                let call = quote!(|#(#names),*| self.#single(#(#names),*));
                let first = &names[0];
                let (mut pattern, mut states) = (quote!(#first), quote!(#first.iter()));
                for n in &names[1..] {
                    pattern = quote!((#pattern, #n));
                    states = quote!(#states.zip(#n.iter()));
                }
                let why = if runtime.is_some() {
                    "its body is too large to unroll `B` wide"
                } else {
                    "it is generated without the runtime crate, whose `Lanes` type vectorised batches need"
                };
                (
                    quote! {
                        let single = #call;
                        let mut out = [#result_path::zeros(); B];
                        for (o, #pattern) in out.iter_mut().zip(#states) {
                            *o = single(#(#names),*);
                        }
                        out
                    },
                    format!(
                        " The code of `{}` called once per state: {why}.",
                        f.single
                    ),
                )
            }
        };
        let doc = f.doc;
        out.extend(quote! {
            #[doc = #doc]
            #[doc = ""]
            #[doc = #how]
            #[inline]
            #[must_use]
            pub fn #name<const B: usize>(&self, #(#params),*) -> [#result; B] {
                #body
            }
        });
    }
    out
}
