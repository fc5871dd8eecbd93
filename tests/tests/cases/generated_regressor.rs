//! The generated regressor functions of every compiled robot that has them
//! ([`REGRESSOR_CASES`]: shipped, reference URDFs, random chains 1–12 joints, random trees
//! with fixed and floating bases, mimic joints, armature and friction; Newton–Euler and
//! Lagrangian files; f64 and f32, std and `no_std`) at seeded random states:
//!
//! - `inertial_parameters()` = the ten standard parameters of each body read off the model's
//!   spatial inertias (a floating base first), in Pinocchio's order;
//! - `regressor(q, q̇, q̈) · π` = the *reference implementation*'s inverse dynamics of the
//!   robot without its rotors (`Y` leaves the armature out) and without friction;
//! - for a random `π`: `base_regressor · base_parameters(π) = regressor · π` (the regrouping
//!   holds for every parameter vector, not only the robot's own), and for the robot's own.
//!
//! f64: ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12 (1e-9 for the random π, whose entries reach 1 where the
//! robot's are small); f32: 2e-3·‖y‖∞ + 1e-4.

use dynamics_model::random::Rng;
use dynamics_model::Robot;
use dynamics_tests::{Case, CASES, REGRESSOR_CASES};
use nalgebra::{DVector, Vector6};

/// The standard parameters `(m, h, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)` of a 6×6 spatial
/// inertia `[[I, [h]], [[h]ᵀ, m]]`.
fn parameters_of(g: &nalgebra::Matrix6<f64>) -> [f64; 10] {
    [
        g[(3, 3)],
        g[(2, 4)],
        g[(0, 5)],
        g[(1, 3)],
        g[(0, 0)],
        g[(0, 1)],
        g[(1, 1)],
        g[(0, 2)],
        g[(1, 2)],
        g[(2, 2)],
    ]
}

fn random_state(rng: &mut Rng, r: &Robot) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q: Vec<f64> = (0..r.nq()).map(|_| rng.uniform(-2.0, 2.0)).collect();
    if r.base.floating {
        let n = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= n);
    }
    let v = (0..r.nv()).map(|_| rng.uniform(-1.5, 1.5)).collect();
    let a = (0..r.nv()).map(|_| rng.uniform(-1.5, 1.5)).collect();
    (q, v, a)
}

#[test]
fn generated_regressors_reproduce_the_reference() {
    assert!(
        REGRESSOR_CASES.len() >= 40,
        "{} cases",
        REGRESSOR_CASES.len()
    );
    let mut worst = [[0.0f64; 4]; 2];
    for (module, imp) in REGRESSOR_CASES {
        let case: &Case = CASES.iter().find(|c| c.module == *module).expect("case");
        let f32 = case.scalar == "f32";
        let (rtol, atol) = if f32 { (2e-3, 1e-4) } else { (1e-10, 1e-12) };
        let robot = case.spec.robot();
        let worst = &mut worst[f32 as usize];
        // π off the model.
        let mut pi: Vec<f64> = Vec::new();
        if robot.base.floating {
            pi.extend(parameters_of(&robot.base.inertia.0));
        }
        for l in &robot.links {
            pi.extend(parameters_of(&l.inertia.0));
        }
        let own = imp.inertial_parameters();
        let (e, s) = dynamics_tests::assert_close(
            &format!("{module}: inertial_parameters"),
            own.as_slice(),
            &pi,
            if f32 { 1e-6 } else { 1e-15 },
            if f32 { 1e-7 } else { 1e-15 },
        );
        worst[0] = worst[0].max(e / s.max(1e-300));
        assert_eq!(imp.parameter_names().len(), pi.len(), "{module}: names");
        let mut rigid = robot.clone();
        rigid.joints.iter_mut().for_each(|j| j.rotor_inertia = 0.0);
        let pi = DVector::from_vec(pi);
        let mut rng = Rng::new(0x7E57);
        let random_pi = DVector::from_fn(pi.len(), |_, _| rng.uniform(-1.0, 1.0));
        for k in 0..3 {
            let (q, v, a) = random_state(&mut rng, &robot);
            let tau = dynamics_reference::inverse_dynamics(
                &rigid,
                &q,
                &v,
                &a,
                &rigid.gravity,
                &Vector6::zeros(),
            );
            let y = imp.regressor(&q, &v, &a);
            let what = format!("{module} state {k}");
            let (e, s) = dynamics_tests::assert_close(
                &format!("{what}: Y π"),
                (&y * &pi).as_slice(),
                tau.as_slice(),
                rtol,
                atol,
            );
            worst[1] = worst[1].max(e / s.max(1e-300));
            let yb = imp.base_regressor(&q, &v, &a);
            assert_eq!(yb.nrows(), y.nrows(), "{what}");
            let (e, s) = dynamics_tests::assert_close(
                &format!("{what}: Y_b π_base"),
                (&yb * imp.base_parameters(pi.as_slice())).as_slice(),
                tau.as_slice(),
                rtol,
                atol,
            );
            worst[2] = worst[2].max(e / s.max(1e-300));
            let (e, s) = dynamics_tests::assert_close(
                &format!("{what}: Y_b π_base of a random π"),
                (&yb * imp.base_parameters(random_pi.as_slice())).as_slice(),
                (&y * &random_pi).as_slice(),
                if f32 { rtol } else { 1e-9 },
                atol,
            );
            worst[3] = worst[3].max(e / s.max(1e-300));
        }
    }
    for (scalar, w) in ["f64", "f32"].iter().zip(worst) {
        println!(
            "{} cases, {scalar}: worst relative errors π {:.1e}, Y π − τ {:.1e}, Y_b π_base − τ {:.1e}, random π {:.1e}",
            REGRESSOR_CASES.len(),
            w[0],
            w[1],
            w[2],
            w[3]
        );
    }
}
