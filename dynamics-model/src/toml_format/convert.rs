//! From the parsed file ([`super::schema`]) to a [`Robot`]: the tree's parents, screw axes,
//! home frames, joint properties, link and base inertias, with every schema-level problem
//! collected.
//!
//! Parent of joint i's link: `parent = "LINK"` names the base or the link of an earlier joint
//! (`λ(i) = None` or k < i); without it, the previous joint's link (`λ(i) = i − 1`, the base
//! for the first joint), so a file without `parent` keys is a serial chain. The end
//! effector's `parent` names any link or the base (default: the last joint's link).
//!
//! Screw axis of joint i in {0}: given as `screw = S_i`, or from `axis = ω` (normalised to
//! `ω̂`) and a point `q` on it: `S_i = (ω̂, −ω̂ × q)` (revolute), `S_i = (0, ω̂)` (prismatic).

use super::body::body_inertia;
use super::pose::{array, pose, vector3};
use super::schema::{BaseSpec, BodySpec, JointSpec, KindSpec, RobotFile};
use crate::error::{Invalid, Subject};
use crate::inertia::SpatialInertia;
use crate::lie::twist;
use crate::robot::{
    Base, EndEffector, Frame, Joint, JointKind, JointLimits, Link, Robot, DEFAULT_GRAVITY,
};
use nalgebra::{Matrix4, Vector3, Vector6};
use std::collections::HashMap;

/// Builds the robot; `Err` holds every problem found (not yet attributed to a file).
pub(crate) fn build(spec: RobotFile, file: &str) -> Result<Robot, Vec<Invalid>> {
    let mut errors = Vec::new();
    if spec.joints.is_empty() {
        errors.push(Invalid::new(
            Subject::Robot,
            "joint",
            "the robot has no movable joint",
            "add at least one `[[joint]]` table with its `[joint.link]`",
        ));
    }
    let gravity = match &spec.gravity {
        None => Vector3::from(DEFAULT_GRAVITY),
        Some(g) => vector3(&Subject::Robot, "gravity", g).unwrap_or_else(|e| {
            errors.push(e);
            Vector3::from(DEFAULT_GRAVITY)
        }),
    };
    let base = base(spec.base.as_ref(), &mut errors);
    let names = Names {
        base: &base.name,
        links: spec.joints.iter().map(|j| j.link.name.as_str()).collect(),
        joints: spec.joints.iter().map(|j| j.name.as_str()).collect(),
    };
    let mut joint_names: HashMap<&str, usize> = HashMap::new();
    let mut link_names: HashMap<&str, usize> = HashMap::new();
    let mut joints = Vec::with_capacity(spec.joints.len());
    let mut links = Vec::with_capacity(spec.joints.len());
    for (i, j) in spec.joints.iter().enumerate() {
        let joint_subject = Subject::Joint {
            index: Some(i),
            name: j.name.clone(),
        };
        let link_subject = Subject::Link {
            index: Some(i),
            name: j.link.name.clone(),
        };
        if let Some(first) = joint_names.insert(&j.name, i) {
            errors.push(Invalid::new(
                joint_subject.clone(),
                "name",
                format!(
                    "joints {} and {} are both called `{}`",
                    first + 1,
                    i + 1,
                    j.name
                ),
                "give every joint its own name",
            ));
        }
        if let Some(first) = link_names.insert(&j.link.name, i) {
            errors.push(Invalid::new(
                link_subject.clone(),
                "name",
                format!(
                    "links {} and {} are both called `{}`",
                    first + 1,
                    i + 1,
                    j.link.name
                ),
                "give every link its own name",
            ));
        } else if j.link.name == base.name {
            errors.push(Invalid::new(
                link_subject.clone(),
                "name",
                format!("the link has the base's name `{}`", base.name),
                "give the base (`[base] name`, default `base`) and every link its own name",
            ));
        }
        let parent = match &j.parent {
            None => i.checked_sub(1),
            Some(p) => names
                .parent(&joint_subject, "parent", p, i)
                .unwrap_or_else(|e| {
                    errors.push(e);
                    None
                }),
        };
        if let Some(joint) = joint(&joint_subject, j, &mut errors) {
            joints.push(joint);
        }
        let home = pose(&link_subject, "home", &j.link.home).unwrap_or_else(|e| {
            errors.push(e);
            Matrix4::identity()
        });
        let own = j.link.own_body();
        if let Some(inertia) = inertia(
            &link_subject,
            "link",
            &own,
            &j.link.bodies,
            "[[joint.link.body]]",
            &mut errors,
        ) {
            links.push(Link {
                name: j.link.name.clone(),
                parent,
                home,
                inertia,
            });
        }
    }
    let n = spec.joints.len();
    let (ee_name, ee_parent, ee_home) = match &spec.end_effector {
        None => (None, None, None),
        Some(ee) => (ee.name.clone(), ee.parent.as_deref(), ee.home.as_ref()),
    };
    let end_effector = EndEffector {
        name: ee_name.unwrap_or_else(|| "end_effector".into()),
        parent: match ee_parent {
            None => n.checked_sub(1),
            Some(p) => names
                .parent(&Subject::EndEffector, "parent", p, n)
                .unwrap_or_else(|e| {
                    errors.push(e);
                    None
                }),
        },
        home: match ee_home {
            None => Matrix4::identity(),
            Some(v) => pose(&Subject::EndEffector, "home", v).unwrap_or_else(|e| {
                errors.push(e);
                Matrix4::identity()
            }),
        },
    };
    let mut frames = Vec::with_capacity(spec.frames.len());
    for f in &spec.frames {
        let subject = Subject::Frame(f.name.clone());
        let parent = names
            .parent(&subject, "parent", &f.parent, n)
            .map_err(|e| errors.push(e));
        let home = match &f.home {
            None => Ok(Matrix4::identity()),
            Some(v) => pose(&subject, "home", v).map_err(|e| errors.push(e)),
        };
        if let (Ok(parent), Ok(home)) = (parent, home) {
            frames.push(Frame {
                name: f.name.clone(),
                parent,
                home,
            });
        }
    }
    if errors.is_empty() {
        mimics(&spec.joints, &mut joints, &mut errors);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Robot {
        name: spec.name,
        source: file.to_string(),
        base,
        joints,
        links,
        end_effector,
        frames,
        gravity,
        runtime: crate::RuntimeParameters::default(),
        parameters: Default::default(),
    })
}

