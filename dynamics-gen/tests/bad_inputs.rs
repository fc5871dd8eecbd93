//! The catalogue of bad inputs. Every case runs as a user would meet it: the `dynamics-gen`
//! binary in an empty directory holding the case's files (so messages carry the file names a
//! user typed), or the library for the Modern Robotics lists. The catalogue, with each input
//! and the exact message it gets, is `docs/bad-inputs.md`; this test writes it anew and fails
//! on any difference, so a changed message is a reviewed change:
//!
//! ```text
//! DYNAMICS_GEN_BLESS=1 cargo test -p dynamics-gen --test bad_inputs   # rewrite the catalogue
//! ```
//!
//! Every case must also end in a one-line-per-problem error with exit code 1 (2 for a
//! command-line usage error), within a few seconds, without a panic; the few inputs that are
//! accepted on purpose (a byte-order mark) say so. The `robot!` and `#[derive(Dynamics)]`
//! cases are `dynamics-macros/tests/ui/fail`, checked exactly by trybuild; the catalogue
//! shows them from there.

use dynamics_model::Robot;
use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The two-joint TOML robot that TOML cases edit.
const TOML: &str = r#"name = "two"

[[joint]]
name = "shoulder"
type = "revolute"
screw = [0, 0, 1, 0, 0, 0]
limits = [-3, 3]

[joint.link]
name = "upper_arm"
home = { xyz = [0, 0, 0.5] }
mass = 1.0
inertia = [0.01, 0.01, 0.01, 0, 0, 0]

[[joint]]
name = "elbow"
type = "revolute"
axis = [0, 1, 0]
point = [0, 0, 0.5]

[joint.link]
name = "forearm"
home = { xyz = [0, 0, 0.4] }
mass = 2.0
inertia = [0.02, 0.02, 0.01, 0, 0, 0]
"#;

/// The two-joint URDF robot that URDF cases edit.
const URDF: &str = r#"<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <link name="upper_arm">
    <inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <link name="forearm">
    <inertial><origin xyz="0 0 0.2"/><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper_arm"/>
    <origin xyz="0 0 0.5" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/>
  </joint>
  <joint name="elbow" type="continuous">
    <parent link="upper_arm"/><child link="forearm"/>
    <origin xyz="0 0 0.4" rpy="0 0 0"/><axis xyz="0 1 0"/>
  </joint>
</robot>
"#;

/// What a case gives the program.
enum Run {
    /// The binary with these arguments (and standard input), in the case's directory.
    Cli {
        args: Vec<String>,
        stdin: Option<Vec<u8>>,
    },
    /// A library call; its error's text.
    Library(fn() -> String),
}

struct Case {
    section: &'static str,
    title: String,
    /// The input as the catalogue shows it (Markdown-free text).
    input: String,
    /// Files written into the case's directory.
    files: Vec<(String, Vec<u8>)>,
    run: Run,
}

fn cli(section: &'static str, title: &str, input: String, args: &[&str]) -> Case {
    Case {
        section,
        title: title.into(),
        input,
        files: vec![],
        run: Run::Cli {
            args: args.iter().map(|s| s.to_string()).collect(),
            stdin: None,
        },
    }
}

fn with_file(mut case: Case, name: &str, bytes: impl Into<Vec<u8>>) -> Case {
    case.files.push((name.into(), bytes.into()));
    case
}

fn with_stdin(mut case: Case, bytes: impl Into<Vec<u8>>) -> Case {
    if let Run::Cli { stdin, .. } = &mut case.run {
        *stdin = Some(bytes.into());
    }
    case
}

/// `text` with the unique occurrence of `from` replaced by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "`{from}` must occur once");
    text.replacen(from, to, 1)
}

/// The base TOML robot with one edit, run through `generate`.
fn toml(title: &str, from: &str, to: &str) -> Case {
    let input = if to.is_empty() {
        format!("two-joint robot without `{from}`")
    } else {
        format!("two-joint robot, `{from}` → `{to}`")
    };
    toml_text(title, input, edit(TOML, from, to))
}

fn toml_text(title: &str, input: String, text: impl Into<Vec<u8>>) -> Case {
    with_file(
        cli(
            "TOML robot files",
            title,
            input,
            &["generate", "robot.toml"],
        ),
        "robot.toml",
        text,
    )
}

