//! The URDF loader: a URDF file to a [`Robot`] in Modern Robotics form, keeping URDF's
//! joint frames.
//!
//! # What comes out
//!
//! - A kinematic tree. The movable joints (revolute, continuous, prismatic) are listed depth
//!   first from the root link, the child joints of a link visited in byte-wise order of their
//!   names, fixed joints traversed but not listed: the order of urdfdom and Pinocchio
//!   (`model.names`, `model.parents`). A serial chain comes out root to tip as before.
//! - Each movable joint's child link is a body, link i. Links welded to it by fixed joints
//!   (flanges, hands, sensors, feet) merge into it. The space frame {0} is the frame of the
//!   URDF root link, which is the base ([`crate::Base`], named after it) together with the
//!   links welded to it; frame {i} is the child link frame of movable joint i.
//! - `λ(i)` ([`crate::Link::parent`]) is the body that joint i's parent link belongs to
//!   (`None` for the base), always an earlier one.
//! - `M_{λ(i),i}` ([`crate::Link::home`]) is joint i's `<origin>` (`R = Rz(yaw) Ry(pitch)
//!   Rx(roll)`, right angles exact, see [`origin`]) with the fixed joints between body λ(i)'s
//!   link and joint i folded in.
//! - `G_i` ([`crate::Link::inertia`]) is the spatial inertia, in {i}, of link i and of every
//!   link welded to it. The base's inertia ([`crate::Base::inertia`], in {0}) is that of the
//!   root link and the links welded to it; it counts only when the base floats.
//! - `S_i = [Ad_{M_{0i}}] (a_i, 0)` for a revolute or continuous joint, `(0, R_{0i} a_i)` for a
//!   prismatic one, with `a_i` the unit `<axis>` (default `(1, 0, 0)`).
//! - The end effector {n+1} is [`LoadOptions::tip`] (any link of the robot; it is attached to
//!   that link's body, [`crate::EndEffector::parent`], `None` for the base), by default the
//!   child link of the last movable joint in the order above.
//! - Continuous joints are unlimited revolute joints; limits with lower = upper = 0 are none.
//!   Their `<limit velocity effort>` is kept, with position limits −∞ and +∞.
//!   `<dynamics damping friction>` is kept on the [`crate::Joint`] (viscous b and Coulomb μ, used
//!   only by the friction functions, see [`crate::actuation`]). Gravity is `(0, 0, −9.81)`.
//!
//! # Floating base
//!
//! The base floats ([`crate::Base::floating`]) when [`LoadOptions::floating_base`] asks for it
//! (the root link is then the floating base), or when the file says so itself: a root link
//! without inertia (no `<inertial>`, or mass and inertia zero) whose only child joint has type
//! `floating`, as in `world` → `floating` → `base_link`. The robot is then the subtree of
//! that joint's child link, which is the base: {0} is the child link's frame, and the floating
//! joint's `<origin>` is ignored (a free joint can put the base anywhere; q = 0 puts it at
//! the world origin). The world link is not part of the robot (it cannot be the `tip`).
//! On a floating base the inertias of the base's links are checked like those of any moving
//! body.
//!
//! # What is read, what is skipped
//!
//! Only what the dynamics need: `<link>` with its `<inertial>`, `<joint>` with its
//! `<origin>`, `<parent>`, `<child>`, `<axis>`, `<limit>`, `<dynamics>` and `<mimic>`.
//! Everything else is skipped unchecked, as urdfdom and Pinocchio skip what they do not use
//! (see the `strip` module): `<visual>`, `<collision>` and their geometry (Pinocchio's `<capsule>`
//! included), materials and textures, `<gazebo>`, `<transmission>`, `<calibration>`,
//! `<safety_controller>`, unknown tags and unknown attributes. Skipped elements must still be
//! well-formed XML.
//!
//! # Mimic joints
//!
//! A movable joint with `<mimic joint="L" multiplier="m" offset="o">` (m = 1, o = 0 by
//! default) is a coupled coordinate, as in Pinocchio 3 (`buildModelFromUrdf(.., mimic=True)`):
//! it keeps its place among the joints and moves its link by `θ = m·θ_L + o`
//! ([`crate::Joint::mimic`], [`crate::mimic`]), but q, ν, ν̇ and τ hold the independent joints
//! only ([`crate::Robot::nq`], [`crate::Robot::joint_names`]). A chain (`c` mimics `b`, which
//! mimics `a`) is resolved to its root leader; the leader may come before or after its
//! followers in the joint order. Grippers and coupled fingers thus load without locks.
//!
//! # Locks
//!
//! [`LoadOptions::lock`] (`--lock JOINT=VALUE`) turns movable joints into fixed ones at a
//! value (see the `locks` module), e.g. to freeze gripper fingers: their links then merge
//! into the body they hang from. The value must be finite, at most 1e6 in magnitude and
//! within the joint's `<limit lower upper>` (continuous joints have none). Locking a joint
//! also locks the movable joints that `<mimic>` it, at `multiplier·value + offset`; a follower
//! locked explicitly too must be locked at that same value. A follower cannot be locked while
//! its leader moves (that would break the coupling): the error gives the lock of the leader
//! that fixes the follower at the value asked for, `--lock L=(value − o)/m`.
//!
//! # What is refused, by name
//!
//! Malformed XML, also inside skipped elements (with line and column where they can be
//! found); missing required fields of what is read (a link's `name`, `<inertial>` without
//! `<mass>` or `<inertia>`, a joint's `name`, `type`, `<parent>`, `<child>`, an `<axis>`
//! without `xyz`, `<limit>` without `velocity` before URDF 1.2, `<mimic>` without `joint`);
//! numbers that do not parse or are not finite; unknown links, links with two parents and
//! closed loops, several roots; `planar` joints, and `floating` joints anywhere but as the
//! floating root joint above; a robot without movable joints; a movable `<mimic>` joint whose
//! leader the file does not have or is not movable (fixed, floating, planar), mimic joints in
//! a cycle, a `<mimic multiplier>` that is zero (the error suggests locking the follower
//! instead, `--lock A=0` on the CLI, [`LoadOptions::lock`] for the Builder and derive); a
//! follower locked while its leader moves (the error names the leader's lock); negative
//! masses and physically impossible inertias (checked per URDF link, on moving bodies and on a
//! floating base); zero axes; lock values that are not finite, absurd or outside the joint's
//! limits (blamed on the lock, not on the file); a `tip` that names no link of the robot.

