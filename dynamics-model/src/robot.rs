//! The robot: a kinematic tree (the serial chain is the special case) in the
//! product-of-exponentials form of Modern Robotics, on a fixed or a floating base.

use crate::error::ModelError;
use crate::inertia::SpatialInertia;
use crate::lie::{adjoint, trans_inv};
use crate::mimic::Mimic;
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
///
/// A joint without position limits that has a velocity or effort limit (URDF's `continuous`
/// joint with `<limit effort=.. velocity=..>`) has `lower = −∞` and `upper = +∞`.
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

impl JointLimits {
    /// Velocity and effort limits of a joint without position limits (`lower = −∞`,
    /// `upper = +∞`); `None` when neither is given.
    pub fn without_position(velocity: Option<f64>, effort: Option<f64>) -> Option<Self> {
        (velocity.is_some() || effort.is_some()).then_some(Self {
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            velocity,
            effort,
        })
    }

    /// The position limits `(lower, upper)`, or `None` for a joint without them (±∞).
    pub fn position(&self) -> Option<(f64, f64)> {
        (self.lower != f64::NEG_INFINITY || self.upper != f64::INFINITY)
            .then_some((self.lower, self.upper))
    }
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
    /// Limits; `None` when the robot file gives none. A continuous joint's velocity and
    /// effort limits are kept with `lower = −∞`, `upper = +∞`.
    pub limits: Option<JointLimits>,
    /// `b_i ≥ 0`, the viscous friction (damping) coefficient (N·m·s/rad or N·s/m): a joint
    /// force `b_i q̇_i` opposing the motion. It enters the dynamics only through the friction
    /// functions (dynamics-reference's `friction_forces`, `τ = ID + τ_friction`), never through
    /// M, c or g.
    pub damping: f64,
    /// `μ_i ≥ 0`, the Coulomb friction (N·m or N): a joint force `μ_i sgn(q̇_i)` opposing the
    /// motion. Like [`Joint::damping`], only through the friction functions.
    pub friction: f64,
    /// `I_rotor ≥ 0`, the rotor's inertia about its own axis (kg·m²), on the motor side of the
    /// gear. With [`Joint::gear_ratio`] it gives the reflected inertia [`Joint::armature`],
    /// which the mass matrix adds to its diagonal (Modern Robotics §8.9.2).
    pub rotor_inertia: f64,
    /// `G ≠ 0`, the gear ratio: motor turns per joint turn (1 for a direct drive). The motor
    /// turns at `G q̇_i` and its torque is multiplied by G; only `G²` enters the dynamics,
    /// through [`Joint::armature`].
    pub gear_ratio: f64,
    /// `Some` for a mimic joint, which follows an independent joint and is not one of the
    /// coordinates of q, ν, ν̇, τ (see [`crate::mimic`]); `None` for an independent joint.
    pub mimic: Option<Mimic>,
}

impl Joint {
    /// The armature `G² I_rotor` (kg·m² or kg): the rotor's inertia reflected through the
    /// gear to the joint side ([`Joint::gear_ratio`]² · [`Joint::rotor_inertia`]), Modern
    /// Robotics §8.9.2. A rotor turning at `G q̇_i` stores `½ I_rotor (G q̇_i)²`, so the joint
    /// sees an extra `G² I_rotor` on the diagonal entry `M_ii` of the mass matrix (the rotor's
    /// gyroscopic coupling with the moving links is neglected, as in the book). This is
    /// Pinocchio's `model.armature`. Zero without a rotor (the default).
    pub fn armature(&self) -> f64 {
        self.gear_ratio * self.gear_ratio * self.rotor_inertia
    }

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
            mimic: None,
        }
    }
}

/// A moving link i, the body moved by joint i.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// The link's name.
    pub name: String,
    /// `λ(i)`: the link this one hangs from (0-based, always before i), or `None` for the
    /// base {0}. A serial chain has `λ(i) = i − 1`.
    pub parent: Option<usize>,
    /// `M_{λ(i),i}`: the pose of frame {i} in its parent's frame at the home configuration
    /// (`M_{i−1,i}` on a serial chain).
    pub home: Matrix4<f64>,
    /// `G_i`: the 6×6 spatial inertia of the link, expressed in frame {i}.
    pub inertia: SpatialInertia,
}

