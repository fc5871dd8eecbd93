//! `joints` and `robots`.

use super::args::ModelArgs;
use dynamics_gen::dynamics_model::{shipped, JointKind};
use std::fmt::Write as _;

/// `dynamics-gen joints`: one movable joint per line, in vector order (a floating base
/// first; on a tree each joint says which link it hangs from), with its index in q (and in
/// ν on a floating base). A mimic joint has no index: it says which joint it follows.
pub fn run(args: &ModelArgs) -> Result<(), String> {
    let robot = args.load()?;
    let mut out = String::new();
    let mut width = robot.joints.iter().map(|j| j.name.len()).max().unwrap_or(0);
    let couplings = robot.couplings();
    let index = |i: usize| -> String {
        if robot.joints[i].mimic.is_some() {
            return "-".into();
        }
        let k = couplings[i].coordinate;
        if robot.base.floating {
            format!("q[{}] ν[{}]", k + 7, k + 6)
        } else {
            format!("q[{k}]")
        }
    };
    let base_index = "q[0..7] ν[0..6]";
    let index_width = (0..robot.joints.len())
        .map(|i| index(i).chars().count())
        .chain(robot.base.floating.then(|| base_index.chars().count()))
        .max()
        .unwrap_or(0);
    if robot.base.floating {
        width = width.max("(floating base)".len());
        writeln!(out,
            "{:<width$}  {:<10}  {:<index_width$}  base link `{}`: q[0..7] = (p, quat x y z w), velocity[0..6] = (ω_b, v_b) in the base frame; the joints follow at q[7..], velocity[6..]",
            "(floating base)",
            "free",
            base_index,
            robot.base.name
        ).ok();
    }
    let tree = !robot.is_serial();
    for (i, j) in robot.joints.iter().enumerate() {
        // `+ 0.0` prints −0 as 0.
        let s: Vec<String> = j.screw.iter().map(|x| format!("{}", x + 0.0)).collect();
        let unit = match j.kind {
            JointKind::Revolute => "rad",
            JointKind::Prismatic => "m",
        };
        let position = j.limits.and_then(|l| l.position());
        let limits = match &position {
            Some((lower, upper)) => format!("limits [{lower}, {upper}] {unit}"),
            None => "unlimited".to_string(),
        };
        // An unlimited revolute joint is URDF's `continuous` (q is the angle).
        let kind = match (j.kind, &position) {
            (JointKind::Revolute, None) => "continuous",
            (kind, _) => kind.as_str(),
        };
        let parent = if tree {
            match robot.links[i].parent {
                Some(p) => format!("  hangs from `{}`", robot.links[p].name),
                None => format!("  hangs from the base `{}`", robot.base.name),
            }
        } else {
            String::new()
        };
        let follows = match &j.mimic {
            Some(m) => format!(
                "  follows `{}` (×{} + {})",
                robot.joints.get(m.leader).map_or("?", |l| l.name.as_str()),
                m.multiplier,
                m.offset
            ),
            None => String::new(),
        };
        writeln!(
            out,
            "{:<width$}  {:<10}  {:<index_width$}  S = ({})  {limits}{parent}{follows}",
            j.name,
            kind,
            index(i),
            s.join(", ")
        )
        .ok();
    }
    super::print(&out)
}

/// A note on stderr when the robot's joints have friction (URDF `<dynamics damping
/// friction>`, TOML `damping`, `friction`) that the generated dynamics leave out
/// (`included`: generated with `--friction`), so that nothing is ignored silently.
pub fn ignored_notes(robot: &dynamics_gen::dynamics_model::Robot, included: bool) {
    let with_dynamics: Vec<&str> = robot
        .joints
        .iter()
        .filter(|j| j.damping != 0.0 || j.friction != 0.0)
        .map(|j| j.name.as_str())
        .collect();
    if !with_dynamics.is_empty() && !included {
        eprintln!(
            "note: the damping and friction of {} {} in the generated `friction(qd)` only, not in inverse or forward dynamics (add --friction to include them; Pinocchio's rnea leaves them out too)",
            with_dynamics.join(", "),
            if with_dynamics.len() == 1 { "is" } else { "are" }
        );
    }
}

/// `dynamics-gen robots`: the shipped robots.
pub fn robots() -> Result<(), String> {
    let mut out = String::new();
    for r in shipped::ROBOTS {
        writeln!(out, "{:<10} {}", r.name, r.file).ok();
    }
    super::print(&out)
}
