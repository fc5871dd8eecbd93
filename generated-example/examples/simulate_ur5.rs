//! Simulates the UR5 released from rest at q = 0 under gravity (τ = 0) for 5 s at 1 kHz with
//! the generated `forward_dynamics`, by semi-implicit (symplectic) Euler and by RK4, and prints
//! the drift of the total energy of each.
//!
//! Total energy `E = ½ q̇ᵀ M(q) q̇ + P(q)`: the kinetic part from the generated mass matrix,
//! the potential `P(q) = −Σ m_i gᵀ p_i(q)` from the reference implementation on the loaded
//! robot (independent of the generated code, so the drift measures the integrator and the
//! generated dynamics together). RK4's drift is at the level of its truncation error; the
//! semi-implicit Euler step, taken in velocity coordinates with a configuration-dependent
//! `M(q)`, is not exactly symplectic, and its energy visibly drifts.
//!
//! Writes `ur5_symplectic_euler.csv`, `ur5_rk4.csv` (t, q1..q6, qd1..qd6, energy) and
//! `ur5_free_fall.png` (top: joint angles, RK4 solid and symplectic Euler thin; bottom: total
//! energy minus E(0), RK4 blue and symplectic Euler red) into `--out DIR` (default: the
//! workspace's `target/simulate_ur5/`).
//!
//! ```text
//! cargo run -p generated-example --example simulate_ur5 --release -- --out /tmp/ur5
//! ```

use generated_example::integrate::{rk4, semi_implicit_euler, State};
use generated_example::ur5::Ur5;
use nalgebra::SVector;
use plotters::prelude::*;
use std::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

type V6 = SVector<f64, 6>;

const DT: f64 = 1e-3;
const STEPS: usize = 5000;

/// One simulated trajectory: time, state and total energy per step.
struct Run {
    name: &'static str,
    t: Vec<f64>,
    q: Vec<V6>,
    qd: Vec<V6>,
    energy: Vec<f64>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = out_dir()?;
    std::fs::create_dir_all(&out)?;
    let robot = dynamics_model::load("ur5", &Default::default())?;
    let gravity = robot.gravity;
    let energy = |(q, qd): &State<6>| -> f64 {
        let kinetic = 0.5 * (qd.transpose() * Ur5.mass_matrix(q) * qd)[0];
        kinetic + dynamics_reference::potential_energy(&robot, q.as_slice(), &gravity)
    };
    let tau = V6::zeros();
    let accel = |q: &V6, qd: &V6| Ur5.forward_dynamics(q, qd, &tau);
    let simulate = |name: &'static str, step: &dyn Fn(State<6>) -> State<6>| {
        let mut state: State<6> = (V6::zeros(), V6::zeros());
        let mut run = Run {
            name,
            t: Vec::with_capacity(STEPS + 1),
            q: Vec::with_capacity(STEPS + 1),
            qd: Vec::with_capacity(STEPS + 1),
            energy: Vec::with_capacity(STEPS + 1),
        };
        for k in 0..=STEPS {
            if k > 0 {
                state = step(state);
            }
            run.t.push(k as f64 * DT);
            run.q.push(state.0);
            run.qd.push(state.1);
            run.energy.push(energy(&state));
        }
        run
    };
    let euler = simulate("symplectic_euler", &|s| semi_implicit_euler(accel, s, DT));
    let rk = simulate("rk4", &|s| rk4(accel, s, DT));

    println!(
        "UR5 released from rest at q = 0, tau = 0, {} s at {} Hz (gravity {:?} m/s^2)",
        STEPS as f64 * DT,
        1.0 / DT,
        gravity.as_slice()
    );
    for run in [&euler, &rk] {
        let e0 = run.energy[0];
        let last = run.energy[STEPS] - e0;
        let max = run
            .energy
            .iter()
            .map(|e| (e - e0).abs())
            .fold(0.0, f64::max);
        println!(
            "{:>16}: E(0) = {e0:.6} J, E(5 s) - E(0) = {last:+.3e} J, max |E(t) - E(0)| = {max:.3e} J, q(5 s) = {:.4?}",
            run.name,
            run.q[STEPS].as_slice()
        );
        write_csv(&out.join(format!("ur5_{}.csv", run.name)), run)?;
    }
    let max_dq = euler
        .q
        .iter()
        .zip(&rk.q)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    println!("max |q_euler - q_rk4| over the run: {max_dq:.3e} rad");
    let png = out.join("ur5_free_fall.png");
    plot(&png, &euler, &rk)?;
    println!(
        "wrote {}, {} and {}",
        out.join("ur5_symplectic_euler.csv").display(),
        out.join("ur5_rk4.csv").display(),
        png.display()
    );
    Ok(())
}