/// A frame rigidly attached to a link or to the base: the end-effector frame {n+1}, or a
/// named frame such as a foot or a hand ([`Robot::frames`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The frame's name (a URDF link, the TOML `end_effector.name` or `frame.name`).
    pub name: String,
    /// The link it is attached to (0-based), or `None` for the base; for the end effector
    /// of a serial chain the last link.
    pub parent: Option<usize>,
    /// Its pose in that link's frame (`M_{n,n+1}` for the end effector of a serial chain).
    pub home: Matrix4<f64>,
}

/// The end-effector frame {n+1}: a [`Frame`].
pub type EndEffector = Frame;

/// The base: the body every root link hangs from, whose frame is {0} at the home
/// configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Base {
    /// The base link's name (the URDF root link; `base` otherwise).
    pub name: String,
    /// Its spatial inertia in {0}; it moves (and counts) only when the base floats.
    pub inertia: SpatialInertia,
    /// `true`: a free 6-DoF joint connects the world to the base (see the crate docs for the
    /// conventions of q, ν and τ); `false`: the base is the fixed world frame {0}.
    pub floating: bool,
}

impl Base {
    /// A fixed, massless base called `base`.
    pub fn fixed() -> Self {
        Self {
            name: "base".into(),
            inertia: SpatialInertia::zero(),
            floating: false,
        }
    }
}

/// A kinematic tree of n movable joints on a fixed or floating base (see the crate docs for
/// the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// The robot's name.
    pub name: String,
    /// Where the description came from (a path, a shipped name, or `Modern Robotics lists`).
    pub source: String,
    /// The base, fixed or floating.
    pub base: Base,
    /// The n movable joints in depth-first order from the base (every joint after its
    /// parent; a serial chain root to tip).
    pub joints: Vec<Joint>,
    /// The n moving links; link i is moved by joint i.
    pub links: Vec<Link>,
    /// The end-effector frame {n+1}.
    pub end_effector: EndEffector,
    /// Named frames whose pose and Jacobians the generated code computes (feet, hands,
    /// sensors), in this order; may be empty.
    pub frames: Vec<Frame>,
    /// The gravity vector in {0} (m/s²).
    pub gravity: Vector3<f64>,
    /// The quantities that generated code reads from its struct at run time instead of
    /// folding them in (none by default).
    pub runtime: RuntimeParameters,
    /// The named parameters of the file and the fields written with them (empty unless a
    /// TOML file declares `[parameters]`); the numbers above already hold their values.
    pub parameters: crate::parameters::Parameters,
}

/// The quantities of a robot left open until run time: the generated struct carries them as
/// fields whose `Default` is the robot's own values, and every function reads them; every
/// other constant stays folded into the code.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RuntimeParameters {
    /// The gravity vector in {0} ([`Robot::gravity`] is its default).
    pub gravity: bool,
    /// The link (0-based) that carries a payload: a rigid body added to the link's own
    /// inertia, given by its mass, its centre of mass in the link's frame and its
    /// rotational inertia about that centre in the link's axes; zero by default.
    pub payload: Option<usize>,
}

