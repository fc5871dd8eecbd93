//! Loading a robot from a file, a string or a shipped name, with the options every front end
//! (CLI, build.rs, macros) shares.

use crate::error::{Invalid, ModelError, Subject};
use crate::robot::Robot;
use nalgebra::Vector3;
use std::path::Path;

/// The format of a robot description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The TOML robot file of [`crate::toml_format`].
    Toml,
    /// URDF, read by [`crate::urdf`].
    Urdf,
}

impl Format {
    /// The format for a file name, by its extension (`.toml`, `.urdf` or `.xml`).
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "toml" => Some(Format::Toml),
            "urdf" | "xml" => Some(Format::Urdf),
            _ => None,
        }
    }
}

/// Options applied while loading.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// URDF: the link whose frame is the end-effector frame {n+1}, any link of the robot
    /// (default: the child link of the last movable joint in the joint order).
    pub tip: Option<String>,
    /// URDF: movable joints to turn into fixed ones at the given value (rad or m), so that
    /// their links merge into the body they hang from (e.g. gripper fingers).
    pub lock: Vec<(String, f64)>,
    /// Replaces the description's gravity vector (in {0}, m/s²).
    pub gravity: Option<Vector3<f64>>,
    /// Puts a free 6-DoF joint between the world and the base ([`crate::Base::floating`]);
    /// a description may also ask for one itself (a URDF root joint of type `floating`).
    pub floating_base: bool,
    /// URDF: the links whose frames the generated code computes the pose and Jacobians of
    /// ([`crate::Robot::frames`]), in this order. `None`: on a tree, every leaf link (a link
    /// nothing hangs from: feet, hands, sensors) in depth-first order; on a serial chain
    /// none (the end effector has its own functions).
    pub frames: Option<Vec<String>>,
    /// Per joint, the armature `G² I_rotor` (kg·m² for a revolute joint, kg for a prismatic
    /// one) added to the mass matrix's diagonal (Modern Robotics §8.9.2, Pinocchio's
    /// `model.armature`): replaces the joint's `rotor_inertia` and `gear_ratio` from the
    /// file by `rotor_inertia = value, gear_ratio = 1`. Any format; an unknown joint or a
    /// negative or non-finite value is refused.
    pub armature: Vec<(String, f64)>,
    /// URDF: `rpy` angles of `<origin>`s (joints' and inertials') within this distance (rad)
    /// of a multiple of π/2 are read as that multiple, so that a file that writes `1.5708`
    /// for π/2 gets the exact right-angle frames (and the generated code the few operations
    /// of axis-aligned joints). `None`: 1e-9 ([`crate::urdf::origin::SNAP_TOL`]), the decimals of π/2
    /// only. The robot is then the file's robot with those angles changed by up to this
    /// much: opt in knowingly (at most 1e-2; refused for TOML files, which can write exact
    /// angles or matrices).
    pub snap_angles: Option<f64>,
}

/// The largest [`LoadOptions::snap_angles`] accepted (rad).
pub const MAX_SNAP_ANGLES: f64 = 1e-2;

/// The name standard input has in errors.
pub const STDIN_NAME: &str = "<stdin>";

/// Loads `spec`: a path to a `.toml` or `.urdf` file, the name of a shipped robot
/// ([`crate::shipped::NAMES`]), or `-` for standard input ([`from_reader`], format sniffed,
/// named `<stdin>` in errors). An existing file wins over a shipped name.
pub fn load(spec: &str, options: &LoadOptions) -> Result<Robot, ModelError> {
    if spec == "-" {
        return from_reader(std::io::stdin().lock(), STDIN_NAME, options);
    }
    let path = Path::new(spec);
    // A directory gets its own message from `read_text`.
    if path.is_file() || path.is_dir() {
        return load_file(path, options);
    }
    if let Some(shipped) = crate::shipped::get(spec) {
        return from_str(shipped.text, shipped.format, shipped.file, options);
    }
    if Format::from_path(path).is_some() || spec.contains('/') || spec.contains('\\') {
        return Err(ModelError::Io {
            file: spec.to_string(),
            message: "no such file; fix: check the path (a relative path starts from the current directory)".into(),
        });
    }
    Err(ModelError::UnknownRobot {
        name: spec.to_string(),
        known: crate::shipped::NAMES
            .iter()
            .map(|s| s.to_string())
            .collect(),
    })
}

