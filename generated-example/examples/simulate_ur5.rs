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
//! Writes `ur5_symplectic_euler.csv`, `ur5_rk4.csv` (t, q1..q6, qd1..qd6, energy) and the
//! 1400 × 1000 plot `ur5_free_fall.png` into `--out DIR` (default: the workspace's
//! `target/simulate_ur5/`). The plot has two panels over a common time axis `t [s]`, each with
//! tick labels, axis titles with units, a title and a legend to its right:
//!
//! - "Joint angles", `q [rad]`: one colour per joint, labelled q1..q6 with the URDF joint names;
//!   RK4 solid, semi-implicit Euler dashed in the same colour (the dashes show where the two
//!   integrators part). Joints whose curves coincide (q1 and q5 here, to within 0.01 rad) are
//!   named in the legend, and the first is drawn wider so that it shows beside the second.
//! - "Total energy drift", `E − E(0) [J]`: RK4 blue, semi-implicit Euler red, with each one's
//!   max |E − E(0)| and E(0) in the legend (RK4's drift is invisible at this scale).
//!
//! The text is drawn in DejaVu Sans, embedded from `examples/fonts/DejaVuSans.ttf` (see
//! `examples/fonts/README.md` for its provenance and licence) and rasterised by plotters'
//! pure-Rust `ab_glyph` feature: no system fonts, fontconfig or freetype are needed.
//!
//! ```text
//! cargo run -p generated-example --example simulate_ur5 --release -- --out /tmp/ur5
//! ```

use generated_example::integrate::{rk4, semi_implicit_euler, State};
use generated_example::ur5::Ur5;
use nalgebra::SVector;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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
    let joints: Vec<String> = robot.joints.iter().map(|j| j.name.clone()).collect();
    plot(&png, &joints, &euler, &rk)?;
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

/// The colours of the joint-angle series, q1..q6 (matplotlib's `tab10`).
const JOINT_COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];
/// RK4's and semi-implicit Euler's colours in the energy panel.
const RK4_COLOUR: RGBColor = RGBColor(31, 119, 180);
const EULER_COLOUR: RGBColor = RGBColor(214, 39, 40);
const GRID: RGBColor = RGBColor(225, 225, 225);
const NOTE: RGBColor = RGBColor(90, 90, 90);

const FONT: &str = "sans-serif";
const WIDTH: u32 = 1400;
const HEIGHT: u32 = 1000;
/// Width of the legend column right of both panels.
const LEGEND_WIDTH: u32 = 300;

/// How a legend entry's sample is drawn.
#[derive(Clone, Copy)]
enum Sample {
    Solid(RGBColor, u32),
    Dashed(RGBColor, u32),
    /// Text only (a note), after a small gap.
    None,
}

/// A legend entry: its sample, its text and an optional smaller second line.
struct Entry {
    sample: Sample,
    text: String,
    detail: Option<String>,
}

impl Entry {
    fn new(sample: Sample, text: impl Into<String>) -> Self {
        Self {
            sample,
            text: text.into(),
            detail: None,
        }
    }
}

