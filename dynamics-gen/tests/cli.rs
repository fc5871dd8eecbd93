//! The `dynamics-gen` binary, run as a user would.

use serde_json::Value;
use std::io::Write;
use std::process::{Command, Output, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn run_with_stdin(args: &[&str], stdin: &str) -> Output {
    let mut child = bin()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(stdin.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

fn reference() -> Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/reference/mr_ur5.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(floats).collect(),
        Value::Number(x) => vec![x.as_f64().unwrap()],
        other => panic!("not a number: {other}"),
    }
}

/// ‖x − y‖∞ ≤ 1e-9·‖y‖∞ + 1e-12; returns the relative error for the report.
fn assert_close(what: &str, x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "{what}: lengths");
    let err = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = y.iter().map(|b| b.abs()).fold(0.0, f64::max);
    assert!(
        err <= 1e-9 * scale + 1e-12,
        "{what}: error {err:e}, scale {scale}\n  got  {x:?}\n  want {y:?}"
    );
    err / scale.max(1e-300)
}

#[test]
fn generate_prints_code_with_the_generated_header() {
    let out = run(&["generate", "pendulum", "--no-std", "--name", "Pend"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let code = text(&out.stdout);
    assert!(code.starts_with("// @generated"), "{code}");
    assert!(code.contains("pub struct Pend;"));
    assert!(code.contains("::libm::sin"));
    for f in [
        "mass_matrix",
        "coriolis",
        "gravity",
        "inverse_dynamics",
        "forward_dynamics",
    ] {
        assert!(code.contains(&format!("pub fn {f}(")), "{f}");
    }
}

#[test]
fn generate_writes_the_file_given_with_o() {
    let path = std::env::temp_dir().join(format!("dynamics-gen-cli-{}.rs", std::process::id()));
    let out = run(&[
        "generate",
        "ur5",
        "--scalar",
        "f32",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(out.stdout.is_empty());
    let code = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(code.starts_with("// @generated"));
    assert!(code.contains("SVector<f32, 6>"));
}

#[test]
fn stats_prints_a_row_per_function_and_featherstone() {
    let out = run(&["stats", "ur5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    for f in [
        "mass_matrix",
        "coriolis",
        "gravity",
        "inverse_dynamics",
        "forward_dynamics",
    ] {
        let row = table
            .lines()
            .find(|l| l.starts_with(f) && l.split_whitespace().next() == Some(f))
            .unwrap_or_else(|| panic!("no row for {f}:\n{table}"));
        let numbers: Vec<usize> = row
            .split_whitespace()
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        assert_eq!(numbers.len(), 7, "{row}");
        // Six revolute joints: one sin/cos per joint at most.
        assert!(numbers[4] <= 6, "{row}");
        assert!(numbers[0] > 0 && numbers[6] > 0, "{row}");
    }
    // 93·6 − 69 = 489, 81·6 − 66 = 420.
    assert!(table.contains("489 mul, 420 add/sub"), "{table}");
}

#[test]
fn eval_matches_the_modern_robotics_library_on_mr_ur5() {
    let data = reference();
    let s = &data["samples"][0];
    let line = serde_json::json!({
        "q": s["thetalist"], "qd": s["dthetalist"], "qdd": s["ddthetalist"],
        "tau": s["taulist"], "f_tip": s["Ftip"],
    })
    .to_string();
    // The same state twice, around a blank line; then q and qd alone.
    let q_only = serde_json::json!({"q": s["thetalist"], "qd": s["dthetalist"]}).to_string();
    let input = format!("{line}\n\n{line}\n{q_only}\n");
    let out = run_with_stdin(&["eval", "mr_ur5"], &input);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let answers: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers.len(), 3, "{stdout}");
    assert_eq!(answers[0], answers[1]);
    let a = &answers[0];
    let o = &s["outputs"];
    let mut worst: f64 = 0.0;
    for (ours, theirs) in [
        ("mass_matrix", "MassMatrix"),
        ("coriolis", "VelQuadraticForces"),
        ("gravity", "GravityForces"),
        ("inverse_dynamics", "InverseDynamics"),
        ("forward_dynamics", "ForwardDynamics"),
        ("end_effector_pose", "FKinSpace"),
    ] {
        worst = worst.max(assert_close(ours, &floats(&a[ours]), &floats(&o[theirs])));
    }
    // Without qdd, tau and f_tip (zero): τ = c + g, the sum of the library's two terms.
    let c_plus_g: Vec<f64> = floats(&o["VelQuadraticForces"])
        .iter()
        .zip(floats(&o["GravityForces"]))
        .map(|(c, g)| c + g)
        .collect();
    assert_close(
        "inverse_dynamics(q, qd)",
        &floats(&answers[2]["inverse_dynamics"]),
        &c_plus_g,
    );
    // C(q, q̇) q̇ = c(q, q̇).
    let n = 6;
    let cm = floats(&a["coriolis_matrix"]);
    let qd = floats(&s["dthetalist"]);
    let c_qd: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| cm[i * n + j] * qd[j]).sum())
        .collect();
    assert_close(
        "coriolis_matrix·qd",
        &c_qd,
        &floats(&o["VelQuadraticForces"]),
    );
    eprintln!("eval vs Modern Robotics, worst relative error: {worst:e}");
}

#[test]
fn eval_reports_a_short_q_with_its_line_and_answers_the_lines_before() {
    let good = r#"{"q": [0, 0, 0, 0, 0, 0]}"#;
    let input = format!("{good}\n{good}\n{{\"q\": [1, 2, 3, 4, 5]}}\n{good}\n");
    let out = run_with_stdin(&["eval", "mr_ur5"], &input);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(text(&out.stdout).lines().count(), 2);
    let err = text(&out.stderr);
    assert!(
        err.contains(r#"error: line 3: "q" has 5 values, the robot has 6 joints"#),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn eval_rejects_an_unknown_key() {
    let input = "{\"q\": [0, 0, 0, 0, 0, 0], \"qdot\": [1, 1, 1, 1, 1, 1]}\n";
    let out = run_with_stdin(&["eval", "mr_ur5"], input);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = text(&out.stderr);
    assert!(
        err.starts_with("error: line 1: unknown field `qdot`"),
        "{err}"
    );
}

#[test]
fn joints_lists_ur5_in_vector_order() {
    let out = run(&["joints", "ur5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let names: Vec<&str> = stdout
        .lines()
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "shoulder_pan_joint",
            "shoulder_lift_joint",
            "elbow_joint",
            "wrist_1_joint",
            "wrist_2_joint",
            "wrist_3_joint"
        ]
    );
    // The shoulder pan axis is the z axis through the base origin.
    assert!(
        stdout
            .lines()
            .next()
            .unwrap()
            .contains("S = (0, 0, 1, 0, 0, 0)"),
        "{stdout}"
    );
    assert!(stdout.lines().all(|l| l.contains("revolute")));
}

#[test]
fn errors_are_one_line_with_exit_code_1() {
    for (args, expected) in [
        (
            &["generate", "no_such_robot"][..],
            "error: unknown robot `no_such_robot`",
        ),
        (
            &["joints", "ur5", "--lock", "elbow_joint"][..],
            "JOINT=VALUE",
        ),
        (&["stats", "ur5", "--gravity", "0,-9.81"][..], "GX,GY,GZ"),
        (
            &["generate", "does/not/exist.urdf"][..],
            "error: does/not/exist.urdf",
        ),
        (
            &["generate", "pendulum", "--name", "not a name"][..],
            "error: `not a name` is not a valid struct name",
        ),
        (
            &["generate", "ur5", "--name", "ur5"][..],
            "did you mean `Ur5`?",
        ),
    ] {
        let out = run(args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("backtrace"),
            "{err}"
        );
    }
}

#[test]
fn gravity_and_lock_options_reach_the_model() {
    // Zero gravity: g(q) = 0.
    let out = run_with_stdin(
        &["eval", "mr_ur5", "--gravity", "0,0,0"],
        "{\"q\": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]}\n",
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: Value = serde_json::from_str(text(&out.stdout).trim()).unwrap();
    assert!(floats(&v["gravity"]).iter().all(|g| *g == 0.0), "{v}");
    // Locking the last UR5 joint leaves five.
    let out = run(&["joints", "ur5", "--lock", "wrist_3_joint=0.5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert_eq!(stdout.lines().count(), 5);
    assert!(!stdout.contains("wrist_3_joint"));
}

#[test]
fn help_names_the_shipped_robots() {
    let out = run(&["generate", "--help"]);
    assert!(out.status.success());
    let help = text(&out.stdout);
    for name in dynamics_gen::dynamics_model::shipped::NAMES {
        assert!(help.contains(name), "{name}: {help}");
    }
    // Every function `--functions` accepts, in the order of the generated impl.
    let list = help.split_whitespace().collect::<Vec<_>>().join(" ");
    for name in dynamics_gen::options::FUNCTIONS {
        assert!(
            list.contains(&format!(" {name},")) || list.contains(&format!(" {name}.")),
            "--functions help lacks {name}: {help}"
        );
    }
}

#[test]
fn eval_refuses_non_finite_results_and_keep_going_answers_later_lines() {
    let input = "{\"q\": [0, 0], \"qd\": [1e300, 0]}\n{\"q\": [0.1, 0.2]}\n";
    // Without --keep-going: an error naming the line and the quantity, never `null`.
    let out = run_with_stdin(&["eval", "pendulum"], input);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("line 1") && err.contains("not finite"),
        "{err}"
    );
    assert!(!text(&out.stdout).contains("null"));
    // With --keep-going: line 1 answered with its error, line 2 with numbers, exit 1.
    let out = run_with_stdin(&["eval", "pendulum", "--keep-going"], input);
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    let lines: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert_eq!(lines[0]["line"], 1);
    assert!(lines[0]["error"].as_str().unwrap().contains("not finite"));
    assert_eq!(floats(&lines[1]["gravity"]).len(), 2);
    // null only where documented: the task space of a 2-joint arm (nv < 6).
    let documented = stdout
        .replace("\"task_space_mass_matrix\":null", "")
        .replace("\"task_space_bias\":null", "");
    assert!(!documented.contains("null"), "{stdout}");
    // Non-finite inputs are refused by name too.
    let out = run_with_stdin(&["eval", "pendulum"], "{\"q\": [0, 1e999]}\n");
    assert!(
        text(&out.stderr).contains("line 1"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn lock_accepts_the_comma_form_and_constants() {
    let repeated = run(&[
        "joints",
        "ur5",
        "--lock",
        "wrist_3_joint=0.5",
        "--lock",
        "wrist_2_joint=-1.5707963267948966",
    ]);
    let comma = run(&[
        "joints",
        "ur5",
        "--lock",
        "wrist_3_joint=0.5,wrist_2_joint=-PI/2",
    ]);
    assert!(comma.status.success(), "{}", text(&comma.stderr));
    assert_eq!(text(&comma.stdout), text(&repeated.stdout));
    assert_eq!(text(&comma.stdout).lines().count(), 4);
    let bad = run(&["joints", "ur5", "--lock", "wrist_3_joint=PIE"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(text(&bad.stderr).contains("PIE"), "{}", text(&bad.stderr));
}

#[test]
fn tip_and_frames_change_the_generated_kinematics() {
    let out = run(&["stats", "ur5", "--tip", "ee_link"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        !text(&out.stderr).contains("note: --tip"),
        "{}",
        text(&out.stderr)
    );
    let default = text(&run(&["generate", "ur5"]).stdout);
    let ee_link = text(&run(&["generate", "ur5", "--tip", "ee_link"]).stdout);
    assert!(default.contains("The end-effector frame is `wrist_3_link`"));
    assert!(ee_link.contains("The end-effector frame is `ee_link` on link `wrist_3_link`"));
    // A serial chain has no named frames unless asked; `--frame` names them, in order.
    assert!(!default.contains("FRAME_NAMES"));
    let framed = text(&run(&["generate", "ur5", "--frame", "wrist_3_link,base_link"]).stdout);
    assert!(
        framed.contains(
            r#"pub const FRAME_NAMES: [&'static str; 2] = ["wrist_3_link", "base_link"];"#
        ),
        "{framed}"
    );
    let bad = run(&["generate", "ur5", "--frame", "foot"]);
    assert_eq!(bad.status.code(), Some(1));
    let err = text(&bad.stderr);
    assert!(
        err.contains(
            "link `foot`: field `frame`: the file has no link of this name to use as a frame"
        ),
        "{err}"
    );
}

#[test]
fn joints_reads_a_urdf_piped_to_standard_input() {
    let urdf = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/ur5.urdf"))
        .unwrap();
    let out = run_with_stdin(&["joints", "-"], &urdf);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let piped = text(&out.stdout);
    assert_eq!(piped, text(&run(&["joints", "ur5"]).stdout));
    assert_eq!(piped.lines().count(), 6);
    // Errors name the input `<stdin>`.
    let out = run_with_stdin(&["joints", "-"], "<robot name=\"t\">\n<link name=\"a\">\n");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.starts_with("error: <stdin>:"), "{err}");
}

#[test]
fn generate_from_standard_input_records_the_hash_of_what_it_read() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/pendulum.toml");
    let toml = std::fs::read_to_string(path).unwrap();
    let out = run_with_stdin(&["generate", "-", "--name", "Pendulum"], &toml);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let piped = text(&out.stdout);
    let hash = dynamics_gen::emit::provenance::sha256_hex(toml.as_bytes());
    assert!(
        piped.contains(&format!("// Source: `<stdin>` (sha256 {hash}).")),
        "{}",
        &piped[..400]
    );
    // The code itself is the file's (only the source's name differs).
    let from_file = text(&run(&["generate", "pendulum", "--name", "Pendulum"]).stdout);
    let body = |s: &str| s[s.find("#[allow(").unwrap()..].to_string();
    assert_eq!(body(&piped), body(&from_file));
}

/// The TALOS upper body with its grippers coupled (`tools/mimic_reference.py`): `joints`
/// gives the coordinates their index and says whom each follower follows; `eval` takes the 20
/// coordinates, names the mimic joints when a vector has the 32 physical joints' length, and
/// agrees with Pinocchio's first sample.
#[test]
fn mimic_joints_in_joints_and_eval() {
    let urdf = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/robots/trees/talos_upper_body_mimic.urdf"
    );
    let out = run(&["joints", urdf]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert_eq!(stdout.lines().count(), 32);
    let line = |name: &str| {
        stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no {name}: {stdout}"))
            .to_string()
    };
    assert!(line("gripper_left_joint").contains(" q[9] "), "{stdout}");
    let follower = line("gripper_left_fingertip_1_joint");
    assert!(
        follower.contains(" - ") && follower.contains("follows `gripper_left_joint` (×-1 + 0)"),
        "{follower}"
    );
    assert!(line("head_2_joint").contains(" q[19] "), "{stdout}");

    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/reference/trees/talos_upper_body_mimic.json"
    );
    let data: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let s = &data["samples"][0];
    let input = serde_json::json!({"q": s["q"], "qd": s["v"], "qdd": s["a"]}).to_string();
    let out = run_with_stdin(&["eval", urdf], &format!("{input}\n"));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let o: Value = serde_json::from_str(text(&out.stdout).trim()).unwrap();
    assert_close("τ", &floats(&o["inverse_dynamics"]), &floats(&s["tau"]));
    let long = serde_json::json!({ "q": vec![0.0; 32] }).to_string();
    let out = run_with_stdin(&["eval", urdf], &format!("{long}\n"));
    let err = text(&out.stderr);
    assert!(
        err.contains(r#""q" has 32 values, the robot has 20 joints; its 12 mimic joints follow their leaders"#),
        "{err}"
    );
}

#[test]
fn functions_selects_what_is_generated() {
    let all = text(&run(&["generate", "ur5"]).stdout);
    let some = run(&[
        "generate",
        "ur5",
        "--functions",
        "gravity,jacobian_body",
        "--no-runtime-trait",
    ]);
    assert!(some.status.success(), "{}", text(&some.stderr));
    let some = text(&some.stdout);
    assert!(some.contains("pub fn gravity(") && some.contains("pub fn jacobian_body("));
    for gone in [
        "fn mass_matrix(",
        "fn forward_dynamics(",
        "fn jacobian_space(",
        "impl ::dynamics_runtime",
    ] {
        assert!(all.contains(gone) && !some.contains(gone), "{gone}");
    }
    assert!(
        some.contains("functions `gravity`, `jacobian_body`"),
        "header records it"
    );
    assert!(some.contains("--functions gravity,jacobian_body --no-runtime-trait"));
    assert!(some.lines().count() * 4 < all.lines().count());
    let cases = [
        (vec!["--functions", "gravity"], "the dynamics_runtime::Dynamics impl needs mass_matrix, coriolis, inverse_dynamics, forward_dynamics"),
        (vec!["--functions", "jacobian", "--no-runtime-trait"], "there is no generated function `jacobian`; fix: choose among mass_matrix"),
        (vec!["--functions", "frame_poses", "--no-runtime-trait"], "`frame_poses` needs named frames, and the robot has none"),
    ];
    for (extra, message) in cases {
        let mut argv = vec!["generate", "ur5"];
        argv.extend(extra);
        let out = run(&argv);
        assert_eq!(out.status.code(), Some(1));
        assert!(text(&out.stderr).contains(message), "{}", text(&out.stderr));
    }
}

#[test]
fn armature_and_friction_options_change_the_code_and_bad_ones_are_refused() {
    let plain = text(&run(&["generate", "ur5"]).stdout);
    let out = run(&[
        "generate",
        "ur5",
        "--armature",
        "shoulder_pan_joint=0.5,elbow_joint=0.25",
        "--friction",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let code = text(&out.stdout);
    assert_ne!(code, plain);
    assert!(code.contains("armature `shoulder_pan_joint` = 0.5, `elbow_joint` = 0.25 (by option)"));
    assert!(code.contains("friction in the dynamics"));
    assert!(code.contains("--armature shoulder_pan_joint=0.5,elbow_joint=0.25 --friction"));
    assert!(code.contains("tau + self.friction(qd)"));
    // A TOML robot with damping and Coulomb friction on joint 2.
    let toml = dynamics_gen::dynamics_model::shipped::get("pendulum")
        .unwrap()
        .text
        .replace(
            "screw = [1, 0, 0, 0, 0, 0]",
            "screw = [1, 0, 0, 0, 0, 0]\ndamping = 0.5\nfriction = 1.5",
        );
    let path =
        std::env::temp_dir().join(format!("dynamics-gen-friction-{}.toml", std::process::id()));
    std::fs::write(&path, toml).unwrap();
    let file = path.to_str().unwrap();
    let exact = text(&run(&["generate", file]).stdout);
    assert!(exact.contains("joint2` (b = 0.5, μ = 1.5)"), "{exact}");
    assert!(exact.contains("if qd1 > 0.0 { 1.5 } else if qd1 < 0.0 { -1.5 } else { 0.0 }"));
    assert!(
        !exact.contains("self.friction(qd)"),
        "not in the dynamics by default"
    );
    let smooth = text(&run(&["generate", file, "--friction-smoothing", "0.02"]).stdout);
    assert!(smooth.contains(".tanh()") && smooth.contains("smoothed with ε = 0.02"));
    assert!(smooth.contains("self.friction(qd)"));
    std::fs::remove_file(&path).ok();
    for (argv, message) in [
        (
            vec!["generate", "ur5", "--armature", "nope=1"],
            "joint `nope`",
        ),
        (
            vec!["generate", "ur5", "--armature", "elbow_joint=-1"],
            "must be finite and ≥ 0",
        ),
        (
            vec!["generate", "ur5", "--friction-smoothing", "0"],
            "not a smoothing velocity",
        ),
    ] {
        let out = run(&argv);
        assert_ne!(out.status.code(), Some(0));
        assert!(text(&out.stderr).contains(message), "{}", text(&out.stderr));
    }
}

#[test]
fn eval_gives_the_task_space_where_it_exists() {
    let out = run_with_stdin(
        &["eval", "ur5"],
        "{\"q\": [0.1, -0.8, 1.2, -0.4, 0.9, 0.3], \"qd\": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]}\n{\"q\": [0, 0, 0, 0, 0, 0]}\n",
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let lines: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let lambda = lines[0]["task_space_mass_matrix"]
        .as_array()
        .expect("Λ at a regular state");
    assert_eq!(lambda.len(), 6);
    assert_eq!(lines[0]["jacobian_body"].as_array().unwrap().len(), 6);
    assert_eq!(floats(&lines[0]["task_space_bias"]).len(), 6);
    // The UR5's home configuration is singular (wrist axes 4 and 6 aligned).
    assert!(lines[1]["task_space_mass_matrix"].is_null(), "{stdout}");
}

/// `stats` on a URDF that writes 1.5708 for π/2 lists the six angles and what
/// `--snap-angles` would save; with the option the list is gone and the counts are those of
/// the exact file, and `generate` records the option in the header and the regenerate line.
#[test]
fn snap_angles_listed_by_stats_and_applied() {
    let exact = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/robots/panda.urdf"
    );
    let rounded = std::fs::read_to_string(exact)
        .unwrap()
        .replace("1.5707963267948966", "1.5708");
    let path = std::env::temp_dir().join(format!("dynamics-gen-snap-{}.urdf", std::process::id()));
    std::fs::write(&path, rounded).unwrap();
    let p = path.to_str().unwrap();
    let out = run(&["stats", p, "--tip", "panda_hand"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stats = text(&out.stdout);
    assert!(
        stats.contains("6 rpy angles lie within 1e-4 rad of a multiple of pi/2 but are used as written (tolerance 1e-9):"),
        "{stats}"
    );
    assert!(stats.contains(
        "joint `panda_joint2` origin roll = -1.5708 (3.7e-6 rad from a multiple of pi/2)"
    ));
    assert!(stats.contains("with --snap-angles 4e-6 (the robot changes by up to that angle)"));
    let line = |s: &str, f: &str| -> String {
        s.lines()
            .find(|l| l.split_whitespace().next() == Some(f))
            .unwrap_or_else(|| panic!("{f} in {s}"))
            .to_string()
    };
    // The saving reported is the count of the exactly written Panda.
    let exact_stats = text(&run(&["stats", exact, "--tip", "panda_hand"]).stdout);
    let snapped = text(&run(&["stats", p, "--tip", "panda_hand", "--snap-angles", "4e-6"]).stdout);
    assert!(!snapped.contains("rpy angles lie within"), "{snapped}");
    let count = |l: String| -> usize {
        let w: Vec<usize> = l
            .split_whitespace()
            .skip(1)
            .take(2)
            .map(|x| x.parse().unwrap())
            .collect();
        w[0] + w[1]
    };
    let exact_mm = count(line(&exact_stats, "mass_matrix"));
    assert_eq!(count(line(&snapped, "mass_matrix")), exact_mm);
    assert!(
        stats
            .lines()
            .any(|l| l.starts_with("  mass_matrix ") && l.ends_with(&format!("-> {exact_mm:>8}"))),
        "{stats}"
    );
    let out = run(&[
        "generate",
        p,
        "--tip",
        "panda_hand",
        "--snap-angles",
        "4e-6",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let code = text(&out.stdout);
    assert!(
        code.contains("rpy angles within 4e-6 rad of a multiple of π/2 read as exact (by option)")
    );
    assert!(code.contains("--snap-angles=4e-6"));
    let out = run(&["generate", "mr_ur5", "--snap-angles", "1e-5"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("`snap_angles` applies to URDF files only"));
    std::fs::remove_file(&path).ok();
}

#[test]
fn method_lagrangian_reaches_generate_and_stats() {
    let out = run(&["generate", "pendulum", "--method", "lagrangian"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let code = text(&out.stdout);
    assert!(code.contains("method lagrangian"), "header");
    assert!(
        code.contains("dynamics-gen generate pendulum --method lagrangian"),
        "regenerate line"
    );
    assert!(code.contains("Method: the Lagrangian route"), "docs");
    let ne = text(&run(&["generate", "pendulum"]).stdout);
    assert!(ne.contains("method newton_euler") && !ne.contains("Lagrangian route"));
    let out = run(&["stats", "ur5", "--method", "lagrangian"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("method lagrangian"));
    let out = run(&["generate", "pendulum", "--method", "euler"]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("unknown method `euler`") && err.contains("lagrangian"),
        "{err}"
    );
}

#[test]
fn equations_prints_the_pendulum_closed_forms() {
    let out = run(&["equations", "pendulum"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let eq = text(&out.stdout);
    for line in [
        "  M11 = 6 sin²θ2 + 8",
        "  M12 = 2 cos θ2",
        "  M22 = 6",
        "  c1 = 12 θ̇1 θ̇2 sin θ2 cos θ2 − 2 θ̇2² sin θ2",
        "  c2 = −6 θ̇1² sin θ2 cos θ2",
        "  g2 = 20 sin θ2",
    ] {
        assert!(eq.lines().any(|l| l == line), "missing {line:?} in\n{eq}");
    }
    let out = run(&["equations", "pendulum", "--format", "latex", "--only", "M"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let tex = text(&out.stdout);
    assert!(tex.contains("\\begin{document}") && tex.contains("M_{12} &= 2 \\, \\cos\\theta_{2}"));
    assert!(!tex.contains("g_{2}"), "--only M");
    let solo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/robots/trees/solo12.urdf"
    );
    let out = run(&["equations", solo, "--floating-base"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("quaternion"));
}
