//! One generated function: the schedule of `let` bindings over the live part of the graph
//! and the tokens of its body.
//!
//! A node gets a `let` when the function uses it more than once, or when it is a division
//! or square root; every other node is written inline into its single user. Inputs are
//! unpacked by destructuring nalgebra's array storage (no indexing, so no panic path);
//! `sin q_i` and `cos q_i` of all joints come from one call of the vectorised `joint_sin_cos`
//! helper ([`super::trig`]), other arguments' from one call each; outputs are packed into
//! `ArrayStorage` column by column. Bindings are numbered in graph order, which is
//! deterministic, so the output is byte-identical across runs.

use super::literal::float_tokens;
use crate::expand::parameters::PARAM;
use crate::expr::{reassociate, ExprGraph, ExprId, Input, Node};
use crate::options::Scalar;
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};

/// The deepest expression written inline: deeper ones get a `let` binding.
const MAX_INLINE_DEPTH: u32 = 24;

/// An argument of a generated function: a vector input named `name` of group `group`.
#[derive(Clone, Debug)]
pub struct Arg {
    /// The Rust parameter name (`q`, `qd`, `qdd`, `tau`).
    pub name: &'static str,
    /// The graph input group it fills.
    pub group: u8,
    /// The vector's length (nq for `q`, nv for the others).
    pub len: usize,
}

/// What a generated function returns, from its outputs in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// One `rows × cols` matrix (a vector for one column), outputs row-major.
    Matrix,
    /// One `rows × cols` matrix, outputs row-major, written entry by entry into a zeroed
    /// matrix (in code the CPU dispatch copies, into the struct's uninitialised union, its
    /// structural zeros written among the stores: [`FunctionBody::written`]) as soon as each
    /// entry is computed, its statements scheduled from the last
    /// entry back (see [`FunctionBody::stores`]), where its literal would keep more than
    /// [`STORED_MIN_LIVE`] values live. As [`Output::Matrix`] otherwise, in a batch body and
    /// in a body split into parts. The mass matrix, `Ṁ` and `M⁻¹`.
    StoredMatrix,
    /// One symmetric `rows × rows` matrix written into the caller's `m: &mut` matrix: its lower
    /// triangle (the diagonal and below), entry by entry as each is computed, as
    /// [`Output::StoredMatrix`] is (scheduled from the last entry back), and nothing else:
    /// no zeroing, no mirror half, no entry that is +0.0 for every input (the tree's
    /// structural zeros). Returns `()`. Where the body is split into parts, which cannot
    /// write into `m`, the same entries are written at the end. `mass_matrix_lower_into`.
    StoredLower,
    /// One scalar (the first output).
    Scalar,
    /// One pose: a rotation by rows (9 outputs), then a translation (3), returned as
    /// `Isometry3` through the `isometry` helper of the impl ([`isometry_helper`]).
    Pose,
    /// An array of this many matrices, each `rows × cols` row-major, one after the other.
    Matrices(usize),
    /// An array of this many poses.
    Poses(usize),
    /// A tuple of `count` (at most 4) matrices of the given `(rows, cols)`, each row-major,
    /// one after the other (`rows`/`cols` of the body are ignored).
    Tuple {
        /// The shapes.
        shapes: [(usize, usize); 4],
        /// How many of `shapes` are used.
        count: usize,
        /// The first matrix is written entry by entry into a zeroed tuple (or the union), as
        /// an [`Output::StoredMatrix`] is (under the same bound), and the others assigned
        /// after it.
        stored_first: bool,
    },
    /// `Option` of one `rows × cols` matrix: the first `2·guards` outputs are pairs
    /// `(d, a)`, and the result is `None` unless every `d > √ε · a` (ε of the scalar type;
    /// false for NaN); the matrix follows them.
    Checked {
        /// The number of `(d, a)` pairs.
        guards: usize,
    },
}

/// `√ε` of the scalar type, the relative pivot below which [`Output::Checked`] gives `None`.
pub fn sqrt_epsilon(scalar: Scalar) -> TokenStream {
    match scalar {
        Scalar::F64 => float_tokens(f64::EPSILON.sqrt(), scalar),
        Scalar::F32 => float_tokens(f64::from(f32::EPSILON.sqrt()), scalar),
    }
}

/// Everything the body writer needs.
pub struct FunctionBody<'a> {
    /// The graph.
    pub graph: &'a ExprGraph,
    /// The arguments.
    pub args: &'a [Arg],
    /// The outputs, row-major (`rows × cols`).
    pub outputs: &'a [ExprId],
    /// Output rows.
    pub rows: usize,
    /// Output columns (1 for a vector).
    pub cols: usize,
    /// How the outputs are returned.
    pub output: Output,
    /// The scalar type.
    pub scalar: Scalar,
    /// `no_std`: square roots through `libm`.
    pub no_std: bool,
    /// The nalgebra path tokens.
    pub nalgebra: &'a TokenStream,
    /// The generated struct, which the pieces of a split body call helpers through (a
    /// nested `fn` cannot name `Self`); `None`: never split (see [`chunked`]).
    pub self_ty: Option<&'a Ident>,
    /// `Some(runtime crate path)`: the body of a `*_batch` function (see
    /// [`crate::emit::batch`]): every value a `Lanes<scalar, B>` of the `B` states, the
    /// arguments arrays of `B` vectors and the result (an [`Output::Matrix`]) an array of `B`
    /// matrices; no fused multiply-adds (lanes have none) and never split.
    pub lanes: Option<&'a TokenStream>,
    /// When each node of `graph` is ready ([`crate::expr::reassociate::ready_times`]): which
    /// of two products an addition fuses. Empty until [`Self::tokens`] fills it.
    pub ready: &'a [u32],
    /// Which nodes to compute as packs of 4-lane vector operations where they are alike
    /// ([`super::pack`], [`Packs`]). With `std` (`f64` or `f32`), in a single-state body
    /// that is not split into parts.
    pub pack: Packs,
    /// Long-lived values parked in memory of the body's own ([`super::park`]): the functions
    /// of [`super::park::PARKED`], in code the CPU dispatch copies (`std`), which allows
    /// `unsafe` code; only where the body has [`super::park::MIN_STATEMENTS`] statements or
    /// more and is not split into parts.
    pub park: bool,
    /// The order of the body's statements: [`super::schedule::Order::Level`] for the functions
    /// of [`super::schedule::LEVEL_ORDER`].
    pub order: super::schedule::Order,
    /// The union a stored result is written into without zeroing ([`written_union_item`]): the
    /// struct's name with `Written` (`G1Written`), in code the CPU dispatch copies (`std`),
    /// which allows `unsafe` code and returns the union from its copies
    /// ([`super::dispatch`]); `None`: a zeroed result, as everywhere else.
    pub written: Option<&'a Ident>,
    /// In a batch body (`lanes`), the fused multiply-adds of the single-state body's packs,
    /// which the batch makes alike ([`Plan`]). Filled by [`Self::tokens`].
    pub plan: Option<&'a Plan>,
    /// With [`Packs::Columns`]: the entries (row-major, `6 × cols`) of a Jacobian that the
    /// body reads, not among its outputs, whose columns' rows seed packs before the
    /// outputs' own: a `J̇` body's `J` ([`JACOBIAN_DOT_PACK_COLUMNS`]). Empty otherwise.
    pub reads_jacobian: &'a [ExprId],
}

/// The most columns a Jacobian may have for its `J̇` bodies to compute its columns' rows in
/// packs ([`FunctionBody::reads_jacobian`]): rand7's `J̇_s` ran 4–8 % faster with them and its
/// `J̇_b` 2–4 % (`f32`: 9–10 % and 13–15 %); G1's `J̇_b` (29 columns, 10 on the path) 2–3 %
/// faster but its `J̇_s` 5–7 % slower, with more spills and shuffles (`docs/performance.md`,
/// forty-fourth session). The UR5's and the Panda's code is the same either way (no seed
/// saves enough).
pub const JACOBIAN_DOT_PACK_COLUMNS: usize = 8;

/// Where a body's packs ([`super::pack`]) start from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packs {
    /// None: every node a scalar.
    None,
    /// The rows of a pose's outputs ([`Output::Pose`], [`Output::Poses`]): each rotation
    /// column's three entries, and the translation (the kinematics).
    Rows,
    /// The rows of a Jacobian's columns (`6 × n`, [`Output::Matrix`] or
    /// [`Output::Matrices`]): each column's `ω` and its `v`, three entries each, which turn
    /// by the same sines and cosines as a pose's rows do (rand7's `J_s` 12–16 % faster, its
    /// `J_b` 8–14 %: `docs/performance.md`, forty-first session). The time derivatives are
    /// left scalar: given these seeds, none of rand7's or the Panda's was kept.
    Columns,
    /// Outputs of one shape ([`super::pack::alike_seeds`]), at least this many to a seed: the
    /// same joint of a tree's alike limbs (the dynamics; see [`ALIKE_PACKS`]).
    Alike(usize),
}

/// The packs of every dynamics function (its single-state body and its batch body's [`Plan`]
/// alike): outputs of one shape, two lanes or more ([`super::pack::MIN_ALIKE_LANES`]). The
/// mass matrix kept three lanes at least from the twenty-eighth session to the thirty-seventh
/// (`docs/performance.md`), as with two it had run 2–9 % slower. Measured again once the
/// copies' frames were aligned (`dispatch::aligns_frame`), two lanes made G1's mass matrix
/// 3–14 % faster and TALOS' mass matrix with the bias 9–19 %.
pub(crate) const ALIKE_PACKS: Packs = Packs::Alike(super::pack::MIN_ALIKE_LANES);

/// What a batch body does as the single-state body's packs do, so that each state's results
/// are the same bits as a single call's: a packed sum fuses the product its pack fuses (or
/// none), and a packed product is never fused by a scalar sum nor written `(c·u)·w` (the
/// pack computes `c·(u·w)`; a scalar reads it from its lane). The pack's lanes are the scalar
/// code's operations otherwise (signs aside, which round alike).
pub struct Plan {
    /// Per node: in a pack.
    packed: Vec<bool>,
    /// Per packed sum or difference: the product it fuses, if any.
    fuses: Vec<Option<ExprId>>,
}

/// What the emitter knows of a body's packs ([`super::pack`]).
struct Packed {
    packing: super::pack::Packing,
    /// Per pack: written inline into its user (a product that a multiply-add fuses).
    inline: Vec<bool>,
    /// Per pack: the largest node id among its nodes, where the body writes it.
    last: Vec<usize>,
    /// Per pack: its nodes that something other than the packs reads as a scalar.
    scalars: Vec<Vec<ExprId>>,
    /// The number of nodes of the graph: the vector of pack `k` is node `nodes + k` of the
    /// body's bookkeeping (bindings, last uses).
    nodes: usize,
}

/// The most `let` statements in one block: longer bodies are split into blocks (see
/// [`chunked`]).
const MAX_BLOCK_LETS: usize = 512;

/// Bodies of more `let` statements than this are split into `#[inline(never)]` functions
/// of [`PART_LETS`] statements each (see [`chunked`]). Below it (every function of a
/// 7-joint arm) the body stays one function, which the optimiser sees whole.
pub(crate) const MAX_UNSPLIT_LETS: usize = 4096;

/// An [`Output::StoredMatrix`] (or the first matrix of an [`Output::Tuple`] with
/// `stored_first`) is stored entry by entry only when, returned as one literal, more values
/// than this would be live at once: twice the registers of an AVX-512 copy.
/// Measured (values live at most as a literal; old → new time, two runs each, see
/// [`FunctionBody::stores`]). The mass matrix: G1 432, −8 %; Solo-12 130, −9 % and −14 %;
/// TALOS' upper body 186, −0.2 % and −1.5 %; the Panda 50, −5 % and −8 %; Baxter's left arm
/// 47, +7 % and −1 %; rand7 43, ±1 %; the xArm7 41, +5 % and +14 %; the UR5 22, −4 to +9 %.
/// The bound keeps every arm measured, the Panda's gain with the others' losses, as a
/// literal. Above it (counted with the emitter's own schedule, 2026-11-27): `M⁻¹` the Panda
/// 69, −4 and −5 %; rand7 66, −3 and −4 %; Solo-12 355, −8 to −10 %; TALOS 386, −10 %. `Ṁ`
/// the Panda 113 and rand7 107, ±1 %; Solo-12 222, −5 to −18 %; TALOS 345, −12 to −15 %;
/// G1 589, −6 %. `(M, c + g)`: the Panda 110, −1 %; rand7 113, +1 to +3.5 % (six runs);
/// Solo-12 274, ±1 %; TALOS 364, −10 %; G1 646, −5 to −6 %.
const STORED_MIN_LIVE: usize = 64;

/// The `let` statements of one part of a split body (see [`chunked`]). Measured on a
/// humanoid's (G1, floating base) derivatives, three functions of 12k–20k statements: one
/// function each, release build 104 s; parts of 2048, 45 s; parts of 512, 31 s. The
/// parts cost 15–19 % more instructions (values crossing a boundary go through memory),
/// whatever their size; wall-clock times stayed within the ±15 % of build-to-build noise.
const PART_LETS: usize = 512;

/// A stored result is written into [`FunctionBody::written`]'s union (not zeroed first) only
/// when it has at least this many entries. Measured (old and new code `include!`d in one
/// binary, interleaved; 2026-12-07): the union gained on every result of 18 entries or more
/// (Solo-12's bias −7.4 %, the 7-joint arms' `M⁻¹` −3.5 and −5.7 %, G1's mass matrix −6.5 %),
/// and lost 1–2 % on the arms' bias, 7 entries (the Panda +1.8, +1.3 %; rand7 +0.8, +1.9 %;
/// AMD Zen 4), whose zeroing is one or two vector stores. Zeroed again, on a Zen 3: rand7's
/// −1 to −2 %, the Panda's ±2 %.
const WRITTEN_MIN_ENTRIES: usize = 16;

/// The union [`FunctionBody::written`] names for the struct `name`: `{name}Written`.
pub(super) fn written_union(name: &Ident) -> Ident {
    format_ident!("{}Written", name)
}