mod assemble;
mod convert;
mod locks;
pub mod origin;
mod parse;
mod strip;
mod tree;
mod xml_scan;

use crate::error::{Invalid, ModelError, Subject};
use crate::load::LoadOptions;
use crate::robot::Robot;

/// Parses a URDF file; `file` names it in errors. `options.tip` and `options.lock` apply
/// here; `options.gravity` is applied by the caller ([`crate::load::from_str`]), which also
/// validates the result.
pub fn from_str(text: &str, file: &str, options: &LoadOptions) -> Result<Robot, ModelError> {
    let mut urdf = parse::read(text, file)?;
    if let Some(tol) = options.snap_angles {
        origin::snap_rpy(&mut urdf, tol);
    }
    let mut robot =
        convert_robot(&urdf, options).map_err(|e| ModelError::Invalid(e).in_file(file))?;
    robot.source = file.to_string();
    Ok(robot)
}

/// The `rpy` angles of a URDF text's `<origin>`s whose distance from a multiple of π/2 is
/// in `(above, up_to]` ([`origin::near_right_angles`]): what `snap_angles` = `up_to` would
/// change beyond a tolerance `above`.
pub fn near_right_angles(
    text: &str,
    file: &str,
    above: f64,
    up_to: f64,
) -> Result<Vec<origin::NearRightAngle>, ModelError> {
    let urdf = parse::read(text, file)?;
    Ok(origin::near_right_angles(&urdf, above, up_to))
}

/// The parsed URDF to a robot; every error found on the way, without the file name.
fn convert_robot(urdf: &urdf_rs::Robot, options: &LoadOptions) -> Result<Robot, Vec<Invalid>> {
    let mut tree = tree::Tree::new(urdf)?;
    let floating_root = tree.floating_root(urdf);
    let mimics = locks::mimics(urdf);
    let locks = locks::resolve(urdf, &options.lock, &mimics)?;
    let mut errors = Vec::new();
    let joints: Vec<_> = urdf
        .joints
        .iter()
        .enumerate()
        .map(|(ji, j)| match floating_root {
            // Above the base: never walked, its origin is not used.
            Some(f) if f == ji => Ok(convert::JointModel::fixed(nalgebra::Matrix4::identity())),
            _ => convert::joint(j, locks.get(&ji).copied()),
        })
        .filter_map(|r| r.map_err(|e| errors.extend(e)).ok())
        .collect();
    let links: Vec<_> = urdf
        .links
        .iter()
        .map(convert::link)
        .filter_map(|r| r.map_err(|e| errors.extend(e)).ok())
        .collect();
    let mut link_index = |name: &str, field: &str, what: &str| match tree
        .link_names
        .iter()
        .position(|l| l == name)
    {
        Some(l) => Some(l),
        None => {
            errors.push(Invalid::new(
                Subject::Link {
                    index: None,
                    name: name.to_string(),
                },
                field,
                format!("the file has no link of this name to use as {what}"),
                format!("give one of the links: {}", tree.link_names.join(", ")),
            ));
            None
        }
    };
    let tip = options
        .tip
        .as_deref()
        .and_then(|name| link_index(name, "tip", "the end effector"));
    let frames: Option<Vec<usize>> = options.frames.as_ref().map(|names| {
        names
            .iter()
            .filter_map(|name| link_index(name, "frame", "a frame"))
            .collect()
    });
    if !errors.is_empty() {
        return Err(errors);
    }
    let movable: Vec<usize> = tree
        .joint_order()
        .into_iter()
        .filter(|&j| joints[j].kind.is_some())
        .collect();
    let mimic = locks::mimic_links(urdf, &movable, &mimics)?;
    let floating = options.floating_base || floating_root.is_some();
    let mut robot = assemble::robot(
        urdf,
        &tree,
        &joints,
        &links,
        &movable,
        tip,
        frames.as_deref(),
        floating,
    )?;
    for (joint, mimic) in robot.joints.iter_mut().zip(mimic) {
        joint.mimic = mimic;
    }
    Ok(robot)
}
