//! The logic of the `dynamics-macros` proc-macros, on [`proc_macro2`] tokens so that it is
//! ordinary, unit-testable library code: `robot! { … }` ([`robot`]) and
//! `#[derive(Dynamics)]` ([`derive_dynamics`]). Both end in the one shared core,
//! [`crate::generate_impl`], as the build.rs [`crate::Builder`] does.
//!
//! # `robot!`
//!
//! The robot is written inline with the vocabulary of the TOML robot file
//! ([`dynamics_model::toml_format`]): the same keys, the same conventions, the same meaning.
//! Keys are written `key: value` and separated by commas; a TOML `[[joint]]`,
//! `[joint.link]`, `[[joint.link.body]]` or `[end_effector]` table is a block
//! `joint KIND NAME { … }`, `link NAME { … }`, `body NAME { … }`, `end_effector NAME { … }`
//! (names are identifiers or strings, and may be left out: `joint1`, `link1`, …).
//!
//! ```text
//! dynamics_macros::robot! {
//!     /// The rotational pendulum of Modern Robotics Exercise 8.4.
//!     pub struct Pendulum;           // the struct to define (any visibility, doc comments)
//!     name: "pendulum",              // optional (default: the struct's name)
//!     gravity: [0, 0, -10],          // optional, in {0}, m/s²; default [0, 0, -9.81]
//!     // parameters: { m1: 2.0, L1: 1.0 },  // optional named parameters, as TOML's
//!     //                             // `[parameters]`: a string where a number goes is an
//!     //                             // expression over them (`mass: "m1"`, `xyz: ["L1/2", 0, 0]`)
//!     method: lagrangian,            // optional: how the dynamics are derived, `newton_euler`
//!                                    // (default) or `lagrangian`; the same API either way
//!
//!     // One block per movable joint, root to tip: `revolute` or `prismatic`, then its name.
//!     joint revolute joint1 {
//!         screw: [0, 0, 1, 0, 0, 0], // S_i = (ω, v) in {0} at home, or
//!                                    // axis: [0, 0, 1], point: [0, 0, 0] (prismatic: axis only)
//!         limits: [-PI, PI],         // optional, and velocity_limit, effort_limit, damping,
//!                                    // friction, rotor_inertia, gear_ratio as in TOML
//!         link arm {                 // the link moved by the joint, with its frame {i}
//!             home: { xyz: [1, 0, 0] },   // M_{i−1,i}: { xyz, rpy } or a 4×4 matrix (rows)
//!             mass: 2,
//!             inertia: [4, 4, 4, 0, 0, 0], // [ixx, iyy, izz, ixy, ixz, iyz] about the COM
//!             // or com, inertia_about: origin, a shape: { box: [w, l, h] } with mass or
//!             // density, spatial_inertia: [[…6…]; 6 rows], or `body NAME { frame, … }` blocks
//!         },
//!     },
//!     // The link's keys may also be written in the joint's block (the link is then `link2`).
//!     joint revolute joint2 {
//!         axis: [1, 0, 0], point: [0, 0, 0],
//!         home: { xyz: [0, 0, -1] },
//!         mass: 2,
//!         inertia: [4, 4, 0, 0, 0, 0],
//!     },
//!     end_effector bob { home: { xyz: [0, 0, 0] } },  // optional: M_{n,n+1}, default identity
//!     // Trees: `parent: LINK` in a joint (default: the previous joint's link) and in the end
//!     // effector; `base NAME { floating: true, mass: …, inertia: … }` for a floating base
//!     // (see `inline` for every key). A mimic joint, which follows another (no coordinate
//!     // of its own): `mimic: { joint: LEADER, multiplier: 1, offset: 0 }` in its block.
//! }
//! ```
//!
//! Numbers are integer or float literals, or constant arithmetic over them (`+ - * /`,
//! parentheses) and the named constants of [`number::CONSTANTS`] (`PI`, `TAU`, `FRAC_PI_2`, …).
//! The macro defines `pub struct Pendulum;` (deriving `Clone, Copy, Debug, Default`) and its
//! `impl` with the API of a generated file: `DOF`, `JOINT_NAMES`, `mass_matrix`, `coriolis`,
//! `gravity`, `inverse_dynamics`, `forward_dynamics`.
//!
//! # `#[derive(Dynamics)]`
//!
//! ```text
//! #[derive(Dynamics)]
//! #[dynamics(file = "robots/ur5.urdf")]   // .urdf or .toml, relative to CARGO_MANIFEST_DIR
//! pub struct Ur5;
//! ```
//!
//! Options: `scalar = "f32"`, `no_std`, `no_cpu_dispatch` (no AVX-512 or AVX2 copies chosen
//! at run time; see [`crate::emit::dispatch`]), `sin_cos_variants` (a `*_from_sin_cos`
//! variant of each function that takes the joints' sines and cosines, and `sin_cos(q)`; see
//! [`crate::emit::given_sin_cos`]), `nalgebra = path::to::nalgebra`,
//! `gravity = [gx, gy, gz]`, `floating_base` (a free 6-DoF joint between the world and the
//! base), `runtime = path::to::dynamics_runtime` or `no_runtime_trait`,
//! and for URDF `tip = "LINK"` (the end effector of `end_effector_pose` and the Jacobians),
//! `frames(LINK, ..)` (the named frames of `frame_poses` and the frame Jacobians; default: a
//! tree's leaf links) and `lock(JOINT = VALUE, ..)`; `functions(NAME, ..)` (generate only
//! these), `armature(JOINT = VALUE, ..)` (G²·I_rotor, kg·m²), `friction` (the joints'
//! damping and Coulomb friction in inverse and forward dynamics) and
//! `friction_smoothing = EPS` (the same with `μ tanh(q̇/ε)`), `method = "lagrangian"` (the
//! Euler–Lagrange equations instead of Newton–Euler; the same API); for URDF `snap_angles = TOL`
//! (`rpy` angles within TOL rad of a multiple of π/2 read as exact; at most 1e-2).
//! The expansion holds an `include_bytes!` of the file, so the crate is rebuilt when the
//! file changes. The environment variable [`derive::MANIFEST_DIR_OVERRIDE`] replaces
//! `CARGO_MANIFEST_DIR` when set.
//!
//! # Errors
//!
//! Compile errors on the offending tokens, all at once; on error `robot!` still defines the
//! struct (without its methods), so no "cannot find type" errors follow.

