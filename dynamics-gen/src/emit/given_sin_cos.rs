//! Variants that take the joints' sines and cosines from the caller
//! (`Options::sin_cos_variants`): for each function `f(&self, q, …)` whose body computes
//! the sines and cosines of joint coordinates, a second function
//!
//! ```text
//! pub fn f_from_sin_cos(&self, q, sin_q, cos_q, …) -> R   // sin_q[i] = sin q_i, cos_q[i] = cos q_i
//! ```
//!
//! with the same body except its first statement: where `f` calls the vectorised
//! `joint_sin_cos` helper on its angles, the variant reads `sin q_i`, `cos q_i` from the two
//! vectors for every angle that is a coordinate itself, and still computes the others (a
//! joint offset folded in, `q_i + a`, or a mimic joint's `m q_j + a`) from `q`. The struct
//! gets `sin_cos(q)`, the sines and cosines of every entry of `q` by the same helper, so
//! that `f_from_sin_cos(q, &s, &c, …)` with `(s, c) = sin_cos(q)` is `f(q, …)` bit for bit
//! (the dispatch takes `sin_cos`, the functions that have a variant and the variants
//! together or not at all, so that their sines are fused alike): a caller who needs several functions at one state (the mass matrix, the bias and a Jacobian in a
//! controller's step) computes the sines and cosines once, and one who has them already
//! (from a previous step's angle-addition update, an encoder that gives them) skips them.
//!
//! A rewrite of the impl block's tokens, before [`super::dispatch`], which then dispatches
//! the variants, their functions and `sin_cos` together or not at all. Left alone:
//! the functions with generic parameters (the batch functions, whose sines and cosines are
//! per state, and `constrained_forward_dynamics`) and bodies split into `extern "C"` parts
//! (the largest trees' derivatives).
//!
//! Measured (one binary, medians of 9 rounds of 20,000 calls at cycled random states,
//! default profile, so the AVX-512 copies; 2026-11-26): a controller's step that needs the
//! mass matrix, coriolis, gravity and the body Jacobian at one state took, as four calls
//! and as `sin_cos` and four variants: the UR5 96–123 ns and 71–73 ns (two runs), the Panda
//! 191–192 and 140–142 ns, rand7 250–252 and 236–237 ns (its general geometry leaves the
//! sines and cosines a smaller part of each call).

use proc_macro2::{Delimiter, Group, Ident, Literal, TokenStream, TokenTree};
use quote::{format_ident, quote};

/// The suffix of the variants' names.
pub const SUFFIX: &str = "_from_sin_cos";

/// The impl block (`attrs impl Name { items }`) with a variant after each eligible function
/// and the `sin_cos` helper when there is any; unchanged when there is none. `q_ty` is the
/// type of `q` (`SVector<T, NQ>`), `nq` its length, `nalgebra` the crate's path.
pub fn apply(
    impl_block: TokenStream,
    q_ty: &TokenStream,
    nq: usize,
    nalgebra: &TokenStream,
) -> TokenStream {
    super::dispatch::with_impl_items(impl_block, |body| {
        let mut out = TokenStream::new();
        let mut any = false;
        for item in super::dispatch::impl_items(body) {
            let variant = variant(&item, q_ty);
            out.extend(item);
            if let Some(variant) = variant {
                out.extend(variant);
                any = true;
            }
        }
        any.then(|| {
            out.extend(helper(q_ty, nq, nalgebra));
            out
        })
    })
}

