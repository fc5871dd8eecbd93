//! The order of a function body's `let` statements: demand-driven, to shorten live ranges
//! ([`demand_order`]), or highest level first, for instruction-level parallelism
//! ([`level_order`], the bodies of [`LEVEL_ORDER`]).
//!
//! The graph creates nodes in the order of the recursion (a forward pass over every link, then
//! a backward one), and a `let` written where its node was created can stay live across most
//! of the body: the Newton–Euler forward pass computes each link's velocity, acceleration and
//! force terms long before the backward pass reads them. Compilers keep the source order of
//! straight-line code (LLVM's x86 back end schedules a block in source order before register
//! allocation), so on the 16 vector registers of the default x86-64 target such a body spills
//! hundreds of values to the stack.
//!
//! [`demand_order`] is a depth-first post-order from the outputs (Sethi & Ullman, "The
//! generation of optimal code for arithmetic expressions", JACM 1970, for trees): each output
//! in turn, before a statement the statements it reads, the operand whose still-unscheduled
//! cone is larger first, so that its result is the one held while the smaller cone is
//! computed. [`level_order`] is a list schedule by levels (the longest chain of statements
//! to an output first): it interleaves the outputs' cones, so that more values are live at
//! once, but the long chains start early; the inverse dynamics and a mass matrix returned by
//! value ran faster so ([`LEVEL_ORDER`]), every other body slower. Either way every statement
//! keeps its tokens, so values and their rounding are unchanged: only the order of the `let`s
//! changes.

/// How a body's statements are ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// [`demand_order`].
    Demand,
    /// [`level_order`] (where no statements must come first; [`demand_order`] there).
    Level,
}

/// The functions whose bodies are ordered by [`level_order`]: the inverse dynamics (the
/// recursive Newton–Euler algorithm) and the mass matrix returned by value (the
/// composite-rigid-body algorithm; a stored one keeps [`demand_order`]). Measured on an AMD
/// Zen 3, the AVX2 copies (`docs/performance.md`, sixty-fifth session): two copies each of the
/// old and new inverse dynamics in one scratch binary, medians of 11 rounds, two runs: rand7
/// −7.3 %, the Panda −5 %, G1 (floating base) −2 to −3 %, the UR5 +0.6 %, Solo-12 −0.5 %
/// (TALOS' upper body −24 %, a body at the op cache's edge: placement); the AVX2 copies'
/// instructions rand7 1,181 → 1,132, the Panda 907 → 885, G1 3,523 → 3,507. In the benchmark
/// binary against HEAD's, seven side-by-side runs of each, the medians of the ratios (two
/// builds): inverse dynamics rand7 −4.8 and −6.4 %, G1 −3.7 and −5.3 %, the Panda −4.2 and
/// −4.0 %; rand7's mass matrix −9.7 and −13 % (1,066 → 978 instructions; now stored entry by
/// entry, as its literal keeps more values live in level order: `STORED_MIN_LIVE`). Left in
/// demand order: the inverse dynamics with a tip wrench (rand7's 1,164 → 1,241 instructions in
/// level order, its time within the noise), and every other body, where level order lost (a
/// benchmark binary with every body so): G1's forward dynamics 8,659 → 10,646 instructions and
/// +42 %, TALOS' +12.5 % (the articulated-body algorithm's long-lived values spill more), the
/// UR5's `J_s` +16 %, rand7's +4.6 %, the `J̇`s +2 to +6 %, constrained forward dynamics +6 %,
/// the derivatives +2 to +5 %.
pub const LEVEL_ORDER: &[&str] = &["inverse_dynamics", "mass_matrix"];

/// A statement of the body for scheduling: the statements whose values it reads.
pub struct Deps {
    /// Indices (into the body in creation order) of the statements it reads.
    pub reads: Vec<usize>,
}

