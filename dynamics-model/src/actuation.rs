//! Actuation and friction of a joint (Modern Robotics §8.9): a motor with rotor inertia
//! `I_rotor` drives the joint through a gear of ratio G, and the joint has viscous and Coulomb
//! friction. The parameters live on [`crate::Joint`] ([`crate::Joint::rotor_inertia`],
//! [`crate::Joint::gear_ratio`], [`crate::Joint::damping`], [`crate::Joint::friction`]):
//!
//! - the rotor's reflected inertia, the armature `G² I_rotor` ([`crate::Joint::armature`]), is
//!   added to the joint's diagonal entry of the mass matrix, so it is part of M, of the
//!   inverse and forward dynamics and of the kinetic energy;
//! - friction `τ_friction,i = b_i q̇_i + μ_i sgn(q̇_i)` is a separate term the caller adds:
//!   `τ = ID(q, q̇, q̈) + τ_friction(q̇)`.

/// `G* = √(I_link / I_rotor)`, the gear ratio that gives the largest joint acceleration for a
/// given motor torque (Modern Robotics Exercise 8.9).
///
/// A motor torque `τ_m` becomes the joint torque `G τ_m`, and the joint sees the link inertia
/// plus the reflected rotor inertia `G² I_rotor`, so
/// ```text
/// θ̈(G) = G τ_m / (I_link + G² I_rotor)
/// dθ̈/dG = τ_m (I_link − G² I_rotor) / (I_link + G² I_rotor)²  = 0   ⇔   G² = I_link / I_rotor
/// ```
/// and the second derivative there, `−τ_m √I_rotor / (2 I_link^{3/2})`, is negative: a maximum,
/// `θ̈(G*) = τ_m / (2 √(I_link I_rotor))` (the reflected rotor inertia then equals the link's).
/// Since `θ̈(G) = θ̈(G*²/G)`, a gear k times too small is as bad as one k times too large.
///
/// `link_inertia` is the link's inertia about the joint axis (kg·m²), `rotor_inertia` the
/// rotor's about its own axis; both should be positive (`I_rotor = 0` gives `+∞`: without a
/// rotor, more gearing always helps).
///
/// ```
/// let g = dynamics_model::actuation::optimal_gear_ratio(0.5, 0.0002);
/// assert!((g - 50.0).abs() < 1e-12);
/// ```
pub fn optimal_gear_ratio(link_inertia: f64, rotor_inertia: f64) -> f64 {
    (link_inertia / rotor_inertia).sqrt()
}