/// Two panels sharing the time axis: the joint angles (RK4 solid, semi-implicit Euler dashed)
/// and the total energy minus E(0) for both integrators, each with a legend on the right.
///
/// Text is drawn with the DejaVu Sans font embedded from `examples/fonts/` and rasterised by
/// plotters' pure-Rust `ab_glyph` backend, so no system fonts or font libraries are needed.
fn plot(path: &Path, joints: &[String], euler: &Run, rk: &Run) -> Result<(), Box<dyn Error>> {
    plotters::style::register_font(
        FONT,
        FontStyle::Normal,
        include_bytes!("fonts/DejaVuSans.ttf"),
    )
    .map_err(|_| "the embedded DejaVu Sans font could not be parsed")?;

    let root = BitMapBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area();
    root.fill(&WHITE)?;
    let (header, body) = root.split_vertically(50);
    header.draw(&Text::new(
        format!(
            "UR5 free fall from rest at q = 0 (τ = 0): {} s, step {} ms",
            STEPS as f64 * DT,
            DT * 1e3
        ),
        ((WIDTH / 2) as i32, 28),
        TextStyle::from((FONT, 24).into_font())
            .pos(Pos::new(HPos::Center, VPos::Center))
            .color(&BLACK),
    ))?;
    let (top, bottom) = body.split_vertically(530);
    let (top, top_legend) = top.split_horizontally(WIDTH - LEGEND_WIDTH);
    let (bottom, bottom_legend) = bottom.split_horizontally(WIDTH - LEGEND_WIDTH);
    let t_end = STEPS as f64 * DT;

    // Joint angles.
    let (q_min, q_max) = rk.q.iter().chain(&euler.q).fold((0.0f64, 0.0f64), |r, q| {
        (r.0.min(q.min()), r.1.max(q.max()))
    });
    let pad = 0.05 * (q_max - q_min);
    let mut chart = panel(&top, "Joint angles", t_end, (q_min - pad)..(q_max + pad))?;
    mesh(&mut chart, "q [rad]", 1)?;
    // Pairs of joints whose RK4 curves lie within 1 % of the axis span of each other all along:
    // the first of each pair is drawn wider, so that it shows on both sides of the second.
    let overlaps: Vec<(usize, usize, f64)> = (0..6)
        .flat_map(|i| (i + 1..6).map(move |j| (i, j)))
        .map(|(i, j)| {
            let d = rk.q.iter().map(|q| (q[i] - q[j]).abs()).fold(0.0, f64::max);
            (i, j, d)
        })
        .filter(|&(_, _, d)| d < 0.01 * (q_max - q_min))
        .collect();
    for (j, &colour) in JOINT_COLOURS.iter().enumerate() {
        let width = if overlaps.iter().any(|o| o.0 == j) {
            5
        } else {
            2
        };
        chart.draw_series(LineSeries::new(
            rk.t.iter().zip(&rk.q).map(|(t, q)| (*t, q[j])),
            colour.stroke_width(width),
        ))?;
    }
    for (j, &colour) in JOINT_COLOURS.iter().enumerate() {
        chart.draw_series(DashedLineSeries::new(
            euler.t.iter().zip(&euler.q).map(|(t, q)| (*t, q[j])),
            7,
            5,
            colour.stroke_width(1),
        ))?;
    }
    let mut entries: Vec<Entry> = joints
        .iter()
        .zip(JOINT_COLOURS)
        .enumerate()
        .map(|(j, (name, colour))| {
            Entry::new(Sample::Solid(colour, 3), format!("q{}  {name}", j + 1))
        })
        .collect();
    entries.push(Entry::new(Sample::None, ""));
    entries.push(Entry::new(Sample::Solid(BLACK, 2), "RK4"));
    entries.push(Entry::new(Sample::Dashed(BLACK, 1), "semi-implicit Euler"));
    for &(i, j, d) in &overlaps {
        entries.push(Entry {
            sample: Sample::None,
            text: format!("q{} and q{} overlap:", i + 1, j + 1),
            detail: Some(format!("|q{} − q{}| ≤ {d:.4} rad (RK4)", i + 1, j + 1)),
        });
    }
    legend(&top_legend, "Joint", &entries)?;

    // Energy drift.
    let de = |run: &Run| -> Vec<(f64, f64)> {
        let e0 = run.energy[0];
        run.t
            .iter()
            .zip(&run.energy)
            .map(|(t, e)| (*t, e - e0))
            .collect()
    };
    let (de_euler, de_rk) = (de(euler), de(rk));
    let max_abs = |d: &[(f64, f64)]| d.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let (lo, hi) = de_euler
        .iter()
        .chain(&de_rk)
        .fold((0.0f64, 0.0f64), |r, p| (r.0.min(p.1), r.1.max(p.1)));
    let pad = 0.08 * (hi - lo).max(1e-12);
    let mut chart = panel(&bottom, "Total energy drift", t_end, (lo - pad)..(hi + pad))?;
    mesh(&mut chart, "E − E(0) [J]", 1)?;
    chart.draw_series(LineSeries::new(
        [(0.0, 0.0), (t_end, 0.0)],
        BLACK.mix(0.4).stroke_width(1),
    ))?;
    chart.draw_series(LineSeries::new(
        de_euler.iter().copied(),
        EULER_COLOUR.stroke_width(2),
    ))?;
    chart.draw_series(LineSeries::new(
        de_rk.iter().copied(),
        RK4_COLOUR.stroke_width(2),
    ))?;
    let entries = [
        Entry {
            sample: Sample::Solid(RK4_COLOUR, 3),
            text: "RK4".into(),
            detail: Some(format!("max |E − E(0)| = {} J", sci(max_abs(&de_rk), 1))),
        },
        Entry {
            sample: Sample::Solid(EULER_COLOUR, 3),
            text: "semi-implicit Euler".into(),
            detail: Some(format!("max |E − E(0)| = {} J", sci(max_abs(&de_euler), 2))),
        },
        Entry {
            sample: Sample::None,
            text: format!("E(0) = {:.3} J", rk.energy[0]),
            detail: None,
        },
    ];
    legend(&bottom_legend, "Integrator", &entries)?;
    root.present()?;
    Ok(())
}

