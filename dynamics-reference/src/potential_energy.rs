//! Potential energy of the robot in a uniform gravity field (Modern Robotics §8.1).

use crate::base::base_pose;
use crate::link_poses::link_poses;
use dynamics_model::{Robot, SpatialInertia};
use nalgebra::{Matrix4, Vector3, Vector4};

/// `P(q) = −Σ_i m_i gᵀ p_i(q)`, with `p_i = T_{0i}(q) c_i` the centre of mass of link i in {0}
/// (`c_i` = [`dynamics_model::SpatialInertia::com`] of `G_i`, in {i}; {i} need not be at the
/// centre of mass) and `g` the gravity vector in {0}. On a floating base the base body counts
/// too (`T_{0b} c_b`, from [`dynamics_model::Base::inertia`]); a fixed base does not move and
/// is left out. Zero height is the origin of {0}, so `g(q) = ∂P/∂q` ([`crate::gravity_forces`];
/// on a floating base along the base's body twist).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn potential_energy(robot: &Robot, q: &[f64], gravity: &Vector3<f64>) -> f64 {
    let links: f64 = link_poses(robot, q)
        .iter()
        .zip(&robot.links)
        .map(|(t_0i, link)| body_potential(t_0i, &link.inertia, gravity))
        .sum();
    if robot.base.floating {
        links + body_potential(&base_pose(robot, q), &robot.base.inertia, gravity)
    } else {
        links
    }
}

/// `−m gᵀ (T c)` for a body of inertia `inertia` (in its frame) at pose `t`.
fn body_potential(t: &Matrix4<f64>, inertia: &SpatialInertia, gravity: &Vector3<f64>) -> f64 {
    let c = inertia.com();
    let p = (t * Vector4::new(c[0], c[1], c[2], 1.0)).xyz();
    -inertia.mass() * gravity.dot(&p)
}
