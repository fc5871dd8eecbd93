//! Mimic joints (coupled coordinates, `dynamics_model::mimic`): the reference against
//! Pinocchio 4.1.0's mimic model on the TALOS upper body with its grippers coupled, against a
//! two-link arm whose second joint turns twice as fast as the first (the dynamics of one
//! coordinate in closed form), and the identities of rigid-body dynamics on random trees with
//! coupled joints, where the finite differences of energies and poses see the coupling from
//! outside the projection.

mod common;

use common::random_tree::{trees_coupled, TreeSample};
use common::{check, check_tol, load_json, mat4, mat_of, vec_of, MaxErr};
use dynamics_model::lie::{rp_to_trans, trans_inv};
use dynamics_model::{LoadOptions, Mimic, Robot};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Matrix6, Vector3, Vector6};

/// `tests/data/reference/trees/talos_upper_body_mimic.json` (made by
/// `tools/mimic_reference.py`): M, nle, g, c, τ, forward dynamics and every joint frame's pose
/// on 20 samples, the robot loaded from its URDF.
#[test]
fn talos_grippers_against_pinocchio() {
    let file = load_json("reference/trees/talos_upper_body_mimic.json");
    let path = format!("{}robots/trees/talos_upper_body_mimic.urdf", common::DATA);
    let robot = dynamics_model::load_file(std::path::Path::new(&path), &LoadOptions::default())
        .expect("the mimic URDF loads");
    let names = |key: &str| -> Vec<String> {
        file[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(robot.joint_names(), names("coordinate_names"));
    assert_eq!(robot.dof(), 32);
    assert_eq!((robot.nq(), robot.nv()), (20, 20));
    // The same physical joints in the same order, the followers with Pinocchio's coupling.
    let physical: Vec<&str> = robot.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(physical, names("joint_names"));
    for m in file["mimic"].as_array().unwrap() {
        let j = robot
            .joints
            .iter()
            .find(|j| j.name == m["name"].as_str().unwrap())
            .unwrap();
        let mimic = j.mimic.expect("a follower");
        assert_eq!(
            robot.joints[mimic.leader].name,
            m["leader"].as_str().unwrap()
        );
        assert_eq!(mimic.multiplier, m["multiplier"].as_f64().unwrap());
        assert_eq!(mimic.offset, m["offset"].as_f64().unwrap());
    }
    let (g, tip) = (robot.gravity, Vector6::zeros());
    let mut max = MaxErr::default();
    for (k, s) in file["samples"].as_array().unwrap().iter().enumerate() {
        let label = format!("talos mimic sample {k}");
        let (q, v, a) = (vec_of(&s["q"]), vec_of(&s["v"]), vec_of(&s["a"]));
        let mut cmp = |what: &str, x: &[f64], y: &[f64]| {
            max.note(what, check(&format!("{label} {what}"), x, y));
        };
        cmp(
            "M",
            dr::mass_matrix(&robot, &q).as_slice(),
            mat_of(&s["M"]).as_slice(),
        );
        let zero = vec![0.0; robot.nv()];
        cmp(
            "nle",
            dr::inverse_dynamics(&robot, &q, &v, &zero, &g, &tip).as_slice(),
            &vec_of(&s["nle"]),
        );
        cmp(
            "g",
            dr::gravity_forces(&robot, &q, &g).as_slice(),
            &vec_of(&s["g"]),
        );
        cmp(
            "c",
            dr::vel_quadratic_forces(&robot, &q, &v).as_slice(),
            &vec_of(&s["c"]),
        );
        cmp(
            "tau",
            dr::inverse_dynamics(&robot, &q, &v, &a, &g, &tip).as_slice(),
            &vec_of(&s["tau"]),
        );
        let a_fd = dr::forward_dynamics(&robot, &q, &v, &vec_of(&s["tau_rand"]), &g, &tip)
            .expect("M is positive definite");
        cmp("a_fd", a_fd.as_slice(), &vec_of(&s["a_fd"]));
        let poses = dr::link_poses(&robot, &q);
        let o_m_i: Vec<Matrix4<f64>> = s["oMi"].as_array().unwrap().iter().map(mat4).collect();
        assert_eq!(poses.len(), o_m_i.len());
        for (t, t_pin) in poses.iter().zip(&o_m_i) {
            cmp("oMi", t.as_slice(), t_pin.as_slice());
        }
    }
    max.report("Pinocchio talos_upper_body_mimic");
}

/// Two point masses on a planar arm, gravity in the plane; joint 2 mimics joint 1 with
/// multiplier 2 and offset o, so with x the one coordinate the masses sit at
/// `p_1 = l_1 (cos x, sin x)` and `p_2 = p_1 + l_2 (cos(3x + o), sin(3x + o))`, and
/// ```text
/// M(x) = m_1 l_1² + m_2 (l_1² + 9 l_2² + 6 l_1 l_2 cos(2x + o))
/// c(x, ẋ) = ½ M'(x) ẋ² = −6 m_2 l_1 l_2 sin(2x + o) ẋ²
/// g(x) = ∂P/∂x = g_0 ((m_1 + m_2) l_1 cos x + 3 m_2 l_2 cos(3x + o))
/// ```
#[test]
fn two_links_turning_at_twice_the_rate() {
    let (m1, m2, l1, l2, g0, o) = (1.5, 0.7, 0.4, 0.3, 9.81, 0.25);
    let at = |x: f64, y: f64| rp_to_trans(&Matrix3::identity(), &Vector3::new(x, y, 0.0));
    let point = |m: f64| Matrix6::from_diagonal(&Vector6::new(0.0, 0.0, 0.0, m, m, m));
    let mut robot = Robot::from_mr_lists(
        &[at(l1, 0.0), at(l2, 0.0), Matrix4::identity()],
        &[point(m1), point(m2)],
        &[
            Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0),
            Vector6::new(0.0, 0.0, 1.0, 0.0, -l1, 0.0),
        ],
        Vector3::new(0.0, -g0, 0.0),
    )
    .unwrap();
    robot.joints[1].mimic = Some(Mimic {
        leader: 0,
        multiplier: 2.0,
        offset: o,
    });
    robot.validate().unwrap();
    assert_eq!((robot.nq(), robot.nv(), robot.dof()), (1, 1, 2));
    let g = robot.gravity;
    for (x, xd, xdd) in [(0.3, 1.2, -0.7), (-1.1, -0.4, 2.0), (2.5, 0.0, 0.3)] {
        let mass =
            m1 * l1 * l1 + m2 * (l1 * l1 + 9.0 * l2 * l2 + 6.0 * l1 * l2 * (2.0 * x + o).cos());
        let c = -6.0 * m2 * l1 * l2 * (2.0 * x + o).sin() * xd * xd;
        let grav = g0 * ((m1 + m2) * l1 * x.cos() + 3.0 * m2 * l2 * (3.0 * x + o).cos());
        let tau = mass * xdd + c + grav;
        let what = format!("x = {x}");
        check(&what, dr::mass_matrix(&robot, &[x]).as_slice(), &[mass]);
        check(
            &what,
            dr::vel_quadratic_forces(&robot, &[x], &[xd]).as_slice(),
            &[c],
        );
        check(
            &what,
            dr::gravity_forces(&robot, &[x], &g).as_slice(),
            &[grav],
        );
        let id = dr::inverse_dynamics(&robot, &[x], &[xd], &[xdd], &g, &Vector6::zeros());
        check(&what, id.as_slice(), &[tau]);
        let fd = dr::forward_dynamics(&robot, &[x], &[xd], &[tau], &g, &Vector6::zeros()).unwrap();
        check(&what, fd.as_slice(), &[xdd]);
        // Energies: K = ½ M ẋ², P = −Σ m gᵀ p.
        let kin = dr::kinetic_energy(&robot, &[x], &[xd]);
        check(&what, &[kin], &[0.5 * mass * xd * xd]);
        let pot = g0 * ((m1 + m2) * l1 * x.sin() + m2 * l2 * (3.0 * x + o).sin());
        check(&what, &[dr::potential_energy(&robot, &[x], &g)], &[pot]);
        // The tip (at mass 2) turns at 3ẋ about z: space twist (0, 0, 3ẋ, v) with v = ṗ − ω × p.
        let p = Vector3::new(
            l1 * x.cos() + l2 * (3.0 * x + o).cos(),
            l1 * x.sin() + l2 * (3.0 * x + o).sin(),
            0.0,
        );
        let p_dot = Vector3::new(
            -l1 * x.sin() - 3.0 * l2 * (3.0 * x + o).sin(),
            l1 * x.cos() + 3.0 * l2 * (3.0 * x + o).cos(),
            0.0,
        ) * xd;
        let w = Vector3::new(0.0, 0.0, 3.0 * xd);
        let v = p_dot - w.cross(&p);
        let twist = dr::jacobian_space(&robot, &[x]) * xd;
        check(
            &what,
            twist.as_slice(),
            &[w[0], w[1], w[2], v[0], v[1], v[2]],
        );
        let pose = dr::end_effector_pose(&robot, &[x]);
        let position = [pose[(0, 3)], pose[(1, 3)], pose[(2, 3)]];
        check(&what, &position, p.as_slice());
    }
}

/// The coupled robot is the physical one (every joint independent) seen through `J`, written
/// out here apart from the crate's own map: `τ = Jᵀ τ_phys(Jx + o, Jẋ, Jẍ)`, `M = Jᵀ M_phys J`,
/// `J_s = J_s,phys J`, and equal kinetic energies and link poses.
#[test]
fn coupled_equals_the_physical_robot_projected() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let r = &s.robot;
        let mut physical = r.clone();
        for j in &mut physical.joints {
            j.mimic = None;
        }
        let ov = r.nv() - r.n_coordinates();
        let couplings = r.couplings();
        let mut jmat = DMatrix::zeros(physical.nv(), r.nv());
        for b in 0..ov {
            jmat[(b, b)] = 1.0;
        }
        let mut q = s.q[..r.nq() - r.n_coordinates()].to_vec();
        for (i, c) in couplings.iter().enumerate() {
            jmat[(ov + i, ov + c.coordinate)] = c.multiplier;
            q.push(c.multiplier * s.q[r.nq() - r.n_coordinates() + c.coordinate] + c.offset);
        }
        let qd: Vec<f64> = (&jmat * DVector::from_column_slice(&s.qd))
            .iter()
            .copied()
            .collect();
        let qdd: Vec<f64> = (&jmat * DVector::from_column_slice(&s.qdd))
            .iter()
            .copied()
            .collect();
        let g = r.gravity;
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let tau_phys = dr::inverse_dynamics(&physical, &q, &qd, &qdd, &g, &s.f_tip);
        let what = format!("tree {k}");
        max.note(
            "τ − Jᵀ τ_phys",
            check(
                &what,
                tau.as_slice(),
                (jmat.transpose() * tau_phys).as_slice(),
            ),
        );
        let m = dr::mass_matrix(r, &s.q);
        let m_phys = dr::mass_matrix(&physical, &q);
        max.note(
            "M − Jᵀ M_phys J",
            check(
                &what,
                m.as_slice(),
                (jmat.transpose() * m_phys * &jmat).as_slice(),
            ),
        );
        let j_s = dr::jacobian_space(r, &s.q);
        max.note(
            "J_s − J_s,phys J",
            check(
                &what,
                j_s.as_slice(),
                (dr::jacobian_space(&physical, &q) * &jmat).as_slice(),
            ),
        );
        let kin = dr::kinetic_energy(r, &s.q, &s.qd);
        max.note(
            "K − K_phys",
            check(&what, &[kin], &[dr::kinetic_energy(&physical, &q, &qd)]),
        );
        for (a, b) in dr::link_poses(r, &s.q)
            .iter()
            .zip(dr::link_poses(&physical, &q))
        {
            max.note("T − T_phys", check(&what, a.as_slice(), b.as_slice()));
        }
    }
    max.report("random trees with mimic joints");
}

