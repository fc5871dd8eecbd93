//! `#[derive(Dynamics)] #[dynamics(file = "…", …)]`: the attribute's options, the robot
//! file's path, and loading it.

use super::number;
use super::value::{parse_value, Errors};
use crate::options::{Options, Scalar};
use dynamics_model::{Format, LoadOptions, ModelError, Robot};
use nalgebra::Vector3;
use proc_macro2::TokenTree;
use quote::ToTokens;
use std::path::{Path, PathBuf};

/// The environment variable that, when set, replaces `CARGO_MANIFEST_DIR` as the directory
/// relative robot paths are resolved against (for test harnesses such as trybuild, which
/// build test crates in a directory of their own).
pub const MANIFEST_DIR_OVERRIDE: &str = "DYNAMICS_GEN_MANIFEST_DIR";

/// The options of one `#[dynamics(..)]` attribute.
pub struct Attr {
    /// `file = "…"`: the path as written, and its literal.
    pub file: Option<syn::LitStr>,
    /// Generator options (`scalar`, `no_std`, `nalgebra`, `gravity`, `floating_base`, `tip`, `frames`,
    /// `lock`).
    pub options: Options,
}

/// The constant expression after `=` (`1e-5`, `PI / 4`, `-0.3`) as a number, or `None` with the
/// error accumulated on its tokens: [`number::evaluate`]'s, or `bad(x)`'s when it says what
/// is wrong with the value.
fn number_value(
    value: syn::parse::ParseStream<'_>,
    errors: &mut Errors,
    bad: impl Fn(f64) -> Option<String>,
) -> syn::Result<Option<f64>> {
    let expr: syn::Expr = value.parse()?;
    let tokens: Vec<TokenTree> = expr.to_token_stream().into_iter().collect();
    Ok(match number::evaluate(&tokens) {
        Ok(x) => match bad(x) {
            None => Some(x),
            Some(problem) => {
                errors.at(&expr, problem);
                None
            }
        },
        Err(e) => {
            errors.push(e);
            None
        }
    })
}

/// With `runtime_parameters` the generated methods read the struct's fields `gravity`,
/// `payload_mass`, `payload_com` and `payload_inertia` (the fields `robot!` and generated
/// files declare): a struct without them gets one error naming what to declare.
fn check_runtime_fields(input: &syn::DeriveInput, errors: &mut Errors) {
    let names: Vec<String> = match &input.data {
        syn::Data::Struct(s) => s
            .fields
            .iter()
            .filter_map(|f| f.ident.as_ref().map(ToString::to_string))
            .collect(),
        _ => Vec::new(),
    };
    let missing: Vec<&str> = crate::expand::parameters::FIELDS
        .iter()
        .map(|f| f.name)
        .filter(|n| !names.iter().any(|x| x == n))
        .collect();
    if !missing.is_empty() {
        errors.at(
            &input.ident,
            format!(
                "with `runtime_parameters` the generated methods read the struct's fields: declare {} (gravity: [S; 3] in m/s², payload_mass: S in kg, payload_com: [S; 3] in m, payload_inertia: [S; 6] in kg·m², S the scalar type; the generated `DEFAULT_GRAVITY` holds the robot file's gravity), or use `robot!` or a generated file, which declare them and their `Default`",
                missing.iter().map(|m| format!("`{m}`")).collect::<Vec<_>>().join(", ")
            ),
        );
    }
}

