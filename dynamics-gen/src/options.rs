//! Options of the generator, shared by the Builder, the CLI and the macros.

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
    /// Emit `no_std` code: `sin`/`cos` through `libm`, only `::core` and nalgebra paths.
    pub no_std: bool,
    /// The path of the nalgebra crate in generated code (default `::nalgebra`).
    pub nalgebra_path: String,
    /// Loader options (gravity override, URDF tip and locked joints).
    pub load: LoadOptions,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            name: None,
            scalar: Scalar::F64,
            no_std: false,
            nalgebra_path: "::nalgebra".into(),
            load: LoadOptions::default(),
        }
    }
}

/// `ur5` → `Ur5`, `mr_3link` → `Mr3link`, `double-pendulum` → `DoublePendulum`.
pub fn upper_camel(name: &str) -> String {
    let mut out = String::new();
    let mut upper = true;
    for ch in name.chars() {
        if ch.is_ascii_alphanumeric() {
            if upper {
                out.extend(ch.to_uppercase());
            } else {
                out.push(ch);
            }
            upper = false;
        } else {
            upper = true;
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "Robot");
    }
    out
}