/// The base URDF robot with one edit, run through `generate`.
fn urdf(title: &str, from: &str, to: &str) -> Case {
    let input = if to.is_empty() {
        format!("two-joint URDF without `{from}`")
    } else {
        format!("two-joint URDF, `{from}` → `{to}`")
    };
    urdf_text(title, input, &edit(URDF, from, to))
}

fn urdf_text(title: &str, input: String, text: &str) -> Case {
    with_file(
        cli("URDF files", title, input, &["generate", "robot.urdf"]),
        "robot.urdf",
        text,
    )
}

/// `eval` of the shipped pendulum on these JSON lines.
fn eval(title: &str, lines: &str) -> Case {
    with_stdin(
        cli(
            "`eval` JSON lines",
            title,
            format!("`eval pendulum` reads: {}", lines.trim_end()),
            &["eval", "pendulum"],
        ),
        lines,
    )
}

fn args(title: &str, args: &[&str]) -> Case {
    cli(
        "Command line",
        title,
        format!("dynamics-gen {}", args.join(" ")),
        args,
    )
}

fn library(title: &str, input: &str, f: fn() -> String) -> Case {
    Case {
        section: "Modern Robotics lists (library)",
        title: title.into(),
        input: input.into(),
        files: vec![],
        run: Run::Library(f),
    }
}

