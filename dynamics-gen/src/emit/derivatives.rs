//! The generated derivatives of the dynamics ([`crate::expand::derivatives`]):
//! `inverse_dynamics_derivatives`, `inverse_dynamics_with_derivatives`,
//! `forward_dynamics_derivatives`, `forward_dynamics_with_derivatives`,
//! `mass_matrix_inverse` and `gravity_derivative`.

use super::function::Output;
use super::{body_tokens, Arg};
use crate::expand::derivatives::Derivatives;
use crate::options::Options;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

/// The six functions (see the module docs), their bodies on the graph of `x`.
pub fn derivative_functions(
    x: &Derivatives,
    nq: usize,
    options: &Options,
    nalgebra: &TokenStream,
    [q, qd, qdd, tau]: [&Arg; 4],
) -> TokenStream {
    let nv_usize = x.nv;
    let nv = proc_macro2::Literal::usize_unsuffixed(nv_usize);
    let nq_lit = proc_macro2::Literal::usize_unsuffixed(nq);
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq_lit>);
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    let mat_ty = quote!(#nalgebra::SMatrix<#scalar, #nv, #nv>);
    let mat_path = quote!(#nalgebra::SMatrix::<#scalar, #nv, #nv>);
    let square = (nv_usize, nv_usize);
    let column = (nv_usize, 1);
    let emit =
        |name: &str, args: &[Arg], parts: &[&[crate::expr::ExprId]], shapes: &[(usize, usize)]| {
            let outputs: Vec<_> = parts.iter().flat_map(|p| p.iter().copied()).collect();
            let output = if shapes.len() == 1 {
                Output::Matrix
            } else {
                let mut all = [(0, 0); 4];
                all[..shapes.len()].copy_from_slice(shapes);
                Output::Tuple {
                    shapes: all,
                    count: shapes.len(),
                    stored_first: false,
                }
            };
            body_tokens(
                name, &x.graph, args, &outputs, shapes[0], output, options, nalgebra,
            )
        };
    let id_args = [q.clone(), qd.clone(), qdd.clone()];
    let fd_args = [q.clone(), qd.clone(), tau.clone()];
    let id_derivatives = emit(
        "inverse_dynamics_derivatives",
        &id_args,
        &[&x.d_tau_dq, &x.d_tau_dqd],
        &[square, square],
    );
    let id_with = emit(
        "inverse_dynamics_with_derivatives",
        &id_args,
        &[&x.inverse_dynamics, &x.d_tau_dq, &x.d_tau_dqd],
        &[column, square, square],
    );
    // `forward_dynamics_derivatives` needs `q̈` as much as `forward_dynamics_with_derivatives`
    // does (`∂q̈/∂q` is taken at it): the two have the same operations. Where both are
    // generated the first calls the second and drops `q̈` (below), so that the body is written
    // and compiled once (the Panda's file 3.1 → 2.8 MB). The call costs the copy of the three
    // matrices: the Panda's 6,955 → 7,151 instructions (+2.8 %, callgrind, its AVX2 copy).
    // Selected alone, or with the `*_from_sin_cos` variants (a variant takes its sines in its
    // own body), the function keeps a body of its own.
    let delegate =
        super::emitted(options, "forward_dynamics_with_derivatives") && !options.sin_cos_variants;
    let fd_derivatives = if delegate {
        quote!()
    } else {
        emit(
            "forward_dynamics_derivatives",
            &fd_args,
            &[&x.d_qdd_dq, &x.d_qdd_dqd, &x.mass_matrix_inverse],
            &[square, square, square],
        )
    };
    let fd_with = emit(
        "forward_dynamics_with_derivatives",
        &fd_args,
        &[
            &x.forward_dynamics,
            &x.d_qdd_dq,
            &x.d_qdd_dqd,
            &x.mass_matrix_inverse,
        ],
        &[column, square, square, square],
    );
    // `M⁻¹` written entry by entry where its literal would keep many values live, as the
    // mass matrix is (see `Output::StoredMatrix`): measured −3 to −10 % (the Panda, rand7,
    // Solo-12, TALOS). `∂g/∂q` stays a literal: stored, rand7's got 8–12 % slower.
    let minv = body_tokens(
        "mass_matrix_inverse",
        &x.graph,
        std::slice::from_ref(q),
        &x.mass_matrix_inverse,
        square,
        Output::StoredMatrix,
        options,
        nalgebra,
    );
    let dg = emit(
        "gravity_derivative",
        std::slice::from_ref(q),
        &[&x.gravity_derivative],
        &[square],
    );
    // With friction in the dynamics: `τ_f(q̇)` is added to inverse dynamics and subtracted
    // from the forces of forward dynamics; its diagonal Jacobian `friction_rate` enters
    // `∂τ/∂q̇` (added) and `∂q̈/∂q̇` (`−M⁻¹ diag(rate)`, column j scaled by `rate_j`).
    let (id_derivatives, id_with, fd_derivatives, fd_with) = match options.friction {
        None => (id_derivatives, id_with, fd_derivatives, fd_with),
        Some(_) => (
            quote! {
                let (d_q, d_qd) = { #id_derivatives };
                (d_q, d_qd + #mat_path::from_diagonal(&self.friction_rate(qd)))
            },
            quote! {
                let (tau, d_q, d_qd) = { #id_with };
                (
                    tau + self.friction(qd),
                    d_q,
                    d_qd + #mat_path::from_diagonal(&self.friction_rate(qd)),
                )
            },
            quote! {
                let tau = &(tau - self.friction(qd));
                let (d_q, mut d_qd, m_inv) = { #fd_derivatives };
                for ((mut c, m), r) in d_qd
                    .column_iter_mut()
                    .zip(m_inv.column_iter())
                    .zip(self.friction_rate(qd).iter())
                {
                    c.axpy(-*r, &m, 1.0);
                }
                (d_q, d_qd, m_inv)
            },
            quote! {
                let tau = &(tau - self.friction(qd));
                let (qdd, d_q, mut d_qd, m_inv) = { #fd_with };
                for ((mut c, m), r) in d_qd
                    .column_iter_mut()
                    .zip(m_inv.column_iter())
                    .zip(self.friction_rate(qd).iter())
                {
                    c.axpy(-*r, &m, 1.0);
                }
                (qdd, d_q, d_qd, m_inv)
            },
        ),
    };
    let fd_derivatives = if delegate {
        quote! {
            let (_, d_q, d_qd, m_inv) = self.forward_dynamics_with_derivatives(q, qd, tau);
            (d_q, d_qd, m_inv)
        }
    } else {
        fd_derivatives
    };
    let tangent_doc = if nq != nv_usize {
        quote! {
            #[doc = ""]
            #[doc = " Floating base: derivatives with respect to `q` are taken in the tangent space, as Pinocchio's are (`nv` columns, not `nq`): column `j` is the derivative along the motion of the configuration at unit velocity `q̇ = e_j`. For the base's six columns that is the body-frame motion `(ω_b, v_b) = e_j` (`ṗ = R v_b`, `quaṫ = ½ quat ⊗ (ω_b, 0)`), i.e. `q ⊕ δ` with `δ` in the base's own frame; for the joints' columns it is the plain partial."]
        }
    } else {
        quote!()
    };
    let layout = " Every matrix is `nv × nv` with entry `(i, j) = ∂f_i/∂x_j`, indices in the order of `JOINT_NAMES` (after the base's six for a floating base). Units follow the functions differentiated (per rad or per m of the coordinate `j`).";
    let m = x.method;
    let form = |analytical: bool| {
        if analytical {
            "the analytical recursion of Carpentier & Mansard (RSS 2018) expanded in joint frames"
        } else {
            "forward-mode differentiation of the expanded dynamics, one sweep per coordinate"
        }
    };
    let id_method = if m.d_tau_dq_analytical == m.d_tau_dqd_analytical {
        format!(
            " Method: both matrices by {}; every constant of the robot folded in.",
            form(m.d_tau_dq_analytical)
        )
    } else {
        format!(
            " Method: `∂τ/∂q` by {}, `∂τ/∂q̇` by {} (each the form with fewer operations); every constant of the robot folded in.",
            form(m.d_tau_dq_analytical),
            form(m.d_tau_dqd_analytical)
        )
    };
    let fd_method = format!(
        "{id_method} Then `∂q̈/∂(q, q̇) = −M⁻¹ ∂τ/∂(q, q̇)` at `q̈ = forward_dynamics(q, q̇, τ)` (implicit function theorem), {}.",
        if m.by_product {
            "as the product with `M⁻¹`, which is returned as well"
        } else {
            "each column solved with the unrolled factorisation `M = Lᵀ D L`"
        }
    );
    let dg_method = format!(
        " Method: {}; every constant of the robot folded in.",
        form(m.gravity_derivative_analytical)
    );
    quote! {
        /// The derivatives of inverse dynamics `τ = ID(q, q̇, q̈)`: `(∂τ/∂q, ∂τ/∂q̇)`;
        /// `∂τ/∂q̈` is `mass_matrix(q)`. What trajectory optimisation and MPC linearise
        /// around each knot.
        #[doc = ""]
        #[doc = #layout]
        #[doc = #id_method]
        #tangent_doc
        #[inline]
        #[must_use]
        pub fn inverse_dynamics_derivatives(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            qdd: &#vec_ty,
        ) -> (#mat_ty, #mat_ty) {
            #id_derivatives
        }

        /// `(τ, ∂τ/∂q, ∂τ/∂q̇)` in one pass: `inverse_dynamics` together with
        /// `inverse_dynamics_derivatives`, sharing the recursion between them.
        #[doc = ""]
        #[doc = #layout]
        #[doc = #id_method]
        #tangent_doc
        #[inline]
        #[must_use]
        pub fn inverse_dynamics_with_derivatives(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            qdd: &#vec_ty,
        ) -> (#vec_ty, #mat_ty, #mat_ty) {
            #id_with
        }

        /// The derivatives of forward dynamics `q̈ = FD(q, q̇, τ)`:
        /// `(∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ)`, the last being `M⁻¹` (symmetric, full). The same
        /// operations as `forward_dynamics_with_derivatives` (`q̈` is needed for the
        /// derivatives), which it calls where both are generated, dropping `q̈`.
        #[doc = ""]
        #[doc = #layout]
        #[doc = #fd_method]
        #tangent_doc
        #[inline]
        #[must_use]
        pub fn forward_dynamics_derivatives(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            tau: &#vec_ty,
        ) -> (#mat_ty, #mat_ty, #mat_ty) {
            #fd_derivatives
        }

        /// `(q̈, ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` in one pass: `forward_dynamics` together with
        /// `forward_dynamics_derivatives` (which computes `q̈` anyway), for a rollout that
        /// needs the next state and its linearisation.
        #[doc = ""]
        #[doc = #layout]
        #[doc = #fd_method]
        #tangent_doc
        #[inline]
        #[must_use]
        pub fn forward_dynamics_with_derivatives(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            tau: &#vec_ty,
        ) -> (#vec_ty, #mat_ty, #mat_ty, #mat_ty) {
            #fd_with
        }

        /// The inverse of the mass matrix, `M(q)⁻¹` (symmetric positive definite, full),
        /// from the unrolled factorisation `M = Lᵀ D L` applied to the unit vectors (lower
        /// triangle computed, upper mirrored). To solve `M x = b` once, `forward_dynamics`'
        /// route is cheaper; this is for when the matrix itself is wanted (operational-space
        /// control, `∂q̈/∂τ`).
        #[inline]
        #[must_use]
        pub fn mass_matrix_inverse(&self, q: &#q_ty) -> #mat_ty {
            #minv
        }

        /// `∂g/∂q`, the derivative of the gravity forces `gravity(q)`: the stiffness that
        /// gravity compensation adds to a joint-space controller.
        #[doc = ""]
        #[doc = #layout]
        #[doc = #dg_method]
        #tangent_doc
        #[inline]
        #[must_use]
        pub fn gravity_derivative(&self, q: &#q_ty) -> #mat_ty {
            #dg
        }
    }
}
