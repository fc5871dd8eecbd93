//! Symbolic expansion of a robot's dynamics over the expression graph, with every constant
//! of the robot folded in.
//!
//! The recursions are the generator's own (they share no code with the reference
//! implementation in `dynamics-reference`, so that comparing the two means something):
//! [`frames`] prepares the chain in joint frames, [`rnea`] expands Newton–Euler, [`crba`] the
//! composite-rigid-body mass matrix and [`ldlt`] the forward-dynamics solve.
//!
//! The leaves of the graph are the inputs of the generated functions: `q`, `q̇`, `q̈`, `τ`
//! (groups [`Q`], [`QD`], [`QDD`], [`TAU`]), and `sin q_i`, `cos q_i` of revolute joints.

pub mod crba;
pub mod frames;
pub mod ldlt;
pub mod rnea;
pub mod rnea_classical;
pub mod spatial;

use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::{JointKind, Robot};
use rnea::LinkForce;
use spatial::JointMotion;

/// Input group of the joint positions q.
pub const Q: u8 = 0;
/// Input group of the joint velocities q̇.
pub const QD: u8 = 1;
/// Input group of the joint accelerations q̈.
pub const QDD: u8 = 2;
/// Input group of the joint forces τ.
pub const TAU: u8 = 3;

/// The leaf for input `group` at joint `index`.
pub fn input(group: u8, index: usize) -> Input {
    Input {
        group,
        index: index as u16,
    }
}

/// The expanded dynamics of one robot: a graph and the outputs of each function.
#[derive(Clone, Debug)]
pub struct Dynamics {
    /// The shared expression graph.
    pub graph: ExprGraph,
    /// n, the number of joints.
    pub dof: usize,
    /// `M(q)`, n×n row-major.
    pub mass_matrix: Vec<ExprId>,
    /// `c(q, q̇)`: Coriolis and centrifugal terms.
    pub coriolis: Vec<ExprId>,
    /// `g(q)`: gravity terms.
    pub gravity: Vec<ExprId>,
    /// `τ = M q̈ + c + g`.
    pub inverse_dynamics: Vec<ExprId>,
    /// `q̈ = M⁻¹(τ − c − g)`.
    pub forward_dynamics: Vec<ExprId>,
}

/// Expands the five functions of `robot` (gravity as in `robot.gravity`).
pub fn expand(robot: &Robot) -> Dynamics {
    let frames = frames::joint_frames(robot);
    let n = robot.dof();
    let mut g = ExprGraph::new();
    let q: Vec<ExprId> = (0..n).map(|i| g.input(input(Q, i))).collect();
    let qd: Vec<ExprId> = (0..n).map(|i| g.input(input(QD, i))).collect();
    let qdd: Vec<ExprId> = (0..n).map(|i| g.input(input(QDD, i))).collect();
    let tau: Vec<ExprId> = (0..n).map(|i| g.input(input(TAU, i))).collect();
    let zero = g.zero();
    let zeros = vec![zero; n];
    let motions: Vec<JointMotion<'_>> = frames
        .joints
        .iter()
        .enumerate()
        .map(|(i, f)| {
            // The joint variable with its home offset: θ_i + θ₀ or d_i + q_i.
            let offset = g.constant(f.offset);
            let angle = g.add(q[i], offset);
            let (sin, cos) = match f.kind {
                JointKind::Revolute => (g.sin(angle), g.cos(angle)),
                JointKind::Prismatic => (zero, zero),
            };
            JointMotion {
                frame: f,
                sin,
                cos,
                q: angle,
            }
        })
        .collect();
    let no_gravity = [0.0; 3];
    let mass_matrix = crba::crba(&mut g, &motions);
    let best_rnea = |g: &mut ExprGraph, qd: &[ExprId], qdd: &[ExprId], gravity: [f64; 3]| {
        let a = rnea::rnea(g, &motions, qd, qdd, gravity, LinkForce::Spatial);
        let b = rnea::rnea(g, &motions, qd, qdd, gravity, LinkForce::Classical);
        let c = rnea_classical::rnea_classical(g, &motions, qd, qdd, gravity);
        // The cheapest of the equal forms (ties keep the earlier one).
        let mut best = a;
        for candidate in [b, c] {
            if g.op_counts(&candidate).total() < g.op_counts(&best).total() {
                best = candidate;
            }
        }
        best
    };
    let coriolis = best_rnea(&mut g, &qd, &zeros, no_gravity);
    let gravity = best_rnea(&mut g, &zeros, &zeros, frames.gravity);
    let inverse_dynamics = best_rnea(&mut g, &qd, &qdd, frames.gravity);
    let bias = best_rnea(&mut g, &qd, &zeros, frames.gravity);
    let rhs: Vec<ExprId> = (0..n).map(|i| g.sub(tau[i], bias[i])).collect();
    let forward_dynamics = ldlt::ldlt_solve(&mut g, &mass_matrix, &rhs);
    Dynamics {
        graph: g,
        dof: n,
        mass_matrix,
        coriolis,
        gravity,
        inverse_dynamics,
        forward_dynamics,
    }
}

#[cfg(test)]
mod tests;
