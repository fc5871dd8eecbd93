//! URDF `<joint>` and `<link>` elements to checked numbers: each joint's transform (with a
//! locked joint's motion folded in), unit axis, limits and friction; each link's mass and
//! inertia.
//!
//! - A joint's transform from its parent link's frame to its child link's frame at q = 0 is
//!   `T = [[Rz(y) Ry(p) Rx(r), xyz], [0, 1]]` (its `<origin>`); a joint locked at value θ
//!   becomes fixed with `T e^{[A]θ}`, `A = (a, 0)` for a revolute joint about the unit axis
//!   `a` (in the joint frame), `A = (0, a)` for a prismatic one.
//! - `<axis>` defaults to `(1, 0, 0)` and is normalised; a zero axis is an error.
//! - Limits with `lower = upper = 0` (and a continuous joint's) mean no position limits; a
//!   velocity or effort limit is kept, with `lower = −∞`, `upper = +∞`.
//! - A link's `<inertial>` gives the mass m, the tensor `I = [[ixx, ixy, ixz], [ixy, iyy,
//!   iyz], [ixz, iyz, izz]]` about the centre of mass in the frame of `<inertial><origin>`;
//!   no `<inertial>` means massless.

use super::origin::origin_transform;
use crate::error::{Invalid, Subject};
use crate::lie::{exp6, twist};
use crate::robot::{JointKind, JointLimits};
use nalgebra::{Matrix3, Matrix4, Vector3};

/// A URDF joint after checking: movable (with its kind) or fixed.
#[derive(Clone, Debug)]
pub struct JointModel {
    /// `Some(kind)` for a movable joint, `None` for a fixed (or locked) one.
    pub kind: Option<JointKind>,
    /// Parent link frame → child link frame at q = 0 (a locked joint's value included).
    pub transform: Matrix4<f64>,
    /// The unit axis in the joint frame (movable joints).
    pub axis: Vector3<f64>,
    /// Position limits (movable joints; `None` when unlimited).
    pub limits: Option<JointLimits>,
    /// `<dynamics damping>`.
    pub damping: f64,
    /// `<dynamics friction>`.
    pub friction: f64,
}

impl JointModel {
    /// A fixed joint with the given transform.
    pub fn fixed(transform: Matrix4<f64>) -> Self {
        Self {
            kind: None,
            transform,
            axis: Vector3::x(),
            limits: None,
            damping: 0.0,
            friction: 0.0,
        }
    }
}

/// A URDF link's mass properties after checking.
#[derive(Clone, Debug)]
pub struct LinkModel {
    /// Mass (kg), 0 without `<inertial>`.
    pub mass: f64,
    /// Rotational inertia about the centre of mass, in the `<inertial><origin>` frame.
    pub inertia: Matrix3<f64>,
    /// Pose of that frame in the link frame.
    pub com_frame: Matrix4<f64>,
}