/// The item of [`written_union`] `w`, which the generated file holds beside the struct when
/// a function writes into it:
///
/// ```text
/// union G1Written<T: Copy> { value: T, uninit: () }
/// ```
///
/// A stored result ([`Output::StoredMatrix`], the first matrix of an [`Output::Tuple`]) is
/// otherwise a zeroed matrix that its stores overwrite. Returned by value, it is the caller's
/// memory (the copies return it through the caller's pointer), and the zeroing is a `memset`
/// of all of it before the body starts: 9,800 bytes for a humanoid's mass matrix (G1, 35
/// coordinates), 88 ns alone on this machine (AMD Zen 4), of 514–536 ns. In the union, the
/// result starts uninitialised: the stores write its entries through `m.value` (a place, as
/// `m.data.0[c][r]` was, so that the optimiser still writes into the caller's memory: through
/// a raw pointer of a `MaybeUninit`, the result was kept in registers and copied at the end,
/// 695 ns), the structural zeros are written among them ([`with_zero_writes`]), and the
/// wrapper reads `value` from what its copy returns. Sound: a straight-line body writes every
/// entry (each stored one once, each other one by a zero write) before the read, and other
/// parts of a tuple are assigned whole. Only in code the CPU dispatch copies ([`super::dispatch`]
/// returns the union from the copies), whose bodies allow `unsafe` code; `no_std` and
/// `--no-cpu-dispatch` code zeroes as before. Measured (G1, floating base, the AVX-512 copy,
/// old and new code in one binary, medians of 11 interleaved rounds, 2026-12-07): see
/// `docs/performance.md`.
pub(super) fn written_union_item(w: &Ident) -> TokenStream {
    let doc = " A result the dispatched copies write entry by entry, every entry once, before \
               it is read: returned through the caller's memory without zeroing it first.";
    quote! {
        #[doc = #doc]
        #[allow(dead_code)]
        union #w<T: Copy> {
            value: T,
            uninit: (),
        }
    }
}

/// A `let` statement of a body, the nodes it names and the named nodes it reads.
pub(super) struct Statement {
    pub(super) defined: Vec<(Ident, ExprId)>,
    pub(super) tokens: TokenStream,
    pub(super) reads: Vec<ExprId>,
}

/// `body` in the demand-driven order of [`super::schedule`], with `last_use` (the index of
/// the last statement reading each named node; `usize::MAX` for the outputs') renumbered to
/// it; `first` are statements of `body` scheduled first, in that order (the stores of an
/// [`Output::StoredMatrix`]), then `output_reads`, the named nodes the outputs read, in
/// output order; then each store moved up to where its value is ready ([`stores_early`]).
fn reorder(
    body: Vec<Statement>,
    first: &[usize],
    output_reads: &[ExprId],
    last_use: &mut [usize],
    how: super::schedule::Order,
) -> Vec<Statement> {
    let order = stores_early(
        &body,
        schedule(&body, first, output_reads, last_use.len(), how),
        first,
        last_use.len(),
    );
    let mut slots: Vec<Option<Statement>> = body.into_iter().map(Some).collect();
    let body: Vec<Statement> = order
        .iter()
        .map(|&k| slots[k].take().expect("a permutation"))
        .collect();
    renumber_last_uses(&body, last_use);
    body
}

/// `body` with the `zeros` ([`FunctionBody::zero_writes`]) spread evenly among its stores
/// (the statements that define nothing), in order: zero `j` of `z` follows store `i` of `n`
/// (counted from 1) for the smallest `i` with `j · n < i · z`.
///
/// Why spread: a store waits in the core's store queue until the cache takes it, and the
/// cache takes about 32 bytes a cycle here (AMD Zen 4; 9,800 bytes zeroed by `memset` took
/// 88 ns, the zero entries of G1's mass matrix alone 72 ns, in a loop of their own): written
/// together, at the top or at the end, the zeros stall the body behind them (G1's mass
/// matrix by value 507–523 ns, against 456–470 spread and 470–536 zeroed by `memset`).
fn with_zero_writes(body: Vec<Statement>, zeros: Vec<Statement>) -> Vec<Statement> {
    let (n, z) = (
        body.iter().filter(|s| s.defined.is_empty()).count(),
        zeros.len(),
    );
    let mut zeros = zeros.into_iter().enumerate().peekable();
    let mut out = Vec::with_capacity(body.len() + z);
    let mut seen = 0;
    for s in body {
        let store = s.defined.is_empty();
        out.push(s);
        if store {
            seen += 1;
            while let Some((_, zero)) = zeros.next_if(|&(j, _)| j * n < seen * z) {
                out.push(zero);
            }
        }
    }
    out.extend(zeros.map(|(_, zero)| zero));
    out
}

/// `last_use` set to the index in `body` of the last statement reading each node, but for
/// the outputs' (`usize::MAX`), which stay.
pub(super) fn renumber_last_uses(body: &[Statement], last_use: &mut [usize]) {
    for (at, s) in body.iter().enumerate() {
        for &id in &s.reads {
            let l = &mut last_use[id.index()];
            if *l != usize::MAX {
                *l = at;
            }
        }
    }
}

/// `order` with each of the `stores` (statements that define nothing, which nothing reads)
/// moved up to just after the last statement it reads, keeping their order among stores
/// that land on the same statement. The demand order computes a store's value with the
/// cone of an earlier store where the two share it (a two-lane pack of mirrored limbs
/// yields both limbs' entries at once), and the value then waited for its own store: in
/// G1's mass matrix the lanes of 60-odd packs lived across half the body. Stored where it
/// is ready, no value lives past its last use by another statement. Measured (AVX-512
/// copies, old and new generated code in one binary, medians of 11–15 interleaved rounds,
/// three to five processes, 2026-12-04): spill stores of the mass matrix G1 533 → 445, TALOS
/// 324 → 299, Solo-12 59 → 45 (G1's copy 34,263 → 32,332 bytes); time TALOS' `(M, c + g)`
/// −8 to −10 % and `M⁻¹` −11 to −15 %, Solo-12's `M⁻¹` −1.5 to −9 %, the Panda's and rand7's
/// `M⁻¹` −0.3 to −2 %, G1's mass matrix and `(M, c + g)` within the spread between
/// processes (−9 to +4 % and −7 to +13 %). Values are the same bits: only the order moves.
fn stores_early(
    body: &[Statement],
    order: Vec<usize>,
    stores: &[usize],
    nodes: usize,
) -> Vec<usize> {
    if stores.is_empty() {
        return order;
    }
    let mut is_store = vec![false; body.len()];
    for &k in stores {
        is_store[k] = true;
    }
    let defined_by = defined_by(body, nodes);
    let mut pos = vec![0; body.len()];
    for (p, &k) in order.iter().enumerate() {
        pos[k] = p;
    }
    // Per position of the order, the stores that follow it; `leading`, those that read
    // nothing (a constant entry).
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); order.len()];
    let mut leading = Vec::new();
    for &k in &order {
        if !is_store[k] {
            continue;
        }
        let anchor = body[k]
            .reads
            .iter()
            .map(|id| defined_by[id.index()])
            .filter(|&d| d != usize::MAX)
            .map(|d| pos[d])
            .max();
        match anchor {
            Some(p) => after[p].push(k),
            None => leading.push(k),
        }
    }
    let mut early = leading;
    for (p, &k) in order.iter().enumerate() {
        if !is_store[k] {
            early.push(k);
        }
        early.extend_from_slice(&after[p]);
    }
    early
}

/// Per node of a graph of `nodes` nodes: the index of the statement of `body` that defines
/// it (`usize::MAX` for none).
fn defined_by(body: &[Statement], nodes: usize) -> Vec<usize> {
    let mut defined_by = vec![usize::MAX; nodes];
    for (k, s) in body.iter().enumerate() {
        for &(_, id) in &s.defined {
            defined_by[id.index()] = k;
        }
    }
    defined_by
}

/// The order of [`reorder`] (statement indices into `body`) for a graph of `nodes` nodes:
/// `how`, but [`super::schedule::demand_order`] where statements must come `first`.
fn schedule(
    body: &[Statement],
    first: &[usize],
    output_reads: &[ExprId],
    nodes: usize,
    how: super::schedule::Order,
) -> Vec<usize> {
    use super::schedule::{demand_order, level_order, Deps, Order};
    let defined_by = defined_by(body, nodes);
    let statement = |id: &ExprId| Some(defined_by[id.index()]).filter(|&k| k != usize::MAX);
    let deps: Vec<Deps> = body
        .iter()
        .map(|s| Deps {
            reads: s.reads.iter().filter_map(statement).collect(),
        })
        .collect();
    let roots: Vec<usize> = first
        .iter()
        .copied()
        .chain(output_reads.iter().filter_map(statement))
        .collect();
    match how {
        Order::Level if first.is_empty() => level_order(&deps),
        _ => demand_order(&deps, &roots),
    }
}

/// `value` with the temporaries (`t0`, `t1`, …, numbered in creation order) renamed in the
/// order the statements of `body` now define them, as are `body` and `bind`: generated code
/// reads `t0`, `t1`, … from the top.
fn renumber(body: &mut [Statement], bind: &mut [Binding], value: TokenStream) -> TokenStream {
    use std::collections::HashMap;
    let is_temporary = |name: &str| {
        name.strip_prefix('t')
            .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
    };
    let mut names: HashMap<String, Ident> = HashMap::new();
    for s in body.iter() {
        for (name, _) in &s.defined {
            let name = name.to_string();
            if is_temporary(&name) {
                let new = format_ident!("t{}", names.len());
                names.insert(name, new);
            }
        }
    }
    if names.iter().all(|(old, new)| *new == old) {
        return value;
    }
    for s in body.iter_mut() {
        s.tokens = rename(std::mem::take(&mut s.tokens), &names);
        for (name, _) in &mut s.defined {
            if let Some(new) = names.get(&name.to_string()) {
                *name = new.clone();
            }
        }
    }
    for b in bind.iter_mut() {
        if let Binding::Named(name) = b {
            if let Some(new) = names.get(&name.to_string()) {
                *name = new.clone();
            }
        }
    }
    rename(value, &names)
}

/// `tokens` with every identifier that `names` maps replaced.
fn rename(tokens: TokenStream, names: &std::collections::HashMap<String, Ident>) -> TokenStream {
    map_idents(tokens, &|i| names.get(&i.to_string()).cloned())
}

/// `tokens` with every identifier for which `f` gives a replacement replaced, inside groups
/// too (their spans kept).
pub(super) fn map_idents(tokens: TokenStream, f: &impl Fn(&Ident) -> Option<Ident>) -> TokenStream {
    use proc_macro2::{Group, TokenTree};
    tokens
        .into_iter()
        .map(|tt| match tt {
            TokenTree::Ident(i) => TokenTree::Ident(f(&i).unwrap_or(i)),
            TokenTree::Group(g) => {
                let mut new = Group::new(g.delimiter(), map_idents(g.stream(), f));
                new.set_span(g.span());
                TokenTree::Group(new)
            }
            other => other,
        })
        .collect()
}

