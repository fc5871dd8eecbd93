//! Operation counts and code size of each generated function.
//!
//! The counts are those of the expression graph live from a function's outputs, every
//! shared node counted once ([`crate::expr::ExprGraph::op_counts`]), after the merging of
//! equivalent nodes the emitter applies ([`crate::expr::equivalent`]): exactly the
//! arithmetic the generated straight-line code performs. For comparison, Featherstone's
//! commonly cited count for the recursive Newton–Euler algorithm on an n-joint chain of
//! revolute joints is `93n − 69` multiplications and `81n − 66` additions
//! ([`featherstone_rnea`]).

use crate::emit::Generated;
use crate::error::Error;
use crate::expand::kinematics::FrameKinematics;
use crate::expr::{ExprId, OpCounts};
use crate::options::Options;
use dynamics_model::Robot;
use quote::quote;
use std::fmt;

/// The statistics of one generated function.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FunctionStats {
    /// The function's name (`mass_matrix`, `coriolis`, `gravity`, `inverse_dynamics`,
    /// `forward_dynamics`, `kinetic_energy`, `potential_energy`, `end_effector_pose`,
    /// `jacobian_space`, `jacobian_body`, and with
    /// named frames `frame_poses`, `frame_jacobians_space`, `frame_jacobians_body`).
    pub name: &'static str,
    /// Its operation counts.
    pub ops: OpCounts,
    /// The number of lines of the function (signature to closing brace, without its doc
    /// comment) in the formatted code; 0 when it is not found in the code.
    pub lines: usize,
}

/// The statistics of every generated function of one robot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stats {
    /// The generated struct's name.
    pub struct_name: String,
    /// n, the number of joints.
    pub dof: usize,
    /// One entry per generated function, in the order of the generated `impl`.
    pub functions: Vec<FunctionStats>,
    /// What a kinematic tree saves (`None` when `M` has no structural zeros).
    pub sparsity: Option<Sparsity>,
}

/// The savings of a tree's branch-induced sparsity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sparsity {
    /// nv: `M` is nv×nv.
    pub nv: usize,
    /// Entries of `M` between dofs on different branches: known zeros, never computed.
    pub zeros: usize,
    /// Factorising and solving `M x = b` with the tree's zeros (Lᵀ D L, no fill-in), with
    /// every other entry of `M` and of `b` an opaque value.
    pub sparse_solve: OpCounts,
    /// The same for a dense nv×nv `M` (what a serial chain of nv dofs needs).
    pub dense_solve: OpCounts,
}

/// The operation counts of solving `M x = b` (factorisation and substitutions) for an
/// nv×nv `M` whose entries are opaque values except where `zero(i, j)`.
fn solve_counts(nv: usize, zero: impl Fn(usize, usize) -> bool) -> (OpCounts, OpCounts) {
    use crate::expr::{ExprGraph, Input};
    let mut g = ExprGraph::new();
    let leaf = |g: &mut ExprGraph, group: u8, k: usize| {
        g.input(Input {
            group,
            index: k as u16,
        })
    };
    let entry = |g: &mut ExprGraph, i: usize, j: usize| {
        let (i, j) = (i.max(j), i.min(j));
        leaf(g, 4, i * nv + j)
    };
    let b: Vec<ExprId> = (0..nv).map(|i| leaf(&mut g, 5, i)).collect();
    let dense: Vec<ExprId> = (0..nv * nv)
        .map(|k| entry(&mut g, k / nv, k % nv))
        .collect();
    let zero_id = g.zero();
    let sparse: Vec<ExprId> = (0..nv * nv)
        .map(|k| {
            if zero(k / nv, k % nv) {
                zero_id
            } else {
                dense[k]
            }
        })
        .collect();
    let x_sparse = crate::expand::ldlt::ltdl_solve(&mut g, &sparse, &b);
    let x_dense = crate::expand::ldlt::ldlt_solve(&mut g, &dense, &b);
    (g.op_counts(&x_sparse), g.op_counts(&x_dense))
}

/// Featherstone's commonly cited operation count of the recursive Newton–Euler algorithm
/// for n revolute joints: `(93n − 69 multiplications, 81n − 66 additions)` (saturating at 0).
pub fn featherstone_rnea(n: usize) -> (usize, usize) {
    ((93 * n).saturating_sub(69), (81 * n).saturating_sub(66))
}

/// The operation counts of the function `roots` of `g` as it is emitted: after
/// [`crate::expr::equivalent::merge_equivalent`].
fn counted(g: &crate::expr::ExprGraph, roots: &[ExprId]) -> OpCounts {
    match crate::expr::equivalent::merge_equivalent(g, roots) {
        Some((merged, roots)) => merged.op_counts(&roots),
        None => g.op_counts(roots),
    }
}

