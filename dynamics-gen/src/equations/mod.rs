//! Closed-form equations of motion: `M(θ)`, `c(θ, θ̇)`, `C(θ, θ̇)` and `g(θ)` as polynomials in
//! `sin θ_i`, `cos θ_i`, `θ̇_i` (and `θ_i` of prismatic joints), from the Lagrangian route's
//! expressions ([`crate::expand::Method::Lagrangian`]), with `sin² + cos² = 1` applied
//! ([`poly`]) and coefficients as exact short forms where they are one ([`number`]).
//!
//! With `steps`, the derivation first, in the order a textbook solution takes it (Modern
//! Robotics §8.1, Exercise 8.4): the body twists `V_i` of the links in their frames {i} (the
//! frames of `M_{0i}`, where the file's `G_i` are given), `K = ½ Σ V_iᵀ G_i V_i`,
//! `P = −Σ m_i gᵀ p_i`, `L = K − P`, `∂L/∂θ̇`, `d/dt ∂L/∂θ̇`, `∂L/∂θ` and
//! `τ = d/dt ∂L/∂θ̇ − ∂L/∂θ`.
//!
//! The terms of each entry are in a deterministic order: by degree in the rates (θ̇, θ̈), then
//! by total degree (both descending), then by variable. Terms whose coefficients are below
//! 1e-11 of the entry's largest are rounding leftovers of cancellations and are dropped.
//! Floating bases (whose orientation is a quaternion) are not printed.

pub mod combine;
pub mod number;
pub mod poly;
mod symbolic;

use crate::error::Error;
use crate::expand::spatial::{JointMotion, Spatial};
use crate::expand::{self, base, input, kinematics, lagrangian, Q, QD, QDD};
use crate::expr::{ExprGraph, ExprId, Input};
use combine::{Factor, Term};
use dynamics_model::lie::{adjoint, trans_inv};
use dynamics_model::Robot;
use number::magnitude;
use poly::{Poly, Var};
use std::fmt::Write as _;

/// The output format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Format {
    /// Plain Unicode text (`sin θ2`, `θ̇1²`, `√2`).
    #[default]
    Text,
    /// LaTeX: an `align*` environment per section.
    Latex,
    /// Markdown with LaTeX math (`$$ … $$`), as GitHub renders it.
    Markdown,
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "text" => Ok(Format::Text),
            "latex" => Ok(Format::Latex),
            "markdown" => Ok(Format::Markdown),
            other => Err(format!(
                "unknown format `{other}`: use `text`, `latex` or `markdown`"
            )),
        }
    }
}

/// What to print.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EquationOptions {
    /// The format.
    pub format: Format,
    /// The derivation's steps before the results.
    pub steps: bool,
    /// Significant digits of coefficients that have no short exact form (17: exact).
    pub digits: usize,
    /// Which of the results to print.
    pub select: Select,
    /// Named parameters of the robot ([`dynamics_model::parameters`]) kept as symbols; the
    /// others take their values.
    pub symbolic: Vec<String>,
}

/// Which of `M`, `c`, `C`, `g` to print (a general 7-joint arm's `c` and `C` run to tens
/// of megabytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Select {
    /// `M(θ)`.
    pub mass_matrix: bool,
    /// `c(θ, θ̇)`.
    pub coriolis: bool,
    /// `C(θ, θ̇)`.
    pub coriolis_matrix: bool,
    /// `g(θ)`.
    pub gravity: bool,
}

impl Default for Select {
    fn default() -> Self {
        Self {
            mass_matrix: true,
            coriolis: true,
            coriolis_matrix: true,
            gravity: true,
        }
    }
}

impl std::str::FromStr for Select {
    type Err = String;
    /// A comma-separated list of `M`, `c`, `C`, `g`.
    fn from_str(s: &str) -> Result<Self, String> {
        let mut out = Select {
            mass_matrix: false,
            coriolis: false,
            coriolis_matrix: false,
            gravity: false,
        };
        for word in s.split(',').map(str::trim) {
            match word {
                "M" => out.mass_matrix = true,
                "c" => out.coriolis = true,
                "C" => out.coriolis_matrix = true,
                "g" => out.gravity = true,
                other => {
                    return Err(format!(
                        "unknown quantity `{other}`: give a comma-separated list of M, c, C, g (case matters: c is the vector, C the matrix)"
                    ))
                }
            }
        }
        Ok(out)
    }
}

