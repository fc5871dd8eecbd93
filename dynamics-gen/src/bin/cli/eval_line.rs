//! One `eval` line: a JSON state in, the reference dynamics (dynamics-reference) out as a
//! JSON object, or what is wrong with the line. No I/O and nothing of the command line, so
//! the fuzz target `eval_line` runs this very file.

use dynamics_gen::dynamics_model::Robot;
use nalgebra::{DMatrix, Matrix4, Vector6};
use serde::{Deserialize, Serialize};

/// One input line. Unknown keys are an error, so a typo is not silently a zero vector.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct State {
    q: Vec<f64>,
    #[serde(default)]
    qd: Option<Vec<f64>>,
    #[serde(default)]
    qdd: Option<Vec<f64>>,
    #[serde(default)]
    tau: Option<Vec<f64>>,
    #[serde(default)]
    f_tip: Option<Vec<f64>>,
}

/// One output line: matrices as lists of rows.
#[derive(Debug, Serialize)]
pub struct Output {
    mass_matrix: Vec<Vec<f64>>,
    coriolis: Vec<f64>,
    gravity: Vec<f64>,
    inverse_dynamics: Vec<f64>,
    forward_dynamics: Vec<f64>,
    coriolis_matrix: Vec<Vec<f64>>,
    mass_matrix_dot: Vec<Vec<f64>>,
    kinetic_energy: f64,
    potential_energy: f64,
    friction: Vec<f64>,
    end_effector_forces: Vec<f64>,
    end_effector_pose: Vec<Vec<f64>>,
    jacobian_space: Vec<Vec<f64>>,
    jacobian_body: Vec<Vec<f64>>,
    jacobian_space_dot: Vec<Vec<f64>>,
    jacobian_body_dot: Vec<Vec<f64>>,
    /// `null` where `J_b M⁻¹ J_bᵀ` is singular (and for fewer than six velocities).
    task_space_mass_matrix: Option<Vec<Vec<f64>>>,
    /// `null` likewise.
    task_space_bias: Option<Vec<f64>>,
}

/// The answer to one line, or what is wrong with it.
pub fn eval_line(robot: &Robot, line: &str) -> Result<Output, String> {
    let state: State = serde_json::from_str(line).map_err(|e| line_error(line, &e))?;
    let (nq, nv) = (robot.nq(), robot.nv());
    let mimic = match robot.dof() - robot.n_coordinates() {
        0 => String::new(),
        m => format!(
            "; its {m} mimic joint{} follow their leaders and have no entries (see `dynamics-gen joints`)",
            if m == 1 { "" } else { "s" }
        ),
    };
    let what = |len: usize| {
        if robot.base.floating {
            format!(
                "{len} (a floating base: q = (p, quat x y z w, {n} joints), velocities, accelerations and forces = (base twist or wrench, {n} joints){mimic})",
                n = robot.n_coordinates()
            )
        } else {
            format!("{len} joints{mimic}")
        }
    };
    let vector = |name: &str, v: Option<Vec<f64>>, len: usize| -> Result<Vec<f64>, String> {
        match v {
            None => Ok(vec![0.0; len]),
            Some(v) if v.len() == len => Ok(v),
            Some(v) => Err(format!(
                "\"{name}\" has {} values, the robot has {}; fix: give {len} values",
                v.len(),
                what(len)
            )),
        }
    };
    let q = vector("q", Some(state.q), nq)?;
    let qd = vector("qd", state.qd, nv)?;
    let qdd = vector("qdd", state.qdd, nv)?;
    let tau = vector("tau", state.tau, nv)?;
    if robot.base.floating && q[3..7].iter().all(|x| *x == 0.0) {
        return Err(
            "\"q\"[3..7], the base quaternion (x, y, z, w), is zero: give any non-zero quaternion (it is normalised), e.g. [0, 0, 0, 1]".into(),
        );
    }
    let f_tip = match state.f_tip {
        None => Vector6::zeros(),
        Some(v) if v.len() == 6 => Vector6::from_column_slice(&v),
        Some(v) => {
            return Err(format!(
                "\"f_tip\" has {} values, a wrench has 6: (mx, my, mz, fx, fy, fz) in the end-effector frame",
                v.len()
            ))
        }
    };
    for (name, v) in [("q", &q), ("qd", &qd), ("qdd", &qdd), ("tau", &tau)] {
        if let Some(k) = v.iter().position(|x| !x.is_finite()) {
            return Err(format!("\"{name}\"[{k}] is not a finite number"));
        }
    }
    let g = robot.gravity;
    let forward = dynamics_reference::forward_dynamics(robot, &q, &qd, &tau, &g, &f_tip)
        .map_err(|e| format!("forward dynamics: {e}"))?;
    Output {
        mass_matrix: rows(&dynamics_reference::mass_matrix(robot, &q)),
        coriolis: dynamics_reference::vel_quadratic_forces(robot, &q, &qd)
            .as_slice()
            .to_vec(),
        gravity: dynamics_reference::gravity_forces(robot, &q, &g)
            .as_slice()
            .to_vec(),
        inverse_dynamics: dynamics_reference::inverse_dynamics(robot, &q, &qd, &qdd, &g, &f_tip)
            .as_slice()
            .to_vec(),
        forward_dynamics: forward.as_slice().to_vec(),
        coriolis_matrix: rows(&dynamics_reference::coriolis_matrix(robot, &q, &qd)),
        mass_matrix_dot: rows(&dynamics_reference::mass_matrix_dot(robot, &q, &qd)),
        kinetic_energy: dynamics_reference::kinetic_energy(robot, &q, &qd),
        potential_energy: dynamics_reference::potential_energy(robot, &q, &g),
        friction: dynamics_reference::friction_forces(robot, &qd, None)
            .as_slice()
            .to_vec(),
        end_effector_forces: dynamics_reference::end_effector_forces(robot, &q, &f_tip)
            .as_slice()
            .to_vec(),
        end_effector_pose: pose_rows(&dynamics_reference::end_effector_pose(robot, &q)),
        jacobian_space: rows(&dynamics_reference::jacobian_space(robot, &q)),
        jacobian_body: rows(&dynamics_reference::jacobian_body(robot, &q)),
        jacobian_space_dot: rows(&dynamics_reference::jacobian_space_dot(robot, &q, &qd)),
        jacobian_body_dot: rows(&dynamics_reference::jacobian_body_dot(robot, &q, &qd)),
        task_space_mass_matrix: dynamics_reference::task_space_mass_matrix(robot, &q)
            .map(|l| l.row_iter().map(|r| r.iter().copied().collect()).collect()),
        task_space_bias: dynamics_reference::task_space_bias(robot, &q, &qd, &g)
            .map(|e| e.as_slice().to_vec()),
    }
    .finite()
}

