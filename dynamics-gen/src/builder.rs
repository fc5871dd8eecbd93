//! The build.rs front end: generate a robot's dynamics into `OUT_DIR`, in the style of
//! `prost-build`.
//!
//! ```no_run
//! // build.rs, in `fn main()`; Cargo.toml: [build-dependencies] dynamics-gen = "0.1"
//! dynamics_gen::Builder::new("robots/my_arm.urdf") // relative to CARGO_MANIFEST_DIR
//!     .name("MyArm")
//!     .no_std(true)
//!     .lock("gripper_joint", 0.0)
//!     .compile_or_report();                        // errors as Cargo errors, no backtrace
//! ```
//!
//! The builder is owned: `let b = Builder::new("ur5").no_std(true);` can be stored, cloned
//! and reused. [`Builder::compile`] returns the error for the build script to handle;
//! [`Builder::compile_or_report`] prints it as `cargo::error=` lines (Cargo shows them as an
//! error of the build script and fails the build, without a panic backtrace).
//!
//! ```ignore
//! // src/lib.rs
//! pub mod my_arm {
//!     include!(concat!(env!("OUT_DIR"), "/my_arm.rs"));
//! }
//! ```
//!
//! A shipped robot is named instead of a path (`Builder::new("ur5")`); the one-line shortcut
//! with the default options is [`compile_robot`].

use crate::error::Error;
use crate::options::{Options, Scalar};
use dynamics_model::load::{self, Format};
use dynamics_model::{shipped, ModelError, Robot};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// Where a robot description comes from, once resolved.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Source {
    /// A robot file: the path as given and the path to read.
    File { given: String, path: PathBuf },
    /// A shipped robot, by name.
    Shipped(String),
}

/// Generates a robot's dynamics from a build script; see the [module docs](self).
#[derive(Clone, Debug)]
pub struct Builder {
    robot: String,
    options: Options,
    out_file: Option<String>,
    out_dir: Option<PathBuf>,
}

impl Builder {
    /// A builder for `robot`: a `.urdf`/`.toml` path (relative paths are taken relative to
    /// `CARGO_MANIFEST_DIR`, the directory of the crate being built) or the name of a shipped
    /// robot ([`dynamics_model::shipped::NAMES`]). An existing file wins over a shipped name.
    pub fn new(robot: impl Into<String>) -> Self {
        Self {
            robot: robot.into(),
            options: Options::default(),
            out_file: None,
            out_dir: None,
        }
    }

