//! The equations with named parameters kept as symbols (`--symbolic m1 L1 …`,
//! [`dynamics_model::parameters`]): a Lagrangian derivation in the book's own terms, the
//! product of exponentials in the link frames {i} (Modern Robotics §8.1, §4.1.3), whose
//! constants are graph nodes built from the file's expressions.
//!
//! ```text
//! A_i      = [Ad_{M_{0i}⁻¹}] S_i                         the screw axis in {i}
//! T_{λ,i}  = M_{λ,i} e^{[A_i] θ_i}                        (numeric rotations, symbolic lengths)
//! V_i      = [Ad_{T_{λ,i}⁻¹}] V_λ + A_i θ̇_i              the body twist of link i
//! K        = ½ Σ V_iᵀ G_i V_i,   G_i = [[I_o, m[c]], [m[c]ᵀ, m 1]]
//! P        = −Σ m_i gᵀ (p_{0i} + R_{0i} c_i)
//! M = ∂²K/∂θ̇²,  c = Ṁ θ̇ − ∂K/∂θ,  g = ∂P/∂θ,  C from the Christoffel symbols of M
//! ```
//! With `e^{[A]θ} = (R, (1 − R)(ω × v) + (ω·v) ω θ)` for a revolute axis `A = (ω, v)`,
//! `|ω| = 1`, and `(1, v θ)` for a prismatic one. Rotations (home `rpy`, axis directions)
//! are numbers; lengths, masses, centres of mass, inertias and gravity may be symbols.
//!
//! The robot's numbers (every parameter at its value) give the same polynomials as the
//! generator's Lagrangian route: `tests` in this module check it.

use super::Steps;
use crate::error::Error;
use crate::expand::spatial::VectorOps;
use crate::expand::{self, base, input, lagrangian, Q, QD};
use crate::expr::{ExprGraph, ExprId, Input};
use dynamics_model::parameters::{Expr, ScrewSpec};
use dynamics_model::{JointKind, Robot};

/// Input group of the symbolic parameters (index into [`dynamics_model::parameters::Parameters::names`]).
pub const SYM: u8 = 9;

type V3 = [ExprId; 3];
/// A rotation: numbers.
type R3 = [[f64; 3]; 3];

/// A pose with a numeric rotation and a symbolic translation.
#[derive(Clone, Copy)]
struct Pose {
    r: [[ExprId; 3]; 3],
    p: V3,
}

/// The parameters to keep as symbols, checked: each declared, and used only where it can
/// stay one.
pub fn symbols(robot: &Robot, names: &[String]) -> Result<Vec<bool>, Error> {
    let params = &robot.parameters;
    let refuse = |problem: String, fix: String| Error::Equations {
        robot: robot.name.clone(),
        problem,
        fix,
    };
    let mut keep = vec![false; params.names.len()];
    for name in names {
        let Some(i) = params.index(name) else {
            return Err(if params.is_empty() {
                refuse(
                    format!("--symbolic `{name}`: the robot declares no parameters"),
                    format!("declare it in the TOML file's `[parameters]` table (`{name} = VALUE`) and write the fields with it (`mass = \"{name}\"`)"),
                )
            } else {
                refuse(
                    format!("--symbolic `{name}` is not a parameter of the robot"),
                    format!("give one of its parameters: {}", params.names.join(", ")),
                )
            });
        };
        if let Some((path, _, why)) = params.elsewhere.iter().find(|(_, set, _)| set.contains(&i)) {
            return Err(refuse(
                format!("parameter `{name}` is used in `{path}`, where it cannot stay a symbol: {why}"),
                format!("leave `{name}` out of --symbolic (its value {} is used), or write `{path}` without it", params.values[i]),
            ));
        }
        keep[i] = true;
    }
    if robot.joints.iter().any(|j| j.mimic.is_some()) {
        return Err(refuse(
            "--symbolic does not take mimic joints".into(),
            "print the equations without --symbolic, or model the coupled joints without `mimic`"
                .into(),
        ));
    }
    Ok(keep)
}

