//! Symbolic spatial algebra over the expression graph: 3-vectors, the joint transforms of
//! [`super::frames`], twists `(ω, v)`, wrenches `(m, f)` and rigid-body inertias.
//!
//! Every operation goes through the graph's simplifying constructors, so multiplications
//! by the zeros and ones of the robot's constants disappear as they are built.

use super::frames::{BodyInertia, JointFrame};
use crate::expr::{ExprGraph, ExprId};
use dynamics_model::JointKind;

/// A symbolic 3-vector.
pub type V3 = [ExprId; 3];

/// A symbolic twist `(ω, v)` or wrench `(m, f)`: angular part first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Spatial {
    /// ω (twist) or m (wrench).
    pub ang: V3,
    /// v (twist) or f (wrench).
    pub lin: V3,
}

/// A symbolic rigid-body inertia: mass `m`, first moment `h = m c`, rotational inertia `I_o`
/// about the frame's origin as `[xx, yy, zz, xy, xz, yz]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Inertia {
    /// m.
    pub m: ExprId,
    /// h = m c.
    pub h: V3,
    /// I_o.
    pub i: [ExprId; 6],
}

/// The symbolic state of joint i: its constant frame change and `sin θ`, `cos θ` (revolute)
/// or `θ` (prismatic).
#[derive(Clone, Copy, Debug)]
pub struct JointMotion<'a> {
    /// The constants.
    pub frame: &'a JointFrame,
    /// `sin θ_i` (revolute) — unused for prismatic joints.
    pub sin: ExprId,
    /// `cos θ_i` (revolute) — unused for prismatic joints.
    pub cos: ExprId,
    /// `θ_i` itself (prismatic).
    pub q: ExprId,
}

/// Graph helpers for vectors.
pub trait VectorOps {
    /// `c · x` for a constant `c`.
    fn cmul(&mut self, c: f64, x: ExprId) -> ExprId;
    /// `a + b`.
    fn add3(&mut self, a: V3, b: V3) -> V3;
    /// `a − b`.
    fn sub3(&mut self, a: V3, b: V3) -> V3;
    /// `s a` for a symbolic scalar `s`.
    fn scale3(&mut self, s: ExprId, a: V3) -> V3;
    /// `a × b`.
    fn cross(&mut self, a: V3, b: V3) -> V3;
    /// `R a` for a constant `R`.
    fn rot(&mut self, r: &[[f64; 3]; 3], a: V3) -> V3;
    /// `Rᵀ a` for a constant `R`.
    fn rot_t(&mut self, r: &[[f64; 3]; 3], a: V3) -> V3;
    /// The constant vector `c`.
    fn const3(&mut self, c: [f64; 3]) -> V3;
    /// The zero vector.
    fn zero3(&mut self) -> V3;
}

impl VectorOps for ExprGraph {
    fn cmul(&mut self, c: f64, x: ExprId) -> ExprId {
        let c = self.constant(c);
        self.mul(c, x)
    }

    fn add3(&mut self, a: V3, b: V3) -> V3 {
        [
            self.add(a[0], b[0]),
            self.add(a[1], b[1]),
            self.add(a[2], b[2]),
        ]
    }

    fn sub3(&mut self, a: V3, b: V3) -> V3 {
        [
            self.sub(a[0], b[0]),
            self.sub(a[1], b[1]),
            self.sub(a[2], b[2]),
        ]
    }

    fn scale3(&mut self, s: ExprId, a: V3) -> V3 {
        [self.mul(s, a[0]), self.mul(s, a[1]), self.mul(s, a[2])]
    }

    fn cross(&mut self, a: V3, b: V3) -> V3 {
        let mut out = [a[0]; 3];
        for k in 0..3 {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let x = self.mul(a[i], b[j]);
            let y = self.mul(a[j], b[i]);
            out[k] = self.sub(x, y);
        }
        out
    }

    fn rot(&mut self, r: &[[f64; 3]; 3], a: V3) -> V3 {
        let mut out = [a[0]; 3];
        for (row, o) in r.iter().zip(out.iter_mut()) {
            let terms = [
                self.cmul(row[0], a[0]),
                self.cmul(row[1], a[1]),
                self.cmul(row[2], a[2]),
            ];
            *o = self.sum(&terms);
        }
        out
    }

