//! The checks a robot passes before anything is generated or evaluated for it, shared by
//! every front end (Builder, CLI `generate`/`stats`/`eval`/`joints`, `robot!`, derive), so
//! that all of them accept and refuse exactly the same robots.
//!
//! 1. [`Robot::validate`]: every rule of `dynamics_model::validate` (unit screw axes,
//!    rigid home frames, physically consistent inertias, …).
//! 2. At least one movable joint.
//! 3. A mass matrix that is not singular for every q. `M(q)` is analytic in q, so if it is
//!    singular at [`SAMPLES`] seeded random configurations it is singular everywhere (a joint
//!    that moves no mass or inertia, or two joints that move the same bodies the same way);
//!    forward dynamics would then divide by zero. The symbolic mass matrix is evaluated at
//!    those configurations and factorised `M = L D Lᵀ` in joint order (with mimic joints, the
//!    `M = Jᵀ M J` of the independent coordinates); the first joint j
//!    whose pivot `D_j ≤ PIVOT_TOL · M_jj` (its column depends on the columns before it), or
//!    whose `M_jj ≤ PIVOT_TOL · max_k M_kk`, at every sample, is named in the error.

use crate::error::Error;
use crate::expand::{self, frames, Q};
use crate::expr::ExprGraph;
use dynamics_model::{Invalid, JointKind, ModelError, Robot, Subject};

/// The number of random configurations the mass matrix is tried at.
pub const SAMPLES: usize = 3;
/// Relative size below which a pivot of `M = L D Lᵀ` counts as zero.
pub const PIVOT_TOL: f64 = 1e-12;