type Panel<'a> = ChartContext<
    'a,
    BitMapBackend<'a>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A chart on `area` with a title, t ∈ [0, t_end] and the given y range.
fn panel<'a>(
    area: &DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>,
    title: &str,
    t_end: f64,
    y: std::ops::Range<f64>,
) -> Result<Panel<'a>, Box<dyn Error>> {
    Ok(ChartBuilder::on(area)
        .caption(title, (FONT, 20))
        .margin_top(10)
        .margin_left(15)
        .margin_right(20)
        .margin_bottom(10)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..t_end, y)?)
}

/// The axes, tick labels (with `y_decimals` decimals on y), axis titles and a light grid.
fn mesh(chart: &mut Panel<'_>, y_desc: &str, y_decimals: usize) -> Result<(), Box<dyn Error>> {
    // A typographic minus sign, as in the axis titles.
    let x_fmt = |v: &f64| format!("{v:.1}").replace('-', "−");
    let y_fmt = |v: &f64| {
        let s = format!("{v:.y_decimals$}");
        // No "−0.0" for a tick that rounds to zero.
        if s.trim_start_matches(['-', '0', '.']).is_empty() {
            s.trim_start_matches('-').to_string()
        } else {
            s.replace('-', "−")
        }
    };
    chart
        .configure_mesh()
        .x_desc("t [s]")
        .y_desc(y_desc)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK)
        .draw()?;
    Ok(())
}

/// `x` with `decimals` decimals, in scientific notation (`5.2 × 10⁻⁹`) below 10⁻³.
fn sci(x: f64, decimals: usize) -> String {
    if x == 0.0 || x.abs() >= 1e-3 {
        return format!("{x:.decimals$}");
    }
    let s = format!("{x:.decimals$e}");
    let (mantissa, exponent) = s.split_once('e').expect("`{:e}` has an exponent");
    let superscript: String = exponent
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            d => ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'][d as usize - '0' as usize],
        })
        .collect();
    format!("{mantissa} × 10{superscript}")
}

/// A boxed legend at the top left of `area`.
fn legend(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    title: &str,
    entries: &[Entry],
) -> Result<(), Box<dyn Error>> {
    const ROW: i32 = 26;
    const DETAIL_ROW: i32 = 20;
    const X0: i32 = 5;
    const Y0: i32 = 40;
    let text = |s: &str, x: i32, y: i32, size: u32, colour: &'static RGBColor| {
        Text::new(
            s.to_string(),
            (x, y),
            TextStyle::from((FONT, size).into_font())
                .pos(Pos::new(HPos::Left, VPos::Center))
                .color(colour),
        )
    };
    let (x1, x2) = (X0 + 14, X0 + 50);
    let mut y = Y0 + 20;
    let mut items = vec![text(title, X0 + 14, y, 17, &BLACK)];
    let mut samples = Vec::new();
    for entry in entries {
        y += ROW;
        let x_text = match entry.sample {
            Sample::Solid(colour, width) => {
                samples.push(PathElement::new(
                    [(x1, y), (x2, y)],
                    colour.stroke_width(width),
                ));
                x2 + 10
            }
            Sample::Dashed(colour, width) => {
                for k in 0..3 {
                    let a = x1 + 14 * k;
                    samples.push(PathElement::new(
                        [(a, y), (a + 8, y)],
                        colour.stroke_width(width),
                    ));
                }
                x2 + 10
            }
            Sample::None => x1,
        };
        let colour: &'static RGBColor = if matches!(entry.sample, Sample::None) {
            &NOTE
        } else {
            &BLACK
        };
        items.push(text(&entry.text, x_text, y, 16, colour));
        if let Some(detail) = &entry.detail {
            y += DETAIL_ROW;
            items.push(text(detail, x_text, y, 15, &NOTE));
        }
    }
    let width = LEGEND_WIDTH as i32 - 25;
    area.draw(&Rectangle::new(
        [(X0, Y0), (X0 + width, y + 20)],
        BLACK.mix(0.5).stroke_width(1),
    ))?;
    for sample in samples {
        area.draw(&sample)?;
    }
    for item in items {
        area.draw(&item)?;
    }
    Ok(())
}
