//! The order of a function body's `let` statements: demand-driven, to shorten live ranges.
//!
//! The graph creates nodes in the order of the recursion (a forward pass over every link, then
//! a backward one), and a `let` written where its node was created can stay live across most
//! of the body: the Newton–Euler forward pass computes each link's velocity, acceleration and
//! force terms long before the backward pass reads them. Compilers keep the source order of
//! straight-line code (LLVM's x86 back end schedules a block in source order before register
//! allocation), so on the 16 vector registers of the default x86-64 target such a body spills
//! hundreds of values to the stack.
//!
//! The schedule here is a depth-first post-order from the outputs (Sethi & Ullman, "The
//! generation of optimal code for arithmetic expressions", JACM 1970, for trees): each output
//! in turn, before a statement the statements it reads, the operand whose still-unscheduled
//! cone is larger first, so that its result is the one held while the smaller cone is
//! computed. Every statement keeps its tokens, so values and their rounding are unchanged:
//! only the order of the `let`s changes.

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

#[cfg(test)]
mod tests {
    use super::*;

    fn deps(reads: &[&[usize]]) -> Vec<Deps> {
        reads.iter().map(|r| Deps { reads: r.to_vec() }).collect()
    }

    #[test]
    fn every_statement_once_after_what_it_reads() {
        // 0, 1 leaves; 2 = f(0, 1); 3 = f(0); 4 = f(2, 3); 5 unreached by the roots.
        let d = deps(&[&[], &[], &[0, 1], &[0], &[2, 3], &[1]]);
        let order = demand_order(&d, &[4]);
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
        assert_eq!(order.last(), Some(&5));
    }

    #[test]
    fn values_are_computed_where_they_are_needed() {
        // Creation order computes both leaves 0 and 1 first; demand order computes 0's user
        // before 1.
        let d = deps(&[&[], &[], &[0], &[1], &[2, 3]]);
        assert_eq!(demand_order(&d, &[4]), vec![0, 2, 1, 3, 4]);
    }
}
