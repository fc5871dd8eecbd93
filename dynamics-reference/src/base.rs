//! The floating base's part of q and ν (see the crate docs of [`dynamics_model`], "Floating
//! base"): its pose from `q = (p, quat, θ)` and the split of ν into base twist and joint rates.

use dynamics_model::lie::rp_to_trans;
use dynamics_model::Robot;
use nalgebra::{Matrix3, Matrix4, Vector3, Vector6};

/// `R(quat)` for `quat = (x, y, z, w)`, scalar last, normalised here (`quat / |quat|`), so any
/// nonzero 4-vector gives a rotation:
/// ```text
/// R = [[1−2(y²+z²), 2(xy−zw),   2(xz+yw)  ],
///      [2(xy+zw),   1−2(x²+z²), 2(yz−xw)  ],
///      [2(xz−yw),   2(yz+xw),   1−2(x²+y²)]]
/// ```
/// `R` maps base-frame vectors into {0}.
///
/// # Panics
/// If `quat` is zero or not finite.
pub fn quaternion_rotation(quat: &[f64; 4]) -> Matrix3<f64> {
    let norm = quat.iter().map(|c| c * c).sum::<f64>().sqrt();
    assert!(
        norm > 0.0 && norm.is_finite(),
        "dynamics-reference: the base quaternion {quat:?} is zero or not finite; pass (x, y, z, w) with w = 1 for no rotation"
    );
    let [x, y, z, w] = quat.map(|c| c / norm);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - z * w),
        2.0 * (x * z + y * w),
        2.0 * (x * y + z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - x * w),
        2.0 * (x * z - y * w),
        2.0 * (y * z + x * w),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// `T_{0b} = [[R(quat), p], [0, 1]]`, the pose of the base in {0}, from the first seven entries
/// of `q`; the identity for a fixed base (whose frame is {0}).
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or the quaternion is zero.
pub fn base_pose(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    crate::check::configuration(robot, "q", q);
    if !robot.base.floating {
        return Matrix4::identity();
    }
    let p = Vector3::new(q[0], q[1], q[2]);
    rp_to_trans(&quaternion_rotation(&[q[3], q[4], q[5], q[6]]), &p)
}

/// The joint values θ: `q` without the base's seven entries.
pub(crate) fn joint_values<'a>(robot: &Robot, q: &'a [f64]) -> &'a [f64] {
    &q[robot.nq() - robot.n_coordinates()..]
}

/// The joint entries of a velocity-like vector (ν, ν̇, τ): without the base's six entries.
pub(crate) fn joint_part<'a>(robot: &Robot, x: &'a [f64]) -> &'a [f64] {
    &x[robot.nv() - robot.n_coordinates()..]
}

/// The base's six entries of a velocity-like vector (angular first); zero for a fixed base.
pub(crate) fn base_part(robot: &Robot, x: &[f64]) -> Vector6<f64> {
    if robot.base.floating {
        Vector6::from_column_slice(&x[..6])
    } else {
        Vector6::zeros()
    }
}

/// The offset of joint 0 in ν: 6 on a floating base, 0 on a fixed one.
pub(crate) fn joint_offset(robot: &Robot) -> usize {
    robot.nv() - robot.n_coordinates()
}