/// The base from `[base]`: its name (default `base`), whether it floats (default not), and
/// its inertia in {0} (default none: a base without inertial keys is massless).
fn base(spec: Option<&BaseSpec>, errors: &mut Vec<Invalid>) -> Base {
    let Some(spec) = spec else {
        return Base::fixed();
    };
    let name = spec.name.clone().unwrap_or_else(|| Base::fixed().name);
    let subject = Subject::Link {
        index: None,
        name: name.clone(),
    };
    let own = spec.own_body();
    let inertia = if own.is_empty() && spec.bodies.is_empty() {
        Some(SpatialInertia::zero())
    } else {
        inertia(
            &subject,
            "base",
            &own,
            &spec.bodies,
            "[[base.body]]",
            errors,
        )
    };
    Base {
        name,
        inertia: inertia.unwrap_or_else(SpatialInertia::zero),
        floating: spec.floating.unwrap_or(false),
    }
}

/// The names a `parent` key may give: the base's and the links', in joint order.
struct Names<'a> {
    base: &'a str,
    links: Vec<&'a str>,
    joints: Vec<&'a str>,
}

impl Names<'_> {
    /// `λ` from a `parent` name: `None` for the base, `Some(k)` for link k, which must come
    /// before `before` (the joint's own index; the number of joints for the end effector).
    fn parent(
        &self,
        subject: &Subject,
        field: &str,
        name: &str,
        before: usize,
    ) -> Result<Option<usize>, Invalid> {
        if name == self.base {
            return Ok(None);
        }
        let earlier = || {
            let mut v = vec![format!("`{}` (the base)", self.base)];
            v.extend(self.links[..before].iter().map(|l| format!("`{l}`")));
            v.join(", ")
        };
        match self.links.iter().position(|&l| l == name) {
            Some(k) if k < before => Ok(Some(k)),
            Some(k) if k == before => Err(Invalid::new(
                subject.clone(),
                field,
                format!("`{name}` is this joint's own link: a link cannot hang from itself"),
                format!("give the link it hangs from: {}", earlier()),
            )),
            Some(k) => Err(Invalid::new(
                subject.clone(),
                field,
                format!(
                    "`{name}` is the link of joint {} `{}`, which comes after this joint: every joint must come after the joint of the link it hangs from",
                    k + 1,
                    self.joints[k]
                ),
                format!(
                    "move this `[[joint]]` after joint `{}`, or hang it from an earlier link: {}",
                    self.joints[k],
                    earlier()
                ),
            )),
            None => Err(Invalid::new(
                subject.clone(),
                field,
                format!("`{name}` is neither the base nor a link of the robot"),
                format!("give one of {}", earlier()),
            )),
        }
    }
}