fn cases() -> Vec<Case> {
    vec![
        // TOML: syntax and schema.
        toml_text(
            "Malformed syntax",
            "two-joint robot, `mass = 2.0` → `mass = [2.0`".into(),
            edit(TOML, "mass = 2.0", "mass = [2.0"),
        ),
        toml("Wrong type", "mass = 2.0", "mass = \"two\""),
        toml_text(
            "Unknown parameter in an expression",
            "two-joint robot with `[parameters] m1 = 1.0, L1 = 0.5` and `mass = \"m2\"`".into(),
            edit(
                &edit(
                    TOML,
                    "name = \"two\"\n",
                    "name = \"two\"\n[parameters]\nm1 = 1.0\nL1 = 0.5\n",
                ),
                "mass = 1.0",
                "mass = \"m2\"",
            ),
        ),
        toml(
            "Malformed expression",
            "home = { xyz = [0, 0, 0.5] }",
            "home = { xyz = [0, 0, \"0.5 *\"] }",
        ),
        toml(
            "Parameter that is not a number",
            "name = \"two\"\n",
            "name = \"two\"\n[parameters]\nL1 = \"half\"\n",
        ),
        toml("Missing field", "mass = 2.0\n", ""),
        toml("Duplicate field", "mass = 2.0", "mass = 2.0\nmass = 3.0"),
        toml("Unknown field", "mass = 2.0", "mas = 2.0"),
        toml("Misspelt joint type", "type = \"revolute\"\naxis", "type = \"revolut\"\naxis"),
        toml(
            "Screw axis of the wrong length",
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0, 0]",
        ),
        toml(
            "Inertia of the wrong length",
            "inertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "inertia = [0.02, 0.02, 0.01]",
        ),
        toml(
            "Screw axis and axis both given",
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nscrew = [0, 1, 0, -0.5, 0, 0]",
        ),
        toml(
            "Prismatic joint with a point",
            "type = \"revolute\"\naxis",
            "type = \"prismatic\"\naxis",
        ),
        toml("NaN mass", "mass = 2.0", "mass = nan"),
        toml(
            "Infinite home offset",
            "xyz = [0, 0, 0.4]",
            "xyz = [0, 0, inf]",
        ),
        toml("Negative mass", "mass = 2.0", "mass = -2.0"),
        toml("Zero mass with inertia", "mass = 2.0", "mass = 0.0"),
        toml("Absurd mass (unit slip)", "mass = 2.0", "mass = 1e300"),
        toml(
            "Absurd length (unit slip)",
            "xyz = [0, 0, 0.4]",
            "xyz = [0, 0, 400000]",
        ),
        toml(
            "Inertia not positive semidefinite",
            "inertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "inertia = [0.02, 0.02, 0.01, 0.05, 0, 0]",
        ),
        toml(
            "Inertia breaking the triangle inequality",
            "inertia = [0.02, 0.02, 0.01, 0, 0, 0]",
            "inertia = [0.01, 0.01, 0.05, 0, 0, 0]",
        ),
        toml(
            "Screw axis not a unit axis",
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 2, 0, 0, 0]",
        ),
        toml(
            "Screw axis with pitch",
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0, 0, 0.1]",
        ),
        toml("Zero axis", "axis = [0, 1, 0]", "axis = [0, 0, 0]"),
        toml(
            "Home frame not rigid",
            "home = { xyz = [0, 0, 0.4] }",
            "home = [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0.4], [0, 0, 0, 1]]",
        ),
        toml(
            "Home frame with a wrong last row",
            "home = { xyz = [0, 0, 0.4] }",
            "home = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.4], [0, 0, 1, 1]]",
        ),
        toml("Limits upside down", "limits = [-3, 3]", "limits = [3, -3]"),
        toml("Gear ratio zero", "limits = [-3, 3]", "limits = [-3, 3]\ngear_ratio = 0"),
        toml("Negative damping", "limits = [-3, 3]", "limits = [-3, 3]\ndamping = -1"),
        toml(
            "Negative velocity limit",
            "limits = [-3, 3]",
            "limits = [-3, 3]\nvelocity_limit = -3.0",
        ),
        toml("Gravity of the wrong length", "name = \"two\"", "name = \"two\"\ngravity = [0, -9.81]"),
        toml(
            "Absurd gravity",
            "name = \"two\"",
            "name = \"two\"\ngravity = [0, 0, -9.81e6]",
        ),
        toml("Two joints with one name", "name = \"elbow\"", "name = \"shoulder\""),
        toml("Empty joint name", "name = \"elbow\"", "name = \"\""),
        toml("Two links with one name", "name = \"forearm\"", "name = \"upper_arm\""),
        toml("A link named as the base", "name = \"forearm\"", "name = \"base\""),
        toml(
            "Parent that is no link (disconnected)",
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nparent = \"nowhere\"",
        ),
        toml(
            "Parent listed later (cycle)",
            "screw = [0, 0, 1, 0, 0, 0]",
            "screw = [0, 0, 1, 0, 0, 0]\nparent = \"forearm\"",
        ),
        toml("Unsupported joint type (planar)", "type = \"revolute\"\naxis", "type = \"planar\"\naxis"),
        toml(
            "Floating joint in a chain",
            "type = \"revolute\"\naxis",
            "type = \"floating\"\naxis",
        ),
        toml(
            "Mimic of an unknown joint",
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nmimic = { joint = \"wrist\" }",
        ),
        toml(
            "Mimic of itself",
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nmimic = { joint = \"elbow\" }",
        ),
        toml(
            "Mimic with a zero multiplier",
            "point = [0, 0, 0.5]",
            "point = [0, 0, 0.5]\nmimic = { joint = \"shoulder\", multiplier = 0 }",
        ),
        toml_text("Empty file", "an empty file".into(), ""),
        toml_text(
            "No joints",
            "`name = \"empty\"` and nothing else".into(),
            "name = \"empty\"\n",
        ),
        toml_text(
            "Not UTF-8",
            "`name = \"` followed by the bytes FF FE".into(),
            &b"name = \"\xff\xfe\"\n"[..],
        ),
        toml_text(
            "A byte-order mark (accepted)",
            "the two-joint robot after the UTF-8 byte-order mark EF BB BF".into(),
            format!("\u{feff}{TOML}"),
        ),
        toml_text(
            "A 50 MB file",
            "50 MB of `#` comment lines".into(),
            "#\n".repeat(25 << 20),
        ),
        // URDF.
        urdf_text(
            "Malformed XML",
            "two-joint URDF, `<child link=\"forearm\"/>` → `<child link=\"forearm\">`".into(),
            &edit(URDF, "<child link=\"forearm\"/>", "<child link=\"forearm\">"),
        ),
        urdf_text(
            "Not a URDF",
            "`<sdf version=\"1.6\"/>`".into(),
            "<sdf version=\"1.6\"/>\n",
        ),
        urdf("Number that is not one", "xyz=\"0 0 0.4\"", "xyz=\"0 0 0.4m\""),
        urdf("Mass that is not one", "<mass value=\"2\"/>", "<mass value=\"two\"/>"),
        urdf("Negative mass", "<mass value=\"2\"/>", "<mass value=\"-2\"/>"),
        urdf("Absurd mass", "<mass value=\"2\"/>", "<mass value=\"1e300\"/>"),
        urdf(
            "Inertia far too large for its mass",
            "<mass value=\"2\"/>",
            "<mass value=\"1e-30\"/>",
        ),
        urdf("Negative effort limit", "effort=\"10\"", "effort=\"-10\""),
        urdf(
            "Inertia not positive semidefinite",
            "ixx=\"0.02\" ixy=\"0\"",
            "ixx=\"0.02\" ixy=\"0.05\"",
        ),
        urdf("NaN in an origin", "rpy=\"0 0 0\"/><axis xyz=\"0 1 0\"", "rpy=\"0 nan 0\"/><axis xyz=\"0 1 0\""),
        urdf("Zero axis", "<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 0\"/>"),
        urdf(
            "Joint to an unknown link",
            "<child link=\"forearm\"/>",
            "<child link=\"forarm\"/>",
        ),
        urdf(
            "Link with two parents",
            "</robot>",
            "<joint name=\"extra\" type=\"fixed\"><parent link=\"base\"/><child link=\"forearm\"/></joint>\n</robot>",
        ),
        urdf(
            "Two roots",
            "<link name=\"base\"/>",
            "<link name=\"base\"/>\n  <link name=\"camera\"/>",
        ),
        urdf(
            "Parent link that is not defined",
            "<parent link=\"upper_arm\"/><child link=\"forearm\"/>",
            "<parent link=\"tool\"/><child link=\"forearm\"/>",
        ),
        urdf(
            "Closed loop",
            "<parent link=\"base\"/><child link=\"upper_arm\"/>",
            "<parent link=\"forearm\"/><child link=\"upper_arm\"/>",
        ),
        urdf(
            "Duplicate link names",
            "<link name=\"base\"/>",
            "<link name=\"base\"/>\n  <link name=\"base\"/>",
        ),
        urdf("Planar joint", "type=\"continuous\"", "type=\"planar\""),
        urdf("Floating joint inside the tree", "type=\"continuous\"", "type=\"floating\""),
        urdf(
            "Mimic of an unknown joint",
            "<axis xyz=\"0 1 0\"/>",
            "<axis xyz=\"0 1 0\"/><mimic joint=\"wrist\"/>",
        ),
        urdf(
            "Inertia without all six attributes",
            " iyz=\"0\" izz=\"0.01\"/></inertial>\n  </link>\n  <joint",
            " izz=\"0.01\"/></inertial>\n  </link>\n  <joint",
        ),
        urdf(
            "Two joints with one name",
            "<joint name=\"elbow\"",
            "<joint name=\"shoulder\"",
        ),
        urdf(
            "Joint joining a link to itself",
            "<parent link=\"upper_arm\"/>",
            "<parent link=\"forearm\"/>",
        ),
        urdf(
            "Mimic of itself",
            "<axis xyz=\"0 1 0\"/>",
            "<axis xyz=\"0 1 0\"/><mimic joint=\"elbow\"/>",
        ),
        urdf(
            "XML entity expansion (billion laughs)",
            "<?xml version=\"1.0\"?>",
            "<?xml version=\"1.0\"?>\n<!DOCTYPE robot [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\">]>",
        ),
        urdf("Two root elements", "</robot>\n", "</robot>\n<robot name=\"three\"/>\n"),
        urdf_text(
            "No movable joint",
            "two-joint URDF with both joints `fixed`".into(),
            &URDF
                .replace("type=\"revolute\"", "type=\"fixed\"")
                .replace("type=\"continuous\"", "type=\"fixed\""),
        ),
        // Command line.
        args("Unknown shipped robot", &["generate", "ur6"]),
        args("File that does not exist", &["generate", "robots/arm.toml"]),
        with_file(
            args("Directory given as a file", &["generate", "robots"]),
            "robots/README.md",
            "",
        ),
        with_file(
            args("Unknown file type", &["generate", "robot.txt"]),
            "robot.txt",
            TOML,
        ),
        args("Unknown command", &["generat", "ur5"]),
        args(
            "Symbolic parameter the robot does not declare",
            &["equations", "planar2r", "--symbolic", "m3"],
        ),
        args("Unknown function", &["generate", "ur5", "--functions", "mass_matrx"]),
        args("Gravity not three numbers", &["generate", "ur5", "--gravity", "0,-9.81"]),
        args("Lock of an unknown joint", &["generate", "ur5", "--lock", "wrist_9_joint=0"]),
        args("Unknown tip link", &["generate", "ur5", "--tip", "gripper"]),
        args(
            "Unknown payload link",
            &["generate", "ur5", "--runtime-parameters", "--payload-link", "gripper"],
        ),
        args(
            "Payload link without run-time parameters",
            &["generate", "ur5", "--payload-link", "wrist_3_link"],
        ),
        args("Unknown scalar type", &["generate", "ur5", "--scalar", "f16"]),
        with_file(
            args("URDF option on a TOML file", &["generate", "robot.toml", "--tip", "forearm"]),
            "robot.toml",
            TOML,
        ),
        // eval.
        eval("Not JSON", "q = [0, 0]\n"),
        eval("q of the wrong length", "{\"q\": [0.1]}\n"),
        eval("q of the wrong type", "{\"q\": \"0.1 0.2\"}\n"),
        eval("Unknown key", "{\"q\": [0, 0], \"qdot\": [0, 0]}\n"),
        eval("Non-finite input", "{\"q\": [0, 1e999]}\n"),
        eval("A line that is not an object", "[0, 0]\n"),
        eval("No q", "{\"qd\": [0, 0]}\n"),
        eval("null in q", "{\"q\": [null, 0]}\n"),
        // The book's lists through the library.
        library(
            "Lists of mismatched sizes",
            "Robot::from_mr_lists with 2 screw axes, 2 inertias and 2 home frames",
            || {
                let s = Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
                let g = Matrix6::identity();
                let m = Matrix4::identity();
                let e = Robot::from_mr_lists(&[m, m], &[g, g], &[s, s], Vector3::zeros());
                e.expect_err("refused").to_string()
            },
        ),
        library(
            "A screw axis with |ω| = 2",
            "Robot::from_mr_lists with S_1 = (0, 0, 2, 0, 0, 0)",
            || {
                let s = Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0);
                let g = Matrix6::identity();
                let m = Matrix4::identity();
                let e = Robot::from_mr_lists(&[m, m], &[g], &[s], Vector3::zeros());
                e.expect_err("refused").to_string()
            },
        ),
    ]
}

