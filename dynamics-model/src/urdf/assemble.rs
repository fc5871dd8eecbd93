//! The serial chain of a checked URDF tree, in Modern Robotics form.
//!
//! Walking the tree from the root, every link gets a body (0 = the fixed base, i = the body
//! moved by movable joint i) and its pose `T_{b,l}` in that body's frame {i} (= the child
//! link frame of joint i):
//!
//! - through a fixed joint with transform `T_j`: same body, `T_{b,c} = T_{b,p} T_j`;
//! - through movable joint i: body i, `T_{i,c} = 1`, and `M_{i−1,i} = T_{i−1,p} T_j`.
//!
//! Then `G_i = Σ_{links l of body i} [Ad_{(T_{i,l} T_{l,c})⁻¹}]ᵀ G_c [Ad_{(T_{i,l} T_{l,c})⁻¹}]`
//! with `T_{l,c}` the `<inertial><origin>` and `G_c = [[I, 0], [0, m·1₃]]`;
//! `M_{0i} = M_{01} ⋯ M_{i−1,i}`; `S_i = [Ad_{M_{0i}}] (a_i, 0)` (revolute) or
//! `(0, R_{0i} a_i)` (prismatic) with `a_i` the unit axis in frame {i}; the end effector's
//! `M_{n,n+1} = T_{n,tip}`.

use super::convert::{JointModel, LinkModel};
use super::tree::Tree;
use crate::error::{Invalid, Subject};
use crate::inertia::SpatialInertia;
use crate::lie::{adjoint, rotation, twist};
use crate::robot::{Base, EndEffector, Joint, JointKind, Link, Robot, DEFAULT_GRAVITY};
use nalgebra::{Matrix4, Vector3};

/// Builds the robot from the checked parts. `chain` is the list of movable joints, root to
/// tip ([`Tree::chain`]); `tip` the end-effector link, if not the last joint's child.
pub fn robot(
    urdf: &urdf_rs::Robot,
    tree: &Tree,
    joints: &[JointModel],
    links: &[LinkModel],
    chain: &[usize],
    tip: Option<usize>,
) -> Result<Robot, Vec<Invalid>> {
    let n = chain.len();
    let Some(&last) = chain.last() else {
        return Err(vec![Invalid::new(
            Subject::Robot,
            "joint",
            "the robot has no movable joint (revolute, continuous or prismatic)",
            "a robot to generate dynamics for needs at least one movable joint; check the joint types and `--lock`",
        )]);
    };
    let mut body_of_joint = vec![0usize; joints.len()];
    for (i, &j) in chain.iter().enumerate() {
        body_of_joint[j] = i + 1;
    }
    // body[l], pose[l] = T_{b,l}; home[i] = M_{i,i+1} (0-based i).
    let n_links = tree.link_names.len();
    let mut body = vec![0usize; n_links];
    let mut pose = vec![Matrix4::identity(); n_links];
    let mut home = vec![Matrix4::identity(); n];
    for l in tree.depth_first() {
        let Some(j) = tree.parent_joint[l] else {
            continue;
        };
        let p = tree.ends[j].0;
        let through = pose[p] * joints[j].transform;
        if joints[j].kind.is_some() {
            let i = body_of_joint[j];
            home[i - 1] = through;
            body[l] = i;
            pose[l] = Matrix4::identity();
        } else {
            body[l] = body[p];
            pose[l] = through;
        }
    }
    let mut inertia = vec![SpatialInertia::zero(); n];
    let mut errors = Vec::new();
    for l in 0..n_links {
        let b = body[l];
        if b == 0 || (links[l].mass == 0.0 && links[l].inertia.amax() == 0.0) {
            continue; // the fixed base never moves; massless links add nothing
        }
        // Each URDF link of a moving body must be a physical rigid body on its own, so that
        // an error names the link as the file has it (merged bodies would hide it).
        errors.extend(crate::validate::check_mass_and_inertia(
            crate::error::Subject::Link {
                index: None,
                name: tree.link_names[l].clone(),
            },
            "inertial.inertia",
            links[l].mass,
            &links[l].inertia,
        ));
        let t_bc = pose[l] * links[l].com_frame;
        inertia[b - 1] =
            inertia[b - 1] + SpatialInertia::from_com_frame(links[l].mass, links[l].inertia, &t_bc);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let tip_link = tip.unwrap_or(tree.ends[last].1);
    if body[tip_link] != n {
        let b = body[tip_link];
        let moved_by = match b {
            0 => "it is on the fixed base, which no joint moves".to_string(),
            b => format!("it is moved by joint `{}`", urdf.joints[chain[b - 1]].name),
        };
        // The movable joints beyond the tip: locking them makes the tip the chain's end.
        // Body b is moved by chain[b − 1]; chain[b..] lie between the tip and the chain's end.
        let beyond: Vec<String> = chain
            .get(b..)
            .unwrap_or(&[])
            .iter()
            .map(|&j| format!("{}=VALUE", urdf.joints[j].name))
            .collect();
        let fix = if b == 0 {
            "choose a tip link attached by fixed joints to the last movable joint's child link"
                .to_string()
        } else {
            format!(
                "choose a tip link attached by fixed joints to link `{}`, or lock the movable joints after the tip (CLI `--lock`, Builder `.lock`, derive `lock(..)`): {}",
                tree.link_names[tree.ends[last].1],
                beyond.join(", ")
            )
        };
        return Err(vec![Invalid::new(
            Subject::EndEffector,
            "tip",
            format!(
                "link `{}` is not rigidly attached to link `{}`, the child of the last movable joint `{}`: {moved_by}",
                tree.link_names[tip_link],
                tree.link_names[tree.ends[last].1],
                urdf.joints[last].name
            ),
            fix,
        )]);
    }
    let mut m0i = Matrix4::identity();
    let mut out_joints = Vec::with_capacity(n);
    let mut out_links = Vec::with_capacity(n);
    for (i, &j) in chain.iter().enumerate() {
        m0i *= home[i];
        let jm = &joints[j];
        let kind = jm.kind.unwrap_or(JointKind::Revolute);
        let screw = match kind {
            JointKind::Revolute => adjoint(&m0i) * twist(&jm.axis, &Vector3::zeros()),
            JointKind::Prismatic => twist(&Vector3::zeros(), &(rotation(&m0i) * jm.axis)),
        };
        let mut joint = Joint::new(urdf.joints[j].name.clone(), kind, screw);
        joint.limits = jm.limits;
        joint.damping = jm.damping;
        joint.friction = jm.friction;
        out_joints.push(joint);
        out_links.push(Link {
            name: tree.link_names[tree.ends[j].1].clone(),
            parent: i.checked_sub(1),
            home: home[i],
            inertia: inertia[i],
        });
    }
    Ok(Robot {
        name: if urdf.name.is_empty() {
            "robot".into()
        } else {
            urdf.name.clone()
        },
        source: String::new(),
        base: Base {
            name: tree.link_names[tree.root].clone(),
            ..Base::fixed()
        },
        joints: out_joints,
        links: out_links,
        end_effector: EndEffector {
            name: tree.link_names[tip_link].clone(),
            parent: n.checked_sub(1),
            home: pose[tip_link],
        },
        gravity: Vector3::from(DEFAULT_GRAVITY),
    })
}