    /// The generated struct's name (default: the robot's name in UpperCamelCase).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.options.name = Some(name.into());
        self
    }

    /// The scalar type of the generated code (default `f64`).
    pub fn scalar(mut self, scalar: Scalar) -> Self {
        self.options.scalar = scalar;
        self
    }

    /// Emit `no_std` code (square roots, and the sines and cosines of angles beyond the
    /// generated `joint_sin_cos` helper's range, through `::libm`, so the crate must depend on `libm`;
    /// [`Builder::write`] warns when the crate's `Cargo.toml` declares no `libm` dependency).
    pub fn no_std(mut self, no_std: bool) -> Self {
        self.options.no_std = no_std;
        self
    }

    /// Replaces the robot's gravity vector (in the base frame {0}, m/s²).
    pub fn gravity(mut self, gravity: [f64; 3]) -> Self {
        self.options.load.gravity = Some(Vector3::from(gravity));
        self
    }

    /// Puts a free 6-DoF joint between the world and the robot's base (a URDF whose root
    /// joint is `floating`, or a TOML `[base] floating = true`, has one already): the
    /// generated functions then take `q = (p, quat (x, y, z, w), θ)` of length `NQ = n + 7`
    /// and `ν = (ω_b, v_b, θ̇)`, `τ = (m_b, f_b, τ_θ)` of length `NV = n + 6`, base twist and
    /// wrench in the base frame.
    pub fn floating_base(mut self, floating: bool) -> Self {
        self.options.load.floating_base = floating;
        self
    }

    /// URDF: the link whose frame is the end-effector frame {n+1}, whose pose and Jacobians
    /// `end_effector_pose`, `jacobian_space` and `jacobian_body` compute (default: the child
    /// link of the last movable joint).
    pub fn tip(mut self, link: impl Into<String>) -> Self {
        self.options.load.tip = Some(link.into());
        self
    }

    /// URDF: the links whose frames get `frame_poses`, `frame_jacobians_space` and
    /// `frame_jacobians_body` (feet, hands), in this order (`FRAME_NAMES`). Default: on a
    /// tree every leaf link of the file, on a serial chain none; an empty list asks for none.
    pub fn frames<I, S>(mut self, links: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        self.options.load.frames = Some(links.into_iter().map(Into::into).collect());
        self
    }

    /// URDF: locks the movable joint `joint` at `value` (rad or m), making it fixed. May be
    /// called several times.
    pub fn lock(mut self, joint: impl Into<String>, value: f64) -> Self {
        self.options.load.lock.push((joint.into(), value));
        self
    }

    /// The armature `G²·I_rotor` of joint `joint` (kg·m², kg for a prismatic joint), added
    /// to the mass matrix's diagonal (Pinocchio's `model.armature`), replacing the file's
    /// `rotor_inertia` and `gear_ratio` for that joint. May be called several times.
    pub fn armature(mut self, joint: impl Into<String>, value: f64) -> Self {
        self.options.load.armature.push((joint.into(), value));
        self
    }

    /// URDF: reads `rpy` angles within `tol` (rad, at most 1e-2) of a multiple of π/2 as
    /// that multiple ([`dynamics_model::LoadOptions::snap_angles`]; default 1e-9). For files
    /// that write `1.5708` for π/2: axis-aligned frames need far fewer operations. The robot
    /// changes by up to `tol`.
    pub fn snap_angles(mut self, tol: f64) -> Self {
        self.options.load.snap_angles = Some(tol);
        self
    }

    /// How the dynamics are derived: [`crate::Method::NewtonEuler`] (the default) or
    /// [`crate::Method::Lagrangian`] (the Euler–Lagrange equations of `K − P` by symbolic
    /// differentiation). The generated functions and their numbers are the same.
    pub fn method(mut self, method: crate::Method) -> Self {
        self.options.method = method;
        self
    }

    /// Leave gravity and a payload open until run time: the generated struct gets the public
    /// fields `gravity`, `payload_mass`, `payload_com` and `payload_inertia` (`Default`: the
    /// robot's gravity, no payload) and every function reads them; every other constant
    /// stays folded. The payload is carried by the end effector's link, or by
    /// [`Builder::payload_link`].
    pub fn runtime_parameters(mut self) -> Self {
        self.options.runtime_parameters = true;
        self
    }

    /// Run-time CPU dispatch (default `true`; `std` code only): on x86-64 each numeric
    /// function also gets copies compiled for AVX-512 and for AVX2 with FMA, called when the
    /// CPU has them (1.3–1.5× faster on the Panda than the default target's SSE2 code with
    /// AVX-512, 1.3–1.8× with AVX2; results can differ by the rounding of fused
    /// multiply-adds). `false`: one copy, no `unsafe` in the generated code,
    /// the same bits on every x86-64 CPU.
    pub fn cpu_dispatch(mut self, dispatch: bool) -> Self {
        self.options.cpu_dispatch = dispatch;
        self
    }

    /// Also generate, for each function that computes the sines and cosines of joint
    /// angles, a `*_from_sin_cos(q, sin_q, cos_q, …)` variant that takes them from the
    /// caller, and `sin_cos(q)` that computes them as the functions do (default `false`): a
    /// controller that needs several functions at one state computes them once
    /// (see [`crate::emit::given_sin_cos`]).
    pub fn sin_cos_variants(mut self, variants: bool) -> Self {
        self.options.sin_cos_variants = variants;
        self
    }

    /// The link that carries the payload of [`Builder::runtime_parameters`] (which this
    /// turns on).
    pub fn payload_link(mut self, link: impl Into<String>) -> Self {
        self.options.runtime_parameters = true;
        self.options.payload_link = Some(link.into());
        self
    }

    /// Include the joints' friction (`b q̇ + μ sgn(q̇)` from the robot file) in
    /// `inverse_dynamics`, `forward_dynamics`, their `_with_tip` forms and
    /// `constrained_forward_dynamics`. Off by default (URDF damping values are often
    /// placeholders, and Pinocchio's `rnea` leaves them out); `friction(qd)` exists either
    /// way.
    pub fn friction(mut self) -> Self {
        if self.options.friction.is_none() {
            self.options.friction = Some(crate::options::Friction::Coulomb);
        }
        self
    }

    /// [`Builder::friction`] with the smooth Coulomb model `μ tanh(q̇/ε)` (ε in rad/s or
    /// m/s, > 0; checked when generating), for simulation.
    pub fn friction_smoothing(mut self, eps: f64) -> Self {
        self.options.friction = Some(crate::options::Friction::Smooth(eps));
        self
    }

    /// The path of the nalgebra crate in the generated code (default `::nalgebra`).
    pub fn nalgebra_path(mut self, path: impl Into<String>) -> Self {
        self.options.nalgebra_path = path.into();
        self
    }

    /// The path of the `dynamics-runtime` crate in the generated code (default
    /// `::dynamics_runtime`), whose `Dynamics` trait the generated struct implements.
    pub fn runtime_path(mut self, path: impl Into<String>) -> Self {
        self.options.runtime_path = Some(path.into());
        self
    }

    /// Generates only the named functions ([`crate::options::FUNCTIONS`]; default all), for
    /// smaller code and faster builds. The runtime trait needs `mass_matrix`, `coriolis`,
    /// `gravity`, `inverse_dynamics` and `forward_dynamics` (or [`Builder::no_runtime_trait`]).
    pub fn functions<I, S>(mut self, names: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        self.options.functions = Some(names.into_iter().map(Into::into).collect());
        self
    }

    /// No `impl dynamics_runtime::Dynamics`: the generated code then needs only nalgebra
    /// (and libm for `no_std`), and the crate no `dynamics-runtime` dependency.
    pub fn no_runtime_trait(mut self) -> Self {
        self.options.runtime_path = None;
        self
    }

    /// The generated file's name in the output directory (default `<robot>.rs`, where
    /// `<robot>` is the robot file's stem or the shipped robot's name).
    pub fn out_file(mut self, file_name: impl Into<String>) -> Self {
        self.out_file = Some(file_name.into());
        self
    }

    /// The output directory (default: the `OUT_DIR` cargo gives build scripts).
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// The generator options collected so far.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Loads and validates the robot, with the tip, locks and gravity applied.
    pub fn load(&self) -> Result<Robot, Error> {
        Ok(self.load_with_source()?.0)
    }

    /// The formatted generated file, without touching the file system (beyond reading the
    /// robot file) or printing anything.
    pub fn generate(&self) -> Result<String, Error> {
        if let Some(name) = &self.options.name {
            crate::options::check_struct_name(name)?;
        }
        let (robot, source, text) = self.load_with_source()?;
        let name = match &source {
            Source::File { given, .. } => given.clone(),
            Source::Shipped(name) => format!("shipped robot {name}"),
        };
        let provenance = crate::Provenance::of_bytes(name, text.as_bytes())
            .command(format!("cargo build (build.rs: {})", self.call()));
        crate::emit::generate_file(&robot, &self.options, provenance)
    }

    /// The builder as the Rust call chain that makes it, for the generated header.
    fn call(&self) -> String {
        let o = &self.options;
        let mut s = format!(
            "dynamics_gen::Builder::new({:?})",
            crate::emit::provenance::portable(&self.robot)
        );
        if let Some(name) = &o.name {
            s += &format!(".name({name:?})");
        }
        if o.scalar != Scalar::F64 {
            s += &format!(".scalar(Scalar::{:?})", o.scalar);
        }
        if o.no_std {
            s += ".no_std(true)";
        }
        if !o.cpu_dispatch {
            s += ".cpu_dispatch(false)";
        }
        if o.sin_cos_variants {
            s += ".sin_cos_variants(true)";
        }
        if let Some(g) = o.load.gravity {
            s += &format!(".gravity([{:?}, {:?}, {:?}])", g[0], g[1], g[2]);
        }
        if o.load.floating_base {
            s += ".floating_base(true)";
        }
        if let Some(tip) = &o.load.tip {
            s += &format!(".tip({tip:?})");
        }
        if let Some(frames) = &o.load.frames {
            s += &format!(".frames({frames:?})");
        }
        if let Some(functions) = &o.functions {
            s += &format!(".functions({functions:?})");
        }
        match &o.payload_link {
            Some(link) => s += &format!(".payload_link({link:?})"),
            None if o.runtime_parameters => s += ".runtime_parameters()",
            None => {}
        }
        for (joint, value) in &o.load.lock {
            s += &format!(".lock({joint:?}, {value:?})");
        }
        match &o.runtime_path {
            None => s += ".no_runtime_trait()",
            Some(p) if Some(p) != Options::default().runtime_path.as_ref() => {
                s += &format!(".runtime_path({p:?})")
            }
            Some(_) => {}
        }
        if o.nalgebra_path != Options::default().nalgebra_path {
            s += &format!(".nalgebra_path({:?})", o.nalgebra_path);
        }
        s + ".compile()"
    }

    /// [`Builder::compile`] for a build script that should fail the way Cargo reports
    /// errors: on error, every line of the message is printed as `cargo::error=…` (Cargo
    /// shows it under the crate's name and fails the build) and `None` is returned; no panic,
    /// no backtrace.
    pub fn compile_or_report(&self) -> Option<PathBuf> {
        match self.compile() {
            Ok(path) => Some(path),
            Err(e) => {
                for line in cargo_errors(&e) {
                    println!("{line}");
                }
                None
            }
        }
    }

    /// Generates the file into the output directory, rewriting it only when its content
    /// changed (so cargo does not rebuild needlessly), and prints
    /// `cargo:rerun-if-changed=<robot file>` when the robot is a file. Returns the path written.
    pub fn write(&self) -> Result<PathBuf, Error> {
        let source = self.resolve();
        let code = self.generate()?;
        let dir = match &self.out_dir {
            Some(dir) => dir.clone(),
            None => std::env::var_os("OUT_DIR")
                .map(PathBuf::from)
                .ok_or_else(|| Error::Io {
                    path: "OUT_DIR".into(),
                    message: "OUT_DIR is not set: call write() from a build script, or give the directory with .out_dir(..)".into(),
                })?,
        };
        let path = dir.join(self.file_name(&source));
        write_if_changed(&path, &code)?;
        if let Source::File { path: robot, .. } = &source {
            println!("cargo:rerun-if-changed={}", robot.display());
        }
        if let Some(dir) = std::env::var_os("CARGO_MANIFEST_DIR") {
            for hint in crate::manifest::missing_dependencies(Path::new(&dir), &self.options) {
                println!("cargo::warning={hint}");
            }
        }
        Ok(path)
    }

    /// The same as [`Builder::write`] (the name prost-build users expect).
    pub fn compile(&self) -> Result<PathBuf, Error> {
        self.write()
    }

    fn file_name(&self, source: &Source) -> String {
        if let Some(name) = &self.out_file {
            return name.clone();
        }
        let stem = match source {
            Source::File { path, .. } => path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "robot".into()),
            Source::Shipped(name) => name.clone(),
        };
        format!("{stem}.rs")
    }

    /// Where the robot comes from: a file (relative to `CARGO_MANIFEST_DIR`) or a shipped name.
    fn resolve(&self) -> Source {
        let given = Path::new(&self.robot);
        let path = match std::env::var_os("CARGO_MANIFEST_DIR") {
            Some(dir) if given.is_relative() => Path::new(&dir).join(given),
            _ => given.to_path_buf(),
        };
        if !path.is_file() && shipped::get(&self.robot).is_some() {
            return Source::Shipped(self.robot.clone());
        }
        Source::File {
            given: self.robot.clone(),
            path,
        }
    }

    /// The robot, where it came from, and the text it was read from.
    fn load_with_source(&self) -> Result<(Robot, Source, String), Error> {
        let source = self.resolve();
        let mut read = String::new();
        let robot = match &source {
            Source::Shipped(name) => {
                read = shipped::get(name)
                    .map(|s| s.text.to_string())
                    .unwrap_or_default();
                load::load(name, &self.options.load)?
            }
            Source::File { given, path } => {
                let looks_like_file = Format::from_path(path).is_some()
                    || given.contains('/')
                    || given.contains('\\');
                if !path.is_file() && !looks_like_file {
                    // Neither a file nor a shipped name: the model's error lists the shipped robots.
                    load::load(given, &self.options.load)?
                } else {
                    let format = Format::from_path(path).ok_or_else(|| ModelError::Io {
                        file: path.display().to_string(),
                        message: load::UNKNOWN_FILE_TYPE.into(),
                    })?;
                    let text = load::read_text(path, &path.display().to_string())?;
                    // Named as given, so the generated file does not depend on the machine.
                    let robot = load::from_str(&text, format, given, &self.options.load)?;
                    read = text;
                    robot
                }
            }
        };
        Ok((robot, source, read))
    }
}