/// The graph of `e` with the kept parameters as leaves and the others at their values.
fn node(g: &mut ExprGraph, e: &Expr, keep: &[bool], values: &[f64]) -> Result<ExprId, String> {
    Ok(match e {
        Expr::Num(x) => g.constant(*x),
        Expr::Param(i) if keep[*i] => g.input(input(SYM, *i)),
        Expr::Param(i) => g.constant(values[*i]),
        Expr::Neg(a) => {
            let a = node(g, a, keep, values)?;
            g.neg(a)
        }
        Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) => {
            let (x, y) = (node(g, a, keep, values)?, node(g, b, keep, values)?);
            match e {
                Expr::Add(..) => g.add(x, y),
                Expr::Sub(..) => g.sub(x, y),
                _ => g.mul(x, y),
            }
        }
        Expr::Div(a, b) => {
            let x = node(g, a, keep, values)?;
            let y = node(g, b, keep, values)?;
            match g.as_const(y) {
                Some(d) if d != 0.0 => g.cmul(1.0 / d, x),
                _ => return Err("it divides by a symbol".into()),
            }
        }
        Expr::Pow(a, b) => {
            let x = node(g, a, keep, values)?;
            let y = node(g, b, keep, values)?;
            match g.as_const(y) {
                Some(k) if k >= 0.0 && k == k.round() && k <= 16.0 => {
                    let mut out = g.one();
                    for _ in 0..k as u32 {
                        out = g.mul(out, x);
                    }
                    out
                }
                _ if g.as_const(x).is_some() => {
                    return Err("it raises a number to a symbolic power".into())
                }
                _ => return Err("it raises a symbol to a power other than 0, 1, 2, …".into()),
            }
        }
    })
}

struct Builder<'a> {
    robot: &'a Robot,
    keep: &'a [bool],
}

impl Builder<'_> {
    fn refuse(&self, field: String, why: String) -> Error {
        Error::Equations {
            robot: self.robot.name.clone(),
            problem: format!("`{field}` is not a polynomial in the symbolic parameters: {why}"),
            fix: "write it as a polynomial (sums and products, divisions by numbers, whole powers), or leave its parameters out of --symbolic".into(),
        }
    }

    fn expr(
        &self,
        g: &mut ExprGraph,
        e: &Expr,
        field: impl Fn() -> String,
    ) -> Result<ExprId, Error> {
        node(g, e, self.keep, &self.robot.parameters.values)
            .map_err(|why| self.refuse(field(), why))
    }

    fn exprs<const N: usize>(
        &self,
        g: &mut ExprGraph,
        es: &[Expr; N],
        field: &str,
    ) -> Result<[ExprId; N], Error> {
        let mut out = [g.zero(); N];
        for (k, e) in es.iter().enumerate() {
            out[k] = self.expr(g, e, || format!("{field}[{k}]"))?;
        }
        Ok(out)
    }
}

fn rot_const(g: &mut ExprGraph, r: &R3) -> [[ExprId; 3]; 3] {
    r.map(|row| row.map(|x| g.constant(x)))
}

/// `R v`.
fn rotate(g: &mut ExprGraph, r: &[[ExprId; 3]; 3], v: V3) -> V3 {
    [0, 1, 2].map(|i| g.dot(&r[i], &v))
}

/// `Rᵀ v`.
fn rotate_t(g: &mut ExprGraph, r: &[[ExprId; 3]; 3], v: V3) -> V3 {
    [0, 1, 2].map(|i| {
        let col = [r[0][i], r[1][i], r[2][i]];
        g.dot(&col, &v)
    })
}

fn compose(g: &mut ExprGraph, a: &Pose, b: &Pose) -> Pose {
    let mut r = [[g.zero(); 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let col = [b.r[0][j], b.r[1][j], b.r[2][j]];
            *x = g.dot(&a.r[i], &col);
        }
    }
    let rp = rotate(g, &a.r, b.p);
    Pose {
        r,
        p: g.add3(a.p, rp),
    }
}

