//! Spatial inertias (Modern Robotics §8.2) and the inertias of primitive solids (Exercise 8.1).
//!
//! A spatial inertia in a frame {b} at the centre of mass is `G_b = [[I_b, 0], [0, m·1₃]]`.
//! In any other frame {a} it is `G_a = [Ad_{T_ba}]ᵀ G_b [Ad_{T_ba}]` (Exercise 8.3), which
//! has the blocks `[[I_a, m[c]], [m[c]ᵀ, m·1₃]]` with `c` the centre of mass in {a} and
//! `I_a = R_baᵀ I_b R_ba + m(cᵀc·1₃ − c cᵀ)` (Steiner's theorem when `R_ba = 1`).
//!
//! Bodies rigidly joined are combined by expressing each in a common frame and adding the
//! 6×6 matrices (Exercise 8.2, the dumbbell).

use crate::lie::{adjoint, skew, trans_inv};
use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3};

/// A 6×6 spatial inertia `G` in some frame, acting on twists `(ω, v)` to give momenta `(m, f)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialInertia(pub Matrix6<f64>);

impl SpatialInertia {
    /// The zero inertia of a massless body.
    pub fn zero() -> Self {
        Self(Matrix6::zeros())
    }

    /// `G = [[I, 0], [0, m·1₃]]`: mass `m` and rotational inertia `I` about the centre of
    /// mass, in a frame at the centre of mass.
    pub fn at_com(mass: f64, inertia: Matrix3<f64>) -> Self {
        let mut g = Matrix6::zeros();
        g.fixed_view_mut::<3, 3>(0, 0).copy_from(&inertia);
        g.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * mass));
        Self(g)
    }

    /// A body of mass `m` and rotational inertia `I` about its centre of mass, given in a
    /// COM frame {c} whose pose in the target frame {a} is `T_ac`; the result is `G_a`.
    pub fn from_com_frame(mass: f64, inertia: Matrix3<f64>, t_ac: &Matrix4<f64>) -> Self {
        Self::at_com(mass, inertia).expressed_in(t_ac)
    }

    /// `G_a = [Ad_{T_ca}]ᵀ G_c [Ad_{T_ca}]` where `self` is `G_c` and `t_ac` is the pose of
    /// {c} in {a} (Exercise 8.3 with `T_ca = T_ac⁻¹`).
    pub fn expressed_in(&self, t_ac: &Matrix4<f64>) -> Self {
        let ad = adjoint(&trans_inv(t_ac));
        let g = ad.transpose() * self.0 * ad;
        Self(symmetrize(&g))
    }

    /// `G_a = [Ad_{T_ba}]ᵀ G_b [Ad_{T_ba}]`, with `t_ba` the pose of {a} seen from {b}
    /// (the book's form of Exercise 8.3).
    pub fn transform_by(&self, t_ba: &Matrix4<f64>) -> Self {
        let ad = adjoint(t_ba);
        Self(symmetrize(&(ad.transpose() * self.0 * ad)))
    }

    /// The total mass `m` (the lower-right block is `m·1₃`).
    pub fn mass(&self) -> f64 {
        self.0[(3, 3)]
    }

    /// The centre of mass `c` in this frame, from the off-diagonal block `m[c]`
    /// (zero for a massless body).
    pub fn com(&self) -> Vector3<f64> {
        let m = self.mass();
        if m == 0.0 {
            return Vector3::zeros();
        }
        // The upper-right block is m[c] with [c] = [[0, −c_z, c_y], [c_z, 0, −c_x], [−c_y, c_x, 0]].
        let b = self.0.fixed_view::<3, 3>(0, 3);
        Vector3::new(b[(2, 1)], b[(0, 2)], b[(1, 0)]) / m
    }

    /// The rotational inertia about this frame's origin (the upper-left block).
    pub fn rotational(&self) -> Matrix3<f64> {
        self.0.fixed_view::<3, 3>(0, 0).into_owned()
    }

    /// The rotational inertia about the centre of mass, in this frame's axes:
    /// `I_c = I_a − m(cᵀc·1₃ − c cᵀ)`.
    pub fn rotational_about_com(&self) -> Matrix3<f64> {
        let m = self.mass();
        let c = self.com();
        self.rotational() - steiner(m, &c)
    }
}

impl core::ops::Add for SpatialInertia {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self(self.0 + rhs.0)
    }
}

/// `m(cᵀc·1₃ − c cᵀ) = −m[c][c]`: the parallel-axis (Steiner) term for an offset `c`.
pub fn steiner(mass: f64, c: &Vector3<f64>) -> Matrix3<f64> {
    let sc = skew(c);
    -(sc * sc) * mass
}

fn symmetrize(g: &Matrix6<f64>) -> Matrix6<f64> {
    (g + g.transpose()) * 0.5
}

/// Rotational inertias of homogeneous primitive solids about their centre of mass, with
/// the axes along the symmetry axes (Exercise 8.1). Each returns the diagonal `(Ixx, Iyy, Izz)`.
pub mod primitive {
    use nalgebra::Vector3;

