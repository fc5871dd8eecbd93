//! Validation of a [`Robot`]: every rule, its tolerance, and the fix it suggests.
//!
//! | rule | tolerance |
//! |---|---|
//! | every number finite | exact |
//! | revolute: `|ω| = 1` | [`UNIT_TOL`] |
//! | revolute: no pitch, `ω · v = 0` (so `v = −ω × q`) | [`UNIT_TOL`] · max(1, `|v|`) |
//! | prismatic: `ω = 0`, `|v| = 1` | [`UNIT_TOL`] |
//! | home frames rigid: `RᵀR = 1`, `det R = 1`, last row `(0, 0, 0, 1)` | [`ORTHO_TOL`] |
//! | `G_i` symmetric, lower-right block `m·1₃`, off-diagonal block `m[c]` (skew) | [`INERTIA_TOL`] · scale |
//! | mass `m ≥ 0` | exact |
//! | a massless link has no rotational inertia | [`INERTIA_TOL`] · scale |
//! | rotational inertia about the COM positive semidefinite | [`INERTIA_TOL`] · scale |
//! | principal moments meet the triangle inequality `I₁ + I₂ ≥ I₃` | [`INERTIA_TOL`] · scale |
//! | mimic: the leader is another joint of the robot and independent (chains resolved, see [`crate::mimic`]) | exact |
//! | mimic: multiplier finite and non-zero, offset finite | exact |
//! | joints and links have non-blank names | exact |
//! | magnitudes: mass ≤ [`MAX_MASS`], rotational inertia ≤ [`MAX_INERTIA`], home offsets and screw axes' `v` ≤ [`MAX_LENGTH`], `|g|` ≤ [`MAX_GRAVITY`] | exact |
//!
//! "scale" is the largest absolute entry of the matrix checked (at least 1e-300). Thin rods
//! (`diag(4, 4, 0)`, the Exercise 8.4 pendulum) meet the triangle inequality with equality
//! and are valid.

use crate::error::{Invalid, Subject};
use crate::lie::{angular, is_rigid_transform, linear};
use crate::robot::{JointKind, Robot};
use nalgebra::{Matrix3, Matrix4, SymmetricEigen};

/// Tolerance on unit lengths of screw axes.
pub const UNIT_TOL: f64 = 1e-9;
/// Tolerance on the orthonormality of rotation matrices.
pub const ORTHO_TOL: f64 = 1e-9;
/// Relative tolerance on the structure and physical consistency of inertias.
pub const INERTIA_TOL: f64 = 1e-9;

/// The largest mass of a link or floating base (kg). Larger numbers are unit slips (grams
/// given as kilograms a millionfold over, or worse); with them the generated `f32` code
/// overflows: the products `m·ℓ²·q̇²` it forms must stay below `f32::MAX` ≈ 3.4e38.
pub const MAX_MASS: f64 = 1e9;
/// The largest distance of a home frame from its parent's origin, and the largest `|v|` of a
/// screw axis (m): 10 km.
pub const MAX_LENGTH: f64 = 1e4;
/// The largest entry of a rotational inertia (kg·m²): [`MAX_MASS`] · [`MAX_LENGTH`]².
pub const MAX_INERTIA: f64 = MAX_MASS * MAX_LENGTH * MAX_LENGTH;
/// The largest gravity (m/s²): a thousand times the Earth's.
pub const MAX_GRAVITY: f64 = 1e4;

/// Every rule broken by `robot`, in chain order (empty when the robot is valid).
pub fn validate(robot: &Robot) -> Vec<Invalid> {
    validate_with(robot, true)
}

