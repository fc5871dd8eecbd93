//! [`Lanes`]: `B` values of one scalar type side by side, for the generated `*_batch`
//! functions (structure of arrays across states).

use core::ops::{Add, Div, Mul, Neg, Sub};
use nalgebra::{ArrayStorage, SMatrix, Scalar};

/// `B` values of the scalar `T` (`f64` or `f32`), one per state of a batch: the value type of
/// the generated `*_batch` functions, whose unrolled code is the single-state code with each
/// scalar replaced by a `Lanes`. Every arithmetic operation acts lane by lane on fixed-size
/// arrays, `#[inline(always)]`, so that the compiler vectorises it across the states (4 lanes
/// of `f64` per AVX2 register, 2 per SSE2 register). Where `debug_assertions` are on they are
/// `#[inline]` instead, as the AVX tokens' register methods are: forced into every operation
/// of a large body, they made an unoptimised or opt-level-1 build (the tests') a third slower
/// (G1's four batch functions, `B` = 8, at opt-level 1 with debug assertions: 132 against
/// 98 s). Lanes never mix: lane `l` of a result depends on lane `l` of the operands only, and
/// gives the same bits as the scalar code's operation on that state. A scalar operand (a constant of the robot, a run-time parameter)
/// acts on every lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<T, const B: usize>(pub [T; B]);

