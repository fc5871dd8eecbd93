//! URDF `<origin xyz rpy>` to a homogeneous transform, with right angles made exact.
//!
//! `T = [[R, p], [0, 1]]` with `p = xyz` and `R = Rz(yaw) Ry(pitch) Rx(roll)`.
//!
//! URDF files write right angles as decimals (`1.57079632679`, `3.14159265359`), and even the
//! exact double nearest π/2 has `cos = 6.1e-17`, not 0. Angles within [`SNAP_TOL`] of a
//! multiple of π/2 are therefore snapped to it, and their sine and cosine taken as exactly
//! 0 or ±1 ([`sin_cos_snapped`]), so that the UR5's frames are exact permutation matrices.

use crate::lie::{rp_to_trans, sin_cos};
use nalgebra::{Matrix3, Matrix4, Vector3};

/// Angles within this distance (rad) of a multiple of π/2 are taken as that multiple.
pub const SNAP_TOL: f64 = 1e-9;

/// `(sin a, cos a)`, exact (0 or ±1) when `a` is within [`SNAP_TOL`] of a multiple `k·π/2`.
///
/// Other angles go through [`crate::lie::sin_cos`] unchanged.
pub fn sin_cos_snapped(a: f64) -> (f64, f64) {
    let k = (a / core::f64::consts::FRAC_PI_2).round();
    // |k| < 2^52 keeps `k` an exact integer and the remainder meaningful.
    if k.abs() < 4.0e15 && (a - k * core::f64::consts::FRAC_PI_2).abs() <= SNAP_TOL {
        // k mod 4, in 0..4, for negative k too.
        match k.rem_euclid(4.0) as u8 {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        sin_cos(a)
    }
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)` with right angles exact (see [`sin_cos_snapped`]).
pub fn rpy_rotation(rpy: [f64; 3]) -> Matrix3<f64> {
    let (sr, cr) = sin_cos_snapped(rpy[0]);
    let (sp, cp) = sin_cos_snapped(rpy[1]);
    let (sy, cy) = sin_cos_snapped(rpy[2]);
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cr, -sr, 0.0, sr, cr);
    let ry = Matrix3::new(cp, 0.0, sp, 0.0, 1.0, 0.0, -sp, 0.0, cp);
    let rz = Matrix3::new(cy, -sy, 0.0, sy, cy, 0.0, 0.0, 0.0, 1.0);
    rz * ry * rx
}

/// `a` as exactly `k·π/2` when it is within `tol` of that multiple, otherwise unchanged.
pub fn snap_to_right_angle(a: f64, tol: f64) -> f64 {
    let k = (a / core::f64::consts::FRAC_PI_2).round();
    if k.abs() < 4.0e15 && (a - k * core::f64::consts::FRAC_PI_2).abs() <= tol {
        k * core::f64::consts::FRAC_PI_2
    } else {
        a
    }
}

/// An `rpy` angle of a URDF `<origin>` near a multiple of π/2 but not on it.
#[derive(Clone, Debug, PartialEq)]
pub struct NearRightAngle {
    /// Where: `joint `NAME`` or `link `NAME` inertial`.
    pub element: String,
    /// Which angle: 0 roll, 1 pitch, 2 yaw.
    pub index: usize,
    /// The angle as written (rad).
    pub value: f64,
    /// Its distance from the nearest multiple of π/2 (rad).
    pub distance: f64,
}

/// The `rpy` angles of every joint's and inertial's `<origin>` of `urdf` whose distance
/// from a multiple of π/2 is in `(above, up_to]`, in file order.
pub fn near_right_angles(urdf: &urdf_rs::Robot, above: f64, up_to: f64) -> Vec<NearRightAngle> {
    let origins = urdf
        .joints
        .iter()
        .map(|j| (format!("joint `{}`", j.name), &j.origin))
        .chain(
            urdf.links
                .iter()
                .map(|l| (format!("link `{}` inertial", l.name), &l.inertial.origin)),
        );
    let mut out = Vec::new();
    for (element, origin) in origins {
        for (index, &value) in origin.rpy.0.iter().enumerate() {
            let k = (value / core::f64::consts::FRAC_PI_2).round();
            let distance = (value - k * core::f64::consts::FRAC_PI_2).abs();
            if distance > above && distance <= up_to {
                out.push(NearRightAngle {
                    element: element.clone(),
                    index,
                    value,
                    distance,
                });
            }
        }
    }
    out
}

/// Every joint's and inertial's `rpy` angle within `tol` of a multiple of π/2 made that
/// multiple ([`snap_to_right_angle`]).
pub fn snap_rpy(urdf: &mut urdf_rs::Robot, tol: f64) {
    let origins = urdf
        .joints
        .iter_mut()
        .map(|j| &mut j.origin)
        .chain(urdf.links.iter_mut().map(|l| &mut l.inertial.origin));
    for origin in origins {
        for a in origin.rpy.0.iter_mut() {
            *a = snap_to_right_angle(*a, tol);
        }
    }
}

/// The transform of a URDF `<origin xyz rpy>`: `[[Rz(y) Ry(p) Rx(r), xyz], [0, 1]]`.
pub fn origin_transform(pose: &urdf_rs::Pose) -> Matrix4<f64> {
    let xyz = pose.xyz.0;
    rp_to_trans(
        &rpy_rotation(pose.rpy.0),
        &Vector3::new(xyz[0], xyz[1], xyz[2]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_2, PI};

    #[test]
    #[allow(clippy::approx_constant)] // the decimals UR5 files write for π/2 and π
    fn right_angles_are_exact() {
        assert_eq!(sin_cos_snapped(FRAC_PI_2), (1.0, 0.0));
        assert_eq!(sin_cos_snapped(1.57079632679), (1.0, 0.0));
        assert_eq!(sin_cos_snapped(-3.14159265359), (0.0, -1.0));
        assert_eq!(sin_cos_snapped(-FRAC_PI_2), (-1.0, 0.0));
        assert_eq!(sin_cos_snapped(2.0 * PI), (0.0, 1.0));
        assert_eq!(sin_cos_snapped(0.0), (0.0, 1.0));
    }

    #[test]
    fn other_angles_are_untouched() {
        let a = FRAC_PI_2 + 1e-6;
        assert_eq!(sin_cos_snapped(a), sin_cos(a));
        assert_eq!(sin_cos_snapped(0.3), sin_cos(0.3));
        let (s, c) = sin_cos_snapped(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }

    #[test]
    fn rpy_matches_the_general_formula() {
        let r = rpy_rotation([0.3, -0.4, 1.2]);
        let want = crate::lie::rpy_to_rotation(0.3, -0.4, 1.2);
        assert!((r - want).amax() < 1e-16);
        // Roll π/2: y → z.
        let r = rpy_rotation([FRAC_PI_2, 0.0, 0.0]);
        assert_eq!(r * Vector3::y(), Vector3::z());
    }
}
