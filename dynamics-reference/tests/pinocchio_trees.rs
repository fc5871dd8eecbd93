//! The reference against Pinocchio 4.1.0 on three kinematic trees
//! (`tests/data/reference/trees/*.json`, schema in that folder's README): the Talos upper body
//! (fixed base, three branches), Solo-12 and the Unitree G1 (floating base). Each robot is built
//! directly from the file's `pinocchio_model` entries (not from its URDF). On all 20 samples:
//! M, nle = c + g, g, c, τ = RNEA(q, v, a), forward dynamics at `tau_rand`, and the joint-frame
//! poses `oMi`, with Pinocchio's free-flyer vectors reordered to ours (angular first).

mod common;

use common::pinocchio::{matrix_to_ours, robot_from_pinocchio, to_ours};
use common::{check, load_json, mat4, mat_of, vec_of, MaxErr};
use dynamics_reference as dr;
use nalgebra::{DMatrix, Vector6};

fn compare(name: &str) {
    let file = load_json(&format!("reference/trees/{name}.json"));
    let robot = robot_from_pinocchio(&file);
    let floating = robot.base.floating;
    let g = robot.gravity;
    let tip = Vector6::zeros();
    let mut max = MaxErr::default();
    // Pinocchio's parents_fromRow: the previous dof on the path to the root, −1 for none (the
    // base's six dofs form a chain, so their reordering does not change it).
    let dof_parent: Vec<i64> = file["tree"]["dof_parent"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_i64().unwrap())
        .collect();
    let samples = file["samples"].as_array().expect("samples");
    assert_eq!(samples.len(), 20);
    for (k, s) in samples.iter().enumerate() {
        let label = format!("{name} sample {k}");
        let q = vec_of(&s["q"]);
        let v = to_ours(floating, &vec_of(&s["v"]));
        let a = to_ours(floating, &vec_of(&s["a"]));
        let ours = |key: &str| to_ours(floating, &vec_of(&s[key]));
        let mut cmp = |what: &str, x: &[f64], y: &[f64]| {
            check(&format!("{label} {what}"), x, y);
            let amax = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |m, e| m.max(e.abs()));
            let diff = amax(&mut x.iter().zip(y).map(|(a, b)| a - b));
            max.note(&format!("{what} ‖x − y‖∞"), diff);
            max.note(
                &format!("{what} ‖x − y‖∞/‖y‖∞"),
                diff / amax(&mut y.iter().copied()),
            );
        };

        let m = dr::mass_matrix(&robot, &q);
        let m_pin = matrix_to_ours(floating, &mat_of(&s["M"]));
        cmp("M", m.as_slice(), m_pin.as_slice());
        // Dofs on different branches: exactly zero in both.
        let mut zeros = 0;
        for i in 0..robot.nv() {
            for j in 0..robot.nv() {
                if !related(&dof_parent, i, j) {
                    assert_eq!(m[(i, j)], 0.0, "{label}: M[{i}, {j}] on different branches");
                    assert_eq!(m_pin[(i, j)], 0.0);
                    zeros += 1;
                }
            }
        }
        assert_eq!(zeros, s["M_structural_zero_count"].as_u64().unwrap());

        let nle = dr::inverse_dynamics(&robot, &q, &v, &vec![0.0; robot.nv()], &g, &tip);
        cmp("nle", nle.as_slice(), &ours("nle"));
        cmp(
            "g",
            dr::gravity_forces(&robot, &q, &g).as_slice(),
            &ours("g"),
        );
        cmp(
            "c",
            dr::vel_quadratic_forces(&robot, &q, &v).as_slice(),
            &ours("c"),
        );
        let tau = dr::inverse_dynamics(&robot, &q, &v, &a, &g, &tip);
        cmp("tau", tau.as_slice(), &ours("tau"));
        let a_fd = dr::forward_dynamics(&robot, &q, &v, &ours("tau_rand"), &g, &tip)
            .expect("M is positive definite");
        cmp("a_fd", a_fd.as_slice(), &ours("a_fd"));

        // Poses of the joint frames (floating: the free flyer's frame is the base).
        let o_m_i: Vec<_> = s["oMi"].as_array().unwrap().iter().map(mat4).collect();
        let mut poses = dr::link_poses(&robot, &q);
        if floating {
            poses.insert(0, dr::base_pose(&robot, &q));
        }
        assert_eq!(poses.len(), o_m_i.len());
        for (t, t_pin) in poses.iter().zip(&o_m_i) {
            cmp("oMi", t.as_slice(), t_pin.as_slice());
        }
    }
    max.report(&format!("Pinocchio {name}"));
}

/// Whether dof i is on the path of dof j or j on that of i.
fn related(dof_parent: &[i64], i: usize, j: usize) -> bool {
    let on_path = |a: usize, b: usize| {
        let mut k = b as i64;
        while k >= 0 {
            if k == a as i64 {
                return true;
            }
            k = dof_parent[k as usize];
        }
        false
    };
    on_path(i, j) || on_path(j, i)
}

#[test]
fn talos_upper_body_fixed_base_tree() {
    compare("talos_upper_body");
}

#[test]
fn solo12_floating_base() {
    compare("solo12");
}

#[test]
fn g1_29dof_floating_base() {
    compare("g1_29dof");
}

/// The free-flyer conventions the comparison relies on, on Pinocchio's own numbers: at rest
/// the base rows of g are `Rᵀ (0, 0, m_total·9.81)` as a force (ours: entries 3..6) and the
/// base block of M is the composite inertia, with `m_total·1₃` in its force rows.
#[test]
fn free_flyer_layout() {
    for name in ["solo12", "g1_29dof"] {
        let file = load_json(&format!("reference/trees/{name}.json"));
        let robot = robot_from_pinocchio(&file);
        let total =
            robot.base.inertia.mass() + robot.links.iter().map(|l| l.inertia.mass()).sum::<f64>();
        let s = &file["samples"][0];
        let q = vec_of(&s["q"]);
        let m = dr::mass_matrix(&robot, &q);
        let lin = m.view((3, 3), (3, 3)).into_owned();
        check(
            &format!("{name} M[3..6, 3..6]"),
            lin.as_slice(),
            (DMatrix::identity(3, 3) * total).as_slice(),
        );
        let r = dynamics_model::lie::rotation(&dr::base_pose(&robot, &q));
        let f = r.transpose() * nalgebra::Vector3::new(0.0, 0.0, total * 9.81);
        let grav = dr::gravity_forces(&robot, &q, &robot.gravity);
        check(
            &format!("{name} g[3..6]"),
            &grav.as_slice()[3..6],
            f.as_slice(),
        );
    }
}