    fn rot_t(&mut self, r: &[[f64; 3]; 3], a: V3) -> V3 {
        let rt = [
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
            [r[0][2], r[1][2], r[2][2]],
        ];
        self.rot(&rt, a)
    }

    fn const3(&mut self, c: [f64; 3]) -> V3 {
        [
            self.constant(c[0]),
            self.constant(c[1]),
            self.constant(c[2]),
        ]
    }

    fn zero3(&mut self) -> V3 {
        let z = self.zero();
        [z, z, z]
    }
}

/// `Rot_z(θ) a = (c a_x − s a_y, s a_x + c a_y, a_z)`.
fn rot_z(g: &mut ExprGraph, s: ExprId, c: ExprId, a: V3) -> V3 {
    let x1 = g.mul(c, a[0]);
    let x2 = g.mul(s, a[1]);
    let y1 = g.mul(s, a[0]);
    let y2 = g.mul(c, a[1]);
    [g.sub(x1, x2), g.add(y1, y2), a[2]]
}

/// `Rot_z(−θ) a = (c a_x + s a_y, −s a_x + c a_y, a_z)`.
pub fn rot_z_t(g: &mut ExprGraph, s: ExprId, c: ExprId, a: V3) -> V3 {
    let x1 = g.mul(c, a[0]);
    let x2 = g.mul(s, a[1]);
    let y1 = g.mul(c, a[1]);
    let y2 = g.mul(s, a[0]);
    [g.add(x1, x2), g.sub(y1, y2), a[2]]
}

/// `e_z × a = (−a_y, a_x, 0)`.
fn ez_cross(g: &mut ExprGraph, a: V3) -> V3 {
    [g.neg(a[1]), a[0], g.zero()]
}

impl JointMotion<'_> {
    /// `[Ad_{T_{J_i,J_{i−1}}}] V`: a twist of {J_{i−1}} expressed in {J_i}.
    /// With `T = (R, p)`: `ω' = R ω`, `v' = R v + p × ω'`, applied for `C_i` and then for
    /// the joint's own `Rot_z(−θ)` or `Trans_z(−θ)`.
    pub fn motion_to_child(&self, g: &mut ExprGraph, v: Spatial) -> Spatial {
        let f = self.frame;
        let w1 = g.rot(&f.r, v.ang);
        let rv = g.rot(&f.r, v.lin);
        let p = g.const3(f.p);
        let pxw = g.cross(p, w1);
        let v1 = g.add3(rv, pxw);
        match f.kind {
            JointKind::Revolute => Spatial {
                ang: rot_z_t(g, self.sin, self.cos, w1),
                lin: rot_z_t(g, self.sin, self.cos, v1),
            },
            JointKind::Prismatic => {
                // p = −θ e_z: v' = v − θ (e_z × ω).
                let ezw = ez_cross(g, w1);
                let t = g.scale3(self.q, ezw);
                Spatial {
                    ang: w1,
                    lin: g.sub3(v1, t),
                }
            }
        }
    }

    /// `[Ad_{T_{J_i,J_{i−1}}}]ᵀ F`: a wrench of {J_i} expressed in {J_{i−1}}.
    /// With `T = (R, p)`: `f' = Rᵀ f`, `m' = Rᵀ (m − p × f)`, applied for the joint's part
    /// first and then for `C_i`.
    pub fn force_to_parent(&self, g: &mut ExprGraph, w: Spatial) -> Spatial {
        let f = self.frame;
        let (m1, f1) = match f.kind {
            JointKind::Revolute => (
                rot_z(g, self.sin, self.cos, w.ang),
                rot_z(g, self.sin, self.cos, w.lin),
            ),
            JointKind::Prismatic => {
                // p = −θ e_z: m' = m + θ (e_z × f).
                let ezf = ez_cross(g, w.lin);
                let t = g.scale3(self.q, ezf);
                (g.add3(w.ang, t), w.lin)
            }
        };
        let p = g.const3(f.p);
        let pxf = g.cross(p, f1);
        let m2 = g.sub3(m1, pxf);
        Spatial {
            ang: g.rot_t(&f.r, m2),
            lin: g.rot_t(&f.r, f1),
        }
    }

    /// `[Ad_T]ᵀ G [Ad_T]` for `T = T_{J_i,J_{i−1}}`: an inertia of {J_i} expressed in {J_{i−1}}.
    pub fn inertia_to_parent(&self, g: &mut ExprGraph, ib: &Inertia) -> Inertia {
        let f = self.frame;
        // Joint part: the pose of the intermediate frame in {J_i} is Rot_z(−θ) or Trans_z(−θ).
        let mid = match f.kind {
            JointKind::Revolute => rotate_inertia_z(g, self.sin, self.cos, ib),
            JointKind::Prismatic => {
                let zero = g.zero();
                let p = [zero, zero, g.neg(self.q)];
                shift_inertia(g, ib, p)
            }
        };
        // Constant part: shift by p, then rotate by R (pose of {J_{i−1}} in the intermediate frame).
        let p = g.const3(f.p);
        let shifted = shift_inertia(g, &mid, p);
        rotate_inertia_const(g, &f.r, &shifted)
    }
}

