//! The kinematic tree of a URDF file: links joined by joints, its root, and the serial chain
//! of movable joints in it.
//!
//! Every link but the root has exactly one parent joint; the root has none. The chain is the
//! path from the root to the last movable joint. Side branches that hold only fixed joints
//! (tool flanges, hands, sensors) are welded to the body they hang from; two or more
//! branches that hold movable joints make a tree, which is not supported yet: [`Tree::chain`]
//! finds every branch point on the way to the tip, so that one error can name them all.

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
    /// For each link: its child joints, in file order.
    pub child_joints: Vec<Vec<usize>>,
    /// The root link.
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

    /// The links reachable from the root, parents before children, children in file order.
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

    /// The movable joints of the subtree below joint `j` (itself included), depth first.
    fn movable_below(&self, j: usize, movable: &[bool]) -> Vec<usize> {
        let mut out = Vec::new();
        let mut stack = vec![j];
        while let Some(j) = stack.pop() {
            if movable[j] {
                out.push(j);
            }
            for &c in self.child_joints[self.ends[j].1].iter().rev() {
                stack.push(c);
            }
        }
        out
    }

    /// The serial chain through the tree and the branch points on it.
    ///
    /// Walking from the root, at every link with two or more child branches holding movable
    /// joints (`movable[j]` per joint) one branch is kept: the one holding `keep_link`, if
    /// given, else the one with the most `independent` joints (the first on a tie). The
    /// chain is the movable joints of the kept branches, root to tip; it is the robot's chain
    /// when there are no branch points, and what is left once the joints of the other
    /// branches are locked.
    pub fn chain(
        &self,
        movable: &[bool],
        independent: &[bool],
        keep_link: Option<usize>,
    ) -> (Vec<usize>, Vec<BranchPoint>) {
        let mut chain = Vec::new();
        let mut points = Vec::new();
        let mut link = self.root;
        loop {
            let branches: Vec<(usize, Vec<usize>)> = self.child_joints[link]
                .iter()
                .map(|&j| (j, self.movable_below(j, movable)))
                .filter(|(_, m)| !m.is_empty())
                .collect();
            let keep = match branches.len() {
                0 => return (chain, points),
                1 => 0,
                _ => self.branch_to_keep(link, &branches, independent, keep_link),
            };
            let j = branches[keep].0;
            if movable[j] {
                chain.push(j);
            }
            if branches.len() > 1 {
                points.push(BranchPoint {
                    link,
                    branches,
                    keep,
                });
            }
            link = self.ends[j].1;
        }
    }

    /// The branch holding `keep_link`, else the one with the most independent joints.
    fn branch_to_keep(
        &self,
        link: usize,
        branches: &[(usize, Vec<usize>)],
        independent: &[bool],
        keep_link: Option<usize>,
    ) -> usize {
        let in_branch = |first: usize, l: usize| -> bool {
            // Walk up from l to `link`; the branch is the child joint we arrive through.
            let mut l = l;
            while let Some(j) = self.parent_joint[l] {
                let parent = self.ends[j].0;
                if parent == link {
                    return j == first;
                }
                l = parent;
            }
            false
        };
        keep_link
            .and_then(|t| branches.iter().position(|(j, _)| in_branch(*j, t)))
            .unwrap_or_else(|| {
                let count = |m: &Vec<usize>| m.iter().filter(|&&k| independent[k]).count();
                let most = branches.iter().map(|(_, m)| count(m)).max().unwrap_or(0);
                branches
                    .iter()
                    .position(|(_, m)| count(m) == most)
                    .unwrap_or(0)
            })
    }
}

/// A link where the tree branches into several branches with movable joints.
#[derive(Debug)]
pub struct BranchPoint {
    /// The link.
    pub link: usize,
    /// Each branch: its first joint and its movable joints, depth first.
    pub branches: Vec<(usize, Vec<usize>)>,
    /// The index in `branches` of the branch the chain goes on through.
    pub keep: usize,
}
