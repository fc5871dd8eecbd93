//! The robot model of dynamics-gen: a kinematic tree (the serial chain of Modern Robotics
//! is its special case) in the product-of-exponentials form of Modern Robotics (Lynch &
//! Park, chapter 8), on a fixed or floating base; its loaders and its validation.
//!
//! # Conventions
//!
//! - Units SI: m, kg, s, rad; joint values q in rad (revolute) or m (prismatic).
//! - Twists and screw axes are `(ω, v)` (angular part first); wrenches are `(m, f)`.
//! - Frames: {0} is the space (base) frame; {i} is the frame of link i (i = 1..n), moved by
//!   joint i; {n+1} is the end-effector (tip) frame. Named frames ([`Robot::frames`]: feet,
//!   hands, sensors) are [`Frame`]s like the end effector: a link (or the base) and a
//!   constant pose in its frame.
//! - Trees: link i hangs from `λ(i)` ([`Link::parent`]; `None` = the base), always an
//!   earlier link, so every vector lists a joint after the joints between it and the base.
//!   A serial chain has `λ(i) = i − 1`.
//! - `M_{λ(i),i}` ([`Link::home`], and [`EndEffector::home`] in the frame of the link it is
//!   attached to) is the pose of {i} in its parent's frame at the home configuration q = 0;
//!   on a serial chain `M_{i−1,i}`, the book's `Mlist`.
//! - `G_i` ([`Link::inertia`]) is link i's 6×6 spatial inertia expressed in {i}. The book puts
//!   {i} at the link's centre of mass, where `G_i = [[I_b, 0], [0, m·1₃]]`; any frame is
//!   allowed here, with the full 6×6 moved by `G_a = [Ad_{T_ba}]ᵀ G_b [Ad_{T_ba}]` (Exercise 8.3).
//! - `S_i` ([`Joint::screw`]) is joint i's screw axis in {0} at the home configuration:
//!   `(ω, −ω × q)` for a revolute joint with unit axis ω through the point q, `(0, v)` with
//!   `|v| = 1` for a prismatic joint.
//! - Gravity ([`Robot::gravity`]) is a vector in {0}, by default `(0, 0, −9.81)` m/s².
//! - The dynamics are `τ = M(q) q̈ + c(q, q̇) + g(q) + J_b(q)ᵀ F_tip`, where `F_tip` is the
//!   wrench the end effector applies to the environment, in {n+1}.
//! - Actuation and friction ([`actuation`]): M includes each joint's armature
//!   `G² I_rotor` ([`Joint::armature`]) on its diagonal; viscous and Coulomb friction
//!   ([`Joint::damping`], [`Joint::friction`]) is a separate term, `τ = ID + τ_friction`.
//!
//! ## Mimic joints
//!
//! A joint with [`Joint::mimic`] follows another joint, its leader: `θ_f = m·θ_L + o`
//! (URDF `<mimic>`, TOML `mimic = { joint, multiplier, offset }`). It keeps its link, which it
//! moves, but it is not a coordinate: the vectors q, ν, ν̇ and τ hold the *independent* joints
//! only, the joints without `mimic`, in the order of [`Robot::joints`]. Hence the counts
//! (see [`mimic`]):
//!
//! - [`Robot::dof`] = n, the physical joints (one per link), followers included;
//! - [`Robot::n_coordinates`] = k, the independent joints ([`Robot::joint_names`] lists them);
//! - [`Robot::nq`] = k (+ 7 on a floating base), [`Robot::nv`] = k (+ 6).
//!
//! Without mimic joints k = n. The dynamics in the coordinates are the physical ones
//! projected by the constant coupling matrix J: `M = Jᵀ M_joints J`, `τ = Jᵀ τ_joints`, so the
//! leader's τ is the force that drives it and all its followers.
//!
//! ## Floating base
//!
//! With [`Base::floating`], a free 6-DoF joint connects the world frame {0} to the base,
//! whose frame coincides with {0} at the home configuration. Then (nq = k + 7, nv = k + 6,
//! k = n without mimic joints):
//!
//! - `q = (p, quat, θ)`: `p` the base origin in {0} (m); `quat = (x, y, z, w)`, scalar
//!   last, the base orientation `R` (base-frame vectors into {0}); `θ` the k joint values.
//!   Code that reads `quat` normalises it (`R` is computed from `quat / |quat|`).
//! - `ν = (ω_b, v_b, θ̇)`: the base's body twist in the base frame, angular first
//!   (`[ω_b] = Rᵀ Ṙ`, `v_b = Rᵀ ṗ`), then the joint rates; `ν̇` likewise.
//! - `τ = (m_b, f_b, τ_θ)`: the wrench applied to the base in the base frame, moment first
//!   (about the base origin), then the joint forces.
//!
//! Pinocchio's free flyer has the same q, and ν and τ with the linear part first:
//! Pinocchio `v = (v_b, ω_b, θ̇)` and `τ = (f_b, m_b, τ_θ)`, so rows and columns 0..3 and 3..6
//! swap between the two.
//!
//! # Where a robot comes from
//!
//! - The book's lists: [`Robot::from_mr_lists`] (validating) and
//!   [`Robot::from_mr_lists_unchecked`] (as given, like the book's own functions).
//! - A TOML robot file ([`toml_format`]).
//! - A URDF file ([`urdf`]).
//! - A shipped robot by name ([`shipped`]), and [`load()`](fn@load) for any of the above.

pub mod actuation;
pub mod error;
pub mod inertia;
pub mod lie;
pub mod mimic;
pub mod parameters;
pub mod random;
pub mod robot;
pub mod validate;

pub use actuation::optimal_gear_ratio;
pub use error::{Invalid, ModelError, Subject};
pub use inertia::SpatialInertia;
pub use mimic::{Coupling, Mimic};
pub use robot::{
    Base, EndEffector, Frame, Joint, JointKind, JointLimits, Link, Robot, RuntimeParameters,
    DEFAULT_GRAVITY,
};
pub mod load;
pub mod shipped;
pub mod toml_format;
pub mod urdf;

pub use load::{load, load_file, Format, LoadOptions};