/// As [`validate`], but with `unit_axes = false` a screw axis is only required to be finite:
/// the book's functions accept any `S_i` (its three-link example has `|ω| = √2`), and so does
/// the reference implementation. The generator always requires unit axes.
pub fn validate_with(robot: &Robot, unit_axes: bool) -> Vec<Invalid> {
    let mut errors = Vec::new();
    if robot.joints.len() != robot.links.len() {
        errors.push(Invalid::new(
            Subject::Robot,
            "joints",
            format!(
                "{} joints but {} links",
                robot.joints.len(),
                robot.links.len()
            ),
            "give one link per movable joint",
        ));
        return errors;
    }
    if robot.gravity.iter().any(|x| !x.is_finite()) {
        errors.push(Invalid::new(
            Subject::Robot,
            "gravity",
            format!("not finite: {:?}", robot.gravity.as_slice()),
            "give three finite numbers in m/s²",
        ));
    }
    let g = robot.gravity.norm();
    if g.is_finite() && g > MAX_GRAVITY {
        errors.push(Invalid::new(
            Subject::Robot,
            "gravity",
            format!("|g| = {g:e} m/s² is beyond the {MAX_GRAVITY:e} m/s² accepted"),
            "give gravity in m/s² (Earth: [0, 0, -9.81])",
        ));
    }
    for (i, j) in robot.joints.iter().enumerate() {
        let subject = Subject::Joint {
            index: Some(i),
            name: j.name.clone(),
        };
        if j.name.trim().is_empty() {
            errors.push(Invalid::new(
                subject.clone(),
                "name",
                format!("joint {} has an empty name", i + 1),
                "give every joint a name (it names the joint in messages and generated docs)",
            ));
        }
        let v = linear(&j.screw).norm();
        if v.is_finite() && v > MAX_LENGTH {
            errors.push(Invalid::new(
                subject.clone(),
                "screw",
                format!("|v| = {v:e} m: the axis passes farther than {MAX_LENGTH:e} m from the origin of {{0}}"),
                "give lengths in metres",
            ));
        }
        if unit_axes {
            errors.extend(check_screw(subject, j.kind, &j.screw));
        } else if j.screw.iter().any(|x| !x.is_finite()) {
            errors.push(Invalid::new(
                subject,
                "screw",
                format!("not finite: {:?}", j.screw.as_slice()),
                "give six finite numbers (ω, v)",
            ));
        }
        if let Some(l) = &j.limits {
            let interval = |(lo, up): (f64, f64)| lo.is_finite() && up.is_finite() && lo <= up;
            if !l.position().is_none_or(interval) {
                errors.push(Invalid::new(
                    Subject::Joint {
                        index: Some(i),
                        name: j.name.clone(),
                    },
                    "limits",
                    format!(
                        "lower {} and upper {} are not an interval",
                        l.lower, l.upper
                    ),
                    "give finite limits with lower ≤ upper, or none for an unlimited joint",
                ));
            }
        }
    }
    errors.extend(check_mimics(robot));
    for (i, l) in robot.links.iter().enumerate() {
        let subject = Subject::Link {
            index: Some(i),
            name: l.name.clone(),
        };
        if l.name.trim().is_empty() {
            errors.push(Invalid::new(
                subject.clone(),
                "name",
                format!("link {} has an empty name", i + 1),
                "give every link a name (it names the link in messages and generated docs)",
            ));
        }
        if let Some(p) = l.parent {
            if p >= i {
                errors.push(Invalid::new(
                    subject.clone(),
                    "parent",
                    format!(
                        "hangs from link {}, which is not before it (links are in depth-first order: every link after its parent)",
                        p + 1
                    ),
                    "list every link after the link it hangs from",
                ));
            }
        }
        if let Some(e) = check_home(subject.clone(), "home", &l.home) {
            errors.push(e);
        }
        let magnitudes = check_magnitudes(subject.clone(), &l.home, &l.inertia.0);
        // An absurd number makes the inertia's own checks meaningless (cancellation).
        if magnitudes.is_empty() {
            errors.extend(check_spatial_inertia(subject, "inertia", &l.inertia.0));
        }
        errors.extend(magnitudes);
    }
    let frames = std::iter::once((Subject::EndEffector, &robot.end_effector)).chain(
        robot
            .frames
            .iter()
            .map(|f| (Subject::Frame(f.name.clone()), f)),
    );
    for (subject, frame) in frames {
        if let Some(e) = check_home(subject.clone(), "home", &frame.home) {
            errors.push(e);
        }
        if let Some(p) = frame.parent {
            if p >= robot.links.len() {
                let fix = format!("attach the {subject} to one of the robot's links");
                errors.push(Invalid::new(
                    subject,
                    "parent",
                    format!(
                        "is attached to link {}, but the robot has {} links",
                        p + 1,
                        robot.links.len()
                    ),
                    fix,
                ));
            }
        }
    }
    let base = Subject::Link {
        index: None,
        name: robot.base.name.clone(),
    };
    if robot.base.floating {
        let magnitudes =
            check_magnitudes(base.clone(), &Matrix4::identity(), &robot.base.inertia.0);
        if magnitudes.is_empty() {
            errors.extend(check_spatial_inertia(
                base,
                "inertia",
                &robot.base.inertia.0,
            ));
        }
        errors.extend(magnitudes);
    }
    errors
}

