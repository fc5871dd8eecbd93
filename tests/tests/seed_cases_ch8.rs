//! The reference implementation against the exact chapter-8 seed cases 8.6–8.10 of
//! `data/seed-cases.json` (see `data/seed-cases.md`, §6–§8): Jacobian derivatives (8.6),
//! Ṁ in closed form (8.7), the apparent mass of a planar 2R arm (8.8), the optimal gear ratio
//! with the armature (8.9) and the constrained dynamics of Exercise 8.10.

use dynamics_model::lie::ad;
use dynamics_model::Robot;
use dynamics_reference as dr;
use dynamics_tests::data_dir;
use dynamics_tests::vecf;
use nalgebra::{DMatrix, DVector, Matrix2, Matrix4, Matrix6, Vector2, Vector3, Vector6};
use serde_json::Value;

fn seed() -> Value {
    let text = std::fs::read_to_string(data_dir().join("seed-cases.json")).expect("seed cases");
    serde_json::from_str(&text).expect("json")
}

/// A row-major JSON matrix.
fn mat(v: &Value) -> DMatrix<f64> {
    let r: Vec<Vec<f64>> = v.as_array().expect("rows").iter().map(vecf).collect();
    DMatrix::from_fn(r.len(), r[0].len(), |i, j| r[i][j])
}

fn mat4(v: &Value) -> Matrix4<f64> {
    let m = mat(v);
    Matrix4::from_fn(|i, j| m[(i, j)])
}

fn mat6(v: &Value) -> Matrix6<f64> {
    let m = mat(v);
    Matrix6::from_fn(|i, j| m[(i, j)])
}

fn vec6(v: &[f64]) -> Vector6<f64> {
    Vector6::from_column_slice(v)
}

/// `‖x − y‖∞ ≤ 1e-9·max(1, ‖y‖∞)` (seed-cases.md §0); returns `‖x − y‖∞`.
fn check(what: &str, x: &[f64], y: &[f64]) -> f64 {
    let (err, scale) = dynamics_tests::max_error(x, y);
    assert!(
        err <= 1e-9 * scale.max(1.0) && x.iter().all(|v| v.is_finite()),
        "{what}: error {err:e}\n got {x:?}\nwant {y:?}"
    );
    err
}

