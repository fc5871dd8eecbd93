//! Locked joints: the values the user gives (checked against the joint's limits), and the
//! mimic joints that follow a locked leader.
//!
//! - A lock value must be finite, at most [`MAX_LOCK`] in magnitude, and within the joint's
//!   `<limit lower upper>` when it has limits (a continuous joint, or `lower = upper = 0`,
//!   has none). Errors name the joint and the field `lock`, never the URDF's numbers.
//! - Locking a joint L at v locks every movable joint with `<mimic joint="L" multiplier="m"
//!   offset="o">` at `m·v + o` (m = 1, o = 0 by default), and their own followers in turn.
//!   The derived value is not checked against the follower's limits (it is what the
//!   mechanism does). A follower also locked explicitly must be locked at that value (to
//!   1e-9, relative): another value is an error, since the mimic ties the two joints.
//! - A movable joint with `<mimic>` left movable (its leader not locked) is refused
//!   ([`mimic_errors`]): coupled coordinates are not modelled, and treating it as an
//!   independent joint would give the wrong dynamics. The error suggests locking it (written
//!   `--lock A=0`; the value is 0, or the nearest limit when 0 is outside the limits) or its
//!   leader.

use super::convert::is_one_dof;
use crate::error::{Invalid, Subject};
use std::collections::HashMap;

/// The largest lock value accepted, in rad or m: larger ones are typing mistakes, and would
/// lose all precision in the pose.
pub const MAX_LOCK: f64 = 1e6;

/// How a joint follows another through `<mimic>`.
#[derive(Clone, Debug)]
pub struct Follows {
    /// The leader's joint index (`None` when the file has no joint of that name).
    pub leader: Option<usize>,
    /// The leader's name as written.
    pub leader_name: String,
    /// `q = multiplier·q_leader + offset`.
    pub multiplier: f64,
    /// See `multiplier`.
    pub offset: f64,
}

fn subject(name: &str) -> Subject {
    Subject::Joint {
        index: None,
        name: name.to_string(),
    }
}

/// For each joint, how it follows another: movable joints with `<mimic>` only.
pub fn mimics(urdf: &urdf_rs::Robot) -> Vec<Option<Follows>> {
    urdf.joints
        .iter()
        .map(|j| {
            let m = j.mimic.as_ref().filter(|_| is_one_dof(&j.joint_type))?;
            Some(Follows {
                leader: urdf.joints.iter().position(|l| l.name == m.joint),
                leader_name: m.joint.clone(),
                multiplier: m.multiplier.unwrap_or(1.0),
                offset: m.offset.unwrap_or(0.0),
            })
        })
        .collect()
}

/// A joint's position limits `(lower, upper)`; `None` when it has none.
pub fn position_limits(j: &urdf_rs::Joint) -> Option<(f64, f64)> {
    let (l, u) = (j.limit.lower, j.limit.upper);
    let limited = j.joint_type != urdf_rs::JointType::Continuous
        && is_one_dof(&j.joint_type)
        && l.is_finite()
        && u.is_finite()
        && !(l == 0.0 && u == 0.0)
        && l <= u;
    limited.then_some((l, u))
}

/// The value suggested for locking a joint: 0, or its nearest limit when 0 is outside them.
pub fn rest(j: &urdf_rs::Joint) -> f64 {
    position_limits(j).map_or(0.0, |(l, u)| 0f64.clamp(l, u))
}

fn unit(j: &urdf_rs::Joint) -> &'static str {
    if j.joint_type == urdf_rs::JointType::Prismatic {
        "m"
    } else {
        "rad"
    }
}

