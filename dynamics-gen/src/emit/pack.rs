//! Packs: isomorphic scalar nodes computed together, one per lane of a 4-lane vector
//! (superword-level parallelism, Larsen and Amarasinghe 2000, on the expression graph).
//!
//! A pose's rotation is three rows computed alike: each row of `R_{0,i}` goes through the
//! same products by the same sines, cosines and constants as the other two (`r ← r · C_i⁻¹ ·
//! Rot_z(θ_i)`), and so do the translation's rows. Written as scalars they are three
//! instruction streams of the same operations, which the optimiser does not pack into vector
//! instructions by itself (it vectorises from stores of adjacent values, and a pose's
//! entries go into a quaternion). [`find`] packs them: seeded by three output entries, the
//! rows of one column, it walks down their operands as long as the three nodes are the same
//! operation, each operand then a pack itself, one value for all lanes (a sine, a joint's
//! cosine), constants, or scalars gathered into a vector.
//!
//! A tree's alike limbs are the same: the four legs of a quadruped go through the same
//! recursion with their own constants, and each joint's torque, velocity and force is one
//! tree of operations in every leg. [`alike_seeds`] seeds the dynamics' bodies with their
//! outputs of one shape ([`crate::expr::shape`]): the torques of the four hips, of the four
//! knees, and the packs grow down from them as far as the legs stay alike (to the base's
//! quantities, which every lane reads: a splat).
//!
//! Signs are free: the simplifier writes `a − b` for one row and `a + b` for another, or pulls
//! a negation out of a product, wherever a row's constant is negative. So a lane is a node
//! and a sign, `±n`, and packs have two operations: sums (`a − b = a + (−b)`) and products
//! (`−(a·b) = (−a)·b`, the sign given to the first factor); negations are peeled into the
//! lanes' signs, and a constant's sign into its value. Every lane computes `±` the value its
//! node has in the scalar code, with the same operations: a sign changes no rounding, and a
//! fused multiply-add `fma(−x, y, c)` is the scalar code's `mul_add(−x, y, c)`.
//!
//! The emitter writes a pack as one `[T; 4]` operation (`Self::v4_fma`, …; `T` is `f64` or
//! `f32`), which the dispatched copies compile to one AVX2 instruction (on a 256-bit
//! register for `f64`, a 128-bit one for `f32`) and the portable code to the scalar
//! operations it had (an unused fourth lane is removed); an `f64` pack of two lanes (a
//! humanoid's legs or arms) as `Self::v2_fma`, …, on the first two lanes, one 128-bit
//! register in the copies. A seed is kept only where it saves instructions ([`MIN_SAVED`]),
//! and only where the packs can be ordered (no lane reads another lane's value of the same
//! pack, directly or through other packs): [`find`] checks that the graph with every pack
//! contracted to one node has no cycle, and drops a seed that would make one.

use crate::expr::{ExprGraph, ExprId, Node};

/// Lanes of a pack.
pub const LANES: usize = 4;

/// A lane: a node and whether it is negated (`None`: an unused lane).
pub type Lane = Option<(ExprId, bool)>;

/// The lanes of a pack or operand.
pub type Lanes = [Lane; LANES];

/// The operation of a pack (the lanes' signs are in the operands).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `a + b`.
    Add,
    /// `a · b`.
    Mul,
}

/// An operand of a pack, lane by lane.
#[derive(Clone, Debug)]
pub enum Operand {
    /// Another pack, lane for lane. `tops`: the nodes the scalar code reads there (a pack's
    /// node, or a negation of one).
    Pack(usize, Lanes),
    /// Lanes of another pack in another order or with other signs: lane `k` is that pack's
    /// lane `map[k].0`, negated when `map[k].1` (0 in unused lanes), e.g. `(p₁, p₂, p₀)` of a
    /// cross product. `tops` as for [`Operand::Pack`].
    Permute(usize, [Option<(usize, bool)>; LANES], Lanes),
    /// One scalar node in every lane, times each lane's sign (`±1`, 0 in unused lanes).
    Splat(ExprId, [f64; LANES]),
    /// Constants (0 in unused lanes).
    Consts([f64; LANES]),
    /// Scalar nodes gathered into lanes, negated where the lane says (0 in unused lanes).
    Gather(Lanes),
}

