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
//! The frames follow the modified Denavit–Hartenberg convention (Craig): `x_i` along the
//! common normal from axis i to axis i+1, so the pose of {J_i} in {J_{i−1}} is
//! `Rot_x(α) Trans_x(a) Rot_z(θ₀ + θ) Trans_z(d)` and `C_i = (Rot_x(−α), (−a, 0, −d))`: four
//! multiplications per rotated vector instead of nine. The home offset θ₀ (or d, for a
//! prismatic joint) goes into the joint variable (`sin(q + θ₀)`), or into `C_i` when it is a
//! multiple of π/2. DH parameters are snapped (angles within [`SNAP`] of kπ/2, lengths below
//! it) so that exact zeros and ones fold, and a DH fit is used only when it rebuilds the pose
//! to [`DH_TOL`]; otherwise the joint keeps a general constant transform.
//!
//! Finally [`regroup`] moves inertial parameters that cannot be seen through a revolute joint
//! to the link before it, which removes three parameters per revolute link.

use dynamics_model::lie::{angular, linear, rotation, rp_to_trans, trans_inv, translation};
use dynamics_model::{JointKind, Robot, SpatialInertia};
use nalgebra::{Matrix3, Matrix4, Vector3};
use std::f64::consts::FRAC_PI_2;

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
    /// The 6×6 spatial inertia `[[I_o, [h]], [[h]ᵀ, m·1₃]]`.
    pub fn to_spatial(&self) -> SpatialInertia {
        let [xx, yy, zz, xy, xz, yz] = self.i;
        let [hx, hy, hz] = self.h;
        let m = self.m;
        SpatialInertia(nalgebra::Matrix6::from_row_slice(&[
            xx, xy, xz, 0.0, -hz, hy, //
            xy, yy, yz, hz, 0.0, -hx, //
            xz, yz, zz, -hy, hx, 0.0, //
            0.0, hz, -hy, m, 0.0, 0.0, //
            -hz, 0.0, hx, 0.0, m, 0.0, //
            hy, -hx, 0.0, 0.0, 0.0, m,
        ]))
    }

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

/// Joint i of the tree, expressed in joint frames.
#[derive(Clone, Debug, PartialEq)]
pub struct JointFrame {
    /// Revolute (about z of {J_i}) or prismatic (along z).
    pub kind: JointKind,
    /// `λ(i)`: the joint whose link this one's hangs from (`None`: the base).
    pub parent: Option<usize>,
    /// `R_i`: rotation of `C_i`, the pose of {J_λ(i)} ({0} for a root joint) in {J_i} at
    /// θ_i = 0 (row-major).
    pub r: [[f64; 3]; 3],
    /// `p_i`: translation of `C_i`.
    pub p: [f64; 3],
    /// Link i's inertia in {J_i}.
    pub inertia: BodyInertia,
    /// The joint's home offset: the joint part is `Rot_z(−(θ_i + offset))` or
    /// `Trans_z(−(θ_i + offset))` (the DH θ or d of the home configuration).
    pub offset: f64,
    /// The armature `G² I_rotor` ([`dynamics_model::Joint::armature`]), added to the
    /// joint's diagonal entry of M and as `armature · θ̈_i` to its force.
    pub armature: f64,
    /// When link i carries the run-time payload ([`dynamics_model::RuntimeParameters`]):
    /// the pose of {J_i} in the link's frame {i}, in which the payload is given.
    pub payload: Option<PayloadPose>,
}

impl JointFrame {
    /// `−Rᵀ p`: the origin of {J_i} in {J_λ(i)} (the translation of `C_i⁻¹`).
    pub fn origin_in_parent(&self) -> [f64; 3] {
        std::array::from_fn(|i| -(0..3).map(|k| self.r[k][i] * self.p[k]).sum::<f64>())
    }
}

/// The pose `T_{i,J_i} = (R, p)` of a joint frame in its link's frame: `R` the axes of
/// {J_i} in {i} (row-major), `p` its origin in {i}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PayloadPose {
    /// R.
    pub r: [[f64; 3]; 3],
    /// p (m).
    pub p: [f64; 3],
}

/// The whole tree in joint frames, the floating base's inertia, and gravity in {0}.
#[derive(Clone, Debug, PartialEq)]
pub struct JointFrames {
    /// The joints, every one after its parent.
    pub joints: Vec<JointFrame>,
    /// A floating base's inertia in {0} (the base frame); `None` for a fixed base.
    pub base: Option<BodyInertia>,
    /// `T_{0,J_i}`: every joint frame's pose in the base frame at the home configuration.
    pub homes: Vec<Matrix4<f64>>,
    /// Gravity in {0} (m/s²): the folded value, or the default of the run-time parameter.
    pub gravity: [f64; 3],
    /// Gravity is a run-time parameter ([`super::parameters`]) rather than a constant.
    pub runtime_gravity: bool,
}

