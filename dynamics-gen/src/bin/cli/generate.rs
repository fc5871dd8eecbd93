//! `generate` and `stats`.

use super::args::{EquationsArgs, GenerateArgs, ModelArgs, StatsArgs};
use dynamics_gen::emit::provenance::portable;
use dynamics_gen::stats::{featherstone_rnea, robot_stats};
use dynamics_gen::{Method, Options, Provenance, Scalar};
use std::fmt::Write as _;

/// `dynamics-gen generate`: the formatted code, to stdout or `-o FILE`.
pub fn run(args: &GenerateArgs) -> Result<(), String> {
    let (robot, source, bytes) = args.model.load_with_source()?;
    let friction = match (args.friction_smoothing, args.friction) {
        (Some(eps), _) => Some(dynamics_gen::options::Friction::Smooth(eps)),
        (None, true) => Some(dynamics_gen::options::Friction::Coulomb),
        (None, false) => None,
    };
    super::joints::ignored_notes(&robot, friction.is_some());
    let options = Options {
        friction,
        name: args.name.clone(),
        scalar: args.scalar,
        no_std: args.no_std,
        nalgebra_path: args.nalgebra_path.clone(),
        runtime_path: (!args.no_runtime_trait).then(|| args.runtime_path.clone()),
        load: args.model.load_options(),
        functions: (!args.functions.is_empty()).then(|| args.functions.clone()),
        method: args.method,
        runtime_parameters: args.runtime_parameters,
        payload_link: args.payload_link.clone(),
        cpu_dispatch: !args.no_cpu_dispatch,
        sin_cos_variants: args.sin_cos_variants,
    };
    if let Some(name) = &args.name {
        dynamics_gen::options::check_struct_name(name).map_err(|e| e.to_string())?;
    }
    let provenance = match &bytes {
        Some(bytes) => Provenance::of_bytes(source, bytes),
        None => Provenance::new(source),
    };
    let provenance = provenance.command(command(args));
    let code =
        dynamics_gen::generate_file(&robot, &options, provenance).map_err(|e| e.to_string())?;
    match &args.output {
        Some(path) => std::fs::write(path, code)
            .map_err(|e| format!("{}: cannot write the generated file: {e}", path.display())),
        None => super::print(&code),
    }
}

/// The `dynamics-gen generate` command line that makes the same file, options in canonical
/// form (no absolute paths).
fn command(args: &GenerateArgs) -> String {
    let m = &args.model;
    let mut words = vec![
        "dynamics-gen".to_string(),
        "generate".into(),
        quote(&portable(&m.robot)),
    ];
    if let Some(name) = &args.name {
        words.extend(["--name".into(), quote(name)]);
    }
    if args.scalar != Scalar::F64 {
        words.extend(["--scalar".into(), args.scalar.as_str().into()]);
    }
    if args.no_std {
        words.push("--no-std".into());
    }
    if args.no_cpu_dispatch {
        words.push("--no-cpu-dispatch".into());
    }
    if args.sin_cos_variants {
        words.push("--sin-cos-variants".into());
    }
    if let Some(g) = m.gravity {
        words.push(format!("--gravity={},{},{}", g[0], g[1], g[2]));
    }
    if let Some(tip) = &m.tip {
        words.extend(["--tip".into(), quote(tip)]);
    }
    if m.floating_base {
        words.push("--floating-base".into());
    }
    if !m.frame.is_empty() {
        words.extend(["--frame".into(), quote(&m.frame.join(","))]);
    }
    let locks: Vec<String> = m.lock.iter().map(|(j, v)| format!("{j}={v}")).collect();
    if !locks.is_empty() {
        words.extend(["--lock".into(), quote(&locks.join(","))]);
    }
    let armature: Vec<String> = m.armature.iter().map(|(j, v)| format!("{j}={v}")).collect();
    if !armature.is_empty() {
        words.extend(["--armature".into(), quote(&armature.join(","))]);
    }
    if let Some(tol) = m.snap_angles {
        words.push(format!("--snap-angles={tol:e}"));
    }
    if args.method != Method::NewtonEuler {
        words.extend(["--method".into(), args.method.as_str().into()]);
    }
    if args.runtime_parameters {
        words.push("--runtime-parameters".into());
    }
    if let Some(link) = &args.payload_link {
        words.extend(["--payload-link".into(), quote(link)]);
    }
    if let Some(eps) = args.friction_smoothing {
        words.push(format!("--friction-smoothing={eps}"));
    } else if args.friction {
        words.push("--friction".into());
    }
    if args.nalgebra_path != Options::default().nalgebra_path {
        words.extend(["--nalgebra-path".into(), quote(&args.nalgebra_path)]);
    }
    if !args.functions.is_empty() {
        words.extend(["--functions".into(), quote(&args.functions.join(","))]);
    }
    if args.no_runtime_trait {
        words.push("--no-runtime-trait".into());
    } else if Some(&args.runtime_path) != Options::default().runtime_path.as_ref() {
        words.extend(["--runtime-path".into(), quote(&args.runtime_path)]);
    }
    if let Some(out) = &args.output {
        words.extend(["-o".into(), quote(&portable(&out.to_string_lossy()))]);
    }
    words.join(" ")
}