impl Default for EquationOptions {
    fn default() -> Self {
        Self {
            format: Format::Text,
            steps: false,
            digits: 6,
            select: Select::default(),
            symbolic: Vec::new(),
        }
    }
}

/// One named quantity: a scalar, a vector or a matrix of polynomials.
#[derive(Clone, Debug)]
pub struct Quantity {
    /// Its symbol in text (`M`, `c`, `∂L/∂θ̇`).
    pub text: &'static str,
    /// Its symbol in LaTeX.
    pub latex: &'static str,
    /// What it is, one line.
    pub title: String,
    /// `(rows, cols)`: `(1, 1)` a scalar, `(n, 1)` a vector.
    pub shape: (usize, usize),
    /// Whether only the entries on and above the diagonal are printed (symmetric).
    pub symmetric: bool,
    /// `Some(i)`: a 6-vector printed on one line as `V{i} = (ω, v)` (a link's twist).
    pub tuple: Option<usize>,
    /// The entries, row-major.
    pub entries: Vec<Poly>,
}

/// Terms below this fraction of an entry's largest coefficient are dropped as rounding
/// leftovers.
const CLEAN: f64 = 1e-11;

/// The closed-form quantities of `robot`: with `steps`, the derivation's, then `M`, `c`, `C`
/// and `g`; the parameters named in `symbols` stay symbols ([`symbolic`]).
pub fn quantities(
    robot: &Robot,
    steps: bool,
    select: Select,
    symbols: &[String],
) -> Result<Vec<Quantity>, Error> {
    let refuse = |problem: &str, fix: &str| Error::Equations {
        robot: robot.name.clone(),
        problem: problem.into(),
        fix: fix.into(),
    };
    if robot.base.floating {
        return Err(refuse(
            "a floating base's orientation is a quaternion, which has no closed form in sines and cosines",
            "print the equations of the robot with a fixed base (without --floating-base or a floating root joint)",
        ));
    }
    if robot.dof() == 0 {
        return Err(refuse(
            "it has no movable joint",
            "give a robot with at least one revolute or prismatic joint",
        ));
    }
    let var = |x: Input| -> Option<Var> {
        let i = x.index;
        match x.group {
            Q => Some(Var::Q(i)),
            QD => Some(Var::Qd(i)),
            QDD => Some(Var::Qdd(i)),
            symbolic::SYM => Some(Var::Param(i)),
            _ => None,
        }
    };
    let to_polys = |g: &ExprGraph, roots: &[ExprId]| -> Result<Vec<Poly>, Error> {
        poly::from_graph(g, roots, &var)
            .map(|ps| ps.into_iter().map(|p| p.cleaned(CLEAN)).collect())
            .map_err(|e| {
                refuse(
                    &e.to_string(),
                    "the closed form exists for revolute and prismatic joints and mimic multipliers that are whole numbers up to 8 (±1, 2, …)",
                )
            })
    };
    let mut out = Vec::new();
    let n = robot.n_coordinates();
    let (derivation, symbolic_results) = if symbols.is_empty() {
        (steps.then(|| Steps::new(robot)), None)
    } else {
        let keep = symbolic::symbols(robot, symbols)?;
        let (s, r) = symbolic::derive(robot, &keep)?;
        (Some(s), Some(r))
    };
    if let (true, Some(s)) = (steps, &derivation) {
        let g = &s.graph;
        let twists: Vec<ExprId> = s
            .twists
            .iter()
            .flat_map(|v| [v.ang, v.lin].concat())
            .collect();
        let twist_polys = to_polys(g, &twists)?;
        for (i, chunk) in twist_polys.chunks(6).enumerate() {
            out.push(Quantity {
                text: "V",
                latex: "V",
                title: format!(
                    "the body twist V{} = (ω, v) of link {} in its frame {{{}}} (the frame of M{}{}: where its G is given)",
                    i + 1,
                    crate::emit::text::inert(&robot.links[i].name),
                    i + 1,
                    i,
                    i + 1
                ),
                shape: (6, 1),
                symmetric: false,
                tuple: Some(i + 1),
                entries: chunk.to_vec(),
            });
        }
        let scalars = to_polys(g, &[s.kinetic, s.potential, s.lagrangian])?;
        for (p, (text, latex, title)) in scalars.into_iter().zip([
            ("K", "K", "the kinetic energy K = ½ Σ_i V_iᵀ G_i V_i"),
            ("P", "P", "the potential energy P = −Σ_i m_i gᵀ p_i"),
            ("L", "L", "the Lagrangian L = K − P"),
        ]) {
            out.push(Quantity {
                text,
                latex,
                title: title.into(),
                shape: (1, 1),
                symmetric: false,
                tuple: None,
                entries: vec![p],
            });
        }
        for (roots, text, latex, title) in [
            (
                &s.dl_dqd,
                "∂L/∂θ̇",
                "\\frac{\\partial L}{\\partial \\dot\\theta}",
                "the generalised momentum ∂L/∂θ̇",
            ),
            (
                &s.ddt,
                "d/dt ∂L/∂θ̇",
                "\\frac{d}{dt}\\frac{\\partial L}{\\partial \\dot\\theta}",
                "its time derivative d/dt ∂L/∂θ̇",
            ),
            (
                &s.dl_dq,
                "∂L/∂θ",
                "\\frac{\\partial L}{\\partial \\theta}",
                "∂L/∂θ",
            ),
            (
                &s.tau,
                "τ",
                "\\tau",
                "the equations of motion τ = d/dt ∂L/∂θ̇ − ∂L/∂θ",
            ),
        ] {
            out.push(Quantity {
                text,
                latex,
                title: title.into(),
                shape: (n, 1),
                symmetric: false,
                tuple: None,
                entries: to_polys(g, roots)?,
            });
        }
    }
    let expanded;
    let (graph, roots): (&ExprGraph, [&[ExprId]; 4]) = match (&derivation, &symbolic_results) {
        (Some(s), Some(r)) => (&s.graph, [&r[0], &r[1], &r[2], &r[3]]),
        _ => {
            expanded = expand::expand_method(robot, expand::Method::Lagrangian);
            let d = &expanded;
            (
                &d.graph,
                [&d.mass_matrix, &d.coriolis, &d.coriolis_matrix, &d.gravity],
            )
        }
    };
    // (printed, symbol, title, shape, expressions).
    type Printed<'a> = (bool, &'static str, &'a str, (usize, usize), &'a [ExprId]);
    let results: [Printed<'_>; 4] = [
        (
            select.mass_matrix,
            "M",
            "the mass matrix M(θ) = ∂²K/∂θ̇² (symmetric: the entries on and above the diagonal)",
            (n, n),
            roots[0],
        ),
        (
            select.coriolis,
            "c",
            "the Coriolis and centrifugal terms c(θ, θ̇) = Ṁ θ̇ − ∂K/∂θ",
            (n, 1),
            roots[1],
        ),
        (
            select.coriolis_matrix,
            "C",
            "the Coriolis matrix C(θ, θ̇) of the Christoffel symbols, C θ̇ = c",
            (n, n),
            roots[2],
        ),
        (
            select.gravity,
            "g",
            "the gravity terms g(θ) = ∂P/∂θ",
            (n, 1),
            roots[3],
        ),
    ];
    for (wanted, symbol, title, shape, roots) in results {
        if wanted {
            out.push(Quantity {
                text: symbol,
                latex: symbol,
                title: title.into(),
                shape,
                symmetric: symbol == "M",
                tuple: None,
                entries: to_polys(graph, roots)?,
            });
        }
    }
    Ok(out)
}