/// A model of the book's lists: `Mlist`, `Glist`, `Slist` (screws as rows), `gravity`.
fn model_robot(model: &Value) -> Robot {
    let m_list: Vec<_> = model["Mlist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat4)
        .collect();
    let g_list: Vec<_> = model["Glist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat6)
        .collect();
    let s_list: Vec<_> = model["Slist"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| vec6(&vecf(s)))
        .collect();
    let g = Vector3::from_column_slice(&vecf(&model["gravity"]));
    Robot::from_mr_lists(&m_list, &g_list, &s_list, g).expect("valid seed model")
}

// ---------------------------------------------------------------------------------------------
// 8.6: ∂J_s,i/∂θ_j = [ad_{J_s,j}] J_s,i (i > j), ∂J_b,i/∂θ_j = [ad_{J_b,i}] J_b,j (i < j).

#[test]
fn ex8_6_jacobian_derivatives() {
    let ex = &seed()["exercises"]["ex8_6_jacobian_derivatives"];
    let s_list: Vec<_> = ex["Slist"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| vec6(&vecf(s)))
        .collect();
    let n = s_list.len();
    // The Jacobians need only the screws and the end effector's home; unit inertias.
    let mut m_list = vec![Matrix4::identity(); n];
    m_list.push(mat4(&ex["M_home"]));
    let g_list = vec![Matrix6::identity(); n];
    let robot = Robot::from_mr_lists(&m_list, &g_list, &s_list, Vector3::zeros()).expect("valid");
    // Blist = Ad_{M⁻¹} S_i, as the source lists them.
    for (b, want) in robot
        .body_frame_screws()
        .iter()
        .zip(ex["Blist"].as_array().unwrap())
    {
        check("Blist", b.as_slice(), &vecf(want));
    }
    let theta = vecf(&ex["theta"]);
    let js = dr::jacobian_space(&robot, &theta);
    let jb = dr::jacobian_body(&robot, &theta);
    let mut worst = [0.0f64; 4];
    worst[0] = check("J_s", js.as_slice(), mat(&ex["Js_expected"]).as_slice());
    worst[1] = check("J_b", jb.as_slice(), mat(&ex["Jb_expected"]).as_slice());

    // J̇(θ, e_j) has ∂J_i/∂θ_j in column i; the JSON tensor is [i][j] = ∂(column i)/∂θ_j.
    let ds = ex["dJs_dtheta_expected"].as_array().unwrap();
    let db = ex["dJb_dtheta_expected"].as_array().unwrap();
    let mut sum_s = DMatrix::zeros(6, n);
    let mut sum_b = DMatrix::zeros(6, n);
    let theta_dot = [0.7, -1.2, 0.4, 2.0];
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let js_dot = dr::jacobian_space_dot(&robot, &theta, &e);
        let jb_dot = dr::jacobian_body_dot(&robot, &theta, &e);
        for i in 0..n {
            let col_s: Vec<f64> = js_dot.column(i).iter().copied().collect();
            let col_b: Vec<f64> = jb_dot.column(i).iter().copied().collect();
            let e_s = check(
                &format!("∂J_s,{}/∂θ_{}", i + 1, j + 1),
                &col_s,
                &vecf(&ds[i][j]),
            );
            let e_b = check(
                &format!("∂J_b,{}/∂θ_{}", i + 1, j + 1),
                &col_b,
                &vecf(&db[i][j]),
            );
            worst[2] = worst[2].max(e_s);
            worst[3] = worst[3].max(e_b);
            // Zero exactly where the exercise says so.
            if i <= j {
                assert!(col_s.iter().all(|x| *x == 0.0));
            }
            if i >= j {
                assert!(col_b.iter().all(|x| *x == 0.0));
            }
        }
        sum_s += js_dot * theta_dot[j];
        sum_b += jb_dot * theta_dot[j];
    }
    // J̇ at any θ̇ is Σ_j ∂J/∂θ_j θ̇_j.
    let js_dot = dr::jacobian_space_dot(&robot, &theta, &theta_dot);
    let jb_dot = dr::jacobian_body_dot(&robot, &theta, &theta_dot);
    check("J̇_s", js_dot.as_slice(), sum_s.as_slice());
    check("J̇_b", jb_dot.as_slice(), sum_b.as_slice());
    // The printed values of §6: ∂J_s,4/∂θ_2, ∂J_s,4/∂θ_3, ∂J_b,1/∂θ_3, ∂J_b,2/∂θ_4.
    let unit = |j: usize| {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        e
    };
    let col = |m: DMatrix<f64>, i: usize| -> Vec<f64> { m.column(i).iter().copied().collect() };
    check(
        "∂J_s,4/∂θ_2 (printed)",
        &col(dr::jacobian_space_dot(&robot, &theta, &unit(1)), 3),
        &[
            0.296792388837658,
            0.399960631346178,
            -0.321836924042141,
            0.135953481355708,
            -0.197836023634373,
            -0.109505006817671,
        ],
    );
    check(
        "∂J_s,4/∂θ_3 (printed)",
        &col(dr::jacobian_space_dot(&robot, &theta, &unit(2)), 3),
        &[
            -0.187879654899778,
            -0.969262737014469,
            -0.126550313748961,
            0.123469022765533,
            0.0519404214581288,
            -0.456713466288553,
        ],
    );
    check(
        "∂J_b,1/∂θ_3 (printed)",
        &col(dr::jacobian_body_dot(&robot, &theta, &unit(2)), 0),
        &[
            -0.126598951811307,
            -0.397403966464243,
            0.0911405063829179,
            -0.300989045591038,
            -0.0926861827813558,
            -0.418812413662541,
        ],
    );
    check(
        "∂J_b,2/∂θ_4 (printed)",
        &col(dr::jacobian_body_dot(&robot, &theta, &unit(3)), 1),
        &[
            -0.448964187660327,
            -0.179878075223855,
            0.343086389453105,
            -0.422170649816286,
            0.62692610971402,
            -0.234061015669908,
        ],
    );
    // Slip 13 of the source: the reversed bracket ad_{J_i}(J_j) has the opposite sign.
    let j2 = vec6(&col(js.clone(), 1));
    let j4 = vec6(&col(js.clone(), 3));
    let wrong = ad(&j4) * j2;
    let right = vec6(&vecf(&ds[3][1]));
    assert!((wrong + right).amax() < 1e-12);
    println!("8.6: worst |error| J_s {:.1e}, J_b {:.1e}, ∂J_s {:.1e}, ∂J_b {:.1e}; reversed bracket off by {:.2}",
        worst[0], worst[1], worst[2], worst[3], (wrong - right).amax());
}

// ---------------------------------------------------------------------------------------------
// 8.7: Ṁ in closed form.

#[test]
fn ex8_7_mass_matrix_derivative() {
    let file = seed();
    let pendulum = model_robot(&file["models"]["rotational_pendulum_ex8_4"]);
    let (q, qd) = ([0.3, -1.1], [0.7, -0.4]);
    let mdot = dr::mass_matrix_dot(&pendulum, &q, &qd);
    let (s2, c2) = q[1].sin_cos();
    let closed = [
        12.0 * s2 * c2 * qd[1],
        -2.0 * s2 * qd[1],
        -2.0 * s2 * qd[1],
        0.0,
    ];
    let printed = [
        1.9403913691670165,
        -0.7129658880491483,
        -0.7129658880491483,
        0.0,
    ];
    let mut worst = check("pendulum Ṁ (closed form)", mdot.as_slice(), &closed);
    worst = worst.max(check("pendulum Ṁ (printed)", mdot.as_slice(), &printed));

    let r3 = model_robot(&file["models"]["spatial_3R"]);
    let (q, qd) = ([0.3, -0.7, 1.2], [0.5, -1.0, 0.8]);
    let mdot = dr::mass_matrix_dot(&r3, &q, &qd);
    let u = [
        1.0617351175614318,
        0.8487459836738495,
        0.5754467803248755,
        0.8788148604776629,
        0.33569575986472766,
        0.0,
    ];
    let want = DMatrix::from_row_slice(
        3,
        3,
        &[u[0], u[1], u[2], u[1], u[3], u[4], u[2], u[4], u[5]],
    );
    worst = worst.max(check("3R Ṁ (printed)", mdot.as_slice(), want.as_slice()));
    assert_eq!(
        mdot[(2, 2)],
        0.0,
        "M_33 is constant: joint 3 is the last joint"
    );

    // Every sample's Mdot, and Ṁ − 2C skew with c = Cq̇.
    for name in ["rotational_pendulum_ex8_4", "spatial_3R", "spatial_RPR"] {
        let model = &file["models"][name];
        let robot = model_robot(model);
        for (k, s) in model["samples"].as_array().unwrap().iter().enumerate() {
            let (q, qd) = (vecf(&s["q"]), vecf(&s["qd"]));
            let mdot = dr::mass_matrix_dot(&robot, &q, &qd);
            worst = worst.max(check(
                &format!("{name} sample {k} Ṁ"),
                mdot.as_slice(),
                mat(&s["Mdot"]).as_slice(),
            ));
            let c = dr::coriolis_matrix(&robot, &q, &qd);
            let skew = &mdot - &c * 2.0;
            let sym = &skew + skew.transpose();
            assert!(
                sym.amax() <= 1e-12 * (1.0 + mdot.amax()),
                "{name} {k}: Ṁ − 2C not skew"
            );
            check(
                &format!("{name} sample {k} Cq̇"),
                (&c * DVector::from_vec(qd.clone())).as_slice(),
                &vecf(&s["c"]),
            );
        }
    }
    println!("8.7: worst |error| of Ṁ {worst:.1e}");
}

// ---------------------------------------------------------------------------------------------
// 8.8: apparent end-effector mass of the planar 2R arm.

#[test]
fn ex8_8_task_space_apparent_mass_2r() {
    let ex = &seed()["exercises"]["ex8_8_task_space_apparent_mass_2R"];
    let robot = model_robot(&ex["model"]);
    let (m1, m2) = (3.0, 2.0);
    let mut worst = 0.0f64;
    for case in ex["cases"].as_array().unwrap() {
        let theta = vecf(&case["theta_rad"]);
        let label = format!("θ = {:?}°", vecf(&case["theta_deg"]));
        let m = dr::mass_matrix(&robot, &theta);
        worst = worst.max(check(
            &format!("{label} M"),
            m.as_slice(),
            mat(&case["M_expected"]).as_slice(),
        ));
        // The planar Jacobian of the tip position: ṗ = R_{0,ee} (J_b rows v), x and y rows.
        let t = dr::end_effector_pose(&robot, &theta);
        let r = t.fixed_view::<3, 3>(0, 0).into_owned();
        let jb = dr::jacobian_body(&robot, &theta);
        let jv = r * jb.fixed_view::<3, 2>(3, 0);
        let j = Matrix2::new(jv[(0, 0)], jv[(0, 1)], jv[(1, 0)], jv[(1, 1)]);
        let (s1, c1) = theta[0].sin_cos();
        let (s12, c12) = (theta[0] + theta[1]).sin_cos();
        let j_book = Matrix2::new(-s1 - s12, -s12, c1 + c12, c12);
        check(&format!("{label} J"), j.as_slice(), j_book.as_slice());
        assert!(jv.row(2).amax() < 1e-15, "planar");
        // Λ = J⁻ᵀ M J⁻¹.
        let m2x2 = Matrix2::new(m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]);
        let j_inv = j.try_inverse().expect("not singular");
        let lambda = j_inv.transpose() * m2x2 * j_inv;
        worst = worst.max(check(
            &format!("{label} Λ"),
            lambda.as_slice(),
            mat(&case["Lambda_expected"]).as_slice(),
        ));
        // Eigenvalues m2 (across link 2) and m2 + m1/sin²θ2 (along it).
        let along = m2 + m1 / theta[1].sin().powi(2);
        let mut eig: Vec<f64> = lambda.symmetric_eigenvalues().iter().copied().collect();
        eig.sort_by(f64::total_cmp);
        worst = worst.max(check(&format!("{label} eigenvalues"), &eig, &[m2, along]));
        check(
            &format!("{label} along link 2"),
            &[along],
            &[case["apparent_mass_along_link2"].as_f64().unwrap()],
        );
        let u = Vector2::new(c12, s12);
        let n = Vector2::new(-s12, c12);
        check(&format!("{label} uᵀΛu"), &[u.dot(&(lambda * u))], &[along]);
        check(
            &format!("{label} nᵀΛn"),
            &[n.dot(&(lambda * n))],
            &[case["apparent_mass_normal_to_link2"].as_f64().unwrap()],
        );
        let dir = case["link2_direction_deg"].as_f64().unwrap();
        assert!(
            ((theta[0] + theta[1]).to_degrees() - dir).abs() < 1e-9,
            "{label}: link 2 direction"
        );
        // nv = 2 < 6: no 6×6 task-space mass matrix.
        assert!(dr::task_space_mass_matrix(&robot, &theta).is_none());
    }
    println!("8.8: worst |error| of M, Λ, eigenvalues {worst:.1e}");
}