/// 120 random trees of 1–12 bodies (two in three floating), about 40 % of the joints coupled
/// to a random independent one (multipliers ±[0.5, 2), offsets in [−0.5, 0.5)).
fn samples() -> Vec<TreeSample> {
    let s = trees_coupled(0x313C_7EE5, 120, 12, 0.4);
    let coupled = s.iter().filter(|s| s.robot.has_mimic()).count();
    assert!(coupled > 80, "{coupled} of 120 trees have mimic joints");
    s
}

/// `q ± h q̇(q, ν)`.
fn shift(s: &TreeSample, qd: &[f64], h: f64) -> Vec<f64> {
    let q_dot = dr::configuration_rate(&s.robot, &s.q, qd);
    s.q.iter()
        .zip(q_dot.iter())
        .map(|(a, b)| a + h * b)
        .collect()
}

/// The equations of motion, FD∘ID = id, and the identities that look at the coupling from
/// outside: `g = ∂P/∂x`, `V_s = J_s ẋ = Ṫ T⁻¹` and `Ṁ` by central differences along the
/// coordinates, `c = C ẋ`, `Ṁ − 2C` skew, power balance, M symmetric positive definite with
/// exact zeros between coordinates whose joints lie on different branches.
#[test]
fn identities_on_random_trees_with_mimic_joints() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let (r, g, nv) = (&s.robot, s.robot.gravity, s.robot.nv());
        let what = format!("tree {k}");
        let qd = DVector::from_column_slice(&s.qd);
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let m = dr::mass_matrix(r, &s.q);
        let terms = [
            &m * DVector::from_column_slice(&s.qdd),
            dr::vel_quadratic_forces(r, &s.q, &s.qd),
            dr::gravity_forces(r, &s.q, &g),
            dr::end_effector_forces(r, &s.q, &s.f_tip),
        ];
        let sum = terms.iter().fold(DVector::zeros(nv), |a, t| a + t);
        let abs = 1e-13 * terms.iter().map(|t| t.amax()).fold(1.0, f64::max);
        max.note(
            "τ − (M ν̇ + c + g + J_bᵀF)",
            check_tol(&what, sum.as_slice(), tau.as_slice(), 1e-9, abs),
        );
        let fd = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &s.f_tip).unwrap();
        let eig = m.clone().symmetric_eigenvalues();
        assert!(eig.min() > 0.0, "{what}: M not positive definite");
        assert_eq!(m, m.transpose(), "{what}: M not symmetric");
        let rel = 1e-9 * (eig.max() / eig.min() / 1e3).max(1.0);
        max.note(
            "FD(ID(ν̇)) − ν̇",
            check_tol(&what, fd.as_slice(), &s.qdd, rel, 1e-12),
        );

        // g = ∂P along each coordinate (and the base's body twist).
        let grav = &terms[2];
        for i in 0..nv {
            let mut e_i = vec![0.0; nv];
            e_i[i] = 1.0;
            let d = (dr::potential_energy(r, &shift(s, &e_i, h), &g)
                - dr::potential_energy(r, &shift(s, &e_i, -h), &g))
                / (2.0 * h);
            let err = (d - grav[i]).abs() / grav.amax().max(1.0);
            assert!(err <= 1e-7, "{what} dof {i}: g {} vs ∂P {d}", grav[i]);
            max.note("g − ∂P (central difference)", err);
        }

        // V_s = J_s ν against the pose's derivative along the motion.
        let t = dr::end_effector_pose(r, &s.q);
        let t_dot = (dr::end_effector_pose(r, &shift(s, &s.qd, h))
            - dr::end_effector_pose(r, &shift(s, &s.qd, -h)))
            / (2.0 * h);
        let vs = t_dot * trans_inv(&t);
        let diff = [
            vs[(2, 1)],
            vs[(0, 2)],
            vs[(1, 0)],
            vs[(0, 3)],
            vs[(1, 3)],
            vs[(2, 3)],
        ];
        let v = dr::jacobian_space(r, &s.q) * &qd;
        for (x, y) in diff.iter().zip(v.iter()) {
            assert!(
                (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                "{what}: J_s ν {y} vs {x}"
            );
            max.note(
                "J_s ν − central difference",
                (x - y).abs() / y.abs().max(1.0),
            );
        }

        // Ṁ against M's central difference; c = C ν; Ṁ − 2C skew; power balance.
        if r.dof() <= 8 {
            let mdot = dr::mass_matrix_dot(r, &s.q, &s.qd);
            let m_diff = (dr::mass_matrix(r, &shift(s, &s.qd, h))
                - dr::mass_matrix(r, &shift(s, &s.qd, -h)))
                / (2.0 * h);
            for (x, y) in m_diff.iter().zip(mdot.iter()) {
                assert!(
                    (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                    "{what}: Ṁ {y} vs {x}"
                );
                max.note("Ṁ − central difference", (x - y).abs() / y.abs().max(1.0));
            }
            let c_mat = dr::coriolis_matrix(r, &s.q, &s.qd);
            max.note(
                "C ν − c",
                check(&what, (&c_mat * &qd).as_slice(), terms[1].as_slice()),
            );
            let n_mat = &mdot - &c_mat * 2.0;
            let skew = (&n_mat + n_mat.transpose()).amax();
            let scale = mdot.amax().max(c_mat.amax()).max(1.0);
            assert!(skew <= 1e-12 * scale, "{what}: Ṁ − 2C not skew");
            let tip = Vector6::zeros();
            let tau = DVector::from_column_slice(&s.qdd) * 3.0;
            let acc = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &tip).unwrap();
            let power = [&m * &acc, &mdot * &qd * 0.5, terms[2].clone()];
            let lhs: f64 = power.iter().map(|t| qd.dot(t)).sum();
            let scale: f64 = power.iter().map(|t| qd.abs().dot(&t.abs())).sum::<f64>()
                + qd.abs().dot(&tau.abs());
            assert!(
                (lhs - qd.dot(&tau)).abs() <= 1e-11 * scale.max(1.0),
                "{what}: power"
            );
        }

        // Exact zeros between coordinates whose joints are on different branches.
        let ov = nv - r.n_coordinates();
        let members: Vec<Vec<usize>> = (0..r.n_coordinates())
            .map(|c| {
                r.couplings()
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.coordinate == c)
                    .map(|(i, _)| i)
                    .collect()
            })
            .collect();
        for a in 0..r.n_coordinates() {
            for b in 0..r.n_coordinates() {
                let related = members[a].iter().any(|&i| {
                    members[b]
                        .iter()
                        .any(|&j| r.path_to(i).contains(&j) || r.path_to(j).contains(&i))
                });
                if !related {
                    assert_eq!(m[(ov + a, ov + b)], 0.0, "{what}: M[{a}, {b}]");
                }
            }
        }
    }
    max.report("random trees with mimic joints");
}
