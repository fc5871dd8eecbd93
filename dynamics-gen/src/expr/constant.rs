//! Finite floating point constants with exact equality and hashing.

use std::fmt;

/// A finite `f64` stored as its bit pattern, so that `Eq` and `Hash` are
/// exact (two constants are equal iff they are the same `f64`).
///
/// Invariants: the value is finite (no NaN, no infinities) and `-0.0` is
/// normalised to `+0.0`, so there is exactly one zero constant.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Const(u64);

impl Const {
    /// Wraps `v`, or returns `None` if `v` is NaN or infinite.
    /// `-0.0` becomes `+0.0`.
    pub fn new(v: f64) -> Option<Const> {
        if !v.is_finite() {
            return None;
        }
        // `-0.0 == 0.0`, so this maps both zeros to +0.0.
        let v = if v == 0.0 { 0.0 } else { v };
        Some(Const(v.to_bits()))
    }

    /// The stored value.
    #[inline]
    pub fn value(self) -> f64 {
        f64::from_bits(self.0)
    }

    /// The raw bit pattern (as produced by [`f64::to_bits`]).
    #[inline]
    pub fn to_bits(self) -> u64 {
        self.0
    }
}

impl fmt::Display for Const {
    /// Shortest text that reads back to the same `f64`: integers below
    /// 1e16 without a fractional part (`2`, `-3`), otherwise Rust's `{:?}`
    /// float format (`0.5`, `1e-7`, `1.5e300`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.value();
        if v.fract() == 0.0 && v.abs() < 1e16 {
            write!(f, "{}", v)
        } else {
            write!(f, "{:?}", v)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_finite_and_normalises_zero() {
        assert!(Const::new(f64::NAN).is_none());
        assert!(Const::new(f64::INFINITY).is_none());
        assert!(Const::new(f64::NEG_INFINITY).is_none());
        let z = Const::new(-0.0).unwrap();
        assert_eq!(z, Const::new(0.0).unwrap());
        assert_eq!(z.to_bits(), 0);
        assert!(z.value().is_sign_positive());
        assert_eq!(Const::new(1.25).unwrap().value(), 1.25);
        let next = f64::from_bits(0.1f64.to_bits() + 1);
        assert_ne!(Const::new(0.1).unwrap(), Const::new(next).unwrap());
    }

    #[test]
    fn display_round_trips() {
        for v in [
            2.0,
            -3.0,
            0.5,
            1e-7,
            1.5e300,
            0.1,
            -1e20,
            123456.0,
            1.0 / 3.0,
        ] {
            let s = Const::new(v).unwrap().to_string();
            assert_eq!(s.parse::<f64>().unwrap(), v, "{s}");
        }
        assert_eq!(Const::new(2.0).unwrap().to_string(), "2");
        assert_eq!(Const::new(-0.5).unwrap().to_string(), "-0.5");
        assert_eq!(Const::new(-0.0).unwrap().to_string(), "0");
    }
}
