//! Mimic joints in the generated code: the TALOS upper body with its grippers coupled (each
//! gripper one coordinate driving six mimic joints) against Pinocchio 4.1.0
//! (`data/reference/trees/talos_upper_body_mimic.json`, made by `tools/mimic_reference.py`),
//! and 80 seeded random trees with coupled joints expanded through the graph against the
//! reference implementation: ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 for M, c, g, nle, τ and forward
//! dynamics. (The compiled random trees with mimic joints are in `generated_vs_reference.rs`.)

use dynamics_gen::expand::{expand, ForwardRoute, Q, QD, QDD, TAU};
use dynamics_gen::expr::{ExprId, Input};
use dynamics_model::random::{random_mimics, random_tree, Rng, TreeSpec};
use dynamics_tests::vecf;
use dynamics_tests::{reference_json, Spec, CASES};
use nalgebra::Vector6;

#[test]
fn generated_talos_grippers_reproduce_pinocchio() {
    let case = CASES
        .iter()
        .find(|c| matches!(c.spec, Spec::UrdfMimic("talos_upper_body_mimic")))
        .expect("the mimic TALOS is compiled");
    let data = reference_json("trees/talos_upper_body_mimic.json");
    let names: Vec<&str> = data["coordinate_names"]
        .as_array()
        .expect("names")
        .iter()
        .map(|x| x.as_str().expect("name"))
        .collect();
    assert_eq!(case.imp.joint_names(), names, "joint order");
    let nv = case.imp.nv();
    assert_eq!((case.imp.dof(), nv), (20, 20));
    let mut worst = [0.0f64; 6];
    for (k, s) in data["samples"]
        .as_array()
        .expect("samples")
        .iter()
        .enumerate()
    {
        let (q, v, a) = (vecf(&s["q"]), vecf(&s["v"]), vecf(&s["a"]));
        let mut check = |i: usize, what: &str, x: &[f64], y: &[f64]| {
            let what = format!("talos mimic sample {k}: {what}");
            let (err, scale) = dynamics_tests::assert_close(&what, x, y, 1e-9, 1e-12);
            worst[i] = worst[i].max(err / scale.max(1e-300));
        };
        let m = case.imp.mass_matrix(&q);
        let rows = s["M"].as_array().expect("M");
        let m_pin: Vec<f64> = (0..nv * nv)
            .map(|e| rows[e / nv][e % nv].as_f64().expect("number"))
            .collect();
        let m_ours: Vec<f64> = (0..nv * nv).map(|e| m[(e / nv, e % nv)]).collect();
        check(0, "M", &m_ours, &m_pin);
        let c = case.imp.coriolis(&q, &v);
        check(1, "c", c.as_slice(), &vecf(&s["c"]));
        let g = case.imp.gravity(&q);
        check(2, "g", g.as_slice(), &vecf(&s["g"]));
        let nle: Vec<f64> = c.iter().zip(g.iter()).map(|(x, y)| x + y).collect();
        check(3, "nle", &nle, &vecf(&s["nle"]));
        let tau = case.imp.inverse_dynamics(&q, &v, &a);
        check(4, "τ", tau.as_slice(), &vecf(&s["tau"]));
        let fd = case.imp.forward_dynamics(&q, &v, &vecf(&s["tau_rand"]));
        check(5, "a_fd", fd.as_slice(), &vecf(&s["a_fd"]));
    }
    println!("talos_upper_body_mimic: worst relative errors (M, c, g, nle, τ, ν̇) {worst:?}");
}

#[test]
fn random_trees_with_mimic_joints_through_the_graph_equal_the_reference() {
    let (mut worst, mut followers) = (0.0f64, 0);
    for seed in 0..80u64 {
        let spec = TreeSpec {
            dof: 2 + (seed as usize * 7) % 24,
            prismatic: 0.25,
            branching: 0.3,
            floating: seed % 2 == 1,
        };
        let robot = random_mimics(random_tree(seed, spec), seed ^ 0x313C, 0.4);
        followers += robot.dof() - robot.n_coordinates();
        let (nq, nv) = (robot.nq(), robot.nv());
        let d = expand(&robot);
        if robot.has_mimic() {
            assert_eq!(d.forward_route, ForwardRoute::Ldlt, "tree {seed}");
        }
        let mut rng = Rng::new(seed ^ 0x313);
        let q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let qdd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let (g, z) = (robot.gravity, Vector6::zeros());
        let tau = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &z);
        let eval = |roots: &[ExprId]| {
            d.graph.eval(roots, &|x: Input| {
                let i = x.index as usize;
                match x.group {
                    Q => q[i],
                    QD => qd[i],
                    QDD => qdd[i],
                    TAU => tau[i],
                    _ => f64::NAN,
                }
            })
        };
        let mut check = |what: &str, x: &[f64], y: &[f64]| {
            let what = format!("tree {seed} {what}");
            let (err, scale) = dynamics_tests::assert_close(&what, x, y, 1e-9, 1e-12);
            worst = worst.max(err / (1e-9 * scale + 1e-12));
        };
        let m_ref = dynamics_reference::mass_matrix(&robot, &q);
        check("M", &eval(&d.mass_matrix), m_ref.transpose().as_slice());
        let c_ref = dynamics_reference::vel_quadratic_forces(&robot, &q, &qd);
        check("c", &eval(&d.coriolis), c_ref.as_slice());
        let g_ref = dynamics_reference::gravity_forces(&robot, &q, &g);
        check("g", &eval(&d.gravity), g_ref.as_slice());
        check("τ", &eval(&d.inverse_dynamics), tau.as_slice());
        let fd_ref = dynamics_reference::forward_dynamics(&robot, &q, &qd, tau.as_slice(), &g, &z)
            .expect("M positive definite");
        check("ν̇", &eval(&d.forward_dynamics), fd_ref.as_slice());
    }
    assert!(followers > 200, "{followers} mimic joints");
    println!(
        "80 random trees with {followers} mimic joints: worst error as a fraction of the tolerance {worst:.3e}"
    );
}