/// The derivation's steps and `[M, c, C, g]`, on one graph, with the kept parameters as
/// symbols.
pub(super) fn derive(robot: &Robot, keep: &[bool]) -> Result<(Steps, [Vec<ExprId>; 4]), Error> {
    let b = Builder { robot, keep };
    let params = &robot.parameters;
    let n = robot.dof();
    let mut g = ExprGraph::new();
    let q: Vec<ExprId> = (0..n).map(|i| g.input(input(Q, i))).collect();
    let qd: Vec<ExprId> = (0..n).map(|i| g.input(input(QD, i))).collect();
    let gravity: V3 = match &params.gravity {
        Some(es) => b.exprs(&mut g, es, "gravity")?,
        None => [0, 1, 2].map(|k| g.constant(robot.gravity[k])),
    };
    // Homes M_{λ,i} and M_{0i} (rotations numeric).
    let mut homes: Vec<Pose> = Vec::with_capacity(n);
    let mut homes0: Vec<Pose> = Vec::with_capacity(n);
    for (i, link) in robot.links.iter().enumerate() {
        let h = &link.home;
        let r: R3 = [0, 1, 2].map(|a| [0, 1, 2].map(|c| h[(a, c)]));
        let p = match params.homes.get(&i) {
            Some(es) => b.exprs(&mut g, es, &format!("link `{}` home.xyz", link.name))?,
            None => [0, 1, 2].map(|a| g.constant(h[(a, 3)])),
        };
        let local = Pose {
            r: rot_const(&mut g, &r),
            p,
        };
        let to0 = match link.parent {
            None => local,
            Some(l) => compose(&mut g, &homes0[l], &local),
        };
        homes.push(local);
        homes0.push(to0);
    }
    // Screw axes in {0}, then A_i in {i}: ω_b = Rᵀ ω, v_b = Rᵀ (v − p × ω).
    let mut axes: Vec<(V3, V3)> = Vec::with_capacity(n);
    for (i, joint) in robot.joints.iter().enumerate() {
        let (w, v) = match params.screws.get(&i) {
            Some(ScrewSpec::Screw(es)) => {
                let s = b.exprs(&mut g, es, &format!("joint `{}` screw", joint.name))?;
                ([s[0], s[1], s[2]], [s[3], s[4], s[5]])
            }
            Some(ScrewSpec::Point { axis, point }) => {
                let pt = b.exprs(&mut g, point, &format!("joint `{}` point", joint.name))?;
                let w = axis.map(|x| g.constant(x));
                let wq = g.cross(w, pt);
                (w, wq.map(|x| g.neg(x)))
            }
            None => {
                let s = joint.screw;
                (
                    [0, 1, 2].map(|k| g.constant(s[k])),
                    [3, 4, 5].map(|k| g.constant(s[k])),
                )
            }
        };
        if joint.kind == JointKind::Prismatic && v.iter().any(|&x| g.as_const(x).is_none()) {
            return Err(Error::Equations {
                robot: robot.name.clone(),
                problem: format!("the direction of prismatic joint `{}` is written with a symbolic parameter", joint.name),
                fix: "give a prismatic joint's axis as numbers, or leave its parameters out of --symbolic".into(),
            });
        }
        let m = homes0[i];
        let wb = rotate_t(&mut g, &m.r, w);
        let pw = g.cross(m.p, w);
        let vw = g.sub3(v, pw);
        let vb = rotate_t(&mut g, &m.r, vw);
        axes.push((wb, vb));
    }
    // T_{λ,i}(θ) = M_{λ,i} e^{[A_i]θ_i}; V_i; T_{0i}.
    let mut twists: Vec<(V3, V3)> = Vec::with_capacity(n);
    let mut poses0: Vec<Pose> = Vec::with_capacity(n);
    let zero3 = g.zero3();
    for (i, joint) in robot.joints.iter().enumerate() {
        let (w, v) = axes[i];
        let e = match joint.kind {
            JointKind::Prismatic => {
                let one = g.one();
                let z = g.zero();
                Pose {
                    r: [[one, z, z], [z, one, z], [z, z, one]],
                    p: v.map(|x| g.mul(x, q[i])),
                }
            }
            JointKind::Revolute => {
                let wn = w.map(|x| g.as_const(x).unwrap_or(0.0));
                let (s, c) = (g.sin(q[i]), g.cos(q[i]));
                let one_c = {
                    let one = g.one();
                    g.sub(one, c)
                };
                // R = 1 + sin θ [ω] + (1 − cos θ) [ω]².
                let k = [
                    [0.0, -wn[2], wn[1]],
                    [wn[2], 0.0, -wn[0]],
                    [-wn[1], wn[0], 0.0],
                ];
                let mut r = [[g.zero(); 3]; 3];
                for a in 0..3 {
                    for bb in 0..3 {
                        let k2: f64 = (0..3).map(|m| k[a][m] * k[m][bb]).sum();
                        let id = if a == bb { 1.0 } else { 0.0 };
                        let t1 = g.cmul(k[a][bb], s);
                        let t2 = g.cmul(k2, one_c);
                        let t = g.add(t1, t2);
                        let idc = g.constant(id);
                        r[a][bb] = g.add(idc, t);
                    }
                }
                // p = (1 − R)(ω × v) + (ω·v) ω θ.
                let wv = g.cross(w, v);
                let rwv = rotate(&mut g, &r, wv);
                let mut p = g.sub3(wv, rwv);
                let pitch = g.dot(&w, &v);
                if g.as_const(pitch) != Some(0.0) {
                    let pt = g.mul(pitch, q[i]);
                    let lead = w.map(|x| g.mul(x, pt));
                    p = g.add3(p, lead);
                }
                Pose { r, p }
            }
        };
        let t = compose(&mut g, &homes[i], &e);
        let (wp, vp, parent0) = match robot.links[i].parent {
            None => (zero3, zero3, None),
            Some(l) => (twists[l].0, twists[l].1, Some(poses0[l])),
        };
        // [Ad_{T⁻¹}] V: ω = Rᵀ ω_λ, v = Rᵀ (v_λ − p × ω_λ); plus A_i θ̇_i.
        let wi = rotate_t(&mut g, &t.r, wp);
        let pw = g.cross(t.p, wp);
        let vv = g.sub3(vp, pw);
        let vi = rotate_t(&mut g, &t.r, vv);
        let wdot = w.map(|x| g.mul(x, qd[i]));
        let vdot = v.map(|x| g.mul(x, qd[i]));
        twists.push((g.add3(wi, wdot), g.add3(vi, vdot)));
        poses0.push(match parent0 {
            None => t,
            Some(p0) => compose(&mut g, &p0, &t),
        });
    }
    // K and P.
    let mut terms = Vec::new();
    let mut potential_terms = Vec::new();
    for (i, link) in robot.links.iter().enumerate() {
        let (w, v) = twists[i];
        let (m, c, io): (ExprId, V3, [[ExprId; 3]; 3]) = match params.inertias.get(&i) {
            Some(spec) => {
                let name = &link.name;
                let m = b.expr(&mut g, &spec.mass, || format!("link `{name}` mass"))?;
                let c = b.exprs(&mut g, &spec.com, &format!("link `{name}` com"))?;
                let e = b.exprs(&mut g, &spec.inertia, &format!("link `{name}` inertia"))?;
                let i3 = [[e[0], e[3], e[4]], [e[3], e[1], e[5]], [e[4], e[5], e[2]]];
                let io = if spec.about_origin {
                    i3
                } else {
                    // I_o = I_c + m (|c|² 1 − c cᵀ).
                    let cc = g.dot(&c, &c);
                    let mut io = i3;
                    for a in 0..3 {
                        for bb in 0..3 {
                            let outer = g.mul(c[a], c[bb]);
                            let shift = if a == bb {
                                g.sub(cc, outer)
                            } else {
                                g.neg(outer)
                            };
                            let ms = g.mul(m, shift);
                            io[a][bb] = g.add(i3[a][bb], ms);
                        }
                    }
                    io
                };
                (m, c, io)
            }
            None => {
                let gi = &link.inertia;
                let mass = gi.mass();
                let com = if mass > 0.0 {
                    gi.com()
                } else {
                    nalgebra::Vector3::zeros()
                };
                let rot = gi.rotational();
                (
                    g.constant(mass),
                    [0, 1, 2].map(|k| g.constant(com[k])),
                    [0, 1, 2].map(|a| [0, 1, 2].map(|bb| g.constant(rot[(a, bb)]))),
                )
            }
        };
        // Vᵀ G V = ωᵀ I_o ω + 2 m ω·(c × v) + m v·v.
        let iw = rotate(&mut g, &io, w);
        let rot = g.dot(&w, &iw);
        let cv = g.cross(c, v);
        let wcv = g.dot(&w, &cv);
        let mix = g.mul(m, wcv);
        let mix2 = g.cmul(2.0, mix);
        let vv = g.dot(&v, &v);
        let lin = g.mul(m, vv);
        let sum = g.sum(&[rot, mix2, lin]);
        terms.push(g.cmul(0.5, sum));
        // −m gᵀ (p + R c).
        let t = poses0[i];
        let rc = rotate(&mut g, &t.r, c);
        let pc = g.add3(t.p, rc);
        let gp = g.dot(&gravity, &pc);
        let mgp = g.mul(m, gp);
        potential_terms.push(g.neg(mgp));
    }
    for (i, joint) in robot.joints.iter().enumerate() {
        let a = joint.armature();
        if a != 0.0 {
            let sq = g.mul(qd[i], qd[i]);
            terms.push(g.cmul(0.5 * a, sq));
        }
    }
    let kinetic = g.sum(&terms);
    let potential = g.sum(&potential_terms);
    // M = ∂²K/∂θ̇², c = Ṁ θ̇ − ∂K/∂θ, g = ∂P/∂θ, C from M.
    let wrt_qd: Vec<Input> = (0..n).map(|j| input(QD, j)).collect();
    let wrt_q: Vec<Input> = (0..n).map(|j| input(Q, j)).collect();
    let momentum = g.grad(kinetic, &wrt_qd);
    let dk = g.grad(kinetic, &wrt_q);
    let mass_matrix = lagrangian::hessian(&mut g, &momentum);
    let rate = base::configuration_rate(&mut g, false, n);
    let p_dot = g.jvp(&momentum, &rate);
    let coriolis: Vec<ExprId> = (0..n).map(|i| g.sub(p_dot[i], dk[i])).collect();
    let gravity_terms = g.grad(potential, &wrt_q);
    let m_dot = g.jvp(&mass_matrix, &rate);
    let coriolis_matrix = expand::coriolis_matrix(&mut g, &mass_matrix, &m_dot, false, n);
    let twists = twists
        .into_iter()
        .map(|(ang, lin)| expand::spatial::Spatial { ang, lin })
        .collect();
    let steps = Steps::from_energies(g, twists, kinetic, potential, n);
    Ok((
        steps,
        [mass_matrix, coriolis, coriolis_matrix, gravity_terms],
    ))
}