/// Loads a robot file; the format comes from the extension.
pub fn load_file(path: &Path, options: &LoadOptions) -> Result<Robot, ModelError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    let format = Format::from_path(path).ok_or_else(|| ModelError::Io {
        file: file.clone(),
        message: UNKNOWN_FILE_TYPE.into(),
    })?;
    from_str(&text, format, &file, options)
}

/// What is wrong with a robot file whose extension is not `.toml`, `.urdf` or `.xml`, and the
/// fix (every front end says it the same way).
pub const UNKNOWN_FILE_TYPE: &str =
    "unknown file type; fix: give a robot file ending in `.toml` or `.urdf` (or `.xml`)";

/// The text of the robot file at `path`, named `file` in errors: refused when it is a
/// directory, larger than [`MAX_FILE_BYTES`] or not UTF-8 (located at its first bad byte); a
/// leading byte-order mark is dropped.
pub fn read_text(path: &Path, file: &str) -> Result<String, ModelError> {
    let io = |e: std::io::Error| ModelError::Io {
        file: file.to_string(),
        message: e.to_string(),
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() {
        return Err(ModelError::Io {
            file: file.to_string(),
            message: "it is a directory; fix: give the path of a `.toml` or `.urdf` file".into(),
        });
    }
    if meta.len() > MAX_FILE_BYTES as u64 {
        return Err(too_large(file));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    decode(&bytes, file).map(str::to_string)
}

/// The largest robot file read (16 MiB). The largest robot descriptions in use (humanoids'
/// URDFs) are a few hundred kilobytes; a bigger file is the wrong file, and is refused before
/// it is read, whatever its size.
pub const MAX_FILE_BYTES: usize = 16 << 20;

fn too_large(file: &str) -> ModelError {
    ModelError::Io {
        file: file.to_string(),
        message: format!(
            "it is larger than {} MiB, the most a robot file is read to; fix: give the robot's \
             `.toml` or `.urdf` file (meshes stay in files of their own)",
            MAX_FILE_BYTES >> 20
        ),
    }
}

/// `bytes` as UTF-8 text without a leading byte-order mark; invalid UTF-8 is an error at
/// the line and column of the first bad byte.
fn decode<'a>(bytes: &'a [u8], file: &str) -> Result<&'a str, ModelError> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let good = &bytes[..e.valid_up_to()];
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        // Columns count characters, as the parsers' do.
        let column = 1 + String::from_utf8_lossy(&good[line_start..]).chars().count();
        ModelError::Parse {
            file: file.to_string(),
            line,
            column,
            message: format!(
                "the file is not UTF-8 text (byte 0x{:02x} at offset {}); fix: save it as UTF-8",
                bytes[e.valid_up_to()],
                e.valid_up_to()
            ),
        }
    })
}

/// The format of a description without a file name: URDF when its first non-whitespace
/// character is `<` (XML), TOML otherwise.
pub fn sniff(text: &str) -> Format {
    if text.trim_start().starts_with('<') {
        Format::Urdf
    } else {
        Format::Toml
    }
}

/// Reads a robot description from `reader` (e.g. standard input) to its end, sniffs its
/// format ([`sniff`]), parses and validates it; `name` names it in errors.
pub fn from_reader(
    reader: impl std::io::Read,
    name: &str,
    options: &LoadOptions,
) -> Result<Robot, ModelError> {
    use std::io::Read;
    let mut bytes = Vec::new();
    reader
        .take(MAX_FILE_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ModelError::Io {
            file: name.to_string(),
            message: e.to_string(),
        })?;
    if bytes.len() > MAX_FILE_BYTES {
        return Err(too_large(name));
    }
    // A byte-order mark is not part of the description.
    let text = decode(&bytes, name)?;
    from_str(text, sniff(text), name, options)
}