/// Joint i: kind, screw axis, limits and drive properties.
fn joint(subject: &Subject, j: &JointSpec, errors: &mut Vec<Invalid>) -> Option<Joint> {
    let n_errors = errors.len();
    let kind = match j.kind {
        KindSpec::Revolute => JointKind::Revolute,
        KindSpec::Prismatic => JointKind::Prismatic,
    };
    let screw = screw(subject, kind, j).map_err(|e| errors.push(e)).ok();
    let limits = match &j.limits {
        Some(l) => match array::<2>(subject, "limits", l) {
            Ok([lower, upper]) => Some(JointLimits {
                lower,
                upper,
                velocity: j.velocity_limit,
                effort: j.effort_limit,
            }),
            Err(e) => {
                errors.push(e);
                None
            }
        },
        // No position limits: a velocity or effort limit is kept with −∞ and +∞.
        None => JointLimits::without_position(j.velocity_limit, j.effort_limit),
    };
    for (key, value) in [
        ("velocity_limit", j.velocity_limit),
        ("effort_limit", j.effort_limit),
    ] {
        if let Some(x) = value {
            if !(x.is_finite() && x > 0.0) {
                errors.push(Invalid::new(
                    subject.clone(),
                    key,
                    format!("must be a positive number, found {x}"),
                    "give a limit > 0, or remove the key",
                ));
            }
        }
    }
    let mut nonnegative = |key: &str, value: Option<f64>| -> f64 {
        let x = value.unwrap_or(0.0);
        if !(x.is_finite() && x >= 0.0) {
            errors.push(Invalid::new(
                subject.clone(),
                key,
                format!("must be finite and ≥ 0, found {x}"),
                "give a value ≥ 0 (or remove the key for 0)",
            ));
        }
        x
    };
    let damping = nonnegative("damping", j.damping);
    let friction = nonnegative("friction", j.friction);
    let rotor_inertia = nonnegative("rotor_inertia", j.rotor_inertia);
    let gear_ratio = j.gear_ratio.unwrap_or(1.0);
    if !(gear_ratio.is_finite() && gear_ratio != 0.0) {
        errors.push(Invalid::new(
            subject.clone(),
            "gear_ratio",
            format!("must be finite and non-zero, found {gear_ratio}"),
            "give the motor turns per joint turn (1 for a direct drive)",
        ));
    }
    let screw = screw?;
    if errors.len() > n_errors {
        return None;
    }
    Some(Joint {
        name: j.name.clone(),
        kind,
        screw,
        limits,
        damping,
        friction,
        rotor_inertia,
        gear_ratio,
        mimic: None,
    })
}

/// The `mimic` keys: each leader found by name, chains resolved to their root leader
/// ([`crate::mimic::resolve_chains`]), cycles refused; `joints` are the built joints, one
/// per spec.
fn mimics(specs: &[JointSpec], joints: &mut [Joint], errors: &mut Vec<Invalid>) {
    let subject = |i: usize| Subject::Joint {
        index: Some(i),
        name: specs[i].name.clone(),
    };
    let others = |i: usize| -> String {
        let v: Vec<String> = specs
            .iter()
            .enumerate()
            .filter(|&(k, s)| k != i && s.mimic.is_none())
            .map(|(_, s)| format!("`{}`", s.name))
            .collect();
        v.join(", ")
    };
    let mut written = vec![None; specs.len()];
    for (i, s) in specs.iter().enumerate() {
        let Some(m) = &s.mimic else { continue };
        let (multiplier, offset) = (m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0));
        match specs.iter().position(|l| l.name == m.joint) {
            None => errors.push(Invalid::new(
                subject(i),
                "mimic",
                format!(
                    "`mimic.joint = \"{}\"` names no joint of the robot",
                    m.joint
                ),
                format!("give the name of the joint it follows: {}", others(i)),
            )),
            Some(l) if l == i => errors.push(Invalid::new(
                subject(i),
                "mimic",
                "the joint follows itself".to_string(),
                format!("give the name of the joint it follows: {}", others(i)),
            )),
            Some(l) => {
                written[i] = Some(crate::mimic::Written {
                    leader: l,
                    multiplier,
                    offset,
                })
            }
        }
    }
    for (i, r) in crate::mimic::resolve_chains(&written)
        .into_iter()
        .enumerate()
    {
        match r {
            None => {}
            Some(Ok(m)) => joints[i].mimic = Some(m),
            Some(Err(cycle)) => {
                let names: Vec<&str> = cycle.iter().map(|&k| specs[k].name.as_str()).collect();
                errors.push(Invalid::new(
                    subject(i),
                    "mimic",
                    format!(
                        "the mimic joints form a cycle ({} → {}): no joint of it is independent",
                        names.join(" → "),
                        names[0]
                    ),
                    "remove `mimic` from one joint of the cycle, which becomes the leader of the others",
                ));
            }
        }
    }
}

