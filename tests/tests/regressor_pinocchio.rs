//! The inertial-parameter regressor ([`expand_regressor`], evaluated through the expression
//! graph) against Pinocchio 4.1.0's `computeJointTorqueRegressor`
//! (`data/reference/**/*.regressor.json`, made by `tools/regressor_reference.py`), on
//!
//! - the UR5, Panda, rand7 and double-pendulum URDFs (3 samples each),
//! - the TALOS upper body (fixed), Solo-12 and Unitree G1 (free flyer) trees (2 samples each),
//! - the 120 seeded random serial chains of `random_chains.derivatives.json` (1 state each).
//!
//! Per sample: `Y` entry by entry, the standard parameters π against Pinocchio's
//! `toDynamicParameters()` (same order, same frames: a URDF link's frame, `I` about its
//! origin), and `Y_b π_base = Y π = τ` (Pinocchio's `rnea`). Pinocchio's free flyer orders
//! the base velocity and wrench linear part first: rows 0..3 and 3..6 swap (the parameter
//! columns do not). ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12 per matrix and vector.

use dynamics_gen::expand::regressor::{expand_regressor, Regressor};
use dynamics_model::{Format, LoadOptions, Robot};
use dynamics_tests::{data_dir, eval_graph, from_pinocchio_order, pinocchio_index};
use dynamics_tests::{reference_json, rows, vecf};
use serde_json::Value;

const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;

/// Worst `‖x − y‖∞ / ‖y‖∞` seen, for the report.
#[derive(Default)]
struct Worst {
    y: f64,
    pi: f64,
    tau: f64,
    base_tau: f64,
    samples: usize,
}

fn close(what: &str, x: &[f64], y: &[f64]) -> f64 {
    let (err, scale) = dynamics_tests::assert_close(what, x, y, RTOL, ATOL);
    err / scale.max(1e-300)
}

fn compare(
    what: &str,
    robot: &Robot,
    floating: bool,
    pin_pi: &[f64],
    samples: &[&Value],
    w: &mut Worst,
) {
    assert_eq!(robot.base.floating, floating, "{what}: base");
    let r: Regressor = expand_regressor(robot);
    let (nv, p) = (r.nv, r.n_parameters());
    assert_eq!(p, pin_pi.len(), "{what}: number of parameters");
    w.pi =
        w.pi.max(close(&format!("{what}: π"), &r.parameters, pin_pi));
    let yb = r.base_y();
    let nb = r.base_columns.len();
    for (k, s) in samples.iter().enumerate() {
        let q = vecf(&s["q"]);
        let v = from_pinocchio_order(&s["v"], floating);
        let a = from_pinocchio_order(&s["a"], floating);
        let tau = from_pinocchio_order(&s["tau"], floating);
        let none: &[f64] = &[];
        let ys = eval_graph(&r.graph, &r.y, [&q, &v, &a, none]);
        let pin_y = rows(&s["Y"]);
        assert_eq!(pin_y.len(), nv * p, "{what}: Y size");
        let pin_y: Vec<f64> = (0..nv * p)
            .map(|e| pin_y[pinocchio_index(e / p, floating) * p + e % p])
            .collect();
        w.y =
            w.y.max(close(&format!("{what} sample {k}: Y"), &ys, &pin_y));
        let y_pi: Vec<f64> = (0..nv)
            .map(|i| (0..p).map(|j| ys[i * p + j] * r.parameters[j]).sum())
            .collect();
        w.tau = w
            .tau
            .max(close(&format!("{what} sample {k}: Y π"), &y_pi, &tau));
        let ybs = eval_graph(&r.graph, &yb, [&q, &v, &a, none]);
        let yb_pi: Vec<f64> = (0..nv)
            .map(|i| (0..nb).map(|j| ybs[i * nb + j] * r.base_values[j]).sum())
            .collect();
        w.base_tau = w.base_tau.max(close(
            &format!("{what} sample {k}: Y_b π_base"),
            &yb_pi,
            &tau,
        ));
        w.samples += 1;
    }
}

fn names(v: &Value) -> Vec<String> {
    v.as_array()
        .expect("names")
        .iter()
        .map(|x| x.as_str().expect("name").to_string())
        .collect()
}

fn check_generator(data: &Value) {
    assert_eq!(data["generator"]["pinocchio"].as_str(), Some("4.1.0"));
    assert_eq!(
        data["generator"]["script"].as_str(),
        Some("tools/regressor_reference.py")
    );
}

#[test]
fn regressor_reproduces_pinocchio_on_the_reference_robots() {
    let mut w = Worst::default();
    for name in ["ur5", "panda", "rand7", "double_pendulum"] {
        let data = reference_json(&format!("{name}.regressor.json"));
        check_generator(&data);
        let path = data_dir().join(format!("robots/{name}.urdf"));
        let robot = dynamics_model::load_file(&path, &LoadOptions::default()).expect("loads");
        assert_eq!(robot.joint_names(), names(&data["joint_names"]), "{name}");
        let samples: Vec<&Value> = data["samples"].as_array().expect("s").iter().collect();
        compare(
            name,
            &robot,
            false,
            &vecf(&data["parameters"]),
            &samples,
            &mut w,
        );
    }
    for (name, floating) in [
        ("talos_upper_body", false),
        ("solo12", true),
        ("g1_29dof", true),
    ] {
        let data = reference_json(&format!("trees/{name}.regressor.json"));
        check_generator(&data);
        let options = LoadOptions {
            floating_base: floating,
            ..Default::default()
        };
        let path = data_dir().join(format!("robots/trees/{name}.urdf"));
        let robot = dynamics_model::load_file(&path, &options).expect("loads");
        let mut pin_names = names(&data["joint_names"]);
        if floating {
            assert_eq!(pin_names.remove(0), "root_joint");
        }
        assert_eq!(robot.joint_names(), pin_names, "{name}: joint order");
        let samples: Vec<&Value> = data["samples"].as_array().expect("s").iter().collect();
        compare(
            name,
            &robot,
            floating,
            &vecf(&data["parameters"]),
            &samples,
            &mut w,
        );
    }
    assert_eq!(w.samples, 4 * 3 + 3 * 2);
    println!(
        "7 robots, {} samples: worst relative errors Y {:.1e}, π {:.1e}, Y π − τ {:.1e}, Y_b π_base − τ {:.1e}",
        w.samples, w.y, w.pi, w.tau, w.base_tau
    );
}

#[test]
fn regressor_reproduces_pinocchio_on_random_chains() {
    let data = reference_json("random_chains.regressor.json");
    check_generator(&data);
    let urdfs = reference_json("random_chains.derivatives.json");
    let chains = data["chains"].as_array().expect("chains");
    assert!(chains.len() >= 100, "{} random chains", chains.len());
    let mut w = Worst::default();
    for (chain, src) in chains
        .iter()
        .zip(urdfs["chains"].as_array().expect("chains"))
    {
        let name = chain["name"].as_str().expect("name");
        assert_eq!(src["name"].as_str(), Some(name));
        let urdf = src["urdf"].as_str().expect("urdf");
        let robot =
            dynamics_model::load::from_str(urdf, Format::Urdf, name, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        compare(
            name,
            &robot,
            false,
            &vecf(&chain["parameters"]),
            &[&chain["sample"]],
            &mut w,
        );
    }
    println!(
        "{} random chains: worst relative errors Y {:.1e}, π {:.1e}, Y π − τ {:.1e}, Y_b π_base − τ {:.1e}",
        w.samples, w.y, w.pi, w.tau, w.base_tau
    );
}
