//! 200 seeded random kinematic trees (1–40 bodies, revolute and prismatic, arbitrary axes,
//! frames and inertias, branching anywhere; every other one on a floating base) expanded
//! symbolically and evaluated through the expression graph, against the reference
//! implementation: ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 for M, c, g, τ and forward dynamics. Each
//! tree's structural zeros of M are exact zeros of the graph.

use dynamics_gen::expand::expand;
use dynamics_gen::expr::ExprId;
use dynamics_model::random::{random_tree, Rng, TreeSpec};
use nalgebra::Vector6;

fn check(seed: u64, what: &str, x: &[f64], y: &[f64]) -> f64 {
    let what = format!("tree {seed} {what}");
    let (err, scale) = dynamics_tests::assert_close(&what, x, y, 1e-9, 1e-12);
    err / (1e-9 * scale + 1e-12)
}

/// Tree `seed`: 1–40 bodies (most between 10 and 40), a quarter prismatic, a floating base
/// for odd seeds.
pub fn tree(seed: u64) -> dynamics_model::Robot {
    let dof = if seed.is_multiple_of(5) {
        1 + (seed as usize / 5) % 9
    } else {
        10 + (seed as usize * 7) % 31
    };
    random_tree(
        seed,
        TreeSpec {
            dof,
            prismatic: 0.25,
            branching: 0.3,
            floating: seed % 2 == 1,
        },
    )
}

#[test]
fn random_trees_through_the_graph_equal_the_reference() {
    const TREES: u64 = 200;
    let (mut worst, mut worst_fd) = (0.0f64, 0.0f64);
    let (mut floating, mut branched, mut bodies, mut zeros) = (0, 0, 0, 0);
    for seed in 0..TREES {
        let robot = tree(seed);
        let (n, nq, nv) = (robot.dof(), robot.nq(), robot.nv());
        floating += usize::from(robot.base.floating);
        branched += usize::from(!robot.is_serial());
        bodies += n;
        let d = expand(&robot);
        let mut rng = Rng::new(seed ^ 0x7EE);
        let q: Vec<f64> = (0..nq).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let qdd: Vec<f64> = (0..nv).map(|_| rng.uniform(-2.0, 2.0)).collect();
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
        worst_fd = worst_fd.max(check(seed, "ν̇", &fd, fd_ref.as_slice()));
        // Dofs on different branches: exact zeros, never computed.
        let off = nv - n;
        for i in 0..n {
            for j in 0..n {
                if !robot.path_to(i).contains(&j) && !robot.path_to(j).contains(&i) {
                    let id = d.mass_matrix[(off + i) * nv + off + j];
                    assert!(d.graph.is_zero(id), "tree {seed}: M[{i}][{j}] is computed");
                    zeros += 1;
                }
            }
        }
    }
    assert!(
        floating == 100 && branched > 150,
        "{floating} floating, {branched} branched"
    );
    println!(
        "{TREES} trees ({bodies} bodies, {floating} floating, {branched} branched, {zeros} \
         structural zeros of M); worst error as a fraction of the tolerance: M, c, g, τ \
         {worst:.3e}, ν̇ {worst_fd:.3e}"
    );
}
