//! The per-configuration quantities shared by the recursive algorithms (Modern Robotics §8.3.2),
//! on a kinematic tree.

use crate::base::{base_pose, joint_values};
use crate::coupling::Coupled;
use dynamics_model::lie::{adjoint, exp6, trans_inv};
use dynamics_model::Robot;
use nalgebra::{Matrix4, Matrix6, Vector6};

/// The screw axes in the link frames and the parent-to-link transforms at one configuration.
///
/// Indices are 0-based: for `i = 0..n`, `a[i]` is the book's `A_{i+1}`, and `t_i_parent[i]` is
/// `T_{i+1,λ(i+1)}` (the pose of link i's parent frame seen from {i+1}; the parent is the base
/// frame when `parent[i]` is `None`); entry n is the end-effector frame's constant transform.
/// On a serial chain `λ(i) = i − 1` and these are the book's `T_{i,i−1}`:
///
/// ```text
/// A_i         = [Ad_{M_{0i}⁻¹}] S_i                    (joint i's screw axis in {i})
/// T_{i,λ(i)}  = e^{−[A_i]θ_i} M_{λ(i),i}⁻¹              i = 1..n
/// T_{n+1,λ}   = M_{λ,n+1}⁻¹                              (the end effector)
/// ```
///
/// On a floating base, [`TreeFrames::base_pose`] is `T_{0b}` from `q`'s first seven entries and
/// the base frame plays the role of {0} in the recursions.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeFrames {
    /// `λ(i)`, i = 1..n+1 (0-based; the last entry is the end effector's link; `None` = the base).
    pub parent: Vec<Option<usize>>,
    /// `A_i`, i = 1..n (0-based).
    pub a: Vec<Vector6<f64>>,
    /// `T_{i,λ(i)}`, i = 1..n+1 (0-based).
    pub t_i_parent: Vec<Matrix4<f64>>,
    /// `[Ad_{T_{i,λ(i)}}]`, i = 1..n+1 (0-based).
    pub ad_t_i_parent: Vec<Matrix6<f64>>,
    /// `T_{0b}`, the base's pose in {0}: the identity for a fixed base.
    pub base_pose: Matrix4<f64>,
}

impl TreeFrames {
    /// The quantities at `q` (θ on a fixed base, `(p, quat, θ)` on a floating one).
    ///
    /// # Panics
    /// If `q.len()` is not `robot.nq()`.
    pub fn new(robot: &Robot, q: &[f64]) -> Self {
        if let Some(c) = Coupled::of(robot) {
            crate::check::configuration(robot, "q", q);
            return Self::new(&c.physical, &c.q(q));
        }
        let base_pose = base_pose(robot, q);
        let theta = joint_values(robot, q);
        let n = robot.dof();
        let m_list = robot.m_list();
        let a = robot.body_screws();
        let mut parent = robot.parents();
        parent.push(robot.end_effector.parent);
        let mut t_i_parent = Vec::with_capacity(n + 1);
        for i in 0..n {
            t_i_parent.push(exp6(&a[i], -theta[i]) * trans_inv(&m_list[i]));
        }
        t_i_parent.push(trans_inv(&m_list[n]));
        let ad_t_i_parent = t_i_parent.iter().map(adjoint).collect();
        Self {
            parent,
            a,
            t_i_parent,
            ad_t_i_parent,
            base_pose,
        }
    }

    /// Where `λ(i)` sits in arrays whose entry 0 is the base and entry k+1 is link k: 0 for the
    /// base, `λ(i) + 1` otherwise (`i` 0-based, n for the end effector).
    pub fn parent_slot(&self, i: usize) -> usize {
        self.parent[i].map_or(0, |p| p + 1)
    }
}
