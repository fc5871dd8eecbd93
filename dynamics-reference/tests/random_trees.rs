//! Identities of rigid-body dynamics on 240 seeded random kinematic trees (1–40 bodies,
//! revolute and prismatic, branching, two in three on a floating base with a non-unit
//! quaternion; see `common/random_tree.rs`), and the serial chains' numbers from before the
//! trees. Each identity links two different algorithms or an algorithm and a finite
//! difference; the floating base's own identities are in `floating_base.rs`.

mod common;

use common::random_chain::chains;
use common::random_tree::{related, trees, TreeSample};
use common::{check, check_tol, MaxErr};
use dynamics_model::lie::{adjoint, trans_inv};
use dynamics_reference as dr;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};
use std::fmt::Write;

const SEED: u64 = 0x7EE5_D1CE;

/// 240 trees of 1–40 bodies.
fn samples() -> Vec<TreeSample> {
    trees(SEED, 240, 40)
}

/// 60 trees of 1–10 bodies, for the O(n⁴) Christoffel C and O(n³) closed-form Ṁ.
fn small_samples() -> Vec<TreeSample> {
    trees(SEED ^ 0x5A11, 60, 10)
}

fn amax(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// `q ± h q̇(q, ν)`: a step along the motion (the base's position and quaternion included).
fn shift(s: &TreeSample, qd: &[f64], h: f64) -> Vec<f64> {
    let q_dot = dr::configuration_rate(&s.robot, &s.q, qd);
    s.q.iter()
        .zip(q_dot.iter())
        .map(|(a, b)| a + h * b)
        .collect()
}

/// `τ = M ν̇ + c + g + J_bᵀ F_tip` (CRBA, Newton–Euler with ν̇ = 0 and ν = 0, body Jacobian vs
/// one Newton–Euler pass), and every column of M is `ID(q, 0, e_j)` without gravity.
#[test]
fn equations_of_motion() {
    let mut max = MaxErr::default();
    let mut branched = 0;
    for (k, s) in samples().iter().enumerate() {
        let (r, g, nv) = (&s.robot, s.robot.gravity, s.robot.nv());
        branched += usize::from(!r.is_serial());
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let m = dr::mass_matrix(r, &s.q);
        let terms = [
            &m * DVector::from_column_slice(&s.qdd),
            dr::vel_quadratic_forces(r, &s.q, &s.qd),
            dr::gravity_forces(r, &s.q, &g),
            dr::end_effector_forces(r, &s.q, &s.f_tip),
        ];
        let sum = terms.iter().fold(DVector::zeros(nv), |a, t| a + t);
        let abs = 1e-13 * terms.iter().map(|t| amax(t.as_slice())).fold(1.0, f64::max);
        max.note(
            "τ − (M ν̇ + c + g + J_bᵀF)",
            check_tol(
                &format!("tree {k} τ"),
                sum.as_slice(),
                tau.as_slice(),
                1e-9,
                abs,
            ),
        );
        let zero = vec![0.0; nv];
        let via_id = dr::inverse_dynamics(r, &s.q, &zero, &zero, &Vector3::zeros(), &s.f_tip);
        max.note(
            "J_bᵀF − ID(0, 0, 0, F)",
            check(
                &format!("tree {k} J_bᵀF"),
                terms[3].as_slice(),
                via_id.as_slice(),
            ),
        );
        for j in 0..nv {
            let mut e_j = zero.clone();
            e_j[j] = 1.0;
            let col =
                dr::inverse_dynamics(r, &s.q, &zero, &e_j, &Vector3::zeros(), &Vector6::zeros());
            max.note(
                "M e_j − ID(q, 0, e_j)",
                check(
                    &format!("tree {k} column {j}"),
                    m.column(j).into_owned().as_slice(),
                    col.as_slice(),
                ),
            );
        }
    }
    assert!(branched > 150, "{branched} of 240 trees branch");
    max.report("random trees");
}

/// forward_dynamics(q, ν, ID(q, ν, ν̇)) = ν̇, with gravity and a tip wrench.
#[test]
fn forward_dynamics_inverts_inverse_dynamics() {
    let mut max = MaxErr::default();
    for (k, s) in samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let tau = dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip);
        let qdd = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &s.f_tip).unwrap();
        // Solving with M loses up to cond(M)·ε; scale the tolerance by cond(M) / 1e3.
        let eig = dr::mass_matrix(r, &s.q).symmetric_eigenvalues();
        let rel = 1e-9 * (eig.max() / eig.min() / 1e3).max(1.0);
        let e = check_tol(
            &format!("tree {k} FD(ID(ν̇))"),
            qdd.as_slice(),
            &s.qdd,
            rel,
            1e-12,
        );
        max.note("FD(ID(ν̇)) − ν̇", e);
    }
    max.report("random trees");
}

