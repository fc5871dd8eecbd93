//! The TOML robot file: a kinematic tree (a serial chain unless said otherwise) written in
//! the vocabulary of Modern Robotics, chapter 8 (`M_{i−1,i}`, `S_i`, `G_i`), for people to
//! write and read.
//!
//! # The format
//!
//! A complete annotated example (every key; `#` starts a comment). Units are SI: m, kg, s,
//! rad. Numbers may be written as integers (`1`) or floats (`1.0`). Unknown keys are errors,
//! so a misspelt key is never silently ignored.
//!
//! ```toml
//! name = "demo"                    # required
//! description = "two joints"       # optional, free text
//! gravity = [0.0, 0.0, -9.81]      # optional, in {0}, m/s²; default [0, 0, -9.81]
//!
//! [base]                           # optional; default: a fixed, massless base called "base"
//! name = "pedestal"                # optional; default "base"
//! floating = false                 # optional: true puts a free 6-DoF joint between the
//! #                                # world and the base (q = (p, quat, θ), see the crate docs)
//! mass = 10.0                      # inertial keys as a link's (below), in the base frame {0};
//! inertia = [0.1, 0.1, 0.1, 0, 0, 0]  # they count only when the base floats; none: massless
//! com = [0, 0, -0.05]              # (also shape, spatial_inertia, [[base.body]], …)
//!
//! # One [[joint]] per movable joint. Joint i moves link i ([joint.link]); every joint comes
//! # after the joint of the link it hangs from (depth-first order, as the vectors list them).
//! [[joint]]
//! name = "shoulder"                # required, unique
//! type = "revolute"                # "revolute" or "prismatic"
//! screw = [0, 0, 1, 0, 0, 0]       # S_i = (ω, v) in {0} at the home configuration, or:
//! # axis = [0, 0, 1]               # the axis direction in {0} (normalised for you), and
//! # point = [0, 0, 0]              # a point on it in {0}: S_i = (ω̂, −ω̂ × q).
//! #                                # A prismatic joint takes `axis` only: S_i = (0, ω̂).
//! limits = [-3.14, 3.14]           # optional [lower, upper] (rad or m); absent: unlimited
//! velocity_limit = 3.0             # optional, rad/s or m/s (with or without `limits`)
//! effort_limit = 150.0             # optional, N·m or N (with or without `limits`)
//! damping = 0.0                    # optional, ≥ 0, viscous friction b, N·m·s/rad; default 0
//! friction = 0.0                   # optional, ≥ 0, Coulomb friction μ, N·m; default 0
//! #                                # (both only in τ_friction = b q̇ + μ sgn(q̇), below)
//! rotor_inertia = 0.0              # optional, ≥ 0, rotor inertia I_rotor, kg·m², motor side
//! gear_ratio = 1.0                 # optional, ≠ 0, motor turns per joint turn; default 1:
//! #                                # the armature G²·I_rotor is added to M's diagonal
//! # mimic = { joint = "elbow", multiplier = 1.0, offset = 0.0 }  # optional: a coupled
//! #                                # joint, θ = multiplier·θ_elbow + offset (see "Mimic joints")
//!
//! [joint.link]                     # the link moved by this joint, with its frame {i}
//! name = "upper_arm"               # required, unique (and not the base's name)
//! home = { xyz = [0, 0, 0.5], rpy = [0, 0, 0] }  # M_{λ(i),i}: pose of {i} in its parent's
//! #                                # frame at q = 0 (here the base's {0})
//! mass = 2.0                       # kg
//! inertia = [0.02, 0.02, 0.01, 0, 0, 0]          # [ixx, iyy, izz, ixy, ixz, iyz], kg·m²
//! com = [0, 0, 0.1]                # optional: centre of mass in {i}; default [0, 0, 0]
//!
//! [[joint]]
//! name = "elbow"
//! type = "revolute"
//! parent = "upper_arm"             # optional: the link this joint's link hangs from, the
//! #                                # base or an earlier joint's link; default: the previous
//! #                                # joint's link (the base for the first joint)
//! axis = [0, 1, 0]
//! point = [0, 0, 0.5]
//!
//! [joint.link]
//! name = "forearm"
//! home = [[1, 0, 0, 0],            # a pose may also be a 4×4 matrix, row by row
//!         [0, 1, 0, 0],
//!         [0, 0, 1, 0.4],
//!         [0, 0, 0, 1]]
//!
//! [[joint.link.body]]              # a link may be several bodies, added in {i}
//! name = "tube"                    # optional, used in messages
//! shape = { cylinder = [0.03, 0.4] }   # radius, height (along z of the body frame)
//! density = 2700.0                 # kg/m³ (or `mass`)
//! frame = { xyz = [0, 0, 0.2] }    # pose of the body frame {b} in {i}; default {i}
//!
//! [[joint.link.body]]
//! name = "gripper"
//! mass = 0.5
//! inertia = [0.001, 0.001, 0.001, 0, 0, 0]
//! frame = { xyz = [0, 0, 0.4], rpy = [0, 1.5707963267948966, 0] }
//!
//! [[joint]]                        # a second branch: a camera on the upper arm
//! name = "camera_pan"
//! type = "revolute"
//! parent = "upper_arm"             # not the previous joint's link (forearm): a tree
//! axis = [0, 0, 1]
//! point = [0.1, 0, 0.3]
//!
//! [joint.link]
//! name = "camera"
//! home = { xyz = [0.1, 0, -0.2] }  # in upper_arm's frame
//! shape = { box = [0.05, 0.1, 0.05] }
//! mass = 0.3
//!
//! [end_effector]                   # optional; default: name "end_effector", home = identity
//! name = "tool"
//! parent = "forearm"               # optional: the link (or base) it is attached to;
//! #                                # default: the last joint's link
//! home = { xyz = [0, 0, 0.45] }    # its pose in that link's frame
//!
//! [[frame]]                        # optional, any number: named frames (feet, hands) whose
//! name = "camera_optical"          # pose and Jacobians the generated code computes
//! parent = "camera"                # required: the link (or base) it is attached to
//! home = { rpy = [-1.5708, 0, -1.5708] }  # its pose in that link's frame (default identity)
//! ```
//!
//! (In TOML, `[joint.link]` and `[[joint.link.body]]` belong to the `[[joint]]` above them,
//! `[[base.body]]` to `[base]`.)
//!
//! ## Trees and the base
//!
//! Link i hangs from `λ(i)`: its joint's `parent`, by default the previous joint's link. The
//! joints are listed so that every joint comes after the joint of the link it hangs from
//! (depth first is the usual order); a `parent` that is unknown, the joint's own link or a
//! later joint's link is an error. `S_i` is always in {0}, the base frame at the home
//! configuration. The base is fixed unless `[base] floating = true` (or the loader is asked
//! for a floating base); its inertial keys are a link's, expressed in {0}, and are part of
//! the dynamics only when it floats.
//!
//! ## Named parameters and expressions
//!
//! `[parameters]` declares names with numeric values (`m1 = 2.0`, `L1 = 1.0`; ASCII letters,
//! digits and `_`, starting with a letter; not `pi`). Anywhere the format takes a number, a
//! string is an arithmetic expression over them: `mass = "m1"`,
//! `home = { xyz = ["L1/2", 0, 0] }`, `inertia = ["m1*L1^2/12", …]`, `rpy = [0, "pi/2", 0]`
//! (`+ - * / ^`, parentheses, numbers, the parameters and `pi`; see
//! [`crate::parameters`]). Each is evaluated when the file is read, in place, so the robot is
//! the numeric robot it describes and later errors keep their line numbers. An unknown name
//! or a malformed expression is an error naming the link or joint and the field. The
//! expressions in gravity, `screw`, `point`, `home.xyz`, `mass`, `com` and `inertia` are kept
//! ([`crate::Robot::parameters`]) for `dynamics-gen equations --symbolic`, which prints the
//! equations with the named parameters as symbols.
//!
//! ## Mimic joints
//!
//! `mimic = { joint = "LEADER", multiplier = m, offset = o }` (m default 1, o default 0)
//! couples a joint to another, as URDF's `<mimic>`: `θ = m·θ_LEADER + o` (and `θ̇ = m·θ̇_LEADER`).
//! The joint keeps its link and moves it, but it is not a coordinate: q, ν, ν̇ and τ hold the
//! other joints only (see [`crate::mimic`]). The leader may come before or after the joint
//! and may follow another joint in turn (the chain is composed); a leader that is no joint of
//! the robot, the joint itself, a cycle of mimics, or a multiplier that is zero or not finite
//! is an error naming the joint and the field `mimic`.
//!
//! ## Actuation and friction
//!
//! `rotor_inertia` (`I_rotor`, ≥ 0) and `gear_ratio` (G, finite and non-zero) describe the
//! motor behind the joint: its reflected inertia, the armature `G²·I_rotor`
//! ([`crate::Joint::armature`], Modern Robotics §8.9.2), is added to the joint's diagonal
//! entry of the mass matrix. `damping` (b) and `friction` (Coulomb μ), both ≥ 0, give the
//! friction force `b q̇ + μ sgn(q̇)`, which is not part of M, c or g: the friction functions
//! compute it and a caller adds it, `τ = ID + τ_friction` (see [`crate::actuation`]).
//! Leaving the four keys out (or 0, 0, 0, 1) gives a joint without motor or friction.
//!
//! ## Poses
//!
//! `home`, `frame` and `end_effector.home` are poses `T = [[R, p], [0, 1]]`, written as
//! - a table `{ xyz = [x, y, z], rpy = [roll, pitch, yaw] }` (either may be left out for
//!   zero), with `R = Rz(yaw) Ry(pitch) Rx(roll)` as in URDF, or
//! - a 4×4 matrix, a list of its four rows (exact, for rotations whose rpy angles would
//!   lose digits). The loader requires a rigid transform (checked by
//!   [`crate::validate`] to 1e-9).
//!
//! `home` is relative, `M_{λ(i),i}`, as in the book's `Mlist`: frame {i} seen from its
//! parent's frame ({i−1} on a serial chain; the base's frame is {0}).
//! `end_effector.home` and `frame.home` are relative to their `parent` link.
//!
//! ## Inertia of a link
//!
//! Give a link (or each of its bodies) exactly one of these. Every body has a frame {b},
//! placed in the link frame {i} by `frame` (default: {b} = {i}); the result is expressed in
//! {i} by `G_i = [Ad_{T_bi}]ᵀ G_b [Ad_{T_bi}]` (Exercise 8.3), and a link's bodies are
//! added (Exercise 8.2, the parallel-axis theorem in 6×6 form).
//!
//! 1. **Mass and rotational inertia**: `mass` and `inertia = [ixx, iyy, izz, ixy, ixz, iyz]`,
//!    the entries of the matrix `I = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]` —
//!    the same convention as URDF's `<inertia>`: the products are the matrix entries
//!    (`ixy = −∫xy dm`), not the integrals. By default `I` is about the centre of mass, with
//!    the axes of {b}; `com = [x, y, z]` is the centre of mass in {b} (default: the origin of
//!    {b}, as the book puts {i} at the COM). With `inertia_about = "origin"`, `I` is about the
//!    origin of {b} instead (e.g. an inertia measured about the joint); `com` then still
//!    says where the centre of mass is. A point mass has `inertia = [0, 0, 0, 0, 0, 0]`; a
//!    massless link is `mass = 0` alone.
//! 2. **A primitive solid** (Exercise 8.1), homogeneous, centred at the origin of {b} with
//!    its axes along {b}'s, with `mass` or `density` (kg/m³; the mass is density × volume):
//!    `shape = { box = [w, l, h] }` (edges along x, y, z), `{ cylinder = [r, h] }` (axis z),
//!    `{ sphere = r }`, `{ ellipsoid = [a, b, c] }` (semi-axes along x, y, z), and the thin
//!    `{ plate = [w, l] }` (in the xy plane) and `{ disc = r }` (normal z), which take a
//!    `mass` only. Place the solid with `frame`; `com` and `inertia` are not allowed.
//! 3. **The 6×6 spatial inertia** in {b}: `spatial_inertia = [[…6…], …6 rows…]`,
//!    `[[I_b, m[c]], [m[c]ᵀ, m·1₃]]` about the origin of {b} (any frame, Exercise 8.3).
//! 4. **Several bodies**: `[[joint.link.body]]` tables (`[[base.body]]` for the base), each
//!    with one of 1–3, its own `frame` and an optional `name`; the link itself then has no
//!    inertial keys.
//!
//! The base takes the same keys, in its frame {0}, and may have none (massless).
//!
//! # Errors
//!
//! Malformed TOML, a wrong type, a missing required key or an unknown key is a
//! [`ModelError::Parse`] with the 1-based line and column. Everything else — wrong array
//! lengths, a mass without inertia, both `mass` and `density`, a negative mass, an inertia
//! that no rigid body has, a non-rigid `frame`, … — is a [`ModelError::Invalid`] naming the
//! file, the link or joint, the field and the fix; all such problems are reported at once.
//!
//! [`from_str`] checks the file and builds the robot exactly as written (a screw axis with
//! `|ω| ≠ 1` is kept, as the book's functions accept it); [`crate::load()`] then validates
//! the robot ([`crate::validate`]: unit screw axes, rigid homes, physical inertias).