/// Reads every `#[dynamics(..)]` attribute of `input`; errors are accumulated.
pub fn parse_attrs(input: &syn::DeriveInput, errors: &mut Errors) -> Attr {
    let mut attr = Attr {
        file: None,
        options: Options {
            name: Some(input.ident.to_string()),
            ..Options::default()
        },
    };
    let mut any = false;
    for a in input.attrs.iter().filter(|a| a.path().is_ident("dynamics")) {
        any = true;
        let result = a.parse_nested_meta(|meta| {
            let key = meta
                .path
                .get_ident()
                .map(ToString::to_string)
                .unwrap_or_default();
            match key.as_str() {
                "file" => {
                    let lit: syn::LitStr = meta.value()?.parse()?;
                    if attr.file.is_some() {
                        errors.at(&meta.path, "duplicate option `file`");
                    }
                    attr.file = Some(lit);
                }
                "scalar" => {
                    let lit: syn::LitStr = meta.value()?.parse()?;
                    match lit.value().parse::<Scalar>() {
                        Ok(s) => attr.options.scalar = s,
                        Err(e) => errors.at(&lit, e),
                    }
                }
                "no_std" => attr.options.no_std = true,
                "no_cpu_dispatch" => attr.options.cpu_dispatch = false,
                "sin_cos_variants" => attr.options.sin_cos_variants = true,
                "floating_base" => attr.options.load.floating_base = true,
                "no_runtime_trait" => attr.options.runtime_path = None,
                "runtime" => {
                    let path: syn::Path = meta.value()?.parse()?;
                    attr.options.runtime_path =
                        Some(path.to_token_stream().to_string().replace(' ', ""));
                }
                "nalgebra" => {
                    let path: syn::Path = meta.value()?.parse()?;
                    attr.options.nalgebra_path = path
                        .to_token_stream()
                        .to_string()
                        .replace(' ', "");
                }
                "gravity" => {
                    let tt: TokenTree = meta.value()?.parse()?;
                    let v = parse_value(std::slice::from_ref(&tt), errors);
                    if let Some(g) = v.numbers(errors) {
                        match <[f64; 3]>::try_from(g.as_slice()) {
                            Ok(g) => attr.options.load.gravity = Some(Vector3::from(g)),
                            Err(_) => errors.at(
                                &tt,
                                format!("`gravity` needs 3 numbers [gx, gy, gz] in m/s², found {}", g.len()),
                            ),
                        }
                    }
                }
                "tip" => {
                    let lit: syn::LitStr = meta.value()?.parse()?;
                    attr.options.load.tip = Some(lit.value());
                }
                "functions" => {
                    let mut names = Vec::new();
                    meta.parse_nested_meta(|inner| match inner.path.get_ident() {
                        Some(f) => {
                            names.push(f.to_string());
                            Ok(())
                        }
                        None => Err(inner.error("expected function names: `functions(mass_matrix, gravity)`")),
                    })?;
                    attr.options.functions = Some(names);
                }
                "frames" => {
                    let mut links = Vec::new();
                    meta.parse_nested_meta(|inner| {
                        match inner.path.get_ident() {
                            Some(link) if inner.input.is_empty() || inner.input.peek(syn::Token![,]) => {
                                links.push(link.to_string());
                                Ok(())
                            }
                            _ => Err(inner.error("expected link names: `frames(LF_FOOT, RF_FOOT)`")),
                        }
                    })?;
                    attr.options.load.frames = Some(links);
                }
                "lock" => {
                    meta.parse_nested_meta(|inner| {
                        let Some(joint) = inner.path.get_ident().map(ToString::to_string) else {
                            return Err(inner.error("expected `JOINT = VALUE`"));
                        };
                        if let Some(x) = number_value(inner.value()?, errors, |_| None)? {
                            attr.options.load.lock.push((joint, x));
                        }
                        Ok(())
                    })?;
                }
                "armature" => {
                    meta.parse_nested_meta(|inner| {
                        let Some(joint) = inner.path.get_ident().map(ToString::to_string) else {
                            return Err(inner.error("expected `JOINT = VALUE` (G²·I_rotor in kg·m²)"));
                        };
                        let bad = |x: f64| {
                            (!(x.is_finite() && x >= 0.0)).then(|| format!("the armature of `{joint}` must be finite and ≥ 0, found {x}: give G²·I_rotor in kg·m² (kg for a prismatic joint)"))
                        };
                        if let Some(x) = number_value(inner.value()?, errors, bad)? {
                            attr.options.load.armature.push((joint, x));
                        }
                        Ok(())
                    })?;
                }
                "friction" => {
                    if attr.options.friction.is_none() {
                        attr.options.friction = Some(crate::options::Friction::Coulomb);
                    }
                }
                "friction_smoothing" => {
                    let bad = |x: f64| {
                        (!(x.is_finite() && x > 0.0))
                            .then(|| format!("`friction_smoothing` must be > 0 (rad/s or m/s), found {x}"))
                    };
                    if let Some(x) = number_value(meta.value()?, errors, bad)? {
                        attr.options.friction = Some(crate::options::Friction::Smooth(x));
                    }
                }
                "snap_angles" => {
                    let max = dynamics_model::load::MAX_SNAP_ANGLES;
                    let bad = |x: f64| {
                        (!(0.0..=max).contains(&x)).then(|| format!("`snap_angles` must be between 0 and {max:e} rad, found {x}: the largest distance from a multiple of π/2 to read as exact, e.g. 1e-5 for files that write 1.5708"))
                    };
                    if let Some(x) = number_value(meta.value()?, errors, bad)? {
                        attr.options.load.snap_angles = Some(x);
                    }
                }
                "method" => {
                    let lit: syn::LitStr = meta.value()?.parse()?;
                    match lit.value().parse::<crate::Method>() {
                        Ok(m) => attr.options.method = m,
                        Err(_) => errors.at(
                            &lit,
                            format!("unknown method \"{}\"; the methods are \"newton_euler\" (the default) and \"lagrangian\"", lit.value()),
                        ),
                    }
                }
                "runtime_parameters" => {
                    attr.options.runtime_parameters = true;
                    check_runtime_fields(input, errors);
                }
                "payload_link" => {
                    let lit: syn::LitStr = meta.value()?.parse()?;
                    attr.options.payload_link = Some(lit.value());
                }
                _ => {
                    return Err(meta.error(format!(
                        "unknown option `{}` of #[dynamics(..)]; the options are file = \"PATH\", scalar = \"f64\" | \"f32\", no_std, no_cpu_dispatch, sin_cos_variants, nalgebra = PATH, runtime = PATH, no_runtime_trait, gravity = [gx, gy, gz], floating_base, tip = \"LINK\", frames(LINK, ..), functions(NAME, ..), lock(JOINT = VALUE, ..), armature(JOINT = VALUE, ..), friction, friction_smoothing = EPS, snap_angles = TOL, method = \"newton_euler\" | \"lagrangian\", runtime_parameters, payload_link = \"LINK\"",
                        meta.path.to_token_stream()
                    )))
                }
            }
            Ok(())
        });
        if let Err(e) = result {
            errors.push(e);
        }
    }
    if !any {
        errors.at(
            &input.ident,
            "#[derive(Dynamics)] needs the robot file: add #[dynamics(file = \"robots/NAME.urdf\")] (a .urdf or .toml path relative to the crate's Cargo.toml)",
        );
    } else if attr.file.is_none() && !errors.any() {
        errors.at(
            &input.ident,
            "missing option `file` in #[dynamics(..)]: add file = \"robots/NAME.urdf\" (a .urdf or .toml path relative to the crate's Cargo.toml)",
        );
    }
    attr
}

