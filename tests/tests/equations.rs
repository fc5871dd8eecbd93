//! The printed closed forms of `dynamics-gen equations` are exact, not only pretty: their
//! text (coefficients with 17 significant digits) is parsed back here, by a parser that knows
//! only the printed notation, and evaluated at seeded random states against the reference
//! implementation's `M`, `c`, `C` and `g`, to ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12: the shipped robots,
//! the Panda (7 joints), and a random chain with prismatic joints; for the shipped general
//! 7-joint `rand7`, whose `c` and `C` run to 115 MB of text, `M` and `g`.

use dynamics_gen::equations::{equations, EquationOptions, Select};
use dynamics_model::random::{random_chain, ChainSpec, Rng};
use dynamics_model::{load, LoadOptions, Robot};
use std::collections::HashMap;

/// The value of one printed coefficient: `12`, `3/4`, `√2`, `3√2/4`, `2π`, `0.5`, `1.5e-7`.
fn coefficient(s: &str) -> f64 {
    let (num, den) = match s.split_once('/') {
        Some((n, d)) => (n, d.parse::<f64>().expect("denominator")),
        None => (s, 1.0),
    };
    let value = if let Some((k, r)) = num.split_once('√') {
        let k = if k.is_empty() {
            1.0
        } else {
            k.parse().expect("factor")
        };
        k * r.parse::<f64>().expect("radicand").sqrt()
    } else if let Some(k) = num.strip_suffix('π') {
        let k = if k.is_empty() {
            1.0
        } else {
            k.parse().expect("factor")
        };
        k * std::f64::consts::PI
    } else {
        num.parse()
            .unwrap_or_else(|_| panic!("coefficient `{num}`"))
    };
    value / den
}

/// `"²"` → 2.
fn power(s: &str) -> i32 {
    if s.is_empty() {
        return 1;
    }
    let digits: String = s
        .chars()
        .map(|c| {
            let i = "⁰¹²³⁴⁵⁶⁷⁸⁹"
                .chars()
                .position(|d| d == c)
                .expect("superscript");
            char::from(b'0' + i as u8)
        })
        .collect();
    digits.parse().expect("power")
}

/// The joint index (1-based) and power after a variable's name: `2²` → (2, 2).
fn index_power(s: &str) -> (usize, i32) {
    let split = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
    (s[..split].parse().expect("index"), power(&s[split..]))
}

/// The value of one printed expression at `q`, `qd` (`θ̈` terms: zero).
fn evaluate(expr: &str, q: &[f64], qd: &[f64]) -> f64 {
    let mut total = 0.0;
    // Terms: a leading "−", then " + " and " − " between them.
    let expr = expr.replace(" − ", " + −");
    for term in expr.split(" + ") {
        let (sign, term) = match term.strip_prefix('−') {
            Some(t) => (-1.0, t),
            None => (1.0, term),
        };
        let mut value = sign;
        let words: Vec<&str> = term.split(' ').collect();
        let mut k = 0;
        while k < words.len() {
            let w = words[k];
            let factor = if let Some(rest) = w.strip_prefix("sin").or_else(|| w.strip_prefix("cos"))
            {
                let is_sin = w.starts_with("sin");
                // `sin θ2` (two words) or `sin²θ2` (one).
                let (p, var) = if rest.is_empty() {
                    k += 1;
                    (1, words[k])
                } else {
                    let at = rest.find('θ').expect("θ after the power");
                    (power(&rest[..at]), &rest[at..])
                };
                let (i, _) = index_power(var.strip_prefix('θ').expect("θ"));
                let x = if is_sin {
                    q[i - 1].sin()
                } else {
                    q[i - 1].cos()
                };
                x.powi(p)
            } else if let Some(rest) = w.strip_prefix("θ\u{307}") {
                let (i, p) = index_power(rest);
                qd[i - 1].powi(p)
            } else if w.starts_with("θ\u{308}") {
                0.0
            } else if let Some(rest) = w.strip_prefix('θ') {
                let (i, p) = index_power(rest);
                q[i - 1].powi(p)
            } else {
                coefficient(w)
            };
            value *= factor;
            k += 1;
        }
        total += value;
    }
    total
}