/// `--out DIR`, or the workspace's `target/simulate_ur5`.
fn out_dir() -> Result<PathBuf, String> {
    let mut args = std::env::args().skip(1);
    let mut out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/simulate_ur5");
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--out" => {
                out = args
                    .next()
                    .ok_or("--out needs a directory: --out DIR")?
                    .into()
            }
            other => {
                return Err(format!(
                    "unknown argument `{other}`; usage: simulate_ur5 [--out DIR]"
                ))
            }
        }
    }
    Ok(out)
}

fn write_csv(path: &Path, run: &Run) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    let names: Vec<String> = (1..=6)
        .map(|i| format!("q{i}"))
        .chain((1..=6).map(|i| format!("qd{i}")))
        .collect();
    writeln!(f, "t,{},energy", names.join(","))?;
    for k in 0..run.t.len() {
        let values: Vec<String> = run.q[k]
            .iter()
            .chain(run.qd[k].iter())
            .map(|x| x.to_string())
            .collect();
        writeln!(f, "{},{},{}", run.t[k], values.join(","), run.energy[k])?;
    }
    f.flush()
}

/// Two panels without text (no fonts needed): joint angles, and energy minus E(0).
fn plot(path: &Path, euler: &Run, rk: &Run) -> Result<(), Box<dyn Error>> {
    let root = BitMapBackend::new(path, (1200, 800)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(500);
    let t_end = STEPS as f64 * DT;
    let colours = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];

    let (q_min, q_max) = rk.q.iter().chain(&euler.q).fold((0.0f64, 0.0f64), |r, q| {
        (r.0.min(q.min()), r.1.max(q.max()))
    });
    let mut chart = ChartBuilder::on(&top)
        .margin(15)
        .build_cartesian_2d(0.0..t_end, (q_min - 0.1)..(q_max + 0.1))?;
    chart.draw_series(LineSeries::new(
        [(0.0, 0.0), (t_end, 0.0)],
        BLACK.mix(0.3).stroke_width(1),
    ))?;
    for (j, colour) in colours.iter().enumerate() {
        chart.draw_series(LineSeries::new(
            rk.t.iter().zip(&rk.q).map(|(t, q)| (*t, q[j])),
            colour.stroke_width(2),
        ))?;
        chart.draw_series(LineSeries::new(
            euler.t.iter().zip(&euler.q).map(|(t, q)| (*t, q[j])),
            colour.mix(0.5).stroke_width(1),
        ))?;
    }

    let de = |run: &Run| -> Vec<(f64, f64)> {
        let e0 = run.energy[0];
        run.t
            .iter()
            .zip(&run.energy)
            .map(|(t, e)| (*t, e - e0))
            .collect()
    };
    let (de_euler, de_rk) = (de(euler), de(rk));
    let bound = de_euler
        .iter()
        .chain(&de_rk)
        .map(|p| p.1.abs())
        .fold(1e-12, f64::max);
    let mut chart = ChartBuilder::on(&bottom)
        .margin(15)
        .build_cartesian_2d(0.0..t_end, (-1.1 * bound)..(1.1 * bound))?;
    chart.draw_series(LineSeries::new(
        [(0.0, 0.0), (t_end, 0.0)],
        BLACK.mix(0.3).stroke_width(1),
    ))?;
    chart.draw_series(LineSeries::new(de_euler, RED.stroke_width(2)))?;
    chart.draw_series(LineSeries::new(de_rk, BLUE.stroke_width(2)))?;
    root.present()?;
    Ok(())
}
