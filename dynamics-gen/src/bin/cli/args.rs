//! Command-line arguments (clap derive) and the parsers of `--gravity` and `--lock`.

use clap::{Args, Parser, Subcommand};
use dynamics_gen::dynamics_model::{LoadOptions, Robot};
use dynamics_gen::{Method, Scalar};
use std::path::PathBuf;

/// Generates unrolled, allocation-free Rust rigid-body dynamics for a robot arm, and
/// evaluates the reference dynamics.
#[derive(Debug, Parser)]
#[command(name = "dynamics-gen", version)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print (or write with -o) the generated Rust code of a robot.
    Generate(GenerateArgs),
    /// Print the operation counts and line counts of each generated function.
    Stats(StatsArgs),
    /// Print the equations of motion in closed form: M(θ), c(θ, θ̇), C(θ, θ̇) and g(θ) as
    /// polynomials in sin θ_i, cos θ_i, θ̇_i (θ_i for prismatic joints), from the Lagrangian,
    /// with sin² + cos² = 1 applied and coefficients as exact short forms where they are one
    /// (integers, simple fractions, √2, √3, √6, π multiples). Fixed-base robots.
    Equations(EquationsArgs),
    /// Evaluate the reference dynamics on states read as JSON lines from stdin.
    ///
    /// Each input line is `{"q": [...], "qd": [...], "qdd": [...], "tau": [...], "f_tip": [...]}`
    /// (all but `q` optional, default zero; `f_tip` = (m, f) applied by the end effector, in
    /// {n+1}). Each output line holds `mass_matrix`, `coriolis`, `gravity`,
    /// `inverse_dynamics`, `forward_dynamics`, `coriolis_matrix`, `mass_matrix_dot`,
    /// `kinetic_energy`, `potential_energy`, `friction` (b q̇ + μ sgn q̇),
    /// `end_effector_forces` (J_bᵀ f_tip), `end_effector_pose`, `jacobian_space`,
    /// `jacobian_body`, `jacobian_space_dot`, `jacobian_body_dot`, `task_space_mass_matrix` and
    /// `task_space_bias` (null where J_b M⁻¹ J_bᵀ is singular) (matrices as lists of rows). A line whose results are not finite (e.g. q̇ = 1e300) is
    /// an error for that line. With mimic joints, q, qd, qdd and tau hold the independent
    /// joints only (see `joints`).
    Eval(EvalArgs),
    /// List the movable joints in vector order: name, type, index in q, screw axis S_i in {0},
    /// limits; a mimic joint has no index and says which joint it follows.
    Joints(ModelArgs),
    /// List the shipped robots.
    Robots,
}

/// The robot and the options that change the model.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// A .urdf or .toml robot file, or the name of a shipped robot (see `dynamics-gen robots`).
    #[arg(value_name = "ROBOT")]
    pub robot: String,
    /// Replace the gravity vector (m/s², in the base frame {0}), e.g. `--gravity 0,0,-9.81`.
    #[arg(long, value_name = "GX,GY,GZ", value_parser = parse_gravity, allow_hyphen_values = true)]
    pub gravity: Option<[f64; 3]>,
    /// URDF: the link whose frame is the end-effector frame {n+1}.
    #[arg(long, value_name = "LINK")]
    pub tip: Option<String>,
    /// URDF: lock movable joints at values (rad or m), making them fixed; repeatable and
    /// comma-separated (`--lock a=0,b=PI/2`). A value is a number or constant arithmetic as in
    /// `robot!` (`PI/2`, `-FRAC_PI_4`, `0.5*PI`).
    #[arg(long, value_name = "JOINT=VALUE[,JOINT=VALUE...]", value_parser = parse_lock, value_delimiter = ',', allow_hyphen_values = true)]
    pub lock: Vec<(String, f64)>,
    /// Put a free 6-DoF joint between the world and the base: q = (p, quat (x, y, z, w), θ),
    /// ν = (ω_b, v_b, θ̇) with the base twist in the base frame, τ = (m_b, f_b, τ_θ). Automatic
    /// for a URDF whose root joint is `floating`.
    #[arg(long)]
    pub floating_base: bool,
    /// URDF: links whose frames get a pose and Jacobians in the generated code (feet,
    /// hands); repeatable and comma-separated. Default: on a tree every leaf link, on a chain
    /// none (the end effector has its own functions).
    #[arg(long, value_name = "LINK[,LINK...]", value_delimiter = ',')]
    pub frame: Vec<String>,
    /// The armature G²·I_rotor of joints (kg·m² or kg), added to the mass matrix's diagonal
    /// (Pinocchio's `model.armature`); replaces the file's rotor_inertia and gear_ratio for
    /// those joints. Repeatable and comma-separated (`--armature j1=0.1,j2=0.05`).
    #[arg(long, value_name = "JOINT=VALUE[,JOINT=VALUE...]", value_parser = parse_armature, value_delimiter = ',')]
    pub armature: Vec<(String, f64)>,
    /// URDF: read `rpy` angles within TOL (rad, at most 1e-2) of a multiple of π/2 as that
    /// multiple (default 1e-9, the decimals of π/2 only). For files that write 1.5708 for
    /// π/2: axis-aligned frames need far fewer operations (`stats` lists the angles it would
    /// change and what it would save). The robot changes by up to TOL: opt in knowingly.
    #[arg(long, value_name = "TOL")]
    pub snap_angles: Option<f64>,
}