/// `e` as `cargo::error=` build-script lines, one per line of its message.
fn cargo_errors(e: &Error) -> Vec<String> {
    e.to_string()
        .lines()
        .map(|line| format!("cargo::error={line}"))
        .collect()
}

/// Writes `code` to `path` unless the file already holds exactly `code`.
fn write_if_changed(path: &Path, code: &str) -> Result<(), Error> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == code) {
        return Ok(());
    }
    std::fs::write(path, code).map_err(|e| Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// The one-line build.rs: generates `robot` (a path relative to `CARGO_MANIFEST_DIR`, or a
/// shipped name) with the default options into `OUT_DIR/<robot>.rs`.
///
/// ```no_run
/// // build.rs, in `fn main()`
/// dynamics_gen::compile_robot("robots/ur5.urdf").unwrap_or_else(|e| panic!("{e}"));
/// ```
pub fn compile_robot(robot: &str) -> Result<PathBuf, Error> {
    Builder::new(robot).compile()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(tag: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("dynamics-gen-builder-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn shipped_name_generates_a_header_naming_it() {
        let code = Builder::new("pendulum").no_std(true).generate().unwrap();
        assert!(code.starts_with("// @generated by dynamics-gen"), "{code}");
        assert!(
            code.contains("Source: `shipped robot pendulum` (sha256 "),
            "{code}"
        );
        assert!(code.contains("::libm::"));
    }

    #[test]
    fn unknown_name_lists_the_shipped_robots() {
        let err = Builder::new("no_such_robot").generate().unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("no_such_robot") && msg.contains("pendulum"),
            "{msg}"
        );
    }

    #[test]
    fn missing_file_names_the_file() {
        let err = Builder::new("robots/missing.urdf").generate().unwrap_err();
        assert!(err.to_string().contains("missing.urdf"), "{err}");
    }

    #[test]
    fn write_uses_the_default_file_name_and_keeps_an_unchanged_file() {
        let dir = temp_dir("write");
        let b = Builder::new("pendulum").out_dir(&dir).name("Pend");
        let path = b.write().unwrap();
        assert_eq!(path, dir.join("pendulum.rs"));
        let code = std::fs::read_to_string(&path).unwrap();
        assert!(code.contains("pub struct Pend"));
        let modified = std::fs::metadata(&path).unwrap().modified().unwrap();
        std::thread::sleep(std::time::Duration::from_millis(20));
        b.write().unwrap();
        assert_eq!(
            std::fs::metadata(&path).unwrap().modified().unwrap(),
            modified
        );
        let other = b.clone().out_file("p.rs").write().unwrap();
        assert_eq!(other, dir.join("p.rs"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn robot_file_is_named_as_given_and_gives_the_file_name() {
        let dir = temp_dir("file");
        let robot = dir.join("my_pendulum.toml");
        std::fs::write(&robot, shipped::get("pendulum").unwrap().text).unwrap();
        let given = robot.to_str().unwrap().to_string();
        let b = Builder::new(given.clone()).out_dir(&dir);
        let code = b.generate().unwrap();
        assert!(
            code.contains("Source: `my_pendulum.toml` (sha256 "),
            "{code}"
        );
        assert!(!code.contains(dir.to_str().unwrap()), "{code}");
        assert!(code.contains("pub struct Pendulum;"));
        assert_eq!(b.write().unwrap(), dir.join("my_pendulum.rs"));
        std::fs::write(&robot, "name = ").unwrap();
        let err = b.generate().unwrap_err().to_string();
        assert!(err.contains("my_pendulum.toml"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn errors_become_one_cargo_error_line_each() {
        let e = Builder::new("no_such_robot").generate().unwrap_err();
        let lines = cargo_errors(&e);
        assert_eq!(lines.len(), e.to_string().lines().count());
        assert!(
            lines[0].starts_with("cargo::error=unknown robot `no_such_robot`"),
            "{lines:?}"
        );
        // A multi-line model error (two invalid fields) gives one directive per line.
        let text = shipped::get("pendulum")
            .unwrap()
            .text
            .replace("mass = 2.0", "mass = -2.0");
        let dir = temp_dir("report");
        let robot = dir.join("bad.toml");
        std::fs::write(&robot, text).unwrap();
        let e = Builder::new(robot.to_string_lossy().into_owned())
            .generate()
            .unwrap_err();
        let lines = cargo_errors(&e);
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(lines
            .iter()
            .all(|l| l.starts_with("cargo::error=") && !l.contains('\n')));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn gravity_override_reaches_the_code() {
        let code = Builder::new("pendulum")
            .gravity([0.0, 0.0, -1.62])
            .generate()
            .unwrap();
        assert!(code.contains("-1.62"), "{code}");
    }
}