/// The statements, in blocks of at most [`MAX_BLOCK_LETS`]: `let (x, y, …) = { …; (x, y,
/// …) };` with the names that later statements or the outputs read. Every `let` opens a
/// lexical scope nested in the previous one, and the debug info of a function with tens of
/// thousands of nested scopes overflows LLVM's stack (a crash in debug builds of large
/// trees' Coriolis matrices); blocks keep the nesting below a few thousand. Values and
/// their order are unchanged, so the optimised code is the same.
///
/// Bodies of more than [`MAX_UNSPLIT_LETS`] statements (a 30-joint chain's mass matrix, a
/// humanoid's derivatives) are split further, into functions of [`PART_LETS`] statements:
/// rustc's time grows faster than linearly in the size of one function (LLVM's passes over
/// one huge block), so each part becomes a nested `#[inline(never)] fn partK([named values
/// it reads]) -> [values later statements read]` called in its place. The values and the
/// order of operations are unchanged (the results are bit-identical); only the part
/// boundaries become calls. Parts call helpers through `self_ty` (`Ur5::mul_add`), since a
/// nested `fn` cannot name `Self`. Parts are `extern "C"`: such a function cannot unwind,
/// so its calls are `nounwind` for the optimiser even from another crate, and the function
/// that calls the parts keeps no unwinding path (which the no-panic test checks). A Rust-ABI
/// part would be opaque there. The parts hold the same kinds of `let` statements as an
/// unsplit body (arithmetic, `mul_add`, `sqrt`, `joint_sin_cos`; no indexing).
fn chunked(
    body: Vec<Statement>,
    last_use: &[usize],
    bind: &[Binding],
    split: Option<(&Ident, Scalar)>,
) -> TokenStream {
    let Some((self_ty, scalar)) = split else {
        return blocks(body, 0, last_use);
    };
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let mut out = TokenStream::new();
    // For each node, 1 + the index of the part that defines it (0: before the body) and 1 +
    // the index of the last part that took it as a parameter.
    let mut defined_in = vec![0u32; bind.len()];
    let mut passed_to = vec![0u32; bind.len()];
    let mut body = body.into_iter().peekable();
    let (mut start, mut k) = (0, 0u32);
    while body.peek().is_some() {
        k += 1;
        let part: Vec<Statement> = body.by_ref().take(PART_LETS).collect();
        let end = start + part.len();
        let mut params = Vec::new();
        for s in &part {
            for &(_, id) in &s.defined {
                defined_in[id.index()] = k;
            }
            for &id in &s.reads {
                let i = id.index();
                if defined_in[i] != k && passed_to[i] != k {
                    passed_to[i] = k;
                    if let Binding::Named(name) = &bind[i] {
                        params.push(name.clone());
                    }
                }
            }
        }
        let exported = exported(&part, end, last_use);
        let stmts = replace_self(blocks(part, start, last_use), self_ty);
        let name = format_ident!("part{}", k - 1);
        let (np, ne) = (
            proc_macro2::Literal::usize_unsuffixed(params.len()),
            proc_macro2::Literal::usize_unsuffixed(exported.len()),
        );
        out.extend(quote! {
            #[inline(never)]
            #[allow(improper_ctypes_definitions)]
            extern "C" fn #name([#(#params),*]: [#t; #np]) -> [#t; #ne] {
                #stmts
                [#(#exported),*]
            }
            let [#(#exported),*] = #name([#(#params),*]);
        });
        start = end;
    }
    out
}

/// The names that `part` (statements `..end` of the body) defines and later statements or
/// the outputs read.
fn exported(part: &[Statement], end: usize, last_use: &[usize]) -> Vec<Ident> {
    part.iter()
        .flat_map(|s| s.defined.iter())
        .filter(|(_, id)| last_use[id.index()] >= end)
        .map(|(name, _)| name.clone())
        .collect()
}

/// `body` (statements `start..` of the whole body) in blocks of at most
/// [`MAX_BLOCK_LETS`] (see [`chunked`]); as it is when it fits in one.
fn blocks(body: Vec<Statement>, start: usize, last_use: &[usize]) -> TokenStream {
    if body.len() <= MAX_BLOCK_LETS {
        return body.into_iter().map(|s| s.tokens).collect();
    }
    let mut out = TokenStream::new();
    let mut start = start;
    let mut body = body.into_iter().peekable();
    while body.peek().is_some() {
        let chunk: Vec<Statement> = body.by_ref().take(MAX_BLOCK_LETS).collect();
        let end = start + chunk.len();
        let exported = exported(&chunk, end, last_use);
        let stmts = chunk.into_iter().map(|s| s.tokens);
        out.extend(quote! {
            let (#(#exported),*) = {
                #(#stmts)*
                (#(#exported),*)
            };
        });
        start = end;
    }
    out
}

/// `tokens` with every `Self` replaced by `self_ty`.
fn replace_self(tokens: TokenStream, self_ty: &Ident) -> TokenStream {
    map_idents(tokens, &|i| (i == "Self").then(|| self_ty.clone()))
}

#[derive(Clone)]
enum Binding {
    /// Written inline where used.
    Inline,
    /// A `let` binding or an input name.
    Named(Ident),
}

impl FunctionBody<'_> {
    /// The body of the function, as a block's statements: its nodes that equal a multiple of
    /// another merged ([`crate::expr::equivalent`]), then its sums re-associated for
    /// instruction-level parallelism ([`crate::expr::reassociate`]) unless the sums as built
    /// pack better: the re-association follows each product's uses, and where a tree's alike
    /// limbs share a product on one side only (TALOS' arms are copies, not mirror images, so
    /// their constants coincide differently) it associates their sums differently and they
    /// no longer pack ([`super::pack`]); packed, they run 16–26 % faster than re-associated
    /// (`docs/performance.md`, thirty-sixth session).
    pub fn tokens(&self) -> TokenStream {
        let rewrite = |reads_jacobian: &[ExprId]| {
            let (graph, outputs, reads_jacobian) = self.rewritten(reads_jacobian);
            let ready = reassociate::ready_times(&graph);
            (graph, outputs, ready, reads_jacobian)
        };
        let mut rewritten = rewrite(self.reads_jacobian);
        // The Jacobian's entries as roots change how sums associate: kept only with packs.
        let (graph, outputs, ready, reads_jacobian) = &rewritten;
        if !reads_jacobian.is_empty()
            && self
                .on(graph, outputs, ready, reads_jacobian)
                .all_packs()
                .is_none()
        {
            rewritten = rewrite(&[]);
        }
        let (graph, outputs, ready, reads_jacobian) = &rewritten;
        let body = self.on(graph, outputs, ready, reads_jacobian);
        if self.lanes.is_none() {
            return body.tokens_as_given();
        }
        let plan = body.all_packs().map(|p| body.plan(&p));
        FunctionBody {
            plan: plan.as_ref(),
            ..body
        }
        .tokens_as_given()
    }

    /// This body on a rewritten graph ([`Self::rewritten`]): its outputs, the nodes' ready
    /// times and the Jacobian it reads, all in that graph.
    fn on<'b>(
        &'b self,
        graph: &'b ExprGraph,
        outputs: &'b [ExprId],
        ready: &'b [u32],
        reads_jacobian: &'b [ExprId],
    ) -> FunctionBody<'b> {
        FunctionBody {
            graph,
            outputs,
            ready,
            reads_jacobian,
            ..*self
        }
    }

    /// [`Self::packs`] of the nodes live for the outputs.
    fn all_packs(&self) -> Option<Packed> {
        let live = self.graph.live(self.outputs);
        self.packs(&live, &self.graph.use_counts(self.outputs))
    }

    /// The graph and outputs as [`Self::tokens`] writes them, with `reads_jacobian`
    /// ([`Self::reads_jacobian`]) mapped into it: equivalent nodes merged, then sums
    /// re-associated unless they pack better as built. The Jacobian goes through both with the
    /// outputs, as roots (so that its entries stay nodes), and is taken off them after.
    fn rewritten(&self, reads_jacobian: &[ExprId]) -> (ExprGraph, Vec<ExprId>, Vec<ExprId>) {
        let n = self.outputs.len();
        let roots: Vec<ExprId> = self.outputs.iter().chain(reads_jacobian).copied().collect();
        let merged = crate::expr::equivalent::merge_equivalent(self.graph, &roots);
        let (built, built_roots) = match &merged {
            Some((g, roots)) => (g, &roots[..]),
            None => (self.graph, &roots[..]),
        };
        let (mut graph, mut roots) = reassociate::reassociate(built, built_roots);
        if self.packs_better_as_built(built, &built_roots[..n], &graph, &roots[..n]) {
            (graph, roots) = (built.clone(), built_roots.to_vec());
        }
        let reads_jacobian = roots.split_off(n);
        (graph, roots, reads_jacobian)
    }

    /// Whether the packs of `built` (the sums as built) save more instructions than those of
    /// `reassociated` (see [`Self::tokens`]); only dynamics bodies seeded by alike outputs
    /// compare (a pose's rows pack either way).
    fn packs_better_as_built(
        &self,
        built: &ExprGraph,
        built_outputs: &[ExprId],
        reassociated: &ExprGraph,
        reassociated_outputs: &[ExprId],
    ) -> bool {
        if !matches!(self.pack, Packs::Alike(_)) {
            return false;
        }
        let saved = |graph: &ExprGraph, outputs: &[ExprId]| {
            let ready = reassociate::ready_times(graph);
            self.on(graph, outputs, &ready, &[])
                .all_packs()
                .map_or(0, |p| super::pack::saved(&p.packing.packs))
        };
        saved(built, built_outputs) > saved(reassociated, reassociated_outputs)
    }

    /// The [`Plan`] of the packs `p` (see there).
    fn plan(&self, p: &Packed) -> Plan {
        use super::pack::{Op, Operand};
        let n = self.graph.len();
        let mut packed = vec![false; n];
        let mut fuses = vec![None; n];
        for (k, place) in p.packing.of.iter().enumerate() {
            packed[k] = place.is_some();
        }
        for pack in &p.packing.packs {
            if pack.op != Op::Add {
                continue;
            }
            let Some(m) = self.fused_operand(p, pack) else {
                continue;
            };
            let Operand::Pack(q, _) = m else {
                unreachable!("fused operands are packs")
            };
            for (lane, product) in pack.lanes.iter().zip(&p.packing.packs[*q].lanes) {
                if let (Some((x, _)), Some((m, _))) = (lane, product) {
                    fuses[x.index()] = Some(*m);
                }
            }
        }
        Plan { packed, fuses }
    }

    /// The operand of the sum pack `pack` that its multiply-add fuses: of two inline products,
    /// the one whose operands are ready later (as in the scalar code).
    fn fused_operand<'p>(
        &self,
        p: &Packed,
        pack: &'p super::pack::Pack,
    ) -> Option<&'p super::pack::Operand> {
        use super::pack::Operand;
        let fused = |o: &Operand| matches!(o, Operand::Pack(q, _) if p.inline[*q]);
        // When the operands of an inline product pack are ready.
        let ready = |o: &Operand| match o {
            Operand::Pack(q, _) => p.packing.packs[*q]
                .lanes
                .iter()
                .flatten()
                .map(|(x, _)| self.ready(*x))
                .max()
                .unwrap_or(0),
            _ => 0,
        };
        let [a, b] = &pack.operands;
        if !fused(a) && !fused(b) {
            return None;
        }
        let fuse_a = fused(a) && (!fused(b) || ready(a) > ready(b));
        Some(if fuse_a { a } else { b })
    }

    /// [`Self::tokens`] for the graph as it is.
    fn tokens_as_given(&self) -> TokenStream {
        let g = self.graph;
        let live = g.live(self.outputs);
        let uses = g.use_counts(self.outputs);
        let packed = self.packed(&live, &uses);
        let slots = g.len() + packed.as_ref().map_or(0, |p| p.packing.packs.len());
        let mut bind: Vec<Binding> = vec![Binding::Inline; slots];
        let mut stmts = TokenStream::new();

        // Inputs.
        for arg in self.args {
            let names: Vec<TokenStream> = (0..arg.len)
                .map(|i| {
                    let input = Input::new(arg.group, i as u16);
                    match g.find_input(input) {
                        Some(id) if live[id.index()] => {
                            let name = format_ident!("{}{}", arg.name, i);
                            bind[id.index()] = Binding::Named(name.clone());
                            quote!(#name)
                        }
                        _ => quote!(_),
                    }
                })
                .collect();
            let arg_ident = Ident::new(arg.name, Span::call_site());
            stmts.extend(if self.lanes.is_some() {
                let lanes = self.lanes_ty();
                quote! {
                    let [#(#names),*] = #lanes::gather(&#arg_ident.each_ref().map(|v| {
                        let [c] = v.data.0;
                        c
                    }));
                }
            } else {
                quote! { let [[#(#names),*]] = #arg_ident.data.0; }
            });
        }

        // Run-time parameters (`crate::expand::parameters`): from the struct's fields.
        for field in crate::expand::parameters::FIELDS {
            let ids: Vec<Option<ExprId>> = (0..field.len)
                .map(|k| {
                    g.find_input(Input::new(PARAM, field.first + k as u16))
                        .filter(|id| live[id.index()])
                })
                .collect();
            if ids.iter().all(Option::is_none) {
                continue;
            }
            let member = Ident::new(field.name, Span::call_site());
            let mut names = Vec::new();
            for (k, id) in ids.iter().enumerate() {
                names.push(match id {
                    Some(id) => {
                        let name = if field.len == 1 {
                            member.clone()
                        } else {
                            format_ident!("{}{}", field.name, k)
                        };
                        bind[id.index()] = Binding::Named(name.clone());
                        quote!(#name)
                    }
                    None => quote!(_),
                });
            }
            stmts.extend(if field.len == 1 {
                quote! { let #(#names)* = self.#member; }
            } else {
                quote! { let [#(#names),*] = self.#member; }
            });
        }

        // sin/cos pairs: one binding per argument with a live sin or cos.
        let mut trig: Vec<(ExprId, Option<ExprId>, Option<ExprId>)> = Vec::new();
        for (k, node) in g.nodes().iter().enumerate() {
            if !live[k] {
                continue;
            }
            let (arg, is_sin) = match node {
                Node::Sin(a) => (*a, true),
                Node::Cos(a) => (*a, false),
                _ => continue,
            };
            let pos = match trig.iter().position(|t| t.0 == arg) {
                Some(p) => p,
                None => {
                    trig.push((arg, None, None));
                    trig.len() - 1
                }
            };
            if is_sin {
                trig[pos].1 = Some(ExprId(k as u32));
            } else {
                trig[pos].2 = Some(ExprId(k as u32));
            }
        }

        let mut counter = 0usize;
        let mut trig_done = vec![false; trig.len()];
        let mut depth = vec![0u32; g.len()];
        // The `let` statements after the inputs', and for each named node the index of the
        // last statement that reads it (`usize::MAX`: the outputs).
        let mut body: Vec<Statement> = Vec::new();
        let mut last_use = vec![0usize; slots];
        // Packed nodes read as scalars, and the packs' vectors, are named up front: a scalar
        // user may come before the pack's last lane in graph order.
        if let Some(p) = &packed {
            for k in 0..p.packing.packs.len() {
                if !p.inline[k] {
                    bind[p.nodes + k] = Binding::Named(format_ident!("lanes{}", k));
                }
                for x in &p.scalars[k] {
                    bind[x.index()] = Binding::Named(format_ident!("t{}", counter));
                    counter += 1;
                }
            }
        }

        // The sines and cosines of inputs (the joint angles) all at once, first: one call of
        // the vectorised `joint_sin_cos` helper (see `trig`).
        // Arguments of the form `a·q_i + b` (joint offsets folded in, mimic joints) are
        // written inline into the batch; when sines and cosines are their only users, they
        // get no `let` of their own.
        let batch: Vec<usize> = (0..trig.len())
            .filter(|&t| of_one_input(g, trig[t].0, MAX_ANGLE_DEPTH))
            .collect();
        let inline_only = angles_inline(g, &live, &uses, &trig, &batch);
        if !batch.is_empty() {
            let mut args = Vec::new();
            let mut s_pats = Vec::new();
            let mut c_pats = Vec::new();
            let mut defined = Vec::new();
            let mut reads = Vec::new();
            for &t in &batch {
                let (arg, sin, cos) = trig[t];
                let suffix = match g.node(arg) {
                    Node::Input(x) => format!("{}", x.index),
                    _ => format!("_{}", arg.0),
                };
                let (s, c) = (format_ident!("s{}", suffix), format_ident!("c{}", suffix));
                args.push(self.expr(&bind, arg));
                self.note_uses(&bind, arg, 0, &mut last_use, &mut reads);
                s_pats.push(self.trig_pattern(&mut bind, &mut defined, s, sin));
                c_pats.push(self.trig_pattern(&mut bind, &mut defined, c, cos));
                trig_done[t] = true;
            }
            // The helper pads the angles to a whole number of the target's vector registers
            // (`sin_cos_lanes`) and returns that many: the patterns end in `..`.
            if args.len() > 1 {
                s_pats.push(quote!(..));
                c_pats.push(quote!(..));
            }
            let call = self.sin_cos_call(&args);
            body.push(Statement {
                defined,
                tokens: quote! {
                    let ([#(#s_pats),*], [#(#c_pats),*]) = #call;
                },
                reads,
            });
        }
        for k in 0..g.len() {
            if !live[k] {
                continue;
            }
            let id = ExprId(k as u32);
            let node = g.node(id);
            if let Some(p) = &packed {
                if let Some((pack, _, _)) = p.packing.of[k] {
                    if k == p.last[pack] && !p.inline[pack] {
                        let statement =
                            self.pack_statement(p, pack, &bind, body.len(), &mut last_use);
                        body.push(statement);
                    }
                    continue;
                }
            }
            match node {
                Node::Const(_) | Node::Input(_) => continue,
                _ if inline_only[k] => continue,
                Node::Sin(a) | Node::Cos(a) => {
                    let Some(t) = trig.iter().position(|t| t.0 == *a) else {
                        continue;
                    };
                    if trig_done[t] {
                        continue;
                    }
                    trig_done[t] = true;
                    let suffix = match g.node(*a) {
                        Node::Input(x) => format!("{}", x.index),
                        _ => format!("_{}", a.0),
                    };
                    let s = format_ident!("s{}", suffix);
                    let c = format_ident!("c{}", suffix);
                    let x = self.operand(&bind, *a, 4);
                    let mut reads = Vec::new();
                    self.note_uses(&bind, *a, body.len(), &mut last_use, &mut reads);
                    let mut defined = Vec::new();
                    let s_pat = self.trig_pattern(&mut bind, &mut defined, s, trig[t].1);
                    let c_pat = self.trig_pattern(&mut bind, &mut defined, c, trig[t].2);
                    let call = self.sin_cos_call(&[x]);
                    body.push(Statement {
                        defined,
                        tokens: quote! { let ([#s_pat], [#c_pat]) = #call; },
                        reads,
                    });
                }
                _ => {
                    // The depth of the expression written inline here (named operands count
                    // 0): bounded, so that no expression nests deeply enough to exhaust the
                    // compiler's stack (rustc recurses over nested expressions).
                    depth[k] = 1 + node
                        .operands()
                        .map(|o| match bind[o.index()] {
                            Binding::Named(_) => 0,
                            Binding::Inline => depth[o.index()],
                        })
                        .max()
                        .unwrap_or(0);
                    let needs_let = uses[k] > 1
                        || depth[k] > MAX_INLINE_DEPTH
                        || matches!(node, Node::Div(..) | Node::Sqrt(_));
                    if needs_let {
                        let name = format_ident!("t{}", counter);
                        counter += 1;
                        let value = self.op(&bind, ExprId(k as u32));
                        let mut reads = Vec::new();
                        for o in node.operands() {
                            self.note_uses(&bind, o, body.len(), &mut last_use, &mut reads);
                        }
                        body.push(Statement {
                            defined: vec![(name.clone(), id)],
                            tokens: quote! { let #name = #value; },
                            reads,
                        });
                        bind[k] = Binding::Named(name);
                    }
                }
            }
        }

        // Outputs.
        let stores = self.stores(&bind, &mut body, &mut last_use);
        let value = match self.output {
            Output::StoredMatrix if !stores.is_empty() => {
                let ty = self.matrix_type();
                match self.written_union() {
                    Some(w) => {
                        stmts.extend(quote!(let mut m: #w<#ty> = #w { uninit: () };));
                        quote!(unsafe { m.value })
                    }
                    None => {
                        stmts.extend(quote!(let mut m = #ty::zeros();));
                        quote!(m)
                    }
                }
            }
            Output::Matrix | Output::StoredMatrix => self.matrix(&bind, self.outputs),
            Output::StoredLower if stores.is_empty() => self.lower_writes(&bind),
            Output::StoredLower => quote!(),
            Output::Scalar => self.expr(&bind, self.outputs[0]),
            Output::Pose => self.pose(&bind, self.outputs),
            Output::Matrices(count) => {
                let size = self.rows * self.cols;
                let items = (0..count).map(|k| self.matrix(&bind, &self.outputs[k * size..]));
                quote!([#(#items),*])
            }
            Output::Poses(count) => {
                let items = (0..count).map(|k| self.pose(&bind, &self.outputs[k * 12..]));
                quote!([#(#items),*])
            }
            Output::Tuple { shapes, count, .. } => {
                let part = |(rows, cols): (usize, usize)| FunctionBody {
                    rows,
                    cols,
                    ..*self
                };
                // Each part's literal, from its first output on; with stores, the first part
                // is written into `m.0` and the others are assigned after it.
                let first = usize::from(!stores.is_empty());
                let mut start: usize = shapes[..first].iter().map(|s| s.0 * s.1).sum();
                let items: Vec<TokenStream> = shapes[first..count]
                    .iter()
                    .map(|&shape| {
                        let t = part(shape).matrix(&bind, &self.outputs[start..]);
                        start += shape.0 * shape.1;
                        t
                    })
                    .collect();
                if stores.is_empty() {
                    quote!((#(#items),*))
                } else {
                    let types = shapes[..count].iter().map(|&s| part(s).matrix_type());
                    let fields = (1..count).map(proc_macro2::Literal::usize_unsuffixed);
                    match self.written_union() {
                        Some(w) => {
                            stmts.extend(quote!(let mut m: #w<(#(#types),*)> = #w { uninit: () };));
                            // A field of the union's field: a safe write (no index).
                            quote!(#(m.value.#fields = #items;)* unsafe { m.value })
                        }
                        None => {
                            stmts.extend(quote!(let mut m = (#(#types::zeros()),*);));
                            quote!(#(m.#fields = #items;)* m)
                        }
                    }
                }
            }
            Output::Checked { guards } => {
                let tol = sqrt_epsilon(self.scalar);
                let tests = (0..guards).map(|k| {
                    let d = self.expr(&bind, self.outputs[2 * k]);
                    let a = self.expr(&bind, self.outputs[2 * k + 1]);
                    quote!(#d > #tol * #a)
                });
                let m = self.matrix(&bind, &self.outputs[2 * guards..]);
                quote! {
                    if !(#(#tests)&&*) {
                        return None;
                    }
                    Some(#m)
                }
            }
        };
        // The outputs the stores do not write are read at the end.
        let stored = if stores.is_empty() {
            0
        } else {
            self.stored_place().map_or(0, |(_, rows, cols)| rows * cols)
        };
        let mut reads = Vec::new();
        for &o in &self.outputs[stored..] {
            self.note_uses(&bind, o, usize::MAX, &mut last_use, &mut reads);
        }
        let mut body = reorder(body, &stores, &reads, &mut last_use, self.order);
        if self.written_union().is_some() && !stores.is_empty() {
            body = with_zero_writes(body, self.zero_writes());
            renumber_last_uses(&body, &mut last_use);
        }
        let value = renumber(&mut body, &mut bind, value);
        let split = self
            .self_ty
            .filter(|_| self.lanes.is_none() && body.len() > MAX_UNSPLIT_LETS)
            .map(|t| (t, self.scalar));
        if self.park
            && self.lanes.is_none()
            && split.is_none()
            && body.len() >= super::park::MIN_STATEMENTS
        {
            let width = |id: ExprId| match &packed {
                Some(p) if id.index() >= p.nodes => {
                    let lanes = &p.packing.packs[id.index() - p.nodes].lanes;
                    if self.two_lanes(lanes) {
                        super::park::Width::Two
                    } else {
                        super::park::Width::Four
                    }
                }
                _ => super::park::Width::One,
            };
            let (buffer, parked) = super::park::park(body, &mut last_use, width, self.scalar);
            stmts.extend(buffer);
            body = parked;
        }
        stmts.extend(chunked(body, &last_use, &bind, split));
        stmts.extend(value);
        stmts
    }

    /// The seeds of the packs (see [`Self::pack`]): the rows of each column of a pose's
    /// rotation, and its translation; the rows of each column of a Jacobian's `ω` and `v`;
    /// or the outputs of one shape.
    fn pack_seeds(&self, live: &[bool]) -> Vec<[Option<ExprId>; super::pack::LANES]> {
        // Each rotation column's rows of a pose, and its translation.
        let pose = || {
            let columns = (0..3).map(|c| [c, 3 + c, 6 + c]);
            columns.chain([[9, 10, 11]]).collect()
        };
        // Each column's `ω` (rows 0–2) and `v` (rows 3–5) of a row-major 6 × cols Jacobian.
        let cols = self.cols;
        let jacobian = || {
            let rows = |c: usize, r: usize| [r, r + 1, r + 2].map(|r| r * cols + c);
            (0..cols).flat_map(|c| [rows(c, 0), rows(c, 3)]).collect()
        };
        // The outputs of one item, how many items, and the seeds of each (three outputs by
        // their indices in the item).
        let (len, items, indices): (usize, usize, Vec<[usize; 3]>) = match (self.pack, self.output)
        {
            (Packs::None, _) => return Vec::new(),
            (Packs::Alike(min), _) => {
                return super::pack::alike_seeds(self.graph, live, self.outputs, min)
            }
            (Packs::Rows, Output::Pose) => (12, 1, pose()),
            (Packs::Rows, Output::Poses(count)) => (12, count, pose()),
            (Packs::Columns, Output::Matrix) if self.rows == 6 => (6 * cols, 1, jacobian()),
            (Packs::Columns, Output::Matrices(count)) if self.rows == 6 => {
                (6 * cols, count, jacobian())
            }
            (Packs::Rows | Packs::Columns, _) => return Vec::new(),
        };
        if len == 0 {
            return Vec::new();
        }
        // A Jacobian the body reads (all of it, its seeds' lanes live) first: its packs are
        // then the operands of the outputs' own.
        let read = (self.pack == Packs::Columns && self.reads_jacobian.len() == len)
            .then_some(self.reads_jacobian)
            .into_iter()
            .flat_map(|j| {
                indices
                    .iter()
                    .filter(|k| k.iter().all(|&i| live[j[i].index()]))
                    .map(|k| [Some(j[k[0]]), Some(j[k[1]]), Some(j[k[2]]), None])
            });
        let own = self.outputs.chunks_exact(len).take(items).flat_map(|out| {
            indices
                .iter()
                .map(|k| [Some(out[k[0]]), Some(out[k[1]]), Some(out[k[2]]), None])
        });
        read.chain(own).collect()
    }

    /// The packs of this body, when [`Self::pack`] asks for them and any is found.
    fn packed(&self, live: &[bool], uses: &[u32]) -> Option<Packed> {
        if self.lanes.is_some() {
            return None;
        }
        self.packs(live, uses)
    }

    /// The packs of this body as a single-state body (a batch body's [`Plan`]).
    fn packs(&self, live: &[bool], uses: &[u32]) -> Option<Packed> {
        use super::pack::Operand;
        // About the body's `let` statements (its shared nodes): a body that will be split into
        // parts ([`chunked`]) is not dispatched, and its portable code is slower with packs.
        let named = (0..live.len()).filter(|&k| live[k] && uses[k] >= 2).count();
        if self.pack == Packs::None || self.no_std || named > MAX_UNSPLIT_LETS {
            return None;
        }
        let g = self.graph;
        let packing = super::pack::find(g, live, &self.pack_seeds(live))?;
        let nodes = g.len();
        // The scalar uses the packs take over: lane k of a pack operand, as the scalar code
        // reads it (through the negations peeled into signs), read by lane k.
        let mut consumed = vec![0u32; nodes];
        let mut permuted = vec![false; packing.packs.len()];
        for pack in &packing.packs {
            for operand in &pack.operands {
                let tops = match operand {
                    Operand::Pack(_, tops) => tops,
                    Operand::Permute(q, _, tops) => {
                        permuted[*q] = true;
                        tops
                    }
                    _ => continue,
                };
                for &(x, _) in tops.iter().flatten() {
                    consumed[x.index()] += 1;
                }
            }
        }
        // And the negations a pack holds read their operands in the same lane (`−m` and `m`
        // are one lane, with other signs): so does an output's `−m` its `m`.
        for (k, place) in packing.of.iter().enumerate() {
            let Some((pack, lane, _)) = *place else {
                continue;
            };
            if let Node::Neg(a) = *g.node(ExprId(k as u32)) {
                if matches!(packing.of[a.index()], Some((p, l, _)) if p == pack && l == lane) {
                    consumed[a.index()] += 1;
                }
            }
        }
        let mut members: Vec<Vec<ExprId>> = vec![Vec::new(); packing.packs.len()];
        for (k, place) in packing.of.iter().enumerate() {
            if let Some((pack, _, _)) = place {
                members[*pack].push(ExprId(k as u32));
            }
        }
        let inline = members
            .iter()
            .zip(&packing.packs)
            .zip(&permuted)
            .map(|((members, pack), &permuted)| {
                pack.op == super::pack::Op::Mul
                    && !permuted
                    && members
                        .iter()
                        .all(|x| uses[x.index()] == 1 && consumed[x.index()] == 1)
            })
            .collect();
        let last = members
            .iter()
            .map(|m| m.iter().map(|x| x.index()).max().unwrap_or(0))
            .collect();
        let scalars = members
            .into_iter()
            .map(|m| {
                m.into_iter()
                    .filter(|x| uses[x.index()] > consumed[x.index()])
                    .collect()
            })
            .collect();
        Some(Packed {
            packing,
            inline,
            last,
            scalars,
            nodes,
        })
    }

    /// `let lanesK = …;` for pack `k`, then its nodes that are read as scalars taken out.
    fn pack_statement(
        &self,
        p: &Packed,
        k: usize,
        bind: &[Binding],
        at: usize,
        last_use: &mut [usize],
    ) -> Statement {
        let mut reads = Vec::new();
        let value = self.pack_expr(p, k, bind, at, last_use, &mut reads);
        let Binding::Named(name) = &bind[p.nodes + k] else {
            unreachable!("a pack written as a statement is named")
        };
        let mut defined = vec![(name.clone(), ExprId((p.nodes + k) as u32))];
        let mut tokens = quote!(let #name = #value;);
        let scalars = &p.scalars[k];
        if !scalars.is_empty() {
            let lane_name = |j: usize| format_ident!("{}_{}", name, j);
            let used: Vec<usize> = scalars
                .iter()
                .filter_map(|x| p.packing.of[x.index()].map(|(_, j, _)| j))
                .collect();
            let pats = (0..super::pack::LANES).map(|j| {
                if used.contains(&j) {
                    let l = lane_name(j);
                    quote!(#l)
                } else {
                    quote!(_)
                }
            });
            tokens.extend(quote!(let [#(#pats),*] = #name;));
            for &x in scalars {
                let (Some((_, j, neg)), Binding::Named(t)) =
                    (p.packing.of[x.index()], &bind[x.index()])
                else {
                    unreachable!("a pack's scalars are named")
                };
                let l = lane_name(j);
                tokens.extend(if neg {
                    quote!(let #t = -#l;)
                } else {
                    quote!(let #t = #l;)
                });
                defined.push((t.clone(), x));
            }
        }
        Statement {
            defined,
            tokens,
            reads,
        }
    }

    /// The vector operation of pack `k` (`Self::v4_fma(…)`, …), its reads noted.
    fn pack_expr(
        &self,
        p: &Packed,
        k: usize,
        bind: &[Binding],
        at: usize,
        last_use: &mut [usize],
        reads: &mut Vec<ExprId>,
    ) -> TokenStream {
        use super::pack::{Op, Operand};
        let pack = &p.packing.packs[k];
        let [a, b] = &pack.operands;
        let [fma, add, mul] = ["fma", "add", "mul"].map(|op| self.vector_op(&pack.lanes, op));
        let fused = if pack.op == Op::Add {
            self.fused_operand(p, pack)
        } else {
            None
        };
        match pack.op {
            Op::Add if fused.is_some() => {
                // A product operand fuses into a multiply-add ([`Self::fused_operand`]).
                let fuse_a = fused.is_some_and(|m| std::ptr::eq(m, a));
                let (m, c) = if fuse_a { (a, b) } else { (b, a) };
                let c = self.pack_operand(p, c, bind, at, last_use, reads);
                let Operand::Pack(q, _) = m else {
                    unreachable!("fused operands are packs")
                };
                let [x, y] = &p.packing.packs[*q].operands;
                let x = self.pack_operand(p, x, bind, at, last_use, reads);
                let y = self.pack_operand(p, y, bind, at, last_use, reads);
                quote!(Self::#fma(#x, #y, #c))
            }
            Op::Add => {
                let a = self.pack_operand(p, a, bind, at, last_use, reads);
                let b = self.pack_operand(p, b, bind, at, last_use, reads);
                quote!(Self::#add(#a, #b))
            }
            Op::Mul => {
                let a = self.pack_operand(p, a, bind, at, last_use, reads);
                let b = self.pack_operand(p, b, bind, at, last_use, reads);
                quote!(Self::#mul(#a, #b))
            }
        }
    }

    /// The helper of vector operation `op` (`fma`, `add`, `mul`, `neg`) on a pack of
    /// `lanes`: `v2_…` where only the first two lanes are used and the scalar is `f64` (one
    /// 128-bit register in the dispatched copies, where a 256-bit operation on two zero lanes
    /// makes LLVM build its constants from two scalar loads and spill them in long bodies:
    /// G1's forward dynamics 57,975 → 55,459 bytes, `docs/performance.md`, fifty-seventh
    /// session), `v4_…` otherwise (`f32`'s four lanes are one 128-bit register already).
    fn vector_op(&self, lanes: &super::pack::Lanes, op: &str) -> Ident {
        let two = self.two_lanes(lanes);
        format_ident!("{}_{}", if two { "v2" } else { "v4" }, op)
    }

    /// Whether a pack of `lanes` is written with the `v2_…` helpers ([`Self::vector_op`]):
    /// `[a, b, 0, 0]`.
    fn two_lanes(&self, lanes: &super::pack::Lanes) -> bool {
        lanes[2..].iter().all(Option::is_none) && self.scalar == Scalar::F64
    }

    /// The tokens of a pack's operand, its reads noted.
    fn pack_operand(
        &self,
        p: &Packed,
        o: &super::pack::Operand,
        bind: &[Binding],
        at: usize,
        last_use: &mut [usize],
        reads: &mut Vec<ExprId>,
    ) -> TokenStream {
        use super::pack::Operand;
        let scalar = |x: ExprId, neg: bool, reads: &mut Vec<ExprId>, last_use: &mut [usize]| {
            self.note_uses(bind, x, at, last_use, reads);
            if neg {
                let e = self.operand(bind, x, 4);
                quote!(-#e)
            } else {
                self.expr(bind, x)
            }
        };
        match o {
            Operand::Pack(q, _) if p.inline[*q] => self.pack_expr(p, *q, bind, at, last_use, reads),
            Operand::Pack(q, _) => self.pack_name(p, *q, bind, at, last_use, reads),
            Operand::Permute(q, map, _) => {
                let name = self.pack_name(p, *q, bind, at, last_use, reads);
                let used = |j: usize| map.iter().flatten().any(|&(i, _)| i == j);
                let pats = (0..super::pack::LANES).map(|j| {
                    if used(j) {
                        let l = format_ident!("l{}", j);
                        quote!(#l)
                    } else {
                        quote!(_)
                    }
                });
                // Every lane in place, all negated: the vector negated (which the optimiser
                // folds into a multiply-add's `vfnmadd`).
                let negated = map
                    .iter()
                    .enumerate()
                    .all(|(k, m)| m.is_none_or(|(j, neg)| j == k && neg));
                if negated {
                    let neg = self.vector_op(&p.packing.packs[*q].lanes, "neg");
                    return quote!(Self::#neg(#name));
                }
                let lanes = map.iter().map(|m| match m {
                    Some((j, neg)) => {
                        let l = format_ident!("l{}", j);
                        if *neg {
                            quote!(-#l)
                        } else {
                            quote!(#l)
                        }
                    }
                    None => self.literal(0.0),
                });
                quote!({
                    let [#(#pats),*] = #name;
                    [#(#lanes),*]
                })
            }
            Operand::Splat(x, signs) => {
                let e = scalar(*x, false, reads, last_use);
                if signs.iter().all(|&s| s >= 0.0) {
                    quote!([#e; 4])
                } else {
                    let lanes = signs.map(|s| (s != 0.0).then_some((*x, s < 0.0)));
                    let mul = self.vector_op(&lanes, "mul");
                    let signs = signs.map(|s| self.literal(s));
                    quote!(Self::#mul([#e; 4], [#(#signs),*]))
                }
            }
            Operand::Consts(c) => {
                let c = c.map(|c| self.literal(c));
                quote!([#(#c),*])
            }
            Operand::Gather(lanes) => {
                let e: Vec<TokenStream> = lanes
                    .iter()
                    .map(|l| match l {
                        Some((x, neg)) => scalar(*x, *neg, reads, last_use),
                        None => self.literal(0.0),
                    })
                    .collect();
                quote!([#(#e),*])
            }
        }
    }

    /// The name of the vector of pack `q`, its read noted.
    fn pack_name(
        &self,
        p: &Packed,
        q: usize,
        bind: &[Binding],
        at: usize,
        last_use: &mut [usize],
        reads: &mut Vec<ExprId>,
    ) -> TokenStream {
        let id = ExprId((p.nodes + q) as u32);
        self.note_uses(bind, id, at, last_use, reads);
        let Binding::Named(name) = &bind[id.index()] else {
            unreachable!("a pack read by name is named")
        };
        quote!(#name)
    }

    /// Records that statement `at` reads the named nodes in the inline expression of `id`
    /// (in `last_use`, and in `reads`, the statement's own list).
    fn note_uses(
        &self,
        bind: &[Binding],
        id: ExprId,
        at: usize,
        last_use: &mut [usize],
        reads: &mut Vec<ExprId>,
    ) {
        match bind[id.index()] {
            Binding::Named(_) => {
                last_use[id.index()] = last_use[id.index()].max(at);
                reads.push(id);
            }
            Binding::Inline => {
                for o in self.graph.node(id).operands() {
                    self.note_uses(bind, o, at, last_use, reads);
                }
            }
        }
    }

    /// For an [`Output::StoredMatrix`] (and the first matrix of an [`Output::Tuple`] with
    /// `stored_first`, `m.0`), one statement per value that is not +0.0, writing every entry
    /// that holds it (`m.data.0[c][r] = value;`), appended to `body` (its reads noted in
    /// `last_use`), and their indices from the last entry back: the roots of the schedule, so
    /// that each store follows the statements it reads and the body is computed from the
    /// last entry back. Empty for any other output, in a batch body, where the body will be
    /// split into parts (see [`chunked`]), which cannot write into the matrix, and where the
    /// literal would keep at most [`STORED_MIN_LIVE`] values live.
    ///
    /// Why, for the mass matrix: returned as one array literal, every entry stays live until
    /// the end, and scheduled from the first entry, the composite inertias of every subtree
    /// are computed first and stay live until their own rows are written (CRBA builds `M`
    /// from the leaves). Scheduled from the last entry back and stored at once, the values
    /// live at any point fall from 273 to 49 on a humanoid (G1, floating base; from 93 to 47
    /// on Solo-12). Measured (old and new generated code side by side in one binary, medians
    /// of 11 interleaved rounds of 20,000 calls at cycled random states, default profile, so
    /// the AVX-512 copies, 2026-11-27): G1 907 → 834 ns (−8 %, two runs; the copy's stack
    /// stores 827 → 566), Solo-12 −9 and −14 %; on smaller bodies it gains little or loses
    /// ([`STORED_MIN_LIVE`]). Either change alone gained less (G1: −1 % scheduled from the
    /// end, +2 to +3 % stored at once), and scheduling every function from its last output
    /// back made G1's inverse dynamics 9–13 % slower.
    fn stores(
        &self,
        bind: &[Binding],
        body: &mut Vec<Statement>,
        last_use: &mut [usize],
    ) -> Vec<usize> {
        let Some((place, rows, cols)) = self.stored_place() else {
            return Vec::new();
        };
        let entries = rows * cols;
        let splits = self.self_ty.is_some() && body.len() + entries > MAX_UNSPLIT_LETS;
        let lower = self.output == Output::StoredLower;
        if self.lanes.is_some()
            || splits
            || (!lower && self.peak_live_as_literal(bind, body, last_use) <= STORED_MIN_LIVE)
        {
            return Vec::new();
        }
        // The entries of each value (both halves of a symmetric matrix), stored together.
        let mut entries_of: Vec<(ExprId, Vec<usize>)> = Vec::new();
        let mut slot: std::collections::HashMap<ExprId, usize> = std::collections::HashMap::new();
        for k in (0..entries).rev() {
            let id = self.outputs[k];
            if !self.is_stored(k, cols) {
                continue;
            }
            match slot.get(&id) {
                Some(&i) => entries_of[i].1.push(k),
                None => {
                    slot.insert(id, entries_of.len());
                    entries_of.push((id, vec![k]));
                }
            }
        }
        let mut roots = Vec::new();
        for (id, ks) in entries_of {
            let places = ks.iter().map(|&k| {
                let (r, c) = (
                    proc_macro2::Literal::usize_unsuffixed(k / cols),
                    proc_macro2::Literal::usize_unsuffixed(k % cols),
                );
                quote!(#place.data.0[#c][#r])
            });
            let value = self.expr(bind, id);
            let tokens = if ks.len() == 1 || matches!(bind[id.index()], Binding::Named(_)) {
                quote! { #(#places = #value;)* }
            } else {
                quote! { { let v = #value; #(#places = v;)* } }
            };
            // A union's field (`m.value`), written before any read of it.
            let tokens = match self.written_union() {
                Some(_) => quote!(unsafe { #tokens }),
                None => tokens,
            };
            let mut reads = Vec::new();
            self.note_uses(bind, id, body.len(), last_use, &mut reads);
            roots.push(body.len());
            body.push(Statement {
                defined: Vec::new(),
                tokens,
                reads,
            });
        }
        roots
    }

    /// The matrix that [`Self::stores`] may write entry by entry, its place in the result and
    /// its shape: an [`Output::StoredMatrix`] (`m`), or the first of an [`Output::Tuple`] with
    /// `stored_first` (`m.0`).
    fn stored_place(&self) -> Option<(TokenStream, usize, usize)> {
        let (rows, cols) = self.stored_shape()?;
        let m = match self.written_union() {
            Some(_) => quote!(m.value),
            None => quote!(m),
        };
        let place = match self.output {
            Output::Tuple { .. } => quote!(#m.0),
            _ => m,
        };
        Some((place, rows, cols))
    }

    /// The shape of the matrix [`Self::stored_place`] names: an [`Output::StoredMatrix`]'s or
    /// [`Output::StoredLower`]'s, or the first of an [`Output::Tuple`] with `stored_first`.
    fn stored_shape(&self) -> Option<(usize, usize)> {
        match self.output {
            Output::StoredMatrix | Output::StoredLower => Some((self.rows, self.cols)),
            Output::Tuple {
                shapes,
                stored_first: true,
                ..
            } => Some(shapes[0]),
            _ => None,
        }
    }

    /// [`Self::written`] where the result is the body's own and has at least
    /// [`WRITTEN_MIN_ENTRIES`] entries: not for an [`Output::StoredLower`], which writes into
    /// the caller's matrix (and nothing else), nor for a small vector, which is zeroed.
    fn written_union(&self) -> Option<&Ident> {
        self.written.filter(|_| {
            self.output != Output::StoredLower
                && self
                    .stored_shape()
                    .is_some_and(|(rows, cols)| rows * cols >= WRITTEN_MIN_ENTRIES)
        })
    }

    /// The writes of `0.0` into the entries of a stored result that [`Self::stores`] leaves
    /// (those +0.0 for every input, the tree's structural zeros) when it is written into
    /// [`Self::written`]'s union, which starts uninitialised: one statement per run of them
    /// in a column, `unsafe { m.value.data.0[c][r] = 0.0; … }`, columns in order. The
    /// optimiser writes a run's adjacent entries with vector stores.
    fn zero_writes(&self) -> Vec<Statement> {
        let Some((place, rows, cols)) = self.stored_place() else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for c in 0..cols {
            let mut r = 0;
            while r < rows {
                let start = r;
                while r < rows && !self.is_stored(r * cols + c, cols) {
                    r += 1;
                }
                if r > start {
                    let c = proc_macro2::Literal::usize_unsuffixed(c);
                    let writes = (start..r).map(|r| {
                        let r = proc_macro2::Literal::usize_unsuffixed(r);
                        quote!(#place.data.0[#c][#r] = 0.0;)
                    });
                    out.push(Statement {
                        defined: Vec::new(),
                        tokens: quote!(unsafe { #(#writes)* }),
                        reads: Vec::new(),
                    });
                } else {
                    r += 1;
                }
            }
        }
        out
    }

    /// The most named values live at once in `body` scheduled for [`Output::Matrix`] (from
    /// the first output, every output live to the end).
    fn peak_live_as_literal(
        &self,
        bind: &[Binding],
        body: &[Statement],
        last_use: &[usize],
    ) -> usize {
        let (mut scratch, mut outputs) = (last_use.to_vec(), Vec::new());
        for &o in self.outputs {
            self.note_uses(bind, o, usize::MAX, &mut scratch, &mut outputs);
        }
        let order = schedule(body, &[], &outputs, last_use.len(), self.order);
        let n = order.len();
        // Each value from the position of its statement to its last reader's (outputs: n).
        let mut end = vec![0usize; last_use.len()];
        for (p, &k) in order.iter().enumerate() {
            for &id in &body[k].reads {
                end[id.index()] = p;
            }
        }
        for id in outputs {
            end[id.index()] = n;
        }
        let mut delta = vec![0i64; n + 2];
        for (p, &k) in order.iter().enumerate() {
            for &(_, id) in &body[k].defined {
                delta[p] += 1;
                delta[end[id.index()].max(p) + 1] -= 1;
            }
        }
        let (mut live, mut peak) = (0i64, 0i64);
        for d in delta {
            live += d;
            peak = peak.max(live);
        }
        usize::try_from(peak).unwrap_or(0)
    }

    /// The type of the result of [`Self::matrix`] (not in a batch body).
    fn matrix_type(&self) -> TokenStream {
        let scalar = Ident::new(self.scalar.as_str(), Span::call_site());
        let na = self.nalgebra;
        let (rows_lit, cols_lit) = (
            proc_macro2::Literal::usize_unsuffixed(self.rows),
            proc_macro2::Literal::usize_unsuffixed(self.cols),
        );
        if self.cols == 1 {
            quote!(#na::SVector::<#scalar, #rows_lit>)
        } else {
            quote!(#na::SMatrix::<#scalar, #rows_lit, #cols_lit>)
        }
    }

    /// A `rows × cols` matrix from the first outputs of `outputs` (row-major), packed column
    /// by column.
    fn matrix(&self, bind: &[Binding], outputs: &[ExprId]) -> TokenStream {
        let na = self.nalgebra;
        let (rows, cols) = (self.rows, self.cols);
        let lanes = self.lanes_ty();
        let columns: Vec<TokenStream> = (0..cols)
            .map(|c| {
                let entries: Vec<TokenStream> = (0..rows)
                    .map(|r| {
                        let e = self.expr(bind, outputs[r * cols + c]);
                        if self.lanes.is_some() {
                            quote!(#lanes::from(#e))
                        } else {
                            e
                        }
                    })
                    .collect();
                quote!([#(#entries),*])
            })
            .collect();
        if self.lanes.is_some() {
            // The lanes by columns, transposed into one matrix per state.
            return quote!(#lanes::scatter(&[#(#columns),*]));
        }
        let ty = self.matrix_type();
        quote!(#ty::from_array_storage(#na::ArrayStorage([#(#columns),*])))
    }

    /// The writes of an [`Output::StoredLower`] whose entries were not stored as computed
    /// (a body split into parts): `m.data.0[c][r] = value;` for each entry on or below the
    /// diagonal that is not +0.0 for every input.
    fn lower_writes(&self, bind: &[Binding]) -> TokenStream {
        let cols = self.cols;
        let writes = (0..self.rows * cols)
            .filter(|&k| self.is_stored(k, cols))
            .map(|k| {
                let e = self.expr(bind, self.outputs[k]);
                let (r, c) = (
                    proc_macro2::Literal::usize_unsuffixed(k / cols),
                    proc_macro2::Literal::usize_unsuffixed(k % cols),
                );
                quote!(m.data.0[#c][#r] = #e;)
            });
        quote!(#(#writes)*)
    }

    /// Whether output `k` (row-major, `cols` columns) of a stored matrix is written: not a
    /// +0.0 constant (the matrix starts zeroed, keeps the caller's zeros, or gets them from
    /// [`Self::zero_writes`]; a −0.0 entry is still written, as the literal has it), and for
    /// an [`Output::StoredLower`] on or below the diagonal.
    fn is_stored(&self, k: usize, cols: usize) -> bool {
        let zero = self
            .graph
            .as_const(self.outputs[k])
            .is_some_and(|x| x.to_bits() == 0);
        let upper = self.output == Output::StoredLower && k / cols < k % cols;
        !zero && !upper
    }

    /// `Self::isometry(R, p)` from the first 12 outputs of `outputs`.
    fn pose(&self, bind: &[Binding], outputs: &[ExprId]) -> TokenStream {
        let e: Vec<TokenStream> = outputs[..12]
            .iter()
            .map(|&id| self.expr(bind, id))
            .collect();
        let (r0, r1, r2, p) = (&e[0..3], &e[3..6], &e[6..9], &e[9..12]);
        quote!(Self::isometry([[#(#r0),*], [#(#r1),*], [#(#r2),*]], [#(#p),*]))
    }

    /// A constant: suffixed with its type in a batch body, where an unsuffixed literal beside
    /// a `Lanes` would leave the compiler to choose among the operator impls of every float
    /// type (measured: the Panda's four batch functions took 11 s to type-check unsuffixed).
    fn literal(&self, x: f64) -> TokenStream {
        if self.lanes.is_none() {
            return float_tokens(x, self.scalar);
        }
        let text = format!(
            "{}_{}",
            super::literal::float_text(x.abs(), self.scalar),
            self.scalar.as_str()
        );
        let lit: proc_macro2::Literal = text
            .parse()
            .unwrap_or_else(|_| proc_macro2::Literal::f64_suffixed(x.abs()));
        if x.is_sign_negative() && x != 0.0 {
            quote!(-#lit)
        } else {
            quote!(#lit)
        }
    }

    /// `::dynamics_runtime::Lanes::<scalar, B>`, the value type of a batch body.
    fn lanes_ty(&self) -> TokenStream {
        let scalar = Ident::new(self.scalar.as_str(), Span::call_site());
        let runtime = self.lanes;
        quote!(#runtime::Lanes::<#scalar, B>)
    }

    /// The sines and cosines of `args` by the `joint_sin_cos` helper: one call, or in a batch
    /// body one call per argument, on its `B` lanes.
    fn sin_cos_call(&self, args: &[TokenStream]) -> TokenStream {
        if self.lanes.is_some() {
            let lanes = self.lanes_ty();
            quote!(Self::joint_sin_cos_rows([#(#lanes::from(#args)),*]))
        } else if args.len() == 1 {
            quote!(Self::joint_sin_cos::<1, 1>([#(#args),*]))
        } else {
            let k = proc_macro2::Literal::usize_unsuffixed(args.len());
            quote!(Self::joint_sin_cos::<#k, { Self::sin_cos_lanes(#k) }>([#(#args),*]))
        }
    }

    /// The pattern binding a sine or cosine named `name` (node `id`, if live), or `_`.
    fn trig_pattern(
        &self,
        bind: &mut [Binding],
        defined: &mut Vec<(Ident, ExprId)>,
        name: Ident,
        id: Option<ExprId>,
    ) -> TokenStream {
        match id {
            Some(id) => {
                bind[id.index()] = Binding::Named(name.clone());
                defined.push((name.clone(), id));
                quote!(#name)
            }
            None => quote!(_),
        }
    }

    /// The tokens for node `id` where it is used: its name, or its operation inline.
    fn expr(&self, bind: &[Binding], id: ExprId) -> TokenStream {
        match &bind[id.index()] {
            Binding::Named(name) => quote!(#name),
            Binding::Inline => self.op(bind, id),
        }
    }

    /// An operand, parenthesised when its precedence is lower than `min` requires.
    fn operand(&self, bind: &[Binding], id: ExprId, min: u8) -> TokenStream {
        let t = self.expr(bind, id);
        if self.precedence(bind, id) < min {
            quote!((#t))
        } else {
            t
        }
    }

    /// 1 for sums, 2 for products and quotients, 3 for negation, 4 for atoms.
    fn precedence(&self, bind: &[Binding], id: ExprId) -> u8 {
        if let Binding::Named(_) = bind[id.index()] {
            return 4;
        }
        match *self.graph.node(id) {
            Node::Add(a, b) | Node::Sub(a, b)
                if self.fuses(bind, id, a) || self.fuses(bind, id, b) =>
            {
                4
            }
            Node::Add(..) | Node::Sub(..) => 1,
            Node::Mul(..) | Node::Div(..) => 2,
            Node::Neg(_) => 3,
            Node::Const(c) if c.value() < 0.0 => 3,
            _ => 4,
        }
    }

    /// Whether node `id` is a product written inline that its user fuses into a
    /// multiply-add: with `std` only (see [`mul_add_helper`]); in a batch body the same
    /// products as in the single-state body, by `mul_add_lanes`.
    fn fused(&self, bind: &[Binding], id: ExprId) -> bool {
        !self.no_std
            && matches!(bind[id.index()], Binding::Inline)
            && matches!(self.graph.node(id), Node::Mul(..))
            && self.plan.is_none_or(|plan| !plan.packed[id.index()])
    }

    /// Whether the sum or difference `x` fuses its operand `id` ([`Self::fused`]); with a
    /// [`Plan`], a packed `x` fuses what its pack fuses.
    fn fuses(&self, bind: &[Binding], x: ExprId, id: ExprId) -> bool {
        match self.plan {
            Some(plan) if plan.packed[x.index()] => plan.fuses[x.index()] == Some(id),
            _ => self.fused(bind, id),
        }
    }

    /// `Self::mul_add(x, y, c)` for the inline product `p = x·y` (`−x` if `negate`).
    fn mul_add(&self, bind: &[Binding], p: ExprId, negate: bool, c: TokenStream) -> TokenStream {
        let Node::Mul(x, y) = *self.graph.node(p) else {
            unreachable!("fused() admits products only")
        };
        let (x, y) = match self.late_factor(bind, p) {
            Some((u, w)) => {
                let x = self.operand(bind, x, 2);
                let u = self.operand(bind, u, 3);
                let xu = if negate {
                    quote!(-(#x * #u))
                } else {
                    quote!(#x * #u)
                };
                (xu, self.expr(bind, w))
            }
            None if negate => {
                let x = self.operand(bind, x, 4);
                (quote!(-#x), self.expr(bind, y))
            }
            None => (self.expr(bind, x), self.expr(bind, y)),
        };
        if self.lanes.is_some() {
            let lanes = self.lanes_ty();
            return quote!(Self::mul_add_lanes(#lanes::from(#x), #lanes::from(#y), #lanes::from(#c)));
        }
        quote!(Self::mul_add(#x, #y, #c))
    }

    /// When the operands of product `id` are ready (the node's own time for anything else).
    fn ready(&self, id: ExprId) -> u32 {
        match *self.graph.node(id) {
            Node::Mul(a, b) => self.ready[a.index()].max(self.ready[b.index()]),
            _ => self.ready[id.index()],
        }
    }

    /// For the product `p = x·y` of a constant `x` and an inline product `y = u·w` whose
    /// factors are ready at different times: `(u, w)` with `w` the later, so that the product
    /// is written `(x·u)·w` and only one multiplication waits for `w`. (The graph keeps
    /// constant factors outermost, `c·(u·w)`, its normal form.) Never where a batch's
    /// [`Plan`] has `p` or `y` in a pack, which computes `c·(u·w)`.
    fn late_factor(&self, bind: &[Binding], p: ExprId) -> Option<(ExprId, ExprId)> {
        let Node::Mul(x, y) = *self.graph.node(p) else {
            return None;
        };
        self.graph.as_const(x)?;
        if self
            .plan
            .is_some_and(|plan| plan.packed[p.index()] || plan.packed[y.index()])
        {
            return None;
        }
        if !matches!(bind[y.index()], Binding::Inline) {
            return None;
        }
        let Node::Mul(u, w) = *self.graph.node(y) else {
            return None;
        };
        let (tu, tw) = (self.ready[u.index()], self.ready[w.index()]);
        match tu.cmp(&tw) {
            std::cmp::Ordering::Less => Some((u, w)),
            std::cmp::Ordering::Greater => Some((w, u)),
            std::cmp::Ordering::Equal => None,
        }
    }

    /// For an inline product `(−c)·x` with a negative constant, the tokens of `c·x`.
    fn negated_product(&self, bind: &[Binding], id: ExprId) -> Option<TokenStream> {
        if !matches!(bind[id.index()], Binding::Inline) {
            return None;
        }
        let Node::Mul(k, x) = *self.graph.node(id) else {
            return None;
        };
        let c = self.graph.as_const(k).filter(|c| *c < 0.0)?;
        let c = self.literal(-c);
        let x = self.operand(bind, x, 3);
        Some(quote!(#c * #x))
    }

    fn op(&self, bind: &[Binding], id: ExprId) -> TokenStream {
        let fused = |x: ExprId| self.fuses(bind, id, x);
        match *self.graph.node(id) {
            Node::Const(c) => self.literal(c.value()),
            Node::Input(x) => {
                let name = format_ident!("in{}_{}", x.group, x.index);
                quote!(#name)
            }
            Node::Neg(a) => {
                let a = self.operand(bind, a, 4);
                quote!(-#a)
            }
            Node::Add(a, b) if fused(a) || fused(b) => {
                // A product operand fuses into a multiply-add: of two, the one whose operands
                // are ready later (the other is computed meanwhile).
                let fuse_a = fused(a) && (!fused(b) || self.ready(a) > self.ready(b));
                let (p, c) = if fuse_a { (a, b) } else { (b, a) };
                self.mul_add(bind, p, false, self.expr(bind, c))
            }
            Node::Sub(a, b) if fused(a) && fused(b) && self.ready(a) > self.ready(b) => {
                // `x·y − b = x·y + (−b)`, the later product fused.
                let c = self.operand(bind, b, 4);
                self.mul_add(bind, a, false, quote!(-#c))
            }
            Node::Sub(a, b) if fused(b) => {
                // `a − x·y = (−x)·y + a`.
                let c = self.expr(bind, a);
                self.mul_add(bind, b, true, c)
            }
            Node::Sub(a, b) if fused(a) => {
                // `x·y − b = x·y + (−b)`.
                let c = self.operand(bind, b, 4);
                self.mul_add(bind, a, false, quote!(-#c))
            }
            Node::Add(a, b) => {
                // `a + (−c)·x` reads better as `a − c·x` (negation is exact).
                if let Some(t) = self.negated_product(bind, b) {
                    let a = self.operand(bind, a, 1);
                    return quote!(#a - #t);
                }
                let (a, b) = (self.operand(bind, a, 1), self.operand(bind, b, 2));
                quote!(#a + #b)
            }
            Node::Sub(a, b) => {
                if let Some(t) = self.negated_product(bind, b) {
                    let a = self.operand(bind, a, 1);
                    return quote!(#a + #t);
                }
                let (a, b) = (self.operand(bind, a, 1), self.operand(bind, b, 2));
                quote!(#a - #b)
            }
            Node::Mul(a, b) => {
                if let Some((u, w)) = self.late_factor(bind, id) {
                    // `c·(u·w)` as `(c·u)·w`: one multiplication after the later factor.
                    let (a, u, w) = (
                        self.operand(bind, a, 2),
                        self.operand(bind, u, 3),
                        self.operand(bind, w, 3),
                    );
                    return quote!(#a * #u * #w);
                }
                let (a, b) = (self.operand(bind, a, 2), self.operand(bind, b, 3));
                quote!(#a * #b)
            }
            Node::Div(a, b) => {
                let (a, b) = (self.operand(bind, a, 2), self.operand(bind, b, 3));
                quote!(#a / #b)
            }
            Node::Sqrt(a) => {
                let a = self.expr(bind, a);
                if self.lanes.is_some() {
                    let lanes = self.lanes_ty();
                    let f = match (self.no_std, self.scalar) {
                        (false, Scalar::F64) => quote!(f64::sqrt),
                        (false, Scalar::F32) => quote!(f32::sqrt),
                        (true, Scalar::F64) => quote!(::libm::sqrt),
                        (true, Scalar::F32) => quote!(::libm::sqrtf),
                    };
                    return quote!(#lanes::from(#a).map(#f));
                }
                match (self.no_std, self.scalar) {
                    (false, _) => quote!((#a).sqrt()),
                    (true, Scalar::F64) => quote!(::libm::sqrt(#a)),
                    (true, Scalar::F32) => quote!(::libm::sqrtf(#a)),
                }
            }
            Node::Sin(a) | Node::Cos(a) => {
                // Only reached for a sin/cos bound by the trig pass; fall back to a call.
                let a = self.expr(bind, a);
                let f = if matches!(self.graph.node(id), Node::Sin(_)) {
                    "sin"
                } else {
                    "cos"
                };
                let f = Ident::new(f, Span::call_site());
                quote!((#a).#f())
            }
        }
    }
}

/// The deepest angle the sine and cosine kernel computes inline: a run of parallel joints' sum
/// (`q_i + q_j + …`, each with its offset) of up to 8 joints, or a mimic joint's `a·q_i + b`.
const MAX_ANGLE_DEPTH: u32 = 16;

/// The nodes written only inline into the kernel's angles (`batch`: the indices in `trig` of
/// the angles it takes): the angles and their parts (`q_i + b`; the partial sums of a run of
/// parallel joints) whose every use is by a kernel's sine or cosine or by another such node.
/// They get no `let` of their own, which nothing would read.
fn angles_inline(
    g: &ExprGraph,
    live: &[bool],
    uses: &[u32],
    trig: &[(ExprId, Option<ExprId>, Option<ExprId>)],
    batch: &[usize],
) -> Vec<bool> {
    let mut part = vec![false; g.len()];
    let mut stack: Vec<ExprId> = batch.iter().map(|&t| trig[t].0).collect();
    while let Some(id) = stack.pop() {
        if !part[id.index()] && !matches!(g.node(id), Node::Input(_) | Node::Const(_)) {
            part[id.index()] = true;
            stack.extend(g.node(id).operands());
        }
    }
    let mut kernel = vec![false; g.len()];
    for &t in batch {
        kernel[trig[t].0.index()] = true;
    }
    // Uses by the kernel's sines and cosines and by inline-only nodes, users first.
    let mut inner = vec![0u32; g.len()];
    let mut inline_only = vec![false; g.len()];
    for k in (0..g.len()).rev() {
        if !live[k] {
            continue;
        }
        match *g.node(ExprId(k as u32)) {
            Node::Sin(a) | Node::Cos(a) if kernel[a.index()] => inner[a.index()] += 1,
            ref node if part[k] && uses[k] == inner[k] => {
                inline_only[k] = true;
                for o in node.operands() {
                    inner[o.index()] += 1;
                }
            }
            _ => {}
        }
    }
    inline_only
}

/// Whether `id` reads inputs of one group (one argument) through sums, differences, products
/// and negations with constants, at most `depth` operations deep: `q_i`, `q_i + b`, `a·q_i +
/// b`, a run of parallel joints' `q_i + q_j − q_k` (see `expand::kinematics`).
fn of_one_input(g: &ExprGraph, id: ExprId, depth: u32) -> bool {
    fn group_of(g: &ExprGraph, id: ExprId, depth: u32) -> Option<Option<u8>> {
        // Some(None): constants only; Some(Some(k)): constants and inputs of group k.
        match *g.node(id) {
            Node::Const(_) => Some(None),
            Node::Input(x) => Some(Some(x.group)),
            Node::Neg(a) if depth > 0 => group_of(g, a, depth - 1),
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) if depth > 0 => {
                match (group_of(g, a, depth - 1)?, group_of(g, b, depth - 1)?) {
                    (Some(x), Some(y)) if x != y => None,
                    // A product of two inputs is no angle of a joint.
                    (Some(_), Some(_)) if matches!(g.node(id), Node::Mul(..)) => None,
                    (x, y) => Some(x.or(y)),
                }
            }
            _ => None,
        }
    }
    matches!(group_of(g, id, depth), Some(Some(_)))
}

/// The private `mul_add(a, b, c) = a·b + c` helper of a generated `std` impl, which every
/// sum or difference with a single-use product operand calls: one fused multiply-add
/// (`f64::mul_add`, one rounding) where the target has the instruction (x86-64 with the
/// `fma` feature, e.g. `-C target-cpu=native`, and AArch64), otherwise the product and the
/// sum as written; `#[inline(always)]`, so either way no call remains. `no_std` code writes
/// products and sums alone (`core` has no `mul_add`, and `libm`'s is a software routine on
/// most targets).
pub fn mul_add_helper(scalar: Scalar) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    quote! {
        /// `a·b + c`: fused (rounded once) where the target has a fused multiply-add
        /// instruction (x86-64 with `fma`, AArch64), otherwise a product and a sum.
        #[inline(always)]
        fn mul_add(a: #t, b: #t, c: #t) -> #t {
            #[cfg(any(target_feature = "fma", target_arch = "aarch64"))]
            {
                a.mul_add(b, c)
            }
            #[cfg(not(any(target_feature = "fma", target_arch = "aarch64")))]
            {
                a * b + c
            }
        }
    }
}

/// The names of the vector helpers of [`vector_helpers`] (and, with the dispatch, of their
/// `_with::<WIDE>` forms).
pub const VECTOR_HELPERS: [&str; 9] = [
    "v4_fma", "v4_mul", "v4_add", "v4_sub", "v4_neg", "v2_fma", "v2_mul", "v2_add", "v2_neg",
];

/// The private helpers on `[T; 4]` (`T` the scalar) that packed bodies call
/// ([`super::pack`]), those of [`VECTOR_HELPERS`] that `called` says are called: lane by lane
/// the scalar operations (`v4_fma` through [`mul_add_helper`]'s `mul_add`), which the
/// optimiser reduces to the scalar code the lanes stand for; the dispatched copies call their
/// AVX2 forms instead ([`super::dispatch`]).
pub fn vector_helpers(scalar: Scalar, called: impl Fn(&str) -> bool) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let helpers = [
        quote! {
            /// `a·b + c` lane by lane, fused as [`Self::mul_add`] is.
            #[inline(always)]
            fn v4_fma(a: [#t; 4], b: [#t; 4], c: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, a2, a3], [b0, b1, b2, b3], [c0, c1, c2, c3]) = (a, b, c);
                [
                    Self::mul_add(a0, b0, c0),
                    Self::mul_add(a1, b1, c1),
                    Self::mul_add(a2, b2, c2),
                    Self::mul_add(a3, b3, c3),
                ]
            }
        },
        quote! {
            /// `a·b` lane by lane.
            #[inline(always)]
            fn v4_mul(a: [#t; 4], b: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (a, b);
                [a0 * b0, a1 * b1, a2 * b2, a3 * b3]
            }
        },
        quote! {
            /// `a + b` lane by lane.
            #[inline(always)]
            fn v4_add(a: [#t; 4], b: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (a, b);
                [a0 + b0, a1 + b1, a2 + b2, a3 + b3]
            }
        },
        quote! {
            /// `a − b` lane by lane.
            #[inline(always)]
            fn v4_sub(a: [#t; 4], b: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (a, b);
                [a0 - b0, a1 - b1, a2 - b2, a3 - b3]
            }
        },
        quote! {
            /// `−a` lane by lane.
            #[inline(always)]
            fn v4_neg(a: [#t; 4]) -> [#t; 4] {
                let [a0, a1, a2, a3] = a;
                [-a0, -a1, -a2, -a3]
            }
        },
        quote! {
            /// [`Self::v4_fma`] on the first two lanes (packs of two, `f64`); the other two 0.
            #[inline(always)]
            fn v2_fma(a: [#t; 4], b: [#t; 4], c: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, ..], [b0, b1, ..], [c0, c1, ..]) = (a, b, c);
                [Self::mul_add(a0, b0, c0), Self::mul_add(a1, b1, c1), 0.0, 0.0]
            }
        },
        quote! {
            /// [`Self::v4_mul`] on the first two lanes; the other two 0.
            #[inline(always)]
            fn v2_mul(a: [#t; 4], b: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, ..], [b0, b1, ..]) = (a, b);
                [a0 * b0, a1 * b1, 0.0, 0.0]
            }
        },
        quote! {
            /// [`Self::v4_add`] on the first two lanes; the other two 0.
            #[inline(always)]
            fn v2_add(a: [#t; 4], b: [#t; 4]) -> [#t; 4] {
                let ([a0, a1, ..], [b0, b1, ..]) = (a, b);
                [a0 + b0, a1 + b1, 0.0, 0.0]
            }
        },
        quote! {
            /// [`Self::v4_neg`] on the first two lanes; the other two 0.
            #[inline(always)]
            fn v2_neg(a: [#t; 4]) -> [#t; 4] {
                let [a0, a1, ..] = a;
                [-a0, -a1, 0.0, 0.0]
            }
        },
    ];
    let called = VECTOR_HELPERS
        .iter()
        .zip(helpers)
        .filter(|(name, _)| called(name))
        .map(|(_, helper)| helper);
    quote!(#(#called)*)
}

/// The private `isometry(r, p)` helper of a generated impl: a rotation matrix (by rows) and a
/// translation as `Isometry3`, the unit quaternion by Shepperd's method (from `1 + tr R` where
/// `tr R > 0`, otherwise from the largest of `1 + 2R₀₀ − tr R`, `1 + 2R₁₁ − tr R`, `1 + 2R₂₂ −
/// tr R`, so that the square root's argument is at least 1 and no division is
/// ill-conditioned). Branches, no panic; `sqrt` through `libm` for `no_std`.
pub fn isometry_helper(scalar: Scalar, no_std: bool, nalgebra: &TokenStream) -> TokenStream {
    let t = Ident::new(scalar.as_str(), Span::call_site());
    let na = nalgebra;
    let s = match (no_std, scalar) {
        (false, _) => quote!(a.sqrt()),
        (true, Scalar::F64) => quote!(::libm::sqrt(a)),
        (true, Scalar::F32) => quote!(::libm::sqrtf(a)),
    };
    quote! {
        /// A rotation matrix (rows) and a translation as an isometry; the unit quaternion by
        /// Shepperd's method: from `4w² = 1 + tr R` where `tr R > 0`, otherwise from the
        /// largest of `4x² = 1 + 2R₀₀ − tr R`, `4y²`, `4z²` (at least 1 either way): with that
        /// one `a`, its component is `√a / 2` and the others `(Rᵢⱼ ± Rⱼᵢ) / (2√a)`,
        /// computed as `((Rᵢⱼ ± Rⱼᵢ) · (½ / a)) · √a`, so that the division runs beside the
        /// square root rather than after it. Always in line: a call would pass the matrix and
        /// the isometry through memory, and from a dispatched copy run the baseline's code.
        #[inline(always)]
        fn isometry(r: [[#t; 3]; 3], p: [#t; 3]) -> #na::Isometry3<#t> {
            let [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]] = r;
            let trace = r00 + r11 + r22;
            let (w, x, y, z) = if trace > 0.0 {
                let a = trace + 1.0;
                let (h, s) = (0.5 / a, #s);
                (0.5 * s, (r21 - r12) * h * s, (r02 - r20) * h * s, (r10 - r01) * h * s)
            } else if r00 > r11 && r00 > r22 {
                let a = 1.0 + r00 - r11 - r22;
                let (h, s) = (0.5 / a, #s);
                ((r21 - r12) * h * s, 0.5 * s, (r01 + r10) * h * s, (r02 + r20) * h * s)
            } else if r11 > r22 {
                let a = 1.0 + r11 - r00 - r22;
                let (h, s) = (0.5 / a, #s);
                ((r02 - r20) * h * s, (r01 + r10) * h * s, 0.5 * s, (r12 + r21) * h * s)
            } else {
                let a = 1.0 + r22 - r00 - r11;
                let (h, s) = (0.5 / a, #s);
                ((r10 - r01) * h * s, (r02 + r20) * h * s, (r12 + r21) * h * s, 0.5 * s)
            };
            // A struct literal: `from_parts` would need `RealField`, which nalgebra without
            // its `std` or `libm` feature does not implement.
            #na::Isometry3::<#t> {
                rotation: #na::UnitQuaternion::new_unchecked(#na::Quaternion::new(w, x, y, z)),
                translation: #na::Translation3::new(p[0], p[1], p[2]),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    /// The dispatched body of `mass_matrix` in `code`, whitespace removed.
    fn mass_matrix_body(code: &str) -> String {
        body_of(code, "mass_matrix")
    }

    /// The body of the dispatched function `name`, whitespace removed.
    fn body_of(code: &str, name: &str) -> String {
        let at = code
            .find(&format!("fn {name}_body<"))
            .expect("a dispatched body");
        let body = &code[at..];
        body[..body.find("\n    }\n").expect("its end")]
            .split_whitespace()
            .collect()
    }

    #[test]
    fn zero_writes_are_spread_evenly_among_the_stores() {
        use super::{with_zero_writes, ExprId, Statement};
        // A statement named by its tokens: `t` defines a value, `s` stores, `z` writes zeros.
        let statement = |name: &str, defines: bool| Statement {
            defined: if defines {
                vec![(quote::format_ident!("{}", name), ExprId(0))]
            } else {
                Vec::new()
            },
            tokens: name.parse().expect("an identifier"),
            reads: Vec::new(),
        };
        let body = vec![
            statement("t0", true),
            statement("s0", false),
            statement("t1", true),
            statement("s1", false),
            statement("s2", false),
            statement("t2", true),
            statement("s3", false),
        ];
        let zeros = vec![statement("z0", false), statement("z1", false)];
        let order: Vec<String> = with_zero_writes(body, zeros)
            .iter()
            .map(|s| s.tokens.to_string())
            .collect();
        // Zero j of 2 after store i of 4 (from 1) for the smallest i with 4 j < 2 i.
        assert_eq!(
            order,
            ["t0", "s0", "z0", "t1", "s1", "s2", "z1", "t2", "s3"]
        );
    }

    #[test]
    fn a_store_follows_the_last_statement_it_reads() {
        use super::{stores_early, ExprId, Statement};
        let statement = |defined: &[u32], reads: &[u32]| Statement {
            defined: defined
                .iter()
                .map(|&k| (quote::format_ident!("t{}", k), ExprId(k)))
                .collect(),
            tokens: proc_macro2::TokenStream::new(),
            reads: reads.iter().map(|&k| ExprId(k)).collect(),
        };
        // t0, t1 = f(t0), t2, then stores of t0 (3), of t1 and t2 (4) and of a constant (5).
        let body = vec![
            statement(&[0], &[]),
            statement(&[1], &[0]),
            statement(&[2], &[]),
            statement(&[], &[0]),
            statement(&[], &[1, 2]),
            statement(&[], &[]),
        ];
        // The demand order puts the stores last (4 before 3, as the entries are stored).
        let order = stores_early(&body, vec![2, 0, 1, 4, 3, 5], &[4, 3, 5], 3);
        assert_eq!(order, vec![5, 2, 0, 3, 1, 4]);
    }

    #[test]
    fn a_general_geometry_pose_is_computed_on_packs_of_rows() {
        let code = crate::Builder::new("rand7")
            .no_runtime_trait()
            .functions(["end_effector_pose", "jacobian_space", "gravity"])
            .generate()
            .expect("generates");
        let pose = body_of(&code, "end_effector_pose");
        assert!(pose.contains("Self::v4_fma_with::<WIDE"), "{pose}");
        assert!(pose.contains("Self::isometry([[t0,t3,t6],[t1,t4,t7],[t2,t5,t8]],[t9,t10,t11])"));
        assert!(code.contains("fn v4_fma_with<const WIDE: bool>"));
        assert!(code.contains("_mm256_fmadd_pd"));
        // The Jacobian packs its columns' rows (`ω` and `v`); the dynamics seed from alike
        // outputs, which a chain has none of.
        assert!(body_of(&code, "jacobian_space").contains("Self::v4_fma_with::<WIDE"));
        assert!(!body_of(&code, "gravity").contains("v4_"));
        // Without the dispatch the scalar helpers, no intrinsics; `f32` on `[f32; 4]` packs,
        // 128-bit registers in the dispatched copies; no packs in `no_std` code.
        let plain = crate::Builder::new("rand7")
            .no_runtime_trait()
            .cpu_dispatch(false)
            .functions(["end_effector_pose"])
            .generate()
            .expect("generates");
        assert!(plain.contains("Self::v4_fma(") && !plain.contains("_mm256"));
        let single = crate::Builder::new("rand7")
            .scalar(crate::Scalar::F32)
            .no_runtime_trait()
            .functions(["end_effector_pose"])
            .generate()
            .expect("generates");
        assert!(body_of(&single, "end_effector_pose").contains("Self::v4_fma_with::<WIDE"));
        assert!(single.contains("fn v4_fma_with<const WIDE: bool>(a: [f32; 4]"));
        assert!(single.contains("_mm_fmadd_ps") && !single.contains("_mm256_fmadd_pd"));
        let code = crate::Builder::new("rand7")
            .no_std(true)
            .no_runtime_trait()
            .functions(["end_effector_pose"])
            .generate()
            .expect("generates");
        assert!(!code.contains("v4_"));
    }

    #[test]
    fn a_jacobian_dot_packs_the_rows_of_the_jacobian_it_reads() {
        let dots = ["jacobian_space_dot", "jacobian_body_dot"];
        let generate = |robot: &str| {
            crate::Builder::new(robot)
                .no_runtime_trait()
                .functions(dots)
                .generate()
                .expect("generates")
        };
        // rand7's `J` packs its columns' rows, and so do its `J̇`s, which read them.
        let code = generate("rand7");
        for dot in dots {
            assert!(
                body_of(&code, dot).contains("Self::v4_fma_with::<WIDE"),
                "{dot}"
            );
        }
        // The UR5's `J` packs nothing (no seed saves enough), and its `J̇`s are scalar; so
        // are those of a Jacobian with more than `JACOBIAN_DOT_PACK_COLUMNS` columns.
        let g1 = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/g1_29dof.urdf"
        );
        for code in [generate("ur5"), generate(g1)] {
            for dot in dots {
                assert!(!body_of(&code, dot).contains("v4_"), "{dot}");
            }
        }
    }

    #[test]
    fn packs_of_two_f64_lanes_are_128_bit_operations() {
        let talos = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/talos_upper_body.urdf"
        );
        let generate = |scalar| {
            crate::Builder::new(talos)
                .floating_base(true)
                .scalar(scalar)
                .no_runtime_trait()
                .functions(["gravity"])
                .generate()
                .expect("generates")
        };
        // TALOS' two arms are alike: packs of two lanes, one 128-bit register each in the
        // dispatched copies.
        let code = generate(crate::Scalar::F64);
        let body = body_of(&code, "gravity");
        assert!(body.contains("Self::v2_fma_with::<WIDE") && !body.contains("v4_"));
        assert!(code.contains("fn v2_fma(a: [f64; 4]") && code.contains("_mm_fmadd_pd("));
        // `f32`'s four lanes are one 128-bit register already: the four-lane helpers.
        let single = generate(crate::Scalar::F32);
        let body = body_of(&single, "gravity");
        assert!(body.contains("Self::v4_fma_with::<WIDE") && !body.contains("v2_"));
        assert!(!single.contains("fn v2_"));
    }

    #[test]
    fn only_the_vector_helpers_called_are_written() {
        let code = super::vector_helpers(crate::Scalar::F64, |h| h == "v4_fma" || h == "v2_mul")
            .to_string();
        for name in super::VECTOR_HELPERS {
            let written = code.contains(&format!("fn {name} ("));
            assert_eq!(written, name == "v4_fma" || name == "v2_mul", "{name}");
        }
    }

    /// Solo-12's code on its floating base, `functions` only, no runtime trait.
    fn solo12_floating(functions: &[&str]) -> String {
        let solo = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/solo12.urdf"
        );
        crate::Builder::new(solo)
            .floating_base(true)
            .no_runtime_trait()
            .functions(functions.iter().copied())
            .generate()
            .expect("generates")
    }

    #[test]
    fn m_inverse_m_dot_and_the_pair_with_many_live_values_are_stored_too() {
        let code = solo12_floating(&[
            "mass_matrix_inverse",
            "mass_matrix_dot",
            "mass_matrix_and_bias",
            "gravity_derivative",
        ]);
        for name in ["mass_matrix_inverse", "mass_matrix_dot"] {
            let body = body_of(&code, name);
            assert!(
                body.contains("letmutm:SoloWritten<::nalgebra::SMatrix<f64,18,18>>="),
                "{name}"
            );
            assert!(
                body.ends_with('m') && !body.contains("from_array_storage"),
                "{name}"
            );
        }
        // The pair: `M` into `m.value.0` entry by entry, `c + g` assigned after it.
        let body = body_of(&code, "mass_matrix_and_bias");
        assert!(body.contains(
            "letmutm:SoloWritten<(::nalgebra::SMatrix<f64,18,18>,::nalgebra::SVector<f64,18>),>=SoloWritten{uninit:()};"
        ));
        let (last, bias) = (
            body.find("m.value.0.data.0[17][17]=")
                .expect("the last entry"),
            body.find("m.value.1=::nalgebra::SVector::<f64,18,>::from_array_storage(")
                .expect("the bias"),
        );
        assert!(last < bias && body.ends_with('m'));
        assert_eq!(body.matches("from_array_storage").count(), 1);
        // `∂g/∂q` stays a literal (stored, rand7's was slower).
        let body = body_of(&code, "gravity_derivative");
        assert!(body.contains("from_array_storage") && !body.contains("letmutm="));
    }

    #[test]
    fn the_bias_with_many_live_values_is_stored_the_inverse_dynamics_not() {
        let code = solo12_floating(&["coriolis", "inverse_dynamics"]);
        let body = body_of(&code, "coriolis");
        assert!(body.contains("letmutm:SoloWritten<::nalgebra::SVector<f64,18>>="));
        assert!(body.contains("m.value.data.0[0][17]=") && body.ends_with('m'));
        let body = body_of(&code, "inverse_dynamics");
        assert!(body.contains("from_array_storage") && !body.contains("letmutm="));
        // The UR5's bias keeps few values live: a literal.
        let code = crate::Builder::new("ur5")
            .no_runtime_trait()
            .functions(["coriolis"])
            .generate()
            .expect("generates");
        assert!(!body_of(&code, "coriolis").contains("letmutm="));
        // rand7's bias is stored too, but its 7 entries into a zeroed vector, not the union
        // (`WRITTEN_MIN_ENTRIES`), whose copies return the vector itself; its `M⁻¹`'s 49 into
        // the union.
        let code = crate::Builder::new("rand7")
            .no_runtime_trait()
            .functions(["coriolis", "mass_matrix_inverse"])
            .generate()
            .expect("generates");
        let body = body_of(&code, "coriolis");
        assert!(body.contains("letmutm=::nalgebra::SVector::<f64,7>::zeros();"));
        assert!(body.contains("m.data.0[0][6]=") && !body.contains("unsafe{m"));
        assert!(code.contains("return unsafe { self.coriolis_avx2(q, qd) };"));
        let body = body_of(&code, "mass_matrix_inverse");
        assert!(body.contains("letmutm:Rand7Written<::nalgebra::SMatrix<f64,7,7>>="));
    }

    #[test]
    fn a_mass_matrix_with_many_live_values_is_stored_entry_by_entry_from_the_last() {
        // Solo-12's literal on its floating base would keep 130 values live: stored.
        let solo = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/robots/trees/solo12.urdf"
        );
        let code = crate::Builder::new(solo)
            .floating_base(true)
            .generate()
            .expect("generates");
        let body = mass_matrix_body(&code);
        // Into the struct's union, uninitialised: its copies return it.
        assert!(body.contains(
            "letmutm:SoloWritten<::nalgebra::SMatrix<f64,18,18>>=SoloWritten{uninit:(),};"
        ));
        assert!(!body.contains("from_array_storage") && !body.contains("zeros()"));
        assert!(code.contains("\nunion SoloWritten<T: Copy> {\n"));
        assert!(code.contains("-> SoloWritten<::nalgebra::SMatrix<f64, 18, 18>> {"));
        assert!(code.contains("return unsafe { self.mass_matrix_avx512(q).value };"));
        // Every entry written exactly once (the structural zeros by zero writes), both
        // halves by one statement.
        for r in 0..18 {
            for c in 0..18 {
                assert_eq!(
                    body.matches(&format!("m.value.data.0[{c}][{r}]=")).count(),
                    1,
                    "M{r},{c}"
                );
            }
        }
        // Structural zeros: two legs' joints.
        assert!(
            body.contains("m.value.data.0[6][9]=0.0;"),
            "a structural zero"
        );
        let (last, first) = (
            body.find("m.value.data.0[17][17]=")
                .expect("the last entry"),
            body.find("m.value.data.0[0][0]=").expect("the first"),
        );
        assert!(last < first, "scheduled from the last entry back");
        let store = "m.value.data.0[16][17]=";
        let at = body.find(store).expect("M₁₇,₁₆") + store.len();
        let value = &body[at..at + body[at..].find(';').expect("a statement")];
        assert!(body.contains(&format!(
            "m.value.data.0[16][17]={value};m.value.data.0[17][16]={value};"
        )));
        assert!(body.ends_with('m'), "returns the union");
        // `mass_matrix_lower_into` writes the lower triangle into the caller's matrix and
        // nothing else: no union, no zero writes (and Solo-12's is not parked).
        let lower = body_of(&code, "mass_matrix_lower_into");
        assert!(lower.contains("m.data.0[17][17]="));
        assert!(!lower.contains("unsafe{m.") && !lower.contains("=0.0;"));
        // Without the dispatch, zeroed, and no `unsafe` code.
        for code in [
            crate::Builder::new(solo)
                .floating_base(true)
                .no_std(true)
                .generate()
                .expect("generates"),
            crate::Builder::new(solo)
                .floating_base(true)
                .cpu_dispatch(false)
                .generate()
                .expect("generates"),
        ] {
            assert!(code.contains("let mut m = ::nalgebra::SMatrix::<f64, 18, 18>::zeros();"));
            assert!(!code.contains("Written") && !code.contains("unsafe"));
        }
        // The UR5's literal keeps few values live: kept. rand7's, in level order
        // (`schedule::LEVEL_ORDER`), would keep more than `STORED_MIN_LIVE`: stored.
        let code = crate::Builder::new("ur5").generate().expect("generates");
        let body = mass_matrix_body(&code);
        assert!(body.contains("from_array_storage") && !body.contains("letmutm"));
        let code = crate::Builder::new("rand7").generate().expect("generates");
        let body = mass_matrix_body(&code);
        assert!(!body.contains("from_array_storage") && body.contains("letmutm:Rand7Written"));
    }
}
