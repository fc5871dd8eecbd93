//! Options of the generator, shared by the Builder, the CLI and the macros.

pub use crate::expand::Method;
use dynamics_model::LoadOptions;

/// The scalar type of the generated code.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Scalar {
    /// `f64` (default).
    #[default]
    F64,
    /// `f32`: constants are folded in f64 and rounded once to f32.
    F32,
}

impl Scalar {
    /// `f64` or `f32`.
    pub fn as_str(self) -> &'static str {
        match self {
            Scalar::F64 => "f64",
            Scalar::F32 => "f32",
        }
    }
}

impl std::str::FromStr for Scalar {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "f64" => Ok(Scalar::F64),
            "f32" => Ok(Scalar::F32),
            other => Err(format!("unknown scalar `{other}`: use `f64` or `f32`")),
        }
    }
}

/// How to emit the code.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The struct's name (default: the robot's name in UpperCamelCase).
    pub name: Option<String>,
    /// The scalar type.
    pub scalar: Scalar,
    /// Emit `no_std` code: only `::core`, nalgebra and `::libm` paths (`libm` for square
    /// roots and for `sin`/`cos` beyond the range of the generated `joint_sin_cos`).
    pub no_std: bool,
    /// The path of the nalgebra crate in generated code (default `::nalgebra`).
    pub nalgebra_path: String,
    /// The path of the `dynamics-runtime` crate whose `Dynamics` trait the generated struct
    /// implements (default `::dynamics_runtime`); `None`: no trait impl, so the generated
    /// code needs only nalgebra (and libm for `no_std`).
    pub runtime_path: Option<String>,
    /// Loader options (gravity override, URDF tip and locked joints).
    pub load: LoadOptions,
    /// The functions to generate, by name ([`FUNCTIONS`]); `None`: all of them.
    pub functions: Option<Vec<String>>,
    /// Whether the joints' friction ([`Friction`]) enters `inverse_dynamics`,
    /// `forward_dynamics`, their `_with_tip` forms and `constrained_forward_dynamics`;
    /// `None` (default): it does not (URDF `<dynamics>` values are often placeholders, and
    /// Pinocchio's `rnea` ignores them too). The `friction` function exists either way.
    pub friction: Option<Friction>,
    /// How the dynamics are derived: Newton–Euler (default) or the Lagrangian
    /// ([`Method::Lagrangian`]); the generated API is the same.
    pub method: Method,
    /// Leave gravity and a payload open until run time: the generated struct gets the
    /// fields `gravity`, `payload_mass`, `payload_com` and `payload_inertia` (`Default`: the
    /// robot's gravity, no payload) and every function reads them
    /// ([`crate::expand::parameters`]).
    pub runtime_parameters: bool,
    /// The link that carries the payload (default: the end effector's link); only with
    /// `runtime_parameters`.
    pub payload_link: Option<String>,
    /// Run-time CPU dispatch ([`crate::emit::dispatch`], default `true`): in `std` code on
    /// x86-64, each numeric function gets copies compiled for AVX-512 and for AVX2 with FMA,
    /// called when the CPU has them. `false`: one copy, no `unsafe`, the same results on every x86-64 CPU.
    pub cpu_dispatch: bool,
    /// Also emit, for each function that computes the sines and cosines of joint angles,
    /// a `*_from_sin_cos` variant that takes them from the caller, and `sin_cos(q)`
    /// ([`crate::emit::given_sin_cos`]); default `false`.
    pub sin_cos_variants: bool,
}

/// The friction model of the generated `friction(q̇)`: viscous damping `b q̇` plus Coulomb
/// friction `μ sgn(q̇)` per joint (Modern Robotics §8.9.1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Friction {
    /// `b q̇ + μ sgn(q̇)`, `sgn(0) = 0`: discontinuous at rest, as the book writes it.
    #[default]
    Coulomb,
    /// `b q̇ + μ tanh(q̇ / ε)` with this ε (rad/s or m/s, > 0): smooth, for simulation with
    /// a fixed-step integrator (at `|q̇| = 3ε` the Coulomb part is 99.5 % of μ).
    Smooth(f64),
}