/// M is exactly symmetric and positive definite; `M_ij` is exactly 0 when joints i and j lie
/// on different branches, and so are the Jacobian columns of joints off the end effector's
/// path.
#[test]
fn mass_matrix_structure() {
    let mut min_ratio = f64::INFINITY;
    let mut zeros = 0;
    for (k, s) in samples().iter().enumerate() {
        let r = &s.robot;
        let off = r.nv() - r.dof();
        let m = dr::mass_matrix(r, &s.q);
        assert_eq!(m, m.transpose(), "tree {k}: M not symmetric");
        let eig = m.clone().symmetric_eigenvalues();
        assert!(eig.min() > 0.0, "tree {k}: eigenvalues {eig}");
        assert!(
            m.clone().cholesky().is_some(),
            "tree {k}: Cholesky of M fails"
        );
        min_ratio = min_ratio.min(eig.min() / eig.max());
        for i in 0..r.dof() {
            for j in 0..r.dof() {
                if !related(r, i, j) {
                    assert_eq!(m[(off + i, off + j)], 0.0, "tree {k}: M[{i}, {j}]");
                    zeros += 1;
                }
            }
        }
        let path = r.end_effector.parent.map_or(vec![], |p| r.path_to(p));
        let (j_s, j_b) = (dr::jacobian_space(r, &s.q), dr::jacobian_body(r, &s.q));
        for i in (0..r.dof()).filter(|i| !path.contains(i)) {
            assert!(
                j_s.column(off + i).iter().all(|x| *x == 0.0),
                "tree {k}: J_s column {i}"
            );
            assert!(
                j_b.column(off + i).iter().all(|x| *x == 0.0),
                "tree {k}: J_b column {i}"
            );
        }
    }
    assert!(zeros > 10_000, "only {zeros} entries between branches");
    eprintln!("random trees: {zeros} entries of M between branches, all 0.0; smallest eigenvalue ratio {min_ratio:.3e}");
}

/// `[V_s] = Ṫ T⁻¹` with `V_s = J_s ν` and Ṫ by central differences along `q̇(q, ν)` (step
/// 1e-6); `J_b = [Ad_{T⁻¹}] J_s`; the end effector's link pose times its home is its pose.
#[test]
fn jacobians_match_pose_derivative() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let r = &s.robot;
        let t = dr::end_effector_pose(r, &s.q);
        let t_dot = (dr::end_effector_pose(r, &shift(s, &s.qd, h))
            - dr::end_effector_pose(r, &shift(s, &s.qd, -h)))
            / (2.0 * h);
        let vs = t_dot * trans_inv(&t);
        let fd = [
            vs[(2, 1)],
            vs[(0, 2)],
            vs[(1, 0)],
            vs[(0, 3)],
            vs[(1, 3)],
            vs[(2, 3)],
        ];
        let j_s = dr::jacobian_space(r, &s.q);
        let v = &j_s * DVector::from_column_slice(&s.qd);
        for (x, y) in fd.iter().zip(v.iter()) {
            assert!(
                (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                "tree {k}: J_s ν {y} vs difference {x}"
            );
            max.note(
                "J_s ν − central difference",
                (x - y).abs() / y.abs().max(1.0),
            );
        }
        let from_s = DMatrix::from_fn(6, r.nv(), |i, j| {
            let ad_inv = adjoint(&trans_inv(&t));
            (0..6).map(|l| ad_inv[(i, l)] * j_s[(l, j)]).sum()
        });
        let j_b = dr::jacobian_body(r, &s.q);
        max.note(
            "J_b − Ad_{T⁻¹} J_s",
            check(&format!("tree {k} J_b"), j_b.as_slice(), from_s.as_slice()),
        );
        let link = match r.end_effector.parent {
            Some(p) => dr::link_poses(r, &s.q)[p],
            None => dr::base_pose(r, &s.q),
        };
        let t_link = link * r.end_effector.home;
        max.note(
            "T_link M − T",
            check(&format!("tree {k} poses"), t_link.as_slice(), t.as_slice()),
        );
    }
    max.report("random trees");
}

