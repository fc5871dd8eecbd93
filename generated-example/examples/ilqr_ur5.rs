//! A reaching motion of the UR5 by iterative LQR on the generated derivatives: from rest at
//! `q = 0` (arm stretched out horizontally) to rest at `q* = (0.8, −1.2, 1.5, −0.6, 0.9, 0.3)`
//! rad in 1.5 s, 150 steps of 10 ms, minimising the joint torque beyond holding `q*` against
//! gravity. Each iteration linearises the dynamics at every step with the generated
//! `forward_dynamics_with_derivatives` (`q̈`, `∂q̈/∂q`, `∂q̈/∂q̇`, `M⁻¹` in one call; see
//! `generated_example::ilqr` for the solver and the discretisation).
//!
//! Prints the cost per iteration and the final error, and writes the plot of the cost per
//! iteration (log scale) to `ilqr_ur5.png` in `--out DIR` (default: the workspace's
//! `target/ilqr_ur5/`), and the trajectory to `ilqr_ur5.csv` (t, q1..q6, qd1..qd6, tau1..tau6).
//!
//! ```text
//! cargo run -p generated-example --example ilqr_ur5 --release -- --out /tmp/ilqr
//! ```

use generated_example::ilqr::{self, Cost, Gains, Iteration};
use generated_example::ur5::Ur5;
use nalgebra::{SMatrix, SVector};
use plotters::prelude::*;
use std::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

const H: f64 = 0.01;
const STEPS: usize = 150;
const ITERATIONS: usize = 100;
const FONT: &str = "DejaVu Sans";

type X = SVector<f64, 12>;
type U = SVector<f64, 6>;

fn main() -> Result<(), Box<dyn Error>> {
    let out = out_dir()?;
    std::fs::create_dir_all(&out)?;
    let goal_q = SVector::<f64, 6>::from([0.8, -1.2, 1.5, -0.6, 0.9, 0.3]);
    let hold = Ur5.gravity(&goal_q);
    let mut goal = X::zeros();
    goal.fixed_rows_mut::<6>(0).copy_from(&goal_q);
    let cost = Cost {
        goal,
        u_ref: hold,
        running: X::zeros(),
        control: U::repeat(1e-3),
        terminal: X::from_fn(|i, _| if i < 6 { 1e4 } else { 1e3 }),
    };
    let step = |x: &X, u: &U| {
        ilqr::semi_implicit_euler::<6, 12>(H, x, u, &|q, qd, tau| {
            Ur5.forward_dynamics_with_derivatives(q, qd, tau)
        })
        .expect("the state is (q, q̇)")
    };
    // Initial guess: hold the start against gravity.
    let mut xs = vec![X::zeros(); STEPS + 1];
    let mut us = vec![Ur5.gravity(&SVector::zeros()); STEPS];
    let mut scratch = vec![(SMatrix::zeros(), SMatrix::zeros()); STEPS];
    let mut gains = vec![Gains::default(); STEPS];
    let mut history = vec![Iteration::default(); ITERATIONS];
    for k in 0..STEPS {
        xs[k + 1] = step(&xs[k], &us[k]).0;
    }
    let initial = cost.total(&xs, &us);
    let start = std::time::Instant::now();
    let ran = ilqr::solve(
        &step,
        &cost,
        &mut xs,
        &mut us,
        &mut scratch,
        &mut gains,
        &mut history,
        1e-6,
    )
    .map_err(|e| format!("{e:?}"))?;
    let elapsed = start.elapsed();
    println!("iteration  cost            step    mu        max|k|");
    println!("{:>9}  {initial:<14.6e}", 0);
    for (i, it) in history[..ran].iter().enumerate() {
        println!(
            "{:>9}  {:<14.6e}  {:<6}  {:<8.1e}  {:.3e}",
            i + 1,
            it.cost,
            it.step,
            it.mu,
            it.feedforward
        );
    }
    let last = xs[STEPS];
    let q_err = (last.fixed_rows::<6>(0) - goal_q).amax();
    let v_err = last.fixed_rows::<6>(6).amax();
    println!(
        "{ran} iterations in {:.1} ms ({} linearisations of {STEPS} steps); final |q − q*|∞ = {q_err:.2e} rad, |q̇|∞ = {v_err:.2e} rad/s",
        elapsed.as_secs_f64() * 1e3,
        ran + 1
    );
    let mut csv = std::io::BufWriter::new(std::fs::File::create(out.join("ilqr_ur5.csv"))?);
    writeln!(
        csv,
        "t,q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6,tau1,tau2,tau3,tau4,tau5,tau6"
    )?;
    for (k, x) in xs.iter().enumerate() {
        let u = us.get(k).copied().unwrap_or(U::zeros());
        let cells: Vec<String> = x.iter().chain(u.iter()).map(|v| v.to_string()).collect();
        writeln!(csv, "{},{}", k as f64 * H, cells.join(","))?;
    }
    let costs: Vec<f64> = std::iter::once(initial)
        .chain(history[..ran].iter().map(|it| it.cost))
        .collect();
    plot(&out.join("ilqr_ur5.png"), &costs)?;
    println!("wrote {}", out.join("ilqr_ur5.png").display());
    Ok(())
}

/// The cost per iteration, log scale.
fn plot(path: &Path, costs: &[f64]) -> Result<(), Box<dyn Error>> {
    plotters::style::register_font(
        FONT,
        FontStyle::Normal,
        include_bytes!("fonts/DejaVuSans.ttf"),
    )
    .map_err(|_| "the embedded DejaVu Sans font could not be parsed")?;
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let lo = costs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = costs.iter().copied().fold(0.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "UR5 reaching by iLQR: cost per iteration",
            (FONT, 24).into_font(),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(90)
        .build_cartesian_2d(
            0f64..(costs.len() - 1).max(1) as f64,
            (lo * 0.5..hi * 2.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("iteration")
        .y_desc("cost (log scale)")
        .label_style((FONT, 16).into_font())
        .axis_desc_style((FONT, 18).into_font())
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    chart.draw_series(LineSeries::new(
        costs.iter().enumerate().map(|(i, c)| (i as f64, *c)),
        BLUE.stroke_width(2),
    ))?;
    chart.draw_series(
        costs
            .iter()
            .enumerate()
            .map(|(i, c)| Circle::new((i as f64, *c), 4, BLUE.filled())),
    )?;
    root.present()?;
    Ok(())
}

fn out_dir() -> Result<PathBuf, String> {
    let mut args = std::env::args().skip(1);
    let mut out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/ilqr_ur5");
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
                    "unknown argument `{other}`; usage: ilqr_ur5 [--out DIR]"
                ))
            }
        }
    }
    Ok(out)
}
