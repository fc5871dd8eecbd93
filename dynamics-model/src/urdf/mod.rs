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
//! (see [`strip`]): `<visual>`, `<collision>` and their geometry (Pinocchio's `<capsule>`
//! included), materials and textures, `<gazebo>`, `<transmission>`, `<calibration>`,
//! `<safety_controller>`, unknown tags and unknown attributes. Skipped elements must still be
//! well-formed XML.
//!
//! # What is refused, by name
//!
//! Malformed XML (with line and column where they can be found), unknown links, links with
//! two parents and closed loops, several roots, `floating`/`planar` joints, movable joints
//! with `<mimic>`, non-finite numbers, negative masses, physically impossible inertias
//! (checked per URDF link), zero axes, and trees: two or more branches with movable joints
//! (lock the joints of the extra branches with [`LoadOptions::lock`], `--lock JOINT=VALUE`).

mod assemble;
mod convert;
pub mod origin;
mod parse;
pub mod strip;
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
    let locks = convert::locks(urdf, &options.lock)?;
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
    let names: Vec<String> = urdf.joints.iter().map(|j| j.name.clone()).collect();
    let chain = tree.chain(&movable, &names, tip)?;
    assemble::robot(urdf, &tree, &joints, &links, &chain, tip)
}