pub mod derive;
pub mod inline;
pub mod number;
pub mod schema;
pub mod spans;
pub mod value;

use crate::options::Options;
use proc_macro2::TokenStream;
use quote::quote;
use value::Errors;

/// Prints the expansion time to stderr when `DYNAMICS_GEN_TIMING` is set.
struct Timer(Option<(std::time::Instant, &'static str)>);

impl Timer {
    fn start(what: &'static str) -> Self {
        Self(std::env::var_os("DYNAMICS_GEN_TIMING").map(|_| (std::time::Instant::now(), what)))
    }
}

impl Drop for Timer {
    fn drop(&mut self) {
        if let Some((t0, what)) = self.0 {
            eprintln!(
                "dynamics-gen: {what} expanded in {:.1} ms",
                t0.elapsed().as_secs_f64() * 1e3
            );
        }
    }
}

/// `robot! { … }`: the struct and its `impl`, or the errors and a stub of the struct.
pub fn robot(input: TokenStream) -> TokenStream {
    let _timer = Timer::start("robot!");
    let parsed = match inline::parse(input) {
        Ok(p) => p,
        Err(e) => return e.into_compile_error(),
    };
    let inline::Head { attrs, vis, ident } = &parsed.head;
    let stub = quote! {
        #(#attrs)*
        #[derive(Clone, Copy, Debug, Default)]
        #vis struct #ident;
    };
    let (robot, generation) = match parsed.robot {
        Ok(r) => r,
        Err(e) => {
            let errors = e.into_compile_error();
            return quote!(#errors #stub);
        }
    };
    let options = Options {
        name: Some(ident.to_string()),
        method: generation.method,
        runtime_parameters: generation.runtime_parameters,
        payload_link: generation.payload_link,
        cpu_dispatch: !generation.no_cpu_dispatch,
        sin_cos_variants: generation.sin_cos_variants,
        ..Options::default()
    };
    match crate::generate_impl(&robot, &options) {
        Ok(g) => {
            // The struct: unit, or with the run-time parameters' fields.
            let (derives, fields, default_impl) =
                crate::emit::struct_parts(&g.robot, ident, options.scalar);
            let stub = quote! {
                #(#attrs)*
                #derives
                #vis struct #ident #fields
                #default_impl
            };
            let impl_block = g.impl_block;
            let has_doc = attrs.iter().any(|a| a.path().is_ident("doc"));
            if has_doc {
                quote!(#stub #impl_block)
            } else {
                let doc = format!(
                    " The dynamics of the robot {} (generated by robot!).",
                    crate::emit::text::inert(&robot.name)
                );
                quote!(#[doc = #doc] #stub #impl_block)
            }
        }
        Err(e) => {
            let errors = syn::Error::new_spanned(ident, e.to_string()).into_compile_error();
            quote!(#errors #stub)
        }
    }
}

/// `#[derive(Dynamics)]`: the `impl` of the robot in the attribute's file, or the errors.
pub fn derive_dynamics(input: TokenStream) -> TokenStream {
    let _timer = Timer::start("#[derive(Dynamics)]");
    let input: syn::DeriveInput = match syn::parse2(input) {
        Ok(i) => i,
        Err(e) => return e.into_compile_error(),
    };
    let mut errors = Errors::default();
    if !input.generics.params.is_empty() {
        errors.at(
            &input.generics,
            "#[derive(Dynamics)] needs a struct without generic parameters (the robot's constants are folded into its methods)",
        );
    }
    let attr = derive::parse_attrs(&input, &mut errors);
    let loaded = match &attr.file {
        Some(lit) if !errors.any() => derive::load(lit, &attr.options.load, &mut errors)
            .map(|(robot, path)| (lit, robot, path)),
        _ => None,
    };
    if let Some(e) = errors.take() {
        return e.into_compile_error();
    }
    let Some((lit, robot, path)) = loaded else {
        return TokenStream::new();
    };
    match crate::generate_impl(&robot, &attr.options) {
        Ok(g) => {
            let impl_block = g.impl_block;
            let path = path.to_string_lossy().into_owned();
            quote! {
                const _: &[u8] = ::core::include_bytes!(#path);
                #impl_block
            }
        }
        Err(e) => syn::Error::new_spanned(lit, e.to_string()).into_compile_error(),
    }
}

#[cfg(test)]
mod tests;
