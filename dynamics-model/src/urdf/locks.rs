//! Locked joints: the values the user gives (checked against the joint's limits), and the
//! mimic joints: following a locked leader, or left movable as coupled coordinates.
//!
//! - A lock value must be finite, at most [`MAX_LOCK`] in magnitude, and within the joint's
//!   `<limit lower upper>` when it has limits (a continuous joint, or `lower = upper = 0`,
//!   has none). Errors name the joint and the field `lock`, never the URDF's numbers.
//! - Locking a joint L at v locks every movable joint with `<mimic joint="L" multiplier="m"
//!   offset="o">` at `m·v + o` (m = 1, o = 0 by default), and their own followers in turn.
//!   The derived value is not checked against the follower's limits (it is what the
//!   mechanism does). A follower also locked explicitly must be locked at that value (to
//!   1e-9, relative): another value is an error, since the mimic ties the two joints.
//! - Locking a follower whose leader stays movable is an error: the mimic ties the follower
//!   to a joint that moves, so it cannot be fixed alone. The error names the lock of the root
//!   leader that fixes it at the value asked for (`--lock L=(v − o)/m`, up the chain), which
//!   locks the leader's other followers with it.
//! - A movable joint with `<mimic>` left movable (its leader not locked) is a coupled
//!   coordinate ([`crate::Joint::mimic`], [`mimic_links`]): chains are resolved to the root
//!   leader, which must be a movable joint of the robot; a leader the file does not have, a
//!   fixed (or floating, planar) leader, a cycle and a multiplier that is zero or not finite
//!   are errors on the field `mimic` that suggest locking the follower instead.

use super::convert::is_one_dof;
use crate::error::{Invalid, Subject};
use crate::mimic::{resolve_chains, Mimic, Written};
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
    errors.extend(followers_locked_alone(urdf, &explicit, &locks, mimics));
    if errors.is_empty() {
        Ok(locks)
    } else {
        Err(errors)
    }
}

/// The errors of explicitly locked followers whose leader is a movable joint left free: each
/// with the lock of the root leader (up the chain of free movable leaders) that gives the
/// value asked for.
fn followers_locked_alone(
    urdf: &urdf_rs::Robot,
    explicit: &HashMap<usize, f64>,
    locks: &HashMap<usize, f64>,
    mimics: &[Option<Follows>],
) -> Vec<Invalid> {
    let free_leader = |f: usize| -> Option<(usize, &Follows)> {
        let m = mimics.get(f)?.as_ref()?;
        let l = m.leader?;
        (is_one_dof(&urdf.joints[l].joint_type) && !locks.contains_key(&l)).then_some((l, m))
    };
    let mut sorted: Vec<(&usize, &f64)> = explicit.iter().collect();
    sorted.sort_by_key(|(f, _)| **f);
    sorted
        .into_iter()
        .filter_map(|(&f, &v)| {
            let (leader, first) = free_leader(f)?;
            // Up the chain: θ_leader = (θ_f − o)/m.
            let (mut root, mut value, mut seen) = (leader, (v - first.offset) / first.multiplier, vec![f, leader]);
            while let Some((l, m)) = free_leader(root).filter(|(l, _)| !seen.contains(l)) {
                value = (value - m.offset) / m.multiplier;
                root = l;
                seen.push(l);
            }
            let name = &urdf.joints[f].name;
            let root_name = &urdf.joints[root].name;
            let fix = if value.is_finite() {
                format!(
                    "lock the leader instead, `--lock {root_name}={value}`, which locks `{name}` at {v} (and the other joints that follow `{root_name}` with it), or drop the lock to keep `{name}` as a coupled joint"
                )
            } else {
                format!("lock the leader `{root_name}` instead (which locks `{name}` with it), or drop the lock to keep `{name}` as a coupled joint")
            };
            Some(Invalid::new(
                subject(name),
                "lock",
                format!(
                    "the joint mimics `{}`, which is not locked: a joint that follows a moving leader cannot be locked alone",
                    first.leader_name
                ),
                fix,
            ))
        })
        .collect()
}

