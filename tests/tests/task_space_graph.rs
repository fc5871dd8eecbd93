//! The Coriolis matrix, the bias `h = c + g`, the factor of `M`, the tip-wrench functions and
//! the task-space dynamics, expanded symbolically and evaluated through the expression graph,
//! against the reference implementation on 160 seeded random robots, two in three serial chains
//! and the rest trees (revolute and prismatic joints, every other one on a floating base, a
//! fifth with mimic joints):
//!
//! - `C` = `dynamics_reference::coriolis_matrix`, `h` = ID with `ν̇ = 0`;
//! - `Lᵀ D L` = `M`;
//! - `J_bᵀ F_tip`, `ID + J_bᵀ F_tip` and `M⁻¹ (τ − h − J_bᵀ F_tip)` = the reference's
//!   `end_effector_forces`, `inverse_dynamics` and `forward_dynamics` with `F_tip`;
//! - `Λ (J_b M⁻¹ J_bᵀ) = I` (M and J_b from the reference), and `F = Λ V̇ + η` for the
//!   motion that the wrench F produces through `τ = J_bᵀ F`.
//!
//! ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12 per quantity (task-space identities 1e-8, see below).

use dynamics_gen::expand::task_space::{expand_task_space, F_TIP};
use dynamics_gen::expand::{expand, kinematics::expand_kinematics, Q, QD, QDD, TAU};
use dynamics_gen::expr::{ExprId, Input};
use dynamics_model::random::{random_mimics, random_tree, Rng, TreeSpec};
use dynamics_model::Robot;
use dynamics_tests::row_major;
use nalgebra::{DMatrix, DVector, Vector6};

fn robot(seed: u64) -> Robot {
    let spec = TreeSpec {
        dof: 1 + (seed as usize * 5) % 14,
        prismatic: 0.25,
        // Two in three are serial chains.
        branching: if seed % 3 == 1 { 0.4 } else { 0.0 },
        floating: seed % 2 == 1,
    };
    let r = random_tree(seed, spec);
    if seed % 5 == 2 {
        random_mimics(r, seed, 0.4)
    } else {
        r
    }
}

