//! Mimic joints: coupled coordinates, as URDF's `<mimic>` and Pinocchio 3's mimic joints.
//!
//! A mimic joint (a *follower*) moves with another joint (its *leader*):
//! ```text
//! θ_f = m·θ_L + o,    θ̇_f = m·θ̇_L,    θ̈_f = m·θ̈_L        (m ≠ 0 the multiplier, o the offset)
//! ```
//! The robot keeps every physical joint and link ([`Robot::joints`], [`Robot::dof`]: the
//! bodies still move by their own joints), and [`Joint::mimic`] says which ones follow. The
//! vectors a user sees (q, ν, ν̇, τ) hold the *independent coordinates* only: the joints
//! without `mimic`, in the order of [`Robot::joints`] ([`Robot::coordinate_joints`],
//! [`Robot::n_coordinates`]; [`Robot::nq`] and [`Robot::nv`] count them, plus the floating
//! base's 7 and 6).
//!
//! With `x` the independent joint values, the physical ones are `θ = J x + o` with the
//! constant n×k matrix `J` (row i: `m_i` in the column of joint i's leader, `1` in its own
//! column for an independent joint, [`Robot::couplings`]) and `o` the offsets. Since `J` is
//! constant, `θ̇ = J ẋ` and `θ̈ = J ẍ`, and the dynamics in the independent coordinates are the
//! physical ones projected (the principle of virtual work):
//! ```text
//! M_x = Jᵀ M(θ) J,    c_x = Jᵀ c(θ, J ẋ),    g_x = Jᵀ g(θ),    τ_x = Jᵀ τ(θ, J ẋ, J ẍ)
//! ```
//! `τ_x` is the force at the leader that drives the leader and all its followers; the base
//! rows and columns of a floating base are the identity part of `J`.
//!
//! A leader is always an independent joint: chains (`c` mimics `b`, which mimics `a`) are
//! resolved by the loaders to the root leader, `θ_c = m_c (m_b θ_a + o_b) + o_c`; cycles are
//! refused ([`resolve_chains`]). [`crate::validate`] checks the stored form: the leader is
//! another joint of the robot and independent, `m` finite and non-zero, `o` finite.

use crate::robot::{Joint, Robot};

/// How a joint follows its leader: `θ = multiplier·θ_leader + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mimic {
    /// The leader: index (0-based, in [`Robot::joints`]) of an independent joint.
    pub leader: usize,
    /// m, non-zero (rad/rad, m/m, or m/rad and rad/m between joints of different kinds).
    pub multiplier: f64,
    /// o (rad or m, the follower's unit).
    pub offset: f64,
}

/// How one physical joint's value is made from the independent coordinates:
/// `θ_i = multiplier·x[coordinate] + offset` (an independent joint: its own coordinate,
/// multiplier 1, offset 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coupling {
    /// The index of the coordinate in the joint part of q (and of ν, ν̇, τ).
    pub coordinate: usize,
    /// m.
    pub multiplier: f64,
    /// o.
    pub offset: f64,
}

impl Joint {
    /// Whether the joint is an independent coordinate (it mimics no other joint).
    pub fn is_independent(&self) -> bool {
        self.mimic.is_none()
    }
}

impl Robot {
    /// The number of independent joint coordinates: the joints that mimic no other
    /// ([`Robot::dof`] when there is no mimic joint).
    pub fn n_coordinates(&self) -> usize {
        self.joints.iter().filter(|j| j.is_independent()).count()
    }

    /// Whether some joint mimics another.
    pub fn has_mimic(&self) -> bool {
        self.joints.iter().any(|j| j.mimic.is_some())
    }

