//! The URDF loader: a URDF file to a [`Robot`] in Modern Robotics form, keeping URDF's
//! joint frames.
//!
//! # What comes out
//!
//! - The movable joints (revolute, continuous, prismatic) from the root to the tip. The space
//!   frame {0} is the URDF root link's frame; frame {i} is the child link frame of movable
//!   joint i.
//! - `M_{i−1,i}` ([`crate::Link::home`]) is joint i's `<origin>` (`R = Rz(yaw) Ry(pitch)
//!   Rx(roll)`, right angles exact, see [`origin`]) with the fixed joints between joint i−1's
//!   child link and joint i folded in.
//! - `G_i` ([`crate::Link::inertia`]) is the spatial inertia, in {i}, of link i and of every
//!   link welded to it by fixed joints (fixed-only side branches: flanges, hands, sensors).
//!   Mass on the fixed base (links before the first movable joint) is ignored.
//! - `S_i = [Ad_{M_{0i}}] (a_i, 0)` for a revolute or continuous joint, `(0, R_{0i} a_i)` for a
//!   prismatic one, with `a_i` the unit `<axis>` (default `(1, 0, 0)`).
//! - The end effector {n+1} is the child link of the last movable joint, or
//!   [`LoadOptions::tip`], a link welded to it.
//! - Continuous joints are unlimited revolute joints; limits with lower = upper = 0 are none.
//!   `<dynamics damping friction>` is kept on the [`crate::Joint`]. Gravity is `(0, 0, −9.81)`.
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
//! # Locks
//!
//! [`LoadOptions::lock`] (`--lock JOINT=VALUE`) turns movable joints into fixed ones at a
//! value (see the `locks` module): the value must be finite, at most 1e6 in magnitude and within the
//! joint's `<limit lower upper>` (continuous joints have none). Locking a joint also locks
//! the movable joints that `<mimic>` it, at `multiplier·value + offset`; a follower locked
//! explicitly too must be locked at that same value.
//!
//! # What is refused, by name
//!
//! Malformed XML, also inside skipped elements (with line and column where they can be
//! found); missing required fields of what is read (a link's `name`, `<inertial>` without
//! `<mass>` or `<inertia>`, a joint's `name`, `type`, `<parent>`, `<child>`, an `<axis>`
//! without `xyz`, `<limit>` without `velocity` before URDF 1.2, `<mimic>` without `joint`);
//! numbers that do not parse or are not finite; unknown links, links with two parents and
//! closed loops, several roots; `floating`/`planar` joints; movable joints with `<mimic>`
//! whose leader is not locked; negative masses and physically impossible inertias (checked
//! per URDF link); zero axes; lock values that are not finite, absurd or outside the joint's
//! limits (blamed on the lock, not on the file); and trees: two or more branches with
//! movable joints. A tree is refused with one error per branch point on the chain this
//! loader would keep, each with the locks that remove its other branches, and all of them
//! (with the mimic joints left on the chain) in the first error, in the form
//! `--lock A=0,B=0` (CLI), [`LoadOptions::lock`] for the Builder and derive.

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
    let urdf = parse::read(text, file)?;
    let mut robot =
        convert_robot(&urdf, options).map_err(|e| ModelError::Invalid(e).in_file(file))?;
    robot.source = file.to_string();
    Ok(robot)
}

/// The parsed URDF to a robot; every error found on the way, without the file name.
fn convert_robot(urdf: &urdf_rs::Robot, options: &LoadOptions) -> Result<Robot, Vec<Invalid>> {
    let tree = tree::Tree::new(urdf)?;
    let mimics = locks::mimics(urdf);
    let locks = locks::resolve(urdf, &options.lock, &mimics)?;
    let mut errors = Vec::new();
    let joints: Vec<_> = urdf
        .joints
        .iter()
        .enumerate()
        .map(|(ji, j)| convert::joint(j, locks.get(&ji).copied()))
        .filter_map(|r| r.map_err(|e| errors.extend(e)).ok())
        .collect();
    let links: Vec<_> = urdf
        .links
        .iter()
        .map(convert::link)
        .filter_map(|r| r.map_err(|e| errors.extend(e)).ok())
        .collect();
    let tip = match &options.tip {
        None => None,
        Some(name) => match tree.link_names.iter().position(|l| l == name) {
            Some(l) => Some(l),
            None => {
                errors.push(Invalid::new(
                    Subject::Link {
                        index: None,
                        name: name.clone(),
                    },
                    "tip",
                    "the file has no link of this name to use as the end effector",
                    format!("give one of the links: {}", tree.link_names.join(", ")),
                ));
                None
            }
        },
    };
    if !errors.is_empty() {
        return Err(errors);
    }
    let movable: Vec<bool> = joints.iter().map(|j| j.kind.is_some()).collect();
    let independent: Vec<bool> = (0..movable.len())
        .map(|j| movable[j] && mimics[j].is_none())
        .collect();
    let (chain, branch_points) = tree.chain(&movable, &independent, tip);
    let errors = locks::structure_errors(urdf, &tree, &chain, &branch_points, &mimics);
    if !errors.is_empty() {
        return Err(errors);
    }
    assemble::robot(urdf, &tree, &joints, &links, &chain, tip)
}
