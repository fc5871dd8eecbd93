//! Seeded random kinematic trees (from [`dynamics_model::random::random_tree`]) with random
//! states, fixed and floating, for identity tests.

use super::random_chain::Rng;
use dynamics_model::random::{random_mimics, random_tree, TreeSpec};
use dynamics_model::{JointKind, Robot};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector6};

/// A random tree with a random state.
pub struct TreeSample {
    /// The robot (fixed or floating base).
    pub robot: Robot,
    /// q (nq): on a floating base `(p, quat, θ)` with a quaternion of norm in [0.5, 2), not
    /// unit on purpose (the reference normalises it).
    pub q: Vec<f64>,
    /// ν (nv).
    pub qd: Vec<f64>,
    /// ν̇ (nv).
    pub qdd: Vec<f64>,
    /// `F_tip` in {n+1}.
    pub f_tip: Vector6<f64>,
}

/// A random q for `robot`: base position in [−1, 1)³ and a random quaternion of norm in
/// [0.5, 2) when floating; θ ∈ [−π, π) (revolute) or [−0.5, 0.5) m (prismatic) for each
/// independent joint (mimic joints have no entry).
pub fn random_configuration(rng: &mut Rng, robot: &Robot) -> Vec<f64> {
    let mut q = Vec::with_capacity(robot.nq());
    if robot.base.floating {
        q.extend(rng.vector(3, -1.0, 1.0));
        let quat = loop {
            let v = rng.vector(4, -1.0, 1.0);
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm > 0.1 && norm <= 1.0 {
                break v.iter().map(|x| x / norm).collect::<Vec<_>>();
            }
        };
        let scale = rng.uniform(0.5, 2.0);
        q.extend(quat.iter().map(|x| x * scale));
    }
    for j in robot.joints.iter().filter(|j| j.is_independent()) {
        q.push(match j.kind {
            JointKind::Revolute => rng.uniform(-std::f64::consts::PI, std::f64::consts::PI),
            JointKind::Prismatic => rng.uniform(-0.5, 0.5),
        });
    }
    q
}

/// `count` random trees from `seed`: tree k has 1 + k mod `max_dof` bodies, a floating base
/// unless k is a multiple of 3, about 30 % prismatic joints and 40 % branching.
pub fn trees(seed: u64, count: usize, max_dof: usize) -> Vec<TreeSample> {
    trees_coupled(seed, count, max_dof, 0.0)
}

/// [`trees`] with each joint made a mimic joint with probability `mimic`
/// ([`dynamics_model::random::random_mimics`]; none for 0, the trees of [`trees`]).
pub fn trees_coupled(seed: u64, count: usize, max_dof: usize, mimic: f64) -> Vec<TreeSample> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|k| {
            let spec = TreeSpec {
                dof: 1 + k % max_dof,
                prismatic: 0.3,
                branching: 0.4,
                floating: k % 3 != 0,
            };
            let tree_seed = seed.wrapping_add(k as u64);
            let mut robot = random_tree(tree_seed, spec);
            if mimic > 0.0 {
                robot = random_mimics(robot, tree_seed, mimic);
            }
            let q = random_configuration(&mut rng, &robot);
            let nv = robot.nv();
            TreeSample {
                q,
                qd: rng.vector(nv, -2.0, 2.0),
                qdd: rng.vector(nv, -2.0, 2.0),
                f_tip: Vector6::from_column_slice(&rng.vector(6, -5.0, 5.0)),
                robot,
            }
        })
        .collect()
}

/// The quaternion `(x, y, z, w)` of a rotation matrix.
pub fn quaternion_of(r: &Matrix3<f64>) -> [f64; 4] {
    let u = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    [u.i, u.j, u.k, u.w]
}

/// Whether dof i lies on the path from the base to joint j or j on that to i (0-based
/// joints).
pub fn related(robot: &Robot, i: usize, j: usize) -> bool {
    robot.path_to(j).contains(&i) || robot.path_to(i).contains(&j)
}