/// Checks `robot` (see the [module docs](self)); errors name the file, the joint, the field
/// and the fix.
pub fn check_robot(robot: &Robot) -> Result<(), Error> {
    robot.validate().map_err(|e| e.in_file(&robot.source))?;
    if robot.dof() == 0 {
        return Err(Error::NoJoints {
            robot: robot.name.clone(),
        });
    }
    let ov = robot.nv() - robot.n_coordinates();
    if let Some(k) = singular_joint(robot) {
        let Some(j) = k.checked_sub(ov) else {
            let e = Invalid::new(
                Subject::Link {
                    index: None,
                    name: robot.base.name.clone(),
                },
                "inertia",
                "the floating base's block of the mass matrix (the composite inertia of the whole robot) is singular, so forward dynamics would divide by zero",
                "give the base link, or the links on it, mass and rotational inertia (URDF <inertial>, TOML `[base]` mass and inertia), or fix the base",
            );
            return Err(ModelError::invalid(e).in_file(&robot.source).into());
        };
        // Coordinate j: its joint and the joints that mimic it, and every link below them.
        let coupling = expand::mimic::Coupling::new(robot);
        let joints: Vec<usize> = coupling.members(ov + j).map(|i| i - ov).collect();
        let j = joints
            .iter()
            .copied()
            .find(|&i| robot.joints[i].is_independent())
            .unwrap_or(j);
        let followers: Vec<usize> = joints.iter().copied().filter(|&i| i != j).collect();
        let moved: Vec<String> = (0..robot.dof())
            .filter(|&l| joints.iter().any(|i| robot.path_to(l).contains(i)))
            .map(|l| format!("`{}`", robot.links[l].name))
            .collect();
        let e = Invalid::new(
            Subject::Joint {
                index: Some(j),
                name: robot.joints[j].name.clone(),
            },
            "inertia",
            format!(
                "the mass matrix is singular for every q: the joint{} moves no mass or inertia that the joints before it do not already move (the links it moves: {}), so forward dynamics would divide by zero",
                match Some(&followers).filter(|f| !f.is_empty()) {
                    Some(f) => format!(
                        ", with the joints that mimic it ({}),",
                        f.iter()
                            .map(|&i| format!("`{}`", robot.joints[i].name))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                    None => String::new(),
                },
                moved.join(", ")
            ),
            "give the links it moves their mass and inertia (URDF <inertial>, TOML `mass` and `inertia`), or lock the joint (`--lock JOINT=VALUE`, Builder `.lock(..)`, derive `lock(..)`)",
        );
        return Err(ModelError::invalid(e).in_file(&robot.source).into());
    }
    Ok(())
}

/// The first dof (base dofs first, then the joint coordinates) whose mass-matrix pivot
/// vanishes at every sample, if any. With mimic joints, `M` is the coordinates' `Jᵀ M J`
/// ([`expand::mimic`]).
fn singular_joint(robot: &Robot) -> Option<usize> {
    let k = robot.n_coordinates();
    let oq = robot.nq() - k;
    let mut frames = frames::joint_frames(robot);
    let coupling = expand::mimic::Coupling::new(robot);
    expand::mimic::offsets(&mut frames, robot);
    let mut g = ExprGraph::new();
    let x: Vec<_> = (0..k).map(|i| g.input(expand::input(Q, oq + i))).collect();
    let q = coupling.positions(&mut g, &x);
    let motions = expand::joint_motions(&mut g, &frames, &q);
    let m = expand::crba::crba(&mut g, &motions, frames.base.as_ref());
    let m = coupling.matrix(&mut g, &m);
    let nv = robot.nv();
    let mut first_singular = vec![None; SAMPLES];
    let mut rng = crate::expr::zeros::SplitMix(0x9e37_79b9_7f4a_7c15);
    for found in &mut first_singular {
        let values: Vec<f64> = robot
            .joints
            .iter()
            .filter(|j| j.is_independent())
            .map(|j| match j.kind {
                JointKind::Revolute => rng.uniform(-std::f64::consts::PI, std::f64::consts::PI),
                JointKind::Prismatic => rng.uniform(-0.5, 0.5),
            })
            .collect();
        // M does not depend on the base's pose: its q entries are never read.
        let mv = g.eval(&m, &|x| values[x.index as usize - oq]);
        *found = first_zero_pivot(&mv, nv);
    }
    // Singular everywhere: the same joint at every sample.
    let j = first_singular[0]?;
    first_singular.iter().all(|f| *f == Some(j)).then_some(j)
}

/// The first j with a vanishing pivot of `M = L D Lᵀ` (row-major n×n), if any.
fn first_zero_pivot(m: &[f64], n: usize) -> Option<usize> {
    let scale = (0..n).map(|k| m[k * n + k].abs()).fold(0.0, f64::max);
    let mut l = vec![0.0; n * n];
    let mut d = vec![0.0; n];
    for j in 0..n {
        let mjj = m[j * n + j];
        let mut dj = mjj;
        for k in 0..j {
            dj -= l[j * n + k] * l[j * n + k] * d[k];
        }
        if !(dj > PIVOT_TOL * mjj && mjj > PIVOT_TOL * scale) {
            return Some(j);
        }
        d[j] = dj;
        for i in j + 1..n {
            let mut y = m[i * n + j];
            for k in 0..j {
                y -= l[i * n + k] * l[j * n + k] * d[k];
            }
            l[i * n + j] = y / dj;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::first_zero_pivot;

    /// A leader whose link and whose follower's link carry no mass: its coordinate moves
    /// nothing, and the error names the leader and both links.
    #[test]
    fn a_massless_coupled_pair_is_named() {
        use dynamics_model::lie::rp_to_trans;
        use dynamics_model::{Mimic, Robot};
        use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};
        let at = |x: f64| rp_to_trans(&Matrix3::identity(), &Vector3::new(x, 0.0, 0.0));
        let heavy = Matrix6::from_diagonal(&Vector6::new(0.1, 0.1, 0.1, 1.0, 1.0, 1.0));
        let z = Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        let mut robot = Robot::from_mr_lists(
            &[at(0.5), at(0.5), at(0.5), Matrix4::identity()],
            &[heavy, Matrix6::zeros(), Matrix6::zeros()],
            &[z, z, z],
            Vector3::new(0.0, 0.0, -9.81),
        )
        .unwrap();
        robot.links[2].parent = Some(0);
        robot.joints[2].mimic = Some(Mimic {
            leader: 1,
            multiplier: -1.0,
            offset: 0.0,
        });
        let e = super::check_robot(&robot).unwrap_err().to_string();
        assert!(
            e.contains("joint `joint2`")
                && e.contains("mimic it (`joint3`)")
                && e.contains("`link2`, `link3`"),
            "{e}"
        );
    }

    #[test]
    fn pivots() {
        assert_eq!(first_zero_pivot(&[2.0, 1.0, 1.0, 2.0], 2), None);
        assert_eq!(first_zero_pivot(&[2.0, 0.0, 0.0, 0.0], 2), Some(1));
        // Two equal columns: the second adds nothing.
        assert_eq!(first_zero_pivot(&[1.0, 1.0, 1.0, 1.0], 2), Some(1));
        assert_eq!(first_zero_pivot(&[0.0, 0.0, 0.0, 1.0], 2), Some(0));
    }
}