/// Arguments of `stats`.
#[derive(Debug, Args)]
pub struct StatsArgs {
    /// The robot and model options.
    #[command(flatten)]
    pub model: ModelArgs,
    /// How the dynamics are derived, as for `generate`.
    #[arg(long, default_value = "newton_euler", value_parser = parse_method)]
    pub method: Method,
    /// Count the code with run-time gravity and payload, as for `generate`.
    #[arg(long)]
    pub runtime_parameters: bool,
    /// The payload's link, as for `generate`.
    #[arg(long, value_name = "LINK", requires = "runtime_parameters")]
    pub payload_link: Option<String>,
}

/// Arguments of `equations`.
#[derive(Debug, Args)]
pub struct EquationsArgs {
    /// The robot and model options.
    #[command(flatten)]
    pub model: ModelArgs,
    /// `text` (Unicode), `latex` (a document with an align* per quantity) or `markdown`
    /// (with $$ math $$, as GitHub renders it).
    #[arg(long, default_value = "text", value_parser = parse_format)]
    pub format: dynamics_gen::equations::Format,
    /// Print the derivation first: the links' body twists V_i, K, P, L = K − P, ∂L/∂θ̇,
    /// d/dt ∂L/∂θ̇, ∂L/∂θ and τ, as a textbook solution takes it.
    #[arg(long)]
    pub steps: bool,
    /// Significant digits of the coefficients that have no short exact form (1 to 17; 17
    /// prints every coefficient exactly as the f64 it is).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(1..=17))]
    pub digits: u8,
    /// Print only these results: a comma-separated list of M, c, C, g (default all four;
    /// c is the vector, C the matrix).
    #[arg(long, value_name = "M,c,C,g", default_value = "M,c,C,g", value_parser = parse_select)]
    pub only: dynamics_gen::equations::Select,
    /// Keep these named parameters of the robot file (its `[parameters]` table) as symbols,
    /// e.g. `--symbolic m1 m2 L1 L2`; the others take their values.
    #[arg(long, num_args = 1.., value_name = "NAME")]
    pub symbolic: Vec<String>,
}

/// Arguments of `eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The robot and model options.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Go on after a bad line: its answer is `{"line": N, "error": "…"}` (the message also
    /// goes to stderr), later lines are answered, and the exit code is 1 at the end.
    #[arg(long)]
    pub keep_going: bool,
}