/// The lock value of every locked joint (by index): the user's `lock`, checked, and the
/// mimic joints that follow a locked joint.
pub fn resolve(
    urdf: &urdf_rs::Robot,
    lock: &[(String, f64)],
    mimics: &[Option<Follows>],
) -> Result<HashMap<usize, f64>, Vec<Invalid>> {
    let movable: Vec<&str> = urdf
        .joints
        .iter()
        .filter(|j| is_one_dof(&j.joint_type))
        .map(|j| j.name.as_str())
        .collect();
    let mut out = HashMap::new();
    let mut errors = Vec::new();
    for (name, value) in lock {
        let value = *value;
        let found = urdf.joints.iter().position(|j| &j.name == name);
        let Some(ji) = found.filter(|&ji| is_one_dof(&urdf.joints[ji].joint_type)) else {
            errors.push(Invalid::new(
                subject(name),
                "lock",
                if found.is_some() {
                    "only a movable joint (revolute, continuous, prismatic) can be locked; this one is not"
                } else {
                    "the file has no joint of this name"
                },
                format!("lock one of the movable joints: {}", movable.join(", ")),
            ));
            continue;
        };
        let j = &urdf.joints[ji];
        let (unit, limits) = (unit(j), position_limits(j));
        let within = limits.map_or(String::new(), |(l, u)| format!(" within [{l}, {u}]"));
        let fix = format!(
            "give a finite joint value in {unit}{within}, e.g. `--lock {name}={}`",
            rest(j)
        );
        let problem = if !value.is_finite() {
            Some(format!("the lock value {value} is not finite"))
        } else if value.abs() > MAX_LOCK {
            Some(format!(
                "the lock value {value} {unit} is not a joint position (|value| > {MAX_LOCK:e})"
            ))
        } else {
            limits
                .filter(|&(l, u)| !(l..=u).contains(&value))
                .map(|(l, u)| {
                    format!(
                        "the lock value {value} {unit} is outside the joint's limits [{l}, {u}]"
                    )
                })
        };
        if let Some(problem) = problem {
            errors.push(Invalid::new(subject(name), "lock", problem, fix));
        } else if out.insert(ji, value).is_some() {
            errors.push(Invalid::new(
                subject(name),
                "lock",
                "the joint is locked twice",
                "lock each joint once",
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    follow_leaders(urdf, out, mimics)
}

/// Adds the lock of every mimic joint whose leader is locked (followers of followers too).
fn follow_leaders(
    urdf: &urdf_rs::Robot,
    explicit: HashMap<usize, f64>,
    mimics: &[Option<Follows>],
) -> Result<HashMap<usize, f64>, Vec<Invalid>> {
    let mut locks = explicit.clone();
    let mut done = vec![false; mimics.len()];
    let mut errors = Vec::new();
    let mut changed = true;
    while changed {
        changed = false;
        for (f, m) in mimics.iter().enumerate() {
            let Some(m) = m.as_ref().filter(|_| !done[f]) else {
                continue;
            };
            let Some(&v) = m.leader.and_then(|l| locks.get(&l)) else {
                continue;
            };
            done[f] = true;
            changed = true;
            let d = m.multiplier * v + m.offset;
            let name = &urdf.joints[f].name;
            let how = format!(
                "the joint mimics `{}` (multiplier {}, offset {}), locked at {v}, so it is locked at {d}",
                m.leader_name, m.multiplier, m.offset
            );
            if !d.is_finite() || d.abs() > MAX_LOCK {
                errors.push(Invalid::new(
                    subject(name),
                    "lock",
                    format!("{how}, which is not a joint position"),
                    format!("lock `{}` at a smaller value", m.leader_name),
                ));
            } else if let Some(&e) = explicit.get(&f) {
                if (e - d).abs() > 1e-9 * d.abs().max(1.0) {
                    errors.push(Invalid::new(
                        subject(name),
                        "lock",
                        format!("locked at {e}, but {how}"),
                        format!(
                            "drop `--lock {name}={e}` (it follows `{}`), or lock it at {d}",
                            m.leader_name
                        ),
                    ));
                }
            } else {
                locks.insert(f, d);
            }
        }
    }
    if errors.is_empty() {
        Ok(locks)
    } else {
        Err(errors)
    }
}

/// The errors of the movable joints (`movable`, in the robot's order) that mimic another
/// joint: one per joint, each with the locks that make it fixed.
pub fn mimic_errors(
    urdf: &urdf_rs::Robot,
    movable: &[usize],
    mimics: &[Option<Follows>],
) -> Vec<Invalid> {
    let name = |j: usize| urdf.joints[j].name.as_str();
    let lock_of = |j: usize| format!("{}={}", name(j), rest(&urdf.joints[j]));
    movable
        .iter()
        .filter_map(|&f| {
            let leader = &mimics[f].as_ref()?.leader_name;
            Some(Invalid::new(
                subject(name(f)),
                "mimic",
                format!(
                    "a movable joint that mimics joint `{leader}` is not supported (it is not an independent joint)"
                ),
                format!(
                    "lock it at a value (CLI `--lock {0}=VALUE`, Builder `.lock(\"{0}\", VALUE)`, derive `lock({0} = VALUE)`), e.g. `--lock {1}`, or lock `{leader}` (which locks it too), or make it fixed",
                    name(f),
                    lock_of(f)
                ),
            ))
        })
        .collect()
}