impl<T: Copy, const B: usize> Lanes<T, B> {
    /// Every lane `x`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn splat(x: T) -> Self {
        Self([x; B])
    }

    /// `f` applied lane by lane.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn map(self, f: impl Fn(T) -> T) -> Self {
        let mut out = self.0;
        for o in &mut out {
            *o = f(*o);
        }
        Self(out)
    }

    /// The `K` values of each of the `B` states (`xs[l][k]`, state `l`, coordinate `k`) as `K`
    /// lanes (`out[k].0[l]`): the transpose into structure of arrays. Inlined: out of line, its
    /// narrow stores were read back by the batch body's wide loads, which waited for them
    /// (measured: a UR5 batch of 8 in AVX-512, 39 ns per state out of line, 31 inlined). Plain
    /// loops with no indexing the optimiser must prove in range, and no `array::from_fn`
    /// (whose drop guard is a cleanup path): `no_panic` sees no panic through it.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn gather<const K: usize>(xs: &[[T; K]; B]) -> [Self; K]
    where
        T: Default,
    {
        let mut out = [Self([T::default(); B]); K];
        for (l, x) in xs.iter().enumerate() {
            for (o, &v) in out.iter_mut().zip(x) {
                if let Some(slot) = o.0.get_mut(l) {
                    *slot = v;
                }
            }
        }
        out
    }

    /// Columns of lanes (`cols[c][r].0[l]`) back to one `R × C` matrix per state (entry
    /// `(r, c)` of matrix `l`): the transpose out of structure of arrays. Not inlined: the
    /// batch body stores whole lanes, which the vectoriser writes as vectors (strided stores
    /// of single lanes would leave the body scalar; inlined, it was slower: a UR5 mass matrix batch
    /// of 8, 34 ns per state out of line, 54 inlined). `extern "C"`, so that a caller knows it
    /// cannot unwind without seeing its body (which has no panic path): a Rust-ABI function left
    /// out of line counts as a possible panic for `no_panic`.
    ///
    /// Up to 8 × 8, nested `array::map`s, which the optimiser unrolls into straight-line copies
    /// (measured: a UR5 mass matrix batch of 8, 17.1 ns per state, against 23–24 with loops).
    /// Larger, plain loops. There (a humanoid's 35-vector of gravity torques) the maps were left
    /// out of line, calling their closures through pointers, and the `extern "C"` body held an
    /// abort path (`panic_cannot_unwind`), which the `no_panic` test's machine-code check
    /// found. Batches of 8 with the loops, against the maps: G1's mass matrix −14 %, forward
    /// dynamics −8 %, gravity −17 %, Solo-12's mass matrix −16 %, the others within ±3 %.
    #[inline(never)]
    #[must_use]
    #[allow(improper_ctypes_definitions)] // called from Rust only
    pub extern "C" fn scatter<const R: usize, const C: usize>(
        cols: &[[Self; R]; C],
    ) -> [SMatrix<T, R, C>; B]
    where
        T: Default + Scalar,
    {
        if R <= 8 && C <= 8 {
            return core::array::from_fn(|l| {
                SMatrix::from_array_storage(ArrayStorage(cols.each_ref().map(|col| {
                    col.each_ref()
                        .map(|x| x.0.get(l).copied().unwrap_or_default())
                })))
            });
        }
        Self::scatter_loops(cols)
    }

    /// [`Self::scatter`]'s transpose as plain loops (its form for matrices over 8 × 8, and
    /// [`Self::scatter_column`]'s): each lane array read once, its values written to the `B`
    /// matrices.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn scatter_loops<const R: usize, const C: usize>(cols: &[[Self; R]; C]) -> [SMatrix<T, R, C>; B]
    where
        T: Default + Scalar,
    {
        let mut out = [SMatrix::from_array_storage(ArrayStorage([[T::default(); R]; C])); B];
        for (c, col) in cols.iter().enumerate() {
            for (r, lanes) in col.iter().enumerate() {
                for (m, &v) in out.iter_mut().zip(&lanes.0) {
                    if let Some(x) = m.data.0.get_mut(c).and_then(|m_col| m_col.get_mut(r)) {
                        *x = v;
                    }
                }
            }
        }
        out
    }

    /// [`Self::scatter`] of one column, inlined: one `R`-vector per state, for the generated
    /// AVX2 bodies of instructions, whose results are whole registers already, so that inlined
    /// it cannot turn a vectorised body scalar (the reason `scatter` stays out of line for the
    /// vectoriser's bodies). In line, the optimiser writes each state's vector by shuffles of
    /// the registers, where `scatter` has the body store its registers, reads them back one lane
    /// at a time and copies its result to the caller's. Measured on a Zen 3 (default profile,
    /// the old and new generated code in one binary, `B` = 8, per state, two runs): the UR5's
    /// inverse dynamics 30.2 → 28.5 and 29.8 → 28.5 ns, the Panda's 45.1 → 42.3 and 45.1 →
    /// 42.0 ns; callgrind 264 → 254 and 420 → 411 instructions (`docs/performance.md`). Plain
    /// loops (`scatter_loops`, [`Self::scatter`]'s for large matrices), as in [`Self::gather`],
    /// for `no_panic`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn scatter_column<const R: usize>(cols: &[[Self; R]; 1]) -> [SMatrix<T, R, 1>; B]
    where
        T: Default + Scalar,
    {
        Self::scatter_loops(cols)
    }

    /// A function of an array to two arrays of the same length (such as the sines and
    /// cosines of all its elements) applied to each of `args`, all `B` lanes at once.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn each2<const K: usize>(
        args: [Self; K],
        f: impl Fn([T; B]) -> ([T; B], [T; B]),
    ) -> ([Self; K], [Self; K]) {
        // Loops rather than `array::map`: a large `f` (the sine-cosine kernel) inside `map`'s
        // closure machinery was left out of line, and a call the caller cannot see into counts
        // as a possible panic for `no_panic`.
        let (mut first, mut second) = (args, args);
        for ((a, s), c) in args.iter().zip(&mut first).zip(&mut second) {
            let (x, y) = f(a.0);
            (s.0, c.0) = (x, y);
        }
        (first, second)
    }
}

impl<T: Copy, const B: usize> From<T> for Lanes<T, B> {
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn from(x: T) -> Self {
        Self::splat(x)
    }
}