/// `word` quoted for a POSIX shell when it needs it.
fn quote(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./=,:+@%".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// `dynamics-gen stats`: the table, and Featherstone's RNEA count for comparison.
pub fn stats(stats_args: &StatsArgs) -> Result<(), String> {
    let args = &stats_args.model;
    let (robot, name, bytes) = args.load_with_source()?;
    let options = Options {
        load: args.load_options(),
        method: stats_args.method,
        runtime_parameters: stats_args.runtime_parameters,
        payload_link: stats_args.payload_link.clone(),
        ..Options::default()
    };
    let stats = robot_stats(&robot, &options).map_err(|e| e.to_string())?;
    let mut out = String::new();
    writeln!(out,
        "robot `{}` ({} joints), struct `{}`, method {}; counts with shared subexpressions computed once",
        robot.name,
        stats.dof,
        stats.struct_name,
        options.method.as_str()
    ).ok();
    write!(out, "{stats}").ok();
    writeln!(
        out,
        "the *_batch functions' counts are per state (each operation runs on all B states at once)"
    )
    .ok();
    let (mul, add) = featherstone_rnea(stats.dof);
    writeln!(out,
        "for comparison, recursive Newton-Euler (Featherstone's count, 93n-69 mul, 81n-66 add): {mul} mul, {add} add/sub"
    ).ok();
    if let Some(text) = bytes.and_then(|b| String::from_utf8(b).ok()) {
        near_right_angles(&mut out, args, options.method, &text, &name, &stats)?;
    }
    super::print(&out)
}

/// `dynamics-gen equations`: the closed forms, to stdout.
pub fn equations(args: &EquationsArgs) -> Result<(), String> {
    let robot = args.model.load()?;
    let options = dynamics_gen::equations::EquationOptions {
        format: args.format,
        steps: args.steps,
        digits: usize::from(args.digits),
        select: args.only,
        symbolic: args.symbolic.clone(),
    };
    let text = dynamics_gen::equations::equations(&robot, &options).map_err(|e| e.to_string())?;
    super::print(&text)
}

/// The widest `--snap-angles` that `stats` reports on.
const NEAR_RIGHT_ANGLE: f64 = 1e-4;

/// For a URDF: the `rpy` angles within [`NEAR_RIGHT_ANGLE`] of a multiple of π/2 that the
/// current tolerance leaves as written, and the operations snapping them would save.
fn near_right_angles(
    out: &mut String,
    args: &ModelArgs,
    method: Method,
    text: &str,
    name: &str,
    stats: &dynamics_gen::stats::Stats,
) -> Result<(), String> {
    use dynamics_gen::dynamics_model::urdf;
    let above = args.snap_angles.unwrap_or(urdf::origin::SNAP_TOL);
    if above >= NEAR_RIGHT_ANGLE {
        return Ok(());
    }
    // Not a URDF (or not one that parses): nothing to list.
    let Ok(near) = urdf::near_right_angles(text, name, above, NEAR_RIGHT_ANGLE) else {
        return Ok(());
    };
    if near.is_empty() {
        return Ok(());
    }
    writeln!(out,
        "{} rpy angles lie within {NEAR_RIGHT_ANGLE:e} rad of a multiple of pi/2 but are used as written (tolerance {above:e}):",
        near.len()
    ).ok();
    const AXES: [&str; 3] = ["roll", "pitch", "yaw"];
    for a in &near {
        writeln!(
            out,
            "  {} origin {} = {} ({:.1e} rad from a multiple of pi/2)",
            a.element, AXES[a.index], a.value, a.distance
        )
        .ok();
    }
    // The largest distance rounded up to one significant digit.
    let widest = near.iter().map(|a| a.distance).fold(0.0, f64::max);
    let exponent = widest.log10().floor() as i32;
    let tol_text = match (widest / 10f64.powi(exponent)).ceil() as i32 {
        10 => format!("1e{}", exponent + 1),
        m => format!("{m}e{exponent}"),
    };
    let tol: f64 = tol_text.parse().map_err(|e| format!("{e}"))?;
    let mut load = args.load_options();
    load.snap_angles = Some(tol);
    let snapped = dynamics_gen::dynamics_model::load::from_reader(text.as_bytes(), name, &load)
        .map_err(|e| e.to_string())?;
    dynamics_gen::check_robot(&snapped).map_err(|e| e.to_string())?;
    let options = Options {
        load,
        method,
        ..Options::default()
    };
    let after = robot_stats(&snapped, &options).map_err(|e| e.to_string())?;
    writeln!(out, "with --snap-angles {tol_text} (the robot changes by up to that angle), mul + add/sub per function:").ok();
    for (b, a) in stats.functions.iter().zip(&after.functions) {
        let (before, now) = (b.ops.mul + b.ops.add_sub, a.ops.mul + a.ops.add_sub);
        if before != now {
            writeln!(out, "  {:<36} {before:>8} -> {now:>8}", b.name).ok();
        }
    }
    Ok(())
}
