//! Kinematics of frames: the pose of a frame rigidly attached to a link (the end effector, a
//! foot, a hand) and its space and body Jacobians (Modern Robotics §4.1, §5.1), on a tree and
//! a floating base.
//!
//! Poses are composed from the base outwards in the joint frames of [`super::frames`]: with
//! `C_i = (R_i, p_i)` the constant part of `T_{J_i,J_λ(i)}(θ) = Rot_z(−θ_i) C_i` (revolute) or
//! `Trans_z(−θ_i) C_i` (prismatic),
//!
//! ```text
//! T_{b,J_i} = T_{b,J_λ(i)} · C_i⁻¹ · Rot_z(θ_i)        (or · Trans_z(θ_i)),   T_{b,J_0} = 1
//! T_{b,f}   = T_{b,J_k} · K_f,    K_f = T_{J_k,f}  (constant: the frame on link k)
//! T_{0,f}   = T_{0b} · T_{b,f}
//! ```
//!
//! with `T_{0b}` the base pose (`q[0..3]` and the normalised quaternion `q[3..7]`; the identity
//! on a fixed base). A joint's axis is the z axis of its joint frame, so with `z_j` and `p_j`
//! its direction and origin in the base frame, the Jacobians' columns for the joints on the
//! path to the frame are
//!
//! ```text
//! space (in {0}):  J_s,j = (z⁰_j, p⁰_j × z⁰_j)   revolute;   (0, z⁰_j)   prismatic
//! body  (in {f}):  J_b,j = (z_j, p_j × z_j)      revolute;   (0, z_j)    prismatic
//! ```
//!
//! with `z⁰`, `p⁰` in {0} (`z⁰ = R_b z`, `p⁰ = p_b + R_b p` from the base-frame pose; any point
//! of the axis serves as `p`, and the space Jacobian takes a cheaper one than the origin where
//! there is one, the foot of the common normal: [`joint_poses`]), and for
//! the body Jacobian `z`, `p` the axis and origin in the frame {f} itself, i.e. the last
//! column and the translation of `X_j = T_{f,J_j}`, computed from the frame inwards:
//! `X = K_f⁻¹`, then `X ← X · Rot_z(−θ_j) · C_j` past each joint of the path. So `J_b,j`
//! depends only on the joints between joint j and the frame (as the book's `JacobianBody`),
//! never on products `R_fᵀ R_j` that cancel only numerically. Columns of joints off the path
//! are zero. A floating base adds six columns for its body twist
//! `ν_b = (ω_b, v_b)`: `[Ad_{T_{bf}⁻¹}]` in the body Jacobian and `[Ad_{T_{0b}}]` in the space
//! Jacobian, so that `V_b = J_b ν` and `V_s = J_s ν` for the whole velocity `ν`.
//!
//! Their rates are the cheaper of the directional derivative of the Jacobian's graph and the
//! twists the columns move with:
//!
//! ```text
//! J̇_s,i = [ad_{V_i}] J_s,i,   V_i = V_base + Σ_{j before i} J_s,j θ̇_j   (the body joint i sits on)
//! J̇_b,i = [ad_{W_i}] J_b,i,   W_i = −Σ_{j after i} J_b,j θ̇_j            (joint i's frame seen from {f})
//! ```

use super::base::{base_rotation, NQ_BASE, NV_BASE};
use super::frames::{joint_frames, BodyInertia, JointFrames};
use super::spatial::{VectorOps, V3};
use super::{input, joint_motions, mimic, Q, QD};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::lie::{rotation, trans_inv, translation};
use dynamics_model::{Frame, JointKind, Robot};
use nalgebra::Matrix4;

/// A symbolic rotation matrix, by rows.
pub type M3 = [[ExprId; 3]; 3];

/// The pose and Jacobians of one frame.
#[derive(Clone, Debug)]
pub struct FrameKinematics {
    /// `T_{0f}(q)`: the rotation by rows (9 entries), then the translation (3).
    pub pose: Vec<ExprId>,
    /// `J_s(q)`, 6×nv row-major (rows ω then v, in {0}); with mimic joints, columns for the
    /// independent coordinates (`J_s · J`).
    pub jacobian_space: Vec<ExprId>,
    /// `J_b(q)`, 6×nv row-major (rows ω then v, in the frame).
    pub jacobian_body: Vec<ExprId>,
}