/// `given` resolved against `base` (relative paths only); `base` is the override directory
/// if set, else the crate's manifest directory.
pub fn resolve(given: &str, override_dir: Option<&str>, manifest_dir: Option<&str>) -> PathBuf {
    let path = Path::new(given);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    match override_dir.or(manifest_dir) {
        Some(base) => Path::new(base).join(path),
        None => path.to_path_buf(),
    }
}

/// The robot file's path for this compilation (see [`MANIFEST_DIR_OVERRIDE`]).
pub fn resolve_from_env(given: &str) -> PathBuf {
    let over = std::env::var(MANIFEST_DIR_OVERRIDE).ok();
    let manifest = std::env::var("CARGO_MANIFEST_DIR").ok();
    resolve(given, over.as_deref(), manifest.as_deref())
}

/// Reads and loads the robot file; errors point at the `file = "…"` literal.
pub fn load(
    lit: &syn::LitStr,
    load: &LoadOptions,
    errors: &mut Errors,
) -> Option<(Robot, PathBuf)> {
    let given = lit.value();
    let path = resolve_from_env(&given);
    let Some(format) = Format::from_path(Path::new(&given)) else {
        errors.at(
            lit,
            format!("`{given}`: {}", dynamics_model::load::UNKNOWN_FILE_TYPE),
        );
        return None;
    };
    let text = match dynamics_model::load::read_text(&path, &given) {
        Ok(t) => t,
        Err(e) => {
            let message = match e {
                ModelError::Io { message, .. } => format!(
                    "cannot read the robot file `{given}` (resolved against CARGO_MANIFEST_DIR, or {MANIFEST_DIR_OVERRIDE} when set): {message}"
                ),
                other => other.to_string(),
            };
            errors.at(lit, message);
            return None;
        }
    };
    match dynamics_model::load::from_str(&text, format, &given, load) {
        Ok(robot) => Some((robot, path)),
        Err(ModelError::Invalid(list)) => {
            for inv in list {
                errors.at(lit, super::spans::message(&inv));
            }
            None
        }
        Err(e) => {
            errors.at(lit, e.to_string());
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_join_the_manifest_dir_or_the_override() {
        assert_eq!(
            resolve("robots/ur5.urdf", None, Some("/crate")),
            PathBuf::from("/crate/robots/ur5.urdf")
        );
        assert_eq!(
            resolve("robots/ur5.urdf", Some("/other"), Some("/crate")),
            PathBuf::from("/other/robots/ur5.urdf")
        );
        assert_eq!(
            resolve("/abs/ur5.urdf", Some("/other"), Some("/crate")),
            PathBuf::from("/abs/ur5.urdf")
        );
    }

    #[test]
    fn unreadable_file_names_the_resolved_path_in_this_crate() {
        // In this test process CARGO_MANIFEST_DIR is dynamics-gen's directory.
        let manifest = env!("CARGO_MANIFEST_DIR");
        let path = resolve("robots/missing.urdf", None, Some(manifest));
        assert_eq!(
            path,
            Path::new(manifest).join("robots").join("missing.urdf")
        );
        assert!(path.is_absolute());
        assert!(!path.exists());
    }
}
