//! The kinematic tree of a checked URDF file, in Modern Robotics form.
//!
//! The movable joints, in the order of [`Tree::joint_order`] (depth first, children by joint
//! name), are joints 1..n. Walking the links in the same order, every link gets a body
//! (0 = the base, i = the body moved by movable joint i) and its pose `T_{b,l}` in that body's
//! frame (the base's frame {0} is the root link's, body i's frame {i} is the child link frame
//! of joint i):
//!
//! - the root link: body 0, `T_{0,root} = 1`;
//! - through a fixed joint with transform `T_j` from link p to link c: c joins p's body,
//!   `T_{b,c} = T_{b,p} T_j`;
//! - through movable joint i from link p (in body b) to link c: body i, `T_{i,c} = 1`,
//!   `λ(i) = b` ([`crate::Link::parent`], `None` for the base) and `M_{λ(i),i} = T_{b,p} T_j`.
//!
//! Then `G_b = Σ_{links l of body b} [Ad_{(T_{b,l} T_{l,c})⁻¹}]ᵀ G_c [Ad_{(T_{b,l} T_{l,c})⁻¹}]`
//! with `T_{l,c}` the `<inertial><origin>` and `G_c = [[I, 0], [0, m·1₃]]` (for b = 0, the
//! base's inertia); `M_{0i} = M_{0,λ(i)} M_{λ(i),i}`; `S_i = [Ad_{M_{0i}}] (a_i, 0)` (revolute)
//! or `(0, R_{0i} a_i)` (prismatic) with `a_i` the unit axis in frame {i}; the end effector at
//! link t is attached to t's body b with home `T_{b,t}`.

use super::convert::{JointModel, LinkModel};
use super::tree::Tree;
use crate::error::{Invalid, Subject};
use crate::inertia::SpatialInertia;
use crate::lie::{adjoint, rotation, twist};
use crate::robot::{Base, Frame, Joint, JointKind, Link, Robot, DEFAULT_GRAVITY};
use nalgebra::{Matrix4, Vector3};