    /// Box with edge `w` along x, `l` along y, `h` along z: `m(l²+h²)/12, m(w²+h²)/12, m(w²+l²)/12`.
    pub fn cuboid(mass: f64, w: f64, l: f64, h: f64) -> Vector3<f64> {
        Vector3::new(
            mass * (l * l + h * h) / 12.0,
            mass * (w * w + h * h) / 12.0,
            mass * (w * w + l * l) / 12.0,
        )
    }

    /// Solid cylinder of radius `r`, height `h`, axis z: `m(3r²+h²)/12, m(3r²+h²)/12, m r²/2`.
    pub fn cylinder(mass: f64, r: f64, h: f64) -> Vector3<f64> {
        let ixx = mass * (3.0 * r * r + h * h) / 12.0;
        Vector3::new(ixx, ixx, mass * r * r / 2.0)
    }

    /// Solid sphere of radius `r`: `2 m r²/5` about every axis.
    pub fn sphere(mass: f64, r: f64) -> Vector3<f64> {
        let i = 2.0 * mass * r * r / 5.0;
        Vector3::new(i, i, i)
    }

    /// Solid ellipsoid with semi-axes `a` (x), `b` (y), `c` (z): `m(b²+c²)/5, m(a²+c²)/5, m(a²+b²)/5`.
    pub fn ellipsoid(mass: f64, a: f64, b: f64, c: f64) -> Vector3<f64> {
        Vector3::new(
            mass * (b * b + c * c) / 5.0,
            mass * (a * a + c * c) / 5.0,
            mass * (a * a + b * b) / 5.0,
        )
    }

    /// Thin rectangular plate with edge `w` along x, `l` along y, normal z:
    /// `m l²/12, m w²/12, m(w²+l²)/12`.
    pub fn plate(mass: f64, w: f64, l: f64) -> Vector3<f64> {
        Vector3::new(
            mass * l * l / 12.0,
            mass * w * w / 12.0,
            mass * (w * w + l * l) / 12.0,
        )
    }

    /// Thin disc of radius `r`, normal z: `m r²/4, m r²/4, m r²/2`.
    pub fn disc(mass: f64, r: f64) -> Vector3<f64> {
        Vector3::new(mass * r * r / 4.0, mass * r * r / 4.0, mass * r * r / 2.0)
    }

    /// Volume of a box.
    pub fn cuboid_volume(w: f64, l: f64, h: f64) -> f64 {
        w * l * h
    }

    /// Volume of a solid cylinder.
    pub fn cylinder_volume(r: f64, h: f64) -> f64 {
        core::f64::consts::PI * r * r * h
    }

    /// Volume of a sphere.
    pub fn sphere_volume(r: f64) -> f64 {
        4.0 / 3.0 * core::f64::consts::PI * r * r * r
    }

    /// Volume of an ellipsoid.
    pub fn ellipsoid_volume(a: f64, b: f64, c: f64) -> f64 {
        4.0 / 3.0 * core::f64::consts::PI * a * b * c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::rp_to_trans;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    #[test]
    fn primitives_match_seed_cases() {
        let b = primitive::cuboid(6.0, 0.3, 0.2, 0.1);
        assert!(close(b[0], 0.025) && close(b[1], 0.05) && close(b[2], 0.065));
        let c = primitive::cylinder(5.0, 0.1, 0.4);
        assert!(close(c[0], 0.95 / 12.0) && close(c[2], 0.025));
        let e = primitive::ellipsoid(2.0, 0.3, 0.2, 0.1);
        assert!(close(e[0], 0.02) && close(e[1], 0.04) && close(e[2], 0.052));
        let s = primitive::sphere(2.0, 0.1);
        assert!(close(s[0], 0.008));
    }

    #[test]
    fn spatial_transform_seed_case_8_3() {
        let ib = Matrix3::new(0.05, 0.002, -0.001, 0.002, 0.04, 0.003, -0.001, 0.003, 0.03);
        let gb = SpatialInertia::at_com(2.5, ib);
        let r_ba = Matrix3::new(-0.6, -0.48, 0.64, 0.8, -0.36, 0.48, 0.0, 0.8, 0.6);
        let t_ba = rp_to_trans(&r_ba, &Vector3::new(0.1, -0.2, 0.3));
        let ga = gb.transform_by(&t_ba);
        let want = [
            [0.27068, 0.150144, 0.079808, 0.0, 0.37, -0.66],
            [0.150144, 0.2113952, -0.1061936, -0.37, 0.0, -0.55],
            [0.079808, -0.1061936, 0.3379248, 0.66, 0.55, 0.0],
            [0.0, -0.37, 0.66, 2.5, 0.0, 0.0],
            [0.37, 0.0, 0.55, 0.0, 2.5, 0.0],
            [-0.66, -0.55, 0.0, 0.0, 0.0, 2.5],
        ];
        for i in 0..6 {
            for j in 0..6 {
                assert!((ga.0[(i, j)] - want[i][j]).abs() < 1e-14, "{i},{j}");
            }
        }
        assert!((ga.com() - Vector3::new(0.22, -0.264, -0.148)).amax() < 1e-14);
        // Same result through the pose of {b} in {a}.
        let gc = gb.expressed_in(&trans_inv(&t_ba));
        assert!((gc.0 - ga.0).amax() < 1e-14);
        assert!((ga.rotational_about_com() - r_ba.transpose() * ib * r_ba).amax() < 1e-14);
    }
}
