//! The symbolic derivatives of the dynamics ([`expand_derivatives`], evaluated through the
//! expression graph) against Pinocchio 4.1.0's analytical derivatives
//! (`data/reference/**/*.derivatives.json`, made by `tools/derivative_reference.py`):
//! `∂τ/∂q`, `∂τ/∂ν` (`computeRNEADerivatives`), `∂ν̇/∂q`, `∂ν̇/∂ν` (`computeABADerivatives`),
//! `M⁻¹` (`computeMinverse`) and `∂g/∂q` (`computeGeneralizedGravityDerivatives`), on
//!
//! - the UR5, Panda, rand7 and double-pendulum URDFs (5 samples each),
//! - the TALOS upper body (fixed), Solo-12 and Unitree G1 (free flyer) trees (3 samples each),
//! - ≥ 100 seeded random serial chains whose URDF text the file holds (2 states each).
//!
//! Derivatives with respect to q are in the tangent space on both sides (columns = velocity
//! directions). Pinocchio's free flyer orders the base velocity, acceleration and wrench
//! linear part first, `(v_b, ω_b)` and `(f_b, m_b)`, both in the base frame; ours angular
//! first: every matrix's rows and columns 0..3 and 3..6 swap ([`pin`]). The configuration q
//! (position, quaternion (x, y, z, w), joints) is the same on both sides.
//!
//! ‖x − y‖∞ ≤ 1e-8·‖y‖∞ + 1e-10 per matrix; the worst relative errors are printed
//! (`--nocapture`).

use dynamics_gen::expand::derivatives::expand_derivatives;
use dynamics_gen::expand::expand;
use dynamics_model::{Format, LoadOptions, Robot};
use dynamics_tests::{data_dir, eval_graph, from_pinocchio_order, pinocchio_index};
use dynamics_tests::{reference_json, rows, vecf};
use serde_json::Value;

const RTOL: f64 = 1e-8;
const ATOL: f64 = 1e-10;
/// The six quantities: Pinocchio's key and our name.
const QUANTITIES: [(&str, &str); 6] = [
    ("dtau_dq", "∂τ/∂q"),
    ("dtau_dv", "∂τ/∂ν"),
    ("ddq_dq", "∂ν̇/∂q"),
    ("ddq_dv", "∂ν̇/∂ν"),
    ("Minv", "M⁻¹"),
    ("dg_dq", "∂g/∂q"),
];

/// A Pinocchio nv×nv matrix in our order (rows and columns permuted), row-major.
fn ours_mat(v: &Value, nv: usize, floating: bool) -> Vec<f64> {
    let x = rows(v);
    assert_eq!(x.len(), nv * nv, "matrix size");
    (0..nv * nv)
        .map(|e| x[pinocchio_index(e / nv, floating) * nv + pinocchio_index(e % nv, floating)])
        .collect()
}

/// Below this `‖y‖∞` a matrix counts as zero (e.g. `∂τ/∂ν` of a one-joint chain, which has no
/// velocity terms): its error is reported as absolute, not relative.
const ZERO: f64 = 1e-8;

/// Per quantity: the worst relative error `‖x − y‖∞ / ‖y‖∞` over the non-zero matrices, the
/// worst absolute error `‖x − y‖∞` over the zero ones and their count, the worst fraction of
/// the tolerance used; and the number of samples.
#[derive(Default)]
struct Worst {
    rel: [f64; 6],
    zero_abs: [f64; 6],
    zeros: [usize; 6],
    of_tolerance: f64,
    samples: usize,
}

impl Worst {
    fn add(&mut self, slot: usize, err: f64, scale: f64) {
        if scale > ZERO {
            self.rel[slot] = self.rel[slot].max(err / scale);
        } else {
            self.zero_abs[slot] = self.zero_abs[slot].max(err);
            self.zeros[slot] += 1;
        }
        self.of_tolerance = self.of_tolerance.max(err / (RTOL * scale + ATOL));
    }

    fn merge(&mut self, other: &Worst) {
        for k in 0..6 {
            self.rel[k] = self.rel[k].max(other.rel[k]);
            self.zero_abs[k] = self.zero_abs[k].max(other.zero_abs[k]);
            self.zeros[k] += other.zeros[k];
        }
        self.of_tolerance = self.of_tolerance.max(other.of_tolerance);
        self.samples += other.samples;
    }

    fn print(&self, what: &str) {
        let list: Vec<String> = QUANTITIES
            .iter()
            .enumerate()
            .map(|(k, (_, name))| {
                let zeros = match self.zeros[k] {
                    0 => String::new(),
                    n => format!(" ({n} zero matrices: worst error {:.1e})", self.zero_abs[k]),
                };
                format!("{name} {:.1e}{zeros}", self.rel[k])
            })
            .collect();
        println!(
            "{what} ({} samples): worst relative errors {}; worst error / tolerance {:.1e}",
            self.samples,
            list.join(", "),
            self.of_tolerance
        );
    }
}