impl Output {
    /// The output, or an error naming the first quantity with a NaN or infinite entry (JSON
    /// has no such numbers; serde_json would print `null`).
    fn finite(self) -> Result<Self, String> {
        let energies = [self.kinetic_energy, self.potential_energy];
        let empty = Vec::new();
        let vectors: [(&str, &[f64]); 8] = [
            ("coriolis", &self.coriolis),
            ("gravity", &self.gravity),
            ("inverse_dynamics", &self.inverse_dynamics),
            ("forward_dynamics", &self.forward_dynamics),
            ("kinetic_energy, potential_energy", &energies),
            ("friction", &self.friction),
            ("end_effector_forces", &self.end_effector_forces),
            (
                "task_space_bias",
                self.task_space_bias.as_ref().unwrap_or(&empty),
            ),
        ];
        let no_rows = Vec::new();
        let matrices: [(&str, &Vec<Vec<f64>>); 9] = [
            ("mass_matrix", &self.mass_matrix),
            ("coriolis_matrix", &self.coriolis_matrix),
            ("mass_matrix_dot", &self.mass_matrix_dot),
            ("end_effector_pose", &self.end_effector_pose),
            ("jacobian_space", &self.jacobian_space),
            ("jacobian_body", &self.jacobian_body),
            ("jacobian_space_dot", &self.jacobian_space_dot),
            ("jacobian_body_dot", &self.jacobian_body_dot),
            (
                "task_space_mass_matrix",
                self.task_space_mass_matrix.as_ref().unwrap_or(&no_rows),
            ),
        ];
        let bad = vectors
            .iter()
            .find(|(_, v)| v.iter().any(|x| !x.is_finite()))
            .map(|(n, _)| *n)
            .or_else(|| {
                matrices
                    .iter()
                    .find(|(_, m)| m.iter().flatten().any(|x| !x.is_finite()))
                    .map(|(n, _)| *n)
            });
        match bad {
            None => Ok(self),
            Some(name) => Err(format!(
                "{name} is not finite at this state (an overflow: are the inputs in SI units and of a sensible size?)"
            )),
        }
    }
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

fn pose_rows(m: &Matrix4<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

/// serde_json's message without its position (a line is one JSON value; the column stays).
/// What is wrong with a line that is not a `State`: not JSON at all, JSON but not an object,
/// or an object with a bad entry (the parser's message). Parsed a second time only here, on
/// the error path.
fn line_error(line: &str, e: &serde_json::Error) -> String {
    const EXAMPLE: &str = r#"{"q": [...], "qd": [...], "qdd": [...]}"#;
    let kind = match serde_json::from_str::<serde_json::Value>(line) {
        Err(e) => {
            let message = json_message(&e);
            return if message.contains("; fix: ") {
                message
            } else {
                format!("not JSON: {message}; fix: write one JSON object per line, like {EXAMPLE}")
            };
        }
        Ok(serde_json::Value::Object(_)) => return json_message(e),
        Ok(serde_json::Value::Array(_)) => "an array",
        Ok(serde_json::Value::String(_)) => "a string",
        Ok(serde_json::Value::Number(_)) => "a number",
        Ok(serde_json::Value::Bool(_)) => "a boolean",
        Ok(serde_json::Value::Null) => "null",
    };
    format!("expected a JSON object, found {kind}; fix: write one object per line, like {EXAMPLE}")
}

fn json_message(e: &serde_json::Error) -> String {
    let text = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let text = match text.strip_suffix(&suffix) {
        Some(message) => format!("{message} (column {})", e.column()),
        None => text,
    };
    match text.strip_prefix("number out of range") {
        Some(rest) => format!(
            "a number is beyond the range of f64{rest}; fix: give finite numbers (a state has no inf or NaN)"
        ),
        None => text,
    }
}
