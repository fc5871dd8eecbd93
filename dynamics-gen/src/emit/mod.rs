//! Emission: the expanded dynamics as Rust tokens, formatted with prettyplease.
//!
//! [`generate_impl`] is the one core shared by every front end (build.rs Builder, CLI,
//! `robot!` and `#[derive(Dynamics)]`): it turns a validated robot into the `impl` block of
//! the generated API. [`generate_file`] adds the struct, the `@generated` header and the
//! formatting.

pub mod batch;
pub mod derivatives;
pub mod dispatch;
pub mod friction;
pub mod function;
pub mod given_sin_cos;
pub mod literal;
pub mod pack;
pub mod park;
pub mod provenance;
pub mod regressor;
pub mod schedule;
pub mod text;
pub mod trig;
pub mod zmm;

use crate::error::Error;
use crate::expand::kinematics::{expand_kinematics_with, Kinematics};
use crate::expand::task_space::{expand_task_space, TaskSpace, F_TIP};
use crate::expand::{self, Dynamics, ForwardRoute, Q, QD, QDD, TAU};
use crate::options::{upper_camel, Options, Scalar};
use dynamics_model::Robot;
use function::{Arg, FunctionBody, Output, Packs};
use proc_macro2::{Ident, Span, TokenStream};
pub use provenance::Provenance;
use quote::{quote, ToTokens};
use text::inert;

/// The version of the generator, written into every generated header.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The result of a generation: the tokens and the expanded dynamics behind them.
pub struct Generated {
    /// The struct's name.
    pub struct_name: String,
    /// `impl Name { … }`.
    pub impl_block: TokenStream,
    /// `#[derive(..)] pub struct Name;` with its documentation.
    pub struct_item: TokenStream,
    /// The expansion (for statistics).
    pub dynamics: Dynamics,
    /// The kinematics of the end effector and the named frames (for statistics).
    pub kinematics: Kinematics,
    /// The tip-wrench and task-space functions (for statistics).
    pub task_space: TaskSpace,
    /// The derivatives (for statistics), when a derivative function is generated.
    pub derivatives: Option<expand::derivatives::Derivatives>,
    /// The regressor (for statistics), when a regressor function is generated.
    pub regressor: Option<expand::regressor::Regressor>,
    /// The friction model, when friction is in the dynamics ([`Options::friction`]).
    pub friction: Option<crate::options::Friction>,
    /// The robot as generated: validated, with the gravity override applied.
    pub robot: Robot,
}

/// The robot as the generator sees it: with the gravity override applied, and passing
/// [`crate::check_robot`].
pub fn prepare(robot: &Robot, options: &Options) -> Result<Robot, Error> {
    let mut robot = robot.clone();
    if let Some(g) = options.load.gravity {
        robot.gravity = g;
    }
    crate::check::check_robot(&robot)?;
    robot.runtime = runtime_parameters(&robot, options)?;
    if let Some(crate::options::Friction::Smooth(eps)) = options.friction {
        if !(eps.is_finite() && eps > 0.0) {
            return Err(Error::InvalidFrictionSmoothing { eps });
        }
    }
    Ok(robot)
}

/// The run-time parameters `options` ask of `robot`: gravity, and a payload on the named
/// link or on the end effector's.
fn runtime_parameters(
    robot: &Robot,
    options: &Options,
) -> Result<dynamics_model::RuntimeParameters, Error> {
    let error = |problem: String, fix: &str| Error::InvalidRuntimeParameters {
        robot: robot.name.clone(),
        problem,
        fix: fix.into(),
    };
    if !options.runtime_parameters {
        return match &options.payload_link {
            None => Ok(dynamics_model::RuntimeParameters::default()),
            Some(link) => Err(error(
                format!(
                    "a payload link ({}) is named, but run-time parameters are off",
                    text::inert(link)
                ),
                "turn run-time parameters on, or drop the payload link",
            )),
        };
    }
    let payload = match &options.payload_link {
        Some(name) => match robot.links.iter().position(|l| l.name == *name) {
            Some(i) => i,
            None if robot.base.name == *name => {
                return Err(error(
                    format!(
                        "the payload link {} is the base, which no joint moves",
                        text::inert(name)
                    ),
                    "name a link that a joint moves",
                ))
            }
            None => {
                let names: Vec<String> = robot.links.iter().map(|l| text::inert(&l.name)).collect();
                return Err(error(
                    format!("the robot has no moving link called {}", text::inert(name)),
                    &format!("name one of its links: {}", names.join(", ")),
                ));
            }
        },
        None => robot.end_effector.parent.ok_or_else(|| {
            error(
                "the end effector is on the base, so no link carries a payload by default".into(),
                "name the payload link",
            )
        })?,
    };
    Ok(dynamics_model::RuntimeParameters {
        gravity: true,
        payload: Some(payload),
    })
}

