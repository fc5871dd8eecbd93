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
    evaluate_with(expr, q, qd, &HashMap::new())
}

/// The value of `sin`/`cos` of a printed angle: `θ2` or `(θ1+θ2−θ3)`.
fn angle(s: &str, q: &[f64]) -> f64 {
    let Some(inner) = s.strip_prefix('(').and_then(|s| s.strip_suffix(')')) else {
        let (i, _) = index_power(s.strip_prefix('θ').expect("θ"));
        return q[i - 1];
    };
    let mut total = 0.0;
    let mut sign = 1.0;
    for part in inner.split_inclusive(['+', '−']) {
        let (body, next) = match part.strip_suffix('+') {
            Some(b) => (b, 1.0),
            None => match part.strip_suffix('−') {
                Some(b) => (b, -1.0),
                None => (part, 1.0),
            },
        };
        if !body.is_empty() {
            let (i, _) = index_power(body.strip_prefix('θ').expect("θ in an angle"));
            total += sign * q[i - 1];
        }
        sign = next;
    }
    total
}

/// The value of one printed expression at `q`, `qd` and the named `symbols` (`m1`, `L2²`).
fn evaluate_with(expr: &str, q: &[f64], qd: &[f64], symbols: &HashMap<&str, f64>) -> f64 {
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
                // `sin θ2` (two words), `sin²θ2`, `sin(θ1+θ2)`, `cos²(θ1−θ2)` (one).
                let (p, var) = if rest.is_empty() {
                    k += 1;
                    (1, words[k])
                } else {
                    let at = rest.find(['θ', '(']).expect("θ or ( after the power");
                    (power(&rest[..at]), &rest[at..])
                };
                let x = angle(var, q);
                let x = if is_sin { x.sin() } else { x.cos() };
                x.powi(p)
            } else if let Some(rest) = w.strip_prefix("θ\u{307}") {
                let (i, p) = index_power(rest);
                qd[i - 1].powi(p)
            } else if w.starts_with("θ\u{308}") {
                0.0
            } else if let Some(rest) = w.strip_prefix('θ') {
                let (i, p) = index_power(rest);
                q[i - 1].powi(p)
            } else if let Some((name, x)) = symbols
                .iter()
                .filter(|(name, _)| w.starts_with(*name))
                .max_by_key(|(name, _)| name.len())
            {
                x.powi(power(&w[name.len()..]))
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
    for name in ["pendulum", "ur5", "mr_ur5", "planar2r"] {
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

/// The planar 2R arm with its masses, lengths and gravity as symbols prints the textbook's
/// Eqs. (8.9)–(8.11) (Modern Robotics §8.1.1): the printed entries, parsed back, equal the
/// book's closed forms at random angles, rates and parameter values (a polynomial identity
/// checked at 20 points), term counts included; and `--steps` prints the book's K and P.
#[test]
fn planar_2r_with_symbolic_parameters_gives_the_textbook_equations() {
    let robot = load("planar2r", &LoadOptions::default()).expect("shipped");
    let names = ["m1", "m2", "L1", "L2", "g"];
    let options = EquationOptions {
        digits: 17,
        steps: true,
        symbolic: names.iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    };
    let text = equations(&robot, &options).expect("equations");
    assert!(
        text.contains("gravity (0, -g, 0) m/s²; symbols m1, m2, L1, L2, g;"),
        "{text}"
    );
    let e = entries(&text);
    let get = |k: &str| {
        e.get(k)
            .unwrap_or_else(|| panic!("no entry {k} in\n{text}"))
    };
    // No number of the file is left: only small exact coefficients.
    for k in ["M11", "M12", "M22", "c1", "c2", "g1", "g2", "K", "P"] {
        assert!(!get(k).contains('.'), "{k} = {}", get(k));
    }
    assert_eq!(get("M22"), "m2 L2²");
    assert_eq!(get("c2"), "m2 L1 L2 θ̇1² sin θ2");
    assert_eq!(get("g2"), "m2 L2 g cos(θ1+θ2)");
    let terms = |k: &str| get(k).replace(" − ", " + ").split(" + ").count();
    // The book's forms, expanded: M11 4 terms, M12 2, c1 2, g1 3 (with cos(θ1+θ2)), P 3.
    for (k, n) in [
        ("M11", 4),
        ("M12", 2),
        ("c1", 2),
        ("g1", 3),
        ("P", 3),
        ("K", 7),
    ] {
        assert_eq!(terms(k), n, "{k} = {}", get(k));
    }
    let mut rng = Rng::new(0x2A2A);
    for _ in 0..20 {
        let (m1, m2, l1, l2, g) = (
            rng.uniform(0.5, 3.0),
            rng.uniform(0.5, 3.0),
            rng.uniform(0.2, 2.0),
            rng.uniform(0.2, 2.0),
            rng.uniform(1.0, 12.0),
        );
        let symbols: HashMap<&str, f64> = names.into_iter().zip([m1, m2, l1, l2, g]).collect();
        let q = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let qd = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        let (c1, s2, c2, c12, s1, s12) = (
            q[0].cos(),
            q[1].sin(),
            q[1].cos(),
            (q[0] + q[1]).cos(),
            q[0].sin(),
            (q[0] + q[1]).sin(),
        );
        let book = [
            (
                "M11",
                m1 * l1 * l1 + m2 * (l1 * l1 + 2.0 * l1 * l2 * c2 + l2 * l2),
            ),
            ("M12", m2 * (l1 * l2 * c2 + l2 * l2)),
            ("M22", m2 * l2 * l2),
            (
                "c1",
                -m2 * l1 * l2 * s2 * (2.0 * qd[0] * qd[1] + qd[1] * qd[1]),
            ),
            ("c2", m2 * l1 * l2 * qd[0] * qd[0] * s2),
            ("g1", (m1 + m2) * l1 * g * c1 + m2 * g * l2 * c12),
            ("g2", m2 * g * l2 * c12),
            (
                "K",
                0.5 * m1 * l1 * l1 * qd[0] * qd[0]
                    + 0.5
                        * m2
                        * ((l1 * l1 + 2.0 * l1 * l2 * c2 + l2 * l2) * qd[0] * qd[0]
                            + 2.0 * (l1 * l2 * c2 + l2 * l2) * qd[0] * qd[1]
                            + l2 * l2 * qd[1] * qd[1]),
            ),
            ("P", (m1 + m2) * g * l1 * s1 + m2 * g * l2 * s12),
        ];
        for (k, want) in book {
            let got = evaluate_with(get(k), &q, &qd, &symbols);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{k}: printed {} = {got}, book {want}",
                get(k)
            );
        }
    }
}