/// The derivation's expressions on one graph.
struct Steps {
    graph: ExprGraph,
    twists: Vec<Spatial>,
    kinetic: ExprId,
    potential: ExprId,
    lagrangian: ExprId,
    dl_dqd: Vec<ExprId>,
    ddt: Vec<ExprId>,
    dl_dq: Vec<ExprId>,
    tau: Vec<ExprId>,
}

impl Steps {
    fn new(robot: &Robot) -> Self {
        // A fixed base (floating ones are refused before): x and ν are the k coordinates.
        let expand::Inputs {
            frames: fr,
            coupling,
            k,
            mut g,
            x,
            xd,
            ..
        } = expand::Inputs::new(robot);
        let q = coupling.positions(&mut g, &x);
        let qd = coupling.rates(&mut g, &xd);
        let motions: Vec<JointMotion<'_>> = expand::joint_motions(&mut g, &fr, &q);
        let zero = g.zero();
        let v0 = Spatial {
            ang: [zero; 3],
            lin: [zero; 3],
        };
        let in_joint_frames = lagrangian::link_twists(&mut g, &motions, v0, &qd);
        // To the link frames {i}: V_i = [Ad_{T_{i,J_i}}] V_{J_i}, T_{i,J_i} = M_{0i}⁻¹ T_{0,J_i}.
        let homes = robot.home_poses();
        let mut twists = Vec::with_capacity(in_joint_frames.len());
        let mut terms = Vec::new();
        for (i, v) in in_joint_frames.iter().enumerate() {
            let t = trans_inv(&homes[i + 1]) * fr.homes[i];
            let a = adjoint(&t);
            let vj = [v.ang, v.lin].concat();
            let vi: Vec<ExprId> = (0..6)
                .map(|r| {
                    let row: Vec<ExprId> = (0..6)
                        .filter(|&c| a[(r, c)] != 0.0)
                        .map(|c| {
                            let k = g.constant(a[(r, c)]);
                            g.mul(k, vj[c])
                        })
                        .collect();
                    g.sum(&row)
                })
                .collect();
            let gi = robot.links[i].inertia.0;
            for r in 0..6 {
                for c in 0..6 {
                    if gi[(r, c)] != 0.0 {
                        let k = g.constant(0.5 * gi[(r, c)]);
                        let p = g.mul(vi[r], vi[c]);
                        terms.push(g.mul(k, p));
                    }
                }
            }
            twists.push(Spatial {
                ang: [vi[0], vi[1], vi[2]],
                lin: [vi[3], vi[4], vi[5]],
            });
        }
        for (i, f) in fr.joints.iter().enumerate() {
            if f.armature != 0.0 {
                let sq = g.mul(qd[i], qd[i]);
                let c = g.constant(0.5 * f.armature);
                terms.push(g.mul(c, sq));
            }
        }
        let kinetic = g.sum(&terms);
        let potential = kinematics::potential_energy_of(&mut g, robot, &fr, &q);
        Self::from_energies(g, twists, kinetic, potential, k)
    }

