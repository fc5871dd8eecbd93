//! The generated code of three kinematic trees against Pinocchio 4.1.0
//! (`data/reference/trees/`, see its README): the TALOS upper body on a fixed pelvis (three
//! branches), the Solo-12 quadruped and the Unitree G1 humanoid (29 joints) on a free-flyer
//! base. Every sample: M, c, g, nle = c + g, τ = rnea(q, v, a), and forward dynamics at
//! `tau_rand` (a wrench on the base included), ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12; the f32 copy of
//! Solo-12 (`f32_tree_solo12`) at f32's tolerances, 1e-4·‖y‖∞ (forward dynamics 1e-3).
//!
//! Pinocchio's free flyer orders the base velocity and wrench linear part first
//! (`v = (v_b, ω_b, θ̇)`, `τ = (f_b, m_b, τ_θ)`); ours angular first.
//! [`dynamics_tests::pinocchio_index`] maps the indices.

use dynamics_tests::vecf;
use dynamics_tests::{from_pinocchio_order, pinocchio_index, reference_json, Spec, CASES};

/// `(rtol, atol)` of the comparisons of `case`, and `rtol` of its forward dynamics: f64's
/// bound, or f32's (as `reference_files.rs` takes them).
fn tolerance(case: &dynamics_tests::Case) -> (f64, f64, f64) {
    if case.scalar == "f32" {
        (1e-4, 0.0, 1e-3)
    } else {
        (1e-9, 1e-12, 1e-9)
    }
}

#[test]
fn generated_trees_reproduce_pinocchio() {
    let (mut count, mut single) = (0, 0);
    for case in CASES {
        let Spec::UrdfTree(name, floating) = case.spec else {
            continue;
        };
        let data = reference_json(&format!("trees/{name}.json"));
        assert_eq!(data["floating"].as_bool(), Some(floating), "{name}");
        let robot = case.spec.robot();
        let mut names: Vec<&str> = data["joint_names"]
            .as_array()
            .expect("names")
            .iter()
            .map(|x| x.as_str().expect("name"))
            .collect();
        if floating {
            assert_eq!(names.remove(0), "root_joint");
        }
        assert_eq!(case.imp.joint_names(), names, "{name}: joint order");
        let nv = robot.nv();
        assert_eq!(data["nv"].as_u64(), Some(nv as u64), "{name}");
        let mut worst = [0.0f64; 6];
        for (k, s) in data["samples"]
            .as_array()
            .expect("samples")
            .iter()
            .enumerate()
        {
            let q = vecf(&s["q"]);
            let v = from_pinocchio_order(&s["v"], floating);
            let a = from_pinocchio_order(&s["a"], floating);
            let what = |w: &str| format!("{} sample {k}: {w}", case.module);
            let (rtol, atol, rtol_fd) = tolerance(case);
            let check_with = |rtol: f64, w: &str, x: &[f64], y: &[f64]| {
                let (err, scale) = dynamics_tests::assert_close(&what(w), x, y, rtol, atol);
                err / scale.max(1e-300)
            };
            let check = |w: &str, x: &[f64], y: &[f64]| check_with(rtol, w, x, y);
            let m = case.imp.mass_matrix(&q);
            let rows = s["M"].as_array().expect("M");
            let m_pin: Vec<f64> = (0..nv * nv)
                .map(|e| {
                    let (i, j) = (
                        pinocchio_index(e / nv, floating),
                        pinocchio_index(e % nv, floating),
                    );
                    rows[i][j].as_f64().expect("number")
                })
                .collect();
            let m_ours: Vec<f64> = (0..nv * nv).map(|e| m[(e / nv, e % nv)]).collect();
            worst[0] = worst[0].max(check("M", &m_ours, &m_pin));
            let c = case.imp.coriolis(&q, &v);
            worst[1] = worst[1].max(check(
                "c",
                c.as_slice(),
                &from_pinocchio_order(&s["c"], floating),
            ));
            let g = case.imp.gravity(&q);
            worst[2] = worst[2].max(check(
                "g",
                g.as_slice(),
                &from_pinocchio_order(&s["g"], floating),
            ));
            let nle: Vec<f64> = c.iter().zip(g.iter()).map(|(x, y)| x + y).collect();
            worst[3] = worst[3].max(check(
                "nle",
                &nle,
                &from_pinocchio_order(&s["nle"], floating),
            ));
            let tau = case.imp.inverse_dynamics(&q, &v, &a);
            worst[4] = worst[4].max(check(
                "τ",
                tau.as_slice(),
                &from_pinocchio_order(&s["tau"], floating),
            ));
            let tau_rand = from_pinocchio_order(&s["tau_rand"], floating);
            let fd = case.imp.forward_dynamics(&q, &v, &tau_rand);
            let a_fd = from_pinocchio_order(&s["a_fd"], floating);
            worst[5] = worst[5].max(check_with(rtol_fd, "a_fd", fd.as_slice(), &a_fd));
            // Structural zeros are exact zeros.
            let zeros = m_ours.iter().filter(|x| **x == 0.0).count();
            assert!(zeros as u64 >= s["M_structural_zero_count"].as_u64().expect("count"));
        }
        println!(
            "{}: worst relative errors (M, c, g, nle, τ, ν̇) {worst:?}",
            case.module
        );
        match case.scalar {
            "f32" => single += 1,
            _ => count += 1,
        }
    }
    assert_eq!(count, 3, "the three trees are compiled");
    assert_eq!(single, 1, "Solo-12 is compiled in f32 too");
}