/// The exit code and standard error of a case, and how long it took.
fn outcome(case: &Case, dir: &Path) -> (i32, String, Duration) {
    let start = Instant::now();
    match &case.run {
        Run::Library(f) => (1, format!("error: {}\n", f()), start.elapsed()),
        Run::Cli { args, stdin } => {
            for (name, bytes) in &case.files {
                let path = dir.join(name);
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::write(path, bytes).unwrap();
            }
            let mut child = Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
                .args(args)
                .current_dir(dir)
                .stdin(Stdio::piped())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("the binary runs");
            let mut pipe = child.stdin.take().unwrap();
            pipe.write_all(stdin.as_deref().unwrap_or_default())
                .unwrap();
            drop(pipe);
            let out = child.wait_with_output().unwrap();
            let code = out.status.code().expect("exited, not killed");
            (
                code,
                String::from_utf8(out.stderr).expect("UTF-8 messages"),
                start.elapsed(),
            )
        }
    }
}

/// Text for a Markdown table cell, as code.
fn cell(text: &str) -> String {
    let escaped = text
        .trim_end()
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('|', "&#124;")
        .replace('\n', "<br>");
    format!("<code>{escaped}</code>")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("bad_inputs")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The `robot!` and derive cases of the macros' trybuild tests: (file, source, message).
fn macro_cases() -> Vec<(String, String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../dynamics-macros/tests/ui/fail");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".rs"))
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let source = std::fs::read_to_string(dir.join(&n)).unwrap();
            let stderr = std::fs::read_to_string(dir.join(n.replace(".rs", ".stderr"))).unwrap();
            (n, source, stderr)
        })
        .collect()
}

