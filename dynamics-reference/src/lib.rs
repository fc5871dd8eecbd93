//! Generic recursive rigid-body dynamics of a kinematic tree (the open serial chain is its
//! special case) on a fixed or floating base, written plainly after Modern Robotics (Lynch &
//! Park), sections 8.3–8.7 and 8.9, with the semantics of the book's Python library
//! (`InverseDynamics`, `MassMatrix`, `ForwardDynamics`, …) and Featherstone's tree
//! recursions (RNEA, CRBA) in the book's notation.
//!
//! This crate is the reference every generated function is checked against. It depends only
//! on the robot model ([`dynamics_model`]) and [`nalgebra`], so it cannot share code with the
//! generator's symbolic recursion. It favours clarity over speed: `f64`, heap vectors, loops
//! over the joints, one algorithm per file with the equation it computes in its doc comment.
//!
//! # Conventions
//!
//! - Units SI: m, kg, s, rad, N, N·m. Joint values are rad (revolute) or m (prismatic).
//! - Twists and screw axes are `(ω, v)`, angular part first; wrenches are `(m, f)`, moment first.
//! - Frames: {0} is the space frame, {i} the frame of link i (i = 1..n), {n+1} the
//!   end-effector frame. `G_i` is link i's spatial inertia in {i}; {i} need not be at the
//!   centre of mass (the full 6×6 is used everywhere, the centre of mass for the potential
//!   energy comes from [`dynamics_model::SpatialInertia::com`]).
//! - Trees: link i hangs from `λ(i)` ([`dynamics_model::Link::parent`], always an earlier
//!   link, or the base); a serial chain has `λ(i) = i − 1` and is not a separate code path.
//!   `A_i = [Ad_{M_{0i}⁻¹}] S_i` is joint i's screw axis in {i};
//!   `T_{i,λ(i)} = e^{−[A_i]θ_i} M_{λ(i),i}⁻¹` and `T_{n+1,λ} = M_{λ,n+1}⁻¹` (see [`TreeFrames`]).
//!   Each link's wrench is carried into its parent; `M_ij = 0` (exactly) when joints i and j
//!   lie on different branches; Jacobian columns of joints off the end effector's path are 0.
//! - `V̇_0 = (0, −g)`: gravity enters as an upward acceleration of the base, so `g` is the
//!   gravity vector in {0} (e.g. `(0, 0, −9.81)`), passed explicitly like the book's functions
//!   do (use [`dynamics_model::Robot::gravity`] for the robot's own).
//! - `F_tip` is the wrench `(m, f)` the end effector applies **to the environment**, expressed
//!   in {n+1}.
//! - The equations of motion are
//!   `τ = M(q) ν̇ + c(q, ν) + g(q) + J_b(q)ᵀ F_tip`, where `J_b` is the body Jacobian of {n+1},
//!   `c = C(q, ν) ν` (Coriolis and centripetal terms) and `g(q) = ∂P/∂q`. On a fixed base
//!   `q = θ`, `ν = θ̇`, `ν̇ = θ̈` (n entries each), as in the book. M includes each joint's
//!   armature (below); friction is a separate term.
//!
//! ## Floating base
//!
//! With [`dynamics_model::Base::floating`], the base is body 0 on a free joint (the
//! conventions of [`dynamics_model`]'s crate docs): nq = n + 7, nv = n + 6 (k for n with mimic joints), and
//!
//! - `q = (p, quat, θ)`: the base origin in {0}, its orientation `R` as a quaternion
//!   `(x, y, z, w)`, scalar last, **normalised inside** (`R` from `quat/|quat|`, any nonzero
//!   4-vector is accepted), then the joint values;
//! - `ν = (ω_b, v_b, θ̇)`: the base's body twist in the base frame, then the joint rates; `ν̇`
//!   likewise (`ν̇_b` is the derivative of the body twist);
//! - `τ = (m_b, f_b, τ_θ)`: the wrench applied to the base, in the base frame (moment about the
//!   base origin), then the joint forces.
//!
//! The recursions start from the base body: `V_0 = ν_b`, `V̇_0 = ν̇_b + (0, −Rᵀ g)`, with the
//! base's own inertia [`dynamics_model::Base::inertia`]; `τ[0..6]` is the total wrench the base
//! body needs. `M[0..6, 0..6]` is the composite spatial inertia of the whole robot in the base
//! frame and `M[0..6, ·] ν` its spatial momentum there; `M` depends on θ only. The potential
//! energy counts the base, and `g(q)` is its derivative along the velocity directions (for
//! the base, along its body twist); the poses ([`link_poses`], [`end_effector_pose`]) are in
//! {0} through the base pose ([`base_pose`]); the Jacobians' six base columns map `ν_b`. The
//! configuration moves by [`configuration_rate`] (`ṗ = R v_b`, `quaṫ = ½ quat ⊗ (ω_b, 0)`).
//!
//! Because `ν_b` is a body twist and not the derivative of coordinates, the Coriolis matrix
//! is not the Christoffel form alone: [`coriolis_matrix`] adds the base's Euler–Poincaré term
//! `−[ad_{ν_b}]ᵀ h_b` (`h_b` the momentum in the base frame) as a skew-symmetric block, so that
//! `c = C ν` and `Ṁ − 2C` is skew-symmetric on floating bases too (a C with these two properties
//! is not unique there, so other libraries' C may differ while c agrees).
//!
//! Pinocchio's free flyer (`JointModelFreeFlyer`, LOCAL base velocity) has the same q; its
//! velocity, acceleration and force vectors put the linear part first:
//! Pinocchio `v = (v_b, ω_b, θ̇)`, `a = (v̇_b, ω̇_b, θ̈)`, `τ = (f_b, m_b, τ_θ)`. So entries 0..3
//! and 3..6 swap, and so do rows and columns 0..3 and 3..6 of M, C and Ṁ: with P the
//! permutation `(3, 4, 5, 0, 1, 2, 6, 7, …)`, `M_here = P M_pinocchio Pᵀ`.
//!
//! ## Mimic joints
//!
//! On a robot with mimic joints ([`dynamics_model::mimic`]: joint f follows its leader L,
//! `θ_f = m·θ_L + o`), every function takes and returns the *independent* coordinates: q, ν,
//! ν̇ and τ hold the joints without `mimic` (nq = k, nv = k with k =
//! [`dynamics_model::Robot::n_coordinates`], + 7 and + 6 on a floating base). Inside, in one
//! place (the `coupling` module), the call is turned into one on the physical robot (every
//! joint independent) with `q_phys = J q + o`, `ν_phys = J ν`, `ν̇_phys = J ν̇` (J constant, so
//! `J̇ = 0`), and the results are projected: `τ = Jᵀ τ_phys`, `M = Jᵀ M_phys J`,
//! `Ṁ = Jᵀ Ṁ_phys J`, `c = Jᵀ c_phys`, `g = Jᵀ g_phys`, Jacobians `J_phys J`; poses and
//! energies are the physical ones. Forward dynamics solves `M ν̇ = τ − Jᵀ bias_phys` with these,
//! and the Coriolis matrix from the Christoffel symbols of the projected M equals
//! `Jᵀ C_phys J`. [`link_poses`] and [`TreeFrames`] still have one entry per physical joint.
//! A robot without mimic joints takes none of this (its numbers are bit for bit as before).
//!
//! ## Actuation, friction, task space, constraints
//!
//! - **Armature** (§8.9.2): a joint with a rotor of inertia `I_rotor` behind a gear of ratio G
//!   ([`dynamics_model::Joint::armature`] = `G² I_rotor`) adds it to its diagonal entry of M:
//!   [`mass_matrix`] and [`inverse_dynamics`] (`+ G² I_rotor θ̈_i`) carry it, so do
//!   [`forward_dynamics`], [`kinetic_energy`] and the trajectories; it is constant, so
//!   [`mass_matrix_dot`] and [`coriolis_matrix`] do not change. Joint entries only (never the
//!   floating base's); on mimic joints at the physical level, then projected.
//! - **Friction**: [`friction_forces`] is `τ_friction = b θ̇ + μ sgn(θ̇)` (or `μ tanh(θ̇/ε)`),
//!   which no other function adds: the actuation is `τ = ID + τ_friction`, and forward dynamics
//!   with friction is `FD(τ − τ_friction)`.
//! - **Jacobian rates** (Exercise 8.6): [`jacobian_space_dot`], [`jacobian_body_dot`] and their
//!   `frame_` forms, `J̇ = dJ/dt` along [`configuration_rate`], from Lie brackets of the columns.
//! - **Task space** (§8.6), in the end-effector frame: [`task_space_mass_matrix`]
//!   `Λ = (J_b M⁻¹ J_bᵀ)⁻¹` and [`task_space_bias`] `η = Λ (J_b M⁻¹ h − J̇_b ν)`, so that
//!   `F = Λ V̇_b + η`; `None` at singularities (an `L D Lᵀ` pivot test, documented there).
//! - **Constraints** (§8.7, Exercise 8.10): [`constrained_forward_dynamics`] solves
//!   `M ν̇ + h = τ + Aᵀλ`, `A ν̇ + Ȧν = 0` for ν̇ and λ.
//!
//! # Example
//!
//! A point mass m on a massless rod of length l, swinging about the x axis of {0}:
//! `M = m l²` and `g(θ) = m g₀ l sin θ`.
//!
//! ```
//! use dynamics_model::lie::rp_to_trans;
//! use dynamics_model::Robot;
//! use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};
//!
//! let (m, l) = (2.0, 0.5);
//! let m01 = rp_to_trans(&Matrix3::identity(), &Vector3::new(0.0, 0.0, -l)); // the mass
//! let g1 = Matrix6::from_diagonal(&Vector6::new(0.0, 0.0, 0.0, m, m, m));
//! let s1 = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
//! let robot = Robot::from_mr_lists(&[m01, Matrix4::identity()], &[g1], &[s1], Vector3::new(0.0, 0.0, -9.81))?;
//!
//! let q = [0.3];
//! let tau = dynamics_reference::inverse_dynamics(&robot, &q, &[0.0], &[1.5], &robot.gravity, &Vector6::zeros());
//! let expected = m * l * l * 1.5 + m * 9.81 * l * q[0].sin();
//! assert!((tau[0] - expected).abs() < 1e-12);
//!
//! let qdd = dynamics_reference::forward_dynamics(&robot, &q, &[0.0], tau.as_slice(), &robot.gravity, &Vector6::zeros())?;
//! assert!((qdd[0] - 1.5).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The same pendulum on a floating base of 1 kg: unactuated and at rest, everything falls
//! together, so the base's body acceleration is `(0, Rᵀ g)` and the joint does not move. The
//! quaternion `(0, 0, 0, 2)` is the identity rotation (it is normalised inside).
//!
//! ```
//! # use dynamics_model::lie::rp_to_trans;
//! # use dynamics_model::{Robot, SpatialInertia};
//! # use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};
//! # let (m, l) = (2.0, 0.5);
//! # let m01 = rp_to_trans(&Matrix3::identity(), &Vector3::new(0.0, 0.0, -l));
//! # let g1 = Matrix6::from_diagonal(&Vector6::new(0.0, 0.0, 0.0, m, m, m));
//! # let s1 = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
//! let mut robot = Robot::from_mr_lists(&[m01, Matrix4::identity()], &[g1], &[s1], Vector3::new(0.0, 0.0, -9.81))?;
//! robot.base.floating = true;
//! robot.base.inertia = SpatialInertia::at_com(1.0, Matrix3::identity() * 0.01);
//! assert_eq!((robot.nq(), robot.nv()), (8, 7));
//!
//! let q = [0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 2.0, 0.4]; // p, quat (x, y, z, w), θ
//! let (rest, no_force) = ([0.0; 7], [0.0; 7]);
//! let acc = dynamics_reference::forward_dynamics(&robot, &q, &rest, &no_force, &robot.gravity, &Vector6::zeros())?;
//! let free_fall = [0.0, 0.0, 0.0, 0.0, 0.0, -9.81, 0.0]; // (ω̇_b, v̇_b, θ̈)
//! assert!(acc.iter().zip(free_fall).all(|(a, b)| (a - b).abs() < 1e-12));
//!
//! // Holding it up takes the weight (m_b + m)·9.81 as an upward force on the base.
//! let hold = dynamics_reference::gravity_forces(&robot, &q, &robot.gravity);
//! assert!((hold[5] - 3.0 * 9.81).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # API
//!
//! Every function takes the robot first. Configurations q are `&[f64]` of length
//! nq = [`dynamics_model::Robot::nq`]; velocities, accelerations and forces (ν, ν̇, τ) are
//! `&[f64]` of length nv = [`dynamics_model::Robot::nv`] (both n on a fixed base without mimic
//! joints; a `DVector`
//! passes with `.as_slice()`); gravity is a `&Vector3<f64>`, `F_tip` a `&Vector6<f64>`.
//! Results are `DVector<f64>` / `DMatrix<f64>` of nv entries / nv×nv (6×nv for Jacobians).
//! Trajectories are `DMatrix<f64>` with one row per time step (N×nq for q, N×nv for ν, ν̇ and
//! τ, N×6 for `F_tip`), as in the book's library.
//!
//! Everything holds for trees, floating bases and mimic joints: inverse and forward dynamics,
//! M, c, g, C, Ṁ, energies, poses, Jacobians and their rates, tip forces, trajectories,
//! friction, the task space and constrained forward dynamics. [`euler_step`] alone is the
//! book's fixed-base step (`q̇ = θ̇`); trajectories step a floating base with
//! [`configuration_rate`].
//!
//! A vector whose length is not nq or nv is a programming error and panics with a message that
//! names the argument; everything else (including a mass matrix that is not positive definite)
//! is reported through [`ReferenceError`], or by `None` from the task-space and constrained
//! functions, whose singularity contract is shared with the generated code.
//!
//! The functions accept every robot [`dynamics_model::Robot::from_mr_lists_unchecked`] builds,
//! e.g. a screw axis with `|ω| ≠ 1`, as the book's library does.

