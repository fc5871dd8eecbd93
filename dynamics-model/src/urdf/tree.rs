//! The kinematic tree of a URDF file: links joined by joints, its root, the order of its
//! joints, and the floating root joint.
//!
//! - Every link but the root has exactly one parent joint; the root has none. Anything else
//!   (a link with two parents, a closed loop, several roots) is refused here.
//! - The order is urdfdom's, which Pinocchio (and so `model.parents`) follows: depth first
//!   from the root link, the child joints of a link visited in byte-wise order of their
//!   names (urdfdom keeps them in a `std::map`). Fixed joints are traversed like the others;
//!   the caller lists only the movable ones.
//! - A root link without mass (no `<inertial>`, or a zero one) whose only child joint is of
//!   type `floating` (`world` → floating → `base_link`) stands for the world: the robot is
//!   the subtree of that joint's child link, on a floating base ([`Tree::floating_root`]).

use crate::error::{Invalid, Subject};
use std::collections::HashMap;

/// The structure of a URDF robot: who is whose parent.
#[derive(Debug)]
pub struct Tree {
    /// Link names, by link index (file order).
    pub link_names: Vec<String>,
    /// For each joint (file order): (parent link, child link) indices.
    pub ends: Vec<(usize, usize)>,
    /// For each link: its parent joint, `None` for the root.
    pub parent_joint: Vec<Option<usize>>,
    /// For each link: its child joints, in byte-wise order of their names.
    pub child_joints: Vec<Vec<usize>>,
    /// The root link: the file's root, or the child of a floating root joint once
    /// [`Tree::floating_root`] has moved it there.
    pub root: usize,
}