/// Expresses an inertia in a frame whose origin is at `p` (same axes):
/// `h' = h − m p`, `I' = I + [h][p] + [p][h] − m[p][p]`.
fn shift_inertia(g: &mut ExprGraph, ib: &Inertia, p: V3) -> Inertia {
    let mp = g.scale3(ib.m, p);
    let h = g.sub3(ib.h, mp);
    // [h][p] + [p][h] = p hᵀ + h pᵀ − 2(h·p) 1, and −m[p][p] = m(p·p 1 − p pᵀ).
    let hp = g.dot(&ib.h, &p);
    let pp = g.dot(&mp, &p);
    let diag_common = {
        let two_hp = g.cmul(2.0, hp);
        g.sub(pp, two_hp)
    };
    let idx = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let mut i = ib.i;
    for (k, &(a, b)) in idx.iter().enumerate() {
        let t1 = g.mul(p[a], ib.h[b]);
        let t2 = g.mul(ib.h[a], p[b]);
        let t3 = g.mul(mp[a], p[b]);
        let s12 = g.add(t1, t2);
        let mut delta = g.sub(s12, t3);
        if a == b {
            delta = g.add(delta, diag_common);
        }
        i[k] = g.add(ib.i[k], delta);
    }
    Inertia { m: ib.m, h, i }
}

fn sym(i: &[ExprId; 6]) -> [[ExprId; 3]; 3] {
    [[i[0], i[3], i[4]], [i[3], i[1], i[5]], [i[4], i[5], i[2]]]
}

/// The entries `xx, yy, zz, xy, xz, yz` of a symmetric 3×3 (the inverse of [`sym`]).
fn unsym(m: &[[ExprId; 3]; 3]) -> [ExprId; 6] {
    [m[0][0], m[1][1], m[2][2], m[0][1], m[0][2], m[1][2]]
}

/// `I' = Rᵀ I R`, `h' = Rᵀ h` for a constant rotation `R` (the new frame's axes in the old),
/// as the articulated inertias ([`rot_const_congruence`]): a DH twist (a turn about one
/// coordinate axis) by the double angle, eight products where the general form takes eighteen.
pub(crate) fn rotate_inertia_const(g: &mut ExprGraph, r: &[[f64; 3]; 3], ib: &Inertia) -> Inertia {
    let h = g.rot_t(r, ib.h);
    let i = rot_const_congruence(g, r, &sym(&ib.i), Block::Symmetric);
    Inertia {
        m: ib.m,
        h,
        i: unsym(&i),
    }
}

/// The inertia in a frame rotated by `Rot_z(−θ)` about z: `I' = R_z(θ) I R_z(θ)ᵀ`,
/// `h' = R_z(θ) h`, through [`rot_axis_congruence`] (the double-angle products).
fn rotate_inertia_z(g: &mut ExprGraph, s: ExprId, c: ExprId, ib: &Inertia) -> Inertia {
    let h = rot_z(g, s, c, ib.h);
    let i = rot_axis_congruence(g, 2, s, c, &sym(&ib.i), Block::SymmetricAlone);
    Inertia {
        m: ib.m,
        h,
        i: unsym(&i),
    }
}

