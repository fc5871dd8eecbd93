//! Joint friction, viscous and Coulomb (Modern Robotics §8.9.2): the force a joint's motor
//! spends on friction, a separate term beside the rigid-body dynamics.

use crate::base::joint_offset;
use crate::check;
use crate::coupling::Coupled;
use dynamics_model::Robot;
use nalgebra::DVector;

/// `τ_friction(ν)`, nv entries: for each joint i, with its viscous coefficient `b_i`
/// ([`dynamics_model::Joint::damping`]) and Coulomb friction `μ_i`
/// ([`dynamics_model::Joint::friction`]),
/// ```text
/// τ_friction,i = b_i θ̇_i + μ_i sgn(θ̇_i)               (smooth = None; sgn(0) = 0)
/// τ_friction,i = b_i θ̇_i + μ_i tanh(θ̇_i / ε)          (smooth = Some(ε), ε > 0)
/// ```
/// the force the joint needs to overcome friction, so the actuation of a motion is
/// `τ = ID(q, ν, ν̇) + τ_friction(ν)` and forward dynamics with friction is
/// `FD(q, ν, τ − τ_friction(ν))`: neither [`crate::inverse_dynamics`] nor
/// [`crate::forward_dynamics`] adds it. The friction dissipates energy:
/// `d(K + P)/dt = νᵀ (τ − τ_friction)` and `νᵀ τ_friction ≥ 0`.
///
/// The smooth form replaces the jump of `sgn` at rest by `tanh` of width ε (rad/s or m/s),
/// for integrators that need a continuous right-hand side.
///
/// On a floating base the base's six entries are 0 (no friction on the free joint). With
/// mimic joints, each physical joint's friction acts at its own rate `θ̇_phys = J ν` and is
/// projected, `τ_friction = Jᵀ τ_friction,phys`: a follower's friction loads its leader.
///
/// # Panics
/// If `qd` does not have `robot.nv()` entries, or `smooth` is `Some(ε)` with ε not positive
/// and finite.
pub fn friction_forces(robot: &Robot, qd: &[f64], smooth: Option<f64>) -> DVector<f64> {
    check::velocity(robot, "qd", qd);
    if let Some(eps) = smooth {
        assert!(
            eps > 0.0 && eps.is_finite(),
            "dynamics-reference: friction_forces: the smoothing width ε = {eps} must be positive and finite; pass None for the exact sgn"
        );
    }
    if let Some(c) = Coupled::of(robot) {
        return c.forces(&friction_forces(&c.physical, &c.v(qd), smooth));
    }
    let off = joint_offset(robot);
    let mut tau = DVector::zeros(robot.nv());
    for (i, joint) in robot.joints.iter().enumerate() {
        let rate = qd[off + i];
        let coulomb = match smooth {
            None => sgn(rate),
            Some(eps) => (rate / eps).tanh(),
        };
        tau[off + i] = joint.damping * rate + joint.friction * coulomb;
    }
    tau
}

/// `sgn(x)`: −1, 0 or 1 (0 at 0, unlike `f64::signum`).
fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
