//! The per-configuration quantities shared by the recursive algorithms (Modern Robotics §8.3.2).

use crate::check;
use dynamics_model::lie::{adjoint, exp6, trans_inv};
use dynamics_model::Robot;
use nalgebra::{Matrix4, Matrix6, Vector6};

/// The screw axes in the link frames and the link-to-link transforms at one configuration θ.
///
/// Indices follow the book's Python library (0-based): for `i = 0..n`, `a[i]` is the book's
/// `A_{i+1}`; for `i = 0..=n`, `t_i_im1[i]` is `T_{i+1,i}` (the pose of {i} seen from {i+1}) and
/// `ad_t_i_im1[i]` is `[Ad_{T_{i+1,i}}]`, with the last entry the constant `T_{n+1,n}` of the
/// end-effector frame:
///
/// ```text
/// A_i       = [Ad_{M_{0i}⁻¹}] S_i                 (joint i's screw axis in {i})
/// T_{i,i−1} = e^{−[A_i]θ_i} M_{i−1,i}⁻¹            i = 1..n
/// T_{n+1,n} = M_{n,n+1}⁻¹
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ChainFrames {
    /// `A_i`, i = 1..n (0-based).
    pub a: Vec<Vector6<f64>>,
    /// `T_{i,i−1}`, i = 1..n+1 (0-based).
    pub t_i_im1: Vec<Matrix4<f64>>,
    /// `[Ad_{T_{i,i−1}}]`, i = 1..n+1 (0-based).
    pub ad_t_i_im1: Vec<Matrix6<f64>>,
}

impl ChainFrames {
    /// The quantities at θ = `q`.
    ///
    /// # Panics
    /// If `q.len()` is not `robot.dof()`.
    pub fn new(robot: &Robot, q: &[f64]) -> Self {
        check::joint_vector(robot, "q", q);
        let n = robot.dof();
        let m_list = robot.m_list();
        let a = robot.body_screws();
        let mut t_i_im1 = Vec::with_capacity(n + 1);
        for i in 0..n {
            t_i_im1.push(exp6(&a[i], -q[i]) * trans_inv(&m_list[i]));
        }
        t_i_im1.push(trans_inv(&m_list[n]));
        let ad_t_i_im1 = t_i_im1.iter().map(adjoint).collect();
        Self {
            a,
            t_i_im1,
            ad_t_i_im1,
        }
    }
}
