//! The Coriolis matrix from the Christoffel symbols of the mass matrix (Modern Robotics
//! §8.1.2), with the Euler–Poincaré term of a floating base.

use crate::base::joint_offset;
use crate::check;
use crate::mass_matrix::mass_matrix;
use crate::mass_matrix_dot::mass_matrix_dot;
use dynamics_model::lie::skew;
use dynamics_model::Robot;
use nalgebra::{DMatrix, DVector, Matrix6, Vector3};

/// `∂M/∂q_k` along each velocity direction k = 1..nv (0-based), exactly: `Ṁ(q, e_k)` by the
/// closed form of [`mass_matrix_dot`] (Ṁ is linear in ν). No finite differences. On a
/// floating base the first six are zero: M, seen from the base frame, does not depend on
/// the base pose.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn mass_matrix_partials(robot: &Robot, q: &[f64]) -> Vec<DMatrix<f64>> {
    check::configuration(robot, "q", q);
    let nv = robot.nv();
    (0..nv)
        .map(|k| {
            if k < joint_offset(robot) {
                return DMatrix::zeros(nv, nv);
            }
            let mut e_k = vec![0.0; nv];
            e_k[k] = 1.0;
            mass_matrix_dot(robot, q, &e_k)
        })
        .collect()
}

/// `C(q, ν)` with the Christoffel symbols of the first kind:
/// ```text
/// C_ij = Σ_k Γ_ijk ν_k,    Γ_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i)
/// ```
/// With this choice `c(q, ν) = C ν` and `Ṁ − 2C` is skew-symmetric (§8.1.2, Proposition 8.1).
///
/// On a floating base the base twist ν_b is a body twist, not the derivative of coordinates,
/// and M does not depend on the base pose (`∂M/∂q_k = 0` for the base directions): the
/// Christoffel part gives the joint rows of c and the `Ṁ ν` part of the base rows, and the base
/// rows of the equations of motion (Euler–Poincaré on SE(3)) add `−[ad_{ν_b}]ᵀ h_b`, with
/// `h_b = M[0..6, ·] ν` the robot's spatial momentum in the base frame. Since
/// `[ad_V]ᵀ h = H(h) V` with the skew-symmetric
/// ```text
/// H(h) = [[ [h_ω], [h_f] ],
///         [ [h_f],   0   ]]       for h = (h_ω, h_f),
/// ```
/// C gets `−H(h_b)` in its base block: still `c = C ν`, and `Ṁ − 2C` stays skew-symmetric.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` not `robot.nv()`.
pub fn coriolis_matrix(robot: &Robot, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    check::velocity(robot, "qd", qd);
    let nv = robot.nv();
    let dm = mass_matrix_partials(robot, q); // dm[k] = ∂M/∂q_k
    let mut c = DMatrix::zeros(nv, nv);
    for i in 0..nv {
        for j in 0..nv {
            for k in 0..nv {
                let gamma_ijk = 0.5 * (dm[k][(i, j)] + dm[j][(i, k)] - dm[i][(j, k)]);
                c[(i, j)] += gamma_ijk * qd[k];
            }
        }
    }
    if robot.base.floating {
        let h_b = mass_matrix(robot, q).rows(0, 6) * DVector::from_column_slice(qd);
        let h = momentum_cross(
            &Vector3::new(h_b[0], h_b[1], h_b[2]),
            &Vector3::new(h_b[3], h_b[4], h_b[5]),
        );
        let mut base = c.view_mut((0, 0), (6, 6));
        base -= h;
    }
    c
}

/// `H(h)`, with `H(h) V = [ad_V]ᵀ h` for every twist V; skew-symmetric.
fn momentum_cross(h_w: &Vector3<f64>, h_f: &Vector3<f64>) -> Matrix6<f64> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&skew(h_w));
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&skew(h_f));
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew(h_f));
    m
}
