//! `robot!` and `#[derive(Dynamics)]`: dynamics-gen as procedural macros.
//!
//! The entry points only; the grammar, the options and the errors are documented and
//! implemented in [`dynamics_gen::macro_support`].
//!
//! ```ignore
//! dynamics_macros::robot! {
//!     pub struct Pendulum;
//!     gravity: [0, 0, -10],
//!     joint revolute joint1 { screw: [0, 0, 1, 0, 0, 0],
//!         link arm { home: { xyz: [1, 0, 0] }, mass: 2, inertia: [4, 4, 4, 0, 0, 0] } },
//!     joint revolute joint2 { screw: [1, 0, 0, 0, 0, 0],
//!         link pendulum { home: { xyz: [0, 0, -1] }, mass: 2, inertia: [4, 4, 0, 0, 0, 0] } },
//! }
//!
//! #[derive(dynamics_macros::Dynamics)]
//! #[dynamics(file = "robots/ur5.urdf")]
//! pub struct Ur5;
//! ```

use proc_macro::TokenStream;

/// Defines a robot inline and emits its struct and `impl` (`DOF`, `JOINT_NAMES`,
/// `mass_matrix`, `coriolis`, `gravity`, `inverse_dynamics`, `forward_dynamics`).
/// See [`dynamics_gen::macro_support`] for the grammar.
#[proc_macro]
pub fn robot(input: TokenStream) -> TokenStream {
    dynamics_gen::macro_support::robot(input.into()).into()
}

/// Implements the dynamics of the robot file named by `#[dynamics(file = "…")]` (URDF or
/// TOML, relative to `CARGO_MANIFEST_DIR`) on the struct. See
/// [`dynamics_gen::macro_support`] for the options.
#[proc_macro_derive(Dynamics, attributes(dynamics))]
pub fn derive_dynamics(input: TokenStream) -> TokenStream {
    dynamics_gen::macro_support::derive_dynamics(input.into()).into()
}
