//! 1,200 seeded random chains (1–12 joints, revolute and prismatic, arbitrary axes, frames
//! and inertias) expanded symbolically and evaluated through the expression graph, against
//! the reference implementation: ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12.

use dynamics_gen::expand::expand;
use dynamics_gen::expr::ExprId;
use dynamics_model::random::{random_chain, ChainSpec, Rng};
use nalgebra::Vector6;

fn check(seed: u64, what: &str, x: &[f64], y: &[f64]) -> f64 {
    let what = format!("chain {seed} {what}");
    let (err, scale) = dynamics_tests::assert_close(&what, x, y, 1e-10, 1e-12);
    err / (1e-10 * scale + 1e-12)
}

/// Forward dynamics, with the condition number of M in the message (a solver's error grows
/// with it).
fn check_fd(seed: u64, x: &[f64], y: &[f64], m: &nalgebra::DMatrix<f64>) -> f64 {
    let eig = m.clone().symmetric_eigen().eigenvalues;
    let cond = eig.max() / eig.min();
    let (err, scale) = dynamics_tests::max_error(x, y);
    assert!(
        err <= 1e-10 * scale + 1e-12,
        "chain {seed} q̈: error {err:e} (scale {scale:e}, cond(M) {cond:e})"
    );
    err / (1e-10 * scale + 1e-12)
}

#[test]
fn random_chains_through_the_graph_equal_the_reference() {
    let mut worst = 0.0f64;
    let mut worst_fd = 0.0f64;
    let mut nodes = 0usize;
    const CHAINS: u64 = 1200;
    for seed in 0..CHAINS {
        let dof = 1 + (seed % 12) as usize;
        let robot = random_chain(
            seed,
            ChainSpec {
                dof,
                prismatic: 0.3,
            },
        );
        let d = expand(&robot);
        d.graph.verify().expect("graph invariants");
        nodes += d.graph.len();
        let mut rng = Rng::new(seed ^ 0xABCD);
        let q: Vec<f64> = (0..dof).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..dof).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let qdd: Vec<f64> = (0..dof).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let g = robot.gravity;
        let z = Vector6::zeros();
        let tau = dynamics_reference::inverse_dynamics(&robot, &q, &qd, &qdd, &g, &z);
        let eval = |roots: &[ExprId]| {
            dynamics_tests::eval_graph(&d.graph, roots, [&q, &qd, &qdd, tau.as_slice()])
        };
        let m_ref = dynamics_reference::mass_matrix(&robot, &q);
        let m_row: Vec<f64> = m_ref.transpose().as_slice().to_vec();
        worst = worst.max(check(seed, "M", &eval(&d.mass_matrix), &m_row));
        let c_ref = dynamics_reference::vel_quadratic_forces(&robot, &q, &qd);
        worst = worst.max(check(seed, "c", &eval(&d.coriolis), c_ref.as_slice()));
        let g_ref = dynamics_reference::gravity_forces(&robot, &q, &g);
        worst = worst.max(check(seed, "g", &eval(&d.gravity), g_ref.as_slice()));
        worst = worst.max(check(seed, "τ", &eval(&d.inverse_dynamics), tau.as_slice()));
        let fd = eval(&d.forward_dynamics);
        let fd_ref = dynamics_reference::forward_dynamics(&robot, &q, &qd, tau.as_slice(), &g, &z)
            .expect("M positive definite");
        let e = check_fd(seed, &fd, fd_ref.as_slice(), &m_ref);
        worst_fd = worst_fd.max(e);
    }
    println!(
        "{CHAINS} chains, {nodes} graph nodes in all; worst error as a fraction of the \
         tolerance: M, c, g, τ {worst:.3e}, q̈ {worst_fd:.3e}"
    );
}