/// The coupling of every movable joint (`movable`: URDF joint indices, in the robot's
/// order): `None` for an independent joint, the [`Mimic`] of a follower with its root leader
/// as an index into `movable`; or every error found (one per joint, each suggesting its lock).
pub fn mimic_links(
    urdf: &urdf_rs::Robot,
    movable: &[usize],
    mimics: &[Option<Follows>],
) -> Result<Vec<Option<Mimic>>, Vec<Invalid>> {
    let name = |j: usize| urdf.joints[j].name.as_str();
    let lock_fix = |f: usize, also: &str| {
        format!(
            "{also}lock it at a value (CLI `--lock {0}=VALUE`, Builder `.lock(\"{0}\", VALUE)`, derive `lock({0} = VALUE)`), e.g. `--lock {0}={1}`, or make it fixed",
            name(f),
            rest(&urdf.joints[f])
        )
    };
    let mut errors = Vec::new();
    // The file's mimics among the movable joints, by URDF joint index.
    let mut written: Vec<Option<Written>> = vec![None; urdf.joints.len()];
    for &f in movable {
        let Some(m) = &mimics[f] else { continue };
        let err =
            |problem: String, fix: String| Invalid::new(subject(name(f)), "mimic", problem, fix);
        let leader = m.leader.filter(|l| movable.contains(l));
        if !(m.multiplier.is_finite() && m.multiplier != 0.0) {
            errors.push(err(
                format!("the multiplier {} is not a finite, non-zero number", m.multiplier),
                lock_fix(f, "give `<mimic multiplier>` a finite non-zero value (θ = multiplier·θ_leader + offset), or "),
            ));
        } else if !m.offset.is_finite() {
            errors.push(err(
                format!("the offset {} is not finite", m.offset),
                lock_fix(f, "give `<mimic offset>` a finite value, or "),
            ));
        } else if let Some(l) = leader {
            written[f] = Some(Written {
                leader: l,
                multiplier: m.multiplier,
                offset: m.offset,
            });
        } else if let Some(l) = m.leader {
            errors.push(err(
                format!(
                    "it mimics joint `{}`, which is {}: a mimic joint follows a movable (revolute, continuous or prismatic) joint",
                    m.leader_name,
                    match &urdf.joints[l].joint_type {
                        urdf_rs::JointType::Fixed => "fixed",
                        _ if is_one_dof(&urdf.joints[l].joint_type) => "not part of the robot",
                        _ => "not a one-degree-of-freedom joint",
                    }
                ),
                lock_fix(f, &format!("make `{}` movable, or ", m.leader_name)),
            ));
        } else {
            errors.push(err(
                format!(
                    "it mimics joint `{}`, which the file does not have",
                    m.leader_name
                ),
                lock_fix(f, "name an existing movable joint in `<mimic joint>`, or "),
            ));
        }
    }
    let position = |j: usize| movable.iter().position(|&m| m == j);
    let mut out = vec![None; movable.len()];
    let resolved = resolve_chains(&written);
    for (k, &f) in movable.iter().enumerate() {
        match &resolved[f] {
            // The root leader has no written mimic: an independent movable joint, or a
            // follower refused above (left out).
            Some(Ok(m)) if mimics[m.leader].is_none() => {
                out[k] = position(m.leader).map(|leader| Mimic { leader, ..*m });
            }
            None | Some(Ok(_)) => {}
            Some(Err(cycle)) => {
                let names: Vec<&str> = cycle.iter().map(|&j| name(j)).collect();
                errors.push(Invalid::new(
                    subject(name(f)),
                    "mimic",
                    format!(
                        "the mimic joints form a cycle ({} → {}): none of them is an independent joint to follow",
                        names.join(" → "),
                        names[0]
                    ),
                    lock_fix(f, "remove the `<mimic>` of one joint of the cycle (it becomes the leader of the others), or "),
                ));
            }
        }
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}