/// Checks every joint's [`crate::Mimic`] (see the module table).
pub fn check_mimics(robot: &Robot) -> Vec<Invalid> {
    let mut errors = Vec::new();
    let n = robot.joints.len();
    for (i, j) in robot.joints.iter().enumerate() {
        let Some(m) = &j.mimic else { continue };
        let err = |problem: String, fix: String| {
            Invalid::new(
                Subject::Joint {
                    index: Some(i),
                    name: j.name.clone(),
                },
                "mimic",
                problem,
                fix,
            )
        };
        let independent: Vec<String> = robot
            .joints
            .iter()
            .enumerate()
            .filter(|&(k, l)| k != i && l.is_independent())
            .map(|(_, l)| format!("`{}`", l.name))
            .collect();
        let leaders = format!(
            "make it follow an independent joint: {}",
            independent.join(", ")
        );
        if m.leader >= n {
            errors.push(err(
                format!(
                    "the leader is joint {} but the robot has {n} joints",
                    m.leader + 1
                ),
                leaders,
            ));
        } else if m.leader == i {
            errors.push(err("the joint follows itself".into(), leaders));
        } else if let Some(up) = &robot.joints[m.leader].mimic {
            let leader = &robot.joints[m.leader];
            let root = robot.joints.get(up.leader).map_or("?", |l| l.name.as_str());
            errors.push(err(
                format!(
                    "the leader `{}` is itself a mimic joint (it follows `{root}`): a leader must be an independent joint",
                    leader.name
                ),
                format!(
                    "follow `{root}` directly, with multiplier {} and offset {} (the chain composed)",
                    m.multiplier * up.multiplier,
                    m.multiplier * up.offset + m.offset
                ),
            ));
        }
        if !(m.multiplier.is_finite() && m.multiplier != 0.0) {
            errors.push(err(
                format!("the multiplier is {}: it must be finite and non-zero", m.multiplier),
                "give a finite, non-zero multiplier (θ = multiplier·θ_leader + offset), or lock the joint instead of coupling it".into(),
            ));
        }
        if !m.offset.is_finite() {
            errors.push(err(
                format!("the offset {} is not finite", m.offset),
                "give a finite offset (rad or m)".into(),
            ));
        }
    }
    errors
}

/// Checks a screw axis for its joint kind (see the module table).
pub fn check_screw(subject: Subject, kind: JointKind, s: &nalgebra::Vector6<f64>) -> Vec<Invalid> {
    let mut errors = Vec::new();
    if s.iter().any(|x| !x.is_finite()) {
        errors.push(Invalid::new(
            subject,
            "screw",
            format!("not finite: {:?}", s.as_slice()),
            "give six finite numbers (ω, v)",
        ));
        return errors;
    }
    let w = angular(s).norm();
    let v = linear(s).norm();
    match kind {
        JointKind::Revolute => {
            if (w - 1.0).abs() > UNIT_TOL {
                errors.push(Invalid::new(
                    subject,
                    "screw",
                    format!("a revolute joint needs |ω| = 1, but |ω| = {w}"),
                    "normalise the axis direction ω (and v = −ω × q with it), or give `axis` and `point` instead",
                ));
            } else {
                let pitch = angular(s).dot(&linear(s));
                if pitch.abs() > UNIT_TOL * v.max(1.0) {
                    errors.push(Invalid::new(
                        subject,
                        "screw",
                        format!(
                            "a revolute joint's screw has no pitch (ω · v = 0), but ω · v = {pitch}: this is a helical (screw) joint, which is not supported"
                        ),
                        "for a rotation about the axis ω through the point q write v = −ω × q (or give `axis` and `point` instead of `screw`)",
                    ));
                }
            }
        }
        JointKind::Prismatic => {
            if w > UNIT_TOL {
                errors.push(Invalid::new(
                    subject,
                    "screw",
                    format!("a prismatic joint needs ω = 0, but |ω| = {w}"),
                    "give S = (0, 0, 0, v) with the unit direction of motion v, or make the joint revolute",
                ));
            } else if (v - 1.0).abs() > UNIT_TOL {
                errors.push(Invalid::new(
                    subject,
                    "screw",
                    format!("a prismatic joint needs |v| = 1, but |v| = {v}"),
                    "normalise the direction of motion v",
                ));
            }
        }
    }
    errors
}