impl Tree {
    /// Builds the tree of `robot`, or every structural error: duplicate names, unknown links,
    /// links with two parents, closed loops, several roots.
    pub fn new(robot: &urdf_rs::Robot) -> Result<Self, Vec<Invalid>> {
        let mut errors = Vec::new();
        let link_subject = |name: &str| Subject::Link {
            index: None,
            name: name.to_string(),
        };
        let joint_subject = |name: &str| Subject::Joint {
            index: None,
            name: name.to_string(),
        };
        let mut index = HashMap::new();
        for (i, l) in robot.links.iter().enumerate() {
            if index.insert(l.name.as_str(), i).is_some() {
                errors.push(Invalid::new(
                    link_subject(&l.name),
                    "name",
                    "two links have this name",
                    "give every link a unique name",
                ));
            }
        }
        let mut joint_names = HashMap::new();
        for j in &robot.joints {
            if joint_names.insert(j.name.as_str(), ()).is_some() {
                errors.push(Invalid::new(
                    joint_subject(&j.name),
                    "name",
                    "two joints have this name",
                    "give every joint a unique name",
                ));
            }
        }
        let n_links = robot.links.len();
        let mut ends = Vec::with_capacity(robot.joints.len());
        let mut parent_joint: Vec<Option<usize>> = vec![None; n_links];
        let mut child_joints = vec![Vec::new(); n_links];
        for (ji, j) in robot.joints.iter().enumerate() {
            let mut find = |field: &str, name: &str| -> Option<usize> {
                let found = index.get(name).copied();
                if found.is_none() {
                    errors.push(Invalid::new(
                        joint_subject(&j.name),
                        field,
                        format!("refers to link `{name}`, which the file does not define"),
                        format!("add <link name=\"{name}\"/> or correct the link name"),
                    ));
                }
                found
            };
            let (p, c) = match (find("parent", &j.parent.link), find("child", &j.child.link)) {
                (Some(p), Some(c)) => (p, c),
                _ => {
                    ends.push((usize::MAX, usize::MAX));
                    continue;
                }
            };
            ends.push((p, c));
            if p == c {
                errors.push(Invalid::new(
                    joint_subject(&j.name),
                    "child",
                    format!("joins link `{}` to itself (a closed loop)", j.child.link),
                    "a joint's parent and child must be different links",
                ));
                continue;
            }
            if let Some(other) = parent_joint[c] {
                errors.push(Invalid::new(
                    link_subject(&j.child.link),
                    "parent",
                    format!(
                        "the link has two parent joints, `{}` and `{}` (a closed loop, or a link used twice)",
                        robot.joints[other].name, j.name
                    ),
                    "URDF describes trees: give every link one parent joint at most (closed chains are not supported)",
                ));
                continue;
            }
            parent_joint[c] = Some(ji);
            child_joints[p].push(ji);
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // urdfdom's order: child joints by name, byte-wise (names are unique here).
        for children in &mut child_joints {
            children.sort_by(|&a, &b| robot.joints[a].name.cmp(&robot.joints[b].name));
        }
        let roots: Vec<usize> = (0..n_links)
            .filter(|&l| parent_joint[l].is_none())
            .collect();
        let root = match roots.as_slice() {
            [r] => *r,
            [] if n_links == 0 => {
                return Err(vec![Invalid::new(
                    Subject::Robot,
                    "link",
                    "the robot has no links",
                    "describe the robot's links and joints",
                )])
            }
            [] => {
                return Err(vec![Invalid::new(
                    Subject::Robot,
                    "joint",
                    "every link has a parent joint, so the joints form a closed loop and there is no root link",
                    "URDF describes trees: remove the joint that closes the loop",
                )])
            }
            many => {
                let names: Vec<String> = many
                    .iter()
                    .map(|&l| format!("`{}`", robot.links[l].name))
                    .collect();
                return Err(vec![Invalid::new(
                    Subject::Robot,
                    "link",
                    format!(
                        "several root links (links without a parent joint): {}",
                        names.join(", ")
                    ),
                    "connect every link but one (the base) to a parent with a joint",
                )]);
            }
        };
        let tree = Self {
            link_names: robot.links.iter().map(|l| l.name.clone()).collect(),
            ends,
            parent_joint,
            child_joints,
            root,
        };
        // With one root and one parent per other link, links the root does not reach lie on
        // closed loops.
        let reached = tree.depth_first();
        if reached.len() < n_links {
            let mut seen = vec![false; n_links];
            for &l in &reached {
                seen[l] = true;
            }
            let loop_links: Vec<String> = (0..n_links)
                .filter(|&l| !seen[l])
                .map(|l| format!("`{}`", tree.link_names[l]))
                .collect();
            return Err(vec![Invalid::new(
                link_subject(&tree.link_names[(0..n_links).find(|&l| !seen[l]).unwrap_or(0)]),
                "parent",
                format!(
                    "the links {} form a closed loop, not connected to the root link `{}`",
                    loop_links.join(", "),
                    tree.link_names[root]
                ),
                "URDF describes trees: remove the joint that closes the loop",
            )]);
        }
        Ok(tree)
    }

    /// The floating root joint, if the file has one: the root link has no mass and no
    /// rotational inertia, and its only child joint has type `floating`. The root then moves
    /// to that joint's child link, whose frame is the base frame (the joint's `<origin>` is
    /// ignored: a free joint can put the base anywhere). Returns the joint's index.
    pub fn floating_root(&mut self, robot: &urdf_rs::Robot) -> Option<usize> {
        let inertial = &robot.links[self.root].inertial;
        let i = &inertial.inertia;
        let massless = inertial.mass.value == 0.0
            && [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
                .iter()
                .all(|&x| x == 0.0);
        match self.child_joints[self.root].as_slice() {
            &[j] if massless && robot.joints[j].joint_type == urdf_rs::JointType::Floating => {
                self.root = self.ends[j].1;
                Some(j)
            }
            _ => None,
        }
    }

    /// The links reachable from the root, parents before children, children in the order of
    /// their joints' names.
    pub fn depth_first(&self) -> Vec<usize> {
        let mut out = Vec::with_capacity(self.link_names.len());
        let mut stack = vec![self.root];
        while let Some(l) = stack.pop() {
            out.push(l);
            for &j in self.child_joints[l].iter().rev() {
                stack.push(self.ends[j].1);
            }
        }
        out
    }

    /// The joints below the root in the same order (each joint is its child link's parent
    /// joint): urdfdom's and Pinocchio's order once the fixed ones are left out.
    pub fn joint_order(&self) -> Vec<usize> {
        self.depth_first()
            .into_iter()
            .filter(|&l| l != self.root)
            .filter_map(|l| self.parent_joint[l])
            .collect()
    }
}