/// A demand-driven order of `deps` (a permutation of `0..deps.len()` in which every statement
/// comes after the ones it reads), from `roots` (the statements the outputs read, in output
/// order); any statement no root reaches (none, in a body of live nodes) follows, from
/// creation order.
pub fn demand_order(deps: &[Deps], roots: &[usize]) -> Vec<usize> {
    let n = deps.len();
    // The size of each statement's cone (itself and what it reads, transitively), counting
    // shared statements once per path but capped, as a cheap estimate of its register need.
    const CAP: u32 = 1 << 20;
    // Creation order is topological (operands first), so one pass computes them.
    let mut cone: Vec<u32> = Vec::with_capacity(n);
    for d in deps {
        let size = d
            .reads
            .iter()
            .map(|&r| cone.get(r).copied().unwrap_or(1))
            .fold(1u32, |a, b| (a + b).min(CAP));
        cone.push(size);
    }
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    // Iterative post-order (bodies reach tens of thousands of statements).
    let mut stack: Vec<(usize, Vec<usize>)> = Vec::new();
    let operands = |i: usize, placed: &[bool]| {
        let mut ops: Vec<usize> = deps[i]
            .reads
            .iter()
            .copied()
            .filter(|&r| !placed[r])
            .collect();
        ops.sort_unstable();
        ops.dedup();
        // Larger cone first; ties in creation order. Reversed: popped from the end.
        ops.sort_by(|&a, &b| cone[a].cmp(&cone[b]).then(b.cmp(&a)));
        ops
    };
    for root in roots.iter().copied().chain(0..n) {
        if placed[root] {
            continue;
        }
        stack.push((root, operands(root, &placed)));
        while let Some((i, ops)) = stack.last_mut() {
            let i = *i;
            match ops.pop() {
                Some(o) if !placed[o] => {
                    let next = operands(o, &placed);
                    stack.push((o, next));
                }
                Some(_) => {}
                None => {
                    stack.pop();
                    if !placed[i] {
                        placed[i] = true;
                        order.push(i);
                    }
                }
            }
        }
    }
    order
}

/// A list order by levels (Hu, "Parallel sequencing and assembly line problems", Operations
/// Research 1961: highest level first): a statement's level is the length of the longest
/// chain of statements from it to one that no statement reads; among the statements whose
/// operands are placed, the one of highest level comes next, ties in creation order. The
/// longest chains start as early as their operands allow, and independent chains interleave,
/// where [`demand_order`] finishes one output's cone before it starts the next's.
pub fn level_order(deps: &[Deps]) -> Vec<usize> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let n = deps.len();
    // Creation order is topological (operands first): levels in one pass from the end.
    let mut level = vec![0u32; n];
    for i in (0..n).rev() {
        for &r in &deps[i].reads {
            level[r] = level[r].max(level[i] + 1);
        }
    }
    let mut pending = vec![0usize; n];
    let mut readers: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, d) in deps.iter().enumerate() {
        let mut reads = d.reads.clone();
        reads.sort_unstable();
        reads.dedup();
        pending[i] = reads.len();
        for r in reads {
            readers[r].push(i);
        }
    }
    let mut ready: BinaryHeap<(u32, Reverse<usize>)> = (0..n)
        .filter(|&i| pending[i] == 0)
        .map(|i| (level[i], Reverse(i)))
        .collect();
    let mut order = Vec::with_capacity(n);
    while let Some((_, Reverse(i))) = ready.pop() {
        order.push(i);
        for &u in &readers[i] {
            pending[u] -= 1;
            if pending[u] == 0 {
                ready.push((level[u], Reverse(u)));
            }
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deps(reads: &[&[usize]]) -> Vec<Deps> {
        reads.iter().map(|r| Deps { reads: r.to_vec() }).collect()
    }

    /// `order` is a permutation of `d`'s statements with every statement after what it reads.
    fn assert_every_statement_once_after_its_operands(d: &[Deps], order: &[usize]) {
        assert_eq!(order.len(), d.len(), "every statement");
        let mut pos = vec![usize::MAX; d.len()];
        for (p, &i) in order.iter().enumerate() {
            assert_eq!(pos[i], usize::MAX, "statement {i} twice");
            pos[i] = p;
        }
        for (i, s) in d.iter().enumerate() {
            for &r in &s.reads {
                assert!(pos[r] < pos[i], "{i} before its operand {r}");
            }
        }
    }

    #[test]
    fn every_statement_once_after_what_it_reads() {
        // 0, 1 leaves; 2 = f(0, 1); 3 = f(0); 4 = f(2, 3); 5 unreached by the roots.
        let d = deps(&[&[], &[], &[0, 1], &[0], &[2, 3], &[1]]);
        let order = demand_order(&d, &[4]);
        assert_every_statement_once_after_its_operands(&d, &order);
        assert_eq!(order.last(), Some(&5));
    }

    #[test]
    fn levels_put_the_longest_chain_first() {
        // 0 → 1 → 2 → 5 (a chain of four), 3 → 4 (two), both read by 5; 6 unread.
        let d = deps(&[&[], &[0], &[1], &[], &[3], &[2, 4], &[]]);
        let order = level_order(&d);
        assert_eq!(order, vec![0, 1, 3, 2, 4, 5, 6]);
        assert_every_statement_once_after_its_operands(&d, &order);
    }

    #[test]
    fn values_are_computed_where_they_are_needed() {
        // Creation order computes both leaves 0 and 1 first; demand order computes 0's user
        // before 1.
        let d = deps(&[&[], &[], &[0], &[1], &[2, 3]]);
        assert_eq!(demand_order(&d, &[4]), vec![0, 2, 1, 3, 4]);
    }
}