/// `g(q) = ∂P/∂q` along each velocity direction e_k (on a floating base along the base's
/// body twist), by central differences of P along `q̇(q, e_k)` (step 1e-6, ≤ 1e-7·‖g‖∞).
#[test]
fn gravity_forces_are_the_potential_gradient() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let grav = dr::gravity_forces(r, &s.q, &g);
        for i in 0..r.nv() {
            let mut e_i = vec![0.0; r.nv()];
            e_i[i] = 1.0;
            let fd = (dr::potential_energy(r, &shift(s, &e_i, h), &g)
                - dr::potential_energy(r, &shift(s, &e_i, -h), &g))
                / (2.0 * h);
            // Relative to the largest entry: P sums many terms, and its difference loses
            // about ε·|P|/h to rounding, which a small entry of g cannot absorb.
            let err = (fd - grav[i]).abs() / grav.amax().max(1.0);
            assert!(err <= 1e-7, "tree {k} dof {i}: g {} vs ∂P {fd}", grav[i]);
            max.note("g − ∂P (central difference)", err);
        }
    }
    max.report("random trees");
}

/// `c = C ν` (Christoffel C, with the floating base's Euler–Poincaré term, vs Newton–Euler c),
/// `Ṁ − 2C` skew, and the closed-form Ṁ against central differences of M along `q̇(q, ν)`
/// (step 1e-6).
#[test]
fn coriolis_matrix_and_mass_matrix_dot() {
    let mut max = MaxErr::default();
    let h = 1e-6;
    for (k, s) in small_samples().iter().enumerate() {
        let r = &s.robot;
        let qd = DVector::from_column_slice(&s.qd);
        let c_mat = dr::coriolis_matrix(r, &s.q, &s.qd);
        let c = dr::vel_quadratic_forces(r, &s.q, &s.qd);
        max.note(
            "C ν − c",
            check(
                &format!("tree {k} C ν"),
                (&c_mat * &qd).as_slice(),
                c.as_slice(),
            ),
        );

        let mdot = dr::mass_matrix_dot(r, &s.q, &s.qd);
        let n_mat = &mdot - &c_mat * 2.0;
        let skew = (&n_mat + n_mat.transpose()).amax();
        let scale = mdot.amax().max(c_mat.amax()).max(1.0);
        assert!(
            skew <= 1e-12 * scale,
            "tree {k}: Ṁ − 2C not skew: {skew:e} (scale {scale:e})"
        );
        max.note("skew(Ṁ − 2C) / scale", skew / scale);

        let fd = (dr::mass_matrix(r, &shift(s, &s.qd, h))
            - dr::mass_matrix(r, &shift(s, &s.qd, -h)))
            / (2.0 * h);
        for (x, y) in fd.iter().zip(mdot.iter()) {
            assert!(
                (x - y).abs() <= 1e-7 * y.abs().max(1.0),
                "tree {k}: Ṁ {y} vs central difference {x}"
            );
            max.note("Ṁ − central difference", (x - y).abs() / y.abs().max(1.0));
        }
    }
    max.report("random trees");
}

/// Power balance `νᵀ(M ν̇ + ½ Ṁ ν + g) = νᵀ τ` with ν̇ from forward dynamics of a random τ (no
/// tip wrench): `d/dt(K + P) = νᵀ τ`; and `K = ½ νᵀ M ν`.
#[test]
fn power_balance() {
    let mut max = MaxErr::default();
    for (k, s) in small_samples().iter().enumerate() {
        let (r, g) = (&s.robot, s.robot.gravity);
        let tau = DVector::from_column_slice(&s.qdd) * 3.0; // any force
        let tip = Vector6::zeros();
        let qdd = dr::forward_dynamics(r, &s.q, &s.qd, tau.as_slice(), &g, &tip).unwrap();
        let qd = DVector::from_column_slice(&s.qd);
        let m = dr::mass_matrix(r, &s.q);
        let terms = [
            &m * &qdd,
            dr::mass_matrix_dot(r, &s.q, &s.qd) * &qd * 0.5,
            dr::gravity_forces(r, &s.q, &g),
        ];
        let lhs: f64 = terms.iter().map(|t| qd.dot(t)).sum();
        let rhs = qd.dot(&tau);
        let scale: f64 =
            terms.iter().map(|t| qd.abs().dot(&t.abs())).sum::<f64>() + qd.abs().dot(&tau.abs());
        assert!(
            (lhs - rhs).abs() <= 1e-11 * scale.max(1.0),
            "tree {k}: power {lhs} vs {rhs}"
        );
        max.note("power balance / scale", (lhs - rhs).abs() / scale.max(1.0));
        let kin = dr::kinetic_energy(r, &s.q, &s.qd);
        assert!((kin - 0.5 * qd.dot(&(&m * &qd))).abs() <= 1e-12 * kin.max(1.0));
    }
    max.report("random trees");
}