impl RuntimeParameters {
    /// Whether any quantity is left open.
    pub fn any(&self) -> bool {
        self.gravity || self.payload.is_some()
    }
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
                parent: i.checked_sub(1),
                home: m_list[i],
                inertia: SpatialInertia(g_list[i]),
            })
            .collect();
        Ok(Self {
            name: "robot".into(),
            source: "Modern Robotics lists".into(),
            base: Base::fixed(),
            joints,
            links,
            end_effector: EndEffector {
                name: "end_effector".into(),
                parent: n.checked_sub(1),
                home: m_list[n],
            },
            frames: Vec::new(),
            gravity,
            runtime: RuntimeParameters::default(),
            parameters: Default::default(),
        })
    }

    /// n, the number of movable joints (the floating base not counted), mimic joints
    /// included: the physical joints, one per moving link.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The length of the configuration vector q: k, or k + 7 on a floating base
    /// (position, unit quaternion, joint values), with k = [`Robot::n_coordinates`] the
    /// independent joints (n when no joint mimics another).
    pub fn nq(&self) -> usize {
        self.n_coordinates() + if self.base.floating { 7 } else { 0 }
    }

    /// The length of the velocity vector ν (and of ν̇ and τ): k, or k + 6 on a floating base
    /// (the base's body twist, then the joint rates), with k = [`Robot::n_coordinates`].
    pub fn nv(&self) -> usize {
        self.n_coordinates() + if self.base.floating { 6 } else { 0 }
    }

    /// `λ(i)` for every link: its parent link, `None` for the base.
    pub fn parents(&self) -> Vec<Option<usize>> {
        self.links.iter().map(|l| l.parent).collect()
    }

    /// Whether the links form one serial chain (`λ(i) = i − 1` for every i).
    pub fn is_serial(&self) -> bool {
        self.links
            .iter()
            .enumerate()
            .all(|(i, l)| l.parent == i.checked_sub(1))
    }

    /// The links on the path from the base to link `i`, base side first, `i` last (the
    /// joints that move link i).
    pub fn path_to(&self, i: usize) -> Vec<usize> {
        let mut path = vec![i];
        let mut k = i;
        while let Some(p) = self.links[k].parent {
            path.push(p);
            k = p;
        }
        path.reverse();
        path
    }

    /// The book's `Mlist` on a serial chain: `M_{λ(i),i}` for i = 1..n, then the end
    /// effector's home.
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
    /// This robot with a payload added to link `link` (0-based): a rigid body of mass `mass`,
    /// centre of mass `com` in the link's frame {i}, and rotational inertia `inertia` about
    /// that centre in {i}'s axes, `[xx, yy, zz, xy, xz, yz]` (the matrix entries). This is
    /// what a run-time payload ([`RuntimeParameters::payload`]) stands for, in the model.
    pub fn with_payload(&self, link: usize, mass: f64, com: [f64; 3], inertia: [f64; 6]) -> Robot {
        let [xx, yy, zz, xy, xz, yz] = inertia;
        let i_c = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        let t = crate::lie::rp_to_trans(&nalgebra::Matrix3::identity(), &Vector3::from(com));
        let payload = SpatialInertia::from_com_frame(mass, i_c, &t);
        let mut r = self.clone();
        r.links[link].inertia = SpatialInertia(r.links[link].inertia.0 + payload.0);
        r
    }

    /// `M_{0i}`, the home pose of every frame in {0}: index 0 the base (identity), 1..=n the
    /// links (`M_{0,λ(i)} M_{λ(i),i}`), n+1 the end effector.
    pub fn home_poses(&self) -> Vec<Matrix4<f64>> {
        let n = self.dof();
        let mut out: Vec<Matrix4<f64>> = Vec::with_capacity(n + 2);
        out.push(Matrix4::identity());
        for l in &self.links {
            let parent = l.parent.map_or(Matrix4::identity(), |p| out[p + 1]);
            out.push(parent * l.home);
        }
        let ee = &self.end_effector;
        let parent = ee.parent.map_or(Matrix4::identity(), |p| out[p + 1]);
        out.push(parent * ee.home);
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
        self.frame_screws(&self.end_effector)
    }

    /// `M_{0f}`: the home pose of a frame (the end effector or one of [`Robot::frames`]) in
    /// {0}.
    pub fn frame_home(&self, frame: &Frame) -> Matrix4<f64> {
        let homes = self.home_poses();
        frame.parent.map_or(Matrix4::identity(), |p| homes[p + 1]) * frame.home
    }

    /// `[Ad_{M_{0f}⁻¹}] S_i`: the screw axes in a frame at home.
    pub fn frame_screws(&self, frame: &Frame) -> Vec<Vector6<f64>> {
        let ad = adjoint(&trans_inv(&self.frame_home(frame)));
        self.joints.iter().map(|j| ad * j.screw).collect()
    }

    /// The joints on the path from the base to a frame, base side first.
    pub fn frame_path(&self, frame: &Frame) -> Vec<usize> {
        frame.parent.map_or(Vec::new(), |p| self.path_to(p))
    }

    /// The names of the independent joints, in the order of every vector (mimic joints are
    /// not coordinates; all names are in [`Robot::joints`]).
    pub fn joint_names(&self) -> Vec<&str> {
        self.joints
            .iter()
            .filter(|j| j.is_independent())
            .map(|j| j.name.as_str())
            .collect()
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