/// Angles within this distance (rad) of a multiple of π/2 are snapped to it, and lengths
/// below it (m) to zero, so that the constants fold to exact zeros and ones.
pub const SNAP: f64 = 1e-12;

/// Common normals whose feet lie further than this (m) from the axes' reference points are
/// ill-conditioned (nearly parallel axes); such axes are treated as parallel.
pub const FAR: f64 = 10.0;

/// A pose is taken as DH-shaped only when the snapped DH parameters rebuild it to within
/// this (rotation entries, and metres); otherwise the joint keeps a general constant
/// transform. Nearly parallel axes make the common normal ill-conditioned: this check, not
/// the construction, guarantees the model.
pub const DH_TOL: f64 = 1e-13;

/// Inertial parameters below this fraction of the largest one are rounding noise: zero.
pub const INERTIA_SNAP: f64 = 1e-13;

/// A joint axis as a line in {0} at the home configuration: a point and a unit direction.
struct AxisLine {
    point: Vector3<f64>,
    dir: Vector3<f64>,
}

fn axis_lines(robot: &Robot) -> Vec<AxisLine> {
    let homes = robot.home_poses();
    robot
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| match j.kind {
            JointKind::Revolute => {
                let w = angular(&j.screw);
                let w = w / w.norm();
                AxisLine {
                    point: w.cross(&linear(&j.screw)),
                    dir: w,
                }
            }
            JointKind::Prismatic => {
                let v = linear(&j.screw);
                AxisLine {
                    point: translation(&homes[i + 1]),
                    dir: v / v.norm(),
                }
            }
        })
        .collect()
}

/// A unit vector perpendicular to `z`, as close as possible to `hint`.
fn perpendicular(z: &Vector3<f64>, hint: &Vector3<f64>) -> Vector3<f64> {
    let x = hint - z * z.dot(hint);
    if x.norm() > 1e-6 {
        return x.normalize();
    }
    let k = (0..3)
        .min_by(|&a, &b| z[a].abs().total_cmp(&z[b].abs()))
        .unwrap_or(0);
    let e = Vector3::ith(k, 1.0);
    (e - z * z[k]).normalize()
}

/// Home poses `T_{0,J_i}` of modified-DH joint frames (Craig's convention), along each
/// joint's only child: `z_i` along axis i, `x_i` along the common normal from axis i to
/// the axis of i's child, origin where that normal leaves axis i (for parallel axes:
/// where the parent's normal landed, so `d_i = 0`). A joint with several children (or none)
/// has its origin where its parent's normal landed and `x_i` nearest its parent's; a joint
/// that is not its parent's only child (or a root joint) starts from the point of its axis
/// nearest its parent's origin.
fn dh_frames(lines: &[AxisLine], parents: &[Option<usize>]) -> Vec<Matrix4<f64>> {
    let n = lines.len();
    // Each joint's only child. A joint with several children places its frame as a last
    // joint does (on its axis where its parent's normal landed, `x` nearest the parent's), so
    // that every child starts from the point of its axis nearest that origin and no child's
    // constants are tuned to the frame: a tree's alike limbs (TALOS' and G1's arms off their
    // torsos) keep one shape (`emit::pack`) instead of the first child's differing from its
    // siblings'.
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, p) in parents.iter().enumerate() {
        if let Some(p) = p {
            children[*p].push(j);
        }
    }
    let only_child: Vec<Option<usize>> = children
        .iter()
        .map(|c| match c[..] {
            [j] => Some(j),
            _ => None,
        })
        .collect();
    let mut frames: Vec<Matrix4<f64>> = Vec::with_capacity(n);
    // Where the parent's common normal lands on axis i, for only children.
    let mut landing_of: Vec<Option<Vector3<f64>>> = vec![None; n];
    for i in 0..n {
        let AxisLine { point, dir: z } = &lines[i];
        let (parent_origin, prev_x) = match parents[i] {
            Some(p) => (
                translation(&frames[p]),
                frames[p].fixed_view::<3, 1>(0, 0).into_owned(),
            ),
            None => (Vector3::zeros(), Vector3::x()),
        };
        // Where the parent's normal landed, or the point nearest the parent's origin; either
        // way projected onto axis i (a "parallel" landing of nearly parallel axes, see
        // [`FAR`], lies beside the axis, and a frame origin off the axis is a wrong model).
        let landing = landing_of[i].unwrap_or(parent_origin);
        let landing = point + z * z.dot(&(landing - point));
        let (origin, x) = match only_child[i] {
            Some(next_i) => {
                let next = &lines[next_i];
                let c = z.cross(&next.dir);
                // Closest point of axis i to the child's axis, and its mirror on that axis;
                // for nearly parallel axes these run off far away (ill-conditioned): treat
                // them as parallel.
                let w = next.point - point;
                let c2 = c.norm_squared().max(f64::MIN_POSITIVE);
                let s = w.cross(&next.dir).dot(&c) / c2;
                let t = w.cross(z).dot(&c) / c2;
                if c.norm() > 1e-6 && s.abs() < FAR && t.abs() < FAR {
                    let o = point + z * s;
                    let land = next.point + next.dir * t;
                    // The normal is perpendicular to axis i by construction; re-project so
                    // that rounding in s and t cannot tilt the frame.
                    let gap = land - o;
                    let gap = gap - z * z.dot(&gap);
                    let x = if gap.norm() > 1e-9 {
                        gap.normalize()
                    } else {
                        let cn = c.normalize();
                        if cn.dot(&prev_x) < 0.0 {
                            -cn
                        } else {
                            cn
                        }
                    };
                    landing_of[next_i] = Some(land);
                    (o, x)
                } else {
                    // Parallel axes: start at the landing point (d = 0).
                    let o = landing;
                    let w = next.point - o;
                    let perp = w - z * z.dot(&w);
                    let x = if perp.norm() > 1e-9 {
                        perp.normalize()
                    } else {
                        perpendicular(z, &prev_x)
                    };
                    landing_of[next_i] = Some(o + perp);
                    (o, x)
                }
            }
            None => (landing, perpendicular(z, &prev_x)),
        };
        let y = z.cross(&x);
        frames.push(rp_to_trans(&Matrix3::from_columns(&[x, y, *z]), &origin));
    }
    frames
}