/// A serial chain is the tree with `λ(i) = i − 1`, not a separate code path: every output on
/// 60 random chains (the chains of `random_chains.rs`) is bit for bit what the chain-only
/// reference gave before the trees (commit 17b07e7). The FNV-1a hash of the outputs' bits was
/// recorded from that reference; a change here means the numbers of serial chains changed.
#[test]
fn serial_chains_unchanged() {
    let mut out = String::new();
    let mut bits = |name: &str, x: &[f64]| {
        write!(out, "{name}:").unwrap();
        for v in x {
            write!(out, " {:016x}", v.to_bits()).unwrap();
        }
        out.push('\n');
    };
    for (k, s) in chains(0x5EED_D1CE, 60).iter().enumerate() {
        let (r, g, n) = (&s.robot, s.robot.gravity, s.robot.dof());
        bits(
            &format!("{k} id"),
            dr::inverse_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip).as_slice(),
        );
        bits(&format!("{k} m"), dr::mass_matrix(r, &s.q).as_slice());
        let fd = dr::forward_dynamics(r, &s.q, &s.qd, &s.qdd, &g, &s.f_tip).unwrap();
        bits(&format!("{k} fd"), fd.as_slice());
        bits(
            &format!("{k} g"),
            dr::gravity_forces(r, &s.q, &g).as_slice(),
        );
        bits(
            &format!("{k} c"),
            dr::vel_quadratic_forces(r, &s.q, &s.qd).as_slice(),
        );
        bits(
            &format!("{k} C"),
            dr::coriolis_matrix(r, &s.q, &s.qd).as_slice(),
        );
        bits(
            &format!("{k} Md"),
            dr::mass_matrix_dot(r, &s.q, &s.qd).as_slice(),
        );
        bits(&format!("{k} K"), &[dr::kinetic_energy(r, &s.q, &s.qd)]);
        bits(&format!("{k} P"), &[dr::potential_energy(r, &s.q, &g)]);
        for (i, t) in dr::link_poses(r, &s.q).iter().enumerate() {
            bits(&format!("{k} T{i}"), t.as_slice());
        }
        bits(
            &format!("{k} Tee"),
            dr::end_effector_pose(r, &s.q).as_slice(),
        );
        bits(&format!("{k} Js"), dr::jacobian_space(r, &s.q).as_slice());
        bits(&format!("{k} Jb"), dr::jacobian_body(r, &s.q).as_slice());
        bits(
            &format!("{k} Fee"),
            dr::end_effector_forces(r, &s.q, &s.f_tip).as_slice(),
        );
        let taumat = DMatrix::from_fn(5, n, |i, j| (0.3 * i as f64 + j as f64).sin());
        let ftipmat = DMatrix::from_fn(5, 6, |i, j| s.f_tip[j] * (0.1 * i as f64).cos());
        let (a, b) =
            dr::forward_dynamics_trajectory(r, &s.q, &s.qd, &taumat, &g, &ftipmat, 0.01, 3)
                .unwrap();
        bits(&format!("{k} traj"), a.as_slice());
        bits(&format!("{k} trajd"), b.as_slice());
        bits(
            &format!("{k} idtraj"),
            dr::inverse_dynamics_trajectory(r, &a, &b, &b, &g, &ftipmat).as_slice(),
        );
    }
    let hash = out.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    assert_eq!(out.len(), 511_900, "the outputs' text changed length");
    assert_eq!(
        hash, 0x4efc_e78d_e9c4_42e7,
        "serial-chain outputs are no longer bit-identical to the chain-only reference"
    );
}