    /// The derivation from `K` and `P` of a fixed-base robot with `k` coordinates: `L = K − P`,
    /// `∂L/∂θ̇`, `∂L/∂θ`, `d/dt ∂L/∂θ̇` along `(θ̇, θ̈)` and `τ`.
    fn from_energies(
        mut g: ExprGraph,
        twists: Vec<Spatial>,
        kinetic: ExprId,
        potential: ExprId,
        k: usize,
    ) -> Self {
        let lagrangian = g.sub(kinetic, potential);
        let wrt_qd: Vec<Input> = (0..k).map(|j| input(QD, j)).collect();
        let wrt_q: Vec<Input> = (0..k).map(|j| input(Q, j)).collect();
        let dl_dqd = g.grad(lagrangian, &wrt_qd);
        let dl_dq = g.grad(lagrangian, &wrt_q);
        let mut rate = base::configuration_rate(&mut g, false, k);
        rate.extend((0..k).map(|j| (input(QD, j), g.input(input(QDD, j)))));
        let ddt = g.jvp(&dl_dqd, &rate);
        let tau = (0..k).map(|i| g.sub(ddt[i], dl_dq[i])).collect();
        Self {
            graph: g,
            twists,
            kinetic,
            potential,
            lagrangian,
            dl_dqd,
            ddt,
            dl_dq,
            tau,
        }
    }
}

/// The equations of `robot`, printed.
pub fn equations(robot: &Robot, options: &EquationOptions) -> Result<String, Error> {
    let qs = quantities(robot, options.steps, options.select, &options.symbolic)?;
    Ok(render(robot, &qs, options))
}

