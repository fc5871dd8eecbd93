//! The mass matrix by the composite-rigid-body algorithm (CRBA), from the quantities of the
//! Newton–Euler recursion (Modern Robotics §8.3.2 and §8.4), on a kinematic tree.

use crate::base::joint_offset;
use crate::coupling::Coupled;
use crate::frames::TreeFrames;
use dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix6};

/// `M(q)`, the nv×nv mass matrix, by the composite-rigid-body algorithm.
///
/// Column j of `M` is the force `ID(q, 0, e_j)` with no gravity and no tip wrench: a unit
/// acceleration of joint j accelerates the subtree of link j rigidly. Its inertias, gathered
/// in frame {i}, form the composite inertia (leaves to root, each carried into its parent)
/// ```text
/// Ic_i = G_i + Σ_{k: λ(k) = i} [Ad_{T_{k,i}}]ᵀ Ic_k [Ad_{T_{k,i}}]
/// ```
/// so joint i's unit acceleration needs the wrench `F = Ic_i A_i` on the subtree, and carried
/// down the path to the base, to each ancestor j of i, by `F ← [Ad_{T_{k,λ(k)}}]ᵀ F`:
/// ```text
/// M_ii = A_iᵀ Ic_i A_i,    M_ji = M_ij = A_jᵀ F    (j an ancestor of i)
/// ```
/// and `M_ij = 0` when neither of i, j is on the other's path to the base (exactly 0.0).
///
/// Floating base (body 0, whose "screw axes" are the six unit twists): `Ic_0 = G_b + Σ_{roots}
/// …` is the composite inertia of the whole robot in the base frame, and
/// ```text
/// M[0..6, 0..6] = Ic_0,    M[0..6, j] = F carried to the base frame (every joint j)
/// ```
///
/// Armature (Modern Robotics §8.9.2): each joint's reflected rotor inertia
/// `G_i² I_rotor,i` ([`dynamics_model::Joint::armature`]) is added to its own diagonal entry,
/// ```text
/// M_ii += G_i² I_rotor,i
/// ```
/// (joint entries only; on a robot with mimic joints at the physical level, before the
/// projection `Jᵀ M J`, so a follower's rotor also loads its leader). It is constant, so Ṁ,
/// C and the Christoffel symbols do not change.
///
/// On a serial chain without armature this equals `AᵀLᵀGLA` of the closed form (8.57) and the
/// book's `MassMatrix` (n Newton–Euler calls); it is symmetric by construction.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries.
pub fn mass_matrix(robot: &Robot, q: &[f64]) -> DMatrix<f64> {
    if let Some(c) = Coupled::of(robot) {
        crate::check::configuration(robot, "q", q);
        return c.matrix(&mass_matrix(&c.physical, &c.q(q)));
    }
    let n = robot.dof();
    let frames = TreeFrames::new(robot, q);
    let a = &frames.a;
    let ad_t_i_parent = &frames.ad_t_i_parent;
    let off = joint_offset(robot);

    // ic[i] = Ic_{i+1}: composite inertia of link i's subtree in its frame (0-based i);
    // ic_base = Ic_0, the whole robot in the base frame (used on a floating base).
    let mut ic = robot.g_list();
    let mut ic_base = robot.base.inertia.0;
    for i in (0..n).rev() {
        let x = &ad_t_i_parent[i];
        let carried = x.transpose() * ic[i] * x;
        match frames.parent[i] {
            Some(p) => ic[p] += carried,
            None => ic_base += carried,
        }
    }

    let mut m = DMatrix::zeros(robot.nv(), robot.nv());
    for i in 0..n {
        // f: the wrench on the subtree for a unit acceleration of joint i, in the frame of
        // the link reached so far on the way to the base.
        let mut f = ic[i] * a[i];
        m[(off + i, off + i)] = a[i].dot(&f) + robot.joints[i].armature();
        let mut k = i;
        while let Some(j) = frames.parent[k] {
            f = ad_t_i_parent[k].transpose() * f;
            m[(off + i, off + j)] = a[j].dot(&f);
            m[(off + j, off + i)] = m[(off + i, off + j)];
            k = j;
        }
        if robot.base.floating {
            f = ad_t_i_parent[k].transpose() * f;
            for r in 0..6 {
                m[(r, off + i)] = f[r];
                m[(off + i, r)] = f[r];
            }
        }
    }
    if robot.base.floating {
        let ic_base = symmetric(&ic_base);
        m.view_mut((0, 0), (6, 6)).copy_from(&ic_base);
    }
    m
}

/// `(X + Xᵀ)/2`, so that `M` is exactly symmetric also in its base block.
fn symmetric(x: &Matrix6<f64>) -> Matrix6<f64> {
    (x + x.transpose()) * 0.5
}