fn snap_angle(a: f64) -> f64 {
    let k = (a / FRAC_PI_2).round();
    if (a - k * FRAC_PI_2).abs() <= SNAP {
        k * FRAC_PI_2
    } else {
        a
    }
}

fn snap_length(x: f64) -> f64 {
    if x.abs() <= SNAP {
        0.0
    } else {
        x
    }
}

/// `(sin a, cos a)`, exact for multiples of π/2.
fn sin_cos(a: f64) -> (f64, f64) {
    let k = a / FRAC_PI_2;
    if k == k.round() && k.abs() < 1e6 {
        match (k as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        dynamics_model::lie::sin_cos(a)
    }
}

fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = sin_cos(a);
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = sin_cos(a);
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Writes the pose `x` of {J_i} in {J_{i−1}} as modified DH parameters
/// `Rot_x(α) Trans_x(a) Rot_z(θ₀) Trans_z(d)` with snapped values, and returns the constant
/// part and offset of `T_{J_i,J_{i−1}}(θ) = Rot_z(−(θ + θ₀)) · (Rot_x(−α), (−a, 0, −d))`
/// (revolute) or `Trans_z(−(θ + d)) · Rot_z(−θ₀) · (Rot_x(−α), (−a, 0, 0))` (prismatic), or
/// `None` if `x` is not of that form.
fn dh_parameters(kind: JointKind, x: &Matrix4<f64>) -> Option<(Matrix3<f64>, Vector3<f64>, f64)> {
    let r = rotation(x);
    let t = translation(x);
    let alpha = snap_angle(libm::atan2(-r[(1, 2)], r[(2, 2)]));
    let theta0 = snap_angle(libm::atan2(-r[(0, 1)], r[(0, 0)]));
    let (sa, ca) = sin_cos(alpha);
    let a = snap_length(t[0]);
    let d = snap_length(t[2] * ca - t[1] * sa);
    // Check that x really has the DH form.
    let rebuilt_r = rot_x(alpha) * rot_z(theta0);
    let rebuilt_t = Vector3::new(a, -d * sa, d * ca);
    if (rebuilt_r - r).amax() > DH_TOL || (rebuilt_t - t).amax() > DH_TOL {
        return None;
    }
    match kind {
        JointKind::Revolute => {
            // Multiples of π/2 fold into the constant part exactly; others go into sin/cos.
            let snapped = theta0 / FRAC_PI_2 == (theta0 / FRAC_PI_2).round();
            let (rz, offset) = if snapped {
                (rot_z(-theta0), 0.0)
            } else {
                (Matrix3::identity(), theta0)
            };
            let p = rz * Vector3::new(-a, 0.0, -d);
            Some((rz * rot_x(-alpha), p, offset))
        }
        JointKind::Prismatic => {
            let rz = rot_z(-theta0);
            Some((rz * rot_x(-alpha), rz * Vector3::new(-a, 0.0, 0.0), d))
        }
    }
}

fn snap_inertia(b: BodyInertia) -> BodyInertia {
    let scale =
        b.h.iter()
            .chain(b.i.iter())
            .fold(b.m.abs(), |m, x| m.max(x.abs()));
    let snap = |x: f64| {
        if x.abs() <= INERTIA_SNAP * scale {
            0.0
        } else {
            x
        }
    };
    BodyInertia {
        m: b.m,
        h: b.h.map(snap),
        i: b.i.map(snap),
    }
}

fn rows(r: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ]
}

