//! Run-time parameters: quantities of the robot that generated code reads from its struct
//! instead of folding them in ([`dynamics_model::RuntimeParameters`]): the gravity vector
//! and a payload carried by one link.
//!
//! They are leaves of the graph in group [`PARAM`], laid out as [`FIELDS`]: gravity `g` in
//! {0} (m/s²); the payload's mass `m_p` (kg), its centre of mass `c_p` in the link's frame
//! {i} (m) and its rotational inertia `I_p` about `c_p` in the axes of {i},
//! `[xx, yy, zz, xy, xz, yz]` (kg·m²). Every recursion takes a link's inertia from
//! [`link_inertia`] and gravity from [`gravity`]; everything else stays folded.
//!
//! The payload is added to link i's inertia in its joint frame {J_i}, whose pose in {i} is
//! `(R, p)` ([`super::frames::PayloadPose`]):
//!
//! ```text
//! c = Rᵀ (c_p − p),   I_c = Rᵀ I_p R,   h = m_p c,   I_o = I_c + m_p (c·c 1 − c cᵀ)
//! ```
//!
//! after the constant inertias are regrouped ([`super::frames::regroup`]), which moves
//! constants only: the dynamics are linear in the inertias, so the sum is exact. With the
//! default values (the robot's gravity, no payload) the expressions evaluate to the folded
//! ones.

use super::frames::{JointFrame, JointFrames, PayloadPose};
use super::spatial::{rotate_inertia_const, Inertia, VectorOps, V3};
use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::Robot;

/// Input group of the run-time parameters.
pub const PARAM: u8 = 7;

/// A field of the generated struct that holds run-time parameters: leaves
/// `first .. first + len` of group [`PARAM`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// The field's name.
    pub name: &'static str,
    /// Its first leaf.
    pub first: u16,
    /// Its length: 1 for a scalar field, otherwise an array.
    pub len: usize,
    /// Whether it exists for gravity (`true`) or for the payload (`false`).
    pub gravity: bool,
    /// Its documentation.
    pub doc: &'static str,
}

/// Index of gravity's leaves.
pub const GRAVITY: u16 = 0;
/// Index of the payload's mass.
pub const PAYLOAD_MASS: u16 = 3;
/// Index of the payload's centre of mass.
pub const PAYLOAD_COM: u16 = 4;
/// Index of the payload's rotational inertia.
pub const PAYLOAD_INERTIA: u16 = 7;

/// The struct fields of the run-time parameters, in the order of their leaves.
pub const FIELDS: [Field; 4] = [
    Field {
        name: "gravity",
        first: GRAVITY,
        len: 3,
        gravity: true,
        doc: "The gravity vector `g` in the base frame {0} (m/s²).",
    },
    Field {
        name: "payload_mass",
        first: PAYLOAD_MASS,
        len: 1,
        gravity: false,
        doc: "The payload's mass (kg).",
    },
    Field {
        name: "payload_com",
        first: PAYLOAD_COM,
        len: 3,
        gravity: false,
        doc: "The payload's centre of mass in the frame of the link that carries it (m).",
    },
    Field {
        name: "payload_inertia",
        first: PAYLOAD_INERTIA,
        len: 6,
        gravity: false,
        doc: "The payload's rotational inertia about its centre of mass, in the axes of the link that carries it, `[xx, yy, zz, xy, xz, yz]` (kg·m²; `xy` is the product of inertia `I_xy`, not its negative).",
    },
];

/// The fields `robot` has (none without run-time parameters).
pub fn fields(robot: &Robot) -> Vec<Field> {
    FIELDS
        .iter()
        .filter(|f| {
            if f.gravity {
                robot.runtime.gravity
            } else {
                robot.runtime.payload.is_some()
            }
        })
        .copied()
        .collect()
}

/// The default value of every leaf (the robot's gravity, no payload), by leaf index.
pub fn defaults(robot: &Robot) -> [f64; 13] {
    let mut v = [0.0; 13];
    v[..3].copy_from_slice(robot.gravity.as_slice());
    v
}

/// Leaf `k` of the run-time parameters.
pub fn leaf(g: &mut ExprGraph, k: u16) -> ExprId {
    g.input(Input::new(PARAM, k))
}

fn leaves<const N: usize>(g: &mut ExprGraph, first: u16) -> [ExprId; N] {
    std::array::from_fn(|k| leaf(g, first + k as u16))
}

/// Gravity in {0}: the run-time parameter or the folded constant.
pub fn gravity(g: &mut ExprGraph, frames: &JointFrames) -> V3 {
    if frames.runtime_gravity {
        leaves(g, GRAVITY)
    } else {
        g.const3(frames.gravity)
    }
}

/// Link i's inertia in {J_i}: its constant inertia, plus the payload's when it carries it.
pub fn link_inertia(g: &mut ExprGraph, frame: &JointFrame) -> Inertia {
    let own = Inertia::constant(g, &frame.inertia);
    match &frame.payload {
        None => own,
        Some(pose) => {
            let payload = payload_inertia(g, pose);
            Inertia::add(g, &own, &payload)
        }
    }
}

