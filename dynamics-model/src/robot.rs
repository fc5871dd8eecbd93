//! The robot: an open serial chain in the product-of-exponentials form of Modern Robotics.

use crate::error::ModelError;
use crate::inertia::SpatialInertia;
use crate::lie::{adjoint, trans_inv};
use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};

/// The standard gravity vector used when a description gives none: `(0, 0, −9.81)` m/s² in {0}.
pub const DEFAULT_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// The kind of a movable joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointKind {
    /// Rotation about the screw axis `S = (ω, −ω × q)`, `|ω| = 1`; q in rad.
    Revolute,
    /// Translation along `S = (0, v)`, `|v| = 1`; q in m.
    Prismatic,
}

impl JointKind {
    /// `revolute` or `prismatic`.
    pub fn as_str(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
        }
    }
}

/// Position limits of a joint (rad or m), and optional velocity and effort limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lower position limit.
    pub lower: f64,
    /// Upper position limit.
    pub upper: f64,
    /// Velocity limit (rad/s or m/s), if given.
    pub velocity: Option<f64>,
    /// Effort limit (N·m or N), if given.
    pub effort: Option<f64>,
}

/// A movable joint i (1-based in the book, 0-based in the vectors here).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// The joint's name (the URDF joint name, or the name in the TOML file).
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// `S_i`: the screw axis in the space frame {0} at the home configuration.
    pub screw: Vector6<f64>,
    /// Position limits; `None` for an unlimited (continuous) joint.
    pub limits: Option<JointLimits>,
    /// Viscous damping coefficient (N·m·s/rad or N·s/m); kept for later, not in the dynamics yet.
    pub damping: f64,
    /// Coulomb friction (N·m or N); kept for later, not in the dynamics yet.
    pub friction: f64,
    /// Rotor inertia (kg·m²) on the motor side; kept for later, not in the dynamics yet.
    pub rotor_inertia: f64,
    /// Gear ratio (motor turns per joint turn); kept for later, not in the dynamics yet.
    pub gear_ratio: f64,
}

impl Joint {
    /// A joint with no limits and no friction, damping or rotor.
    pub fn new(name: impl Into<String>, kind: JointKind, screw: Vector6<f64>) -> Self {
        Self {
            name: name.into(),
            kind,
            screw,
            limits: None,
            damping: 0.0,
            friction: 0.0,
            rotor_inertia: 0.0,
            gear_ratio: 1.0,
        }
    }
}

/// A moving link i, the body moved by joint i.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// The link's name.
    pub name: String,
    /// `M_{i−1,i}`: the pose of frame {i} in frame {i−1} at the home configuration.
    pub home: Matrix4<f64>,
    /// `G_i`: the 6×6 spatial inertia of the link, expressed in frame {i}.
    pub inertia: SpatialInertia,
}

/// The end-effector frame {n+1}.
#[derive(Clone, Debug, PartialEq)]
pub struct EndEffector {
    /// The frame's name (the URDF tip link, or the TOML `end_effector.name`).
    pub name: String,
    /// `M_{n,n+1}`: its pose in the last link's frame {n}.
    pub home: Matrix4<f64>,
}

/// An open serial chain of n movable joints (see the crate docs for the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// The robot's name.
    pub name: String,
    /// Where the description came from (a path, a shipped name, or `Modern Robotics lists`).
    pub source: String,
    /// The n movable joints, root to tip.
    pub joints: Vec<Joint>,
    /// The n moving links; link i is moved by joint i.
    pub links: Vec<Link>,
    /// The end-effector frame {n+1}.
    pub end_effector: EndEffector,
    /// The gravity vector in {0} (m/s²).
    pub gravity: Vector3<f64>,
}

impl Robot {
    /// Builds and validates a robot from the book's lists: `m_list` = `M_{i−1,i}` for
    /// i = 1..n+1 (the last is the end effector), `g_list` = `G_i` in frame {i},
    /// `s_list` = `S_i` in {0}, and the gravity vector. Joints with `ω = 0` are prismatic.
    pub fn from_mr_lists(
        m_list: &[Matrix4<f64>],
        g_list: &[Matrix6<f64>],
        s_list: &[Vector6<f64>],
        gravity: Vector3<f64>,
    ) -> Result<Self, ModelError> {
        let robot = Self::from_mr_lists_unchecked(m_list, g_list, s_list, gravity)?;
        robot.validate()?;
        Ok(robot)
    }

