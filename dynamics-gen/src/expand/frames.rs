//! Joint frames: the numeric preparation of a robot for the symbolic recursions.
//!
//! The book's recursions run in the link frames {i}, where joint i's screw axis is
//! `A_i = [Ad_{M_{0i}⁻¹}] S_i` and `T_{i,i−1}(θ_i) = e^{−[A_i]θ_i} M_{i−1,i}⁻¹`. Any frame
//! rigidly attached to link i serves as well, and one choice makes the expansion much
//! cheaper: the *joint frame* {J_i}, whose z axis is joint i's axis and whose origin lies on
//! it. There `A_i = (0,0,1, 0,0,0)` (revolute) or `(0,0,0, 0,0,1)` (prismatic), so
//!
//! ```text
//! T_{J_i,J_{i−1}}(θ_i) = Rot_z(−θ_i) · C_i      (revolute)
//!                      = Trans_z(−θ_i) · C_i    (prismatic)
//! ```
//!
//! with a constant `C_i = (R_i, p_i)`, the pose of {J_{i−1}} in {J_i} at θ_i = 0
//! ({J_0} = {0}). The joint's part costs a handful of multiplications by `sin θ_i` and
//! `cos θ_i`, `τ_i` is one component of the link wrench, and every zero or one in `C_i` and
//! in the inertias folds away.
//!
//! When the axis is a coordinate axis of the link frame (as in most URDF files), the frame
//! change is a signed permutation with exact entries, so nothing is lost to rounding.

use dynamics_model::lie::{angular, linear, rotation, rp_to_trans, trans_inv, translation};
use dynamics_model::{JointKind, Robot, SpatialInertia};
use nalgebra::{Matrix3, Matrix4, Vector3};

/// A rigid body's inertia in a frame: mass `m`, first moment `h = m c` (c = centre of mass)
/// and rotational inertia `I_o` about the frame's origin; `G = [[I_o, [h]], [[h]ᵀ, m·1₃]]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyInertia {
    /// Mass m (kg).
    pub m: f64,
    /// First moment of mass `h = m c` (kg·m).
    pub h: [f64; 3],
    /// Rotational inertia about the origin, `[xx, yy, zz, xy, xz, yz]` (kg·m²).
    pub i: [f64; 6],
}

impl BodyInertia {
    /// Reads the ten inertial parameters off a 6×6 spatial inertia.
    pub fn from_spatial(g: &SpatialInertia) -> Self {
        let m = g.0;
        Self {
            m: m[(3, 3)],
            // Upper-right block [h] = [[0, −h_z, h_y], [h_z, 0, −h_x], [−h_y, h_x, 0]].
            h: [m[(2, 4)], m[(0, 5)], m[(1, 3)]],
            i: [
                m[(0, 0)],
                m[(1, 1)],
                m[(2, 2)],
                m[(0, 1)],
                m[(0, 2)],
                m[(1, 2)],
            ],
        }
    }
}

/// Joint i of the chain, expressed in joint frames.
#[derive(Clone, Debug, PartialEq)]
pub struct JointFrame {
    /// Revolute (about z of {J_i}) or prismatic (along z).
    pub kind: JointKind,
    /// `R_i`: rotation of `C_i`, the pose of {J_{i−1}} in {J_i} at θ_i = 0 (row-major).
    pub r: [[f64; 3]; 3],
    /// `p_i`: translation of `C_i`.
    pub p: [f64; 3],
    /// Link i's inertia in {J_i}.
    pub inertia: BodyInertia,
}

/// The whole chain in joint frames, and gravity in {0}.
#[derive(Clone, Debug, PartialEq)]
pub struct JointFrames {
    /// The joints, root to tip.
    pub joints: Vec<JointFrame>,
    /// Gravity in {0} (m/s²).
    pub gravity: [f64; 3],
}

/// The pose `T_{i,J_i}` of joint i's frame in link frame {i}: z along the joint axis, origin
/// on the axis (revolute) or at the link frame's origin (prismatic).
pub fn joint_frame_in_link(kind: JointKind, a: &nalgebra::Vector6<f64>) -> Matrix4<f64> {
    let (axis, origin) = match kind {
        JointKind::Revolute => {
            let w = angular(a);
            let w = w / w.norm();
            // For A = (ω, −ω × q), ω × v = q − (ω·q) ω: the point of the axis nearest the origin.
            (w, w.cross(&linear(a)))
        }
        JointKind::Prismatic => {
            let v = linear(a);
            (v / v.norm(), Vector3::zeros())
        }
    };
    rp_to_trans(&frame_with_z(&axis), &origin)
}

/// A rotation whose third column is the unit vector `z`; a signed permutation (exact) when
/// `z` is a coordinate axis.
fn frame_with_z(z: &Vector3<f64>) -> Matrix3<f64> {
    for k in 0..3 {
        let s = z[k];
        if (s == 1.0 || s == -1.0) && z.iter().enumerate().all(|(j, &x)| j == k || x == 0.0) {
            // x' = e_{k+1}, y' = z' × x' (exact signed permutation).
            let zc = Vector3::ith(k, s);
            let xc = Vector3::ith((k + 1) % 3, 1.0);
            let yc = zc.cross(&xc);
            return Matrix3::from_columns(&[xc, yc, zc]);
        }
    }
    // Gram–Schmidt from the coordinate axis least aligned with z.
    let k = (0..3)
        .min_by(|&a, &b| z[a].abs().total_cmp(&z[b].abs()))
        .unwrap_or(0);
    let e = Vector3::ith(k, 1.0);
    let x = (e - z * z[k]).normalize();
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, *z])
}

/// Expresses `robot` in joint frames (see the module docs).
pub fn joint_frames(robot: &Robot) -> JointFrames {
    let a_list = robot.body_screws();
    // T_{J_{i−1}} in {i−1}; {J_0} = {0}.
    let mut t_prev_link_joint = Matrix4::identity();
    let mut joints = Vec::with_capacity(robot.dof());
    for (i, (joint, link)) in robot.joints.iter().zip(&robot.links).enumerate() {
        let t_link_joint = joint_frame_in_link(joint.kind, &a_list[i]);
        // C_i = T_{J_i, J_{i−1}} = T_{J_i,i} · M_{i−1,i}⁻¹ · T_{i−1,J_{i−1}}.
        let c = trans_inv(&t_link_joint) * trans_inv(&link.home) * t_prev_link_joint;
        let r = rotation(&c);
        let p = translation(&c);
        let inertia = BodyInertia::from_spatial(&link.inertia.transform_by(&t_link_joint));
        joints.push(JointFrame {
            kind: joint.kind,
            r: [
                [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
            ],
            p: [p[0], p[1], p[2]],
            inertia,
        });
        t_prev_link_joint = t_link_joint;
    }
    JointFrames {
        joints,
        gravity: [robot.gravity[0], robot.gravity[1], robot.gravity[2]],
    }
}