/// The order of terms: rate degree, then total degree in the joint variables (descending),
/// then the factors.
fn term_order(a: &Term, b: &Term) -> std::cmp::Ordering {
    let rate = |t: &Term| -> u32 {
        t.factors
            .iter()
            .filter(|(f, _)| matches!(f, Factor::Var(Var::Qd(_) | Var::Qdd(_))))
            .map(|(_, p)| p)
            .sum()
    };
    let total = |t: &Term| -> u32 {
        t.factors
            .iter()
            .filter(|(f, _)| !matches!(f, Factor::Var(Var::Param(_))))
            .map(|(_, p)| p)
            .sum()
    };
    rate(b)
        .cmp(&rate(a))
        .then(total(b).cmp(&total(a)))
        .then(a.factors.cmp(&b.factors))
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

fn superscript(p: u32) -> String {
    p.to_string()
        .chars()
        .map(|c| SUPERSCRIPTS[c.to_digit(10).unwrap_or(0) as usize])
        .collect()
}

/// One factor `v^p` in text: `θ̇2²`, `sin²θ2`, `θ3`.
fn factor_text(v: Var, p: u32, names: &[String]) -> String {
    let pow = if p == 1 {
        String::new()
    } else {
        superscript(p)
    };
    match v {
        Var::Param(i) => format!("{}{pow}", names[i as usize]),
        Var::Qd(i) => format!("θ̇{}{pow}", i + 1),
        Var::Qdd(i) => format!("θ̈{}{pow}", i + 1),
        Var::Q(i) => format!("θ{}{pow}", i + 1),
        Var::Sin(i) if p == 1 => format!("sin θ{}", i + 1),
        Var::Cos(i) if p == 1 => format!("cos θ{}", i + 1),
        Var::Sin(i) => format!("sin{pow}θ{}", i + 1),
        Var::Cos(i) => format!("cos{pow}θ{}", i + 1),
    }
}

/// `θ1+θ2−θ3` (text) or `\\theta_{1}+\\theta_{2}-\\theta_{3}` (LaTeX).
fn angle_string(a: &combine::Angle, latex: bool) -> String {
    let mut out = String::new();
    for (k, &(i, s)) in a.iter().enumerate() {
        match (k, s < 0, latex) {
            (_, true, false) => out.push('−'),
            (_, true, true) => out.push('-'),
            (0, false, _) => {}
            (_, false, _) => out.push('+'),
        }
        if latex {
            out.push_str(&format!("\\theta_{{{}}}", i + 1));
        } else {
            out.push_str(&format!("θ{}", i + 1));
        }
    }
    out
}

/// One printed factor: a variable, or the sine or cosine of an angle.
fn factor_string(f: &Factor, p: u32, latex: bool, names: &[String]) -> String {
    match f {
        Factor::Var(v) if latex => factor_latex(*v, p, names),
        Factor::Var(v) => factor_text(*v, p, names),
        Factor::Trig(cos, a) if a.len() == 1 && a[0].1 > 0 => {
            let v = if *cos {
                Var::Cos(a[0].0)
            } else {
                Var::Sin(a[0].0)
            };
            if latex {
                factor_latex(v, p, names)
            } else {
                factor_text(v, p, names)
            }
        }
        Factor::Trig(cos, a) => {
            let name = if *cos { "cos" } else { "sin" };
            let angle = angle_string(a, latex);
            match (latex, p) {
                (false, 1) => format!("{name}({angle})"),
                (false, p) => format!("{name}{}({angle})", superscript(p)),
                (true, 1) => format!("\\{name}({angle})"),
                (true, p) => format!("\\{name}^{{{p}}}({angle})"),
            }
        }
    }
}

/// One factor in LaTeX.
fn factor_latex(v: Var, p: u32, names: &[String]) -> String {
    let pow = if p == 1 {
        String::new()
    } else {
        format!("^{{{p}}}")
    };
    match v {
        Var::Param(i) => format!("{}{pow}", latex_name(&names[i as usize])),
        Var::Qd(i) => format!("\\dot\\theta_{{{}}}{pow}", i + 1),
        Var::Qdd(i) => format!("\\ddot\\theta_{{{}}}{pow}", i + 1),
        Var::Q(i) => format!("\\theta_{{{}}}{pow}", i + 1),
        Var::Sin(i) => format!("\\sin{pow}\\theta_{{{}}}", i + 1),
        Var::Cos(i) => format!("\\cos{pow}\\theta_{{{}}}", i + 1),
    }
}

/// A parameter's name in LaTeX: trailing digits as a subscript (`L1` → `L_{1}`), `_` escaped.
fn latex_name(name: &str) -> String {
    let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let digits = &name[stem.len()..];
    let stem = stem.replace('_', "\\_");
    let stem = if stem.chars().count() > 1 {
        format!("\\mathit{{{stem}}}")
    } else {
        stem
    };
    if digits.is_empty() {
        format!("{{{stem}}}")
    } else {
        format!("{{{stem}_{{{digits}}}}}")
    }
}

/// A polynomial in text or LaTeX; `names` are the robot's parameters ([`Var::Param`]).
pub fn poly_string(p: &Poly, latex: bool, digits: usize, names: &[String]) -> String {
    if p.terms.is_empty() {
        return "0".into();
    }
    let mut terms = combine::combined(p);
    terms.sort_by(term_order);
    let mut out = String::new();
    for (
        k,
        Term {
            coef: c,
            factors: m,
        },
    ) in terms.into_iter().enumerate()
    {
        let minus = c < 0.0;
        match (k, minus, latex) {
            (0, true, false) => out.push('−'),
            (0, true, true) => out.push('-'),
            (0, false, _) => {}
            (_, true, false) => out.push_str(" − "),
            (_, true, true) => out.push_str(" - "),
            (_, false, _) => out.push_str(" + "),
        }
        let mag = magnitude(c, digits);
        let mut parts: Vec<String> = Vec::new();
        if !mag.is_one() || m.is_empty() {
            parts.push(if latex { mag.latex() } else { mag.text() });
        }
        for (f, pw) in &m {
            parts.push(factor_string(f, *pw, latex, names));
        }
        out.push_str(&parts.join(if latex { " \\, " } else { " " }));
    }
    out
}

/// The indices of entry `(r, c)` of a quantity of shape `(rows, cols)`, 1-based, joined
/// without a separator when every index is one digit.
fn indices((rows, cols): (usize, usize), r: usize, c: usize) -> String {
    let wide = rows >= 10 || cols >= 10;
    match (rows, cols) {
        (1, 1) => String::new(),
        (_, 1) => format!("{}", r + 1),
        _ if wide => format!("{},{}", r + 1, c + 1),
        _ => format!("{}{}", r + 1, c + 1),
    }
}

/// Terms on one line of a LaTeX equation: a line wider than TeX's largest dimension
/// (16384 pt) is a fatal error, and a general arm's entries run to thousands of terms.
const TERMS_PER_LINE: usize = 6;

/// A LaTeX polynomial cut into lines of `per_line` terms, each after the first starting
/// with its sign.
fn wrap_latex(body: &str, per_line: usize) -> Vec<String> {
    let mut terms: Vec<&str> = Vec::new();
    let mut start = 0;
    let bytes = body.as_bytes();
    let mut i = 1;
    while i + 2 < bytes.len() {
        if bytes[i] == b' '
            && (bytes[i + 1] == b'+' || bytes[i + 1] == b'-')
            && bytes[i + 2] == b' '
        {
            terms.push(&body[start..i]);
            start = i + 1;
            i += 3;
        } else {
            i += 1;
        }
    }
    terms.push(&body[start..]);
    terms.chunks(per_line).map(|c| c.join(" ")).collect()
}

fn render(robot: &Robot, qs: &[Quantity], options: &EquationOptions) -> String {
    let names: Vec<String> = robot
        .joints
        .iter()
        .filter(|j| j.mimic.is_none())
        .map(|j| crate::emit::text::inert(&j.name))
        .collect();
    let legend: Vec<String> = names
        .iter()
        .enumerate()
        .map(|(i, n)| format!("θ{} = {n}", i + 1))
        .collect();
    let params = &robot.parameters;
    let kept: Vec<usize> = options
        .symbolic
        .iter()
        .filter_map(|n| params.index(n))
        .collect();
    let gravity: Vec<String> = match &params.gravity {
        Some(es) if !kept.is_empty() => es
            .iter()
            .map(|e| {
                // The kept parameters by name, the others by value.
                let mut names = params.names.clone();
                for (i, n) in names.iter_mut().enumerate() {
                    if !kept.contains(&i) {
                        *n = format!("{}", params.values[i]);
                    }
                }
                e.to_text(&names)
            })
            .collect(),
        _ => robot.gravity.iter().map(|x| x.to_string()).collect(),
    };
    let symbols = if kept.is_empty() {
        String::new()
    } else {
        let values: Vec<String> = (0..params.names.len())
            .filter(|i| !kept.contains(i))
            .map(|i| format!("{} = {}", params.names[i], params.values[i]))
            .collect();
        format!(
            "; symbols {}{}",
            options.symbolic.join(", "),
            if values.is_empty() {
                String::new()
            } else {
                format!(" (and {})", values.join(", "))
            }
        )
    };
    let header = format!(
        "Equations of motion of {} (Lagrangian route), τ = M(θ) θ̈ + c(θ, θ̇) + g(θ); {}; gravity ({}) m/s²{symbols}; SI units (rad, m, kg, s).",
        crate::emit::text::inert(&robot.name),
        legend.join(", "),
        gravity.join(", "),
    );
    let mut out = String::new();
    let latex = options.format != Format::Text;
    match options.format {
        Format::Text => writeln!(out, "{header}").ok(),
        Format::Markdown => writeln!(out, "# Equations of motion\n\n{header}").ok(),
        Format::Latex => writeln!(
            out,
            "% {header}\n\\documentclass{{article}}\n\\usepackage{{amsmath}}\n\\allowdisplaybreaks\n\\begin{{document}}"
        )
        .ok(),
    };
    for q in qs {
        match options.format {
            Format::Text => writeln!(out, "\n{}:", q.title).ok(),
            Format::Markdown => writeln!(out, "\n## {}\n", q.title).ok(),
            Format::Latex => writeln!(out, "\n% {}\n\\begin{{align*}}", q.title).ok(),
        };
        let (rows, cols) = q.shape;
        let mut lines = Vec::new();
        if let Some(i) = q.tuple {
            let parts: Vec<String> = q
                .entries
                .iter()
                .map(|p| poly_string(p, latex, options.digits, &robot.parameters.names))
                .collect();
            lines.push(if latex {
                format!(
                    "{}_{{{i}}} &= \\left( {} \\right)",
                    q.latex,
                    parts.join(",\\; ")
                )
            } else {
                format!("  {}{i} = ({})", q.text, parts.join(", "))
            });
        }
        for r in 0..rows {
            for c in 0..cols {
                if q.tuple.is_some() || (q.symmetric && c < r) {
                    continue;
                }
                let idx = indices(q.shape, r, c);
                let body = poly_string(
                    &q.entries[r * cols + c],
                    latex,
                    options.digits,
                    &robot.parameters.names,
                );
                let line = if latex {
                    let sym = if idx.is_empty() {
                        q.latex.to_string()
                    } else {
                        format!("{}_{{{idx}}}", q.latex)
                    };
                    wrap_latex(&body, TERMS_PER_LINE)
                        .iter()
                        .enumerate()
                        .map(|(k, part)| {
                            if k == 0 {
                                format!("{sym} &= {part}")
                            } else {
                                format!("&\\quad {part}")
                            }
                        })
                        .collect::<Vec<_>>()
                        .join(" \\\\\n")
                } else {
                    format!("  {}{idx} = {body}", q.text)
                };
                lines.push(line);
            }
        }
        match options.format {
            Format::Text => {
                for l in lines {
                    writeln!(out, "{l}").ok();
                }
            }
            Format::Markdown => {
                writeln!(
                    out,
                    "$$\n\\begin{{aligned}}\n{}\n\\end{{aligned}}\n$$",
                    lines.join(" \\\\\n")
                )
                .ok();
            }
            Format::Latex => {
                writeln!(out, "{}\n\\end{{align*}}", lines.join(" \\\\\n")).ok();
            }
        }
    }
    if options.format == Format::Latex {
        writeln!(out, "\n\\end{{document}}").ok();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pendulum() -> Robot {
        dynamics_model::load::load("pendulum", &Default::default()).expect("shipped")
    }

    fn lines(text: &str) -> Vec<&str> {
        text.lines().map(str::trim).collect()
    }

    /// Exercise 8.4 as `tests/data/seed-cases.md` corrects it, line by line (the order of
    /// terms is the printer's: rate degree, then total degree, descending).
    #[test]
    fn pendulum_closed_forms_and_steps() {
        let options = EquationOptions {
            steps: true,
            ..Default::default()
        };
        let text = equations(&pendulum(), &options).unwrap();
        let got = lines(&text);
        for want in [
            "V1 = (0, 0, θ̇1, 0, θ̇1, 0)",
            "V2 = (θ̇2, θ̇1 sin θ2, θ̇1 cos θ2, −θ̇1 sin θ2, θ̇1 cos θ2 + θ̇2, −θ̇1 sin θ2)",
            "K = 3 θ̇1² sin²θ2 + 2 θ̇1 θ̇2 cos θ2 + 4 θ̇1² + 3 θ̇2²",
            "P = −20 cos θ2",
            "L = 3 θ̇1² sin²θ2 + 2 θ̇1 θ̇2 cos θ2 + 4 θ̇1² + 3 θ̇2² + 20 cos θ2",
            "∂L/∂θ̇1 = 6 θ̇1 sin²θ2 + 2 θ̇2 cos θ2 + 8 θ̇1",
            "∂L/∂θ̇2 = 2 θ̇1 cos θ2 + 6 θ̇2",
            "d/dt ∂L/∂θ̇1 = 12 θ̇1 θ̇2 sin θ2 cos θ2 − 2 θ̇2² sin θ2 + 6 θ̈1 sin²θ2 + 2 θ̈2 cos θ2 + 8 θ̈1",
            "d/dt ∂L/∂θ̇2 = −2 θ̇1 θ̇2 sin θ2 + 2 θ̈1 cos θ2 + 6 θ̈2",
            "∂L/∂θ1 = 0",
            "∂L/∂θ2 = 6 θ̇1² sin θ2 cos θ2 − 2 θ̇1 θ̇2 sin θ2 − 20 sin θ2",
            "τ1 = 12 θ̇1 θ̇2 sin θ2 cos θ2 − 2 θ̇2² sin θ2 + 6 θ̈1 sin²θ2 + 2 θ̈2 cos θ2 + 8 θ̈1",
            "τ2 = −6 θ̇1² sin θ2 cos θ2 + 2 θ̈1 cos θ2 + 6 θ̈2 + 20 sin θ2",
            "M11 = 6 sin²θ2 + 8",
            "M12 = 2 cos θ2",
            "M22 = 6",
            "c1 = 12 θ̇1 θ̇2 sin θ2 cos θ2 − 2 θ̇2² sin θ2",
            "c2 = −6 θ̇1² sin θ2 cos θ2",
            "C11 = 6 θ̇2 sin θ2 cos θ2",
            "C12 = 6 θ̇1 sin θ2 cos θ2 − 2 θ̇2 sin θ2",
            "C21 = −6 θ̇1 sin θ2 cos θ2",
            "C22 = 0",
            "g1 = 0",
            "g2 = 20 sin θ2",
        ] {
            assert!(got.contains(&want), "missing `{want}` in\n{text}");
        }
        // Deterministic.
        assert_eq!(text, equations(&pendulum(), &options).unwrap());
    }

    #[test]
    fn latex_and_markdown_environments_are_balanced() {
        for format in [Format::Latex, Format::Markdown] {
            let options = EquationOptions {
                format,
                steps: true,
                ..Default::default()
            };
            let text = equations(&pendulum(), &options).unwrap();
            for env in ["align*", "aligned", "document"] {
                let open = text.matches(&format!("\\begin{{{env}}}")).count();
                let close = text.matches(&format!("\\end{{{env}}}")).count();
                assert_eq!(open, close, "{format:?} {env}");
            }
            let braces = text.chars().fold(0i64, |d, c| match c {
                '{' => d + 1,
                '}' => d - 1,
                _ => d,
            });
            assert_eq!(braces, 0, "{format:?}: unbalanced braces");
            assert!(
                text.contains("M_{11} &= 6 \\, \\sin^{2}\\theta_{2} + 8"),
                "{text}"
            );
            assert_eq!(text.matches("$$").count() % 2, 0);
        }
    }

    #[test]
    fn floating_bases_are_refused_with_the_fix() {
        let mut r = pendulum();
        r.base.floating = true;
        let e = equations(&r, &EquationOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("quaternion") && e.contains("fixed base"), "{e}");
    }

    #[test]
    fn selections_parse() {
        let s: Select = "M,g".parse().unwrap();
        assert!(s.mass_matrix && s.gravity && !s.coriolis && !s.coriolis_matrix);
        let e = "M,x".parse::<Select>().unwrap_err();
        assert!(e.contains("`x`"), "{e}");
    }
}