impl Inertia {
    /// The constant inertia `b`.
    pub fn constant(g: &mut ExprGraph, b: &BodyInertia) -> Self {
        Self {
            m: g.constant(b.m),
            h: g.const3(b.h),
            i: [
                g.constant(b.i[0]),
                g.constant(b.i[1]),
                g.constant(b.i[2]),
                g.constant(b.i[3]),
                g.constant(b.i[4]),
                g.constant(b.i[5]),
            ],
        }
    }

    /// `a + b`.
    pub fn add(g: &mut ExprGraph, a: &Inertia, b: &Inertia) -> Self {
        let mut i = a.i;
        for k in 0..6 {
            i[k] = g.add(a.i[k], b.i[k]);
        }
        Self {
            m: g.add(a.m, b.m),
            h: g.add3(a.h, b.h),
            i,
        }
    }

    /// `I_o ω`.
    pub fn rotational(&self, g: &mut ExprGraph, w: V3) -> V3 {
        let s = sym(&self.i);
        [g.dot(&s[0], &w), g.dot(&s[1], &w), g.dot(&s[2], &w)]
    }

    /// The momentum `G V = (I_o ω + h × v, m v − h × ω)`.
    pub fn apply(&self, g: &mut ExprGraph, v: &Spatial) -> Spatial {
        let s = sym(&self.i);
        let mut iw = [self.m; 3];
        for r in 0..3 {
            iw[r] = g.dot(&s[r], &v.ang);
        }
        let hxv = g.cross(self.h, v.lin);
        let hxw = g.cross(self.h, v.ang);
        let mv = g.scale3(self.m, v.lin);
        Spatial {
            ang: g.add3(iw, hxv),
            lin: g.sub3(mv, hxw),
        }
    }
}

/// A symbolic 3×3 matrix, row-major.
pub type M3 = [[ExprId; 3]; 3];

/// A symbolic symmetric 6×6 spatial inertia `[[A, B], [Bᵀ, C]]` (21 distinct entries), with
/// `A = Aᵀ` and `C = Cᵀ` stored as mirrored ids: the articulated-body inertias of
/// [`super::aba`], which are not rigid-body inertias. It maps a twist `(ω, v)` to the wrench
/// `(A ω + B v, Bᵀ ω + C v)`; a rigid body has `A = I_o`, `B = [h]`, `C = m 1₃`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SymInertia {
    /// `A`: angular–angular block (symmetric).
    pub a: M3,
    /// `B`: angular–linear block.
    pub b: M3,
    /// `C`: linear–linear block (symmetric).
    pub c: M3,
}