/// Builds the robot from the checked parts. `movable` lists the movable joints in the
/// robot's order ([`Tree::joint_order`] without the fixed and locked ones); `tip` is the
/// end-effector link, if not the last movable joint's child; `frames` the links of the named
/// frames (`None`: the leaf links of a tree, none on a serial chain); `floating` says whether
/// the base floats (then the inertias of its links are checked as a moving body's).
pub fn robot(
    urdf: &urdf_rs::Robot,
    tree: &Tree,
    joints: &[JointModel],
    links: &[LinkModel],
    movable: &[usize],
    tip: Option<usize>,
    frames: Option<&[usize]>,
    floating: bool,
) -> Result<Robot, Vec<Invalid>> {
    let n = movable.len();
    let Some(&last) = movable.last() else {
        return Err(vec![Invalid::new(
            Subject::Robot,
            "joint",
            "the robot has no movable joint (revolute, continuous or prismatic)",
            "a robot to generate dynamics for needs at least one movable joint; check the joint types and `--lock`",
        )]);
    };
    let mut body_of_joint = vec![0usize; joints.len()];
    for (i, &j) in movable.iter().enumerate() {
        body_of_joint[j] = i + 1;
    }
    // body[l] (None: above a floating root joint, not part of the robot), pose[l] = T_{b,l};
    // parent[i], home[i] = λ(i), M_{λ(i),i} (0-based i, body i + 1).
    let n_links = tree.link_names.len();
    let mut body: Vec<Option<usize>> = vec![None; n_links];
    let mut pose = vec![Matrix4::identity(); n_links];
    let mut parent = vec![None; n];
    let mut home = vec![Matrix4::identity(); n];
    body[tree.root] = Some(0);
    for l in tree.depth_first() {
        let Some(j) = tree.parent_joint[l].filter(|_| l != tree.root) else {
            continue;
        };
        let p = tree.ends[j].0;
        let b = body[p].unwrap_or(0); // depth first: the parent link has its body already
        let through = pose[p] * joints[j].transform;
        if joints[j].kind.is_some() {
            let i = body_of_joint[j];
            parent[i - 1] = b.checked_sub(1);
            home[i - 1] = through;
            body[l] = Some(i);
            pose[l] = Matrix4::identity();
        } else {
            body[l] = Some(b);
            pose[l] = through;
        }
    }
    let mut base_inertia = SpatialInertia::zero();
    let mut inertia = vec![SpatialInertia::zero(); n];
    let mut errors = Vec::new();
    for l in 0..n_links {
        let Some(b) = body[l] else { continue };
        if links[l].mass == 0.0 && links[l].inertia.amax() == 0.0 {
            continue; // massless links add nothing
        }
        // Each URDF link of a moving body must be a physical rigid body on its own, so that
        // an error names the link as the file has it (merged bodies would hide it). A fixed
        // base never moves: its links are not checked. A floating base is checked as the one
        // merged body it is (`validate` of `Base::inertia`): legged robots' files often hang
        // a dummy link of 1e-6 kg with a non-physical inertia on the base (ANYmal, Go1, B1),
        // which Pinocchio loads, and which changes nothing measurable in the merged body.
        if b > 0 {
            errors.extend(crate::validate::check_mass_and_inertia(
                Subject::Link {
                    index: None,
                    name: tree.link_names[l].clone(),
                },
                "inertial.inertia",
                links[l].mass,
                &links[l].inertia,
            ));
        }
        let t_bc = pose[l] * links[l].com_frame;
        let g = SpatialInertia::from_com_frame(links[l].mass, links[l].inertia, &t_bc);
        match b {
            0 => base_inertia = base_inertia + g,
            b => inertia[b - 1] = inertia[b - 1] + g,
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let tip_link = tip.unwrap_or(tree.ends[last].1);
    // A frame on link l: on l's body, at l's pose in it.
    let frame_at = |l: usize, subject: Subject, field: &str| match body[l] {
        Some(b) => Ok(Frame {
            name: tree.link_names[l].clone(),
            parent: b.checked_sub(1),
            home: pose[l],
        }),
        None => Err(vec![Invalid::new(
            subject,
            field,
            format!(
                "link `{}` is the world above the floating root joint, not a link of the robot",
                tree.link_names[l]
            ),
            format!(
                "choose a link of the robot, e.g. the floating base `{}`",
                tree.link_names[tree.root]
            ),
        )]),
    };
    let end_effector = frame_at(tip_link, Subject::EndEffector, "tip")?;
    // Default frames: the leaf links of a tree (depth first).
    let is_tree = parent
        .iter()
        .enumerate()
        .any(|(i, p)| *p != i.checked_sub(1));
    let leaves: Vec<usize> = tree
        .depth_first()
        .into_iter()
        .filter(|&l| body[l].is_some() && tree.child_joints[l].is_empty())
        .collect();
    let frame_links = match frames {
        Some(f) => f,
        None if is_tree => &leaves[..],
        None => &[],
    };
    let frames: Vec<Frame> = frame_links
        .iter()
        .map(|&l| {
            let subject = Subject::Link {
                index: None,
                name: tree.link_names[l].clone(),
            };
            frame_at(l, subject, "frame")
        })
        .collect::<Result<_, _>>()?;
    let mut m0: Vec<Matrix4<f64>> = Vec::with_capacity(n);
    let mut out_joints = Vec::with_capacity(n);
    let mut out_links = Vec::with_capacity(n);
    for (i, &j) in movable.iter().enumerate() {
        let m0i = parent[i].map_or(Matrix4::identity(), |p: usize| m0[p]) * home[i];
        m0.push(m0i);
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
            parent: parent[i],
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
            inertia: base_inertia,
            floating,
        },
        joints: out_joints,
        links: out_links,
        end_effector,
        frames,
        gravity: Vector3::from(DEFAULT_GRAVITY),
        runtime: crate::RuntimeParameters::default(),
        parameters: Default::default(),
    })
}