/// A pack: lane `k` is `op` of lane `k` of each operand.
#[derive(Clone, Debug)]
pub struct Pack {
    /// Its nodes and signs: lane `k` of the vector is `±lanes[k].0`.
    pub lanes: Lanes,
    /// The operation.
    pub op: Op,
    /// The two operands.
    pub operands: [Operand; 2],
}

/// Where a packed node is: `(pack, lane, negated)`, the node being the lane's value, or its
/// negation when `negated`. A pack holds its lanes' nodes and the negations of them that its
/// users read (`−n` peeled into a sign).
pub type Place = (usize, usize, bool);

/// The packs of a function, and for every node of the graph its place.
#[derive(Clone, Debug, Default)]
pub struct Packing {
    /// The packs, operands before their users.
    pub packs: Vec<Pack>,
    /// `of[node]`: where a packed node is.
    pub of: Vec<Option<Place>>,
}

/// The fewest scalar instructions a seed must save to be kept: lanes beyond the first of
/// every pack, less the instructions its operands cost (a splat 1, with signs 2, a permutation
/// 1 or 2, one per gathered lane). The seed's own lanes are then taken out of the vector for
/// the scalar code that reads them (a pose's quaternion), about two instructions more.
pub const MIN_SAVED: i64 = 6;

/// [`MIN_SAVED`] for a seed of two lanes, whose packs save one instruction each: a limb's
/// worth. G1's legs save 433 instructions in its inverse dynamics (17–19 % faster), 43 in its
/// gravity; Solo-12's `base_parameters` had two seeds of 11 and 12, and ran 15–26 % slower with
/// them (`docs/performance.md`, twenty-eighth session).
pub const MIN_SAVED_TWO_LANES: i64 = 32;

/// The pack of lanes whose operands are being built.
const BUILDING: usize = usize::MAX;

/// How many levels of operands [`Finder::likeness`] compares.
const LIKENESS_DEPTH: u32 = 2;

/// How deep a seed's packs may nest (the walk is recursive).
const MAX_DEPTH: u32 = 256;

/// The packs of the nodes live in `g` (`live`), grown from `seeds` (lanes of positive
/// nodes): `None` when none is kept.
pub fn find(g: &ExprGraph, live: &[bool], seeds: &[[Option<ExprId>; LANES]]) -> Option<Packing> {
    let mut finder = Finder {
        g,
        packing: Packing {
            packs: Vec::new(),
            of: vec![None; g.len()],
        },
        aliases: Vec::new(),
    };
    for seed in seeds {
        let start = finder.packing.packs.len();
        let aliases = finder.aliases.len();
        let lanes = seed.map(|x| x.map(|x| (x, false)));
        if !matches!(finder.build(lanes, 0), Operand::Pack(..)) {
            finder.undo(start, aliases);
            continue;
        }
        let min_saved = if seed.iter().flatten().count() == 2 {
            MIN_SAVED_TWO_LANES
        } else {
            MIN_SAVED
        };
        let kept =
            saved(&finder.packing.packs[start..]) >= min_saved && acyclic(g, live, &finder.packing);
        if !kept {
            finder.undo(start, aliases);
        }
    }
    (!finder.packing.packs.is_empty()).then_some(finder.packing)
}

/// The fewest alike outputs [`alike_seeds`] packs together by default: two, a humanoid's
/// mirrored legs (G1's inverse dynamics 17–19 % faster, coriolis 9–19 %: `docs/performance.md`,
/// twenty-eighth session). Two lanes pay only with a two-lane gather counted as the one
/// instruction it is ([`gather_cost`]); counted as two, every seed's packs were undone.
pub const MIN_ALIKE_LANES: usize = 2;

