//! Coefficients as exact short forms where they are one (integers, simple fractions, multiples
//! of √2, √3, √6 and π), otherwise a given number of significant digits.

/// How a coefficient's magnitude is written.
#[derive(Clone, Debug, PartialEq)]
pub enum Magnitude {
    /// `n/d` (d = 1: an integer), times `√r` (r = 1: none) or π.
    Exact {
        /// Numerator.
        n: u64,
        /// Denominator.
        d: u64,
        /// The irrational factor.
        factor: Factor,
    },
    /// A decimal: its mantissa digits and exponent as `format!("{:e}")` gives them.
    Decimal(String),
}

/// The irrational factor of an exact coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factor {
    /// None.
    One,
    /// `√r`.
    Sqrt(u32),
    /// π.
    Pi,
}

/// The largest denominator tried.
const MAX_DEN: u64 = 12;

/// How close (relative) a coefficient must be to a short form to be written as one.
pub const EXACT_TOL: f64 = 1e-10;

/// `|x|` (non-zero, finite) as a short exact form, or a decimal with `digits` significant
/// digits (17 or more: the shortest decimal that reads back as the same `f64`).
pub fn magnitude(x: f64, digits: usize) -> Magnitude {
    let x = x.abs();
    let candidates = [
        (Factor::One, 1.0),
        (Factor::Sqrt(2), std::f64::consts::SQRT_2),
        (Factor::Sqrt(3), 3f64.sqrt()),
        (Factor::Sqrt(6), 6f64.sqrt()),
        (Factor::Pi, std::f64::consts::PI),
    ];
    for (factor, f) in candidates {
        let y = x / f;
        for d in 1..=MAX_DEN {
            let n = (y * d as f64).round();
            if (1.0..1e7).contains(&n) && (n / d as f64 * f - x).abs() <= EXACT_TOL * x {
                let n = n as u64;
                // In lowest terms (a smaller d would have matched first).
                return Magnitude::Exact { n, d, factor };
            }
        }
    }
    if digits >= 17 {
        return Magnitude::Decimal(format!("{x}"));
    }
    let s = format!("{:.*e}", digits.max(1) - 1, x);
    // Plain notation for exponents −4..=6, trailing zeros dropped.
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if (-4..=6).contains(&exp) {
        let value: f64 = s.parse().unwrap_or(x);
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        let plain = format!("{value:.decimals$}");
        let plain = if plain.contains('.') {
            plain
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        } else {
            plain
        };
        Magnitude::Decimal(plain)
    } else {
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        Magnitude::Decimal(format!("{mantissa}e{exp}"))
    }
}

impl Magnitude {
    /// Whether this is exactly 1.
    pub fn is_one(&self) -> bool {
        matches!(
            self,
            Magnitude::Exact {
                n: 1,
                d: 1,
                factor: Factor::One
            }
        )
    }

    /// Plain text: `12`, `3/4`, `√2`, `3√2/4`, `2π`, `0.123457`, `1.5e-7`.
    pub fn text(&self) -> String {
        self.render(false)
    }

    /// LaTeX: `12`, `\frac{3}{4}`, `\sqrt{2}`, `\frac{3\sqrt{2}}{4}`, `2\pi`,
    /// `1.5 \times 10^{-7}`.
    pub fn latex(&self) -> String {
        self.render(true)
    }

    fn render(&self, latex: bool) -> String {
        match self {
            Magnitude::Decimal(s) => match s.split_once('e') {
                Some((m, e)) if latex => format!("{m} \\times 10^{{{e}}}"),
                _ => s.clone(),
            },
            Magnitude::Exact { n, d, factor } => {
                let f = match (factor, latex) {
                    (Factor::One, _) => String::new(),
                    (Factor::Sqrt(r), false) => format!("√{r}"),
                    (Factor::Sqrt(r), true) => format!("\\sqrt{{{r}}}"),
                    (Factor::Pi, false) => "π".into(),
                    (Factor::Pi, true) => "\\pi".into(),
                };
                let num = match (n, factor) {
                    (1, Factor::One) => "1".to_string(),
                    (1, _) => f,
                    _ => format!("{n}{f}"),
                };
                match (d, latex) {
                    (1, _) => num,
                    (_, false) => format!("{num}/{d}"),
                    (_, true) => format!("\\frac{{{num}}}{{{d}}}"),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_forms() {
        let t = |x: f64| magnitude(x, 6).text();
        assert_eq!(t(8.0), "8");
        assert_eq!(t(7.999999999999999), "8");
        assert_eq!(t(0.75), "3/4");
        assert_eq!(t(2f64.sqrt()), "√2");
        assert_eq!(t(3.0 * 2f64.sqrt() / 4.0), "3√2/4");
        assert_eq!(t(2.0 * std::f64::consts::PI), "2π");
        assert_eq!(t(0.123456789), "0.123457");
        assert_eq!(t(1.5e-7 + 1e-13), "1.5e-7");
        assert_eq!(t(123456789.0), "1.23457e8");
        assert_eq!(magnitude(0.1234567891234, 17).text(), "0.1234567891234");
        assert_eq!(magnitude(0.75, 6).latex(), "\\frac{3}{4}");
        assert_eq!(
            magnitude(2f64.sqrt() / 2.0, 6).latex(),
            "\\frac{\\sqrt{2}}{2}"
        );
    }
}
