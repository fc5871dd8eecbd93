//! Inverse dynamics by the recursive Newton–Euler algorithm (Modern Robotics §8.3.2, eqs.
//! 8.50–8.56), on a kinematic tree (Featherstone's RNEA in the book's notation).

use crate::base::{base_part, joint_offset, joint_part};
use crate::check;
use crate::coupling::Coupled;
use crate::frames::TreeFrames;
use dynamics_model::lie::{ad, rotation, twist};
use dynamics_model::Robot;
use nalgebra::{DVector, Vector3, Vector6};

/// `τ = M(q) ν̇ + c(q, ν) + g(q) + J_b(q)ᵀ F_tip` by the recursive Newton–Euler algorithm; on a
/// serial chain exactly the book's `InverseDynamics`.
///
/// Initialisation, base (body 0): on a fixed base `V_0 = 0`, `V̇_0 = (0, −g)` (gravity as an
/// upward base acceleration); on a floating base, with `R` the base orientation,
/// ```text
/// V_0 = ν_b,    V̇_0 = ν̇_b + (0, −Rᵀ g)
/// ```
/// With `A_i`, `λ(i)` and `T_{i,λ(i)}` of [`TreeFrames`]:
///
/// Forward pass, i = 1..n (parents before children):
/// ```text
/// V_i = [Ad_{T_{i,λ(i)}}] V_{λ(i)} + A_i θ̇_i                                     (8.51)
/// V̇_i = [Ad_{T_{i,λ(i)}}] V̇_{λ(i)} + [ad_{V_i}] A_i θ̇_i + A_i θ̈_i               (8.52)
/// ```
/// Backward pass, i = n..1, each link's wrench carried into its parent's sum (the tip wrench
/// `F_tip`, in {n+1}, into the end effector's link first):
/// ```text
/// F_i = Σ_{k: λ(k) = i} [Ad_{T_{k,i}}]ᵀ F_k + G_i V̇_i − [ad_{V_i}]ᵀ G_i V_i       (8.53)
/// τ_i = F_iᵀ A_i + G_i² I_rotor,i θ̈_i                                              (8.54)
/// ```
/// where `G_i² I_rotor,i` is joint i's armature ([`dynamics_model::Joint::armature`], the
/// rotor inertia reflected through the gear, §8.9.2; zero without a rotor), the diagonal term
/// [`crate::mass_matrix`] adds to `M_ii`. Friction is not included: add
/// [`crate::friction_forces`] for the torque that also overcomes it.
/// Floating base: `τ[0..6] = F_0`, the same sum for the base body with its own inertia `G_b`
/// ([`dynamics_model::Base::inertia`]): the wrench the base needs, in the base frame.
///
/// `gravity` is the gravity vector in {0}; `f_tip` is the wrench `(m, f)` the end effector
/// applies to the environment, in {n+1}.
///
/// # Panics
/// If `q` does not have `robot.nq()` entries, or `qd` or `qdd` not `robot.nv()`.
pub fn inverse_dynamics(
    robot: &Robot,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: &Vector3<f64>,
    f_tip: &Vector6<f64>,
) -> DVector<f64> {
    check::velocity(robot, "qd", qd);
    check::velocity(robot, "qdd", qdd);
    if let Some(c) = Coupled::of(robot) {
        check::configuration(robot, "q", q);
        let tau = inverse_dynamics(&c.physical, &c.q(q), &c.v(qd), &c.v(qdd), gravity, f_tip);
        return c.forces(&tau);
    }
    let n = robot.dof();
    let frames = TreeFrames::new(robot, q);
    let a = &frames.a;
    let ad_t_i_parent = &frames.ad_t_i_parent;
    let g_list = robot.g_list();
    let (theta_d, theta_dd) = (joint_part(robot, qd), joint_part(robot, qdd));

    // v_i[k] = V_k and vd_i[k] = V̇_k for k = 0..n (index 0 is the base, k = i + 1 link i).
    let mut v_i = vec![Vector6::zeros(); n + 1];
    let mut vd_i = vec![Vector6::zeros(); n + 1];
    if robot.base.floating {
        let r = rotation(&frames.base_pose);
        v_i[0] = base_part(robot, qd);
        vd_i[0] = base_part(robot, qdd) + twist(&Vector3::zeros(), &(-(r.transpose() * gravity)));
    } else {
        vd_i[0] = twist(&Vector3::zeros(), &(-gravity));
    }

    // Forward pass: twists and accelerations, root to leaves.
    for i in 0..n {
        let p = frames.parent_slot(i);
        v_i[i + 1] = ad_t_i_parent[i] * v_i[p] + a[i] * theta_d[i];
        vd_i[i + 1] =
            ad_t_i_parent[i] * vd_i[p] + ad(&v_i[i + 1]) * a[i] * theta_d[i] + a[i] * theta_dd[i];
    }

    // Backward pass: wrenches, leaves to root. from_children[k] gathers the wrenches the
    // children of body k (and the end effector) exert on it, in frame {k}.
    let mut from_children = vec![Vector6::zeros(); n + 1];
    from_children[frames.parent_slot(n)] += ad_t_i_parent[n].transpose() * f_tip;
    let off = joint_offset(robot);
    let mut tau = DVector::zeros(robot.nv());
    for i in (0..n).rev() {
        let f_i = from_children[i + 1] + g_list[i] * vd_i[i + 1]
            - ad(&v_i[i + 1]).transpose() * (g_list[i] * v_i[i + 1]);
        tau[off + i] = f_i.dot(&a[i]) + robot.joints[i].armature() * theta_dd[i];
        from_children[frames.parent_slot(i)] += ad_t_i_parent[i].transpose() * f_i;
    }
    if robot.base.floating {
        let g_b = robot.base.inertia.0;
        let f_0 = from_children[0] + g_b * vd_i[0] - ad(&v_i[0]).transpose() * (g_b * v_i[0]);
        tau.rows_mut(0, 6).copy_from(&f_0);
    }
    tau
}