/// `S_i` from `screw`, or from `axis` (and `point` for a revolute joint).
fn screw(subject: &Subject, kind: JointKind, j: &JointSpec) -> Result<Vector6<f64>, Invalid> {
    let fail = |field: &str, problem: String, fix: &str| {
        Err(Invalid::new(subject.clone(), field, problem, fix))
    };
    match (&j.screw, &j.axis) {
        (Some(_), Some(_)) => fail(
            "axis",
            "both `screw` and `axis` are given".into(),
            "give either `screw = [ωx, ωy, ωz, vx, vy, vz]` or `axis` (with `point` for a revolute joint)",
        ),
        (None, None) => fail(
            "screw",
            "the joint has neither `screw` nor `axis`".into(),
            "give `screw = [ωx, ωy, ωz, vx, vy, vz]` in {0}, or `axis = [x, y, z]` (with `point = [x, y, z]` on it for a revolute joint)",
        ),
        (Some(s), None) => {
            if j.point.is_some() {
                return fail(
                    "point",
                    "`point` is given with `screw`".into(),
                    "`point` goes with `axis`; a screw axis already holds its location in v = −ω × q",
                );
            }
            array::<6>(subject, "screw", s).map(Vector6::from)
        }
        (None, Some(a)) => {
            let w = vector3(subject, "axis", a)?;
            let norm = w.norm();
            if !(norm.is_finite() && norm > 0.0) {
                return fail(
                    "axis",
                    format!("the axis {a:?} has no direction (length {norm})"),
                    "give a non-zero, finite direction",
                );
            }
            let w = w / norm;
            match (kind, &j.point) {
                (JointKind::Revolute, Some(p)) => {
                    let q = vector3(subject, "point", p)?;
                    Ok(twist(&w, &(-w.cross(&q))))
                }
                (JointKind::Revolute, None) => fail(
                    "point",
                    "a revolute `axis` is given without a `point` on it".into(),
                    "add `point = [x, y, z]`, a point of the axis in {0} at the home configuration",
                ),
                (JointKind::Prismatic, Some(_)) => fail(
                    "point",
                    "a prismatic joint has no axis location, but `point` is given".into(),
                    "remove `point`: a prismatic joint's screw axis is (0, axis)",
                ),
                (JointKind::Prismatic, None) => Ok(twist(&Vector3::zeros(), &w)),
            }
        }
    }
}

/// The spatial inertia of a link (`what` = `link`) or of the base (`base`): its own keys, or
/// the sum of its bodies (`table`, for messages).
fn inertia(
    subject: &Subject,
    what: &str,
    own: &BodySpec,
    bodies: &[BodySpec],
    table: &str,
    errors: &mut Vec<Invalid>,
) -> Option<SpatialInertia> {
    if bodies.is_empty() {
        return body_inertia(subject, "", own, errors);
    }
    if !own.is_empty() {
        errors.push(Invalid::new(
            subject.clone(),
            "body",
            format!("the {what} has both its own inertial keys (mass, inertia, shape, …) and `{table}` tables"),
            format!("move the {what}'s own mass and inertia into one more `{table}`, or remove the bodies"),
        ));
        return None;
    }
    let mut total = Some(SpatialInertia::zero());
    for (k, b) in bodies.iter().enumerate() {
        let prefix = match &b.name {
            Some(name) => format!("body[{name}]."),
            None => format!("body[{k}]."),
        };
        let g = body_inertia(subject, &prefix, b, errors);
        total = match (total, g) {
            (Some(t), Some(g)) => Some(t + g),
            _ => None,
        };
    }
    total
}
