//! Inverse dynamics by the recursive Newton–Euler algorithm (Modern Robotics §8.3.2, eqs. 8.50–8.56).

use crate::chain::ChainFrames;
use crate::check;
use dynamics_model::lie::{ad, twist};
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `τ = M(θ) θ̈ + c(θ, θ̇) + g(θ) + J_b(θ)ᵀ F_tip` by the recursive Newton–Euler algorithm,
/// exactly the book's `InverseDynamics`.
///
/// Initialisation: `V_0 = 0`, `V̇_0 = (0, −g)` (gravity as an upward base acceleration),
/// `F_{n+1} = F_tip`. With `A_i` and `T_{i,i−1}` of [`ChainFrames`]:
///
/// Forward pass, i = 1..n:
/// ```text
/// V_i = [Ad_{T_{i,i−1}}] V_{i−1} + A_i θ̇_i                                   (8.51)
/// V̇_i = [Ad_{T_{i,i−1}}] V̇_{i−1} + [ad_{V_i}] A_i θ̇_i + A_i θ̈_i             (8.52)
/// ```
/// Backward pass, i = n..1:
/// ```text
/// F_i = [Ad_{T_{i+1,i}}]ᵀ F_{i+1} + G_i V̇_i − [ad_{V_i}]ᵀ G_i V_i             (8.53)
/// τ_i = F_iᵀ A_i                                                              (8.54)
/// ```
///
/// `gravity` is the gravity vector in {0}; `f_tip` is the wrench `(m, f)` the end effector
/// applies to the environment, in {n+1}.
///
/// # Panics
/// If `q`, `qd` or `qdd` does not have `robot.dof()` entries.
pub fn inverse_dynamics(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: &Vector3<f64>,
    f_tip: &Vector6<f64>,
) -> DVector<f64> {
    check::joint_vector(robot, "qd", qd);
    check::joint_vector(robot, "qdd", qdd);
    let n = robot.dof();
    let chain = ChainFrames::new(robot, q);
    let a = &chain.a;
    let ad_t_i_im1 = &chain.ad_t_i_im1;
    let g_list = robot.g_list();

    // v_i[i] = V_i and vd_i[i] = V̇_i for i = 0..n (index 0 is the base frame {0}).
    let mut v_i = vec![Vector6::zeros(); n + 1];
    let mut vd_i = vec![Vector6::zeros(); n + 1];
    vd_i[0] = twist(&Vector3::zeros(), &(-gravity));

    // Forward pass: twists and accelerations, root to tip.
    for i in 0..n {
        v_i[i + 1] = ad_t_i_im1[i] * v_i[i] + a[i] * qd[i];
        vd_i[i + 1] = ad_t_i_im1[i] * vd_i[i] + ad(&v_i[i + 1]) * a[i] * qd[i] + a[i] * qdd[i];
    }

    // Backward pass: wrenches, tip to root. f_i starts as F_{n+1} = F_tip.
    let mut tau = DVector::zeros(n);
    let mut f_i = *f_tip;
    for i in (0..n).rev() {
        f_i = ad_t_i_im1[i + 1].transpose() * f_i + g_list[i] * vd_i[i + 1]
            - ad(&v_i[i + 1]).transpose() * (g_list[i] * v_i[i + 1]);
        tau[i] = f_i.dot(&a[i]);
    }
    tau
}