/// Seeds for a body whose outputs are not a pose's rows: its outputs (sums, differences and
/// products) of one shape ([`crate::expr::shape`]), `min_lanes` to [`LANES`] in each
/// seed, in the outputs' order: the torques of a quadruped's four hips, each leg's own chain of the same
/// operations on its own constants. [`find`] then packs as far as they stay alike.
pub fn alike_seeds(
    g: &ExprGraph,
    live: &[bool],
    outputs: &[ExprId],
    min_lanes: usize,
) -> Vec<[Option<ExprId>; LANES]> {
    let shape = crate::expr::shape::shapes(g, live);
    let mut index: std::collections::HashMap<u64, usize> = std::collections::HashMap::new();
    let mut groups: Vec<Vec<ExprId>> = Vec::new();
    for &o in outputs {
        let mut x = o;
        while let Node::Neg(a) = *g.node(x) {
            x = a;
        }
        if !matches!(g.node(x), Node::Add(..) | Node::Sub(..) | Node::Mul(..)) {
            continue;
        }
        let k = *index.entry(shape[x.index()]).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        if !groups[k].contains(&x) {
            groups[k].push(x);
        }
    }
    let mut seeds = Vec::new();
    for group in &groups {
        for chunk in group.chunks(LANES).filter(|c| c.len() >= min_lanes) {
            seeds.push(std::array::from_fn(|k| chunk.get(k).copied()));
        }
    }
    seeds
}

/// The instructions that gather `n` scalars into the lanes of a pack of `width` lanes: into a
/// pack of two, one `unpcklpd` of two registers (or a load and a `movhpd`); into a wider one,
/// one per lane, as the packs of three and four lanes were measured with (counted as one
/// there, TALOS' three-lane packs of its grippers ran 2–16 % slower).
fn gather_cost(n: usize, width: usize) -> i64 {
    if width == 2 {
        1
    } else {
        n as i64
    }
}

/// The scalar instructions `packs` save (see [`MIN_SAVED`]).
pub(crate) fn saved(packs: &[Pack]) -> i64 {
    let mut saved = 0i64;
    for pack in packs {
        let width = pack.lanes.iter().flatten().count();
        saved += width as i64 - 1;
        for operand in &pack.operands {
            saved -= match operand {
                Operand::Splat(_, signs) => 1 + i64::from(signs.iter().any(|&s| s < 0.0)),
                Operand::Gather(lanes) => gather_cost(lanes.iter().flatten().count(), width),
                Operand::Permute(_, map, _) => {
                    let moved = map
                        .iter()
                        .enumerate()
                        .any(|(k, m)| m.is_some_and(|(j, _)| j != k));
                    let signed = map.iter().flatten().any(|&(_, neg)| neg);
                    i64::from(moved) + i64::from(signed)
                }
                Operand::Pack(..) | Operand::Consts(_) => 0,
            };
        }
    }
    saved
}

/// Whether the live graph with every pack contracted to one node is acyclic (Kahn's
/// algorithm on the contracted graph).
fn acyclic(g: &ExprGraph, live: &[bool], packing: &Packing) -> bool {
    let n = g.len();
    let unit = |id: usize| packing.of[id].map_or(id, |(p, _, _)| n + p);
    let units = n + packing.packs.len();
    let mut edges: Vec<Vec<usize>> = vec![Vec::new(); units];
    let mut indegree = vec![0usize; units];
    let mut present = vec![false; units];
    for k in (0..n).filter(|&k| live[k]) {
        let to = unit(k);
        present[to] = true;
        for o in g.node(ExprId(k as u32)).operands() {
            let from = unit(o.index());
            if from != to {
                edges[from].push(to);
                indegree[to] += 1;
            }
        }
    }
    let mut ready: Vec<usize> = (0..units)
        .filter(|&u| present[u] && indegree[u] == 0)
        .collect();
    let mut seen = 0;
    while let Some(u) = ready.pop() {
        seen += 1;
        for &v in &edges[u] {
            indegree[v] -= 1;
            if indegree[v] == 0 {
                ready.push(v);
            }
        }
    }
    seen == present.iter().filter(|&&p| p).count()
}