/// The named frames (every leaf link of the URDF, the default on a tree) against Pinocchio's
/// `oMf` and `getFrameJacobian` in `LOCAL` (our body Jacobian) and `WORLD` (our space
/// Jacobian) at every sample (`data/reference/trees/<robot>.frames.json`, made by
/// `tools/frame_reference.py`): rows (v, ω) → (ω, v), columns mapped as the velocity.
#[test]
fn generated_frames_reproduce_pinocchio() {
    let mut worst = [0.0f64; 3];
    let mut count = 0;
    for case in CASES {
        let Spec::UrdfTree(name, floating) = case.spec else {
            continue;
        };
        let data = reference_json(&format!("trees/{name}.frames.json"));
        let names: Vec<&str> = data["frames"]
            .as_array()
            .expect("frames")
            .iter()
            .map(|x| x.as_str().expect("name"))
            .collect();
        let ours = case.imp.frame_names();
        let mut sorted = ours.clone();
        sorted.sort_unstable();
        let mut theirs = names.clone();
        theirs.sort_unstable();
        assert_eq!(
            sorted, theirs,
            "{name}: the default frames are the leaf links"
        );
        let nv = case.imp.nv();
        for (k, s) in data["samples"]
            .as_array()
            .expect("samples")
            .iter()
            .enumerate()
        {
            let q = vecf(&s["q"]);
            let poses = case.imp.frame_poses(&q);
            let bodies = case.imp.frame_jacobians_body(&q);
            let spaces = case.imp.frame_jacobians_space(&q);
            for (f, frame) in names.iter().enumerate() {
                let i = ours.iter().position(|x| x == frame).expect("frame");
                let what = |w: &str| format!("{} sample {k} frame {frame}: {w}", case.module);
                let (rtol, atol, _) = tolerance(case);
                let pose: Vec<f64> = s["oMf"][f]
                    .as_array()
                    .expect("rows")
                    .iter()
                    .flat_map(vecf)
                    .collect();
                let ours_pose: Vec<f64> = (0..16).map(|e| poses[i][(e / 4, e % 4)]).collect();
                let mut check = |slot: usize, w: &str, x: &[f64], y: &[f64]| {
                    let (err, scale) = dynamics_tests::assert_close(&what(w), x, y, rtol, atol);
                    if case.scalar == "f64" {
                        worst[slot] = worst[slot].max(err / scale.max(1e-300));
                    }
                };
                check(0, "oMf", &ours_pose, &pose);
                for (slot, key, j) in [(1, "J_local", &bodies[i]), (2, "J_world", &spaces[i])] {
                    let rows = s[key][f].as_array().expect("rows");
                    let theirs: Vec<f64> = (0..6 * nv)
                        .map(|e| {
                            let (r, c) = (e / nv, e % nv);
                            rows[(r + 3) % 6][pinocchio_index(c, floating)]
                                .as_f64()
                                .expect("number")
                        })
                        .collect();
                    let x: Vec<f64> = (0..6 * nv).map(|e| j[(e / nv, e % nv)]).collect();
                    check(slot, key, &x, &theirs);
                }
                // The f64 trees' frame samples (the f32 copy's are checked, not counted).
                count += usize::from(case.scalar == "f64");
            }
        }
    }
    assert!(count >= 3 * 20 * 4, "{count} frame samples");
    println!(
        "{count} frame samples: worst relative errors pose {:e}, J_b (LOCAL) {:e}, J_s (WORLD) {:e}",
        worst[0], worst[1], worst[2]
    );
}
