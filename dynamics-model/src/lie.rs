//! Numeric Lie-group helpers in Modern Robotics notation (chapter 3).
//!
//! Twists and screw axes are `(ω, v)`, wrenches `(m, f)`; homogeneous transforms are 4×4
//! matrices `T = [[R, p], [0, 1]]`.
//!
//! - `[Ad_T] = [[R, 0], [[p]R, R]]`
//! - `[ad_V] = [[[ω], 0], [[v], [ω]]]`
//! - `e^{[S]θ}`: Rodrigues' formula for the rotation, `G(θ) v` for the translation.

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};

/// Tolerance used to decide that a rotation axis is zero (pure translation) in [`exp6`].
pub const EXP_ZERO_TOL: f64 = 1e-12;

/// `[x]`: the 3×3 skew-symmetric matrix with `[x] y = x × y`.
pub fn skew(x: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -x[2], x[1], x[2], 0.0, -x[0], -x[1], x[0], 0.0)
}

/// The rotation part `R` of a homogeneous transform.
pub fn rotation(t: &Matrix4<f64>) -> Matrix3<f64> {
    t.fixed_view::<3, 3>(0, 0).into_owned()
}

/// The translation part `p` of a homogeneous transform.
pub fn translation(t: &Matrix4<f64>) -> Vector3<f64> {
    t.fixed_view::<3, 1>(0, 3).into_owned()
}

/// Builds `T = [[R, p], [0, 1]]`.
pub fn rp_to_trans(r: &Matrix3<f64>, p: &Vector3<f64>) -> Matrix4<f64> {
    let mut t = Matrix4::identity();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    t.fixed_view_mut::<3, 1>(0, 3).copy_from(p);
    t
}

/// `T⁻¹ = [[Rᵀ, −Rᵀp], [0, 1]]` (exact for rigid transforms, no general inverse).
pub fn trans_inv(t: &Matrix4<f64>) -> Matrix4<f64> {
    let r = rotation(t);
    let p = translation(t);
    let rt = r.transpose();
    rp_to_trans(&rt, &(-(rt * p)))
}

/// `[Ad_T] = [[R, 0], [[p]R, R]]`: maps a twist in frame {b} to frame {a} for `T = T_ab`.
pub fn adjoint(t: &Matrix4<f64>) -> Matrix6<f64> {
    let r = rotation(t);
    let p = translation(t);
    let mut ad = Matrix6::zeros();
    ad.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    ad.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    ad.fixed_view_mut::<3, 3>(3, 0).copy_from(&(skew(&p) * r));
    ad
}

/// `[ad_V] = [[[ω], 0], [[v], [ω]]]`, the Lie bracket `[ad_V] W = [V, W]`.
pub fn ad(v: &Vector6<f64>) -> Matrix6<f64> {
    let w = Vector3::new(v[0], v[1], v[2]);
    let lin = Vector3::new(v[3], v[4], v[5]);
    let mut m = Matrix6::zeros();
    let sw = skew(&w);
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&sw);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&sw);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew(&lin));
    m
}

/// The angular part ω of a twist or screw.
pub fn angular(v: &Vector6<f64>) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

/// The linear part v of a twist or screw (or the force part f of a wrench).
pub fn linear(v: &Vector6<f64>) -> Vector3<f64> {
    Vector3::new(v[3], v[4], v[5])
}

/// Joins an angular and a linear part into a 6-vector `(ω, v)`.
pub fn twist(w: &Vector3<f64>, v: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(w[0], w[1], w[2], v[0], v[1], v[2])
}

/// `e^{[S]θ}` for a screw axis `S = (ω, v)` and a joint value θ (MR eq. 3.88).
///
/// Works for any `ω` (the book's `MatrixExp6` normalises by `|ω|θ`, so a non-unit `ω`
/// is accepted as the library does); `ω = 0` gives the pure translation `v θ`.
pub fn exp6(s: &Vector6<f64>, theta: f64) -> Matrix4<f64> {
    let w = angular(s) * theta;
    let v = linear(s) * theta;
    let angle = w.norm();
    if angle < EXP_ZERO_TOL {
        return rp_to_trans(&Matrix3::identity(), &v);
    }
    let wn = skew(&(w / angle));
    let (s_a, c_a) = sin_cos(angle);
    let r = Matrix3::identity() + wn * s_a + wn * wn * (1.0 - c_a);
    let g = Matrix3::identity() * angle + wn * (1.0 - c_a) + wn * wn * (angle - s_a);
    rp_to_trans(&r, &(g * (v / angle)))
}

