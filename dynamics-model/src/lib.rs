//! The robot model of dynamics-gen: an open serial chain in the product-of-exponentials
//! form of Modern Robotics (Lynch & Park, chapter 8), its loaders and its validation.
//!
//! # Conventions
//!
//! - Units SI: m, kg, s, rad; joint values q in rad (revolute) or m (prismatic).
//! - Twists and screw axes are `(ω, v)` (angular part first); wrenches are `(m, f)`.
//! - Frames: {0} is the space (base) frame; {i} is the frame of link i (i = 1..n), moved by
//!   joint i; {n+1} is the end-effector (tip) frame.
//! - `M_{i−1,i}` ([`Link::home`], and [`EndEffector::home`] for i = n+1) is the pose of {i} in
//!   {i−1} at the home configuration q = 0.
//! - `G_i` ([`Link::inertia`]) is link i's 6×6 spatial inertia expressed in {i}. The book puts
//!   {i} at the link's centre of mass, where `G_i = [[I_b, 0], [0, m·1₃]]`; any frame is
//!   allowed here, with the full 6×6 moved by `G_a = [Ad_{T_ba}]ᵀ G_b [Ad_{T_ba}]` (Exercise 8.3).
//! - `S_i` ([`Joint::screw`]) is joint i's screw axis in {0} at the home configuration:
//!   `(ω, −ω × q)` for a revolute joint with unit axis ω through the point q, `(0, v)` with
//!   `|v| = 1` for a prismatic joint.
//! - Gravity ([`Robot::gravity`]) is a vector in {0}, by default `(0, 0, −9.81)` m/s².
//! - The dynamics are `τ = M(q) q̈ + c(q, q̇) + g(q) + J_b(q)ᵀ F_tip`, where `F_tip` is the
//!   wrench the end effector applies to the environment, in {n+1}.
//!
//! # Where a robot comes from
//!
//! - The book's lists: [`Robot::from_mr_lists`] (validating) and
//!   [`Robot::from_mr_lists_unchecked`] (as given, like the book's own functions).
//! - A TOML robot file ([`toml_format`]).
//! - A URDF file ([`urdf`]).
//! - A shipped robot by name ([`shipped`]), and [`load()`](fn@load) for any of the above.

pub mod error;
pub mod inertia;
pub mod lie;
pub mod random;
pub mod robot;
pub mod validate;

pub use error::{Invalid, ModelError, Subject};
pub use inertia::SpatialInertia;
pub use robot::{EndEffector, Joint, JointKind, JointLimits, Link, Robot, DEFAULT_GRAVITY};
pub mod load;
pub mod shipped;
pub mod toml_format;
pub mod urdf;

pub use load::{load, load_file, Format, LoadOptions};