// The helpers return `Result<_, Invalid>` on a cold path whose errors are collected into a
// `Vec<Invalid>`; boxing them would only add noise.
#![allow(clippy::result_large_err)]

mod body;
mod convert;
mod locate;
mod params;
mod pose;
mod schema;

use crate::error::ModelError;
use crate::robot::Robot;

/// Parses a TOML robot file and builds the robot as written; `file` names it in errors.
///
/// Schema-level problems are errors; the robot itself is not validated here (see the
/// module docs; [`crate::load::from_str`] does both).
pub fn from_str(text: &str, file: &str) -> Result<Robot, ModelError> {
    let (substituted, parameters) = match params::substitute(text) {
        Err(errors) => return Err(ModelError::Invalid(errors).in_file(file)),
        Ok(None) => (None, crate::parameters::Parameters::default()),
        Ok(Some((text, parameters))) => (Some(text), parameters),
    };
    let text = substituted.as_deref().unwrap_or(text);
    let spec: schema::RobotFile = toml::from_str(text).map_err(|e| {
        let (line, column) = e
            .span()
            .map(|span| line_column(text, span.start))
            .unwrap_or((0, 0));
        let message = hint(e.message().trim(), text, e.span());
        let message = match e.span().and_then(|span| locate::context(text, span.start)) {
            Some(context) => format!("{message} (in {context})"),
            None => message,
        };
        ModelError::Parse {
            file: file.to_string(),
            line,
            column,
            message,
        }
    })?;
    let mut robot =
        convert::build(spec, file).map_err(|errors| ModelError::Invalid(errors).in_file(file))?;
    robot.parameters = parameters;
    Ok(robot)
}