macro_rules! lane_ops {
    ($($t:ty),*) => {$(
        lane_ops!(@op $t, Add, add, +);
        lane_ops!(@op $t, Sub, sub, -);
        lane_ops!(@op $t, Mul, mul, *);
        lane_ops!(@op $t, Div, div, /);
        impl<const B: usize> Neg for Lanes<$t, B> {
            type Output = Self;
            #[cfg_attr(debug_assertions, inline)]
            #[cfg_attr(not(debug_assertions), inline(always))]
            fn neg(self) -> Self {
                Self(self.0.map(|a| -a))
            }
        }
    )*};
    (@op $t:ty, $trait:ident, $f:ident, $op:tt) => {
        impl<const B: usize> $trait for Lanes<$t, B> {
            type Output = Self;
            #[cfg_attr(debug_assertions, inline)]
            #[cfg_attr(not(debug_assertions), inline(always))]
            #[allow(clippy::assign_op_pattern)] // `$op`, not `$op=`: the same macro for all four
            fn $f(self, rhs: Self) -> Self {
                let mut out = self.0;
                for (o, r) in out.iter_mut().zip(rhs.0) {
                    *o = *o $op r;
                }
                Self(out)
            }
        }
        impl<const B: usize> $trait<$t> for Lanes<$t, B> {
            type Output = Self;
            #[cfg_attr(debug_assertions, inline)]
            #[cfg_attr(not(debug_assertions), inline(always))]
            fn $f(self, rhs: $t) -> Self {
                Self(self.0.map(|a| a $op rhs))
            }
        }
        impl<const B: usize> $trait<Lanes<$t, B>> for $t {
            type Output = Lanes<$t, B>;
            #[cfg_attr(debug_assertions, inline)]
            #[cfg_attr(not(debug_assertions), inline(always))]
            fn $f(self, rhs: Lanes<$t, B>) -> Lanes<$t, B> {
                Lanes(rhs.0.map(|b| self $op b))
            }
        }
    };
}

lane_ops!(f32, f64);

#[cfg(test)]
mod tests {
    use super::Lanes;

    #[test]
    fn lanes_act_lane_by_lane() {
        let a = Lanes([1.0f64, 2.0, 3.0, 4.0]);
        let b = Lanes([0.5f64, -1.0, 2.0, 8.0]);
        assert_eq!((a + b).0, [1.5, 1.0, 5.0, 12.0]);
        assert_eq!((a - b).0, [0.5, 3.0, 1.0, -4.0]);
        assert_eq!((a * b).0, [0.5, -2.0, 6.0, 32.0]);
        assert_eq!((a / b).0, [2.0, -2.0, 1.5, 0.5]);
        assert_eq!((-a).0, [-1.0, -2.0, -3.0, -4.0]);
        assert_eq!((2.0 * a).0, [2.0, 4.0, 6.0, 8.0]);
        assert_eq!((a - 1.0).0, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!((1.0 - a).0, [0.0, -1.0, -2.0, -3.0]);
        assert_eq!((12.0 / a).0, [12.0, 6.0, 4.0, 3.0]);
        assert_eq!(Lanes::<f32, 3>::from(2.5).0, [2.5; 3]);
        assert_eq!(a.map(|x| x * x).0, [1.0, 4.0, 9.0, 16.0]);
    }

    #[test]
    fn gather_and_scatter_are_transposes() {
        let states = [[1.0f64, 2.0], [3.0, 4.0], [5.0, 6.0]];
        let lanes = Lanes::gather(&states);
        assert_eq!(lanes[0].0, [1.0, 3.0, 5.0]);
        assert_eq!(lanes[1].0, [2.0, 4.0, 6.0]);
        let back = Lanes::scatter(&[lanes]);
        assert_eq!(
            back.map(|m| m.data.0),
            [[[1.0, 2.0]], [[3.0, 4.0]], [[5.0, 6.0]]]
        );
        assert_eq!(Lanes::scatter_column(&[lanes]), back);
        let (s, c) = Lanes::each2(lanes, |x: [f64; 3]| (x.map(|v| v + 1.0), x.map(|v| -v)));
        assert_eq!(s[1].0, [3.0, 5.0, 7.0]);
        assert_eq!(c[0].0, [-1.0, -3.0, -5.0]);
    }
}
