//! The serde form of a TOML robot file, exactly as written (see the module docs of
//! [`crate::toml_format`] for the meaning of every key).
//!
//! Every table denies unknown keys, so a misspelt key is an error with its line and column.
//! Arrays are read as `Vec`s and their lengths checked while building the robot, where the
//! message can name the link or joint. Poses (`home`, `frame`) accept two forms (a 4×4
//! matrix or a table of `xyz`/`rpy`) and are read as raw [`toml::Value`]s, interpreted by
//! [`super::pose`].

use serde::Deserialize;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RobotFile {
    /// The robot's name.
    pub name: String,
    /// Free text; not used.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: Option<String>,
    /// Gravity in {0} (3 numbers).
    #[serde(default)]
    pub gravity: Option<Vec<f64>>,
    /// `[parameters]`: already applied ([`super::params`]).
    #[serde(default)]
    #[allow(dead_code)]
    pub parameters: Option<toml::Value>,
    /// The base `[base]`.
    #[serde(default)]
    pub base: Option<BaseSpec>,
    /// The movable joints, every one after the joint of the link it hangs from (`[[joint]]`).
    #[serde(default, rename = "joint")]
    pub joints: Vec<JointSpec>,
    /// The end-effector frame `[end_effector]`.
    #[serde(default)]
    pub end_effector: Option<EndEffectorSpec>,
    /// Named frames `[[frame]]` (feet, hands, sensors).
    #[serde(default, rename = "frame")]
    pub frames: Vec<FrameSpec>,
}

/// `revolute` or `prismatic`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum KindSpec {
    Revolute,
    Prismatic,
}

/// One `[[joint]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JointSpec {
    pub name: String,
    #[serde(rename = "type")]
    pub kind: KindSpec,
    /// The link this joint's link hangs from (an earlier joint's link, or the base).
    pub parent: Option<String>,
    /// `S_i` in {0} (6 numbers).
    pub screw: Option<Vec<f64>>,
    /// Axis direction in {0} (3 numbers).
    pub axis: Option<Vec<f64>>,
    /// A point on a revolute axis in {0} (3 numbers).
    pub point: Option<Vec<f64>>,
    /// `[lower, upper]`.
    pub limits: Option<Vec<f64>>,
    pub velocity_limit: Option<f64>,
    pub effort_limit: Option<f64>,
    pub damping: Option<f64>,
    pub friction: Option<f64>,
    pub rotor_inertia: Option<f64>,
    pub gear_ratio: Option<f64>,
    /// `mimic = { joint = "..", multiplier = .., offset = .. }`: a coupled joint.
    pub mimic: Option<MimicSpec>,
    /// The link this joint moves (`[joint.link]`).
    pub link: LinkSpec,
}

/// `mimic = { joint = "leader", multiplier = m, offset = o }`: θ = m·θ_leader + o.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MimicSpec {
    /// The joint followed (by name).
    pub joint: String,
    /// m (default 1).
    pub multiplier: Option<f64>,
    /// o (default 0).
    pub offset: Option<f64>,
}

/// Where a rotational inertia is taken about.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum AboutSpec {
    /// About the centre of mass (the default).
    Com,
    /// About the origin of the body frame.
    Origin,
}

/// A primitive solid, centred at the origin of its body frame, axes along the frame's.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub(crate) enum ShapeSpec {
    /// `box = [w, l, h]`: edges along x, y, z.
    #[serde(rename = "box")]
    Cuboid(Vec<f64>),
    /// `cylinder = [r, h]`: axis z.
    Cylinder(Vec<f64>),
    /// `sphere = r`.
    Sphere(f64),
    /// `ellipsoid = [a, b, c]`: semi-axes along x, y, z.
    Ellipsoid(Vec<f64>),
    /// `plate = [w, l]`: a thin plate in the xy plane.
    Plate(Vec<f64>),
    /// `disc = r`: a thin disc in the xy plane.
    Disc(f64),
}