// ---------------------------------------------------------------------------------------------
// 8.9: optimal gear ratio.

/// One revolute joint about z through the link's centre of mass, `I_zz = i_link`, no gravity,
/// with a rotor of inertia `i_rotor` behind a gear of ratio `gear`.
fn geared_link(i_link: f64, i_rotor: f64, gear: f64) -> Robot {
    let g1 = Matrix6::from_diagonal(&Vector6::new(i_link, i_link, i_link, 1.0, 1.0, 1.0));
    let s1 = Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
    let mut robot = Robot::from_mr_lists(
        &[Matrix4::identity(), Matrix4::identity()],
        &[g1],
        &[s1],
        Vector3::zeros(),
    )
    .expect("valid");
    robot.joints[0].rotor_inertia = i_rotor;
    robot.joints[0].gear_ratio = gear;
    robot
}

#[test]
fn ex8_9_optimal_gear_ratio() {
    let ex = &seed()["exercises"]["ex8_9_optimal_gear_ratio"];
    let tau_m = ex["tau_m"].as_f64().unwrap();
    let i_link = ex["I_link"].as_f64().unwrap();
    let i_rotor = ex["I_rotor"].as_f64().unwrap();
    let g_opt = dynamics_model::optimal_gear_ratio(i_link, i_rotor);
    check("G*", &[g_opt], &[ex["G_opt_expected"].as_f64().unwrap()]);
    // θ̈(G) from the reference forward dynamics: the joint torque is G τ_m, M = I_link + G² I_rotor.
    let acc = |gear: f64| -> f64 {
        let robot = geared_link(i_link, i_rotor, gear);
        let qdd = dr::forward_dynamics(
            &robot,
            &[0.4],
            &[1.3],
            &[gear * tau_m],
            &robot.gravity,
            &Vector6::zeros(),
        )
        .expect("positive definite");
        qdd[0]
    };
    let mut worst = check(
        "θ̈(G*)",
        &[acc(g_opt)],
        &[ex["acc_at_opt_expected"].as_f64().unwrap()],
    );
    for s in ex["acc_samples"].as_array().unwrap() {
        let gear = s["G"].as_f64().unwrap();
        worst = worst.max(check(
            &format!("θ̈({gear})"),
            &[acc(gear)],
            &[s["acc_expected"].as_f64().unwrap()],
        ));
        // θ̈(G) = θ̈(G*²/G).
        check(
            &format!("θ̈({gear}) = θ̈(G*²/G)"),
            &[acc(g_opt * g_opt / gear)],
            &[acc(gear)],
        );
    }
    // G* is a maximum.
    for f in [0.9, 0.99, 1.01, 1.1] {
        assert!(acc(g_opt * f) < acc(g_opt), "θ̈({}) ≥ θ̈(G*)", g_opt * f);
    }
    // The closed form θ̈(G*) = τ_m / (2√(I_link I_rotor)).
    check(
        "θ̈(G*) closed form",
        &[acc(g_opt)],
        &[tau_m / (2.0 * (i_link * i_rotor).sqrt())],
    );
    println!("8.9: G* = {g_opt}, worst |error| of θ̈ {worst:.1e}");
}

