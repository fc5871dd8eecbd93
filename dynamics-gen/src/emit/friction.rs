//! The generated `friction(q̇)` (Modern Robotics §8.9.1), written directly (its `sgn` and
//! `tanh` are not operations of the expression graph), and how it enters the dynamics when
//! [`Options::friction`] asks for it.

use super::literal::{float_text, float_tokens};
use super::text::inert;
use crate::options::{Friction, Options, Scalar};
use dynamics_model::Robot;
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};

/// `pub fn friction(&self, qd) -> SVector<T, NV>`: per coordinate `b q̇ + μ sgn(q̇)` (or
/// `μ tanh(q̇/ε)`), zero for a floating base's six entries. A mimic follower f of leader L
/// (`θ_f = m θ_L + o`) adds its own friction at its rate `m q̇_L`, projected on the leader:
/// `m² b_f q̇_L + |m| μ_f sgn(q̇_L)` (smooth: `|m| μ_f tanh(|m| q̇_L/ε)`).
pub fn friction_function(robot: &Robot, options: &Options, nalgebra: &TokenStream) -> TokenStream {
    let scalar = options.scalar;
    let ty = Ident::new(scalar.as_str(), Span::call_site());
    let nv = robot.nv();
    let off = nv - robot.n_coordinates();
    let model = options.friction.unwrap_or_default();
    // (coordinate, multiplier, damping, Coulomb) per physical joint.
    let couplings = robot.couplings();
    let mut used = vec![false; nv];
    let entries: Vec<TokenStream> = (0..nv)
        .map(|i| {
            if i < off {
                return float_tokens(0.0, scalar);
            }
            let c = i - off;
            let x = format_ident!("qd{}", i);
            let mut terms: Vec<TokenStream> = Vec::new();
            let mut b_eff = 0.0;
            for (joint, k) in robot.joints.iter().zip(&couplings) {
                if k.coordinate != c {
                    continue;
                }
                let m = k.multiplier;
                b_eff += joint.damping * m * m;
                if joint.friction != 0.0 {
                    let mu = float_tokens(joint.friction * m.abs(), scalar);
                    terms.push(match model {
                        Friction::Coulomb => quote! {
                            (if #x > 0.0 { #mu } else if #x < 0.0 { -#mu } else { 0.0 })
                        },
                        Friction::Smooth(eps) => {
                            let scale = float_tokens(m.abs() / eps, scalar);
                            let tanh = tanh_call(quote!(#scale * #x), scalar, options.no_std);
                            quote!(#mu * #tanh)
                        }
                    });
                }
            }
            if b_eff != 0.0 {
                let b = float_tokens(b_eff, scalar);
                terms.insert(0, quote!(#b * #x));
            }
            if terms.is_empty() {
                return float_tokens(0.0, scalar);
            }
            used[i] = true;
            quote!(#(#terms)+*)
        })
        .collect();
    let names = (0..nv).map(|i| {
        if used[i] {
            let x = format_ident!("qd{}", i);
            quote!(#x)
        } else {
            quote!(_)
        }
    });
    let na = nalgebra;
    let nv_lit = proc_macro2::Literal::usize_unsuffixed(nv);
    let list: Vec<String> = robot
        .joints
        .iter()
        .filter(|j| j.damping != 0.0 || j.friction != 0.0)
        .map(|j| {
            format!(
                "{} (b = {}, μ = {})",
                inert(&j.name),
                float_text(j.damping, Scalar::F64),
                float_text(j.friction, Scalar::F64)
            )
        })
        .collect();
    let coefficients = if list.is_empty() {
        " No joint of this robot has damping or Coulomb friction: the result is zero.".to_string()
    } else {
        format!(
            " Coefficients (b in N·m·s/rad or N·s/m, μ in N·m or N): {}.",
            list.join(", ")
        )
    };
    let model_doc = match model {
        Friction::Coulomb => " Model: `sgn(0) = 0` (the Coulomb part is discontinuous at rest; for simulation generate with a smoothing ε, `--friction-smoothing`).".to_string(),
        Friction::Smooth(eps) => format!(" Model: smooth, `μ tanh(q̇/ε)` with ε = {} (rad/s or m/s).", float_text(eps, Scalar::F64)),
    };
    let included = match options.friction {
        Some(_) => " Included in `inverse_dynamics`, `forward_dynamics`, their `_with_tip` forms and `constrained_forward_dynamics` (generated with friction).",
        None => " Not included in the other functions (generate with `--friction` to include it); add it yourself: `τ = inverse_dynamics(q, q̇, q̈) + friction(q̇)`.",
    };
    quote! {
        /// The joint friction `τ_f(q̇) = b q̇ + μ sgn(q̇)` (Modern Robotics §8.9.1): viscous
        /// damping b and Coulomb friction μ per joint, from the robot file (URDF
        /// `<dynamics damping friction>`, TOML and `robot!` `damping`, `friction`); the
        /// force the joint's actuator needs in addition to overcome them.
        #[doc = ""]
        #[doc = #coefficients]
        #[doc = #model_doc]
        #[doc = #included]
        #[inline]
        #[must_use]
        pub fn friction(&self, qd: &#na::SVector<#ty, #nv_lit>) -> #na::SVector<#ty, #nv_lit> {
            let [[#(#names),*]] = qd.data.0;
            #na::SVector::<#ty, #nv_lit>::from_array_storage(#na::ArrayStorage([[#(#entries),*]]))
        }
    }
}

/// The private `friction_rate(&self, qd)`: the diagonal of `∂τ_f/∂q̇`, `b + μ/ε (1 −
/// tanh²(q̇/ε))` per coordinate (Coulomb model: `b`, the derivative of `sgn` away from rest),
/// with the mimic projection of [`friction_function`]. Empty without friction in the
/// dynamics (only the derivative functions call it).
pub fn friction_rate_function(
    robot: &Robot,
    options: &Options,
    nalgebra: &TokenStream,
) -> TokenStream {
    let Some(model) = options.friction else {
        return quote!();
    };
    let scalar = options.scalar;
    let ty = Ident::new(scalar.as_str(), Span::call_site());
    let nv = robot.nv();
    let off = nv - robot.n_coordinates();
    let couplings = robot.couplings();
    let mut used = vec![false; nv];
    let entries: Vec<TokenStream> = (0..nv)
        .map(|i| {
            if i < off {
                return float_tokens(0.0, scalar);
            }
            let c = i - off;
            let x = format_ident!("qd{}", i);
            let mut b_eff = 0.0;
            let mut terms: Vec<TokenStream> = Vec::new();
            for (joint, k) in robot.joints.iter().zip(&couplings) {
                if k.coordinate != c {
                    continue;
                }
                let m = k.multiplier;
                b_eff += joint.damping * m * m;
                if let (Friction::Smooth(eps), true) = (model, joint.friction != 0.0) {
                    // d/dx μ|m| tanh(|m| x/ε) = μ m²/ε (1 − tanh²(|m| x/ε)).
                    let gain = float_tokens(joint.friction * m * m / eps, scalar);
                    let scale = float_tokens(m.abs() / eps, scalar);
                    let tanh = tanh_call(quote!(#scale * #x), scalar, options.no_std);
                    used[i] = true;
                    terms.push(quote!(#gain * { let t = #tanh; 1.0 - t * t }));
                }
            }
            if b_eff != 0.0 {
                terms.insert(0, float_tokens(b_eff, scalar));
            }
            if terms.is_empty() {
                return float_tokens(0.0, scalar);
            }
            quote!(#(#terms)+*)
        })
        .collect();
    let names = (0..nv).map(|i| {
        if used[i] {
            let x = format_ident!("qd{}", i);
            quote!(#x)
        } else {
            quote!(_)
        }
    });
    let na = nalgebra;
    let nv_lit = proc_macro2::Literal::usize_unsuffixed(nv);
    quote! {
        /// The diagonal of `∂friction(q̇)/∂q̇` (the Coulomb part's `sgn` counts as flat away
        /// from rest).
        #[inline]
        #[must_use]
        fn friction_rate(&self, qd: &#na::SVector<#ty, #nv_lit>) -> #na::SVector<#ty, #nv_lit> {
            let [[#(#names),*]] = qd.data.0;
            #na::SVector::<#ty, #nv_lit>::from_array_storage(#na::ArrayStorage([[#(#entries),*]]))
        }
    }
}

fn tanh_call(x: TokenStream, scalar: Scalar, no_std: bool) -> TokenStream {
    match (no_std, scalar) {
        (false, _) => quote!((#x).tanh()),
        (true, Scalar::F64) => quote!(::libm::tanh(#x)),
        (true, Scalar::F32) => quote!(::libm::tanhf(#x)),
    }
}

/// `body` (an expression of joint forces) plus the friction, when the options include it.
pub fn add_friction(body: TokenStream, options: &Options) -> TokenStream {
    match options.friction {
        None => body,
        Some(_) => quote! {
            let tau = { #body };
            tau + self.friction(qd)
        },
    }
}

/// A batch function's `body` with friction, when the options include it: added to each
/// state's result of `inverse_dynamics_batch`, subtracted from each state's `tau` before
/// `forward_dynamics_batch` (as [`add_friction`] and [`subtract_friction`] do for one state).
pub fn batch_friction(single: &str, body: TokenStream, options: &Options) -> TokenStream {
    match (options.friction, single) {
        (Some(_), "inverse_dynamics") => quote! {
            let mut tau = { #body };
            for (t, v) in tau.iter_mut().zip(qd.iter()) {
                *t += self.friction(v);
            }
            tau
        },
        (Some(_), "forward_dynamics") => quote! {
            let tau = &{
                let mut t = *tau;
                for (x, v) in t.iter_mut().zip(qd.iter()) {
                    *x -= self.friction(v);
                }
                t
            };
            #body
        },
        _ => body,
    }
}

/// `body` (which reads `tau`) with `tau − friction(q̇)` as its `tau`, when the options
/// include friction.
pub fn subtract_friction(body: TokenStream, options: &Options) -> TokenStream {
    match options.friction {
        None => body,
        Some(_) => quote! {
            let tau = &(tau - self.friction(qd));
            #body
        },
    }
}