/// Every function the generator can emit, in the order of the generated `impl`. The
/// `frame_*` ones exist only for a robot with named frames; the runtime trait needs the first
/// five.
pub const FUNCTIONS: &[&str] = &[
    "mass_matrix",
    "coriolis",
    "gravity",
    "inverse_dynamics",
    "forward_dynamics",
    "kinetic_energy",
    "mass_matrix_dot",
    "friction",
    "coriolis_matrix",
    "mass_matrix_and_bias",
    "mass_matrix_lower_into",
    "end_effector_forces",
    "inverse_dynamics_with_tip",
    "forward_dynamics_with_tip",
    "task_space_mass_matrix",
    "task_space_bias",
    "constrained_forward_dynamics",
    "inverse_dynamics_derivatives",
    "inverse_dynamics_with_derivatives",
    "forward_dynamics_derivatives",
    "forward_dynamics_with_derivatives",
    "mass_matrix_inverse",
    "gravity_derivative",
    "inverse_dynamics_batch",
    "forward_dynamics_batch",
    "mass_matrix_batch",
    "gravity_batch",
    "regressor",
    "inertial_parameters",
    "base_regressor",
    "base_parameters",
    "potential_energy",
    "end_effector_pose",
    "jacobian_space",
    "jacobian_body",
    "jacobian_space_dot",
    "jacobian_body_dot",
    "frame_poses",
    "frame_jacobians_space",
    "frame_jacobians_body",
];

impl Default for Options {
    fn default() -> Self {
        Self {
            name: None,
            scalar: Scalar::F64,
            no_std: false,
            nalgebra_path: "::nalgebra".into(),
            runtime_path: Some("::dynamics_runtime".into()),
            load: LoadOptions::default(),
            functions: None,
            friction: None,
            method: Method::NewtonEuler,
            runtime_parameters: false,
            cpu_dispatch: true,
            payload_link: None,
            sin_cos_variants: false,
        }
    }
}

/// The struct name derived from a robot's name: UpperCamelCase from its ASCII letters and
/// digits (word boundaries at `_`, `-`, spaces and case changes, as `heck` finds them):
/// `ur5` → `Ur5`, `mr_3link` → `Mr3link`, `double-pendulum` → `DoublePendulum`,
/// `UFROBOT` → `Ufrobot`, `xArm7` → `XArm7`. A name that would start with a digit, be
/// empty, or be `Self` gets the prefix or suffix `Robot`.
pub fn upper_camel(name: &str) -> String {
    use heck::ToUpperCamelCase;
    let ascii: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { ' ' })
        .collect();
    let mut out = ascii.to_upper_camel_case();
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "Robot");
    }
    if out == "Self" {
        out.push_str("Robot");
    }
    out
}

/// Checks a struct name given with `--name` or `.name(..)`: a Rust identifier in
/// UpperCamelCase (`Ur5`, not `ur5`), so the generated type reads like every other type.
pub fn check_struct_name(name: &str) -> Result<(), crate::Error> {
    let is_ident = syn::parse_str::<proc_macro2::Ident>(name).is_ok();
    let camel = upper_camel(name);
    if is_ident && camel == name {
        return Ok(());
    }
    let suggestion = if is_ident || camel != "Robot" {
        format!("; did you mean `{camel}`?")
    } else {
        String::new()
    };
    Err(crate::Error::InvalidName {
        name: name.to_string(),
        hint: format!("a struct name is an identifier in UpperCamelCase{suggestion}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_names_are_upper_camel_case() {
        for (name, want) in [
            ("ur5", "Ur5"),
            ("mr_3link", "Mr3link"),
            ("double-pendulum", "DoublePendulum"),
            ("UFROBOT", "Ufrobot"),
            ("panda_arm_hand", "PandaArmHand"),
            ("xArm7", "XArm7"),
            ("7dof", "Robot7dof"),
            ("", "Robot"),
            ("ü", "Robot"),
            ("self", "SelfRobot"),
            ("a\nfn x() {}", "AFnX"),
        ] {
            assert_eq!(upper_camel(name), want, "{name}");
        }
    }

    #[test]
    fn given_names_must_be_upper_camel_identifiers() {
        assert!(check_struct_name("Ur5").is_ok());
        assert!(check_struct_name("MyArm").is_ok());
        let e = check_struct_name("ur5").unwrap_err().to_string();
        assert!(e.contains("did you mean `Ur5`"), "{e}");
        let e = check_struct_name("my arm").unwrap_err().to_string();
        assert!(e.contains("`MyArm`"), "{e}");
        assert!(check_struct_name("fn").is_err());
    }
}
