//! Long-lived values parked in memory of the body's own.
//!
//! A value that a long body reads again [`GAP`] statements or more after its definition (or
//! its last read) is written, just after its definition, into a buffer local to the body,
//! and read back (`let t = …;`, shadowing the name) just before the read after the gap. The
//! buffer is written through one copy of its address and read through another, both passed
//! through `core::hint::black_box` at the top of the body (before anything is written, so the
//! barrier orders nothing): the optimiser cannot tell that the two point to the same memory,
//! so it cannot forward a write to its read and keeps the value in memory, as written.
//!
//! Why: such values are spilled anyway (the articulated-body algorithm's pass-2 results wait
//! for pass 3), and the register allocator addresses its spill slots from `rsp`, which costs
//! a SIB byte on every access and, in a frame of kilobytes, a 32-bit displacement: G1's forward
//! dynamics (floating base) made 2,621 of its 7,926 instructions address the stack, 2,167 of
//! them with 32-bit displacements, and ran at the rate this core fetches straight-line code
//! from beyond its 32 KB instruction cache (`docs/performance.md`, fifty-ninth session). The
//! buffer is addressed from a register (no SIB byte), and the values' reads land next to
//! their uses, freeing registers across the gap. Measured (the AVX-512 copies, scratch
//! binaries with old and new code twice each, medians of 9–11 interleaved rounds,
//! 2026-12-07, Zen 4; `docs/performance.md`, sixtieth session): G1's forward dynamics 55,472
//! → 51,232 bytes, 7,944 → 7,550 instructions, 966–971 → 886 ns (−8.6 %), the same bits; the
//! gap tried from 50 to 1,000 statements (150–300 best). A `black_box` barrier before each
//! read instead of the two addresses: +3 % (the barriers order every memory access); volatile
//! reads: +11 %.
//!
//! Where: only in the bodies of [`PARKED`] of [`MIN_STATEMENTS`] statements or more, where it
//! was measured to gain. Elsewhere it lost: a parked value's write and read add a store's
//! forwarding to its path (and this core forwards a spill slot's store to its reload through
//! `rsp` at no cost), which bodies bound by latency rather than by fetching their code pay:
//! TALOS' task-space bias +95 %, Solo-12's forward dynamics (602 statements) +41 %, G1's
//! inverse dynamics (927 statements, 27 KB of code) +13 %, the factor-based `M⁻¹`, `Λ` and
//! the forward dynamics with a tip wrench +4 to +6 %. Parking only the values whose reader is
//! ready long after them (a latency model's slack of 40 cycles) lost G1's gain (+3 %).
//!
//! Only in bodies that are dispatched to CPU copies (`std`, CPU dispatch on), which carry
//! `#[allow(unsafe_code)]` already: the writes and reads are `unsafe` (a raw pointer into an
//! uninitialised buffer, each slot read only after its write: reads follow writes in the one
//! straight-line body), and a buffer initialised instead would cost its zeroing.

use super::function::Statement;
use crate::expr::ExprId;
use crate::options::Scalar;
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

/// A value read again this many statements or more after its definition or its last read is
/// parked (see the module's measurements).
pub(super) const GAP: usize = 150;

/// Bodies of fewer statements are left as they are (every arm's; Solo-12's forward dynamics,
/// 602 statements, ran 41 % slower parked).
pub(super) const MIN_STATEMENTS: usize = 1000;

/// The functions whose bodies are parked: the forward dynamics (the articulated-body
/// algorithm) and the mass matrices (the composite-rigid-body algorithm) of large trees,
/// fetch-bound. Measured, old → new, G1 (floating base) and TALOS' upper body: the forward
/// dynamics −8.6 % and −9 %, `mass_matrix_dot` −7 % and −24 %, `mass_matrix_and_bias` −7 %
/// and −16 %; G1's `mass_matrix` −10 % and `mass_matrix_lower_into` −7 % (TALOS' mass
/// matrix, 643 statements, is not parked).
pub(super) const PARKED: &[&str] = &[
    "forward_dynamics",
    "mass_matrix",
    "mass_matrix_lower_into",
    "mass_matrix_dot",
    "mass_matrix_and_bias",
];

/// What a named value is: a scalar, or a pack of two lanes (`f64`, the `v2_…` packs of
/// [`super::function`]: `[a, b, 0, 0]`, two stored) or of four.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Width {
    One,
    Two,
    Four,
}

impl Width {
    fn lanes(self) -> usize {
        match self {
            Width::One => 1,
            Width::Two => 2,
            Width::Four => 4,
        }
    }
}