/// The inertial keys shared by a link and each of its `[[joint.link.body]]`s.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BodySpec {
    /// A name for messages (bodies only).
    pub name: Option<String>,
    /// The body frame {b} in the link frame {i} (default: {i}).
    pub frame: Option<toml::Value>,
    pub mass: Option<f64>,
    pub density: Option<f64>,
    pub shape: Option<ShapeSpec>,
    /// Centre of mass in {b} (3 numbers).
    pub com: Option<Vec<f64>>,
    /// `[ixx, iyy, izz, ixy, ixz, iyz]`.
    pub inertia: Option<Vec<f64>>,
    pub inertia_about: Option<AboutSpec>,
    /// 6×6 in {b}, rows.
    pub spatial_inertia: Option<Vec<Vec<f64>>>,
}

impl BodySpec {
    /// Whether any inertial key is set.
    pub fn is_empty(&self) -> bool {
        self.frame.is_none()
            && self.mass.is_none()
            && self.density.is_none()
            && self.shape.is_none()
            && self.com.is_none()
            && self.inertia.is_none()
            && self.inertia_about.is_none()
            && self.spatial_inertia.is_none()
    }
}

/// `[joint.link]`: the body keys of [`BodySpec`] (repeated here because serde's `flatten`
/// does not work with `deny_unknown_fields`), plus the link's name, home and bodies.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LinkSpec {
    pub name: String,
    /// `M_{λ(i),i}`: in the parent link's frame.
    pub home: toml::Value,
    pub frame: Option<toml::Value>,
    pub mass: Option<f64>,
    pub density: Option<f64>,
    pub shape: Option<ShapeSpec>,
    pub com: Option<Vec<f64>>,
    pub inertia: Option<Vec<f64>>,
    pub inertia_about: Option<AboutSpec>,
    pub spatial_inertia: Option<Vec<Vec<f64>>>,
    /// `[[joint.link.body]]`.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
}

impl LinkSpec {
    /// The link's own inertial keys as a body.
    pub fn own_body(&self) -> BodySpec {
        BodySpec {
            name: None,
            frame: self.frame.clone(),
            mass: self.mass,
            density: self.density,
            shape: self.shape.clone(),
            com: self.com.clone(),
            inertia: self.inertia.clone(),
            inertia_about: self.inertia_about,
            spatial_inertia: self.spatial_inertia.clone(),
        }
    }
}

/// `[base]`: the body keys of [`BodySpec`] (repeated, as in [`LinkSpec`]), plus the base's
/// name, whether it floats, and its bodies.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BaseSpec {
    pub name: Option<String>,
    pub floating: Option<bool>,
    pub frame: Option<toml::Value>,
    pub mass: Option<f64>,
    pub density: Option<f64>,
    pub shape: Option<ShapeSpec>,
    pub com: Option<Vec<f64>>,
    pub inertia: Option<Vec<f64>>,
    pub inertia_about: Option<AboutSpec>,
    pub spatial_inertia: Option<Vec<Vec<f64>>>,
    /// `[[base.body]]`.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
}

impl BaseSpec {
    /// The base's own inertial keys as a body.
    pub fn own_body(&self) -> BodySpec {
        BodySpec {
            name: None,
            frame: self.frame.clone(),
            mass: self.mass,
            density: self.density,
            shape: self.shape.clone(),
            com: self.com.clone(),
            inertia: self.inertia.clone(),
            inertia_about: self.inertia_about,
            spatial_inertia: self.spatial_inertia.clone(),
        }
    }
}

/// `[end_effector]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EndEffectorSpec {
    pub name: Option<String>,
    /// The link it is attached to (default: the last joint's link).
    pub parent: Option<String>,
    /// Its pose in the parent link's frame (default identity).
    pub home: Option<toml::Value>,
}

/// `[[frame]]`: a named frame on a link or the base.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FrameSpec {
    pub name: String,
    /// The link (or base) it is attached to.
    pub parent: String,
    /// Its pose in the parent link's frame (default identity).
    pub home: Option<toml::Value>,
}

/// The table form of a pose.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PoseSpec {
    pub xyz: Option<Vec<f64>>,
    pub rpy: Option<Vec<f64>>,
}