/// `sin_cos(q)`: the sines and cosines of every entry of `q` by the `joint_sin_cos` helper.
fn helper(q_ty: &TokenStream, nq: usize, na: &TokenStream) -> TokenStream {
    let names: Vec<Ident> = (0..nq).map(|i| format_ident!("q{}", i)).collect();
    let s: Vec<Ident> = (0..nq).map(|i| format_ident!("s{}", i)).collect();
    let c: Vec<Ident> = (0..nq).map(|i| format_ident!("c{}", i)).collect();
    let k = Literal::usize_unsuffixed(nq);
    let (call, rest) = if nq == 1 {
        (quote!(Self::joint_sin_cos::<1, 1>), quote!())
    } else {
        (
            quote!(Self::joint_sin_cos::<#k, { Self::sin_cos_lanes(#k) }>),
            quote!(, ..),
        )
    };
    quote! {
        /// The sines and cosines of the entries of `q` (`sin q_i`, `cos q_i`), computed as
        /// every function of this struct computes them: the arguments of the
        /// `*_from_sin_cos` variants, which then equal the functions they vary. Only the
        /// entries of revolute joint coordinates are read there (not those of a floating
        /// base's position and quaternion, nor of a prismatic joint).
        #[inline]
        #[must_use]
        pub fn sin_cos(&self, q: &#q_ty) -> (#q_ty, #q_ty) {
            let [[#(#names),*]] = q.data.0;
            let ([#(#s),* #rest], [#(#c),* #rest]) = #call([#(#names),*]);
            (
                <#q_ty>::from_array_storage(#na::ArrayStorage([[#(#s),*]])),
                <#q_ty>::from_array_storage(#na::ArrayStorage([[#(#c),*]])),
            )
        }
    }
}

/// The variant of `item` (attributes, `pub fn name(&self, q: &Q, …) -> R { body }`), or
/// `None` when it is not eligible: no `q` argument of type `q_ty`, or no batch of sines and
/// cosines with an angle that is a coordinate itself.
fn variant(item: &[TokenTree], q_ty: &TokenStream) -> Option<TokenStream> {
    let (f, name) = super::dispatch::public_fn(item)?;
    let TokenTree::Group(args) = item.get(f + 2)? else {
        return None; // generic: the batch functions and `constrained_forward_dynamics`
    };
    if args.delimiter() != Delimiter::Parenthesis {
        return None;
    }
    let TokenTree::Group(body) = item.last()? else {
        return None;
    };
    // A body split into nested `extern "C"` parts (the largest trees) is left alone: its
    // parts cannot see the new arguments.
    if super::dispatch::contains_ident(&body.stream(), "extern") {
        return None;
    }
    let q_arg = quote!(q: &#q_ty).to_string();
    let parts = super::dispatch::split_commas(args.stream());
    let qi = parts
        .iter()
        .position(|a| a.iter().cloned().collect::<TokenStream>().to_string() == q_arg)?;
    let new_body = unbind_unused(given(body.stream())?);
    // The arguments with `sin_q`, `cos_q` after `q`.
    let mut new_args = TokenStream::new();
    for (k, a) in parts.into_iter().enumerate() {
        new_args.extend(a);
        new_args.extend(quote!(,));
        if k == qi {
            new_args.extend(quote!(sin_q: &#q_ty, cos_q: &#q_ty,));
        }
    }
    let ret: TokenStream = item[f + 3..item.len() - 1].iter().cloned().collect();
    let vname = format_ident!("{}{}", name, SUFFIX);
    let doc = format!(
        " [`Self::{name}`] with the sines and cosines of the joint angles given: `sin_q[i] = \
         sin q_i` and `cos_q[i] = cos q_i` for each revolute joint coordinate `q_i` (other \
         entries are not read; angles with an offset or a mimic multiplier are computed from \
         `q`, as [`Self::{name}`] does). With `(sin_q, cos_q) = self.sin_cos(q)` it is \
         [`Self::{name}`]: the same values, bit for bit where both are dispatched alike."
    );
    // A function that writes into an argument (`mass_matrix_lower_into`) returns nothing.
    let must_use = (!ret.is_empty()).then(|| quote!(#[must_use]));
    Some(quote! {
        #[doc = #doc]
        #[inline]
        #must_use
        pub fn #vname(#new_args) #ret {
            #new_body
        }
    })
}

/// `body` with its batch of sines and cosines (`let ([s…], [c…]) =
/// Self::joint_sin_cos::<K, P>([args]);`, at the top level or in the first block that has it)
/// taken from `sin_q`, `cos_q` for each argument that is a coordinate `q<i>`; `None` when
/// there is no such batch (or no such argument in it).
fn given(body: TokenStream) -> Option<TokenStream> {
    let tokens: Vec<TokenTree> = body.into_iter().collect();
    // `let (…) = Self :: joint_sin_cos :: < K , P > ( [args] ) ;`
    let is_punct = |t: &TokenTree, c: char| matches!(t, TokenTree::Punct(p) if p.as_char() == c);
    let is_ident = |t: &TokenTree, s: &str| matches!(t, TokenTree::Ident(i) if i == s);
    for k in 0..tokens.len() {
        if let TokenTree::Group(g) = &tokens[k] {
            if g.delimiter() == Delimiter::Brace {
                if let Some(inner) = given(g.stream()) {
                    let mut out = tokens.clone();
                    let mut new = Group::new(Delimiter::Brace, inner);
                    new.set_span(g.span());
                    out[k] = TokenTree::Group(new);
                    return Some(out.into_iter().collect());
                }
            }
            continue;
        }
        if !is_ident(&tokens[k], "let") {
            continue;
        }
        let Some(window) = tokens.get(k..k + 15) else {
            continue;
        };
        let [_, TokenTree::Group(pats), eq, self_, c1, c2, f, c3, c4, lt, _k, comma, _p, gt, TokenTree::Group(call)] =
            window
        else {
            continue;
        };
        let shaped = is_punct(eq, '=')
            && is_ident(self_, "Self")
            && is_punct(c1, ':')
            && is_punct(c2, ':')
            && is_ident(f, "joint_sin_cos")
            && is_punct(c3, ':')
            && is_punct(c4, ':')
            && is_punct(lt, '<')
            && is_punct(comma, ',')
            && is_punct(gt, '>')
            && pats.delimiter() == Delimiter::Parenthesis
            && call.delimiter() == Delimiter::Parenthesis;
        if !shaped || !tokens.get(k + 15).is_some_and(|t| is_punct(t, ';')) {
            continue;
        }
        let inner: Vec<TokenTree> = call.stream().into_iter().collect();
        let [TokenTree::Group(array)] = &inner[..] else {
            continue;
        };
        let replacement = replacement(&pats.stream(), &array.stream())?;
        let mut out: Vec<TokenTree> = tokens[..k].to_vec();
        out.extend(replacement);
        out.extend(tokens[k + 16..].iter().cloned());
        return Some(out.into_iter().collect());
    }
    None
}

/// The statements that bind the patterns `pats` (`[s…], [c…]`) of the batch over `args`:
/// `sin_q`, `cos_q` entries for the arguments `q<i>`, one smaller batch for the rest.
fn replacement(pats: &TokenStream, args: &TokenStream) -> Option<TokenStream> {
    let args = super::dispatch::split_commas(args.clone());
    let index = |a: &[TokenTree]| match a {
        [TokenTree::Ident(i)] => i.to_string().strip_prefix('q')?.parse::<usize>().ok(),
        _ => None,
    };
    if args.iter().all(|a| index(a).is_none()) {
        return None;
    }
    let rest: Vec<TokenStream> = args
        .iter()
        .filter(|a| index(a).is_none())
        .map(|a| a.iter().cloned().collect())
        .collect();
    let mut sines = Vec::new();
    let mut cosines = Vec::new();
    let mut m = 0usize;
    for a in &args {
        match index(a) {
            Some(i) => {
                let i = Literal::usize_unsuffixed(i);
                sines.push(quote!(sin_q.data.0[0][#i]));
                cosines.push(quote!(cos_q.data.0[0][#i]));
            }
            None => {
                let j = Literal::usize_unsuffixed(m);
                m += 1;
                sines.push(quote!(kernel_s[#j]));
                cosines.push(quote!(kernel_c[#j]));
            }
        }
    }
    let kernel = match rest.len() {
        0 => quote!(),
        1 => quote! { let (kernel_s, kernel_c) = Self::joint_sin_cos::<1, 1>([#(#rest),*]); },
        r => {
            let r = Literal::usize_unsuffixed(r);
            quote! {
                let (kernel_s, kernel_c) =
                    Self::joint_sin_cos::<#r, { Self::sin_cos_lanes(#r) }>([#(#rest),*]);
            }
        }
    };
    Some(quote! {
        #kernel
        let (#pats) = ([#(#sines),*], [#(#cosines),*]);
    })
}

/// `body` with each coordinate `q<i>` that its destructuring of `q` (`let [[q0, …]] =
/// q.data.0;`) binds but nothing else reads bound to `_` instead: the angles the variant
/// takes as sines and cosines.
fn unbind_unused(body: TokenStream) -> TokenStream {
    fn count(stream: &TokenStream, counts: &mut std::collections::HashMap<String, usize>) {
        for t in stream.clone() {
            match t {
                TokenTree::Ident(i) => *counts.entry(i.to_string()).or_default() += 1,
                TokenTree::Group(g) => count(&g.stream(), counts),
                _ => {}
            }
        }
    }
    let mut counts = std::collections::HashMap::new();
    count(&body, &mut counts);
    let is_coordinate = |i: &Ident| {
        let s = i.to_string();
        s.strip_prefix('q')
            .is_some_and(|n| n.parse::<usize>().is_ok())
            && counts[&s] == 1
    };
    let mut tokens: Vec<TokenTree> = body.into_iter().collect();
    // `let [[…]] = q . data . 0 ;`
    let at = tokens.windows(4).position(|w| {
        matches!(&w[0], TokenTree::Ident(l) if l == "let")
            && matches!(&w[1], TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket)
            && matches!(&w[2], TokenTree::Punct(p) if p.as_char() == '=')
            && matches!(&w[3], TokenTree::Ident(q) if q == "q")
    });
    let Some(at) = at else {
        return tokens.into_iter().collect();
    };
    let TokenTree::Group(outer) = &tokens[at + 1] else {
        return tokens.into_iter().collect();
    };
    let rebuilt: TokenStream = outer
        .stream()
        .into_iter()
        .map(|t| match t {
            TokenTree::Group(inner) if inner.delimiter() == Delimiter::Bracket => {
                let names: TokenStream = inner
                    .stream()
                    .into_iter()
                    .map(|t| match t {
                        TokenTree::Ident(i) if is_coordinate(&i) => {
                            TokenTree::Ident(Ident::new("_", i.span()))
                        }
                        other => other,
                    })
                    .collect();
                TokenTree::Group(Group::new(Delimiter::Bracket, names))
            }
            other => other,
        })
        .collect();
    tokens[at + 1] = TokenTree::Group(Group::new(Delimiter::Bracket, rebuilt));
    tokens.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use quote::quote;

    #[test]
    fn each_function_with_joint_angles_gets_a_variant_and_the_struct_sin_cos() {
        let plain = crate::Builder::new("ur5").generate().expect("generates");
        assert!(!plain.contains("_from_sin_cos") && !plain.contains("pub fn sin_cos("));
        let code = crate::Builder::new("ur5")
            .sin_cos_variants(true)
            .generate()
            .expect("generates");
        assert!(code.contains("pub fn sin_cos("));
        for f in [
            "mass_matrix",
            "inverse_dynamics",
            "forward_dynamics",
            "jacobian_body",
        ] {
            assert!(code.contains(&format!("pub fn {f}_from_sin_cos(")), "{f}");
            // Dispatched as its function is.
            assert!(
                code.contains(&format!("fn {f}_from_sin_cos_avx512(")),
                "{f}"
            );
        }
        // No variant of what takes no angles, nor of the generic functions.
        for f in ["friction", "inertial_parameters", "inverse_dynamics_batch"] {
            assert!(!code.contains(&format!("fn {f}_from_sin_cos")), "{f}");
        }
        // The variant reads the given sines and cosines and leaves the angles unbound.
        let body = &code[code
            .find("fn gravity_from_sin_cos_body")
            .expect("a dispatched body")..];
        let body: String = body[..body.find("\n    }\n").expect("its end")]
            .split_whitespace()
            .collect();
        assert!(body.contains("let[[_,_,_,_,_,_]]=q.data.0;"), "{body}");
        assert!(body.contains("sin_q.data.0[0][1]") && body.contains("cos_q.data.0[0][3]"));
        assert!(!body.contains("joint_sin_cos") && !body.contains("sin_cos_n"));
    }

    #[test]
    fn angles_with_a_multiplier_or_an_offset_are_still_computed_from_q() {
        let pats = quote!([s1, s_7, s_9, ..], [c1, c_7, c_9, ..]);
        let args = quote!(q1, q2 + 0.5, 2.0 * q3);
        let out = super::replacement(&pats, &args)
            .expect("q1 is given")
            .to_string();
        let out: String = out.split_whitespace().collect();
        assert!(out.contains(
            "let(kernel_s,kernel_c)=Self::joint_sin_cos::<2,{Self::sin_cos_lanes(2)}>([q2+0.5,2.0*q3]);"
        ), "{out}");
        assert!(out.contains(
            "let([s1,s_7,s_9,..],[c1,c_7,c_9,..])=([sin_q.data.0[0][1],kernel_s[0],kernel_s[1]],[cos_q.data.0[0][1],kernel_c[0],kernel_c[1]]);"
        ), "{out}");
        // Nothing to take from the caller: no variant.
        assert!(super::replacement(&pats, &quote!(q1 + 0.5)).is_none());
    }
}