/// `body` with its long-lived values parked (see the module), and the statements that make
/// the buffer (empty when nothing is parked); `last_use` renumbered to the new body, with an
/// entry for each new binding.
pub(super) fn park(
    body: Vec<Statement>,
    last_use: &mut Vec<usize>,
    width: impl Fn(ExprId) -> Width,
    scalar: Scalar,
) -> (TokenStream, Vec<Statement>) {
    // Per node, the statements that read it, in order.
    let mut reads: Vec<Vec<usize>> = vec![Vec::new(); last_use.len()];
    for (at, s) in body.iter().enumerate() {
        for &id in &s.reads {
            let r = &mut reads[id.index()];
            if r.last() != Some(&at) {
                r.push(at);
            }
        }
    }
    let t = Ident::new(scalar.as_str(), Span::call_site());
    // Per statement, the writes after it and the reads before it.
    let mut writes: Vec<Vec<(ExprId, TokenStream)>> = vec![Vec::new(); body.len()];
    let mut loads: Vec<Vec<(Ident, ExprId, TokenStream)>> = vec![Vec::new(); body.len()];
    let mut len = 0usize;
    for (at, s) in body.iter().enumerate() {
        for (name, id) in &s.defined {
            let mut last = at;
            let mut after_gaps = Vec::new();
            for &r in &reads[id.index()] {
                if r >= last + GAP {
                    after_gaps.push(r);
                }
                last = r;
            }
            if after_gaps.is_empty() {
                continue;
            }
            let w = width(*id);
            let offset = len.next_multiple_of(w.lanes());
            len = offset + w.lanes();
            let k = Literal::usize_unsuffixed(offset);
            let (write, load) = match w {
                Width::One => (
                    quote!(unsafe { park_w.add(#k).write(#name) };),
                    quote!(let #name = unsafe { park_r.add(#k).read() };),
                ),
                Width::Two => (
                    quote!(unsafe { park_w.add(#k).cast::<[#t; 2]>().write([#name[0], #name[1]]) };),
                    quote! {
                        let #name = {
                            let [a, b] = unsafe { park_r.add(#k).cast::<[#t; 2]>().read() };
                            [a, b, 0.0, 0.0]
                        };
                    },
                ),
                Width::Four => (
                    quote!(unsafe { park_w.add(#k).cast::<[#t; 4]>().write(#name) };),
                    quote!(let #name = unsafe { park_r.add(#k).cast::<[#t; 4]>().read() };),
                ),
            };
            writes[at].push((*id, write));
            for r in after_gaps {
                loads[r].push((name.clone(), *id, load.clone()));
            }
        }
    }
    if len == 0 {
        return (TokenStream::new(), body);
    }
    // Each value read back is a new binding of its name, with an id of its own (after the
    // graph's) so that the blocks of `super::function::chunked` export each binding only as
    // far as it is read; the statements after it read that id.
    let nodes = last_use.len();
    let mut current: Vec<ExprId> = (0..nodes as u32).map(ExprId).collect();
    let mut parked = Vec::with_capacity(body.len());
    for (at, mut s) in body.into_iter().enumerate() {
        for (name, id, tokens) in std::mem::take(&mut loads[at]) {
            let binding = ExprId(last_use.len() as u32);
            last_use.push(0);
            current[id.index()] = binding;
            parked.push(Statement {
                defined: vec![(name, binding)],
                tokens,
                reads: Vec::new(),
            });
        }
        for id in &mut s.reads {
            *id = current[id.index()];
        }
        parked.push(s);
        for (id, tokens) in std::mem::take(&mut writes[at]) {
            parked.push(Statement {
                defined: Vec::new(),
                tokens,
                reads: vec![id],
            });
        }
    }
    // The outputs (`usize::MAX`) read the last binding of each name.
    for id in 0..nodes {
        if last_use[id] == usize::MAX && current[id].index() != id {
            last_use[current[id].index()] = usize::MAX;
            last_use[id] = 0;
        }
    }
    super::function::renumber_last_uses(&parked, last_use);
    let len = Literal::usize_unsuffixed(len);
    let prelude = quote! {
        #[repr(C, align(16))]
        struct Parked([#t; #len]);
        let mut parked = ::core::mem::MaybeUninit::<Parked>::uninit();
        let park_w: *mut #t = ::core::hint::black_box(parked.as_mut_ptr().cast());
        let park_r: *const #t = ::core::hint::black_box(park_w);
    };
    (prelude, parked)
}

#[cfg(test)]
mod tests {
    use super::{park, Width, GAP, MIN_STATEMENTS};
    use crate::expr::ExprId;
    use crate::options::Scalar;
    use quote::{format_ident, quote};

    /// `let t{k} = …;` reading `reads`, or a statement defining nothing.
    fn statement(defined: Option<u32>, reads: &[u32]) -> super::Statement {
        super::Statement {
            defined: defined
                .map(|k| (format_ident!("t{}", k), ExprId(k)))
                .into_iter()
                .collect(),
            tokens: match defined {
                Some(k) => {
                    let t = format_ident!("t{}", k);
                    quote!(let #t = 0.0;)
                }
                None => quote!(other();),
            },
            reads: reads.iter().map(|&k| ExprId(k)).collect(),
        }
    }

    #[test]
    fn a_value_read_again_after_the_gap_is_written_once_and_read_back_before_that_read() {
        // t0 read at 1 and again at GAP + 1 (parked); t1 read at 2 and GAP (not: its reads
        // are never GAP apart); t2, a pack of two lanes, read at GAP + 5 and GAP + 6 (parked,
        // read back once); t3 read at the end only, by the outputs (not parked).
        let n = MIN_STATEMENTS;
        let mut body: Vec<_> = (0..n).map(|_| statement(None, &[])).collect();
        body[0] = statement(Some(0), &[]);
        body[1] = statement(Some(1), &[0]);
        body[2] = statement(Some(2), &[1]);
        body[3] = statement(Some(3), &[]);
        body[GAP] = statement(None, &[1]);
        body[GAP + 1] = statement(None, &[0]);
        body[GAP + 5] = statement(None, &[2]);
        body[GAP + 6] = statement(None, &[2, 0]);
        let mut last_use = vec![0, GAP, GAP + 6, usize::MAX];
        last_use[0] = GAP + 6;
        let width = |id: ExprId| if id.0 == 2 { Width::Two } else { Width::One };
        let (buffer, parked) = park(body, &mut last_use, width, Scalar::F64);
        let text: Vec<String> = parked.iter().map(|s| s.tokens.to_string()).collect();
        let find = |needle: &str| -> Vec<usize> {
            (0..text.len())
                .filter(|&k| text[k].contains(needle))
                .collect()
        };
        // Writes just after the definitions: t0 at slot 0, t2 at slot 2 (a pair, aligned).
        assert_eq!(find("park_w"), vec![1, 4]);
        assert!(
            text[1].contains("park_w . add (0) . write (t0)"),
            "{}",
            text[1]
        );
        assert!(
            text[4].contains("park_w . add (2) . cast :: < [f64 ; 2] >"),
            "{}",
            text[4]
        );
        // Read back once each, just before the first read after the gap: t0 before the
        // statement that was GAP + 1, t2 before GAP + 5 (its read at GAP + 6 follows).
        // Each read back is a binding of its own (ids 4 and 5), which the later reads read.
        let loads = find("park_r");
        assert_eq!(loads.len(), 2, "{text:?}");
        assert!(text[loads[0]].starts_with("let t0 ="));
        assert_eq!(
            parked[loads[0]].defined,
            vec![(format_ident!("t0"), ExprId(4))]
        );
        assert_eq!(parked[loads[0] + 1].reads, vec![ExprId(4)]);
        assert!(text[loads[1]].starts_with("let t2 ="));
        assert_eq!(
            parked[loads[1]].defined,
            vec![(format_ident!("t2"), ExprId(5))]
        );
        assert_eq!(parked[loads[1] + 1].reads, vec![ExprId(5)]);
        assert_eq!(parked[loads[1] + 2].reads, vec![ExprId(5), ExprId(4)]);
        // Nothing else added; the last uses renumbered (t0's first binding is last read by
        // t1's statement, t2's by its write); the buffer holds the four slots.
        assert_eq!(parked.len(), n + 4);
        let end = loads[1] + 2;
        assert_eq!(last_use, vec![2, loads[0] - 1, 4, usize::MAX, end, end]);
        let buffer = buffer.to_string();
        assert!(buffer.contains("struct Parked ([f64 ; 4])"), "{buffer}");
        assert!(buffer.contains("black_box"));
    }

    #[test]
    fn a_body_without_long_gaps_is_left_as_it_is() {
        let body: Vec<_> = (0..MIN_STATEMENTS as u32)
            .map(|k| statement(Some(k), &k.checked_sub(1).into_iter().collect::<Vec<_>>()))
            .collect();
        let mut last_use: Vec<usize> = (0..MIN_STATEMENTS).map(|k| k + 1).collect();
        let before = last_use.clone();
        let (buffer, parked) = park(body, &mut last_use, |_| Width::One, Scalar::F64);
        assert!(buffer.is_empty());
        assert_eq!(parked.len(), MIN_STATEMENTS);
        assert_eq!(last_use, before);
    }
}
