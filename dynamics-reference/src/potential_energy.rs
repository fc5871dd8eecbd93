//! Potential energy of the chain in a uniform gravity field (Modern Robotics §8.1).

use crate::link_poses::link_poses;
use dynamics_model::Robot;
use nalgebra::{Vector3, Vector4};

/// `P(θ) = −Σ_i m_i gᵀ p_i(θ)`, with `p_i = T_{0i}(θ) c_i` the centre of mass of link i in {0}
/// (`c_i` = [`dynamics_model::SpatialInertia::com`] of `G_i`, in {i}; {i} need not be at the
/// centre of mass) and `g` the gravity vector in {0}. Zero height is the origin of {0}, so
/// `g(θ) = ∂P/∂θ` ([`crate::gravity_forces`]).
///
/// # Panics
/// If `q` does not have `robot.dof()` entries.
pub fn potential_energy(robot: &Robot, q: &[f64], gravity: &Vector3<f64>) -> f64 {
    link_poses(robot, q)
        .iter()
        .zip(&robot.links)
        .map(|(t_0i, link)| {
            let c = link.inertia.com();
            let p_i = (t_0i * Vector4::new(c[0], c[1], c[2], 1.0)).xyz();
            -link.inertia.mass() * gravity.dot(&p_i)
        })
        .sum()
}