    /// The independent joints (indices into [`Robot::joints`]), in the order of every vector.
    pub fn coordinate_joints(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&i| self.joints[i].is_independent())
            .collect()
    }

    /// For every physical joint, how it is made from the independent coordinates (the rows of
    /// `J` and `o` of the [module docs](crate::mimic)). Meaningful on a robot that passes
    /// [`Robot::validate`]; a leader that is not an independent joint maps to coordinate 0.
    pub fn couplings(&self) -> Vec<Coupling> {
        let mut coordinate_of = vec![None; self.joints.len()];
        for (k, i) in self.coordinate_joints().into_iter().enumerate() {
            coordinate_of[i] = Some(k);
        }
        self.joints
            .iter()
            .enumerate()
            .map(|(i, j)| match &j.mimic {
                None => Coupling {
                    coordinate: coordinate_of[i].unwrap_or(0),
                    multiplier: 1.0,
                    offset: 0.0,
                },
                Some(m) => Coupling {
                    coordinate: coordinate_of.get(m.leader).copied().flatten().unwrap_or(0),
                    multiplier: m.multiplier,
                    offset: m.offset,
                },
            })
            .collect()
    }
}

/// A `<mimic>` as a file writes it: the index of the joint followed (which may follow another
/// in turn), the multiplier and the offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Written {
    /// The joint followed, in the file's own joint indices.
    pub leader: usize,
    /// m.
    pub multiplier: f64,
    /// o.
    pub offset: f64,
}

/// Every follower of `written` (indexed like it) resolved to its root leader, the first joint
/// up the chain that follows no other: `θ_f = m_k(⋯(m_1 θ_L + o_1)⋯) + o_k`, so
/// `m = m_k⋯m_1` and `o = m_k(⋯) + o_k`. `Err` holds the joints of a cycle, starting at the
/// follower (`a → b → a` for `[a, b]`); the leader index of the result is in `written`'s
/// indices.
pub fn resolve_chains(written: &[Option<Written>]) -> Vec<Option<Result<Mimic, Vec<usize>>>> {
    (0..written.len())
        .map(|f| {
            let first = written[f]?;
            let mut path = vec![f];
            let (mut multiplier, mut offset) = (1.0, 0.0);
            let mut step = first;
            loop {
                // θ_f = multiplier·θ_cur + offset, θ_cur = m·θ_leader + o.
                offset += multiplier * step.offset;
                multiplier *= step.multiplier;
                if path.contains(&step.leader) {
                    let start = path.iter().position(|&j| j == step.leader).unwrap_or(0);
                    return Some(Err(path[start..].to_vec()));
                }
                path.push(step.leader);
                match written.get(step.leader).copied().flatten() {
                    Some(next) => step = next,
                    None => {
                        return Some(Ok(Mimic {
                            leader: step.leader,
                            multiplier,
                            offset,
                        }))
                    }
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(leader: usize, multiplier: f64, offset: f64) -> Option<Written> {
        Some(Written {
            leader,
            multiplier,
            offset,
        })
    }

    #[test]
    fn chains_compose_to_the_root_leader() {
        // 2 follows 1 (×2 + 0.1), 1 follows 0 (×−3 + 0.5): θ_2 = 2(−3θ_0 + 0.5) + 0.1.
        let r = resolve_chains(&[None, w(0, -3.0, 0.5), w(1, 2.0, 0.1)]);
        assert_eq!(r[0], None);
        let m = |x: &Option<Result<Mimic, Vec<usize>>>| {
            x.clone().expect("a follower").expect("no cycle")
        };
        assert_eq!(
            (m(&r[1]).leader, m(&r[1]).multiplier, m(&r[1]).offset),
            (0, -3.0, 0.5)
        );
        let m2 = m(&r[2]);
        assert_eq!((m2.leader, m2.multiplier), (0, -6.0));
        assert!((m2.offset - 1.1).abs() < 1e-15);
    }

    #[test]
    fn cycles_are_reported() {
        let r = resolve_chains(&[
            w(1, 1.0, 0.0),
            w(0, 1.0, 0.0),
            w(1, 1.0, 0.0),
            w(3, 1.0, 0.0),
        ]);
        assert_eq!(r[0], Some(Err(vec![0, 1])));
        assert_eq!(r[1], Some(Err(vec![1, 0])));
        assert_eq!(r[2], Some(Err(vec![1, 0])));
        assert_eq!(r[3], Some(Err(vec![3])));
    }
}