#[test]
fn every_bad_input_gets_its_catalogued_message() {
    let cases = cases();
    let mut doc = String::from(
        "<!-- @generated by dynamics-gen/tests/bad_inputs.rs: \
         DYNAMICS_GEN_BLESS=1 cargo test -p dynamics-gen --test bad_inputs -->\n\
         # Bad inputs and their messages\n\n\
         Every input below is a test (`dynamics-gen/tests/bad_inputs.rs` and, for the macros, \
         `dynamics-macros/tests/ui`): each gets exactly the message shown, exit code 1, and \
         never a panic. Files are named as the user gave them; \
         TOML and URDF cases edit one line of a valid two-joint robot (shown at the end); \
         `generate` stands for any command that reads a robot.\n",
    );
    let mut section = "";
    let mut n = 0;
    let mut failures = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        let dir = scratch(&format!("{i:02}"));
        let (code, stderr, took) = outcome(case, &dir);
        let _ = std::fs::remove_dir_all(&dir);
        let accepted = case.title.contains("(accepted)");
        let want_code = if accepted { 0 } else { 1 };
        if code != want_code {
            failures.push(format!(
                "{}: exit code {code}, not {want_code}: {stderr}",
                case.title
            ));
        }
        if stderr.contains("panicked") {
            failures.push(format!("{}: panicked: {stderr}", case.title));
        }
        if !accepted && !stderr.starts_with("error: ") {
            failures.push(format!("{}: no `error: `: {stderr}", case.title));
        }
        if took > Duration::from_secs(10) {
            failures.push(format!("{}: took {took:?}", case.title));
        }
        for (name, _) in &case.files {
            let shown = Path::new(name)
                .parent()
                .filter(|p| !p.as_os_str().is_empty());
            let name = shown.map_or(name.as_str(), |p| p.to_str().unwrap());
            if !accepted && !stderr.contains(name) {
                failures.push(format!(
                    "{}: the message does not name `{name}`",
                    case.title
                ));
            }
        }
        if case.section != section {
            section = case.section;
            write!(
                doc,
                "\n## {section}\n\n| # | case | input | message |\n|---|---|---|---|\n"
            )
            .unwrap();
        }
        n += 1;
        let command = match &case.run {
            Run::Cli { args, .. } => format!("dynamics-gen {}", args.join(" ")),
            Run::Library(_) => String::new(),
        };
        let input = if case.section == "Command line" || command.is_empty() {
            case.input.clone()
        } else {
            format!("{}\n$ {command}", case.input)
        };
        let message = if accepted {
            "(accepted: exit code 0)".to_string()
        } else {
            stderr
        };
        writeln!(
            doc,
            "| {n} | {} | {} | {} |",
            case.title,
            cell(&input),
            cell(&message)
        )
        .unwrap();
    }
    write!(
        doc,
        "\n## `robot!` and `#[derive(Dynamics)]`\n\nCompile errors with their spans, from \
         `dynamics-macros/tests/ui/fail`.\n\n| # | case | message |\n|---|---|---|\n"
    )
    .unwrap();
    for (name, _source, stderr) in macro_cases() {
        n += 1;
        writeln!(doc, "| {n} | `{name}` | {} |", cell(&stderr)).unwrap();
    }
    write!(
        doc,
        "\n## The robots the cases edit\n\n```toml\n{TOML}```\n\n```xml\n{URDF}```\n"
    )
    .unwrap();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(n >= 60, "the catalogue has {n} cases");

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/bad-inputs.md");
    if std::env::var_os("DYNAMICS_GEN_BLESS").is_some() {
        std::fs::write(&path, &doc).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != doc {
        let first = committed
            .lines()
            .zip(doc.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(committed.lines().count().min(doc.lines().count()));
        panic!(
            "docs/bad-inputs.md differs from the messages, first at line {}:\ncommitted: {}\nnow:       {}\n\
             (rerun with DYNAMICS_GEN_BLESS=1 to accept the new messages)",
            first + 1,
            committed.lines().nth(first).unwrap_or("<end>"),
            doc.lines().nth(first).unwrap_or("<end>")
        );
    }
}