#[cfg(test)]
mod tests {
    use super::super::{quantities, Select};
    use super::*;
    use crate::equations::poly::{Poly, Var};
    use dynamics_model::random::Rng;

    /// A spatial arm with a parameter in every field that can stay a symbol: gravity, a
    /// `screw`, a `point`, homes with numeric rotations, masses, centres of mass and
    /// inertias (about the centre of mass and about the origin), a prismatic joint, and a
    /// link whose inertia is numbers.
    const SPATIAL: &str = r#"
name = "spatial"
gravity = ["gx", 0, "-g0"]

[parameters]
gx = 0.7
g0 = 9.81
L1 = 0.4
L2 = 0.35
d = 0.12
m1 = 3.0
m2 = 2.2
c2 = 0.05
I2 = 0.03
m3 = 0.8

[[joint]]
name = "j1"
type = "revolute"
axis = [0, 0, 1]
point = ["d", 0, 0]

[joint.link]
name = "l1"
home = { xyz = ["d", 0, "L1/2"], rpy = [0.3, 0, 0] }
mass = "m1"
com = [0, "L1/10", 0]
inertia = ["m1*L1^2/12", "m1*L1^2/12", 0.01, 0, 0, 0.002]

[[joint]]
name = "j2"
type = "revolute"
screw = [0, 1, 0, "-L1", 0, "d"]

[joint.link]
name = "l2"
home = { xyz = [0, 0, "L1/2 + L2"], rpy = [-0.3, 0.2, 0] }
mass = "m2"
com = ["c2", 0, "-c2"]
inertia = ["I2", "I2", "I2", 0.001, 0, 0]
inertia_about = "origin"

[[joint]]
name = "j3"
type = "prismatic"
axis = [0, 0, 1]

[joint.link]
name = "l3"
home = { xyz = [0, 0.1, "L2"] }
mass = "m3"
inertia = [0.003, 0.003, 0.001, 0, 0, 0]

[[joint]]
name = "j4"
type = "revolute"
axis = [1, 0, 0]
point = [0, 0.1, "L1 + 2*L2"]

[joint.link]
name = "l4"
home = { xyz = [0.05, 0, 0.1] }
mass = 0.4
inertia = [0.001, 0.002, 0.002, 0, 0, 0]
"#;

