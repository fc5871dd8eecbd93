//! Seeded random serial chains with physically valid inertias, for property tests and
//! fuzzing: arbitrary unit axes through arbitrary points (revolute) or arbitrary unit
//! directions (prismatic), random rigid home frames, and inertias with random principal
//! moments that meet the triangle inequality, rotated and offset so that `G_i` is given in
//! a frame away from the centre of mass.
//!
//! The generator is a SplitMix64 stream: the same seed gives the same robot on every host.

use crate::inertia::SpatialInertia;
use crate::lie::{exp6, rotation, rp_to_trans, twist};
use crate::robot::{Base, EndEffector, Joint, JointKind, JointLimits, Link, Robot};
use nalgebra::{Matrix3, Matrix4, Vector3};

/// A small deterministic random number generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in [lo, hi] (inclusive).
    pub fn range(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// A uniformly distributed unit vector.
    pub fn unit_vector(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    /// A random rotation (exponential of a random axis-angle).
    pub fn rotation(&mut self) -> Matrix3<f64> {
        let axis = self.unit_vector();
        let angle = self.uniform(-std::f64::consts::PI, std::f64::consts::PI);
        rotation(&exp6(&twist(&axis, &Vector3::zeros()), angle))
    }

    /// A vector with entries uniform in [−r, r).
    pub fn vector(&mut self, r: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(-r, r),
            self.uniform(-r, r),
            self.uniform(-r, r),
        )
    }
}

/// How random chains are drawn.
#[derive(Clone, Copy, Debug)]
pub struct ChainSpec {
    /// Number of joints n.
    pub dof: usize,
    /// Probability that a joint is prismatic.
    pub prismatic: f64,
}

/// A random valid inertia: mass in [0.3, 6) kg, principal moments meeting the triangle
/// inequality, rotated, expressed in a frame offset from the centre of mass.
pub fn random_inertia(rng: &mut Rng) -> SpatialInertia {
    let m = rng.uniform(0.3, 6.0);
    // Principal moments of a box with random edges: always physically valid.
    let (w, l, h) = (
        rng.uniform(0.02, 0.5),
        rng.uniform(0.02, 0.5),
        rng.uniform(0.02, 0.5),
    );
    let d = crate::inertia::primitive::cuboid(m, w, l, h);
    let r = rng.rotation();
    let i_com = r * Matrix3::from_diagonal(&d) * r.transpose();
    let t_ac = rp_to_trans(&rng.rotation(), &rng.vector(0.3));
    SpatialInertia::from_com_frame(m, i_com, &t_ac)
}

/// Body i of a random robot, hanging from `parent` whose home pose in {0} is `parent_pose`:
/// joint i (an axis through a point near the link's origin, in {0}; prismatic with
/// probability `prismatic`; limits ±3), link i with its home and inertia, and the link's
/// home pose in {0}. The one draw order of [`random_chain`] and [`random_tree`].
fn random_body(
    rng: &mut Rng,
    i: usize,
    parent: Option<usize>,
    parent_pose: &Matrix4<f64>,
    prismatic: f64,
) -> (Joint, Link, Matrix4<f64>) {
    let home = rp_to_trans(&rng.rotation(), &rng.vector(0.4));
    let t0 = parent_pose * home;
    let kind = if rng.unit() < prismatic {
        JointKind::Prismatic
    } else {
        JointKind::Revolute
    };
    let dir = rng.unit_vector();
    let point = t0.fixed_view::<3, 1>(0, 3).into_owned() + rng.vector(0.1);
    let screw = match kind {
        JointKind::Revolute => twist(&dir, &(-dir.cross(&point))),
        JointKind::Prismatic => twist(&Vector3::zeros(), &dir),
    };
    let mut joint = Joint::new(format!("j{}", i + 1), kind, screw);
    joint.limits = Some(JointLimits {
        lower: -3.0,
        upper: 3.0,
        velocity: None,
        effort: None,
    });
    let link = Link {
        name: format!("l{}", i + 1),
        parent,
        home,
        inertia: random_inertia(rng),
    };
    (joint, link, t0)
}

/// A random serial chain (see the module docs), named `random_<seed>`.
pub fn random_chain(seed: u64, spec: ChainSpec) -> Robot {
    let mut rng = Rng::new(seed);
    let mut joints = Vec::with_capacity(spec.dof);
    let mut links = Vec::with_capacity(spec.dof);
    let mut t0 = Matrix4::identity();
    for i in 0..spec.dof {
        let (joint, link, pose) = random_body(&mut rng, i, i.checked_sub(1), &t0, spec.prismatic);
        t0 = pose;
        joints.push(joint);
        links.push(link);
    }
    let tip = rp_to_trans(&rng.rotation(), &rng.vector(0.2));
    let gravity = rng.vector(1.0).normalize() * 9.81;
    Robot {
        name: format!("random_{seed}"),
        source: format!("dynamics_model::random::random_chain({seed})"),
        base: Base::fixed(),
        joints,
        links,
        end_effector: EndEffector {
            name: "tip".into(),
            parent: spec.dof.checked_sub(1),
            home: tip,
        },
        frames: Vec::new(),
        gravity,
        runtime: crate::RuntimeParameters::default(),
        parameters: Default::default(),
    }
}

/// How random trees are drawn.
#[derive(Clone, Copy, Debug)]
pub struct TreeSpec {
    /// Number of joints (bodies) n.
    pub dof: usize,
    /// Probability that a joint is prismatic.
    pub prismatic: f64,
    /// Probability that a body starts a new branch (hangs from a random earlier body or the
    /// base) instead of continuing from the body before it.
    pub branching: f64,
    /// Whether the base floats (its inertia is drawn either way).
    pub floating: bool,
}

