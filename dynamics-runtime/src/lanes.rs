//! [`Lanes`]: `B` values of one scalar type side by side, for the generated `*_batch`
//! functions (structure of arrays across states).

use core::mem::MaybeUninit;
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
    /// The matrices are written where the caller wants its result, by [`Self::scatter_fill`]
    /// into this function's return slot, never built in a local and copied: the optimiser
    /// hands `scatter_fill` the return slot itself (LLVM's call-slot optimisation: `out` is
    /// uninitialised, written by the call and then only moved), whatever it makes of the
    /// loops. The earlier form, nested `array::map`s inside `array::from_fn`, wrote into the
    /// return slot only where the optimiser unrolled all `B` matrices: it did in a small crate,
    /// and in the test crate's benchmark it kept a loop over the matrices, built them in its
    /// frame and copied them out, 3,136 bytes for a batch of eight 7 × 7 mass matrices, which
    /// glibc copies with `rep movsb` above 2 KB, at a speed that on a Zen 3 depends on where the
    /// two buffers lie: rand7's mass-matrix batch took 1,832 ns in one build and 678 ns with
    /// `rep movsb` turned off (`GLIBC_TUNABLES=glibc.cpu.x86_rep_movsb_threshold=1000000`),
    /// 0.66× of eight single calls against 1.68×.
    #[inline(never)]
    #[must_use]
    #[allow(improper_ctypes_definitions)] // called from Rust only
    #[allow(unsafe_code)]
    pub extern "C" fn scatter<const R: usize, const C: usize>(
        cols: &[[Self; R]; C],
    ) -> [SMatrix<T, R, C>; B]
    where
        T: Scalar,
    {
        let mut out = MaybeUninit::<[SMatrix<T, R, C>; B]>::uninit();
        Self::scatter_fill(cols, &mut out);
        // SAFETY: `scatter_fill` wrote every entry of every matrix (its loops run over all
        // `C` columns, `R` rows and `B` lanes), and an `SMatrix` is its entries alone.
        unsafe { out.assume_init() }
    }

    /// [`Self::scatter`]'s transpose into `out`: entry `(r, c)` of matrix `l` is lane `l` of
    /// `cols[c][r]`, every entry written (so `out` is initialised after it). Out of line and
    /// `extern "C"` for the call-slot optimisation in `scatter` (a call it can see into, inlined,
    /// would leave the stores in `scatter`'s frame again) and for `no_panic`, as `scatter`;
    /// iterators and pointer offsets within the arrays, no index to check.
    #[inline(never)]
    #[allow(improper_ctypes_definitions)] // called from Rust only
    #[allow(unsafe_code)]
    extern "C" fn scatter_fill<const R: usize, const C: usize>(
        cols: &[[Self; R]; C],
        out: &mut MaybeUninit<[SMatrix<T, R, C>; B]>,
    ) where
        T: Scalar,
    {
        let matrices = out.as_mut_ptr().cast::<SMatrix<T, R, C>>();
        for (c, col) in cols.iter().enumerate() {
            for (r, lanes) in col.iter().enumerate() {
                for (l, &v) in lanes.0.iter().enumerate() {
                    // SAFETY: `l < B`, `c < C` and `r < R` (positions in the arrays `lanes.0`,
                    // `cols` and `col`): matrix `l` of the `B` in `out`, column `c` of its `C`
                    // arrays of `R` entries (`ArrayStorage`), entry `r` of it; written through
                    // raw pointers, no reference to the uninitialised memory made.
                    unsafe {
                        let columns =
                            core::ptr::addr_of_mut!((*matrices.add(l)).data.0).cast::<[T; R]>();
                        columns.add(c).cast::<T>().add(r).write(v);
                    }
                }
            }
        }
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
    /// loops into a zeroed local, as in [`Self::gather`], for `no_panic`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[must_use]
    pub fn scatter_column<const R: usize>(cols: &[[Self; R]; 1]) -> [SMatrix<T, R, 1>; B]
    where
        T: Default + Scalar,
    {
        let mut out = [SMatrix::from_array_storage(ArrayStorage([[T::default(); R]; 1])); B];
        let [col] = cols;
        for (r, lanes) in col.iter().enumerate() {
            for (m, &v) in out.iter_mut().zip(&lanes.0) {
                if let Some(x) = m.data.0[0].get_mut(r) {
                    *x = v;
                }
            }
        }
        out
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
        // A 2 × 3 matrix per state (columns of lanes): entry (r, c) of state l is lane l.
        let entry =
            |r: usize, c: usize| Lanes::<f64, 3>([0, 1, 2].map(|l| (100 * l + 10 * r + c) as f64));
        let cols = [0, 1, 2].map(|c| [entry(0, c), entry(1, c)]);
        for (l, m) in Lanes::scatter(&cols).iter().enumerate() {
            assert_eq!(
                *m,
                nalgebra::SMatrix::<f64, 2, 3>::from_fn(|r, c| (100 * l + 10 * r + c) as f64)
            );
        }
        let (s, c) = Lanes::each2(lanes, |x: [f64; 3]| (x.map(|v| v + 1.0), x.map(|v| -v)));
        assert_eq!(s[1].0, [3.0, 5.0, 7.0]);
        assert_eq!(c[0].0, [-1.0, -3.0, -5.0]);
    }
}