/// Checks a link's home offset and its mass and inertia against [`MAX_LENGTH`], [`MAX_MASS`]
/// and [`MAX_INERTIA`]; non-finite numbers are left to the other checks.
fn check_magnitudes(
    subject: Subject,
    home: &Matrix4<f64>,
    g: &nalgebra::Matrix6<f64>,
) -> Vec<Invalid> {
    let mut errors = Vec::new();
    let offset = home.fixed_view::<3, 1>(0, 3).norm();
    if offset.is_finite() && offset > MAX_LENGTH {
        errors.push(Invalid::new(
            subject.clone(),
            "home",
            format!(
                "the frame is {offset:e} m from its parent's, beyond the {MAX_LENGTH:e} m accepted"
            ),
            "give lengths in metres",
        ));
    }
    let mass = g[(3, 3)];
    if mass.is_finite() && mass > MAX_MASS {
        errors.push(Invalid::new(
            subject.clone(),
            "mass",
            format!("{mass:e} kg is beyond the {MAX_MASS:e} kg accepted"),
            "give the mass in kg",
        ));
    }
    let inertia = g.fixed_view::<3, 3>(0, 0).amax();
    if inertia.is_finite() && inertia > MAX_INERTIA && mass <= MAX_MASS {
        errors.push(Invalid::new(
            subject,
            "inertia",
            format!("an entry of {inertia:e} kg·m² is beyond the {MAX_INERTIA:e} kg·m² accepted"),
            "give the inertia in kg·m²",
        ));
    }
    errors
}

/// Checks that `t` is a rigid transform (see the module table).
pub fn check_home(subject: Subject, field: &str, t: &Matrix4<f64>) -> Option<Invalid> {
    if t.iter().any(|x| !x.is_finite()) {
        return Some(Invalid::new(
            subject,
            field,
            "the home frame has a non-finite entry",
            "give finite numbers",
        ));
    }
    if is_rigid_transform(t, ORTHO_TOL) {
        return None;
    }
    let r = crate::lie::rotation(t);
    let ortho = (r.transpose() * r - Matrix3::identity()).amax();
    Some(Invalid::new(
        subject,
        field,
        format!(
            "the home frame is not a rigid transform (‖RᵀR − 1‖max = {ortho:.3e}, det R = {:.6}, last row {:?})",
            r.determinant(),
            [t[(3, 0)], t[(3, 1)], t[(3, 2)], t[(3, 3)]]
        ),
        format!("give an orthonormal rotation with det +1 (within {ORTHO_TOL:e}) and last row (0, 0, 0, 1), e.g. as xyz + rpy"),
    ))
}