/// The TOML parser's `message`, with the key named and a fix where the parser gives neither.
fn hint(message: &str, text: &str, span: Option<std::ops::Range<usize>>) -> String {
    let joint_kind = |kind: &str| format!("unknown variant `{kind}`");
    if message == "duplicate key" {
        let key = span
            .and_then(|span| text.get(span.start..))
            .and_then(|rest| rest.split(['=', '\n']).next())
            .map(str::trim)
            .filter(|key| !key.is_empty());
        return match key {
            Some(key) => format!("duplicate key `{key}`; fix: give each key once"),
            None => format!("{message}; fix: give each key once"),
        };
    }
    if message.starts_with(&joint_kind("floating")) {
        return format!(
            "{message}; fix: a floating base is `floating = true` in `[base]`, not a joint"
        );
    }
    if message.starts_with(&joint_kind("planar")) || message.starts_with(&joint_kind("spherical")) {
        return format!(
            "{message}; fix: write a multi-degree-of-freedom joint as revolute and prismatic joints with massless links between them"
        );
    }
    if message.starts_with(&joint_kind("fixed")) {
        return format!(
            "{message}; fix: a rigidly attached body is a `[[joint.link.body]]` of the link it is fixed to, not a joint"
        );
    }
    message.to_string()
}

/// The 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_counts_from_one() {
        let text = "a = 1\nbé = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        // "bé" is 3 bytes; the space after it is the 3rd character of line 2.
        assert_eq!(line_column(text, 9), (2, 3));
        assert_eq!(line_column(text, 1000), (3, 1));
    }

    #[test]
    fn velocity_and_effort_limits_need_no_position_limits() {
        let text = include_str!("../../../robots/pendulum.toml").replacen(
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0, 0, 0]\neffort_limit = 12.5\nvelocity_limit = 3.0",
            1,
        );
        let opts = crate::load::LoadOptions::default();
        let robot = crate::load::from_str(&text, crate::Format::Toml, "pendulum.toml", &opts)
            .expect("a continuous joint with velocity and effort limits");
        let l = robot.joints[0].limits.expect("the limits are kept");
        assert_eq!((l.lower, l.upper), (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!((l.velocity, l.effort), (Some(3.0), Some(12.5)));
        assert_eq!(robot.joints[1].limits, None);
    }
}