/// The kinematics of the end effector and of the robot's named frames, on their own graph.
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// The expression graph (its inputs are the `q` entries, group [`Q`]).
    pub graph: ExprGraph,
    /// The end-effector frame {n+1}.
    pub end_effector: FrameKinematics,
    /// `J̇_s(q, ν)` of the end effector: the directional derivative of its `jacobian_space`
    /// along the configuration rate ([`super::base::configuration_rate`]; inputs `q` and `ν`)
    /// or `[ad_{V_i}] J_s,i` column by column (module docs), the cheaper.
    pub jacobian_space_dot: Vec<ExprId>,
    /// `J̇_b(q, ν)` of the end effector, likewise (`[ad_{W_i}] J_b,i`).
    pub jacobian_body_dot: Vec<ExprId>,
    /// [`Robot::frames`], in order.
    pub frames: Vec<FrameKinematics>,
    /// `P(q) = −gᵀ Σ_i (m_i p_i + R_i h_i)`: the potential energy, every link's mass `m_i` and
    /// first moment `h_i = m_i c_i` (in its joint frame, before any regrouping, so that `P`
    /// itself and not only `∂P/∂q` is the robot's) moved to {0} by the joint frame's pose
    /// `(R_i, p_i)`; a floating base's own body included.
    pub potential_energy: ExprId,
}

/// A pose `(R, p)`, and a point of its z axis (a joint's axis in its joint frame).
#[derive(Clone, Copy)]
struct Pose {
    r: M3,
    p: V3,
    /// A point of the z axis for a Jacobian's `v = point × z`: `p`, or where one costs fewer
    /// operations, the foot of the perpendicular from the parent joint frame's origin or that
    /// origin itself where it lies on the axis ([`joint_poses`]).
    on_z: V3,
}

impl Pose {
    fn new(r: M3, p: V3) -> Self {
        Pose { r, p, on_z: p }
    }
}

fn identity(g: &mut ExprGraph) -> Pose {
    let (o, l) = (g.zero(), g.one());
    Pose::new([[l, o, o], [o, l, o], [o, o, l]], [o, o, o])
}

/// `v = w + d u` for a unit vector `u`: `(w, d)` with `w ⟂ u`. Entries of `w` and a `d` below
/// 64 ulp of `|v|` are rounding residue (`v`'s own part along `u` or across it, not a length of
/// the robot) and are zero.
fn split_along(v: [f64; 3], u: [f64; 3]) -> ([f64; 3], f64) {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let residue = 64.0 * f64::EPSILON * norm;
    let d = (0..3).map(|k| v[k] * u[k]).sum::<f64>();
    let d = if d.abs() <= residue { 0.0 } else { d };
    let w = std::array::from_fn(|k| {
        let x = v[k] - d * u[k];
        if x.abs() <= residue {
            0.0
        } else {
            x
        }
    });
    (w, d)
}

/// The nonzero entries of `v`.
fn nonzero(v: &[f64; 3]) -> usize {
    v.iter().filter(|x| **x != 0.0).count()
}

fn column(r: &M3, j: usize) -> V3 {
    [r[0][j], r[1][j], r[2][j]]
}

/// `A c` for a symbolic `A` and a constant `c`.
fn mul_const(g: &mut ExprGraph, a: &M3, c: &[[f64; 3]; 3]) -> M3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let terms: Vec<ExprId> = (0..3).map(|k| g.cmul(c[k][j], a[i][k])).collect();
            g.sum(&terms)
        })
    })
}

/// `A v` for a constant `v`.
fn apply_const(g: &mut ExprGraph, a: &M3, v: [f64; 3]) -> V3 {
    std::array::from_fn(|i| {
        let terms: Vec<ExprId> = (0..3).map(|k| g.cmul(v[k], a[i][k])).collect();
        g.sum(&terms)
    })
}