/// The printed entries by name (`M12`, `c1`, `C21`, `g3`).
fn entries(text: &str) -> HashMap<String, String> {
    text.lines()
        .filter_map(|l| l.strip_prefix("  "))
        .filter_map(|l| l.split_once(" = "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn close(what: &str, x: &[f64], y: &[f64]) {
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        err <= 1e-10 * scale + 1e-12,
        "{what}: error {err:e} at scale {scale:e}\n printed {x:?}\n reference {y:?}"
    );
}

fn check(name: &str, robot: &Robot, select: Select) {
    let options = EquationOptions {
        digits: 17,
        select,
        ..Default::default()
    };
    let text = equations(robot, &options).unwrap_or_else(|e| panic!("{name}: {e}"));
    let e = entries(&text);
    let n = robot.n_coordinates();
    let key = |s: &str, i: usize, j: Option<usize>| match j {
        Some(j) if n >= 10 => format!("{s}{},{}", i + 1, j + 1),
        Some(j) => format!("{s}{}{}", i + 1, j + 1),
        None => format!("{s}{}", i + 1),
    };
    let get = |k: &str| e.get(k).unwrap_or_else(|| panic!("{name}: no entry {k}"));
    let mut rng = Rng::new(0xE9A7);
    for _ in 0..3 {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-2.5, 2.5)).collect();
        let qd: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
        if select.mass_matrix {
            let m_ref = dynamics_reference::mass_matrix(robot, &q);
            let m: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    let (a, b) = (i.min(j), i.max(j));
                    evaluate(get(&key("M", a, Some(b))), &q, &qd)
                })
                .collect();
            let want: Vec<f64> = (0..n * n).map(|k| m_ref[(k / n, k % n)]).collect();
            close(&format!("{name} M"), &m, &want);
        }
        if select.coriolis {
            let c_ref = dynamics_reference::vel_quadratic_forces(robot, &q, &qd);
            let c: Vec<f64> = (0..n)
                .map(|i| evaluate(get(&key("c", i, None)), &q, &qd))
                .collect();
            close(&format!("{name} c"), &c, c_ref.as_slice());
        }
        if select.coriolis_matrix {
            let cm_ref = dynamics_reference::coriolis_matrix(robot, &q, &qd);
            let cm: Vec<f64> = (0..n * n)
                .map(|k| evaluate(get(&key("C", k / n, Some(k % n))), &q, &qd))
                .collect();
            let want: Vec<f64> = (0..n * n).map(|k| cm_ref[(k / n, k % n)]).collect();
            close(&format!("{name} C"), &cm, &want);
        }
        if select.gravity {
            let g_ref = dynamics_reference::gravity_forces(robot, &q, &robot.gravity);
            let g: Vec<f64> = (0..n)
                .map(|i| evaluate(get(&key("g", i, None)), &q, &qd))
                .collect();
            close(&format!("{name} g"), &g, g_ref.as_slice());
        }
    }
}

#[test]
fn printed_equations_evaluate_to_the_reference() {
    let all = Select::default();
    for name in ["pendulum", "ur5", "mr_ur5"] {
        let robot = load(name, &LoadOptions::default()).expect("shipped");
        check(name, &robot, all);
    }
    let panda = dynamics_model::load_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/robots/panda.urdf"),
        &LoadOptions::default(),
    )
    .expect("panda loads");
    check("panda", &panda, all);
    let chain = random_chain(
        7,
        ChainSpec {
            dof: 4,
            prismatic: 0.5,
        },
    );
    assert!(chain
        .joints
        .iter()
        .any(|j| j.kind == dynamics_model::JointKind::Prismatic));
    check("random chain", &chain, all);
    let rand7 = load("rand7", &LoadOptions::default()).expect("shipped");
    let m_g: Select = "M,g".parse().expect("selection");
    check("rand7", &rand7, m_g);
}