/// Arguments of `generate`.
#[derive(Debug, Args)]
pub struct GenerateArgs {
    /// The robot and model options.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The generated struct's name (default: the robot's name in UpperCamelCase).
    #[arg(long)]
    pub name: Option<String>,
    /// The scalar type of the generated code.
    #[arg(long, default_value = "f64", value_parser = parse_scalar)]
    pub scalar: Scalar,
    /// Emit no_std code (square roots, and sin/cos beyond |q| = 1e6, through `::libm`).
    #[arg(long)]
    pub no_std: bool,
    /// The path of the nalgebra crate in the generated code.
    #[arg(long, default_value = "::nalgebra", value_name = "PATH")]
    pub nalgebra_path: String,
    /// The path of the dynamics-runtime crate, whose `Dynamics` trait the struct implements.
    #[arg(long, default_value = "::dynamics_runtime", value_name = "PATH")]
    pub runtime_path: String,
    /// No `impl dynamics_runtime::Dynamics`: the code then needs only nalgebra (and libm).
    #[arg(long)]
    pub no_runtime_trait: bool,
    /// Generate only these functions (comma-separated or repeated; default all), named as in
    /// the generated impl: mass_matrix, coriolis, gravity, inverse_dynamics,
    /// forward_dynamics, kinetic_energy, mass_matrix_dot, friction, coriolis_matrix,
    /// mass_matrix_and_bias, mass_matrix_lower_into, end_effector_forces, inverse_dynamics_with_tip,
    /// forward_dynamics_with_tip, task_space_mass_matrix, task_space_bias,
    /// constrained_forward_dynamics, inverse_dynamics_derivatives,
    /// inverse_dynamics_with_derivatives, forward_dynamics_derivatives,
    /// forward_dynamics_with_derivatives, mass_matrix_inverse, gravity_derivative,
    /// inverse_dynamics_batch, forward_dynamics_batch, mass_matrix_batch, gravity_batch, regressor,
    /// inertial_parameters, base_regressor, base_parameters,
    /// potential_energy, end_effector_pose, jacobian_space,
    /// jacobian_body, jacobian_space_dot, jacobian_body_dot, frame_poses,
    /// frame_jacobians_space, frame_jacobians_body. The runtime trait needs the first five
    /// (or --no-runtime-trait).
    #[arg(long, value_name = "FN[,FN...]", value_delimiter = ',')]
    pub functions: Vec<String>,
    /// Include the joints' friction (damping b q̇ + Coulomb μ sgn(q̇), from the robot file) in
    /// inverse_dynamics, forward_dynamics, their _with_tip forms and
    /// constrained_forward_dynamics. Off by default: URDF damping values are often
    /// placeholders, and Pinocchio's rnea leaves them out. `friction(qd)` exists either way.
    #[arg(long)]
    pub friction: bool,
    /// Smooth Coulomb friction for simulation: μ tanh(q̇/ε) instead of μ sgn(q̇), with this ε
    /// (rad/s or m/s, > 0). Implies --friction.
    #[arg(long, value_name = "EPS", value_parser = parse_smoothing)]
    pub friction_smoothing: Option<f64>,
    /// How the dynamics are derived: `newton_euler` (recursive Newton–Euler, the
    /// composite-rigid-body and articulated-body algorithms) or `lagrangian` (the
    /// Euler–Lagrange equations of K − P by symbolic differentiation). The same functions
    /// and the same numbers either way; `stats --method` compares their costs.
    #[arg(long, default_value = "newton_euler", value_parser = parse_method)]
    pub method: Method,
    /// Leave gravity and a payload open until run time: the struct gets the public fields
    /// `gravity`, `payload_mass`, `payload_com` and `payload_inertia` (Default: the robot's
    /// gravity, no payload), and every function reads them; every other constant stays
    /// folded.
    #[arg(long)]
    pub runtime_parameters: bool,
    /// The link that carries the payload of --runtime-parameters (default: the end
    /// effector's link).
    #[arg(long, value_name = "LINK", requires = "runtime_parameters")]
    pub payload_link: Option<String>,
    /// No run-time CPU dispatch: by default std code on x86-64 also holds copies of each
    /// numeric function compiled for AVX-512 and for AVX2 with FMA, called when the CPU has
    /// them (results can then differ by the rounding of fused multiply-adds); with this flag,
    /// one copy, no `unsafe`, the same bits on every x86-64 CPU.
    #[arg(long)]
    pub no_cpu_dispatch: bool,
    /// Also generate, for each function that computes the sines and cosines of joint
    /// angles, a `*_from_sin_cos(q, sin_q, cos_q, ...)` variant that takes them from the
    /// caller, and `sin_cos(q)`, which computes them as the functions do (for a controller
    /// that calls several functions at one state: the sines and cosines once).
    #[arg(long)]
    pub sin_cos_variants: bool,
    /// Write the code to FILE instead of standard output.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

impl ModelArgs {
    /// The loader options.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            frames: (!self.frame.is_empty()).then(|| self.frame.clone()),
            tip: self.tip.clone(),
            lock: self.lock.clone(),
            gravity: self.gravity.map(Into::into),
            floating_base: self.floating_base,
            armature: self.armature.clone(),
            snap_angles: self.snap_angles,
        }
    }

    /// Loads the robot and applies the checks every front end shares
    /// ([`dynamics_gen::check_robot`]), so that `generate`, `stats`, `eval` and `joints`
    /// accept and refuse the same robots.
    pub fn load(&self) -> Result<Robot, String> {
        Ok(self.load_with_source()?.0)
    }

    /// [`ModelArgs::load`], and the source's name and bytes as the generated header records
    /// them (`<stdin>` for `-`, `shipped robot NAME`, or the path as given).
    pub fn load_with_source(&self) -> Result<(Robot, String, Option<Vec<u8>>), String> {
        use dynamics_gen::dynamics_model::{load, shipped};
        let spec = self.robot.as_str();
        let options = self.load_options();
        let (robot, name, bytes) = if spec == "-" {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut std::io::stdin().lock(), &mut text)
                .map_err(|e| format!("{}: cannot read standard input: {e}", load::STDIN_NAME))?;
            let robot = load::from_reader(text.as_bytes(), load::STDIN_NAME, &options);
            (robot, load::STDIN_NAME.to_string(), Some(text.into_bytes()))
        } else {
            let robot = load::load(spec, &options);
            match shipped::get(spec).filter(|_| !std::path::Path::new(spec).is_file()) {
                Some(s) => (
                    robot,
                    format!("shipped robot {spec}"),
                    Some(s.text.as_bytes().to_vec()),
                ),
                None => (robot, spec.to_string(), std::fs::read(spec).ok()),
            }
        };
        let robot = robot.map_err(|e| e.to_string())?;
        dynamics_gen::check_robot(&robot).map_err(|e| e.to_string())?;
        Ok((robot, name, bytes))
    }
}