/// `A v`.
fn apply(g: &mut ExprGraph, a: &M3, v: V3) -> V3 {
    std::array::from_fn(|i| {
        let terms: Vec<ExprId> = (0..3).map(|k| g.mul(a[i][k], v[k])).collect();
        g.sum(&terms)
    })
}

/// `A B`.
fn mul(g: &mut ExprGraph, a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let terms: Vec<ExprId> = (0..3).map(|k| g.mul(a[i][k], b[k][j])).collect();
            g.sum(&terms)
        })
    })
}

/// `A · Rot_z(θ)` (columns `(c a₀ + s a₁, −s a₀ + c a₁, a₂)`), or `A · Rot_z(−θ)` when
/// `inverse` (columns `(c a₀ − s a₁, s a₀ + c a₁, a₂)`), from `s = sin θ`, `c = cos θ`.
fn times_rot_z(g: &mut ExprGraph, a: &M3, s: ExprId, c: ExprId, inverse: bool) -> M3 {
    let (a0, a1) = (column(a, 0), column(a, 1));
    let ca0 = g.scale3(c, a0);
    let sa1 = g.scale3(s, a1);
    let ca1 = g.scale3(c, a1);
    let sa0 = g.scale3(s, a0);
    let (col0, col1) = if inverse {
        (g.sub3(ca0, sa1), g.add3(sa0, ca1))
    } else {
        (g.add3(ca0, sa1), g.sub3(ca1, sa0))
    };
    std::array::from_fn(|i| [col0[i], col1[i], a[i][2]])
}

fn rows_of(m: &Matrix4<f64>) -> ([[f64; 3]; 3], [f64; 3]) {
    let r = rotation(m);
    let p = translation(m);
    (
        std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)])),
        [p[0], p[1], p[2]],
    )
}

/// `T_{b,J_i}(θ)` for every joint, from the base outwards (see the module docs).
///
/// A run of parallel revolute joints (`C_i`'s rotation maps z to ±z exactly: the UR arms'
/// shoulder, elbow and first wrist joint, a leg's hip pitch, knee and ankle pitch) turns about
/// one axis, so that `Rot_z(θ_λ) C_i⁻¹ = C_i⁻¹ Rot_z(±θ_λ)` and the run's rotations are
/// `R_{b,J_i} = A_i Rot_z(φ_i)` with `A_i` the rotation where the run starts (times the
/// constant `C⁻¹`s) and `φ_i = ±θ_λ … + θ_i` the sum of the run's angles: each rotation one
/// step from `A_i` (the sines and cosines of the sums come from the same vectorised kernel),
/// not a chain of products one joint after another: a shorter path, and fewer operations where
/// `A_i` is sparse (a run that starts from an axis-aligned frame; the UR5's pose 92 → 62).
fn joint_poses(g: &mut ExprGraph, frames: &JointFrames, q: &[ExprId], runs: bool) -> Vec<Pose> {
    let motions = joint_motions(g, frames, q);
    let base = identity(g);
    let mut poses: Vec<Pose> = Vec::with_capacity(motions.len());
    // `(A_i, φ_i)` with `R_{b,J_i} = A_i Rot_z(φ_i)`, for the joints a run can go on from.
    let mut turns: Vec<Option<(M3, ExprId)>> = Vec::with_capacity(motions.len());
    for m in &motions {
        let f = m.frame;
        let parent = f.parent.map_or(base, |p| poses[p]);
        // C⁻¹ = (Rᵀ, −Rᵀ p).
        let rt: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| f.r[j][i]));
        let minus_rt_p = f.origin_in_parent();
        let a = mul_const(g, &parent.r, &rt);
        // The origin `p = p_λ + R_λ (−Rᵀ p_c)`, or, with `−Rᵀ p_c = w + d u` (`u = Rᵀ z` the
        // joint's axis in {J_λ}, `w ⟂ u`), `p = f + d z` from the foot `f = p_λ + R_λ w` of the
        // perpendicular from `p_λ` to the axis and the axis `z = R_λ u`, which the rotation
        // computes anyway, where that takes fewer products: the modified-DH step `(a, −d sin α,
        // d cos α)` of a twisted joint takes `a x_λ + d z` instead of three columns (rand7: 3
        // products fewer a joint). The foot then serves the Jacobian's `v = f × z`; so does `p_λ`
        // where it lies on the axis (`w = 0`) and has more constant entries than `p` (the Panda's
        // third joint: `(0, 0, 0.333)`, 4 products fewer).
        let axis = [rt[0][2], rt[1][2], rt[2][2]];
        let (w, d) = split_along(minus_rt_p, axis);
        let (mut p, on_z) = if nonzero(&w) + usize::from(d != 0.0) < nonzero(&minus_rt_p) {
            let shift = apply_const(g, &parent.r, w);
            let foot = g.add3(parent.p, shift);
            let along: V3 = std::array::from_fn(|k| g.cmul(d, a[k][2]));
            (g.add3(foot, along), foot)
        } else {
            let shift = apply_const(g, &parent.r, minus_rt_p);
            let p = g.add3(parent.p, shift);
            let constants = |x: &V3| x.iter().filter(|e| g.as_const(**e).is_some()).count();
            let on_axis = nonzero(&w) == 0 && constants(&parent.p) > constants(&p);
            (p, if on_axis { parent.p } else { p })
        };
        // The run this joint goes on with: A_λ C_i⁻¹ and ±φ_λ.
        let run = match (f.parent.and_then(|k| turns[k]), z_sign(&f.r)) {
            (Some((a, phi)), Some(sign)) if runs => {
                let phi = if sign < 0.0 { g.neg(phi) } else { phi };
                Some((mul_const(g, &a, &rt), phi))
            }
            _ => None,
        };
        let (r, turn) = match f.kind {
            JointKind::Revolute => match run {
                Some((a, phi)) => {
                    let phi = g.add(phi, m.q);
                    let (s, c) = (g.sin(phi), g.cos(phi));
                    (times_rot_z(g, &a, s, c, false), Some((a, phi)))
                }
                None => (times_rot_z(g, &a, m.sin, m.cos, false), Some((a, m.q))),
            },
            JointKind::Prismatic => {
                let d = g.scale3(m.q, column(&a, 2));
                p = g.add3(p, d);
                (a, run)
            }
        };
        poses.push(Pose { r, p, on_z });
        turns.push(turn);
    }
    poses
}

