//! Checks of the expansion against the exact seed cases (Modern Robotics chapter 8), through
//! the graph's numeric evaluation.

use super::*;
use dynamics_model::Robot;
use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};
use serde_json::Value;

fn seed() -> Value {
    let text = include_str!("../../../tests/data/seed-cases.json");
    serde_json::from_str(text).expect("seed-cases.json parses")
}

fn mat<const R: usize, const C: usize>(v: &Value) -> nalgebra::SMatrix<f64, R, C> {
    nalgebra::SMatrix::from_fn(|i, j| v[i][j].as_f64().expect("number"))
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

fn robot(model: &Value) -> Robot {
    let m: Vec<Matrix4<f64>> = model["Mlist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat::<4, 4>)
        .collect();
    let g: Vec<Matrix6<f64>> = model["Glist"]
        .as_array()
        .unwrap()
        .iter()
        .map(mat::<6, 6>)
        .collect();
    let s: Vec<Vector6<f64>> = model["Slist"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| Vector6::from_vec(vecf(x)))
        .collect();
    let gr = vecf(&model["gravity"]);
    Robot::from_mr_lists(&m, &g, &s, Vector3::new(gr[0], gr[1], gr[2])).expect("valid model")
}

fn eval(
    d: &Dynamics,
    roots: &[ExprId],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &[f64],
) -> Vec<f64> {
    d.graph.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => qd[i],
            QDD => qdd[i],
            _ => tau[i],
        }
    })
}

fn close(a: &[f64], b: &[f64], what: &str) {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let err = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        err <= 1e-10 * scale + 1e-12,
        "{what}: error {err:e}\n got {a:?}\nwant {b:?}"
    );
}

#[test]
fn seed_models_match_their_samples() {
    let seed = seed();
    for name in ["rotational_pendulum_ex8_4", "spatial_3R", "spatial_RPR"] {
        let model = &seed["models"][name];
        let r = robot(model);
        let d = expand(&r);
        d.graph.verify().expect("graph invariants");
        for s in model["samples"].as_array().unwrap() {
            let (q, qd, qdd) = (vecf(&s["q"]), vecf(&s["qd"]), vecf(&s["qdd"]));
            let n = q.len();
            let tau_want = vecf(&s["tau"]);
            let m_want: Vec<f64> = s["M"].as_array().unwrap().iter().flat_map(vecf).collect();
            close(
                &eval(&d, &d.mass_matrix, &q, &qd, &qdd, &tau_want),
                &m_want,
                name,
            );
            close(
                &eval(&d, &d.coriolis, &q, &qd, &qdd, &tau_want),
                &vecf(&s["c"]),
                name,
            );
            close(
                &eval(&d, &d.gravity, &q, &qd, &qdd, &tau_want),
                &vecf(&s["g"]),
                name,
            );
            close(
                &eval(&d, &d.inverse_dynamics, &q, &qd, &qdd, &tau_want),
                &tau_want,
                name,
            );
            let fd = eval(&d, &d.forward_dynamics, &q, &qd, &vec![0.0; n], &tau_want);
            close(&fd, &qdd, name);
        }
    }
}
