//! Seeded random serial chains for identity tests (self-contained: copy this file freely).
//!
//! A chain of n joints (revolute or prismatic) with random unit axes through random points,
//! random rigid home frames `M_{i−1,i}`, and physically valid random inertias: principal moments
//! meeting the triangle inequality strictly, rotated by a random rotation, about a centre of
//! mass offset from the link frame, so `G_i` has all four blocks filled (a non-COM frame).
//! Random numbers come from SplitMix64, so every run sees the same chains.

use dynamics_model::{lie, Robot, SpatialInertia};
use nalgebra::{Matrix3, Matrix4, Matrix6, Quaternion, UnitQuaternion, Vector3, Vector6};

/// SplitMix64: a tiny, good-enough seeded generator (Steele, Lea & Flood 2014).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
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

    /// A vector with entries uniform in [lo, hi).
    pub fn vector(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.uniform(lo, hi)).collect()
    }

    /// A 3-vector with entries uniform in [lo, hi).
    pub fn vector3(&mut self, lo: f64, hi: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        )
    }

    /// A random unit vector (rejection sampling in the unit ball).
    pub fn unit_vector3(&mut self) -> Vector3<f64> {
        loop {
            let v = self.vector3(-1.0, 1.0);
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    /// A random rotation (a normalised random quaternion).
    pub fn rotation(&mut self) -> Matrix3<f64> {
        loop {
            let q = Quaternion::new(
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            );
            let n = q.norm();
            if n > 0.1 && n <= 1.0 {
                return UnitQuaternion::from_quaternion(q)
                    .to_rotation_matrix()
                    .into_inner();
            }
        }
    }

    /// A random rigid transform with translation entries in [−r, r).
    pub fn transform(&mut self, r: f64) -> Matrix4<f64> {
        let rot = self.rotation();
        let p = self.vector3(-r, r);
        lie::rp_to_trans(&rot, &p)
    }
}

/// A random physically valid spatial inertia in a frame {i} that is not at the centre of mass:
/// mass in [0.3, 5), principal moments (a, b, c) with c strictly inside (|a − b|, a + b),
/// rotated by a random rotation, COM at a random offset in [−0.3, 0.3)³.
pub fn random_inertia(rng: &mut Rng) -> Matrix6<f64> {
    let mass = rng.uniform(0.3, 5.0);
    let a = rng.uniform(0.01, 0.5);
    let b = rng.uniform(0.01, 0.5);
    let lo = (a - b).abs();
    let hi = a + b;
    let c = rng.uniform(lo + 0.05 * (hi - lo), hi - 0.05 * (hi - lo));
    let principal = Matrix3::from_diagonal(&Vector3::new(a, b, c));
    let t_ic = lie::rp_to_trans(&rng.rotation(), &rng.vector3(-0.3, 0.3));
    SpatialInertia::from_com_frame(mass, principal, &t_ic).0
}

/// A random chain of `n` joints; about one joint in four is prismatic. Gravity is a random
/// vector of norm 9.81. Built with the validating [`Robot::from_mr_lists`].
pub fn random_robot(rng: &mut Rng, n: usize) -> Robot {
    let m_list: Vec<Matrix4<f64>> = (0..=n).map(|_| rng.transform(0.5)).collect();
    let g_list: Vec<Matrix6<f64>> = (0..n).map(|_| random_inertia(rng)).collect();
    let s_list: Vec<Vector6<f64>> = (0..n)
        .map(|_| {
            let axis = rng.unit_vector3();
            if rng.unit() < 0.25 {
                lie::twist(&Vector3::zeros(), &axis)
            } else {
                let point = rng.vector3(-1.0, 1.0);
                lie::twist(&axis, &(-axis.cross(&point)))
            }
        })
        .collect();
    let gravity = rng.unit_vector3() * 9.81;
    Robot::from_mr_lists(&m_list, &g_list, &s_list, gravity).expect("random chain is valid")
}

/// A random state (θ, θ̇, θ̈) of `robot`: θ ∈ [−π, π) for revolute joints and [−0.5, 0.5) m
/// for prismatic ones, θ̇, θ̈ ∈ [−2, 2).
pub fn random_state(rng: &mut Rng, robot: &Robot) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let q = robot
        .joints
        .iter()
        .map(|j| match j.kind {
            dynamics_model::JointKind::Revolute => {
                rng.uniform(-std::f64::consts::PI, std::f64::consts::PI)
            }
            dynamics_model::JointKind::Prismatic => rng.uniform(-0.5, 0.5),
        })
        .collect();
    let n = robot.dof();
    (q, rng.vector(n, -2.0, 2.0), rng.vector(n, -2.0, 2.0))
}

/// A random tip wrench with entries in [−5, 5).
pub fn random_wrench(rng: &mut Rng) -> Vector6<f64> {
    Vector6::from_column_slice(&rng.vector(6, -5.0, 5.0))
}

/// `count` seeded random chains with 1, 2, …, 12, 1, 2, … joints, each with a random state and
/// tip wrench.
pub fn chains(seed: u64, count: usize) -> Vec<Sample> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|k| {
            let robot = random_robot(&mut rng, 1 + k % 12);
            let (q, qd, qdd) = random_state(&mut rng, &robot);
            let f_tip = random_wrench(&mut rng);
            Sample {
                robot,
                q,
                qd,
                qdd,
                f_tip,
            }
        })
        .collect()
}

/// A random robot with a random state.
pub struct Sample {
    /// The robot.
    pub robot: Robot,
    /// θ.
    pub q: Vec<f64>,
    /// θ̇.
    pub qd: Vec<f64>,
    /// θ̈.
    pub qdd: Vec<f64>,
    /// `F_tip` in {n+1}.
    pub f_tip: Vector6<f64>,
}