/// The identity rotation.
const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `a b` of two constant rotations.
fn times(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// `±1` when the rotation `r` maps z to ±z exactly (its third row and column are `(0, 0, ±1)`),
/// so that `Rot_z(θ) rᵀ = rᵀ Rot_z(±θ)`.
fn z_sign(r: &[[f64; 3]; 3]) -> Option<f64> {
    let axis = r[0][2] == 0.0 && r[1][2] == 0.0 && r[2][0] == 0.0 && r[2][1] == 0.0;
    (axis && r[2][2].abs() == 1.0).then_some(r[2][2])
}

/// Expands the pose and Jacobians of the end effector and of every named frame of `robot`,
/// runs of parallel joints taking the sines and cosines of their sums ([`joint_poses`]).
pub fn expand_kinematics(robot: &Robot) -> Kinematics {
    expand_kinematics_with(robot, true)
}

/// [`expand_kinematics`], with `runs: false` every rotation one joint after the other, so that
/// the sines and cosines taken are the joint angles' own (`q_i + offset`): the form of the
/// `*_from_sin_cos` variants, which then need no sine of their own (a run's sums would be
/// computed from `q` in them).
pub fn expand_kinematics_with(robot: &Robot, runs: bool) -> Kinematics {
    let mut frames = joint_frames(robot);
    // Mimic joints: the inputs are the independent coordinates (see [`super::mimic`]).
    mimic::offsets(&mut frames, robot);
    let coupling = mimic::Coupling::new(robot);
    let n = robot.dof();
    let floating = robot.base.floating;
    let (oq, ov) = if floating { (NQ_BASE, NV_BASE) } else { (0, 0) };
    let nv = n + ov;
    let mut g = ExprGraph::new();
    let x: Vec<ExprId> = (0..robot.n_coordinates())
        .map(|i| g.input(input(Q, oq + i)))
        .collect();
    let q = coupling.positions(&mut g, &x);
    let poses = joint_poses(&mut g, &frames, &q, runs);
    // The base pose T_{0b}: from q on a floating base.
    let base = floating.then(|| {
        let r = base_rotation(&mut g);
        let p: V3 = std::array::from_fn(|k| g.input(input(Q, k)));
        Pose::new(r, p)
    });
    // The physical joints' columns onto the coordinates: each row times J.
    let couple = |g: &mut ExprGraph, j: &[ExprId]| -> Vec<ExprId> {
        j.chunks(nv)
            .flat_map(|row| coupling.forces(g, row))
            .collect()
    };
    let coupled = |g: &mut ExprGraph, k: &FrameKinematics| FrameKinematics {
        pose: k.pose.clone(),
        jacobian_space: couple(g, &k.jacobian_space),
        jacobian_body: couple(g, &k.jacobian_body),
    };
    let physical = frame_kinematics(
        &mut g,
        robot,
        &frames,
        &q,
        &poses,
        base,
        &robot.end_effector,
        nv,
        runs,
    );
    // J̇ by the twists the columns move with, on the physical joints' rates.
    let nu: Vec<ExprId> = (0..ov + robot.n_coordinates())
        .map(|i| g.input(input(QD, i)))
        .collect();
    let rates = coupling.rates(&mut g, &nu);
    let path = robot.frame_path(&robot.end_effector);
    let space_dot = space_jacobian_dot(&mut g, &physical.jacobian_space, &path, ov, &rates);
    let body_dot = body_jacobian_dot(&mut g, &physical.jacobian_body, &path, ov, &rates);
    let (space_dot, body_dot) = (couple(&mut g, &space_dot), couple(&mut g, &body_dot));
    let end_effector = coupled(&mut g, &physical);
    let named = robot
        .frames
        .iter()
        .map(|f| {
            let k = frame_kinematics(&mut g, robot, &frames, &q, &poses, base, f, nv, runs);
            coupled(&mut g, &k)
        })
        .collect();
    let potential_energy = potential_energy(&mut g, robot, &frames, &poses, base);
    // J̇ as the directional derivative of J's graph, or by the twists: the cheaper.
    let rate = super::base::configuration_rate(&mut g, floating, robot.n_coordinates());
    let by_jvp = g.jvp(&end_effector.jacobian_space, &rate);
    let jacobian_space_dot = super::cheaper(&g, by_jvp, space_dot);
    let by_jvp = g.jvp(&end_effector.jacobian_body, &rate);
    let jacobian_body_dot = super::cheaper(&g, by_jvp, body_dot);
    Kinematics {
        graph: g,
        end_effector,
        jacobian_space_dot,
        jacobian_body_dot,
        frames: named,
        potential_energy,
    }
}

/// Column `c` of the 6×`nv` row-major `j` as `(ω, v)`.
fn twist_column(j: &[ExprId], nv: usize, c: usize) -> (V3, V3) {
    (
        std::array::from_fn(|k| j[k * nv + c]),
        std::array::from_fn(|k| j[(3 + k) * nv + c]),
    )
}

/// Column `c` of the 6×`nv` row-major `m` set to `(ω, v)`.
fn set_column(m: &mut [ExprId], nv: usize, c: usize, (w, v): (V3, V3)) {
    for k in 0..3 {
        m[k * nv + c] = w[k];
        m[(3 + k) * nv + c] = v[k];
    }
}

/// `[ad_W] X = (ω × ω_x, v × ω_x + ω × v_x)` for `W = (ω, v)`.
fn ad(g: &mut ExprGraph, w: (V3, V3), x: (V3, V3)) -> (V3, V3) {
    let ang = g.cross(w.0, x.0);
    let a = g.cross(w.1, x.0);
    let b = g.cross(w.0, x.1);
    (ang, g.add3(a, b))
}

/// `J = Σ_c J_c ν_c` over the columns `cols` of `j`, added to `acc`.
fn add_twists(
    g: &mut ExprGraph,
    j: &[ExprId],
    nv: usize,
    cols: &[usize],
    rates: &[ExprId],
    acc: (V3, V3),
) -> (V3, V3) {
    cols.iter().fold(acc, |(w, v), &c| {
        let (jw, jv) = twist_column(j, nv, c);
        let (sw, sv) = (g.scale3(rates[c], jw), g.scale3(rates[c], jv));
        (g.add3(w, sw), g.add3(v, sv))
    })
}

/// `J̇_s` of a space Jacobian `j` (6×nv row-major, the physical joints' columns) from the
/// twists its columns move with: a column is `Ad_{T_{0,J_i}} A_i`, so `J̇_s,i = [ad_{V_i}]
/// J_s,i` with `V_i` the space twist of the body joint i sits on: the base's
/// (`Σ_{c<6} J_s,c ν_c` on a floating base, whose six columns move with it too) plus
/// `J_s,j θ̇_j` of the joints before i on the path (`path`, base outwards). `rates`: ν on the
/// physical joints.
fn space_jacobian_dot(
    g: &mut ExprGraph,
    j: &[ExprId],
    path: &[usize],
    ov: usize,
    rates: &[ExprId],
) -> Vec<ExprId> {
    let nv = j.len() / 6;
    let zero = g.zero();
    let mut out = vec![zero; 6 * nv];
    let base: Vec<usize> = (0..ov).collect();
    let still = (g.zero3(), g.zero3());
    let mut twist = add_twists(g, j, nv, &base, rates, still);
    for &c in &base {
        let rate = ad(g, twist, twist_column(j, nv, c));
        set_column(&mut out, nv, c, rate);
    }
    for &i in path {
        let rate = ad(g, twist, twist_column(j, nv, ov + i));
        set_column(&mut out, nv, ov + i, rate);
        twist = add_twists(g, j, nv, &[ov + i], rates, twist);
    }
    out
}

/// `J̇_b` of a body Jacobian `j` (as [`space_jacobian_dot`]): a column is `Ad_{T_{f,J_i}}
/// A_i`, so `J̇_b,i = [ad_{W_i}] J_b,i` with `W_i = −Σ_{j after i} J_b,j θ̇_j`, the twist of
/// joint i's frame relative to the frame {f}, in {f}; a floating base's six columns move with
/// all the joints of the path.
fn body_jacobian_dot(
    g: &mut ExprGraph,
    j: &[ExprId],
    path: &[usize],
    ov: usize,
    rates: &[ExprId],
) -> Vec<ExprId> {
    let nv = j.len() / 6;
    let zero = g.zero();
    let mut out = vec![zero; 6 * nv];
    let mut after = (g.zero3(), g.zero3());
    for &i in path.iter().rev() {
        let rate = ad(g, twist_column(j, nv, ov + i), after);
        set_column(&mut out, nv, ov + i, rate);
        after = add_twists(g, j, nv, &[ov + i], rates, after);
    }
    for c in 0..ov {
        let rate = ad(g, twist_column(j, nv, c), after);
        set_column(&mut out, nv, c, rate);
    }
    out
}

/// `P(q)` of `robot` on the caller's graph, from the physical joints' positions `q` (after
/// the mimic coupling) and `frames` (its joint frames with the mimic offsets), a floating
/// base's pose from the q inputs: the same expression as [`Kinematics::potential_energy`].
pub(crate) fn potential_energy_of(
    g: &mut ExprGraph,
    robot: &Robot,
    frames: &JointFrames,
    q: &[ExprId],
) -> ExprId {
    let poses = joint_poses(g, frames, q, true);
    let base = robot.base.floating.then(|| {
        let r = base_rotation(g);
        let p: V3 = std::array::from_fn(|k| g.input(input(Q, k)));
        Pose::new(r, p)
    });
    potential_energy(g, robot, frames, &poses, base)
}

/// `P(q)`: see [`Kinematics::potential_energy`]. The first moments are summed in the base
/// frame, `F = Σ_i (m_i p_i + R_i h_i)`, then moved to {0} once: `F⁰ = m p_b + R_b (F + h_b)`
/// with `m` the total mass (a fixed base: `F⁰ = F`).
fn potential_energy(
    g: &mut ExprGraph,
    robot: &Robot,
    frames: &JointFrames,
    poses: &[Pose],
    base: Option<Pose>,
) -> ExprId {
    let homes = robot.home_poses();
    let mut total_mass = 0.0;
    let mut payload_mass = None;
    let mut terms: [Vec<ExprId>; 3] = Default::default();
    for (i, link) in robot.links.iter().enumerate() {
        // Link i's inertia in its joint frame {J_i}: T_{i,J_i} = M_{0i}⁻¹ T_{0,J_i}.
        let t_link_joint = trans_inv(&homes[i + 1]) * frames.homes[i];
        let b = BodyInertia::from_spatial(&link.inertia.transform_by(&t_link_joint));
        total_mass += b.m;
        let rh = apply_const(g, &poses[i].r, b.h);
        for k in 0..3 {
            terms[k].push(g.cmul(b.m, poses[i].p[k]));
            terms[k].push(rh[k]);
        }
        // A run-time payload ([`super::parameters`]): its mass and first moment in {J_i}.
        if let Some(pose) = &frames.joints[i].payload {
            let payload = super::parameters::payload_inertia(g, pose);
            payload_mass = Some(payload.m);
            let rh = apply(g, &poses[i].r, payload.h);
            for k in 0..3 {
                terms[k].push(g.mul(payload.m, poses[i].p[k]));
                terms[k].push(rh[k]);
            }
        }
    }
    let mut moment: V3 = std::array::from_fn(|k| g.sum(&terms[k]));
    if let Some(b) = base {
        let own = BodyInertia::from_spatial(&robot.base.inertia);
        total_mass += own.m;
        let h = g.const3(own.h);
        let f = g.add3(moment, h);
        let rf = apply(g, &b.r, f);
        let total_mass = {
            let m = g.constant(total_mass);
            match payload_mass {
                Some(p) => g.add(m, p),
                None => m,
            }
        };
        let mp: V3 = std::array::from_fn(|k| g.mul(total_mass, b.p[k]));
        moment = g.add3(mp, rf);
    }
    let gravity = super::parameters::gravity(g, frames);
    let nonzero: Vec<usize> = (0..3).filter(|&k| !g.is_zero(gravity[k])).collect();
    let terms: Vec<ExprId> = nonzero
        .into_iter()
        .map(|k| {
            let minus_g = g.neg(gravity[k]);
            g.mul(minus_g, moment[k])
        })
        .collect();
    g.sum(&terms)
}

fn frame_kinematics(
    g: &mut ExprGraph,
    robot: &Robot,
    frames: &JointFrames,
    q: &[ExprId],
    poses: &[Pose],
    base: Option<Pose>,
    frame: &Frame,
    nv: usize,
    runs: bool,
) -> FrameKinematics {
    let ov = nv - robot.dof();
    // K_f = T_{J_k,f}: the frame in its link's joint frame (in {0} for the base).
    let home = robot.frame_home(frame);
    let (link_pose, k) = match frame.parent {
        Some(k) => (poses[k], trans_inv(&frames.homes[k]) * home),
        None => (identity(g), home),
    };
    let (kr, kp) = rows_of(&k);
    let r_f = mul_const(g, &link_pose.r, &kr);
    let shift = apply_const(g, &link_pose.r, kp);
    let p_f = g.add3(link_pose.p, shift);
    let zero = g.zero();
    let mut j_b = vec![zero; 6 * nv];
    let mut j_s = vec![zero; 6 * nv];
    // Body Jacobian, from the frame towards the base: X = T_{f,J_j} starts at K_f⁻¹ and
    // moves past each joint, X ← X · Rot_z(−θ_j) · C_j; column j = [Ad_X] A_j.
    let k_inv = trans_inv(&k);
    let (xr, xp) = rows_of(&k_inv);
    let mut x = Pose::new(
        std::array::from_fn(|i| std::array::from_fn(|j| g.constant(xr[i][j]))),
        g.const3(xp),
    );
    let motions = joint_motions(g, frames, q);
    // A run of parallel revolute joints (as in `joint_poses`): `X_r = B Rot_z(−ψ) D` with `D`
    // the product of the run's constant rotations, each mapping z to ±z, so that `D
    // Rot_z(−θ) = Rot_z(∓θ) D` and `ψ` sums the run's angles; `(B, ψ, D)` while in a run.
    let mut run: Option<(M3, ExprId, [[f64; 3]; 3])> = None;
    for i in robot.frame_path(frame).into_iter().rev() {
        let m = &motions[i];
        let z = column(&x.r, 2);
        let (w, v) = match m.frame.kind {
            JointKind::Revolute => (z, g.cross(x.p, z)),
            JointKind::Prismatic => ([zero; 3], z),
        };
        set_column(&mut j_b, nv, ov + i, (w, v));
        // X · Rot_z(−θ): columns (c a₀ − s a₁, s a₀ + c a₁, a₂); X · Trans_z(−θ): p − θ a₂.
        match (m.frame.kind, run) {
            (JointKind::Revolute, Some((b, psi, d))) => {
                let theta = if d[2][2] < 0.0 { g.neg(m.q) } else { m.q };
                let psi = g.add(psi, theta);
                let (s, c) = (g.sin(psi), g.cos(psi));
                let turned = times_rot_z(g, &b, s, c, true);
                x.r = mul_const(g, &turned, &d);
                run = Some((b, psi, d));
            }
            (JointKind::Revolute, None) => {
                let b = x.r;
                x.r = times_rot_z(g, &x.r, m.sin, m.cos, true);
                run = Some((b, m.q, IDENTITY));
            }
            // A translation keeps the rotation, and the run goes on (as in `joint_poses`).
            (JointKind::Prismatic, _) => {
                let d = g.scale3(m.q, z);
                x.p = g.sub3(x.p, d);
            }
        }
        // X · C_j.
        let shift = apply_const(g, &x.r, m.frame.p);
        x.p = g.add3(x.p, shift);
        x.r = mul_const(g, &x.r, &m.frame.r);
        run = match (run, z_sign(&m.frame.r)) {
            (Some((b, psi, d)), Some(_)) if runs => Some((b, psi, times(&d, &m.frame.r))),
            _ => None,
        };
    }
    if ov > 0 {
        // X = T_{f,b}: the base columns are [Ad_X].
        for c in 0..3 {
            let w = column(&x.r, c);
            let v = g.cross(x.p, w);
            set_column(&mut j_b, nv, c, (w, v));
            set_column(&mut j_b, nv, 3 + c, ([zero; 3], w));
        }
    }
    let world = match base {
        None => Pose::new(r_f, p_f),
        Some(b) => {
            let r = mul(g, &b.r, &r_f);
            let rp = apply(g, &b.r, p_f);
            Pose::new(r, g.add3(b.p, rp))
        }
    };
    // Space Jacobian: joint axes in {0}, then a floating base's [Ad_{T_0b}].
    for i in robot.frame_path(frame) {
        let (z, p) = match base {
            None => (column(&poses[i].r, 2), poses[i].on_z),
            Some(b) => {
                let z = apply(g, &b.r, column(&poses[i].r, 2));
                let rp = apply(g, &b.r, poses[i].on_z);
                (z, g.add3(b.p, rp))
            }
        };
        let (w, v) = match robot.joints[i].kind {
            JointKind::Revolute => (z, g.cross(p, z)),
            JointKind::Prismatic => ([zero; 3], z),
        };
        set_column(&mut j_s, nv, ov + i, (w, v));
    }
    if let Some(b) = base {
        for c in 0..3 {
            let w = column(&b.r, c);
            let v = g.cross(b.p, w);
            set_column(&mut j_s, nv, c, (w, v));
            set_column(&mut j_s, nv, 3 + c, ([zero; 3], w));
        }
    }
    let mut pose: Vec<ExprId> = world.r.iter().flatten().copied().collect();
    pose.extend(world.p);
    FrameKinematics {
        pose,
        jacobian_space: j_s,
        jacobian_body: j_b,
    }
}