fn parse_scalar(s: &str) -> Result<Scalar, String> {
    s.parse()
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.parse()
}

fn parse_format(s: &str) -> Result<dynamics_gen::equations::Format, String> {
    s.parse()
}

fn parse_select(s: &str) -> Result<dynamics_gen::equations::Select, String> {
    s.parse()
}

/// `GX,GY,GZ` → `[GX, GY, GZ]`.
pub fn parse_gravity(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || {
        format!("`{s}` is not a gravity vector: give three comma-separated numbers in m/s², like `0,0,-9.81`")
    };
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut g = [0.0; 3];
    for (gi, p) in g.iter_mut().zip(&parts) {
        *gi = p.parse::<f64>().map_err(|_| bad())?;
        if !gi.is_finite() {
            return Err(bad());
        }
    }
    Ok(g)
}

/// `JOINT=VALUE` → `(JOINT, VALUE)` for `--armature` (kg·m² or kg, ≥ 0).
pub fn parse_armature(s: &str) -> Result<(String, f64), String> {
    let bad = |why: &str| {
        format!("`{s}` is not an armature: {why}; write JOINT=VALUE with G²·I_rotor in kg·m² (kg for a prismatic joint), like `shoulder=0.12`")
    };
    let (joint, value) = s.split_once('=').ok_or_else(|| bad("there is no `=`"))?;
    let joint = joint.trim();
    if joint.is_empty() {
        return Err(bad("the joint name is empty"));
    }
    let value = parse_number(value.trim()).map_err(|e| bad(&e))?;
    if !(value.is_finite() && value >= 0.0) {
        return Err(bad("the value must be finite and ≥ 0"));
    }
    Ok((joint.to_string(), value))
}

/// `--friction-smoothing EPS`: finite and > 0.
fn parse_smoothing(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!(
            "`{s}` is not a smoothing velocity: give ε > 0 in rad/s or m/s, like `0.01`"
        )),
    }
}

/// `JOINT=VALUE` → `(JOINT, VALUE)`.
pub fn parse_lock(s: &str) -> Result<(String, f64), String> {
    let bad = |why: &str| {
        format!("`{s}` is not a joint lock: {why}; write JOINT=VALUE with the value in rad or m, like `gripper_joint=0.0`")
    };
    let (joint, value) = s.split_once('=').ok_or_else(|| bad("there is no `=`"))?;
    let joint = joint.trim();
    if joint.is_empty() {
        return Err(bad("the joint name is empty"));
    }
    let value = parse_number(value.trim()).map_err(|e| bad(&e))?;
    Ok((joint.to_string(), value))
}

/// A number as `robot!` reads one: a literal or constant arithmetic over the named constants
/// (`PI/2`, `-FRAC_PI_4`, `2*PI/3`); finite.
pub fn parse_number(text: &str) -> Result<f64, String> {
    use dynamics_gen::macro_support::number;
    if let Ok(x) = text.parse::<f64>() {
        return if x.is_finite() {
            Ok(x)
        } else {
            Err("the value is not finite".into())
        };
    }
    let tokens: proc_macro2::TokenStream = text
        .parse()
        .map_err(|_| format!("`{text}` is not a number ({})", number::allowed()))?;
    let tokens: Vec<proc_macro2::TokenTree> = tokens.into_iter().collect();
    if tokens.is_empty() {
        return Err("the value is empty".into());
    }
    number::evaluate(&tokens).map_err(|e| format!("`{text}`: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lock_values_take_constants() {
        assert_eq!(parse_lock("a=0.5").unwrap(), ("a".into(), 0.5));
        assert_eq!(
            parse_lock("a = PI/2").unwrap().1,
            std::f64::consts::FRAC_PI_2
        );
        assert_eq!(
            parse_lock("a=-FRAC_PI_4").unwrap().1,
            -std::f64::consts::FRAC_PI_4
        );
        assert_eq!(
            parse_lock("a=2*PI/3").unwrap().1,
            2.0 * std::f64::consts::PI / 3.0
        );
        assert!(parse_lock("a=inf").is_err());
        assert!(parse_lock("a=1/0").is_err());
        let e = parse_lock("a=PIE").unwrap_err();
        assert!(e.contains("PIE"), "{e}");
        assert!(parse_lock("a").unwrap_err().contains("no `=`"));
    }
}