    fn load(text: &str) -> Robot {
        let robot = dynamics_model::toml_format::from_str(text, "test.toml").expect("parses");
        let problems = dynamics_model::validate::validate(&robot);
        assert!(problems.is_empty(), "{problems:?}");
        robot
    }

    fn value(v: Var, params: &[f64], q: &[f64], qd: &[f64], qdd: &[f64]) -> f64 {
        match v {
            Var::Param(i) => params[i as usize],
            Var::Qdd(i) => qdd[i as usize],
            Var::Qd(i) => qd[i as usize],
            Var::Q(i) => q[i as usize],
            Var::Sin(i) => q[i as usize].sin(),
            Var::Cos(i) => q[i as usize].cos(),
        }
    }

    /// Every quantity with every parameter a symbol, evaluated at the file's values, equals
    /// the numeric robot's (the generator's Lagrangian route, and its steps).
    fn symbolic_equals_numeric(robot: &Robot) {
        let names = robot.parameters.names.clone();
        let sym = quantities(robot, true, Select::default(), &names).expect("symbolic");
        let num = quantities(robot, true, Select::default(), &[]).expect("numeric");
        assert_eq!(sym.len(), num.len());
        assert!(sym.iter().flat_map(|q| &q.entries).any(|p| p
            .terms
            .keys()
            .any(|m| m.iter().any(|(v, _)| matches!(v, Var::Param(_))))));
        let n = robot.dof();
        let mut rng = Rng::new(0x5e7b);
        for _ in 0..3 {
            let q: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let qd: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let qdd: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let at = |p: &Poly| p.eval(&|v| value(v, &robot.parameters.values, &q, &qd, &qdd));
            for (a, b) in sym.iter().zip(&num) {
                assert_eq!(a.title, b.title);
                let x: Vec<f64> = a.entries.iter().map(at).collect();
                let y: Vec<f64> = b.entries.iter().map(at).collect();
                let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let err = x
                    .iter()
                    .zip(&y)
                    .fold(0.0f64, |m, (p, r)| m.max((p - r).abs()));
                assert!(
                    err <= 1e-10 * scale + 1e-12,
                    "{}: {}: error {err:e} at scale {scale:e}",
                    robot.name,
                    a.title
                );
            }
        }
    }

