//! Every shipped TOML robot reproduces the lists it was written from: `mr_ur5`,
//! `mr_3link` (test data) and `rand7` the Modern Robotics library's `Mlist`/`Glist`/`Slist`/`g`
//! (tests/data/reference/mr_*.json), `pendulum` the Exercise 8.4 model of
//! tests/data/seed-cases.json.

use dynamics_model::{load, shipped, toml_format, LoadOptions, Robot};
use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};
use serde_json::Value;

fn data(path: &str) -> Value {
    let full = format!("{}/../tests/data/{path}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"));
    serde_json::from_str(&text).unwrap()
}

fn nums(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(nums).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("not a number: {other}"),
    }
}

/// The model's lists as flat row-major vectors.
struct Lists {
    m: Vec<Vec<f64>>,
    g: Vec<Vec<f64>>,
    s: Vec<Vec<f64>>,
    gravity: Vec<f64>,
}

fn from_json(model: &Value, slist_key: &str, gravity_key: &str) -> Lists {
    let list = |k: &str| model[k].as_array().unwrap().iter().map(nums).collect();
    Lists {
        m: list("Mlist"),
        g: list("Glist"),
        s: list(slist_key),
        gravity: nums(&model[gravity_key]),
    }
}

fn from_robot(r: &Robot) -> Lists {
    let m4 = |m: &Matrix4<f64>| m.transpose().iter().copied().collect::<Vec<_>>();
    let m6 = |m: &Matrix6<f64>| m.transpose().iter().copied().collect::<Vec<_>>();
    let v6 = |v: &Vector6<f64>| v.iter().copied().collect::<Vec<_>>();
    let v3 = |v: &Vector3<f64>| v.iter().copied().collect::<Vec<_>>();
    Lists {
        m: r.m_list().iter().map(m4).collect(),
        g: r.g_list().iter().map(m6).collect(),
        s: r.s_list().iter().map(v6).collect(),
        gravity: v3(&r.gravity),
    }
}

/// ‖x − y‖∞ ≤ 1e-12·max(1, ‖y‖∞) for every listed vector/matrix; returns the worst error.
fn compare(name: &str, got: &Lists, want: &Lists) -> f64 {
    let mut worst: f64 = 0.0;
    let mut check = |what: &str, x: &[Vec<f64>], y: &[Vec<f64>]| {
        assert_eq!(x.len(), y.len(), "{name}: number of {what}");
        for (i, (a, b)) in x.iter().zip(y).enumerate() {
            assert_eq!(a.len(), b.len());
            let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = a
                .iter()
                .zip(b)
                .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(
                err <= 1e-12 * scale.max(1.0),
                "{name}: {what}[{i}] differs by {err:e}\n got {a:?}\nwant {b:?}"
            );
            worst = worst.max(err);
        }
    };
    check("Mlist", &got.m, &want.m);
    check("Glist", &got.g, &want.g);
    check("Slist", &got.s, &want.s);
    check(
        "gravity",
        std::slice::from_ref(&got.gravity),
        std::slice::from_ref(&want.gravity),
    );
    worst
}

#[test]
fn mr_ur5_reproduces_the_course_lists() {
    let robot = load("mr_ur5", &LoadOptions::default()).unwrap();
    let want = from_json(&data("reference/mr_ur5.json")["model"], "screw_axes", "g");
    let err = compare("mr_ur5", &from_robot(&robot), &want);
    // Written with exact numbers: axis + point and 4×4 homes reproduce every digit.
    assert_eq!(err, 0.0);
    assert_eq!(
        robot.joint_names(),
        [
            "shoulder_pan_joint",
            "shoulder_lift_joint",
            "elbow_joint",
            "wrist_1_joint",
            "wrist_2_joint",
            "wrist_3_joint"
        ]
    );
}

#[test]
fn rand7_reproduces_mr_random7_through_every_inertia_form() {
    let robot = load("rand7", &LoadOptions::default()).unwrap();
    let want = from_json(
        &data("reference/mr_random7.json")["model"],
        "screw_axes",
        "g",
    );
    let err = compare("rand7", &from_robot(&robot), &want);
    eprintln!("rand7: worst error {err:e}");
}

#[test]
fn pendulum_is_exercise_8_4() {
    let robot = load("pendulum", &LoadOptions::default()).unwrap();
    let want = from_json(
        &data("seed-cases.json")["models"]["rotational_pendulum_ex8_4"],
        "Slist",
        "gravity",
    );
    assert_eq!(compare("pendulum", &from_robot(&robot), &want), 0.0);
}

#[test]
fn mr_3link_reads_with_its_axes_as_given_but_fails_full_validation() {
    // Test data, not a shipped robot: its S₁ has |ω| = √2, as in the book's docstrings.
    assert!(shipped::get("mr_3link").is_none());
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/robots/mr_3link.toml"
    );
    let text = std::fs::read_to_string(file).unwrap();
    let robot = toml_format::from_str(&text, "mr_3link.toml").unwrap();
    let want = from_json(
        &data("reference/mr_docstring3.json")["model"],
        "screw_axes",
        "g",
    );
    assert_eq!(compare("mr_3link", &from_robot(&robot), &want), 0.0);
    // The validating loader refuses the non-unit S₁, naming file, joint and field.
    let e = load(file, &LoadOptions::default()).unwrap_err();
    let errors = e.errors();
    assert_eq!(errors.len(), 1, "{e}");
    assert_eq!(errors[0].file.as_deref(), Some(file));
    assert_eq!(errors[0].field, "screw");
    let msg = e.to_string();
    assert!(
        msg.contains("joint `joint1`") && msg.contains("|ω| = 1"),
        "{msg}"
    );
}

#[test]
fn every_shipped_toml_robot_is_listed_and_named() {
    for name in ["mr_ur5", "pendulum", "rand7"] {
        assert!(shipped::NAMES.contains(&name));
        let s = shipped::get(name).unwrap();
        assert_eq!(s.file, format!("robots/{name}.toml"));
        let robot = toml_format::from_str(s.text, s.file).unwrap();
        assert_eq!(robot.name, name);
        assert_eq!(robot.source, s.file);
    }
}