/// A symmetric 3×3 matrix from its upper triangle `f(i, j)`, `i ≤ j`, built row by row.
fn sym3(mut f: impl FnMut(usize, usize) -> ExprId) -> M3 {
    let mut m = [[None; 3]; 3];
    for i in 0..3 {
        for j in i..3 {
            m[i][j] = Some(f(i, j));
        }
    }
    let mut out = [[ExprId(0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let (a, b) = if i <= j { (i, j) } else { (j, i) };
            out[i][j] = m[a][b].unwrap_or(ExprId(0));
        }
    }
    out
}

/// A general 3×3 matrix from `f(i, j)`, built row by row.
fn gen3(mut f: impl FnMut(usize, usize) -> ExprId) -> M3 {
    let mut out = [[ExprId(0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = f(i, j);
        }
    }
    out
}

/// The cross-product matrix `[p]`.
fn skew(g: &mut ExprGraph, p: V3) -> M3 {
    let z = g.zero();
    let [x, y, w] = p;
    let (nx, ny, nw) = (g.neg(x), g.neg(y), g.neg(w));
    [[z, nw, y], [w, z, nx], [ny, x, z]]
}

/// `(a b)_{ij}` for symbolic 3×3 matrices.
fn mat_entry(g: &mut ExprGraph, a: &M3, b: &M3, i: usize, j: usize) -> ExprId {
    let col = [b[0][j], b[1][j], b[2][j]];
    g.dot(&a[i], &col)
}

/// The shape of a 3×3 block a congruence turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    /// Any 3×3.
    General,
    /// Symmetric, turned beside a general block of the same turn (which forms `c²`).
    Symmetric,
    /// Symmetric, the turn's only block (a rigid inertia's: no `c²` formed for it).
    SymmetricAlone,
}

/// `Q M Qᵀ` with `Q` the rotation by θ about coordinate axis `k` (`sin θ = s`,
/// `cos θ = c`). With `(x, y, z)` the axes `(k+1, k+2, k)` cyclically, `Q` turns the xy plane
/// by `[[c, −s], [s, c]]`: the z row and column turn like vectors, and the xy block is
///
/// ```text
/// t = (m_xx − m_yy) s² + (m_xy + m_yx) s c,   m_xx' = m_xx − t,   m_yy' = m_yy + t
/// m_xy' = (m_xx − m_yy) s c + m_xy c² − m_yx s²,   m_yx' = (m_xx − m_yy) s c + m_yx c² − m_xy s²
/// ```
///
/// (for symmetric `M`: `m_xy' = m_yx' = (m_xx − m_yy) s c + m_xy (c² − s²)`, or, where no
/// other block of the turn needs `c²` ([`Block::SymmetricAlone`]), `m_xy + (m_xx − m_yy) s c −
/// (m_xy + m_yx) s²`: one product fewer, one addition more).
fn rot_axis_congruence(
    g: &mut ExprGraph,
    k: usize,
    s: ExprId,
    c: ExprId,
    m: &M3,
    block: Block,
) -> M3 {
    let symmetric = block != Block::General;
    let (x, y, z) = ((k + 1) % 3, (k + 2) % 3, k);
    let turn = |g: &mut ExprGraph, u: ExprId, w: ExprId| {
        let a = g.mul(c, u);
        let b = g.mul(s, w);
        let e = g.mul(s, u);
        let f = g.mul(c, w);
        (g.sub(a, b), g.add(e, f))
    };
    let (col_x, col_y) = turn(g, m[x][z], m[y][z]);
    let (row_x, row_y) = if symmetric {
        (col_x, col_y)
    } else {
        turn(g, m[z][x], m[z][y])
    };
    let ss = g.mul(s, s);
    let sc = g.mul(s, c);
    let diff = g.sub(m[x][x], m[y][y]);
    let off = g.add(m[x][y], m[y][x]);
    let t1 = g.mul(diff, ss);
    let t2 = g.mul(off, sc);
    let t = g.add(t1, t2);
    let xx = g.sub(m[x][x], t);
    let yy = g.add(m[y][y], t);
    let dsc = g.mul(diff, sc);
    let (xy, yx) = if block == Block::SymmetricAlone {
        // m_xy (c² − s²) = m_xy − (2 m_xy) s², with 2 m_xy = `off`: no c².
        let o = g.mul(off, ss);
        let d = g.sub(dsc, o);
        let xy = g.add(m[x][y], d);
        (xy, xy)
    } else if symmetric {
        let cc = g.mul(c, c);
        let cos2 = g.sub(cc, ss);
        let o = g.mul(m[x][y], cos2);
        let xy = g.add(dsc, o);
        (xy, xy)
    } else {
        let cc = g.mul(c, c);
        let a = g.mul(m[x][y], cc);
        let b = g.mul(m[y][x], ss);
        let ab = g.sub(a, b);
        let xy = g.add(dsc, ab);
        let a = g.mul(m[y][x], cc);
        let b = g.mul(m[x][y], ss);
        let ab = g.sub(a, b);
        (xy, g.add(dsc, ab))
    };
    let mut out = *m;
    out[x][x] = xx;
    out[y][y] = yy;
    out[x][y] = xy;
    out[y][x] = yx;
    out[x][z] = col_x;
    out[y][z] = col_y;
    out[z][x] = row_x;
    out[z][y] = row_y;
    out
}

/// `Rᵀ M R` for a constant rotation `R`. A rotation about a coordinate axis by an angle
/// that is not a multiple of π/2 (the DH `Rot_x(−α)`) goes through [`rot_axis_congruence`];
/// any other through two products, where the zeros of a signed permutation fold away.
fn rot_const_congruence(g: &mut ExprGraph, r: &[[f64; 3]; 3], m: &M3, block: Block) -> M3 {
    for k in 0..3 {
        let (x, y) = ((k + 1) % 3, (k + 2) % 3);
        let axis_fixed = (0..3).all(|j| {
            let e = if j == k { 1.0 } else { 0.0 };
            r[k][j] == e && r[j][k] == e
        });
        // Rᵀ = Q = [[c, −s], [s, c]] in the (x, y) plane.
        let (c, s) = (r[x][x], r[x][y]);
        if axis_fixed && r[y][y] == c && r[y][x] == -s && s != 0.0 && c != 0.0 {
            let (s, c) = (g.constant(s), g.constant(c));
            return rot_axis_congruence(g, k, s, c, m, block);
        }
    }
    let rc = gen3(|i, j| g.constant(r[i][j]));
    let rt = gen3(|i, j| rc[j][i]);
    let mr = gen3(|i, j| mat_entry(g, m, &rc, i, j));
    if block != Block::General {
        sym3(|i, j| mat_entry(g, &rt, &mr, i, j))
    } else {
        gen3(|i, j| mat_entry(g, &rt, &mr, i, j))
    }
}

impl SymInertia {
    /// The rigid-body inertia `ib` as a symmetric 6×6: `A = I_o`, `B = [h]`, `C = m 1₃`.
    pub fn rigid(g: &mut ExprGraph, ib: &Inertia) -> Self {
        let z = g.zero();
        let diag = [[ib.m, z, z], [z, ib.m, z], [z, z, ib.m]];
        Self {
            a: sym(&ib.i),
            b: skew(g, ib.h),
            c: diag,
        }
    }

    /// The entry `(j, k)` of the 6×6 matrix (angular indices 0–2, linear 3–5).
    pub fn entry(&self, j: usize, k: usize) -> ExprId {
        match (j < 3, k < 3) {
            (true, true) => self.a[j][k],
            (true, false) => self.b[j][k - 3],
            (false, true) => self.b[k][j - 3],
            (false, false) => self.c[j - 3][k - 3],
        }
    }

    /// The symmetric 6×6 matrix with upper-triangle entries `f(j, k)`, `j ≤ k`, built in
    /// row order.
    pub fn from_upper(mut f: impl FnMut(usize, usize) -> ExprId) -> Self {
        let mut m = [[ExprId(0); 6]; 6];
        for j in 0..6 {
            for k in j..6 {
                m[j][k] = f(j, k);
                m[k][j] = m[j][k];
            }
        }
        Self {
            a: gen3(|i, j| m[i][j]),
            b: gen3(|i, j| m[i][j + 3]),
            c: gen3(|i, j| m[i + 3][j + 3]),
        }
    }

    /// `x + y`.
    pub fn add(g: &mut ExprGraph, x: &Self, y: &Self) -> Self {
        Self {
            a: sym3(|i, j| g.add(x.a[i][j], y.a[i][j])),
            b: gen3(|i, j| g.add(x.b[i][j], y.b[i][j])),
            c: sym3(|i, j| g.add(x.c[i][j], y.c[i][j])),
        }
    }

    /// The wrench `(A ω + B v, Bᵀ ω + C v)` of the twist `v = (ω, v)`.
    pub fn apply(&self, g: &mut ExprGraph, v: &Spatial) -> Spatial {
        let mut ang = v.ang;
        let mut lin = v.lin;
        for r in 0..3 {
            let bt = [self.b[0][r], self.b[1][r], self.b[2][r]];
            let x = g.dot(&self.a[r], &v.ang);
            let y = g.dot(&self.b[r], &v.lin);
            ang[r] = g.add(x, y);
            let x = g.dot(&bt, &v.ang);
            let y = g.dot(&self.c[r], &v.lin);
            lin[r] = g.add(x, y);
        }
        Spatial { ang, lin }
    }

    /// The matrix in a frame whose origin is at `p` (same axes): with `P = [p]`,
    /// `A' = A + B P + (B P)ᵀ − P C P`, `B' = B − P C`, `C' = C`; `form` says how `A'` is
    /// written out.
    pub fn shift(&self, g: &mut ExprGraph, p: V3, form: ShiftForm) -> Self {
        let pm = skew(g, p);
        let pc = gen3(|i, j| mat_entry(g, &pm, &self.c, i, j));
        let b = gen3(|i, j| g.sub(self.b[i][j], pc[i][j]));
        let dense = p.iter().filter(|&&x| !g.is_zero(x)).count() >= 2;
        let a = match form {
            ShiftForm::Folded => true,
            ShiftForm::Direct => false,
            ShiftForm::Sparse => dense,
        };
        let a = if a {
            let e = gen3(|i, j| g.add(self.b[i][j], b[i][j]));
            let h = gen3(|i, j| mat_entry(g, &e, &pm, i, j));
            sym3(|i, j| {
                if i == j {
                    g.add(self.a[i][i], h[i][i])
                } else {
                    let t = g.add(h[i][j], h[j][i]);
                    let t = g.cmul(0.5, t);
                    g.add(self.a[i][j], t)
                }
            })
        } else {
            let bp = gen3(|i, j| mat_entry(g, &self.b, &pm, i, j));
            sym3(|i, j| {
                let pcp = mat_entry(g, &pc, &pm, i, j);
                let t = g.add(bp[i][j], bp[j][i]);
                let t = g.sub(t, pcp);
                g.add(self.a[i][j], t)
            })
        };
        Self { a, b, c: self.c }
    }
}

/// How [`SymInertia::shift`] writes out `A' = A + B P + (B P)ᵀ − P C P`; the forms are equal,
/// and which needs fewer operations depends on the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShiftForm {
    /// As written.
    Direct,
    /// `A' = A + ½ (H + Hᵀ)` with `H = (B + B') P` (`(P C P)ᵀ = P C P`): fewer products
    /// when `P` is dense, and the ½ folds into later constant factors.
    Folded,
    /// [`ShiftForm::Folded`] when `p` has two or more non-zero components, else
    /// [`ShiftForm::Direct`].
    Sparse,
}

