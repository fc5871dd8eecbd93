//! Float literals in shortest round-trip form for the scalar type.

use crate::options::Scalar;
use proc_macro2::{Literal, TokenStream};
use quote::ToTokens;

/// The shortest decimal that reads back as `x` in the scalar type (`x` rounded once to f32
/// for [`Scalar::F32`]), always with a `.` or an exponent so it is a float literal.
pub fn float_text(x: f64, scalar: Scalar) -> String {
    let mut s = match scalar {
        Scalar::F64 => format!("{x:?}"),
        Scalar::F32 => format!("{:?}", x as f32),
    };
    if !s.contains(['.', 'e', 'E']) {
        s.push_str(".0");
    }
    s
}

/// The literal as tokens (a leading `-` becomes a unary minus token).
pub fn float_tokens(x: f64, scalar: Scalar) -> TokenStream {
    let text = float_text(x.abs(), scalar);
    let lit: Literal = text
        .parse()
        .unwrap_or_else(|_| Literal::f64_unsuffixed(x.abs()));
    if x.is_sign_negative() && x != 0.0 {
        quote::quote!(-#lit)
    } else {
        lit.into_token_stream()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_round_trip() {
        assert_eq!(float_text(0.1, Scalar::F64), "0.1");
        assert_eq!(float_text(2.0, Scalar::F64), "2.0");
        assert_eq!(float_text(1e-20, Scalar::F64), "1e-20");
        assert_eq!(float_text(0.1, Scalar::F32), "0.1");
        assert_eq!(float_text(std::f64::consts::PI, Scalar::F32), "3.1415927");
        for x in [0.1, 1.0 / 3.0, 6.02214076e23, -1.5e-300, 0.089159] {
            assert_eq!(float_text(x, Scalar::F64).parse::<f64>().ok(), Some(x));
        }
    }
}