// ---------------------------------------------------------------------------------------------
// 8.10: constrained dynamics.

/// Three prismatic joints whose constant mass matrix is Exercise 8.10's
/// `M = [[4, 1, 0], [1, 3, 1], [0, 1, 2]]` and whose gravity force is its `h = (0.5, −1, 2)`
/// (c = 0: nothing rotates). With directions d_i and masses m_k (links 1, 2, 3):
/// `M_ij = (Σ_{k ≥ max(i, j)} m_k) d_i·d_j`, `g_i = −(Σ_{k ≥ i} m_k) d_i·g₀`. Masses (1, 1, 2),
/// `d1 = x`, `d3 = z`, `d2 = (1/3, √23/6, 1/2)` give M; `g₀ = (−1/8, 21/(4√23), −1)` gives h.
fn prismatic_3() -> Robot {
    let r23 = 23.0f64.sqrt();
    let dirs = [
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(1.0 / 3.0, r23 / 6.0, 0.5),
        Vector3::new(0.0, 0.0, 1.0),
    ];
    let s_list: Vec<_> = dirs
        .iter()
        .map(|d| Vector6::new(0.0, 0.0, 0.0, d.x, d.y, d.z))
        .collect();
    let g_list: Vec<_> = [1.0, 1.0, 2.0]
        .iter()
        .map(|&m| Matrix6::from_diagonal(&Vector6::new(0.1, 0.1, 0.1, m, m, m)))
        .collect();
    let gravity = Vector3::new(-1.0 / 8.0, 21.0 / (4.0 * r23), -1.0);
    Robot::from_mr_lists(&[Matrix4::identity(); 4], &g_list, &s_list, gravity).expect("valid")
}