impl JointMotion<'_> {
    /// `[Ad_T]ᵀ I [Ad_T]` for `T = T_{J_i,J_{i−1}}` and a symmetric 6×6 `I` of {J_i}: `I`
    /// expressed in {J_{i−1}}. As in [`JointMotion::inertia_to_parent`], in two stages: the
    /// joint's own `Rot_z(−θ)` (`A, B, C ↦ Q A Qᵀ, Q B Qᵀ, Q C Qᵀ` with `Q = Rot_z(θ)`) or
    /// `Trans_z(−θ)` (a shift), then the constant `C_i`: shift by `p`, then rotate by `R`.
    /// Shifts are written out as `form` says.
    pub fn sym_inertia_to_parent(
        &self,
        g: &mut ExprGraph,
        ia: &SymInertia,
        form: ShiftForm,
    ) -> SymInertia {
        let f = self.frame;
        let mid = match f.kind {
            JointKind::Revolute => SymInertia {
                a: rot_axis_congruence(g, 2, self.sin, self.cos, &ia.a, Block::Symmetric),
                b: rot_axis_congruence(g, 2, self.sin, self.cos, &ia.b, Block::General),
                c: rot_axis_congruence(g, 2, self.sin, self.cos, &ia.c, Block::Symmetric),
            },
            JointKind::Prismatic => {
                let zero = g.zero();
                let p = [zero, zero, g.neg(self.q)];
                ia.shift(g, p, form)
            }
        };
        let p = g.const3(f.p);
        let shifted = mid.shift(g, p, form);
        SymInertia {
            a: rot_const_congruence(g, &f.r, &shifted.a, Block::Symmetric),
            b: rot_const_congruence(g, &f.r, &shifted.b, Block::General),
            c: rot_const_congruence(g, &f.r, &shifted.c, Block::Symmetric),
        }
    }
}