/// The statistics of `generated`, with line counts taken from `code`, the formatted code of
/// the same generation (e.g. the output of [`crate::generate_file`]).
pub fn stats(generated: &Generated, code: &str) -> Stats {
    let d = &generated.dynamics;
    let outputs: [(&'static str, &[ExprId]); 5] = [
        ("mass_matrix", &d.mass_matrix),
        ("coriolis", &d.coriolis),
        ("gravity", &d.gravity),
        ("inverse_dynamics", &d.inverse_dynamics),
        ("forward_dynamics", &d.forward_dynamics),
    ];
    let mut functions: Vec<FunctionStats> = outputs
        .iter()
        .map(|&(name, roots)| FunctionStats {
            name,
            ops: counted(&d.graph, roots),
            lines: function_lines(code, name),
        })
        .collect();
    functions.push(FunctionStats {
        name: "kinetic_energy",
        ops: counted(&d.graph, &[d.kinetic_energy]),
        lines: function_lines(code, "kinetic_energy"),
    });
    functions.push(FunctionStats {
        name: "mass_matrix_dot",
        ops: counted(&d.graph, &d.mass_matrix_dot),
        lines: function_lines(code, "mass_matrix_dot"),
    });
    // friction(q̇) is written directly: per coordinate a product for the damping and, per
    // joint with Coulomb friction, a sign test (not counted) or tanh (counted as a product
    // and a call, like sin/cos), and the sums.
    let robot = &generated.robot;
    let mut friction = crate::expr::OpCounts::default();
    let couplings = robot.couplings();
    for c in 0..robot.n_coordinates() {
        let members: Vec<usize> = (0..robot.joints.len())
            .filter(|&j| couplings[j].coordinate == c)
            .collect();
        let damped = members.iter().any(|&j| robot.joints[j].damping != 0.0);
        let coulomb = members
            .iter()
            .filter(|&&j| robot.joints[j].friction != 0.0)
            .count();
        let terms = usize::from(damped) + coulomb;
        friction.mul += usize::from(damped);
        friction.add_sub += terms.saturating_sub(1);
        if let Some(crate::options::Friction::Smooth(_)) = generated.friction {
            friction.mul += 2 * coulomb;
            friction.sin_cos += coulomb;
        }
    }
    functions.push(FunctionStats {
        name: "friction",
        ops: friction,
        lines: function_lines(code, "friction"),
    });
    functions.push(FunctionStats {
        name: "coriolis_matrix",
        ops: counted(&d.graph, &d.coriolis_matrix),
        lines: function_lines(code, "coriolis_matrix"),
    });
    let both: Vec<ExprId> = d.mass_matrix.iter().chain(&d.bias).copied().collect();
    functions.push(FunctionStats {
        name: "mass_matrix_and_bias",
        ops: counted(&d.graph, &both),
        lines: function_lines(code, "mass_matrix_and_bias"),
    });
    functions.push(FunctionStats {
        name: "mass_matrix_lower_into",
        ops: counted(&d.graph, &d.mass_matrix),
        lines: function_lines(code, "mass_matrix_lower_into"),
    });
    // The unrolled part of constrained forward dynamics: the factor of M and the
    // unconstrained accelerations (the K-sized part runs in loops and depends on the
    // caller's K).
    let factor: Vec<ExprId> = d
        .mass_matrix_factor
        .iter()
        .chain(&d.mass_matrix_inv_d)
        .chain(&d.unconstrained)
        .copied()
        .collect();
    functions.push(FunctionStats {
        name: "constrained_forward_dynamics",
        ops: counted(&d.graph, &factor),
        lines: function_lines(code, "constrained_forward_dynamics"),
    });
    let t = &generated.task_space;
    let pivots: Vec<ExprId> = t.pivots.iter().flat_map(|&(a, b)| [a, b]).collect();
    let with_pivots = |x: &[ExprId]| -> Vec<ExprId> { pivots.iter().chain(x).copied().collect() };
    for (name, roots) in [
        ("end_effector_forces", t.end_effector_forces.clone()),
        (
            "inverse_dynamics_with_tip",
            t.inverse_dynamics_with_tip.clone(),
        ),
        (
            "forward_dynamics_with_tip",
            t.forward_dynamics_with_tip.clone(),
        ),
        ("task_space_mass_matrix", with_pivots(&t.mass_matrix)),
        ("task_space_bias", with_pivots(&t.bias)),
    ] {
        functions.push(FunctionStats {
            name,
            ops: counted(&t.graph, &roots),
            lines: function_lines(code, name),
        });
    }
    if let Some(x) = &generated.derivatives {
        let cat = |parts: &[&[ExprId]]| -> Vec<ExprId> { parts.concat() };
        for (name, roots) in [
            (
                "inverse_dynamics_derivatives",
                cat(&[&x.d_tau_dq, &x.d_tau_dqd]),
            ),
            (
                "inverse_dynamics_with_derivatives",
                cat(&[&x.inverse_dynamics, &x.d_tau_dq, &x.d_tau_dqd]),
            ),
            (
                "forward_dynamics_derivatives",
                cat(&[&x.d_qdd_dq, &x.d_qdd_dqd, &x.mass_matrix_inverse]),
            ),
            (
                "forward_dynamics_with_derivatives",
                cat(&[
                    &x.forward_dynamics,
                    &x.d_qdd_dq,
                    &x.d_qdd_dqd,
                    &x.mass_matrix_inverse,
                ]),
            ),
            ("mass_matrix_inverse", x.mass_matrix_inverse.clone()),
            ("gravity_derivative", x.gravity_derivative.clone()),
        ] {
            functions.push(FunctionStats {
                name,
                ops: counted(&x.graph, &roots),
                lines: function_lines(code, name),
            });
        }
    }
    // The batch functions: the single-state function's operations, per state (each on all
    // `B` lanes at once).
    for (name, roots) in [
        ("inverse_dynamics_batch", &d.inverse_dynamics),
        ("forward_dynamics_batch", &d.forward_dynamics),
        ("mass_matrix_batch", &d.mass_matrix),
        ("gravity_batch", &d.gravity),
    ] {
        functions.push(FunctionStats {
            name,
            ops: counted(&d.graph, roots),
            lines: function_lines(code, name),
        });
    }
    if let Some(r) = &generated.regressor {
        for (name, roots) in [
            ("regressor", r.y.clone()),
            ("inertial_parameters", r.parameter_nodes.clone()),
            ("base_regressor", r.base_y()),
            ("base_parameters", r.base_map.clone()),
        ] {
            functions.push(FunctionStats {
                name,
                ops: counted(&r.graph, &roots),
                lines: function_lines(code, name),
            });
        }
    }
    let k = &generated.kinematics;
    let all = |f: fn(&FrameKinematics) -> &Vec<ExprId>| -> Vec<ExprId> {
        k.frames.iter().flat_map(|x| f(x).iter().copied()).collect()
    };
    let mut kinematics: Vec<(&'static str, Vec<ExprId>)> = vec![
        ("potential_energy", vec![k.potential_energy]),
        ("end_effector_pose", k.end_effector.pose.clone()),
        ("jacobian_space", k.end_effector.jacobian_space.clone()),
        ("jacobian_body", k.end_effector.jacobian_body.clone()),
        ("jacobian_space_dot", k.jacobian_space_dot.clone()),
        ("jacobian_body_dot", k.jacobian_body_dot.clone()),
    ];
    if !k.frames.is_empty() {
        kinematics.extend([
            ("frame_poses", all(|x| &x.pose)),
            ("frame_jacobians_space", all(|x| &x.jacobian_space)),
            ("frame_jacobians_body", all(|x| &x.jacobian_body)),
        ]);
    }
    functions.extend(kinematics.iter().map(|(name, roots)| FunctionStats {
        name,
        ops: counted(&k.graph, roots),
        lines: function_lines(code, name),
    }));
    // Only what was generated (a `functions` selection leaves some out).
    functions.retain(|f| function_lines(code, f.name) > 0);
    let nv = d.nv;
    // Structural zeros: off-diagonal zeros that the tree explains (dofs on different
    // branches), not zeros that happen to fold.
    let robot = &generated.robot;
    let off = nv - d.dof;
    // The joints behind each joint coordinate (with mimic joints: a leader and its followers).
    let coupling = crate::expand::mimic::Coupling::new(robot);
    let joints: Vec<Vec<usize>> = (off..nv)
        .map(|r| coupling.members(r).map(|i| i - off).collect())
        .collect();
    let on_path = |a: usize, b: usize| {
        joints[a]
            .iter()
            .any(|&i| joints[b].iter().any(|&j| robot.path_to(i).contains(&j)))
    };
    let related = |i: usize, j: usize| {
        i < off || j < off || on_path(i - off, j - off) || on_path(j - off, i - off)
    };
    let zeros = (0..nv * nv).filter(|&k| !related(k / nv, k % nv)).count();
    let sparsity = (zeros > 0).then(|| {
        let (sparse_solve, dense_solve) = solve_counts(nv, |i, j| !related(i, j));
        Sparsity {
            nv,
            zeros,
            sparse_solve,
            dense_solve,
        }
    });
    Stats {
        struct_name: generated.struct_name.clone(),
        dof: d.dof,
        functions,
        sparsity,
    }
}

/// Expands `robot` once and returns its statistics (lines counted in the formatted `impl`).
pub fn robot_stats(robot: &Robot, options: &Options) -> Result<Stats, Error> {
    let generated = crate::emit::generate_impl(robot, options)?;
    let (item, block) = (&generated.struct_item, &generated.impl_block);
    let file: syn::File = syn::parse2(quote!(#item #block))
        .map_err(|e| Error::Internal(format!("generated code does not parse: {e}")))?;
    let code = prettyplease::unparse(&file);
    Ok(stats(&generated, &code))
}

/// Lines of `fn name` in `code`: from the line declaring it to its closing brace, which
/// prettyplease puts alone on a line at the declaration's indentation.
pub fn function_lines(code: &str, name: &str) -> usize {
    let needles = [format!("fn {name}("), format!("fn {name}<")];
    let lines: Vec<&str> = code.lines().collect();
    let Some(start) = lines
        .iter()
        .position(|l| needles.iter().any(|n| l.contains(n)))
    else {
        return 0;
    };
    let indent = lines[start].len() - lines[start].trim_start().len();
    let close = format!("{}}}", " ".repeat(indent));
    lines[start..]
        .iter()
        .position(|l| *l == close)
        .map_or(0, |end| end + 1)
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The name column as wide as the longest name (frame functions carry user names).
        let w = self
            .functions
            .iter()
            .map(|s| s.name.chars().count())
            .max()
            .unwrap_or(0)
            .max(28);
        writeln!(
            f,
            "{:<w$} {:>7} {:>8} {:>5} {:>5} {:>8} {:>5} {:>7}",
            "function", "mul", "add/sub", "div", "sqrt", "sin/cos", "neg", "lines"
        )?;
        for s in &self.functions {
            let o = s.ops;
            writeln!(
                f,
                "{:<w$} {:>7} {:>8} {:>5} {:>5} {:>8} {:>5} {:>7}",
                s.name, o.mul, o.add_sub, o.div, o.sqrt, o.sin_cos, o.neg, s.lines
            )?;
        }
        if let Some(sp) = &self.sparsity {
            writeln!(
                f,
                "tree: {} of the {}x{} entries of M are structural zeros (dofs on different branches), never computed",
                sp.zeros, sp.nv, sp.nv
            )?;
            let (s, d) = (sp.sparse_solve, sp.dense_solve);
            writeln!(
                f,
                "solving M x = b with the tree's zeros (Lᵀ D L): {} mul, {} add/sub, {} div; dense (a serial chain of {} dofs): {} mul, {} add/sub, {} div",
                s.mul, s.add_sub, s.div, sp.nv, d.mul, d.add_sub, d.div
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn featherstone_count_for_six_joints() {
        assert_eq!(featherstone_rnea(6), (489, 420));
        assert_eq!(featherstone_rnea(0), (0, 0));
    }

    #[test]
    fn function_lines_counts_signature_to_closing_brace() {
        let code = "impl A {\n    /// doc\n    pub fn f(&self) -> u8 {\n        let x = 1;\n        x\n    }\n    pub fn g() {}\n}\n";
        assert_eq!(function_lines(code, "f"), 4);
        assert_eq!(function_lines(code, "h"), 0);
    }

    #[test]
    fn pendulum_mass_matrix_depends_on_q2_only() {
        let robot = dynamics_model::load("pendulum", &Default::default()).unwrap();
        let s = robot_stats(&robot, &Options::default()).unwrap();
        // Every function but the three of named frames.
        assert_eq!(s.functions.len(), crate::options::FUNCTIONS.len() - 3);
        assert_eq!(s.dof, 2);
        // M(q) of a serial chain never depends on q_1: only q_2 needs a sin/cos.
        assert_eq!(s.functions[0].name, "mass_matrix");
        assert_eq!(s.functions[0].ops.sin_cos, 1);
        // Forward dynamics divides by the LDLᵀ pivots.
        assert!(s.functions[4].ops.div >= 1);
        assert!(s.functions.iter().all(|f| f.lines > 0));
        assert_eq!(s.to_string().lines().count(), s.functions.len() + 1);
    }
}
