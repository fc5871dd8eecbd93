//! The generated inertial-parameter regressor ([`crate::expand::regressor`]): `regressor`,
//! `inertial_parameters`, `base_regressor`, `base_parameters` and the parameters' names.

use super::function::Output;
use super::text::inert;
use super::{body_tokens, Arg};
use crate::expand::regressor::{Regressor, PI};
use crate::options::Options;
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

/// A coefficient for the docs: its shortest exact decimal.
fn number(x: f64) -> String {
    format!("{x}")
}

/// The regrouping of every base parameter, one doc line each.
fn regrouping_doc(r: &Regressor) -> Vec<String> {
    r.base_columns
        .iter()
        .zip(&r.regrouped)
        .enumerate()
        .map(|(k, (&j, terms))| {
            let mut line = format!(" - `{k}`: {}", inert(&r.parameter_name(j)));
            for &(d, beta) in terms {
                let sign = if beta < 0.0 { '−' } else { '+' };
                line.push_str(&format!(
                    " {sign} {} · {}",
                    number(beta.abs()),
                    inert(&r.parameter_name(d))
                ));
            }
            line
        })
        .collect()
}

/// The four functions and two constants (see the module docs).
pub fn regressor_functions(
    r: &Regressor,
    options: &Options,
    nalgebra: &TokenStream,
    [q, qd, qdd]: [&Arg; 3],
) -> TokenStream {
    let (nv_usize, p_usize, b_usize) = (r.nv, r.n_parameters(), r.base_columns.len());
    let nv = Literal::usize_unsuffixed(nv_usize);
    let nq = Literal::usize_unsuffixed(r.nq);
    let p = Literal::usize_unsuffixed(p_usize);
    let b = Literal::usize_unsuffixed(b_usize);
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq>);
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    let emit =
        |name: &str, args: &[Arg], outputs: &[crate::expr::ExprId], shape: (usize, usize)| {
            body_tokens(
                name,
                &r.graph,
                args,
                outputs,
                shape,
                Output::Matrix,
                options,
                nalgebra,
            )
        };
    let state = [q.clone(), qd.clone(), qdd.clone()];
    let y = emit("regressor", &state, &r.y, (nv_usize, p_usize));
    let yb = emit("base_regressor", &state, &r.base_y(), (nv_usize, b_usize));
    let pi_values = emit("inertial_parameters", &[], &r.parameter_nodes, (p_usize, 1));
    let pi = Arg {
        name: "pi",
        group: PI,
        len: p_usize,
    };
    let base_map = emit(
        "base_parameters",
        std::slice::from_ref(&pi),
        &r.base_map,
        (b_usize, 1),
    );
    let names: Vec<String> = (0..p_usize).map(|j| r.parameter_name(j)).collect();
    let base_names: Vec<String> = r
        .base_columns
        .iter()
        .map(|&j| r.parameter_name(j))
        .collect();
    let bodies = r
        .bodies
        .iter()
        .map(|b| inert(b))
        .collect::<Vec<_>>()
        .join(", ");
    let base_first = if r.nq != r.nv {
        " (the floating base first)"
    } else {
        ""
    };
    let layout = format!(
        " Columns: ten per body, the bodies in the order {bodies}{base_first}, each `(m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)` in the body's own frame (a URDF link's frame; {{i}} of the Modern Robotics lists), `I` about that frame's origin (`I = I_c − m [c]²`), in kg, kg·m and kg·m²: the order and frames of Pinocchio's `computeJointTorqueRegressor` and `Inertia::toDynamicParameters`. `PARAMETER_NAMES` names them."
    );
    let excluded = " Not in `Y`: the rotors' armature (`τ = Y π + diag(a) q̈`, `a` the joints' `G² I_rotor`) and friction. Method: Newton–Euler of the robot with one unit parameter (the recursion is linear in the inertias, so column `j` is `∂τ/∂π_j` exactly), the kinematics shared by every column, the robot's constants folded in; on both derivation methods.";
    let zero: Vec<String> = r
        .unidentifiable
        .iter()
        .map(|&j| inert(&r.parameter_name(j)))
        .collect();
    let zero_doc = if zero.is_empty() {
        " Every standard parameter moves τ.".to_string()
    } else {
        format!(
            " The {} standard parameters with no effect on τ (their columns are zero): {}.",
            zero.len(),
            zero.join(", ")
        )
    };
    let regrouping = regrouping_doc(r);
    let base_doc = format!(
        " Found numerically at generation time: `Y` at seeded random states, Gram–Schmidt with column pivoting (a column is dependent when its residual is below {:e} of its norm), the regrouping coefficients by least squares (Gautier 1991). {b_usize} base parameters of {p_usize}.",
        crate::expand::regressor::RANK_TOLERANCE
    );
    quote! {
        /// The number of standard inertial parameters: ten per moving body.
        pub const N_PARAMETERS: usize = #p;
        /// The number of base (identifiable) parameters: the rank of the regressor.
        pub const N_BASE_PARAMETERS: usize = #b;
        /// The standard inertial parameters' names, `body.parameter`, in the order of the
        /// columns of `regressor` and of `inertial_parameters`.
        pub const PARAMETER_NAMES: [&'static str; #p] = [#(#names),*];
        /// The base parameters' names: the standard parameter each one extends (see
        /// `base_parameters` for what is regrouped into it).
        pub const BASE_PARAMETER_NAMES: [&'static str; #b] = [#(#base_names),*];

        /// The inertial-parameter regressor `Y(q, q̇, q̈)`: `τ = Y π` for the standard
        /// parameters `π` (`inertial_parameters` gives the robot's own), what parameter
        /// identification and adaptive control need.
        #[doc = ""]
        #[doc = #layout]
        #[doc = ""]
        #[doc = #excluded]
        #[doc = #zero_doc]
        #[inline]
        #[must_use]
        pub fn regressor(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            qdd: &#vec_ty,
        ) -> #nalgebra::SMatrix<#scalar, #nv, #p> {
            #y
        }

        /// The robot's own standard inertial parameters `π` (from its description), in the
        /// order of `PARAMETER_NAMES`: `regressor(q, q̇, q̈) · inertial_parameters()` is
        /// `inverse_dynamics(q, q̇, q̈)` without armature and friction.
        #[inline]
        #[must_use]
        pub fn inertial_parameters(&self) -> #nalgebra::SVector<#scalar, #p> {
            #pi_values
        }

        /// The base regressor `Y_b(q, q̇, q̈)`: the columns of `regressor` named by
        /// `BASE_PARAMETER_NAMES`, of full column rank, with `τ = Y_b base_parameters(π)`
        /// for every `π`.
        #[doc = ""]
        #[doc = #base_doc]
        #[inline]
        #[must_use]
        pub fn base_regressor(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            qdd: &#vec_ty,
        ) -> #nalgebra::SMatrix<#scalar, #nv, #b> {
            #yb
        }

        /// The base parameters of the standard parameters `pi`: each a standard parameter
        /// with the ones that cannot be told apart from it regrouped into it, so that
        /// `base_regressor(q, q̇, q̈) · base_parameters(π) = regressor(q, q̇, q̈) · π`.
        #[doc = ""]
        #[doc = " The regrouping (`BASE_PARAMETER_NAMES[k]` = …):"]
        #[doc = ""]
        #(#[doc = #regrouping])*
        #[inline]
        #[must_use]
        pub fn base_parameters(
            &self,
            pi: &#nalgebra::SVector<#scalar, #p>,
        ) -> #nalgebra::SVector<#scalar, #b> {
            #base_map
        }
    }
}