/// Parses and validates a robot description held in memory; `file` names it in errors.
pub fn from_str(
    text: &str,
    format: Format,
    file: &str,
    options: &LoadOptions,
) -> Result<Robot, ModelError> {
    let robot = parse(text, format, file, options)?;
    robot.validate().map_err(|e| e.in_file(file))?;
    Ok(robot)
}

/// Parses (without the physical validation) and applies the gravity override.
fn parse(
    text: &str,
    format: Format,
    file: &str,
    options: &LoadOptions,
) -> Result<Robot, ModelError> {
    if let Some(tol) = options.snap_angles {
        if !(0.0..=MAX_SNAP_ANGLES).contains(&tol) {
            return Err(ModelError::BadOption {
                file: file.to_string(),
                message: format!("snap_angles must be between 0 and {MAX_SNAP_ANGLES:e} rad, found {tol:e}: give the largest distance (rad) from a multiple of π/2 that should count as exact, e.g. 1e-5 for files that write 1.5708"),
            });
        }
    }
    let nonempty = || {
        if text.trim().is_empty() {
            return Err(ModelError::Parse {
                file: file.to_string(),
                line: 1,
                column: 1,
                message: "the file is empty; fix: give the robot's description (TOML or URDF)"
                    .into(),
            });
        }
        Ok(())
    };
    let mut robot = match format {
        Format::Toml => {
            if options.snap_angles.is_some() {
                return Err(ModelError::BadOption {
                    file: file.to_string(),
                    message: "`snap_angles` applies to URDF files only; write exact angles (1.5707963267948966) or 4×4 matrices in a TOML file".into(),
                });
            }
            if options.tip.is_some() || !options.lock.is_empty() {
                return Err(ModelError::BadOption {
                    file: file.to_string(),
                    message: "`tip` and `lock` apply to URDF files only; a TOML file states its chain and end effector itself".into(),
                });
            }
            nonempty()?;
            crate::toml_format::from_str(text, file)?
        }
        Format::Urdf => {
            nonempty()?;
            crate::urdf::from_str(text, file, options)?
        }
    };
    if let Some(g) = options.gravity {
        robot.gravity = g;
    }
    if options.floating_base {
        robot.base.floating = true;
    }
    apply_armature(&mut robot, &options.armature).map_err(|e| e.in_file(file))?;
    Ok(robot)
}

/// [`LoadOptions::armature`] onto the robot's joints.
fn apply_armature(robot: &mut Robot, armature: &[(String, f64)]) -> Result<(), ModelError> {
    let mut errors = Vec::new();
    for (name, value) in armature {
        let Some((index, joint)) = robot
            .joints
            .iter_mut()
            .enumerate()
            .find(|(_, j)| &j.name == name)
        else {
            let known: Vec<&str> = robot.joints.iter().map(|j| j.name.as_str()).collect();
            errors.push(Invalid::new(
                Subject::Joint {
                    index: None,
                    name: name.clone(),
                },
                "armature",
                "no movable joint has this name",
                format!("give one of {}", known.join(", ")),
            ));
            continue;
        };
        if !(value.is_finite() && *value >= 0.0) {
            errors.push(Invalid::new(
                Subject::Joint {
                    index: Some(index),
                    name: name.clone(),
                },
                "armature",
                format!("must be finite and ≥ 0, found {value}"),
                "give the reflected rotor inertia G²·I_rotor (kg·m² or kg), ≥ 0",
            ));
            continue;
        }
        joint.rotor_inertia = *value;
        joint.gear_ratio = 1.0;
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(ModelError::Invalid(errors))
    }
}
