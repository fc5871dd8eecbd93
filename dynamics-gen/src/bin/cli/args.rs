//! Command-line arguments (clap derive) and the parsers of `--gravity` and `--lock`.

use clap::{Args, Parser, Subcommand};
use dynamics_gen::dynamics_model::{LoadOptions, Robot};
use dynamics_gen::Scalar;
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
    Stats(ModelArgs),
    /// Evaluate the reference dynamics on states read as JSON lines from stdin.
    ///
    /// Each input line is `{"q": [...], "qd": [...], "qdd": [...], "tau": [...], "f_tip": [...]}`
    /// (all but `q` optional, default zero; `f_tip` = (m, f) applied by the end effector, in
    /// {n+1}). Each output line holds `mass_matrix`, `coriolis`, `gravity`,
    /// `inverse_dynamics`, `forward_dynamics`, `coriolis_matrix` and `end_effector_pose`
    /// (matrices as lists of rows).
    Eval(ModelArgs),
    /// List the movable joints in vector order: name, type, screw axis S_i in {0}, limits.
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
    /// URDF: lock a movable joint at a value (rad or m), making it fixed; repeatable.
    #[arg(long, value_name = "JOINT=VALUE", value_parser = parse_lock)]
    pub lock: Vec<(String, f64)>,
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
    /// Emit no_std code (sin/cos through `::libm`).
    #[arg(long)]
    pub no_std: bool,
    /// The path of the nalgebra crate in the generated code.
    #[arg(long, default_value = "::nalgebra", value_name = "PATH")]
    pub nalgebra_path: String,
    /// Write the code to FILE instead of standard output.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

impl ModelArgs {
    /// The loader options.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            tip: self.tip.clone(),
            lock: self.lock.clone(),
            gravity: self.gravity.map(Into::into),
        }
    }

    /// Loads the robot and applies the checks every front end shares
    /// ([`dynamics_gen::check_robot`]), so that `generate`, `stats`, `eval` and `joints`
    /// accept and refuse the same robots.
    pub fn load(&self) -> Result<Robot, String> {
        let robot = dynamics_gen::dynamics_model::load(&self.robot, &self.load_options())
            .map_err(|e| e.to_string())?;
        dynamics_gen::check_robot(&robot).map_err(|e| e.to_string())?;
        Ok(robot)
    }
}

fn parse_scalar(s: &str) -> Result<Scalar, String> {
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
    let value: f64 = value
        .trim()
        .parse()
        .map_err(|_| bad("the value is not a number"))?;
    if !value.is_finite() {
        return Err(bad("the value is not finite"));
    }
    Ok((joint.to_string(), value))
}