    #[test]
    fn symbols_at_their_values_give_the_numeric_equations() {
        symbolic_equals_numeric(&load(include_str!("../../../robots/planar2r.toml")));
        symbolic_equals_numeric(&load(SPATIAL));
    }

    #[test]
    fn parameters_that_cannot_stay_symbols_are_refused_with_the_field() {
        let text = SPATIAL.replace("rpy = [0.3, 0, 0]", "rpy = [\"d\", 0, 0]");
        let robot = load(&text);
        let err = symbols(&robot, &["d".to_string()]).unwrap_err().to_string();
        assert!(err.contains("`joint[0].link.home.rpy[0]`"), "{err}");
        assert!(err.contains("leave `d` out of --symbolic"), "{err}");
        // The other parameters still can.
        assert!(symbols(&robot, &["L1".to_string()]).is_ok());
        let err = symbols(&robot, &["L9".to_string()])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("give one of its parameters: gx, g0, L1"),
            "{err}"
        );
        let text = SPATIAL.replace("\"I2\", 0.001", "\"I2*I2/I2\", 0.001");
        let robot = load(&text);
        let keep = symbols(&robot, &["I2".to_string()]).expect("declared");
        let err = derive(&robot, &keep).err().expect("refused").to_string();
        assert!(err.contains("`link `l2` inertia[2]`"), "{err}");
        assert!(err.contains("divides by a symbol"), "{err}");
    }
}