/// A random kinematic tree, named `random_tree_<seed>`: bodies in depth-first order, each
/// hanging from the one before it or, with probability `spec.branching`, from a random
/// earlier body or the base; axes, homes and inertias drawn as in [`random_chain`]. The end
/// effector hangs from the last body.
pub fn random_tree(seed: u64, spec: TreeSpec) -> Robot {
    let mut rng = Rng::new(seed ^ 0x7EE5);
    let mut joints = Vec::with_capacity(spec.dof);
    let mut links: Vec<Link> = Vec::with_capacity(spec.dof);
    let mut poses: Vec<Matrix4<f64>> = Vec::with_capacity(spec.dof);
    // The bodies a new body may hang from while keeping depth-first order: the previous
    // body and its ancestors (the open path), or the base.
    let mut open: Vec<usize> = Vec::new();
    for i in 0..spec.dof {
        let parent = if i == 0 || rng.unit() >= spec.branching {
            i.checked_sub(1)
        } else {
            let k = (rng.unit() * (open.len() + 1) as f64) as usize;
            open.get(k).copied()
        };
        // Close the path below the chosen parent.
        match parent {
            Some(p) => {
                while open.last().is_some_and(|&l| l != p) {
                    open.pop();
                }
            }
            None => open.clear(),
        }
        open.push(i);
        let parent_pose = parent.map_or(Matrix4::identity(), |p| poses[p]);
        let (joint, link, pose) = random_body(&mut rng, i, parent, &parent_pose, spec.prismatic);
        poses.push(pose);
        joints.push(joint);
        links.push(link);
    }
    let tip = rp_to_trans(&rng.rotation(), &rng.vector(0.2));
    let gravity = rng.vector(1.0).normalize() * 9.81;
    Robot {
        name: format!("random_tree_{seed}"),
        source: format!("dynamics_model::random::random_tree({seed})"),
        base: Base {
            name: "base".into(),
            inertia: random_inertia(&mut rng),
            floating: spec.floating,
        },
        joints,
        links,
        end_effector: EndEffector {
            name: "tip".into(),
            parent: spec.dof.checked_sub(1),
            home: tip,
        },
        frames: Vec::new(),
        gravity,
        runtime: crate::RuntimeParameters::default(),
        parameters: Default::default(),
    }
}

/// `robot` with some joints coupled as mimic joints ([`crate::mimic`]), drawn from `seed`
/// apart from the robot's own draws: each joint becomes a follower with probability
/// `probability` (at least one joint stays independent), of a leader drawn among the
/// independent joints (before or after it), with a multiplier of magnitude in [0.5, 2) and
/// random sign and an offset in [−0.5, 0.5). The name gets `_mimic`.
pub fn random_mimics(mut robot: Robot, seed: u64, probability: f64) -> Robot {
    let mut rng = Rng::new(seed ^ 0x313C_C0DE);
    let n = robot.joints.len();
    let mut follows: Vec<bool> = (0..n).map(|_| rng.unit() < probability).collect();
    if n > 0 && follows.iter().all(|&f| f) {
        let keep = rng.range(0, n - 1);
        follows[keep] = false;
    }
    let independent: Vec<usize> = (0..n).filter(|&i| !follows[i]).collect();
    for i in (0..n).filter(|&i| follows[i]) {
        let leader = independent[rng.range(0, independent.len() - 1)];
        let magnitude = rng.uniform(0.5, 2.0);
        let multiplier = if rng.unit() < 0.5 {
            -magnitude
        } else {
            magnitude
        };
        robot.joints[i].mimic = Some(crate::mimic::Mimic {
            leader,
            multiplier,
            offset: rng.uniform(-0.5, 0.5),
        });
    }
    robot.name.push_str("_mimic");
    robot
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_mimics_are_valid_and_keep_a_coordinate() {
        let mut coupled = 0;
        for seed in 0..30 {
            let spec = TreeSpec {
                dof: 1 + (seed as usize % 10),
                prismatic: 0.3,
                branching: 0.4,
                floating: seed % 2 == 0,
            };
            let r = random_mimics(random_tree(seed, spec), seed, 0.4);
            assert!(r.validate().is_ok(), "seed {seed}: {:?}", r.validate());
            assert!(r.n_coordinates() >= 1);
            coupled += r.dof() - r.n_coordinates();
        }
        assert!(coupled > 20, "{coupled} followers");
    }

    #[test]
    fn random_trees_are_valid_reproducible_and_branched() {
        let mut branched = 0;
        for seed in 0..50 {
            let spec = TreeSpec {
                dof: 1 + (seed as usize % 20),
                prismatic: 0.3,
                branching: 0.4,
                floating: seed % 2 == 0,
            };
            let r = random_tree(seed, spec);
            assert!(r.validate().is_ok(), "seed {seed}: {:?}", r.validate());
            assert_eq!(r, random_tree(seed, spec));
            branched += usize::from(!r.is_serial());
        }
        assert!(branched > 30, "{branched} of 50 trees branch");
    }

    #[test]
    fn random_chains_are_valid_and_reproducible() {
        for seed in 0..50 {
            let spec = ChainSpec {
                dof: 1 + (seed as usize % 12),
                prismatic: 0.3,
            };
            let r = random_chain(seed, spec);
            assert!(r.validate().is_ok(), "seed {seed}: {:?}", r.validate());
            assert_eq!(r, random_chain(seed, spec));
        }
    }
}