    /// As [`Robot::from_mr_lists`], but accepts the lists as given, as the book's functions
    /// do (e.g. a screw axis with `|ω| ≠ 1`). Only the list sizes are checked.
    pub fn from_mr_lists_unchecked(
        m_list: &[Matrix4<f64>],
        g_list: &[Matrix6<f64>],
        s_list: &[Vector6<f64>],
        gravity: Vector3<f64>,
    ) -> Result<Self, ModelError> {
        let n = s_list.len();
        if g_list.len() != n || m_list.len() != n + 1 {
            return Err(ModelError::invalid(crate::Invalid::new(
                crate::Subject::Robot,
                "Mlist/Glist/Slist",
                format!(
                    "list sizes do not fit: {} screw axes, {} inertias and {} home frames",
                    n,
                    g_list.len(),
                    m_list.len()
                ),
                "give n screw axes, n spatial inertias and n+1 home frames (the last one is the end effector)",
            )));
        }
        let joints = s_list
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let kind = if s.fixed_rows::<3>(0).norm() == 0.0 {
                    JointKind::Prismatic
                } else {
                    JointKind::Revolute
                };
                Joint::new(format!("joint{}", i + 1), kind, *s)
            })
            .collect();
        let links = (0..n)
            .map(|i| Link {
                name: format!("link{}", i + 1),
                home: m_list[i],
                inertia: SpatialInertia(g_list[i]),
            })
            .collect();
        Ok(Self {
            name: "robot".into(),
            source: "Modern Robotics lists".into(),
            joints,
            links,
            end_effector: EndEffector {
                name: "end_effector".into(),
                home: m_list[n],
            },
            gravity,
        })
    }

    /// n, the number of movable joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The book's `Mlist`: `M_{i−1,i}` for i = 1..n+1.
    pub fn m_list(&self) -> Vec<Matrix4<f64>> {
        let mut v: Vec<_> = self.links.iter().map(|l| l.home).collect();
        v.push(self.end_effector.home);
        v
    }

    /// The book's `Glist`: `G_i` in frame {i}.
    pub fn g_list(&self) -> Vec<Matrix6<f64>> {
        self.links.iter().map(|l| l.inertia.0).collect()
    }

    /// The book's `Slist` (as a list of columns): `S_i` in {0}.
    pub fn s_list(&self) -> Vec<Vector6<f64>> {
        self.joints.iter().map(|j| j.screw).collect()
    }

    /// `M_{0i}` = `M_{01} M_{12} ⋯ M_{i−1,i}` for i = 0..n+1 (i = 0 is the identity,
    /// i = n+1 the end effector's home pose `M`).
    pub fn home_poses(&self) -> Vec<Matrix4<f64>> {
        let mut out = Vec::with_capacity(self.dof() + 2);
        let mut t = Matrix4::identity();
        out.push(t);
        for m in self.m_list() {
            t *= m;
            out.push(t);
        }
        out
    }

    /// `A_i = [Ad_{M_{0i}⁻¹}] S_i`: joint i's screw axis in link frame {i}, for i = 0..n−1
    /// (0-based).
    pub fn body_screws(&self) -> Vec<Vector6<f64>> {
        let poses = self.home_poses();
        self.joints
            .iter()
            .enumerate()
            .map(|(i, j)| adjoint(&trans_inv(&poses[i + 1])) * j.screw)
            .collect()
    }

    /// `B_i = [Ad_{M⁻¹}] S_i`: the screw axes in the end-effector frame at home.
    pub fn body_frame_screws(&self) -> Vec<Vector6<f64>> {
        let m = self.home_poses()[self.dof() + 1];
        let ad = adjoint(&trans_inv(&m));
        self.joints.iter().map(|j| ad * j.screw).collect()
    }

    /// The names of the movable joints, in the order of every vector.
    pub fn joint_names(&self) -> Vec<&str> {
        self.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// Checks the robot against every rule of [`crate::validate`]; see there.
    pub fn validate(&self) -> Result<(), ModelError> {
        let errors = crate::validate::validate(self);
        if errors.is_empty() {
            Ok(())
        } else {
            Err(ModelError::Invalid(errors))
        }
    }
}