/// The payload's inertia in the joint frame whose pose in the payload's link frame is
/// `pose` (see the module docs).
pub fn payload_inertia(g: &mut ExprGraph, pose: &PayloadPose) -> Inertia {
    let m = leaf(g, PAYLOAD_MASS);
    let c_p: V3 = leaves(g, PAYLOAD_COM);
    let i_p: [ExprId; 6] = leaves(g, PAYLOAD_INERTIA);
    let p = g.const3(pose.p);
    let d = g.sub3(c_p, p);
    // Rotated together: `h` carries c − p to Rᵀ (c − p), `i` becomes Rᵀ I_p R.
    let rotated = rotate_inertia_const(g, &pose.r, &Inertia { m, h: d, i: i_p });
    let c = rotated.h;
    let h = g.scale3(m, c);
    Inertia {
        m,
        h,
        i: about_origin(g, rotated.i, h, c),
    }
}

/// `I_c + m (c·c 1 − c cᵀ)` with `h = m c`, as `[xx, yy, zz, xy, xz, yz]`.
fn about_origin(g: &mut ExprGraph, i_c: [ExprId; 6], h: V3, c: V3) -> [ExprId; 6] {
    let hc: [[ExprId; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| g.mul(h[a], c[b])));
    let diag = |g: &mut ExprGraph, a: usize, b: usize, x: ExprId| {
        let s = g.add(hc[a][a], hc[b][b]);
        g.add(x, s)
    };
    let off = |g: &mut ExprGraph, a: usize, b: usize, x: ExprId| g.sub(x, hc[a][b]);
    [
        diag(g, 1, 2, i_c[0]),
        diag(g, 0, 2, i_c[1]),
        diag(g, 0, 1, i_c[2]),
        off(g, 0, 1, i_c[3]),
        off(g, 0, 2, i_c[4]),
        off(g, 1, 2, i_c[5]),
    ]
}

/// The payload's ten standard parameters in its link's frame {i}, in the order of
/// [`super::regressor::PARAMETER_NAMES`]: `m`, `m c`, then `I` about the origin of {i}
/// (`I_xx, I_xy, I_yy, I_xz, I_yz, I_zz`).
pub fn payload_standard_parameters(g: &mut ExprGraph) -> [ExprId; 10] {
    let m = leaf(g, PAYLOAD_MASS);
    let c: V3 = leaves(g, PAYLOAD_COM);
    let i_p: [ExprId; 6] = leaves(g, PAYLOAD_INERTIA);
    let h = g.scale3(m, c);
    let [xx, yy, zz, xy, xz, yz] = about_origin(g, i_p, h, c);
    [m, h[0], h[1], h[2], xx, xy, yy, xz, yz, zz]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expand::frames::BodyInertia;
    use dynamics_model::lie::rp_to_trans;
    use dynamics_model::{JointKind, SpatialInertia};
    use nalgebra::{Matrix3, Rotation3, Vector3};

    /// The payload's inertia in {J} from the graph equals the spatial inertia of the same
    /// body transformed numerically (`SpatialInertia::transform_by`).
    #[test]
    fn payload_inertia_is_the_transformed_body() {
        let rot = Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        let p = Vector3::new(0.1, -0.25, 0.4);
        let t_link_joint = rp_to_trans(&rot, &p);
        let rows: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| rot[(a, b)]));
        let frame = JointFrame {
            kind: JointKind::Revolute,
            parent: None,
            r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            p: [0.0; 3],
            inertia: BodyInertia {
                m: 0.0,
                h: [0.0; 3],
                i: [0.0; 6],
            },
            offset: 0.0,
            armature: 0.0,
            payload: Some(PayloadPose {
                r: rows,
                p: [p[0], p[1], p[2]],
            }),
        };
        let mut g = ExprGraph::new();
        let ib = link_inertia(&mut g, &frame);
        let (m, c) = (2.5, Vector3::new(0.05, 0.2, -0.1));
        let i_c = Matrix3::new(0.3, 0.01, -0.02, 0.01, 0.2, 0.03, -0.02, 0.03, 0.25);
        let values = [
            0.0, 0.0, 0.0, m, c[0], c[1], c[2], 0.3, 0.2, 0.25, 0.01, -0.02, 0.03,
        ];
        let outputs: Vec<ExprId> = [ib.m].into_iter().chain(ib.h).chain(ib.i).collect();
        let got = g.eval(&outputs, &|x: Input| {
            assert_eq!(x.group, PARAM);
            values[x.index as usize]
        });
        let body = SpatialInertia::from_com_frame(m, i_c, &rp_to_trans(&Matrix3::identity(), &c))
            .transform_by(&t_link_joint);
        let want = BodyInertia::from_spatial(&body);
        let want: Vec<f64> = [want.m].into_iter().chain(want.h).chain(want.i).collect();
        for (a, b) in got.iter().zip(&want) {
            assert!((a - b).abs() < 1e-14, "{got:?} != {want:?}");
        }
    }
}