/// Expands `robot` and emits its `impl` block and struct item.
pub fn generate_impl(robot: &Robot, options: &Options) -> Result<Generated, Error> {
    let robot = prepare(robot, options)?;
    let struct_name = options
        .name
        .clone()
        .unwrap_or_else(|| upper_camel(&robot.name));
    let ident = syn::parse_str::<Ident>(&struct_name).map_err(|_| Error::InvalidName {
        name: struct_name.clone(),
        hint: "not a Rust identifier; give a name like `Ur5`".into(),
    })?;
    // From here on `options.name` is the struct's name: the pieces of a split function body
    // call the impl's helpers through it (see `function::chunked`).
    // A selected batch function brings its single-state function: the per-state form of
    // the batch (no runtime crate, or a body too large to unroll `B` wide) calls it.
    let functions = options.functions.as_ref().map(|selected| {
        let mut all = selected.clone();
        for f in selected {
            if let Some(single) = f.strip_suffix("_batch") {
                if !all.iter().any(|s| s == single) {
                    all.push(single.to_string());
                }
            }
        }
        all
    });
    let options = &Options {
        name: Some(struct_name.clone()),
        functions,
        ..options.clone()
    };
    let nalgebra = path_tokens(&options.nalgebra_path)?;
    let runtime = options
        .runtime_path
        .as_deref()
        .map(path_tokens)
        .transpose()?;
    let dynamics = expand::expand_method(&robot, options.method);
    let (n_usize, nq_usize, nv_usize) = (dynamics.dof, dynamics.nq, dynamics.nv);
    let n = proc_macro2::Literal::usize_unsuffixed(n_usize);
    let nq = proc_macro2::Literal::usize_unsuffixed(nq_usize);
    let nv = proc_macro2::Literal::usize_unsuffixed(nv_usize);
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq>);
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    let mat_ty = quote!(#nalgebra::SMatrix<#scalar, #nv, #nv>);
    let body =
        |name: &str, outputs: &[crate::expr::ExprId], args: &[Arg], cols: usize, output: Output| {
            body_tokens(
                name,
                &dynamics.graph,
                args,
                outputs,
                (nv_usize, cols),
                output,
                options,
                &nalgebra,
            )
        };
    let q = Arg {
        name: "q",
        group: Q,
        len: nq_usize,
    };
    let qd = Arg {
        name: "qd",
        group: QD,
        len: nv_usize,
    };
    let qdd = Arg {
        name: "qdd",
        group: QDD,
        len: nv_usize,
    };
    let tau = Arg {
        name: "tau",
        group: TAU,
        len: nv_usize,
    };
    let mass_matrix = body(
        "mass_matrix",
        &dynamics.mass_matrix,
        std::slice::from_ref(&q),
        nv_usize,
        Output::StoredMatrix,
    );
    let mass_matrix_lower = body(
        "mass_matrix_lower_into",
        &dynamics.mass_matrix,
        std::slice::from_ref(&q),
        nv_usize,
        Output::StoredLower,
    );
    // The bias written entry by entry where its literal would keep many values live, as the
    // mass matrix is (see `Output::StoredMatrix`): measured (2026-12-04, old and new code in
    // one binary, interleaved, five processes) G1 (floating base) −6 to −15 %, TALOS −9 to
    // +2 %, Solo-12 −8 to +10 %. Not the inverse or forward dynamics: the same treatment made
    // G1's and TALOS' inverse dynamics 3–5 % slower (the AVX-512 copy's spill stores 489 → 597
    // for G1, while its coriolis' fell 455 → 343) and moved the forward dynamics by −1 to +5 %.
    let coriolis = body(
        "coriolis",
        &dynamics.coriolis,
        &[q.clone(), qd.clone()],
        1,
        Output::StoredMatrix,
    );
    let gravity = body(
        "gravity",
        &dynamics.gravity,
        std::slice::from_ref(&q),
        1,
        Output::Matrix,
    );
    let inverse = body(
        "inverse_dynamics",
        &dynamics.inverse_dynamics,
        &[q.clone(), qd.clone(), qdd.clone()],
        1,
        Output::Matrix,
    );
    let forward = body(
        "forward_dynamics",
        &dynamics.forward_dynamics,
        &[q.clone(), qd.clone(), tau.clone()],
        1,
        Output::Matrix,
    );
    let kinetic = body_tokens(
        "kinetic_energy",
        &dynamics.graph,
        &[q.clone(), qd.clone()],
        &[dynamics.kinetic_energy],
        (1, 1),
        Output::Scalar,
        options,
        &nalgebra,
    );
    // `Ṁ` written entry by entry where its literal would keep many values live, as `M` is
    // (see `Output::StoredMatrix`): the trees −5 to −18 %, the 7-joint arms ±1 %.
    let mass_matrix_dot = body(
        "mass_matrix_dot",
        &dynamics.mass_matrix_dot,
        &[q.clone(), qd.clone()],
        nv_usize,
        Output::StoredMatrix,
    );
    let inverse = friction::add_friction(inverse, options);
    let forward = friction::subtract_friction(forward, options);
    let friction_fn = friction::friction_function(&robot, options, &nalgebra);
    let friction_fn = {
        let rate = friction::friction_rate_function(&robot, options, &nalgebra);
        quote!(#friction_fn #rate)
    };
    // The variants take the joints' sines and cosines from the caller: no run's sums.
    let kinematics = expand_kinematics_with(&robot, !options.sin_cos_variants);
    let task_space = expand_task_space(&dynamics, &kinematics);
    let extras = dynamics_extras(
        &dynamics,
        &task_space,
        options,
        &nalgebra,
        [&q, &qd, &qdd, &tau],
    );
    let wanted = |f: &str| {
        options
            .functions
            .as_ref()
            .is_none_or(|s| s.iter().any(|x| x == f))
    };
    let derivatives = DERIVATIVE_FUNCTIONS
        .iter()
        .any(|f| wanted(f))
        .then(|| expand::derivatives::expand_derivatives(&dynamics, &robot));
    let derivative_fns = match &derivatives {
        Some(x) => derivatives::derivative_functions(
            x,
            nq_usize,
            options,
            &nalgebra,
            [&q, &qd, &qdd, &tau],
        ),
        None => quote!(),
    };
    // The batch functions: vectorised in the runtime crate's `Lanes`, or per state.
    let batch_fns = {
        {
            let id_args = [q.clone(), qd.clone(), qdd.clone()];
            let fd_args = [q.clone(), qd.clone(), tau.clone()];
            let fns = [
                batch::Batched {
                    name: "inverse_dynamics_batch",
                    single: "inverse_dynamics",
                    args: &id_args,
                    outputs: &dynamics.inverse_dynamics,
                    cols: 1,
                    doc: " Inverse dynamics for a batch of states: `τ[l] = inverse_dynamics(q[l], q̇[l], q̈[l])` for each of the `B` states (MPC, sampling-based planning, learning).",
                },
                batch::Batched {
                    name: "forward_dynamics_batch",
                    single: "forward_dynamics",
                    args: &fd_args,
                    outputs: &dynamics.forward_dynamics,
                    cols: 1,
                    doc: " Forward dynamics for a batch of states: `q̈[l] = forward_dynamics(q[l], q̇[l], τ[l])` for each of the `B` states (rollouts of many trajectories at once).",
                },
                batch::Batched {
                    name: "mass_matrix_batch",
                    single: "mass_matrix",
                    args: std::slice::from_ref(&q),
                    outputs: &dynamics.mass_matrix,
                    cols: nv_usize,
                    doc: " The mass matrix for a batch of configurations: `M[l] = mass_matrix(q[l])` for each of the `B` configurations.",
                },
                batch::Batched {
                    name: "gravity_batch",
                    single: "gravity",
                    args: std::slice::from_ref(&q),
                    outputs: &dynamics.gravity,
                    cols: 1,
                    doc: " The gravity forces for a batch of configurations: `g[l] = gravity(q[l])` for each of the `B` configurations.",
                },
            ];
            batch::batch_functions(
                &dynamics.graph,
                &fns,
                nv_usize,
                options,
                &nalgebra,
                runtime.as_ref(),
                |name| emitted(options, name),
                &|single, body| friction::batch_friction(single, body, options),
            )
        }
    };
    let regressor = REGRESSOR_FUNCTIONS
        .iter()
        .any(|f| wanted(f))
        .then(|| expand::regressor::expand_regressor(&robot));
    let regressor_fns = match &regressor {
        Some(r) => regressor::regressor_functions(r, options, &nalgebra, [&q, &qd, &qdd]),
        None => quote!(),
    };
    let kinematics_fns = kinematics_functions(&kinematics, &robot, options, &nalgebra, &[q, qd]);
    let names: Vec<&str> = robot.joint_names();
    let units = unit_doc(&robot);
    let gravity_doc = if robot.runtime.gravity {
        " Gravity: the field `gravity` (m/s², in the base frame {0}), read at run time.".to_string()
    } else {
        format!(
            " Gravity: ({}, {}, {}) m/s² in the base frame {{0}}, folded into the code.",
            robot.gravity[0], robot.gravity[1], robot.gravity[2]
        )
    };
    let lagrangian = dynamics.method == expand::Method::Lagrangian;
    let forward_doc = match dynamics.forward_route {
        _ if lagrangian => " Method: the mass matrix and the bias `c + g` from the Lagrangian (see `mass_matrix`), then an unrolled LDLᵀ factorisation of `M` (no pivoting, no explicit inverse; one division per coordinate).",
        ForwardRoute::Ldlt if robot.has_mimic() => " Method: the mass matrix `M = Jᵀ M_joints J` of the independent coordinates by the composite-rigid-body algorithm, the bias `c + g` by Newton–Euler, then an unrolled LDLᵀ factorisation of `M` (no pivoting, no explicit inverse; one division per coordinate). The articulated-body algorithm does not apply: it assumes one coordinate per joint, and mimic joints share theirs.",
        ForwardRoute::Ldlt => " Method: the mass matrix by the composite-rigid-body algorithm, the bias `c + g` by Newton–Euler, then an unrolled LDLᵀ factorisation of `M` (no pivoting, no explicit inverse; one division per joint). Chosen over the articulated-body algorithm because it needs fewer operations for this robot.",
        ForwardRoute::Aba => " Method: Featherstone's articulated-body algorithm, unrolled (one division per joint). Chosen over CRBA + LDLᵀ because it needs fewer operations for this robot.",
    };
    let friction_doc = if options.friction.is_some() {
        quote! {
            #[doc = ""]
            #[doc = " Friction included (generated with friction): `τ_f = friction(q̇)` is added to the joint forces, `τ = M q̈ + c + g + τ_f`."]
        }
    } else {
        quote!()
    };
    let armature: Vec<String> = robot
        .joints
        .iter()
        .filter(|j| j.armature() != 0.0)
        .map(|j| format!("{} {}", inert(&j.name), j.armature()))
        .collect();
    let armature_doc = if armature.is_empty() {
        quote!()
    } else {
        let text = format!(
            " The joints' armature `G² I_rotor` (Modern Robotics §8.9.2) is on the diagonal of `M` and in every function built on it: {}.",
            armature.join(", ")
        );
        quote! {
            #[doc = ""]
            #[doc = #text]
        }
    };
    let [mass_doc, coriolis_doc, gravity_doc_method, inverse_doc] = if lagrangian {
        [
            " Method: the Lagrangian route (Modern Robotics §8.1). `M = ∂²K/∂q̇²` of the kinetic energy `K = ½ Σ_i V_iᵀ G_i V_i` (`V_i` the body twist of link i), by symbolic differentiation; the robot's constants folded in.",
            " Method: the Lagrangian route, `c = Ṁ q̇ − ∂K/∂q`, which is the Christoffel form `c_i = Σ_jk Γ_ijk q̇_j q̇_k` of `M` contracted with `q̇` (on a floating base, plus the Euler–Poincaré term `−[ad_ν_b]ᵀ ∂K/∂ν_b` of the base's body twist).",
            " Method: the Lagrangian route, `g = ∂P/∂q` of the potential energy `P = −Σ_i m_i gᵀ p_i`.",
            " Method: the Lagrangian route, `τ = M q̈ + c + g` assembled from the Euler–Lagrange equations of `L = K − P` (see `mass_matrix`, `coriolis`, `gravity`).",
        ]
    } else {
        [
            " Method: the composite-rigid-body algorithm.",
            " Method: recursive Newton–Euler with `q̈ = 0` and no gravity.",
            " Method: recursive Newton–Euler with `q̇ = q̈ = 0`.",
            " Method: recursive Newton–Euler.",
        ]
    };
    let limits = limit_consts(&robot, options.scalar, n_usize);
    let gravity_const = if robot.runtime.gravity {
        let g = robot
            .gravity
            .iter()
            .map(|&x| literal::float_tokens(x, options.scalar));
        quote! {
            /// The robot file's gravity vector in {0} (m/s²): the default of the run-time
            /// field `gravity`.
            pub const DEFAULT_GRAVITY: [#scalar; 3] = [#(#g),*];
        }
    } else {
        quote!()
    };
    let allow = allow_attrs();
    let mul_add_fn = if options.no_std {
        quote!()
    } else {
        function::mul_add_helper(options.scalar)
    };
    // Only revolute joints (mimic ones included) bring sines and cosines.
    let sin_cos_fn = if robot
        .joints
        .iter()
        .any(|j| j.kind == dynamics_model::JointKind::Revolute)
    {
        trig::sin_cos_helper(options.scalar, options.no_std)
    } else {
        quote!()
    };
    let items = quote! {
        /// The number of joints n (the floating base not counted; mimic joints, which
        /// follow another joint, not counted either).
        pub const DOF: usize = #n;
        /// The length of the configuration `q`: n, or n + 7 with a floating base.
        pub const NQ: usize = #nq;
        /// The length of the velocity `qd`, the acceleration `qdd` and the forces `tau`: n,
        /// or n + 6 with a floating base.
        pub const NV: usize = #nv;
        /// The joint names, in the order of every vector and matrix index.
        pub const JOINT_NAMES: [&'static str; #n] = [#(#names),*];
        #limits
        #gravity_const

        /// The joint-space mass matrix `M(q)` (symmetric positive definite; kg·m², kg·m or kg
        /// by joint types).
        #[doc = ""]
        #[doc = #mass_doc]
        #[doc = ""]
        #[doc = #units]
        #armature_doc
        #[inline]
        #[must_use]
        pub fn mass_matrix(&self, q: &#q_ty) -> #mat_ty {
            #mass_matrix
        }

        /// `M(q)`, as [`Self::mass_matrix`] computes it (the same bits), written in place: its
        /// lower triangle (the diagonal and below) into `m`, and nothing else. The entries
        /// above the diagonal and the entries that are zero whatever `q` (a tree's joints on
        /// different branches) are not written: start from a zero matrix and pass it at every
        /// call, and `m` holds `M(q)`'s lower triangle with zeros above it, which is what
        /// nalgebra's `Cholesky::new` reads (`m.fill_upper_triangle_with_lower_triangle()`
        /// gives the whole `M`). Without the zeroing and the mirror half that a fresh
        /// symmetric matrix needs, a tree's mass matrix takes a third to a half less time.
        #[doc = ""]
        #[doc = #mass_doc]
        #[doc = ""]
        #[doc = #units]
        #armature_doc
        #[inline]
        pub fn mass_matrix_lower_into(&self, q: &#q_ty, m: &mut #mat_ty) {
            #mass_matrix_lower
        }

        /// The Coriolis and centrifugal terms `c(q, q̇)` of `τ = M(q) q̈ + c(q, q̇) + g(q)`.
        /// Quadratic in `qd`.
        #[doc = ""]
        #[doc = #coriolis_doc]
        #[doc = ""]
        #[doc = #units]
        #[inline]
        #[must_use]
        pub fn coriolis(&self, q: &#q_ty, qd: &#vec_ty) -> #vec_ty {
            #coriolis
        }

        /// The gravity terms `g(q)` of `τ = M(q) q̈ + c(q, q̇) + g(q)`: the joint forces that
        /// hold the robot still.
        #[doc = ""]
        #[doc = #gravity_doc_method]
        #[doc = ""]
        #[doc = #gravity_doc]
        #[doc = #units]
        #[inline]
        #[must_use]
        pub fn gravity(&self, q: &#q_ty) -> #vec_ty {
            #gravity
        }

        /// Inverse dynamics `τ = M(q) q̈ + c(q, q̇) + g(q)`: the joint forces (N·m for
        /// revolute, N for prismatic joints) that produce `qdd`.
        #[doc = ""]
        #[doc = #inverse_doc]
        #[doc = ""]
        #[doc = #gravity_doc]
        #[doc = #units]
        #friction_doc
        #[inline]
        #[must_use]
        pub fn inverse_dynamics(&self, q: &#q_ty, qd: &#vec_ty, qdd: &#vec_ty) -> #vec_ty {
            #inverse
        }

        /// Forward dynamics `q̈ = M(q)⁻¹ (τ − c(q, q̇) − g(q))`.
        #[doc = ""]
        #[doc = #forward_doc]
        #[doc = ""]
        #[doc = #gravity_doc]
        #[doc = #units]
        #friction_doc
        #[inline]
        #[must_use]
        pub fn forward_dynamics(&self, q: &#q_ty, qd: &#vec_ty, tau: &#vec_ty) -> #vec_ty {
            #forward
        }

        /// The kinetic energy `K = ½ q̇ᵀ M(q) q̇` (J); on a floating base `q̇ = ν`, the
        /// base's own motion included.
        #[inline]
        #[must_use]
        pub fn kinetic_energy(&self, q: &#q_ty, qd: &#vec_ty) -> #scalar {
            #kinetic
        }

        /// The time derivative `Ṁ(q, q̇) = Σ_k ∂M/∂q_k q̇_k` of the mass matrix (Modern
        /// Robotics Exercise 8.7): the exact symbolic derivative of `mass_matrix`, so that
        /// `Ṁ − 2C` is skew-symmetric for the Christoffel `C`.
        #[doc = ""]
        #[doc = #units]
        #[inline]
        #[must_use]
        pub fn mass_matrix_dot(&self, q: &#q_ty, qd: &#vec_ty) -> #mat_ty {
            #mass_matrix_dot
        }

        #friction_fn

        #extras

        #derivative_fns

        #batch_fns

        #regressor_fns

        #kinematics_fns

        #mul_add_fn
    };
    // The vector helpers where a function calls them (`pack`: the poses' rows, alike
    // outputs), found in the functions themselves.
    let vector_fns =
        function::vector_helpers(options.scalar, |h| dispatch::contains_ident(&items, h));
    let impl_block = quote! {
        #allow
        #[rustfmt::skip]
        impl #ident {
            #items
            #vector_fns

            #sin_cos_fn
        }
    };
    let impl_block = select_functions(impl_block, &robot, options)?;
    let impl_block = if options.sin_cos_variants {
        given_sin_cos::apply(impl_block, &q_ty, nq_usize, &nalgebra)
    } else {
        impl_block
    };
    let impl_block = if options.no_std || !options.cpu_dispatch {
        impl_block
    } else {
        dispatch::apply(impl_block, options.scalar)
    };
    let impl_block = batch::out_of_line(impl_block);
    let written = function::written_union(&ident);
    let impl_block = if dispatch::contains_ident(&impl_block, &written.to_string()) {
        let item = function::written_union_item(&written);
        quote!(#impl_block #item)
    } else {
        impl_block
    };
    let impl_block = match &runtime {
        None => impl_block,
        Some(runtime) => {
            let trait_impl = runtime_impl(&ident, runtime, &nalgebra, &scalar, (&nq, &nv));
            quote!(#impl_block #trait_impl)
        }
    };
    let struct_doc = struct_doc(&robot, options);
    let (derives, fields, default_impl) = struct_parts(&robot, &ident, options.scalar);
    let struct_item = quote! {
        #(#[doc = #struct_doc])*
        #allow
        #[rustfmt::skip]
        #derives
        pub struct #ident #fields
        #default_impl
    };
    Ok(Generated {
        struct_name,
        impl_block,
        struct_item,
        dynamics,
        kinematics,
        task_space,
        derivatives,
        regressor,
        friction: options.friction,
        robot,
    })
}

/// The generated struct's derives, its fields (`;` for a unit struct) and its `Default` impl
/// (derived for a unit struct): with run-time parameters
/// ([`crate::expand::parameters::FIELDS`]), one public field each, whose default is the
/// robot's value.
pub fn struct_parts(
    robot: &Robot,
    ident: &Ident,
    scalar: Scalar,
) -> (TokenStream, TokenStream, TokenStream) {
    let fields = expand::parameters::fields(robot);
    if fields.is_empty() {
        return (
            quote!(#[derive(Clone, Copy, Debug, Default)]),
            quote!(;),
            quote! {
                impl #ident {
                    /// The robot (as `Default::default()`, for `const` and `static` items; with
                    /// run-time parameters it holds their defaults).
                    pub const DEFAULT: Self = Self;
                }
            },
        );
    }
    let defaults = expand::parameters::defaults(robot);
    let ty = Ident::new(scalar.as_str(), Span::call_site());
    let mut decls = Vec::new();
    let mut inits = Vec::new();
    for f in &fields {
        let name = Ident::new(f.name, Span::call_site());
        let values: Vec<TokenStream> = (0..f.len)
            .map(|k| literal::float_tokens(defaults[f.first as usize + k], scalar))
            .collect();
        let (field_ty, value) = if f.len == 1 {
            (quote!(#ty), quote!(#(#values)*))
        } else {
            let len = proc_macro2::Literal::usize_unsuffixed(f.len);
            (quote!([#ty; #len]), quote!([#(#values),*]))
        };
        let doc = format!(" {} Read by every function that depends on it.", f.doc);
        let default_doc = format!(" Default: {}.", default_text(f, &defaults, robot));
        decls.push(quote! {
            #[doc = #doc]
            #[doc = ""]
            #[doc = #default_doc]
            pub #name: #field_ty
        });
        inits.push(quote!(#name: #value));
    }
    (
        quote!(#[derive(Clone, Copy, Debug, PartialEq)]),
        quote!({ #(#decls),* }),
        quote! {
            impl #ident {
                /// The robot's own values: the robot file's gravity, no payload (as
                /// `Default::default()`, for `const` and `static` items).
                pub const DEFAULT: Self = Self { #(#inits),* };
            }
            impl ::core::default::Default for #ident {
                /// [`Self::DEFAULT`]: the robot file's gravity, no payload.
                fn default() -> Self {
                    Self::DEFAULT
                }
            }
        },
    )
}

/// The default of a run-time parameter field, for its documentation.
fn default_text(f: &expand::parameters::Field, defaults: &[f64; 13], robot: &Robot) -> String {
    let values: Vec<String> = (0..f.len)
        .map(|k| format!("{}", defaults[f.first as usize + k]))
        .collect();
    let link = robot
        .runtime
        .payload
        .map(|i| inert(&robot.links[i].name))
        .unwrap_or_default();
    match f.name {
        "gravity" => format!("({}), the robot's", values.join(", ")),
        "payload_mass" => format!("0: no payload (the payload is carried by link {link})"),
        _ => format!("[{}]", values.join(", ")),
    }
}

/// The body of a generated function: `outputs` of `graph` as `output`, `(rows, cols)` its
/// matrix shape, in the scalar type and trigonometry of `options`; its outputs of one shape
/// (the same joint of a quadruped's four legs, alike entries of a task-space matrix) computed
/// together as packs ([`Packs::Alike`]; measured in `docs/performance.md`: Solo-12's functions
/// 4–58 % faster, rand7's `Λ` 8 %, no function slower).
fn body_tokens(
    name: &str,
    graph: &crate::expr::ExprGraph,
    args: &[Arg],
    outputs: &[crate::expr::ExprId],
    shape: (usize, usize),
    output: Output,
    options: &Options,
    nalgebra: &TokenStream,
) -> TokenStream {
    body_tokens_with(
        name,
        graph,
        args,
        outputs,
        shape,
        output,
        options,
        nalgebra,
        (function::ALIKE_PACKS, &[]),
    )
}

/// [`body_tokens`] with the packs `pack` ([`Packs::Rows`]: the kinematics' poses;
/// [`Packs::Columns`]: its Jacobians, and with the entries of the Jacobian a body reads, its
/// `J̇`s: [`FunctionBody::reads_jacobian`]).
fn body_tokens_with(
    name: &str,
    graph: &crate::expr::ExprGraph,
    args: &[Arg],
    outputs: &[crate::expr::ExprId],
    (rows, cols): (usize, usize),
    output: Output,
    options: &Options,
    nalgebra: &TokenStream,
    (pack, reads_jacobian): (Packs, &[crate::expr::ExprId]),
) -> TokenStream {
    if !emitted(options, name) {
        return quote!();
    }
    // `generate_impl` sets the name (see there); it is a valid identifier.
    let self_ty = options
        .name
        .as_deref()
        .and_then(|n| syn::parse_str::<Ident>(n).ok());
    let written = self_ty.as_ref().map(function::written_union);
    FunctionBody {
        graph,
        args,
        outputs,
        rows,
        cols,
        output,
        scalar: options.scalar,
        no_std: options.no_std,
        nalgebra,
        self_ty: self_ty.as_ref(),
        lanes: None,
        ready: &[],
        pack,
        park: options.cpu_dispatch && !options.no_std && park::PARKED.contains(&name),
        order: if schedule::LEVEL_ORDER.contains(&name) {
            schedule::Order::Level
        } else {
            schedule::Order::Demand
        },
        written: written
            .as_ref()
            .filter(|_| options.cpu_dispatch && !options.no_std),
        plan: None,
        reads_jacobian,
    }
    .tokens()
}

/// Input groups of the solve `M⁻¹ b` written into `constrained_forward_dynamics` (once per
/// constraint row): the packed factor `L` and `1/D`.
const FACTOR_L: u8 = 5;
const FACTOR_INV_D: u8 = 6;

/// `coriolis_matrix`, `mass_matrix_and_bias`, the tip-wrench functions, the task-space
/// functions, and `constrained_forward_dynamics` with its private helpers
/// (`mass_matrix_factor`, `solve_constraint`).
fn dynamics_extras(
    d: &Dynamics,
    t: &TaskSpace,
    options: &Options,
    nalgebra: &TokenStream,
    [q, qd, qdd, tau]: [&Arg; 4],
) -> TokenStream {
    let nv_usize = d.nv;
    let nv = proc_macro2::Literal::usize_unsuffixed(nv_usize);
    let nq = proc_macro2::Literal::usize_unsuffixed(d.nq);
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq>);
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    let mat_ty = quote!(#nalgebra::SMatrix<#scalar, #nv, #nv>);
    let six_ty = quote!(#nalgebra::SVector<#scalar, 6>);
    let lambda_ty = quote!(#nalgebra::SMatrix<#scalar, 6, 6>);
    let f_tip = Arg {
        name: "f_tip",
        group: F_TIP,
        len: 6,
    };
    let emit = |name: &str,
                graph: &crate::expr::ExprGraph,
                args: &[Arg],
                outputs: &[crate::expr::ExprId],
                (rows, cols): (usize, usize),
                output: Output| {
        body_tokens(
            name,
            graph,
            args,
            outputs,
            (rows, cols),
            output,
            options,
            nalgebra,
        )
    };
    let (q, qd, qdd, tau) = (q.clone(), qd.clone(), qdd.clone(), tau.clone());
    let coriolis_matrix = emit(
        "coriolis_matrix",
        &d.graph,
        &[q.clone(), qd.clone()],
        &d.coriolis_matrix,
        (nv_usize, nv_usize),
        Output::Matrix,
    );
    // `M` written entry by entry into the returned pair where the literal would keep many
    // values live (the trees: TALOS −10 %, G1 −5 %; see `STORED_MIN_LIVE`), `c + g` after it.
    let both: Vec<_> = d.mass_matrix.iter().chain(&d.bias).copied().collect();
    let mass_and_bias = emit(
        "mass_matrix_and_bias",
        &d.graph,
        &[q.clone(), qd.clone()],
        &both,
        (0, 0),
        Output::Tuple {
            shapes: [(nv_usize, nv_usize), (nv_usize, 1), (0, 0), (0, 0)],
            count: 2,
            stored_first: true,
        },
    );
    let tip_forces = emit(
        "end_effector_forces",
        &t.graph,
        &[q.clone(), f_tip.clone()],
        &t.end_effector_forces,
        (nv_usize, 1),
        Output::Matrix,
    );
    let id_tip = friction::add_friction(
        emit(
            "inverse_dynamics_with_tip",
            &t.graph,
            &[q.clone(), qd.clone(), qdd.clone(), f_tip.clone()],
            &t.inverse_dynamics_with_tip,
            (nv_usize, 1),
            Output::Matrix,
        ),
        options,
    );
    let fd_tip = friction::subtract_friction(
        emit(
            "forward_dynamics_with_tip",
            &t.graph,
            &[q.clone(), qd.clone(), tau.clone(), f_tip.clone()],
            &t.forward_dynamics_with_tip,
            (nv_usize, 1),
            Output::Matrix,
        ),
        options,
    );
    let guards: Vec<_> = t.pivots.iter().flat_map(|&(a, b)| [a, b]).collect();
    let checked = |name: &str, value: &[crate::expr::ExprId], args: &[Arg], cols: usize| {
        if value.is_empty() {
            let names = args.iter().map(|a| Ident::new(a.name, Span::call_site()));
            return quote! {
                let _ = (#(#names),*);
                None
            };
        }
        let outputs: Vec<_> = guards.iter().chain(value).copied().collect();
        emit(
            name,
            &t.graph,
            args,
            &outputs,
            (6, cols),
            Output::Checked {
                guards: t.pivots.len(),
            },
        )
    };
    let lambda = checked(
        "task_space_mass_matrix",
        &t.mass_matrix,
        std::slice::from_ref(&q),
        6,
    );
    let eta = checked("task_space_bias", &t.bias, &[q.clone(), qd.clone()], 1);
    let tol = function::sqrt_epsilon(options.scalar);
    let singular_doc = format!(
        " `None` when `A = J_b M⁻¹ J_bᵀ` is singular or nearly so: some pivot `D_k` of its factorisation `L D Lᵀ` (no pivoting, rows `ω₁ ω₂ ω₃ v₁ v₂ v₃`) is not greater than `√ε · A_kk` (√ε = {:e} for `{}`), e.g. at a kinematic singularity, and always for fewer than six velocity coordinates. Never NaN, never a panic.",
        match options.scalar {
            Scalar::F64 => f64::EPSILON.sqrt(),
            Scalar::F32 => f64::from(f32::EPSILON.sqrt()),
        },
        options.scalar.as_str()
    );

    // M = Lᵀ D L, packed: the strictly lower entries of L that are not structural zeros.
    let packed: Vec<(usize, usize)> = (0..nv_usize)
        .flat_map(|i| (0..i).map(move |j| (i, j)))
        .filter(|&(i, j)| !d.graph.is_zero(d.mass_matrix_factor[i * nv_usize + j]))
        .collect();
    let nl_usize = packed.len();
    let nl = proc_macro2::Literal::usize_unsuffixed(nl_usize);
    let l_ty = quote!(#nalgebra::SVector<#scalar, #nl>);
    let factor_outputs: Vec<_> = packed
        .iter()
        .map(|&(i, j)| d.mass_matrix_factor[i * nv_usize + j])
        .chain(d.mass_matrix_inv_d.iter().copied())
        .chain(d.unconstrained.iter().copied())
        .collect();
    let factor = emit(
        "mass_matrix_factor",
        &d.graph,
        &[q.clone(), qd.clone(), tau.clone()],
        &factor_outputs,
        (0, 0),
        Output::Tuple {
            shapes: [(nl_usize, 1), (nv_usize, 1), (nv_usize, 1), (0, 0)],
            count: 3,
            stored_first: false,
        },
    );
    let mut sg = crate::expr::ExprGraph::new();
    let zero = sg.zero();
    let mut h = vec![zero; nv_usize * nv_usize];
    for (p, &(i, j)) in packed.iter().enumerate() {
        h[i * nv_usize + j] = sg.input(expand::input(FACTOR_L, p));
    }
    let inv_d: Vec<_> = (0..nv_usize)
        .map(|i| sg.input(expand::input(FACTOR_INV_D, i)))
        .collect();
    let b: Vec<_> = (0..nv_usize)
        .map(|i| sg.input(expand::input(TAU, i)))
        .collect();
    let x = crate::expand::ldlt::ltdl_apply(&mut sg, &h, &inv_d, &b);
    // Written into `constrained_forward_dynamics`' body (once per constraint row).
    let solve = emit(
        "constrained_forward_dynamics",
        &sg,
        &[
            Arg {
                name: "l",
                group: FACTOR_L,
                len: nl_usize,
            },
            Arg {
                name: "inv_d",
                group: FACTOR_INV_D,
                len: nv_usize,
            },
            Arg {
                name: "b",
                group: TAU,
                len: nv_usize,
            },
        ],
        &x,
        (nv_usize, 1),
        Output::Matrix,
    );
    let tol_doc = format!(
        " `None` when `A M⁻¹ Aᵀ` is singular or nearly so: a pivot `D_k` of its factorisation `L D Lᵀ` is not greater than `√ε` times its diagonal entry (√ε of `{}`), e.g. for dependent constraint rows. Never NaN, never a panic.",
        options.scalar.as_str()
    );
    let constrained_friction = match options.friction {
        Some(_) => quote!(let tau = &(tau - self.friction(qd));),
        None => quote!(),
    };
    quote! {
        /// The Coriolis matrix `C(q, q̇)` with `C_ij = Σ_k Γ_ijk q̇_k`, `Γ_ijk` the Christoffel
        /// symbols of the first kind of `M` (Modern Robotics §8.1.2): `C q̇ = coriolis(q, q̇)`
        /// and `Ṁ − 2C` is skew-symmetric. On a floating base the base block adds the
        /// Euler–Poincaré term `−[ad_{ν_b}]ᵀ` of the base's body twist, as a skew-symmetric
        /// block that keeps both properties.
        #[inline]
        #[must_use]
        pub fn coriolis_matrix(&self, q: &#q_ty, qd: &#vec_ty) -> #mat_ty {
            #coriolis_matrix
        }

        /// `(M(q), h(q, q̇))` with `h = c + g`, in one pass: what a controller needs each
        /// tick (`τ = M q̈ + h`), sharing the trigonometry and every common subexpression
        /// between the two.
        #[inline]
        #[must_use]
        pub fn mass_matrix_and_bias(&self, q: &#q_ty, qd: &#vec_ty) -> (#mat_ty, #vec_ty) {
            #mass_and_bias
        }

        /// `J_b(q)ᵀ F_tip`: the joint forces that make the end effector apply the wrench
        /// `f_tip = (m, f)` (N·m, N) to the environment, expressed in the end-effector frame
        /// (Modern Robotics §5.2, `EndEffectorForces`); zero for joints off its path.
        #[inline]
        #[must_use]
        pub fn end_effector_forces(&self, q: &#q_ty, f_tip: &#six_ty) -> #vec_ty {
            #tip_forces
        }

        /// Inverse dynamics with a tip wrench, `τ = M q̈ + c + g + J_bᵀ F_tip` (Modern Robotics
        /// eq. 8.1 with §8.3.3): `f_tip = (m, f)` is the wrench the end effector applies to
        /// the environment, in the end-effector frame.
        #[inline]
        #[must_use]
        pub fn inverse_dynamics_with_tip(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            qdd: &#vec_ty,
            f_tip: &#six_ty,
        ) -> #vec_ty {
            #id_tip
        }

        /// Forward dynamics with a tip wrench, `q̈ = M⁻¹ (τ − c − g − J_bᵀ F_tip)`, by the
        /// unrolled factorisation `M = Lᵀ D L` (no explicit inverse); `f_tip` as in
        /// [`Self::inverse_dynamics_with_tip`].
        #[inline]
        #[must_use]
        pub fn forward_dynamics_with_tip(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            tau: &#vec_ty,
            f_tip: &#six_ty,
        ) -> #vec_ty {
            #fd_tip
        }

        /// The task-space mass matrix `Λ(q) = (J_b M⁻¹ J_bᵀ)⁻¹` of the end-effector frame
        /// (Modern Robotics §8.6), so that the end effector's wrench is `F = Λ V̇ + η` with
        /// `V̇ = J_b q̈ + J̇_b q̇` its body acceleration; for redundant arms this is the
        /// dynamically consistent generalisation of `J_b⁻ᵀ M J_b⁻¹`. By factorisations: `M⁻¹
        /// J_bᵀ` by `M = Lᵀ D L`, `Λ` from `A = J_b M⁻¹ J_bᵀ = L D Lᵀ`.
        #[doc = ""]
        #[doc = #singular_doc]
        #[inline]
        #[must_use]
        pub fn task_space_mass_matrix(&self, q: &#q_ty) -> Option<#lambda_ty> {
            #lambda
        }

        /// The task-space bias `η(q, q̇) = Λ (J_b M⁻¹ h − J̇_b q̇)` (`h = c + g`) of
        /// `F = Λ V̇ + η` (Modern Robotics §8.6, eq. 8.90 generalised to redundant arms), in the
        /// end-effector frame; gravity included.
        #[doc = ""]
        #[doc = #singular_doc]
        #[inline]
        #[must_use]
        pub fn task_space_bias(&self, q: &#q_ty, qd: &#vec_ty) -> Option<#six_ty> {
            #eta
        }

        /// Forward dynamics under `K` linear velocity constraints `A(q) q̇ = 0` (Modern
        /// Robotics §8.7, Exercise 8.10): `(q̈, λ)` with `M q̈ + h = τ + Aᵀ λ` and
        /// `A q̈ + Ȧ q̇ = 0`, where `a` is `A(q)` and `a_dot_qd` is `Ȧ q̇`; `λ` are the
        /// constraint forces' multipliers (`Aᵀ λ` the joint forces the constraints apply).
        /// By the Schur complement: `q̈₀ = M⁻¹(τ − h)`, `Y = M⁻¹ Aᵀ` (the unrolled
        /// `M = Lᵀ D L`, `q̈₀` in the factor's body), `(A Y) λ = −(A q̈₀ + Ȧ q̇)`,
        /// `q̈ = q̈₀ + Y λ`. `K` is the caller's, so the `K`-sized part runs in loops (no
        /// allocation), each column of `Y` by the unrolled substitutions.
        #[doc = ""]
        #[doc = #tol_doc]
        #[inline]
        #[must_use]
        pub fn constrained_forward_dynamics<const K: usize>(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            tau: &#vec_ty,
            a: &#nalgebra::SMatrix<#scalar, K, #nv>,
            a_dot_qd: &#nalgebra::SVector<#scalar, K>,
        ) -> Option<(#vec_ty, #nalgebra::SVector<#scalar, K>)> {
            #constrained_friction
            let (l, inv_d, free) = self.mass_matrix_factor(q, qd, tau);
            let mut y = #nalgebra::SMatrix::<#scalar, #nv, K>::zeros();
            for (mut column, row) in y.column_iter_mut().zip(a.row_iter()) {
                // `M⁻¹ b` from the factors: `Lᵀ y = b`, `z = D⁻¹ y`, `L x = z`.
                let (l, inv_d, b) = (&l, &inv_d, &row.transpose());
                column.copy_from(&{ #solve });
            }
            let s = a * y;
            let r = -(a * free + a_dot_qd);
            let lambda = Self::solve_constraint(s, r)?;
            Some((free + y * lambda, lambda))
        }

        /// `(L, 1/D, q̈₀)`: the factorisation `M = Lᵀ D L` (the entries of the unit lower
        /// triangular `L` that are not structural zeros, row by row) and the unconstrained
        /// accelerations `q̈₀ = M⁻¹ (τ − h)` (`h = c + g`) by it, in the same body.
        #[inline]
        fn mass_matrix_factor(
            &self,
            q: &#q_ty,
            qd: &#vec_ty,
            tau: &#vec_ty,
        ) -> (#l_ty, #vec_ty, #vec_ty) {
            #factor
        }

        /// `S⁻¹ r` for the symmetric `S` by `S = L D Lᵀ` (in place, no pivoting); `None` when
        /// a pivot is not greater than `√ε` times its diagonal entry.
        #[inline]
        fn solve_constraint<const K: usize>(
            mut s: #nalgebra::SMatrix<#scalar, K, K>,
            mut r: #nalgebra::SVector<#scalar, K>,
        ) -> Option<#nalgebra::SVector<#scalar, K>> {
            for j in 0..K {
                let mut d = s[(j, j)];
                for k in 0..j {
                    d -= s[(j, k)] * s[(j, k)] * s[(k, k)];
                }
                if !(d > #tol * s[(j, j)]) {
                    return None;
                }
                s[(j, j)] = d;
                for i in j + 1..K {
                    let mut x = s[(i, j)];
                    for k in 0..j {
                        x -= s[(i, k)] * s[(j, k)] * s[(k, k)];
                    }
                    s[(i, j)] = x / d;
                }
            }
            for i in 0..K {
                for k in 0..i {
                    let t = s[(i, k)] * r[k];
                    r[i] -= t;
                }
            }
            for i in 0..K {
                r[i] /= s[(i, i)];
            }
            for i in (0..K).rev() {
                for k in i + 1..K {
                    let t = s[(k, i)] * r[k];
                    r[i] -= t;
                }
            }
            Some(r)
        }
    }
}

/// The impl block with only the functions of `options.functions` (all when `None`), after
/// checking the selection: known names, frame functions only with named frames, and the
/// five functions of the runtime trait when it is implemented.
fn select_functions(
    impl_block: TokenStream,
    robot: &Robot,
    options: &Options,
) -> Result<TokenStream, Error> {
    // Without a selection every function stays, and with them every helper they call: no
    // parse (it costs seconds on a large tree).
    let Some(selected) = &options.functions else {
        return Ok(impl_block);
    };
    let mut item: syn::ItemImpl = syn::parse2(impl_block)
        .map_err(|e| Error::Internal(format!("generated impl does not parse: {e}")))?;
    retain_selected(&mut item, selected, robot, options)?;
    finish_helpers(&mut item);
    Ok(quote!(#item))
}

/// Checks the selection and keeps only the selected functions and the helpers they call.
fn retain_selected(
    item: &mut syn::ItemImpl,
    selected: &[String],
    robot: &Robot,
    options: &Options,
) -> Result<(), Error> {
    let known = crate::options::FUNCTIONS;
    let list = || known.join(", ");
    for name in selected {
        if !known.contains(&name.as_str()) {
            return Err(Error::InvalidFunctions {
                problem: format!("there is no generated function {}", inert(name)),
                fix: format!("choose among {}", list()),
            });
        }
        if name.starts_with("frame_") && robot.frames.is_empty() {
            return Err(Error::InvalidFunctions {
                problem: format!("`{name}` needs named frames, and the robot has none"),
                fix: "name the frames (--frame LINK, .frames(..), frames(..), TOML [[frame]]) or leave it out".into(),
            });
        }
    }
    if options.runtime_path.is_some() {
        let missing: Vec<&str> = known[..5]
            .iter()
            .copied()
            .filter(|f| !selected.iter().any(|s| s == f))
            .collect();
        if !missing.is_empty() {
            return Err(Error::InvalidFunctions {
                problem: format!(
                    "the dynamics_runtime::Dynamics impl needs {}, which the selection leaves out",
                    missing.join(", ")
                ),
                fix: "add them, or leave the trait out (--no-runtime-trait, .no_runtime_trait(), no_runtime_trait)".into(),
            });
        }
    }
    let wanted = |name: &str| selected.iter().any(|s| s == name);
    item.items.retain(|it| match it {
        syn::ImplItem::Fn(f) => {
            let name = f.sig.ident.to_string();
            match HELPERS.iter().find(|(helper, _)| *helper == name) {
                // A private helper stays while a selected function calls it.
                // (The named frames' own functions, always generated with the frames, need
                // `isometry` too.)
                Some((helper, users)) => {
                    users.iter().any(|u| wanted(u))
                        || (*helper == "isometry" && !robot.frames.is_empty())
                }
                None => !known.contains(&name.as_str()) || wanted(&name),
            }
        }
        _ => true,
    });
    Ok(())
}

/// Removes `mul_add`, `joint_sin_cos` (with `sin_cos_n`, `sin_cos_into` and `sin_cos_poly`) and
/// `sin_cos_lanes` where no function calls them.
fn finish_helpers(item: &mut syn::ItemImpl) {
    // `mul_add` and `joint_sin_cos` stay while a function calls them.
    let bodies: Vec<(String, String)> = item
        .items
        .iter()
        .filter_map(|it| match it {
            syn::ImplItem::Fn(f) => Some((
                f.sig.ident.to_string(),
                f.block.to_token_stream().to_string(),
            )),
            _ => None,
        })
        .collect();
    let called = |helper: &str| {
        bodies
            .iter()
            .any(|(name, body)| name != helper && body.contains(helper))
    };
    let mut keep = vec![
        ("mul_add", called("mul_add")),
        ("joint_sin_cos", called("joint_sin_cos")),
        ("sin_cos_n", called("joint_sin_cos")),
        ("sin_cos_into", called("joint_sin_cos")),
        ("sin_cos_poly", called("joint_sin_cos")),
        ("sin_cos_lanes", called("sin_cos_lanes")),
    ];
    keep.extend(function::VECTOR_HELPERS.iter().map(|&h| (h, called(h))));
    item.items.retain(|it| match it {
        syn::ImplItem::Fn(f) => keep
            .iter()
            .all(|(helper, kept)| f.sig.ident != helper || *kept),
        _ => true,
    });
}

/// Whether the body of the function `name` is written: always without a selection; with
/// one, when `name` is selected, is a private helper of a selected function, or is not
/// selectable (a named frame's own functions, `""`). The others get an empty body:
/// `select_functions` removes them whole, and writing them first would cost most of the
/// generation time of a large robot (five functions of a 60-joint chain: 17 s before, 2 s after).
fn emitted(options: &Options, name: &str) -> bool {
    let Some(selected) = &options.functions else {
        return true;
    };
    let wanted = |f: &str| selected.iter().any(|s| s == f);
    let known = crate::options::FUNCTIONS.contains(&name);
    match HELPERS.iter().find(|(helper, _)| *helper == name) {
        Some((_, users)) => users.iter().any(|u| wanted(u)),
        None => {
            debug_assert!(known || name.is_empty(), "unknown function {name}");
            !known || wanted(name)
        }
    }
}

/// The private helpers of the generated impl and the functions that call them.
const HELPERS: &[(&str, &[&str])] = &[
    ("friction_rate", DERIVATIVE_FUNCTIONS),
    ("isometry", &["end_effector_pose", "frame_poses"]),
    ("mass_matrix_factor", &["constrained_forward_dynamics"]),
    ("solve_constraint", &["constrained_forward_dynamics"]),
];

/// The functions of [`regressor`].
const REGRESSOR_FUNCTIONS: &[&str] = &[
    "regressor",
    "inertial_parameters",
    "base_regressor",
    "base_parameters",
];

/// The functions of [`derivatives`].
const DERIVATIVE_FUNCTIONS: &[&str] = &[
    "inverse_dynamics_derivatives",
    "inverse_dynamics_with_derivatives",
    "forward_dynamics_derivatives",
    "forward_dynamics_with_derivatives",
    "mass_matrix_inverse",
    "gravity_derivative",
];

/// `end_effector_pose`, `jacobian_space`, `jacobian_body`, and for named frames
/// `FRAME_NAMES`, `frame_poses`, `frame_jacobians_space`, `frame_jacobians_body`; the
/// private `isometry` helper they share.
fn kinematics_functions(
    k: &Kinematics,
    robot: &Robot,
    options: &Options,
    nalgebra: &TokenStream,
    args: &[Arg; 2],
) -> TokenStream {
    let q = &args[0];
    let nv_usize = robot.nv();
    let nv = proc_macro2::Literal::usize_unsuffixed(nv_usize);
    let nq = proc_macro2::Literal::usize_unsuffixed(robot.nq());
    let scalar = Ident::new(options.scalar.as_str(), Span::call_site());
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq>);
    let iso_ty = quote!(#nalgebra::Isometry3<#scalar>);
    let jac_ty = quote!(#nalgebra::SMatrix<#scalar, 6, #nv>);
    let body =
        |name: &str, outputs: &[crate::expr::ExprId], rows: usize, cols: usize, output: Output| {
            let q = std::slice::from_ref(q);
            // The Jacobians (6 rows) by their columns' rows, the poses by theirs.
            let pack = if rows == 6 {
                Packs::Columns
            } else {
                Packs::Rows
            };
            body_tokens_with(
                name,
                &k.graph,
                q,
                outputs,
                (rows, cols),
                output,
                options,
                nalgebra,
                (pack, &[]),
            )
        };
    let ee = &k.end_effector;
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    // A `J̇` by the packs of the `J` it reads, on arms ([`function::JACOBIAN_DOT_PACK_COLUMNS`]).
    let dot = |name: &str, outputs: &[crate::expr::ExprId], j: &[crate::expr::ExprId]| {
        let shape = (6, nv_usize);
        let packs = if nv_usize <= function::JACOBIAN_DOT_PACK_COLUMNS {
            (Packs::Columns, j)
        } else {
            (Packs::None, &[][..])
        };
        body_tokens_with(
            name,
            &k.graph,
            args,
            outputs,
            shape,
            Output::Matrix,
            options,
            nalgebra,
            packs,
        )
    };
    let j_s_dot = dot(
        "jacobian_space_dot",
        &k.jacobian_space_dot,
        &ee.jacobian_space,
    );
    let j_b_dot = dot("jacobian_body_dot", &k.jacobian_body_dot, &ee.jacobian_body);
    let pose = body("end_effector_pose", &ee.pose, 0, 0, Output::Pose);
    let j_s = body(
        "jacobian_space",
        &ee.jacobian_space,
        6,
        nv_usize,
        Output::Matrix,
    );
    let j_b = body(
        "jacobian_body",
        &ee.jacobian_body,
        6,
        nv_usize,
        Output::Matrix,
    );
    let helper = function::isometry_helper(options.scalar, options.no_std, nalgebra);
    let ee_doc = format!(
        " The end-effector frame is {}{}.",
        inert(&robot.end_effector.name),
        match robot.end_effector.parent {
            Some(p) => format!(" on link {}", inert(&robot.links[p].name)),
            None => format!(" on the base {}", inert(&robot.base.name)),
        }
    );
    let base_doc = if robot.base.floating {
        quote! {
            #[doc = ""]
            #[doc = " With the floating base, `q` includes the base pose and the first six columns map the base's body twist `(ω_b, v_b)` (`qd`'s first six entries)."]
        }
    } else {
        quote!()
    };
    let p_body = body(
        "potential_energy",
        &[k.potential_energy],
        0,
        0,
        Output::Scalar,
    );
    let mut out = quote! {
        #helper

        /// The potential energy `P(q) = −Σ_i m_i gᵀ p_i` (J) in the gravity field of the
        /// struct's docs, with `p_i` link i's centre of mass in {0} (height measured from the
        /// origin of {0}), so that `∂P/∂q = g(q)`; a floating base's own mass included.
        #[inline]
        #[must_use]
        pub fn potential_energy(&self, q: &#q_ty) -> #scalar {
            #p_body
        }

        /// Forward kinematics `T_{0,n+1}(q)` (Modern Robotics §4.1, `FKinSpace`): the pose of
        /// the end-effector frame in {0} (m).
        #[doc = ""]
        #[doc = #ee_doc]
        #[inline]
        #[must_use]
        pub fn end_effector_pose(&self, q: &#q_ty) -> #iso_ty {
            #pose
        }

        /// The space Jacobian `J_s(q)` of the end-effector frame (Modern Robotics §5.1.1): rows
        /// `(ω, v)` in {0}, the twist `V_s = J_s q̇`; zero columns for joints not on the path
        /// to the end effector.
        #[doc = ""]
        #[doc = #ee_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn jacobian_space(&self, q: &#q_ty) -> #jac_ty {
            #j_s
        }

        /// The body Jacobian `J_b(q) = [Ad_{T⁻¹}] J_s(q)` of the end-effector frame (Modern
        /// Robotics §5.1.3): rows `(ω, v)` in the end-effector frame, the twist `V_b = J_b q̇`.
        #[doc = ""]
        #[doc = #ee_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn jacobian_body(&self, q: &#q_ty) -> #jac_ty {
            #j_b
        }

        /// The time derivative `J̇_s(q, q̇)` of [`Self::jacobian_space`]: the exact symbolic
        /// derivative along `q̇` (Modern Robotics Exercise 8.6), so that the end effector's
        /// spatial acceleration is `J_s q̈ + J̇_s q̇`.
        #[doc = ""]
        #[doc = #ee_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn jacobian_space_dot(&self, q: &#q_ty, qd: &#vec_ty) -> #jac_ty {
            #j_s_dot
        }

        /// The time derivative `J̇_b(q, q̇)` of [`Self::jacobian_body`] (Modern Robotics
        /// Exercise 8.6): `V̇_b = J_b q̈ + J̇_b q̇`.
        #[doc = ""]
        #[doc = #ee_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn jacobian_body_dot(&self, q: &#q_ty, qd: &#vec_ty) -> #jac_ty {
            #j_b_dot
        }
    };
    let nf_usize = robot.frames.len();
    if nf_usize == 0 {
        return out;
    }
    let nf = proc_macro2::Literal::usize_unsuffixed(nf_usize);
    let names: Vec<&str> = robot.frames.iter().map(|f| f.name.as_str()).collect();
    let list: Vec<String> = robot
        .frames
        .iter()
        .map(|f| {
            let on = match f.parent {
                Some(p) => inert(&robot.links[p].name),
                None => format!("the base {}", inert(&robot.base.name)),
            };
            format!("{} (on {on})", inert(&f.name))
        })
        .collect();
    let frames_doc = format!(" Frames, in order: {}.", list.join(", "));
    let cat = |f: fn(&crate::expand::kinematics::FrameKinematics) -> &Vec<crate::expr::ExprId>| {
        k.frames
            .iter()
            .flat_map(|x| f(x).iter().copied())
            .collect::<Vec<_>>()
    };
    let poses = body(
        "frame_poses",
        &cat(|x| &x.pose),
        0,
        0,
        Output::Poses(nf_usize),
    );
    let js = body(
        "frame_jacobians_space",
        &cat(|x| &x.jacobian_space),
        6,
        nv_usize,
        Output::Matrices(nf_usize),
    );
    let jb = body(
        "frame_jacobians_body",
        &cat(|x| &x.jacobian_body),
        6,
        nv_usize,
        Output::Matrices(nf_usize),
    );
    out.extend(quote! {
        /// The named frames (feet, hands, sensors), in the order of the `frame_*` functions'
        /// arrays.
        pub const FRAME_NAMES: [&'static str; #nf] = [#(#names),*];

        /// The pose in {0} of every named frame (`FRAME_NAMES` order), computed together
        /// (shared subexpressions).
        #[doc = ""]
        #[doc = #frames_doc]
        #[inline]
        #[must_use]
        pub fn frame_poses(&self, q: &#q_ty) -> [#iso_ty; #nf] {
            #poses
        }

        /// The space Jacobian of every named frame (`FRAME_NAMES` order): rows `(ω, v)` in
        /// {0}, the frame's twist `V_s = J_s q̇`; zero columns for joints not on its path.
        #[doc = ""]
        #[doc = #frames_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn frame_jacobians_space(&self, q: &#q_ty) -> [#jac_ty; #nf] {
            #js
        }

        /// The body Jacobian of every named frame (`FRAME_NAMES` order): rows `(ω, v)` in
        /// the frame itself, its twist `V_b = J_b q̇`. The frame's linear velocity in {0} is
        /// `R v` with `R` the rotation of its pose.
        #[doc = ""]
        #[doc = #frames_doc]
        #base_doc
        #[inline]
        #[must_use]
        pub fn frame_jacobians_body(&self, q: &#q_ty) -> [#jac_ty; #nf] {
            #jb
        }
    });
    // Each frame's own three functions, named after it.
    let taken: Vec<&str> = crate::options::FUNCTIONS
        .iter()
        .copied()
        .chain(HELPERS.iter().map(|(h, _)| *h))
        .collect();
    let stems = text::method_stems(&names, &taken);
    for ((frame, fk), stem) in robot.frames.iter().zip(&k.frames).zip(&stems) {
        let pose_fn = Ident::new(&format!("{stem}_pose"), Span::call_site());
        let js_fn = Ident::new(&format!("{stem}_jacobian_space"), Span::call_site());
        let jb_fn = Ident::new(&format!("{stem}_jacobian_body"), Span::call_site());
        let on = match frame.parent {
            Some(p) => inert(&robot.links[p].name),
            None => format!("the base {}", inert(&robot.base.name)),
        };
        let doc = format!(" Frame {} (on {on}).", inert(&frame.name));
        // A named frame's own functions are always written (not selectable).
        let pose = body("", &fk.pose, 0, 0, Output::Pose);
        let js = body("", &fk.jacobian_space, 6, nv_usize, Output::Matrix);
        let jb = body("", &fk.jacobian_body, 6, nv_usize, Output::Matrix);
        out.extend(quote! {
            /// The pose of this named frame in {0} (m): its entry of `frame_poses`, alone.
            #[doc = ""]
            #[doc = #doc]
            #[inline]
            #[must_use]
            pub fn #pose_fn(&self, q: &#q_ty) -> #iso_ty {
                #pose
            }

            /// The space Jacobian of this named frame: rows `(ω, v)` in {0}.
            #[doc = ""]
            #[doc = #doc]
            #base_doc
            #[inline]
            #[must_use]
            pub fn #js_fn(&self, q: &#q_ty) -> #jac_ty {
                #js
            }

            /// The body Jacobian of this named frame: rows `(ω, v)` in the frame itself.
            #[doc = ""]
            #[doc = #doc]
            #base_doc
            #[inline]
            #[must_use]
            pub fn #jb_fn(&self, q: &#q_ty) -> #jac_ty {
                #jb
            }
        });
    }
    out
}

/// The whole generated file: `@generated` header (how it was made: generator version,
/// source, input hash, every option, the command that regenerates it), struct, impl,
/// formatted with prettyplease. `provenance` names the source; a plain `&str` is taken as
/// the source's name.
pub fn generate_file(
    robot: &Robot,
    options: &Options,
    provenance: impl Into<Provenance>,
) -> Result<String, Error> {
    let provenance = provenance.into();
    let generated = generate_impl(robot, options)?;
    let header = provenance.header(&generated, options);
    let Generated {
        struct_item,
        impl_block,
        ..
    } = generated;
    let file: syn::File = syn::parse2(quote!(#struct_item #impl_block))
        .map_err(|e| Error::Internal(format!("generated code does not parse: {e}")))?;
    let body = prettyplease::unparse(&file);
    Ok(format!("{header}\n{body}"))
}

/// A crate path option (`::nalgebra`, `crate::rt`) as tokens, or the error naming it.
fn path_tokens(path: &str) -> Result<TokenStream, Error> {
    syn::parse_str::<syn::Path>(path)
        .map(|p| quote!(#p))
        .map_err(|_| Error::InvalidPath { path: path.into() })
}

/// `impl Dynamics<T, NQ, NV> for Name`, forwarding to the inherent functions and constants.
fn runtime_impl(
    ident: &Ident,
    runtime: &TokenStream,
    nalgebra: &TokenStream,
    scalar: &Ident,
    (nq, nv): (&proc_macro2::Literal, &proc_macro2::Literal),
) -> TokenStream {
    let q_ty = quote!(#nalgebra::SVector<#scalar, #nq>);
    let vec_ty = quote!(#nalgebra::SVector<#scalar, #nv>);
    let mat_ty = quote!(#nalgebra::SMatrix<#scalar, #nv, #nv>);
    quote! {
        #[rustfmt::skip]
        impl #runtime::Dynamics<#scalar, #nq, #nv> for #ident {
            const JOINT_NAMES: &'static [&'static str] = &Self::JOINT_NAMES;
            const POSITION_LIMITS: &'static [[#scalar; 2]] = &Self::POSITION_LIMITS;
            const VELOCITY_LIMITS: &'static [#scalar] = &Self::VELOCITY_LIMITS;
            const EFFORT_LIMITS: &'static [#scalar] = &Self::EFFORT_LIMITS;
            #[inline]
            fn mass_matrix(&self, q: &#q_ty) -> #mat_ty {
                #ident::mass_matrix(self, q)
            }
            #[inline]
            fn coriolis(&self, q: &#q_ty, qd: &#vec_ty) -> #vec_ty {
                #ident::coriolis(self, q, qd)
            }
            #[inline]
            fn gravity(&self, q: &#q_ty) -> #vec_ty {
                #ident::gravity(self, q)
            }
            #[inline]
            fn inverse_dynamics(&self, q: &#q_ty, qd: &#vec_ty, qdd: &#vec_ty) -> #vec_ty {
                #ident::inverse_dynamics(self, q, qd, qdd)
            }
            #[inline]
            fn forward_dynamics(&self, q: &#q_ty, qd: &#vec_ty, tau: &#vec_ty) -> #vec_ty {
                #ident::forward_dynamics(self, q, qd, tau)
            }
        }
    }
}

fn allow_attrs() -> TokenStream {
    quote! {
        #[allow(
            clippy::all,
            clippy::pedantic,
            clippy::nursery,
            clippy::approx_constant,
            clippy::excessive_precision,
            clippy::unreadable_literal,
            clippy::too_many_lines,
            clippy::many_single_char_names,
            clippy::neg_multiply,
            clippy::suboptimal_flops,
            unused_parens,
            non_snake_case,
            dead_code
        )]
    }
}

/// `POSITION_LIMITS`, `VELOCITY_LIMITS`, `EFFORT_LIMITS`: ±∞ where the robot file gives none.
fn limit_consts(robot: &Robot, scalar: Scalar, n: usize) -> TokenStream {
    let ty = scalar.ident();
    let n = proc_macro2::Literal::usize_unsuffixed(n);
    let value = |v: Option<f64>, sign: f64| match v {
        Some(v) => literal::float_tokens(v, scalar),
        None if sign < 0.0 => quote!(#ty::NEG_INFINITY),
        None => quote!(#ty::INFINITY),
    };
    let independent = || robot.joints.iter().filter(|j| j.is_independent());
    let position: Vec<TokenStream> = independent()
        .map(|j| {
            let position = j.limits.and_then(|l| l.position());
            let lo = value(position.map(|p| p.0), -1.0);
            let hi = value(position.map(|p| p.1), 1.0);
            quote!([#lo, #hi])
        })
        .collect();
    let velocity: Vec<TokenStream> = independent()
        .map(|j| value(j.limits.and_then(|l| l.velocity), 1.0))
        .collect();
    let effort: Vec<TokenStream> = independent()
        .map(|j| value(j.limits.and_then(|l| l.effort), 1.0))
        .collect();
    quote! {
        /// Position limits `[lower, upper]` per joint (rad or m), from the robot file;
        /// `[-∞, ∞]` for a joint without limits (continuous).
        pub const POSITION_LIMITS: [[#ty; 2]; #n] = [#(#position),*];
        /// Velocity limits per joint (rad/s or m/s), from the robot file; `∞` where none is given.
        pub const VELOCITY_LIMITS: [#ty; #n] = [#(#velocity),*];
        /// Effort limits per joint (N·m or N), from the robot file; `∞` where none is given.
        pub const EFFORT_LIMITS: [#ty; #n] = [#(#effort),*];
    }
}

fn unit_doc(robot: &Robot) -> String {
    let kinds: Vec<String> = robot
        .joints
        .iter()
        .filter(|j| j.is_independent())
        .map(|j| {
            format!(
                "{} ({})",
                inert(&j.name),
                match j.kind {
                    dynamics_model::JointKind::Revolute => "revolute: rad, N·m",
                    dynamics_model::JointKind::Prismatic => "prismatic: m, N",
                }
            )
        })
        .collect();
    format!(" Joints, in vector order: {}.", kinds.join(", "))
}

fn struct_doc(robot: &Robot, options: &Options) -> Vec<String> {
    let mut doc = vec![
        format!(
            " Rigid-body dynamics of {} ({} joints{}), generated by dynamics-gen {VERSION}.",
            inert(&robot.name),
            robot.n_coordinates(),
            match robot.dof() - robot.n_coordinates() {
                0 => String::new(),
                m => format!(" and {m} mimic joints"),
            }
        ),
        String::new(),
        format!(" Source: {}.", inert(&provenance::portable(&robot.source))),
        String::new(),
        " Conventions (Modern Robotics, chapter 8): SI units (m, kg, s, rad); joint vectors in the"
            .into(),
        " order of [`Self::JOINT_NAMES`]; `τ = M(q) q̈ + c(q, q̇) + g(q)`, with `q` the joint".into(),
        " angles (rad) or displacements (m) measured from the robot file's home configuration."
            .into(),
        format!(
            " Scalar `{}`; straight-line code: no loops, no heap, no panics{}.",
            options.scalar.as_str(),
            if options.no_std {
                ", `no_std` (libm)"
            } else {
                ""
            }
        ),
        match (robot.runtime.gravity, robot.runtime.payload) {
            (false, _) => format!(
                " Gravity ({}, {}, {}) m/s² in the base frame.",
                robot.gravity[0], robot.gravity[1], robot.gravity[2]
            ),
            (true, payload) => format!(
                " Run-time parameters, read from the struct's fields (`Default`: the robot's own values), every other constant folded into the code: gravity in the base frame (field `gravity`, default ({}, {}, {}) m/s²){}.",
                robot.gravity[0],
                robot.gravity[1],
                robot.gravity[2],
                payload.map_or(String::new(), |i| format!(
                    ", and a payload carried by link {} (fields `payload_mass`, `payload_com`, `payload_inertia`; default none), added to the link's own inertia in every function",
                    inert(&robot.links[i].name)
                ))
            ),
        },
    ];
    if !robot.is_serial() {
        doc.extend([
            String::new(),
            " A kinematic tree: joints in depth-first order from the base (every joint after the one it hangs from); entries of `M` between joints on different branches are structural zeros, never computed.".to_string(),
        ]);
    }
    if robot.has_mimic() {
        doc.extend([String::new(), mimic_doc(robot)]);
    }
    if robot.base.floating {
        doc.extend([
            String::new(),
            format!(
                " Floating base {}: a free 6-DoF joint between the world {{0}} and the base. `q = (p, quat, θ)` has `NQ = DOF + 7` entries: `p` the base origin in {{0}} (m), `quat = (x, y, z, w)` its orientation (scalar last; normalised inside, never trusted to be unit; it must not be zero), `θ` the joints. `qd = ν = (ω_b, v_b, θ̇)`, `qdd = ν̇` and `tau = (m_b, f_b, τ_θ)` have `NV = DOF + 6`: the base's body twist in the base frame, angular first, and the wrench on the base in the base frame, moment first (about the base origin); `τ_base = 0` for an unactuated base.",
                inert(&robot.base.name)
            ),
            " Pinocchio's free flyer has the same `q` and puts the linear part first: its `v = (v_b, ω_b, θ̇)` and `τ = (f_b, m_b, τ_θ)`, so swap entries 0..3 with 3..6 (rows and columns of `M`).".to_string(),
        ]);
    }
    doc
}

/// The paragraph on mimic joints: what they follow, and that vectors hold the leaders only.
fn mimic_doc(robot: &Robot) -> String {
    let followers: Vec<String> = robot
        .joints
        .iter()
        .filter_map(|j| {
            let m = j.mimic?;
            let leader = robot.joints.get(m.leader).map_or("?", |l| l.name.as_str());
            let offset = if m.offset == 0.0 {
                String::new()
            } else if m.offset < 0.0 {
                format!(" − {}", -m.offset)
            } else {
                format!(" + {}", m.offset)
            };
            Some(format!(
                "{} = {}·{}{offset}",
                inert(&j.name),
                m.multiplier,
                inert(leader)
            ))
        })
        .collect();
    format!(
        " Mimic joints follow another joint and are not coordinates: {}. Vectors hold the other joints only ([`Self::JOINT_NAMES`]); a follower moves with its leader (`q̇`, `q̈` scaled by the multiplier), and the leader's entry of `tau` is the force that drives it and all its followers (`τ = Jᵀ τ_joints`, `M = Jᵀ M_joints J`).",
        followers.join("; ")
    )
}

impl Scalar {
    /// The Rust type name as an identifier.
    pub fn ident(self) -> Ident {
        Ident::new(self.as_str(), Span::call_site())
    }
}