fn joint_subject(name: &str) -> Subject {
    Subject::Joint {
        index: None,
        name: name.to_string(),
    }
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Whether a joint type has one degree of freedom (can move, can be locked).
pub fn is_one_dof(t: &urdf_rs::JointType) -> bool {
    matches!(
        t,
        urdf_rs::JointType::Revolute
            | urdf_rs::JointType::Continuous
            | urdf_rs::JointType::Prismatic
    )
}

/// Checks a joint and computes its [`JointModel`]; `lock` is its lock value, if any.
pub fn joint(j: &urdf_rs::Joint, lock: Option<f64>) -> Result<JointModel, Vec<Invalid>> {
    use urdf_rs::JointType as T;
    let subject = || joint_subject(&j.name);
    let mut errors = Vec::new();
    let kind = match j.joint_type {
        T::Fixed => None,
        T::Revolute | T::Continuous => Some(JointKind::Revolute),
        T::Prismatic => Some(JointKind::Prismatic),
        T::Floating => {
            return Err(vec![Invalid::new(
                subject(),
                "type",
                "a `floating` joint is supported only as the root joint: the only child joint of a root link without inertia (e.g. `world` → floating → `base_link`), which puts the robot on a floating base",
                "make the joint's parent a root link without <inertial> and with no other child joint, or remove the joint and load the robot with a floating base (CLI `--floating-base`, `LoadOptions::floating_base`)",
            )]);
        }
        T::Planar | T::Spherical => {
            let t = format!("{:?}", j.joint_type).to_lowercase();
            return Err(vec![Invalid::new(
                subject(),
                "type",
                format!("joint type `{t}` is not supported (only revolute, continuous, prismatic and fixed)"),
                "model the joint as a chain of 1-dof joints, or make it fixed",
            )]);
        }
    };
    check_origin(&subject, "origin", &j.origin, &mut errors);
    let transform = origin_transform(&j.origin);
    let Some(kind) = kind else {
        return if errors.is_empty() {
            Ok(JointModel::fixed(transform))
        } else {
            Err(errors)
        };
    };
    let a = Vector3::from(j.axis.xyz.0);
    let axis = if !all_finite(a.as_slice()) {
        errors.push(Invalid::new(
            subject(),
            "axis",
            format!("not finite: {:?}", j.axis.xyz.0),
            "give three finite numbers",
        ));
        Vector3::x()
    } else if a.norm() == 0.0 {
        errors.push(Invalid::new(
            subject(),
            "axis",
            "the axis is zero",
            "give the joint's axis direction, e.g. <axis xyz=\"0 0 1\"/>",
        ));
        Vector3::x()
    } else {
        a / a.norm()
    };
    let limits = limits(j, &mut errors);
    let (damping, friction) = j
        .dynamics
        .as_ref()
        .map_or((0.0, 0.0), |d| (d.damping, d.friction));
    for (field, v) in [
        ("dynamics.damping", damping),
        ("dynamics.friction", friction),
    ] {
        if !v.is_finite() {
            errors.push(Invalid::new(
                subject(),
                field,
                format!("not finite: {v}"),
                "give a finite number",
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    match lock {
        Some(value) => {
            let motion = match kind {
                JointKind::Revolute => twist(&axis, &Vector3::zeros()),
                JointKind::Prismatic => twist(&Vector3::zeros(), &axis),
            };
            let transform = transform * exp6(&motion, value);
            if !all_finite(transform.as_slice()) {
                return Err(vec![Invalid::new(
                    subject(),
                    "lock",
                    format!("locking the joint at {value} gives a non-finite pose"),
                    "give a lock value (rad or m) within the joint's range of motion",
                )]);
            }
            Ok(JointModel {
                kind: None,
                transform,
                axis,
                limits: None,
                damping: 0.0,
                friction: 0.0,
            })
        }
        None => Ok(JointModel {
            kind: Some(kind),
            transform,
            axis,
            limits,
            damping,
            friction,
        }),
    }
}

/// The `<limit>` of a movable joint. Its position limits are none for a continuous joint
/// (URDF ignores its `lower` and `upper`), and where `lower = upper = 0` or both are infinite
/// (as URDF 1.2 writes omitted limits); then a velocity or effort limit is kept with
/// `lower = −∞`, `upper = +∞`, and without either the result is `None`.
fn limits(j: &urdf_rs::Joint, errors: &mut Vec<Invalid>) -> Option<JointLimits> {
    let l = &j.limit;
    if l.lower.is_nan() || l.upper.is_nan() || l.velocity.is_nan() || l.effort.is_nan() {
        errors.push(Invalid::new(
            joint_subject(&j.name),
            "limit",
            format!(
                "not a number: lower {}, upper {}, velocity {}, effort {}",
                l.lower, l.upper, l.velocity, l.effort
            ),
            "give numbers",
        ));
        return None;
    }
    // 0 (and +∞) is URDF's "not given"; a negative limit is a slip, not "none".
    for (name, v) in [("velocity", l.velocity), ("effort", l.effort)] {
        if v < 0.0 {
            errors.push(Invalid::new(
                joint_subject(&j.name),
                "limit",
                format!("{name} {v} is negative"),
                format!("give the {name} limit's magnitude, or {name}=\"0\" for none"),
            ));
        }
    }
    let positive = |v: f64| (v.is_finite() && v > 0.0).then_some(v);
    let (velocity, effort) = (positive(l.velocity), positive(l.effort));
    if j.joint_type == urdf_rs::JointType::Continuous
        || (l.lower == 0.0 && l.upper == 0.0)
        || !(l.lower.is_finite() && l.upper.is_finite())
    {
        return JointLimits::without_position(velocity, effort);
    }
    if l.lower > l.upper {
        errors.push(Invalid::new(
            joint_subject(&j.name),
            "limit",
            format!("lower {} is above upper {}", l.lower, l.upper),
            "give lower ≤ upper",
        ));
        return None;
    }
    Some(JointLimits {
        lower: l.lower,
        upper: l.upper,
        velocity,
        effort,
    })
}

/// Checks a link's `<inertial>` (finite, `m ≥ 0`, a physically possible tensor) and
/// returns its [`LinkModel`].
pub fn link(l: &urdf_rs::Link) -> Result<LinkModel, Vec<Invalid>> {
    let subject = || Subject::Link {
        index: None,
        name: l.name.clone(),
    };
    let inertial = &l.inertial;
    let i = &inertial.inertia;
    let tensor = Matrix3::new(
        i.ixx, i.ixy, i.ixz, //
        i.ixy, i.iyy, i.iyz, //
        i.ixz, i.iyz, i.izz,
    );
    let mass = inertial.mass.value;
    let mut errors = Vec::new();
    check_origin(&subject, "inertial.origin", &inertial.origin, &mut errors);
    if !mass.is_finite() {
        errors.push(Invalid::new(
            subject(),
            "inertial.mass",
            format!("not finite: {mass}"),
            "give the mass in kg",
        ));
    } else if mass < 0.0 {
        errors.push(Invalid::new(
            subject(),
            "inertial.mass",
            format!("negative mass {mass} kg"),
            "give a mass ≥ 0 in kg (0, or no <inertial>, for a massless link)",
        ));
    }
    if !all_finite(tensor.as_slice()) {
        errors.push(Invalid::new(
            subject(),
            "inertial.inertia",
            format!(
                "not finite: ixx {} ixy {} ixz {} iyy {} iyz {} izz {}",
                i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz
            ),
            "give finite numbers in kg·m²",
        ));
    }
    // The physical checks (positive semidefinite, triangle inequality) are made when the
    // link is assembled into a moving body (a floating base included): links on a fixed base
    // never move, and some real files carry meaningless inertias there (Pinocchio loads them
    // too).
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(LinkModel {
        mass,
        inertia: tensor,
        com_frame: origin_transform(&inertial.origin),
    })
}

/// Reports a non-finite `xyz` or `rpy` of an `<origin>` as `{field}.xyz` / `{field}.rpy`.
fn check_origin(
    subject: &dyn Fn() -> Subject,
    field: &str,
    origin: &urdf_rs::Pose,
    errors: &mut Vec<Invalid>,
) {
    for (part, v) in [("xyz", origin.xyz.0), ("rpy", origin.rpy.0)] {
        if !all_finite(&v) {
            errors.push(Invalid::new(
                subject(),
                format!("{field}.{part}"),
                format!("not finite: {v:?}"),
                "give three finite numbers",
            ));
        }
    }
}