#[test]
fn coriolis_matrix_bias_factor_and_tip_functions_match_the_reference() {
    let mut worst = 0.0f64;
    let (mut task_checked, mut task_singular) = (0, 0);
    for seed in 0..160u64 {
        let r = robot(seed);
        let (nq, nv) = (r.nq(), r.nv());
        let d = expand(&r);
        let k = expand_kinematics(&r);
        let t = expand_task_space(&d, &k);
        let mut rng = Rng::new(seed ^ 0x7A5C);
        let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform(-2.5, 2.5)).collect();
        if r.base.floating {
            let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            for x in &mut q[3..7] {
                *x /= norm;
            }
        }
        let v: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let a: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let tau: Vec<f64> = (0..nv).map(|_| rng.uniform(-5.0, 5.0)).collect();
        let f = Vector6::from_fn(|_, _| rng.uniform(-3.0, 3.0));
        let gravity = r.gravity;
        let zero6 = Vector6::zeros();
        let mut check = |what: &str, x: &[f64], y: &[f64], rtol: f64| {
            let (err, scale) =
                dynamics_tests::assert_close(&format!("seed {seed}: {what}"), x, y, rtol, 1e-12);
            worst = worst.max(err / (rtol * scale + 1e-12));
        };
        let dyn_eval =
            |roots: &[ExprId]| dynamics_tests::eval_graph(&d.graph, roots, [&q, &v, &a, &tau]);
        let c = dynamics_reference::coriolis_matrix(&r, &q, &v);
        check("C", &dyn_eval(&d.coriolis_matrix), &row_major(&c), 1e-9);
        let zeros = vec![0.0; nv];
        let h = dynamics_reference::inverse_dynamics(&r, &q, &v, &zeros, &gravity, &zero6);
        check("h", &dyn_eval(&d.bias), h.as_slice(), 1e-9);
        // Lᵀ D L = M.
        let m = dynamics_reference::mass_matrix(&r, &q);
        let l_entries = dyn_eval(&d.mass_matrix_factor);
        let inv_d = dyn_eval(&d.mass_matrix_inv_d);
        let l = DMatrix::from_fn(nv, nv, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Greater => l_entries[i * nv + j],
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Less => 0.0,
        });
        let dd = DMatrix::from_diagonal(&DVector::from_iterator(nv, inv_d.iter().map(|x| 1.0 / x)));
        check(
            "LᵀDL",
            &row_major(&(l.transpose() * dd * &l)),
            &row_major(&m),
            1e-9,
        );

        let te = |roots: &[ExprId]| {
            t.graph.eval(roots, &|x: Input| {
                let i = x.index as usize;
                match x.group {
                    Q => q[i],
                    QD => v[i],
                    QDD => a[i],
                    TAU => tau[i],
                    F_TIP => f[i],
                    _ => f64::NAN,
                }
            })
        };
        let ef = dynamics_reference::end_effector_forces(&r, &q, &f);
        check("J_bᵀF", &te(&t.end_effector_forces), ef.as_slice(), 1e-9);
        let id = dynamics_reference::inverse_dynamics(&r, &q, &v, &a, &gravity, &f);
        check(
            "ID with tip",
            &te(&t.inverse_dynamics_with_tip),
            id.as_slice(),
            1e-9,
        );
        let fd = dynamics_reference::forward_dynamics(&r, &q, &v, &tau, &gravity, &f).unwrap();
        check(
            "FD with tip",
            &te(&t.forward_dynamics_with_tip),
            fd.as_slice(),
            1e-9,
        );

        if nv < 6 {
            assert!(t.mass_matrix.is_empty() && t.pivots.is_empty());
            continue;
        }
        let pivots_ok = t
            .pivots
            .iter()
            .all(|&(dk, akk)| te(&[dk])[0] > f64::EPSILON.sqrt() * te(&[akk])[0]);
        if !pivots_ok {
            task_singular += 1;
            continue;
        }
        task_checked += 1;
        let lambda = DMatrix::from_row_slice(6, 6, &te(&t.mass_matrix));
        let jb = dynamics_reference::jacobian_body(&r, &q);
        let m_inv_jt = m.clone().cholesky().unwrap().solve(&jb.transpose());
        let a_mat = &jb * &m_inv_jt;
        // Λ A = I: relative to the conditioning of A, which random trees make poor at times.
        let cond = a_mat.norm() * lambda.norm();
        let prod = &lambda * &a_mat;
        check(
            "ΛA = I",
            &row_major(&prod),
            &row_major(&DMatrix::identity(6, 6)),
            1e-13 * cond.max(1.0),
        );
        // The wrench F acting alone through τ = J_bᵀ F: F = Λ V̇ + η.
        let tau_f = dynamics_reference::end_effector_forces(&r, &q, &f);
        let acc =
            dynamics_reference::forward_dynamics(&r, &q, &v, tau_f.as_slice(), &gravity, &zero6)
                .unwrap();
        let jb_dot_graph = k
            .graph
            .eval(&k.jacobian_body_dot, &|x: Input| match x.group {
                Q => q[x.index as usize],
                _ => v[x.index as usize],
            });
        let jb_dot = DMatrix::from_row_slice(6, nv, &jb_dot_graph);
        let vdot = &jb * &acc + &jb_dot * DVector::from_column_slice(&v);
        let eta = DVector::from_column_slice(&te(&t.bias));
        let f_back = &lambda * vdot + eta;
        check(
            "F = ΛV̇ + η",
            f_back.as_slice(),
            f.as_slice(),
            1e-13 * cond.max(1.0),
        );
    }
    eprintln!(
        "worst error {worst:.3} of the tolerance; task space checked at {task_checked} states, {task_singular} singular (None)"
    );
    assert!(
        task_checked >= 15,
        "too few task-space checks: {task_checked}"
    );
}