mod base;
mod check;
mod configuration_rate;
mod constrained_forward_dynamics;
mod coriolis_matrix;
mod coupling;
mod end_effector_forces;
mod end_effector_pose;
mod error;
mod euler_step;
mod forward_dynamics;
mod forward_dynamics_trajectory;
mod frames;
mod friction_forces;
mod gravity_forces;
mod inverse_dynamics;
mod inverse_dynamics_trajectory;
mod jacobian_body;
mod jacobian_body_dot;
mod jacobian_space;
mod jacobian_space_dot;
mod kinetic_energy;
mod ldlt;
mod link_poses;
mod mass_matrix;
mod mass_matrix_dot;
mod potential_energy;
mod task_space_bias;
mod task_space_mass_matrix;
mod vel_quadratic_forces;

pub use base::{base_pose, quaternion_rotation};
pub use configuration_rate::configuration_rate;
pub use constrained_forward_dynamics::constrained_forward_dynamics;
pub use coriolis_matrix::{coriolis_matrix, mass_matrix_partials};
pub use end_effector_forces::end_effector_forces;
pub use end_effector_pose::{end_effector_pose, frame_pose};
pub use error::ReferenceError;
pub use euler_step::euler_step;
pub use forward_dynamics::forward_dynamics;
pub use forward_dynamics_trajectory::forward_dynamics_trajectory;
pub use frames::TreeFrames;
pub use friction_forces::friction_forces;
pub use gravity_forces::gravity_forces;
pub use inverse_dynamics::inverse_dynamics;
pub use inverse_dynamics_trajectory::inverse_dynamics_trajectory;
pub use jacobian_body::{frame_jacobian_body, jacobian_body};
pub use jacobian_body_dot::{frame_jacobian_body_dot, jacobian_body_dot};
pub use jacobian_space::{frame_jacobian_space, jacobian_space};
pub use jacobian_space_dot::{frame_jacobian_space_dot, jacobian_space_dot};
pub use kinetic_energy::kinetic_energy;
pub use link_poses::link_poses;
pub use mass_matrix::mass_matrix;
pub use mass_matrix_dot::mass_matrix_dot;
pub use potential_energy::potential_energy;
pub use task_space_bias::task_space_bias;
pub use task_space_mass_matrix::task_space_mass_matrix;
pub use vel_quadratic_forces::vel_quadratic_forces;

/// The literature acronym for [`inverse_dynamics`]: the recursive Newton–Euler algorithm.
pub use inverse_dynamics::inverse_dynamics as rnea;
/// The literature acronym for [`mass_matrix`]: the composite-rigid-body algorithm.
pub use mass_matrix::mass_matrix as crba;