/// Checks a 6×6 spatial inertia: structure, mass, and physical consistency of the
/// rotational inertia about the centre of mass.
pub fn check_spatial_inertia(
    subject: Subject,
    field: &str,
    g: &nalgebra::Matrix6<f64>,
) -> Vec<Invalid> {
    let mut errors = Vec::new();
    let err = |problem: String, fix: &str| Invalid::new(subject.clone(), field, problem, fix);
    if g.iter().any(|x| !x.is_finite()) {
        errors.push(err(
            "the inertia has a non-finite entry".into(),
            "give finite numbers",
        ));
        return errors;
    }
    let scale = g.amax().max(1e-300);
    let tol = INERTIA_TOL * scale;
    if (g - g.transpose()).amax() > tol {
        errors.push(err(
            "the 6×6 spatial inertia is not symmetric".into(),
            "give a symmetric matrix [[I, m[c]], [m[c]ᵀ, m·1]]",
        ));
        return errors;
    }
    let m = g[(3, 3)];
    let lower = g.fixed_view::<3, 3>(3, 3).into_owned();
    if (lower - Matrix3::identity() * m).amax() > tol {
        errors.push(err(
            "the lower-right 3×3 block is not m·1₃".into(),
            "the lower-right block of a spatial inertia is the mass times the identity",
        ));
        return errors;
    }
    let off = g.fixed_view::<3, 3>(0, 3).into_owned();
    if (off + off.transpose()).amax() > tol {
        errors.push(err(
            "the upper-right 3×3 block is not skew-symmetric (it must be m[c])".into(),
            "the off-diagonal blocks of a spatial inertia are m[c] and its transpose",
        ));
        return errors;
    }
    errors.extend(check_mass_and_inertia(
        subject.clone(),
        field,
        m,
        &crate::inertia::SpatialInertia(*g).rotational_about_com(),
    ));
    errors
}

/// Checks a mass and a rotational inertia about the centre of mass: `m ≥ 0`, no rotational
/// inertia without mass, symmetric, positive semidefinite, triangle inequality.
pub fn check_mass_and_inertia(
    subject: Subject,
    field: &str,
    mass: f64,
    i_com: &Matrix3<f64>,
) -> Vec<Invalid> {
    let mut errors = Vec::new();
    let err = |problem: String, fix: &str| Invalid::new(subject.clone(), field, problem, fix);
    if !mass.is_finite() || i_com.iter().any(|x| !x.is_finite()) {
        errors.push(err(
            "the mass or inertia is not finite".into(),
            "give finite numbers",
        ));
        return errors;
    }
    if mass < 0.0 {
        errors.push(err(
            format!("negative mass {mass} kg"),
            "give a mass ≥ 0 (0 for a massless link)",
        ));
        return errors;
    }
    let scale = i_com.amax();
    if mass == 0.0 {
        if scale > 0.0 {
            errors.push(err(
                format!("a massless link carries rotational inertia (largest entry {scale})"),
                "give the link's mass, or set its rotational inertia to zero",
            ));
        }
        return errors;
    }
    // Every principal moment is at most m·R², R the body's extent from its centre of mass:
    // an inertia that needs the mass beyond MAX_LENGTH is a unit slip (grams for kg), like
    // the other magnitudes.
    let gyration = (scale / mass).sqrt();
    if gyration > MAX_LENGTH {
        errors.push(err(
            format!(
                "a rotational inertia of {scale:e} kg·m² (largest entry) with a mass of {mass:e} kg puts the mass {gyration:.1e} m from its centre (radius of gyration √(I/m)), beyond the {MAX_LENGTH:e} m accepted"
            ),
            "give the mass in kg and the inertia in kg·m² about the centre of mass",
        ));
        return errors;
    }
    let tol = INERTIA_TOL * scale.max(1e-300);
    if (i_com - i_com.transpose()).amax() > tol {
        errors.push(err(
            "the rotational inertia is not symmetric".into(),
            "give ixy, ixz, iyz once each (the matrix is symmetric)",
        ));
        return errors;
    }
    let eig = SymmetricEigen::new(*i_com).eigenvalues;
    let mut p = [eig[0], eig[1], eig[2]];
    p.sort_by(f64::total_cmp);
    if p[0] < -tol {
        errors.push(err(
            format!(
                "the rotational inertia about the centre of mass is not positive semidefinite (principal moments {:.6e}, {:.6e}, {:.6e})",
                p[0], p[1], p[2]
            ),
            "check the signs of the products of inertia (URDF ixy is +∫xy dm's negative: I = [[ixx, ixy, ixz], …])",
        ));
    } else if p[0] + p[1] < p[2] - tol {
        errors.push(err(
            format!(
                "the principal moments {:.6e}, {:.6e}, {:.6e} break the triangle inequality (I₁ + I₂ ≥ I₃): no rigid body has this inertia",
                p[0], p[1], p[2]
            ),
            "check the inertia values and their units (kg·m²); a thin rod has I₁ + I₂ = I₃ at most",
        ));
    }
    errors
}