struct Finder<'a> {
    g: &'a ExprGraph,
    packing: Packing,
    /// The negations placed in packs as aliases of their operands, in order (for undoing).
    aliases: Vec<ExprId>,
}

impl Finder<'_> {
    /// Removes the packs from `start` on and the aliases from `aliases` on.
    fn undo(&mut self, start: usize, aliases: usize) {
        for pack in self.packing.packs.drain(start..) {
            for (id, _) in pack.lanes.iter().flatten() {
                self.packing.of[id.index()] = None;
            }
        }
        for id in self.aliases.drain(aliases..) {
            self.packing.of[id.index()] = None;
        }
    }

    /// `(n, neg)` with negations peeled off `n` into the sign, and the negations peeled.
    fn peel(&self, (mut n, mut neg): (ExprId, bool)) -> ((ExprId, bool), Vec<ExprId>) {
        let mut peeled = Vec::new();
        while let Node::Neg(a) = *self.g.node(n) {
            peeled.push(n);
            n = a;
            neg = !neg;
        }
        ((n, neg), peeled)
    }

    /// The operand that computes `tops` (lanes as the scalar code reads them), creating the
    /// packs it needs.
    fn build(&mut self, tops: Lanes, depth: u32) -> Operand {
        let mut lanes: Lanes = [None; LANES];
        let mut peeled: Vec<Vec<ExprId>> = vec![Vec::new(); LANES];
        for k in 0..LANES {
            if let Some(top) = tops[k] {
                let (lane, negations) = self.peel(top);
                lanes[k] = Some(lane);
                peeled[k] = negations;
            }
        }
        let present: Vec<(ExprId, bool)> = lanes.iter().flatten().copied().collect();
        let Some(&(first, _)) = present.first() else {
            return Operand::Consts([0.0; LANES]);
        };
        let sign = |neg: bool| if neg { -1.0 } else { 1.0 };
        if present.iter().all(|&(x, _)| self.g.as_const(x).is_some()) {
            return Operand::Consts(lanes.map(|l| {
                l.and_then(|(x, neg)| self.g.as_const(x).map(|c| sign(neg) * c))
                    .unwrap_or(0.0)
            }));
        }
        if present.len() > 1 && present.iter().all(|&(x, _)| x == first) {
            return Operand::Splat(first, lanes.map(|l| l.map_or(0.0, |(_, neg)| sign(neg))));
        }
        // Lanes of one pack (and the negations peeled on the way, which are then that pack's
        // too): as they are, or permuted.
        if let Some((p, _, _)) = self.packing.of[first.index()].filter(|o| o.0 != BUILDING) {
            let map = lanes.map(|l| {
                l.map(|(x, neg)| match self.packing.of[x.index()] {
                    Some((q, j, flip)) if q == p => Some((j, neg != flip)),
                    _ => None,
                })
            });
            if map.iter().all(|m| m.is_none_or(|m| m.is_some())) {
                let map = map.map(Option::flatten);
                for (k, negations) in peeled.iter().enumerate() {
                    let Some((x, _)) = lanes[k] else { continue };
                    let Some((_, j, flip)) = self.packing.of[x.index()] else {
                        continue;
                    };
                    // The peeled negations, from the innermost: `−x`, `x`, `−x`, ….
                    let mut neg = !flip;
                    for &n in negations.iter().rev() {
                        if self.packing.of[n.index()].is_none() {
                            self.packing.of[n.index()] = Some((p, j, neg));
                            self.aliases.push(n);
                        }
                        neg = !neg;
                    }
                }
                let identity = map
                    .iter()
                    .enumerate()
                    .all(|(k, m)| m.is_none_or(|(j, neg)| j == k && !neg));
                return if identity {
                    Operand::Pack(p, tops)
                } else {
                    Operand::Permute(p, map, tops)
                };
            }
        }
        let distinct = present
            .iter()
            .enumerate()
            .all(|(k, (x, _))| !present[..k].iter().any(|(y, _)| y == x));
        let free = present
            .iter()
            .all(|(x, _)| self.packing.of[x.index()].is_none())
            && peeled
                .iter()
                .flatten()
                .all(|x| self.packing.of[x.index()].is_none());
        let op = self.op_of(first);
        if present.len() < 2
            || depth > MAX_DEPTH
            || !distinct
            || !free
            || op.is_none()
            || present.iter().any(|&(x, _)| self.op_of(x) != op)
        {
            return Operand::Gather(tops);
        }
        let op = op.expect("checked");
        // The lanes are taken while their operands are built (so that no operand packs
        // them again), and the pack is pushed after its operands' packs.
        for (k, lane) in lanes.iter().enumerate() {
            if let Some((x, neg)) = lane {
                self.packing.of[x.index()] = Some((BUILDING, k, *neg));
            }
        }
        // Each lane's two operands, in the order that matches lane 0's best (sums and
        // products commute), with the lane's sign: `±(a + b) = (±a) + (±b)`, `a − b = a +
        // (−b)`, `±(a·b) = (±a)·b`.
        let (a0, b0) = self.operands(first);
        let mut a: Lanes = [None; LANES];
        let mut b: Lanes = [None; LANES];
        for (k, lane) in lanes.iter().enumerate() {
            let Some((x, neg)) = *lane else { continue };
            let (p, q) = self.operands(x);
            let is_mul = matches!(self.g.node(x), Node::Mul(..));
            // The two terms (or factors) with their signs, as written.
            let (tp, tq) = match *self.g.node(x) {
                Node::Mul(..) => ((p, neg), (q, false)),
                Node::Sub(..) => ((p, neg), (q, !neg)),
                _ => ((p, neg), (q, neg)),
            };
            let keep = self.likeness(p, a0) + self.likeness(q, b0);
            let swap = self.likeness(q, a0) + self.likeness(p, b0);
            let (tp, tq) = if swap > keep { (tq, tp) } else { (tp, tq) };
            // A product's sign goes to its first factor (moved below if that is one value).
            let (tp, tq) = if is_mul {
                ((tp.0, neg), (tq.0, false))
            } else {
                (tp, tq)
            };
            a[k] = Some(tp);
            b[k] = Some(tq);
        }
        // Products whose first factors are one value in every lane (a sine, a constant)
        // carry their signs on the second factor, where a pack takes them for free, rather
        // than as a splat times signs.
        let one_value = {
            let firsts: Vec<ExprId> = a.iter().flatten().map(|&(x, _)| x).collect();
            firsts.iter().all(|&x| x == firsts[0])
        };
        if op == Op::Mul && one_value {
            for k in 0..LANES {
                if let (Some((x, neg)), Some((y, _))) = (a[k], b[k]) {
                    a[k] = Some((x, false));
                    b[k] = Some((y, neg));
                }
            }
        }
        let (start, aliases) = (self.packing.packs.len(), self.aliases.len());
        let operands = [self.build(a, depth + 1), self.build(b, depth + 1)];
        let index = self.packing.packs.len();
        for (k, lane) in lanes.iter().enumerate() {
            if let Some((x, neg)) = lane {
                self.packing.of[x.index()] = Some((index, k, *neg));
            }
        }
        for (k, negations) in peeled.iter().enumerate() {
            let Some((_, neg)) = lanes[k] else { continue };
            let mut flip = !neg;
            for &x in negations.iter().rev() {
                self.packing.of[x.index()] = Some((index, k, flip));
                self.aliases.push(x);
                flip = !flip;
            }
        }
        self.packing.packs.push(Pack {
            lanes,
            op,
            operands,
        });
        // A pack (with the packs under it) that saves no more than gathering its lanes
        // costs: its lanes gathered as scalars instead, computed as the scalar code does.
        if saved(&self.packing.packs[start..]) + present.len() as i64 <= 0 {
            for (x, _) in lanes.iter().flatten() {
                self.packing.of[x.index()] = None;
            }
            self.undo(start, aliases);
            return Operand::Gather(tops);
        }
        Operand::Pack(index, tops)
    }

    /// The pack operation of node `id`, if it is one (after negations are peeled).
    fn op_of(&self, id: ExprId) -> Option<Op> {
        match self.g.node(id) {
            Node::Add(..) | Node::Sub(..) => Some(Op::Add),
            Node::Mul(..) => Some(Op::Mul),
            _ => None,
        }
    }

    /// The operands of a sum, difference or product.
    fn operands(&self, id: ExprId) -> (ExprId, ExprId) {
        match *self.g.node(id) {
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) => (a, b),
            _ => unreachable!("packs hold sums, differences and products"),
        }
    }

    /// How alike two nodes are as lanes of one operand (negations peeled): the same node,
    /// lanes of one pack, two constants, the same operation (then more the more alike their
    /// operands are, [`LIKENESS_DEPTH`] levels down), or nothing.
    fn likeness(&self, x: ExprId, y: ExprId) -> u32 {
        self.likeness_to(x, y, LIKENESS_DEPTH)
    }

    fn likeness_to(&self, x: ExprId, y: ExprId, depth: u32) -> u32 {
        let ((x, _), _) = self.peel((x, false));
        let ((y, _), _) = self.peel((y, false));
        let pack = |x: ExprId| self.packing.of[x.index()].map(|(p, _, _)| p);
        if x == y {
            64
        } else if pack(x).is_some() && pack(x) == pack(y) && pack(x) != Some(BUILDING) {
            48
        } else if self.g.as_const(x).is_some() && self.g.as_const(y).is_some() {
            32
        } else if self.op_of(x).is_some() && self.op_of(x) == self.op_of(y) {
            if depth == 0 {
                return 16;
            }
            let ((a, b), (c, d)) = (self.operands(x), self.operands(y));
            let like = |p, q| self.likeness_to(p, q, depth - 1);
            16 + (like(a, c) + like(b, d)).max(like(a, d) + like(b, c)) / 4
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Input;

    /// Three rows turned by three rotations, `(x, y) ← (c x − s y, s x + c y)`, the second
    /// row's products written with their signs flipped, `−(s y − c x)` and `−(−(s x) − c y)`,
    /// as the simplifier does where a constant is negative. The last `(x, y)` of each row.
    fn rows(g: &mut ExprGraph) -> ([Option<ExprId>; LANES], [Option<ExprId>; LANES]) {
        let mut first = [None; LANES];
        let mut second = [None; LANES];
        for k in 0..3usize {
            let mut x = g.input(Input::new(1, k as u16));
            let mut y = g.input(Input::new(2, k as u16));
            for turn in 0..3u16 {
                let (s, c) = (
                    g.input(Input::new(0, 2 * turn)),
                    g.input(Input::new(0, 2 * turn + 1)),
                );
                let (cx, sy, sx, cy) = (g.mul(c, x), g.mul(s, y), g.mul(s, x), g.mul(c, y));
                (x, y) = if k == 1 {
                    let a = g.sub(sy, cx);
                    let nsx = g.neg(sx);
                    let b = g.sub(nsx, cy);
                    (g.neg(a), g.neg(b))
                } else {
                    (g.sub(cx, sy), g.add(sx, cy))
                };
            }
            first[k] = Some(x);
            second[k] = Some(y);
        }
        (first, second)
    }

    #[test]
    fn rows_turned_alike_are_packed_whatever_their_signs() {
        let mut g = ExprGraph::new();
        let (first, second) = rows(&mut g);
        let roots: Vec<ExprId> = first.iter().chain(&second).flatten().copied().collect();
        let live = g.live(&roots);
        let packing = find(&g, &live, &[first, second]).expect("packs");
        // The first seed's tree holds the second's but its last sum (whose three packs
        // save fewer than `MIN_SAVED` instructions on their own).
        for root in first.iter().flatten() {
            let (_, _, neg) = packing.of[root.index()].expect("the outputs are packed");
            assert!(!neg, "a seed's lanes are its nodes");
        }
        // Every lane of a pack is ± its node's value, as the node's place says, and the
        // packs' operations on their operands' lanes give those values.
        let value = |x: Input| f64::from(x.group) * 0.7 + f64::from(x.index) * 0.3 + 0.1;
        let values = g.eval_all(&value);
        let lane = |o: &Operand, k: usize, vectors: &[[f64; LANES]]| -> f64 {
            let signed = |(x, neg): (ExprId, bool)| {
                if neg {
                    -values[x.index()]
                } else {
                    values[x.index()]
                }
            };
            match o {
                Operand::Pack(q, _) => vectors[*q][k],
                Operand::Permute(q, map, _) => {
                    map[k].map_or(
                        0.0,
                        |(j, neg)| {
                            if neg {
                                -vectors[*q][j]
                            } else {
                                vectors[*q][j]
                            }
                        },
                    )
                }
                Operand::Splat(x, signs) => signs[k] * values[x.index()],
                Operand::Consts(c) => c[k],
                Operand::Gather(lanes) => lanes[k].map_or(0.0, signed),
            }
        };
        let mut vectors: Vec<[f64; LANES]> = Vec::new();
        for (p, pack) in packing.packs.iter().enumerate() {
            let mut v = [0.0; LANES];
            for (k, l) in pack.lanes.iter().enumerate() {
                let Some((x, neg)) = *l else { continue };
                let (a, b) = (
                    lane(&pack.operands[0], k, &vectors),
                    lane(&pack.operands[1], k, &vectors),
                );
                v[k] = match pack.op {
                    Op::Add => a + b,
                    Op::Mul => a * b,
                };
                let expected = if neg {
                    -values[x.index()]
                } else {
                    values[x.index()]
                };
                assert!(
                    (v[k] - expected).abs() <= 1e-12 * expected.abs().max(1.0),
                    "pack {p} lane {k}"
                );
                assert_eq!(packing.of[x.index()], Some((p, k, neg)));
            }
            vectors.push(v);
        }
        // Three turns of three rows: the second row's negations peeled into signs, never
        // gathered.
        assert!(packing.packs.len() >= 12, "{}", packing.packs.len());
    }

    #[test]
    fn alike_legs_are_seeded_together_and_packed() {
        // Four legs on one base: each joint's torque the same operations on the leg's own
        // angle, rate and constants, one leg's signs flipped; the base's rate read by all.
        let mut g = ExprGraph::new();
        let base = g.input(Input::new(1, 0));
        let mut torques = Vec::new();
        for leg in 0..4u16 {
            let (q, qd) = (g.input(Input::new(0, leg)), g.input(Input::new(1, 1 + leg)));
            let (s, c) = (g.sin(q), g.cos(q));
            let k = f64::from(leg) + 1.25;
            let mut w = g.add(base, qd);
            let (kc, kc2) = (g.constant(k), g.constant(2.0 * k));
            let (cs, cc) = (g.mul(kc, s), g.mul(kc2, c));
            for turn in 0..4 {
                let a = g.mul(cs, w);
                let b = g.mul(cc, w);
                let ab = if leg == 2 { g.sub(b, a) } else { g.add(a, b) };
                let kt = g.constant(k + f64::from(turn));
                let abk = g.mul(kt, ab);
                w = g.add(abk, w);
            }
            let t = g.mul(w, qd);
            let t = if leg == 2 { g.neg(t) } else { t };
            torques.push(g.add(t, base));
        }
        // An output of another shape.
        let other = g.mul(base, base);
        let outputs: Vec<ExprId> = torques.iter().copied().chain([other]).collect();
        let live = g.live(&outputs);
        let seeds = alike_seeds(&g, &live, &outputs, MIN_ALIKE_LANES);
        assert_eq!(seeds, vec![[0, 1, 2, 3].map(|k| Some(torques[k]))]);
        let packing = find(&g, &live, &seeds).expect("packs");
        for t in &torques {
            assert!(
                packing.of[t.index()].is_some(),
                "every leg's torque is packed"
            );
        }
        // The base's rate is one value in every lane, never packed.
        assert!(packing.of[base.index()].is_none());
    }

    /// Two mirrored legs on one base: each leg's torque `turns` steps of the same operations
    /// on the leg's own angle, rate and constants, the second leg's signs flipped.
    fn two_legs(g: &mut ExprGraph, turns: u16) -> [ExprId; 2] {
        let base = g.input(Input::new(1, 0));
        [0u16, 1].map(|leg| {
            let (q, qd) = (g.input(Input::new(0, leg)), g.input(Input::new(1, 1 + leg)));
            let (s, c) = (g.sin(q), g.cos(q));
            let sign = if leg == 0 { 1.0 } else { -1.0 };
            let mut w = g.add(base, qd);
            for turn in 0..turns {
                let k = g.constant(sign * (0.5 + f64::from(turn)));
                let (a, b) = (g.mul(s, w), g.mul(c, w));
                let ab = if leg == 0 { g.add(a, b) } else { g.sub(b, a) };
                let abk = g.mul(k, ab);
                w = g.add(abk, w);
            }
            g.mul(w, qd)
        })
    }

    #[test]
    fn two_alike_legs_are_packed_when_they_save_a_limbs_worth() {
        // Deep enough, a pair of legs is one seed of two lanes, packed down to the legs' own
        // inputs (each gathered pair one instruction).
        let mut g = ExprGraph::new();
        let legs = two_legs(&mut g, 12);
        let live = g.live(&legs);
        let seeds = alike_seeds(&g, &live, &legs, MIN_ALIKE_LANES);
        assert_eq!(seeds, vec![[Some(legs[0]), Some(legs[1]), None, None]]);
        let packing = find(&g, &live, &seeds).expect("packs");
        assert!(saved(&packing.packs) >= MIN_SAVED_TWO_LANES);
        assert!(legs.iter().all(|l| packing.of[l.index()].is_some()));
        // Two turns save fewer than `MIN_SAVED_TWO_LANES`: the seed is dropped.
        let mut g = ExprGraph::new();
        let legs = two_legs(&mut g, 2);
        let live = g.live(&legs);
        let seeds = alike_seeds(&g, &live, &legs, MIN_ALIKE_LANES);
        assert_eq!(seeds.len(), 1);
        assert!(find(&g, &live, &seeds).is_none());
        // Every dynamics function, the mass matrix too (three lanes until the thirty-seventh
        // session), asks for seeds of two: this one is found.
        let crate::emit::function::Packs::Alike(min) = crate::emit::function::ALIKE_PACKS else {
            panic!("the dynamics pack alike outputs")
        };
        assert_eq!(min, MIN_ALIKE_LANES);
        assert_eq!(alike_seeds(&g, &live, &legs, min).len(), 1);
    }

    #[test]
    fn a_lane_that_reads_another_lane_is_not_packed() {
        // r0 = a·x, r1 = a·r0: lane 1 reads lane 0, so the two cannot be one vector.
        let mut g = ExprGraph::new();
        let (a, x) = (g.input(Input::new(0, 0)), g.input(Input::new(0, 1)));
        let r0 = g.mul(a, x);
        let r1 = g.mul(a, r0);
        let y = g.input(Input::new(0, 2));
        let r2 = g.mul(a, y);
        let live = g.live(&[r0, r1, r2]);
        let seed = [Some(r0), Some(r1), Some(r2), None];
        assert!(find(&g, &live, &[seed]).is_none());
    }
}