/// Expresses `robot` in modified-DH joint frames (see the module docs).
pub fn joint_frames(robot: &Robot) -> JointFrames {
    let lines = axis_lines(robot);
    let parents = robot.parents();
    let frames = dh_frames(&lines, &parents);
    let homes = robot.home_poses();
    let mut joints = Vec::with_capacity(robot.dof());
    for (i, (joint, link)) in robot.joints.iter().zip(&robot.links).enumerate() {
        let t_0j = frames[i];
        // T_{i,J_i}: the joint frame in link frame {i}.
        let t_link_joint = trans_inv(&homes[i + 1]) * t_0j;
        let inertia = snap_inertia(BodyInertia::from_spatial(
            &link.inertia.transform_by(&t_link_joint),
        ));
        let parent = link.parent;
        let t_prev = parent.map_or(Matrix4::identity(), |p| frames[p]);
        // Pose of {J_i} in {J_λ(i)} at home.
        let x = trans_inv(&t_prev) * t_0j;
        let dh = parent.and_then(|_| dh_parameters(joint.kind, &x));
        let (r, p, offset) = dh.unwrap_or_else(|| {
            let c = trans_inv(&x);
            (rotation(&c), translation(&c), 0.0)
        });
        joints.push(JointFrame {
            kind: joint.kind,
            parent,
            r: rows(&r),
            p: [p[0], p[1], p[2]],
            inertia,
            offset,
            armature: joint.armature(),
            payload: (robot.runtime.payload == Some(i)).then(|| PayloadPose {
                r: rows(&rotation(&t_link_joint)),
                p: {
                    let p = translation(&t_link_joint);
                    [p[0], p[1], p[2]]
                },
            }),
        });
    }
    let mut base = robot
        .base
        .floating
        .then(|| snap_inertia(BodyInertia::from_spatial(&robot.base.inertia)));
    regroup(&mut joints, &mut base, &frames);
    JointFrames {
        joints,
        base,
        homes: frames,
        gravity: [robot.gravity[0], robot.gravity[1], robot.gravity[2]],
        runtime_gravity: robot.runtime.gravity,
    }
}

/// Regroups inertial parameters across revolute joints (after Khalil and Gautier's base
/// parameters), tip to base.
///
/// Point masses on a revolute joint's axis move the same whether they belong to the link
/// it drives or to the link before it. Link i's mass `m`, first moment `h_z` along the axis
/// and an equal share `λ = I_yy` of `I_xx` and `I_yy` are exactly such a distribution
/// (`Σm = m`, `Σmz = h_z`, `Σmz² = λ`; the dynamics are linear in these parameters, so the
/// distribution need not be physical), so they are moved to link λ(i) (to a floating base;
/// dropped at a fixed base). Link i keeps `h_x, h_y, I_xx − I_yy, I_zz, I_xy, I_xz, I_yz`: three fewer non-zero
/// parameters per revolute joint, and the dynamics are unchanged.
pub fn regroup(joints: &mut [JointFrame], base: &mut Option<BodyInertia>, frames: &[Matrix4<f64>]) {
    for i in (0..joints.len()).rev() {
        if joints[i].kind != JointKind::Revolute {
            continue;
        }
        let b = joints[i].inertia;
        let lambda = b.i[1];
        let moved = BodyInertia {
            m: b.m,
            h: [0.0, 0.0, b.h[2]],
            i: [lambda, lambda, 0.0, 0.0, 0.0, 0.0],
        };
        joints[i].inertia = BodyInertia {
            m: 0.0,
            h: [b.h[0], b.h[1], 0.0],
            i: [b.i[0] - lambda, 0.0, b.i[2], b.i[3], b.i[4], b.i[5]],
        };
        // The moved masses lie on axis i: express them in the parent's frame at any θ_i.
        match joints[i].parent {
            Some(p) => {
                let t = trans_inv(&frames[p]) * frames[i];
                let g = moved.to_spatial().expressed_in(&t);
                let parent = joints[p].inertia.to_spatial();
                joints[p].inertia = snap_inertia(BodyInertia::from_spatial(&(parent + g)));
            }
            None => {
                if let Some(b) = base {
                    let g = moved.to_spatial().expressed_in(&frames[i]);
                    *b = snap_inertia(BodyInertia::from_spatial(&(b.to_spatial() + g)));
                }
            }
        }
    }
}