/// Expands `robot`'s derivatives and compares them with every sample of `samples`.
fn compare(what: &str, robot: &Robot, floating: bool, samples: &[Value]) -> Worst {
    assert_eq!(robot.base.floating, floating, "{what}: base");
    let d = expand(robot);
    let der = expand_derivatives(&d, robot);
    let nv = der.nv;
    assert_eq!(nv, robot.nv(), "{what}: nv");
    let ours = [
        &der.d_tau_dq,
        &der.d_tau_dqd,
        &der.d_qdd_dq,
        &der.d_qdd_dqd,
        &der.mass_matrix_inverse,
        &der.gravity_derivative,
    ];
    let roots: Vec<_> = ours.iter().flat_map(|r| r.iter().copied()).collect();
    let mut worst = Worst::default();
    for (k, s) in samples.iter().enumerate() {
        let q = vecf(&s["q"]);
        assert_eq!(q.len(), robot.nq(), "{what}: nq");
        let v = from_pinocchio_order(&s["v"], floating);
        let a = from_pinocchio_order(&s["a"], floating);
        let tau = from_pinocchio_order(&s["tau"], floating);
        let values = eval_graph(&der.graph, &roots, [&q, &v, &a, &tau]);
        for (slot, (key, name)) in QUANTITIES.iter().enumerate() {
            let x = &values[slot * nv * nv..(slot + 1) * nv * nv];
            let y = ours_mat(&s[*key], nv, floating);
            let (err, scale) = dynamics_tests::assert_close(
                &format!("{what} sample {k}: {name} ({key})"),
                x,
                &y,
                RTOL,
                ATOL,
            );
            worst.add(slot, err, scale);
        }
        worst.samples += 1;
    }
    worst
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
        Some("tools/derivative_reference.py")
    );
}

#[test]
fn derivatives_reproduce_pinocchio_on_the_reference_robots() {
    let mut total = Worst::default();
    let mut robots = 0;
    for name in ["ur5", "panda", "rand7", "double_pendulum"] {
        let data = reference_json(&format!("{name}.derivatives.json"));
        check_generator(&data);
        let tip = data["ee_frame"].as_str().expect("ee_frame");
        let options = LoadOptions {
            tip: Some(tip.to_string()),
            ..Default::default()
        };
        let path = data_dir().join(format!("robots/{name}.urdf"));
        let robot = dynamics_model::load_file(&path, &options).expect("loads");
        assert_eq!(robot.joint_names(), names(&data["joint_names"]), "{name}");
        let worst = compare(name, &robot, false, data["samples"].as_array().expect("s"));
        worst.print(name);
        total.merge(&worst);
        robots += 1;
    }
    for (name, floating) in [
        ("talos_upper_body", false),
        ("solo12", true),
        ("g1_29dof", true),
    ] {
        let data = reference_json(&format!("trees/{name}.derivatives.json"));
        check_generator(&data);
        assert_eq!(data["floating"].as_bool(), Some(floating), "{name}");
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
        let worst = compare(
            name,
            &robot,
            floating,
            data["samples"].as_array().expect("s"),
        );
        worst.print(name);
        total.merge(&worst);
        robots += 1;
    }
    assert_eq!(robots, 7, "all seven Pinocchio robots");
    total.print("all 7 robots");
}

#[test]
fn derivatives_reproduce_pinocchio_on_random_chains() {
    let data = reference_json("random_chains.derivatives.json");
    check_generator(&data);
    let chains = data["chains"].as_array().expect("chains");
    assert!(chains.len() >= 100, "{} random chains", chains.len());
    let mut total = Worst::default();
    let mut prismatic = 0;
    for chain in chains {
        let name = chain["name"].as_str().expect("name");
        let urdf = chain["urdf"].as_str().expect("urdf");
        let robot =
            dynamics_model::load::from_str(urdf, Format::Urdf, name, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        let nv = chain["nv"].as_u64().expect("nv") as usize;
        let expected: Vec<String> = (1..=nv).map(|i| format!("joint{i}")).collect();
        assert_eq!(robot.joint_names(), expected, "{name}: joints");
        prismatic += chain["joint_types"]
            .as_array()
            .expect("types")
            .iter()
            .filter(|t| t.as_str() == Some("prismatic"))
            .count();
        let worst = compare(name, &robot, false, chain["samples"].as_array().expect("s"));
        total.merge(&worst);
    }
    assert!(prismatic > 0, "prismatic joints covered");
    total.print(&format!("{} random chains", chains.len()));
}