#[test]
fn ex8_10_constrained_dynamics() {
    let ex = &seed()["exercises"]["ex8_10_constrained_dynamics_projection"];
    let robot = prismatic_3();
    let (q, qd) = ([0.1, -0.2, 0.3], [0.7, -0.2, 0.4]);
    let m = dr::mass_matrix(&robot, &q);
    let h = dr::inverse_dynamics(
        &robot,
        &q,
        &qd,
        &[0.0; 3],
        &robot.gravity,
        &Vector6::zeros(),
    );
    check("M", m.as_slice(), mat(&ex["M"]).as_slice());
    check("h", h.as_slice(), &vecf(&ex["h"]));
    let a = mat(&ex["A"]);
    let tau = vecf(&ex["tau"]);
    let (qdd, lambda) = dr::constrained_forward_dynamics(
        &robot,
        &q,
        &qd,
        &tau,
        &a,
        &DVector::zeros(1),
        &robot.gravity,
    )
    .expect("one independent constraint");
    let exact_qdd = [-5.0 / 36.0, 7.0 / 18.0, 23.0 / 36.0];
    let e1 = check("θ̈", qdd.as_slice(), &exact_qdd);
    check("θ̈ (JSON)", qdd.as_slice(), &vecf(&ex["qdd_expected"]));
    let e2 = check("λ", lambda.as_slice(), &[-2.0 / 3.0]);
    check("λ (JSON)", lambda.as_slice(), &vecf(&ex["lambda_expected"]));
    assert!((&a * &qdd).amax() < 1e-15, "Aθ̈ = 0");
    let lhs = &m * &qdd + &h;
    let rhs = DVector::from_vec(tau.clone()) + a.transpose() * &lambda;
    check("Mθ̈ + h = τ + Aᵀλ", lhs.as_slice(), rhs.as_slice());

    // P and P_θ̈ from the reference M, and their properties.
    let m_inv = m.clone().try_inverse().unwrap();
    let s_inv = (&a * &m_inv * a.transpose()).try_inverse().unwrap();
    let eye = DMatrix::<f64>::identity(3, 3);
    let p = &eye - a.transpose() * &s_inv * &a * &m_inv;
    let p_qdd = &eye - &m_inv * a.transpose() * &s_inv * &a;
    let e3 = check("P", p.as_slice(), mat(&ex["P_expected"]).as_slice());
    let e4 = check(
        "P_θ̈",
        p_qdd.as_slice(),
        mat(&ex["P_qdd_expected"]).as_slice(),
    );
    assert!((&p * a.transpose()).amax() < 1e-15, "PAᵀ = 0");
    assert!((&p * &p - &p).amax() < 1e-15 && (&p_qdd * &p_qdd - &p_qdd).amax() < 1e-15);
    assert!((&a * &p_qdd).amax() < 1e-15, "AP_θ̈ = 0");
    let tau_h = DVector::from_vec(tau) - &h;
    check(
        "θ̈ = P_θ̈ M⁻¹(τ − h)",
        qdd.as_slice(),
        (&p_qdd * &m_inv * &tau_h).as_slice(),
    );
    check(
        "P(τ − h) = PMθ̈",
        (&p * &tau_h).as_slice(),
        (&p * &m * &qdd).as_slice(),
    );
    println!("8.10: |error| θ̈ {e1:.1e}, λ {e2:.1e}, P {e3:.1e}, P_θ̈ {e4:.1e}");
}