/// `(sin x, cos x)` through `libm`, so that the constants folded into generated code do not
/// depend on the host's math library.
pub fn sin_cos(x: f64) -> (f64, f64) {
    (libm::sin(x), libm::cos(x))
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)`, the URDF convention for `rpy`.
pub fn rpy_to_rotation(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    let (sr, cr) = sin_cos(roll);
    let (sp, cp) = sin_cos(pitch);
    let (sy, cy) = sin_cos(yaw);
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cr, -sr, 0.0, sr, cr);
    let ry = Matrix3::new(cp, 0.0, sp, 0.0, 1.0, 0.0, -sp, 0.0, cp);
    let rz = Matrix3::new(cy, -sy, 0.0, sy, cy, 0.0, 0.0, 0.0, 1.0);
    rz * ry * rx
}

/// The transform with translation `xyz` and rotation `rpy` (URDF `<origin>`).
pub fn xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Matrix4<f64> {
    rp_to_trans(
        &rpy_to_rotation(rpy[0], rpy[1], rpy[2]),
        &Vector3::new(xyz[0], xyz[1], xyz[2]),
    )
}

/// Whether `t` is a rigid transform: `RᵀR = 1` and `det R = 1` within `tol`, last row `(0,0,0,1)`.
pub fn is_rigid_transform(t: &Matrix4<f64>, tol: f64) -> bool {
    let r = rotation(t);
    let ortho = (r.transpose() * r - Matrix3::identity()).amax() <= tol;
    let det = (r.determinant() - 1.0).abs() <= tol;
    let last = t[(3, 0)] == 0.0 && t[(3, 1)] == 0.0 && t[(3, 2)] == 0.0 && t[(3, 3)] == 1.0;
    ortho && det && last && t.iter().all(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_identity_of_ad_seed_case() {
        // Exercise 8.5 of seed-cases.md.
        let v1 = Vector6::new(1.0, -2.0, 0.5, 0.3, 0.7, -1.1);
        let v2 = Vector6::new(0.2, 0.4, -0.6, 2.0, -1.0, 0.5);
        let v3 = Vector6::new(-0.3, 1.5, 0.9, -0.8, 0.1, 1.2);
        let a12 = ad(&v1) * v2;
        let want = Vector6::new(1.0, 0.7, 0.8, -0.48, 0.46, 2.98);
        assert!((a12 - want).amax() < 1e-14);
        let a1_23 = ad(&v1) * (ad(&v2) * v3);
        let want = Vector6::new(-0.84, 0.21, 2.52, -4.931, -5.107, -4.812);
        assert!((a1_23 - want).amax() < 1e-13);
        let sum = a1_23 + ad(&v3) * (ad(&v1) * v2) + ad(&v2) * (ad(&v3) * v1);
        assert!(sum.amax() < 1e-12);
    }

    #[test]
    fn exp6_matches_rotation_about_offset_axis() {
        // Revolute about z through (1, 0, 0): S = (0,0,1, 0,-1,0). A quarter turn maps the
        // origin to (1, -1, 0).
        let s = Vector6::new(0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
        let t = exp6(&s, std::f64::consts::FRAC_PI_2);
        assert!((translation(&t) - Vector3::new(1.0, -1.0, 0.0)).amax() < 1e-15);
        assert!(is_rigid_transform(&t, 1e-12));
        let inv = trans_inv(&t);
        assert!((inv * t - Matrix4::identity()).amax() < 1e-15);
    }

    #[test]
    fn adjoint_of_product_is_product_of_adjoints() {
        let a = xyz_rpy([0.1, -0.2, 0.3], [0.4, -0.5, 0.6]);
        let b = xyz_rpy([-0.7, 0.2, 0.9], [-1.1, 0.3, 2.0]);
        let lhs = adjoint(&(a * b));
        let rhs = adjoint(&a) * adjoint(&b);
        assert!((lhs - rhs).amax() < 1e-14);
    }
}
