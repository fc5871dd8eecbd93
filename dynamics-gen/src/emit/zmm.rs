//! The AVX-512 and AVX2 copies of a large batch body, each `Lanes` operation one vector
//! instruction.
//!
//! A batch body ([`super::batch`]) is the single-state code with every value a `Lanes<T,
//! B>`, whose operators are loops over the `B` lanes. The optimiser fully unrolls those
//! loops early, and its SLP vectoriser must then rebuild each operation's lanes into a vector
//! instruction. On bodies of a thousand operations and more it rebuilds part of them only:
//! the AVX-512 copy of Solo-12's inverse dynamics batch (`B` = 8, 1,310 operations) held
//! 4,864 instructions, 482 of them scalar and 1,018 on 256-bit registers.
//!
//! So the AVX-512 and AVX2 copies of such a body get a body of their own each,
//! `X_body_avx512` and `X_body_avx2`: the same statements, with every `a + b`, `a − b`,
//! `a · b`, `a / b`, `−a` and fused multiply-add of lanes a method of a token of the runtime
//! (`z.add(a, b)`, …), `Avx512` or `Avx2`, each one instruction. A body of instructions is
//! for one register of states (AVX-512: 8 `f64`, 16 `f32`; AVX2: 4 and 8), not generic, and
//! its batch function runs it once per register. The token is made from its `unsafe`
//! `new_unchecked` once, at the top of the body, which is itself an `unsafe fn` called only
//! by its copy (after the run-time check that chose it). Each method gives its operator's
//! bits, so a state's result is still the single-state function's bit for bit.
//!
//! Measured (old and new generated code in one binary, default profile, `B` = 8 against 8
//! single calls, per state, two runs; README "Batches of states"): in the AVX-512 copy,
//! Solo-12's inverse dynamics 121.7–123.4 → 86.8–88.7 ns (1.27–1.29× → 1.77–1.80× single
//! calls), Talos' upper body 184.6–186.1 → 126.1–127.4 ns (1.36–1.39× → 2.00–2.03×). Small
//! bodies, which the vectoriser handles whole, lost a little in a first scratch version (the
//! UR5's inverse dynamics 22.7 → 25.6 ns, the Panda's 37.8 → 40.8 ns), hence [`MIN_OPS`];
//! `f64` bodies with a vector result get them from [`VECTOR_MIN_OPS`] on.
//!
//! A body of more than [`super::batch::MAX_LANES_OPS`] operations, which the vectoriser
//! leaves mostly scalar (Solo-12's forward dynamics with `B` = 8 ran at 0.64–0.71× of single
//! calls), runs on lanes in these two copies alone ([`ONLY_MARK`]): the batch function checks
//! for the CPU's features and `B` a multiple of the register's lanes, and otherwise calls the
//! single-state function once per state; there is no portable copy of its lanes. Measured as
//! above in the AVX-512 copy (medians of 11 rounds, two runs; "before" the per-state calls):
//! Solo-12's forward dynamics (2,966 operations) 0.93–0.95× → 2.61–2.69× single calls, Talos'
//! upper body's (5,501) 1.00× → 2.66–2.77×, G1's inverse dynamics (4,059) 0.92–0.99× →
//! 1.99–2.10× and forward dynamics (9,731) 1.00× → 2.64–2.71×. Compile time, G1's four batch
//! functions at `B` = 8 in a crate of their own: release 11.7 → 40 s, debug 5.0 → 27.6 s with
//! the AVX-512 copy's body alone (the runtime's token methods had first made it 541 s in
//! release: see `dynamics_runtime::x86`).

use proc_macro2::TokenStream;
use quote::quote;
use std::collections::HashSet;
use syn::visit_mut::{self, VisitMut};
use syn::{parse_quote, BinOp, Expr, GenericArgument, Pat, UnOp};

/// The fewest lane operations (after inlining) for a batch body to get its copies of
/// instructions whatever its result: Solo-12's inverse dynamics (1,310) gets them. Below it
/// only an `f64` body with a vector result does ([`VECTOR_MIN_OPS`]); mass matrices keep the
/// vectoriser's body (see there).
pub const MIN_OPS: usize = 1000;

/// The fewest lane operations for an `f64` batch body with a vector result (inverse and
/// forward dynamics, gravity) to get its bodies of instructions in both copies.
///
/// In the AVX2 copy (measured on a Zen 3, AVX2 and FMA, no AVX-512; a scratch harness, the
/// code before and after in one binary, `B` = 8 against 8 single calls of the same code,
/// medians of 31 interleaved rounds, two runs; README "Batches of states"): a body of the
/// vectoriser's, `B` = 8, holds each value in two 256-bit registers, and spills. The UR5's
/// inverse dynamics (297 operations) 1.83×, 1.39× → 1.82×, 1.89× single calls (316 → 264
/// instructions per state, the kernel's change included), the Panda's (687) 1.63×, 1.51× →
/// 2.07×, 2.14×, the UR5's forward dynamics (562) 1.97×, 1.86× → 2.61×, 2.34×. The UR5's
/// gravity (16 operations) lost in a first trial (1.74 → 1.45×): the body of instructions runs
/// once per register, and a small body does not pay for the calls; mass matrices lost more
/// (1.33 → 0.94×), their 4 × 36 results copied out of each register's call.
///
/// In the AVX-512 copy these bodies kept the vectoriser's at first (a first scratch version
/// lost: the UR5's inverse dynamics 22.7 → 25.6 ns, the Panda's 37.8 → 40.8 ns), until the
/// kernel's fallback left the copies (`super::dispatch`, "far angles"): with it gone, on a Zen
/// 4 (old and new code in one binary, `B` = 8 against 8 single calls, medians of 41
/// interleaved rounds, two runs), the Panda's inverse dynamics (693 operations) ran at 2.09×,
/// 2.21× single calls with the vectoriser's body and 2.64×, 2.46× with the instructions,
/// rand7's (983) 2.57×, 2.63× and 2.93×, 2.76×, the UR5's (302) 2.22×, 2.42× and 2.49×,
/// 2.31×, the UR5's forward dynamics (567) 2.71×, 2.75× and 3.04×, 2.87×. Gravity (Panda 104,
/// rand7 203 operations) gained nothing (2.30×, 2.42× and 2.24×, 2.16×; 2.10×, 2.04× and
/// 2.11×, 1.99×), mass matrices lost (Panda 1.91×, 2.37× → 1.77×, 2.21×; UR5 1.82×, 2.59× →
/// 1.68×, 2.32×), so the bound stays 250. `f32`'s registers hold twice the lanes, the
/// vectoriser's body one register per value at `B` = 8: not measured, left alone.
pub const VECTOR_MIN_OPS: usize = 250;

/// The words of a batch function's doc comment that ask the dispatch for the bodies of
/// instructions ([`super::batch`] writes them for bodies of at least [`MIN_OPS`] operations).
pub const DOC_MARK: &str =
    "its AVX-512 and AVX2 copies compute each operation as one vector instruction";

/// The words that follow [`DOC_MARK`] in the doc comment of a batch body too large for the
/// optimiser's vectoriser ([`super::batch::MAX_LANES_OPS`]): the dispatch gives it the bodies
/// of instructions, for `B` a multiple of a register's lanes, and otherwise calls the
/// single-state function once per state (no portable copy of the lanes).
pub const ONLY_MARK: &str = "on other CPUs and targets and for other `B` it calls";

/// The statements of `body` (a batch body in its dispatched `WIDE` form) with its lane
/// arithmetic on the token `z`, or `None` when it does not parse as a block.
///
/// Arithmetic on scalars alone (the robot's constants, run-time parameters such as
/// `gravity0`, bound from `self`) stays as it is; a scalar operand of lane arithmetic is
/// spread over the lanes (`Self::lanes(x)`, as the operators do).
pub fn token_body(body: &TokenStream) -> Option<TokenStream> {
    let mut block: syn::Block = syn::parse2(quote!({ #body })).ok()?;
    let mut rewrite = Rewrite {
        scalars: HashSet::new(),
    };
    rewrite.visit_block_mut(&mut block);
    let stmts = &block.stmts;
    Some(quote!(#(#stmts)*))
}

/// The operator-to-method rewrite.
struct Rewrite {
    /// The locals that hold scalars (not lanes).
    scalars: HashSet<String>,
}

impl Rewrite {
    /// Whether `e` is a scalar: literals, `self`'s fields, scalar locals, and arithmetic on
    /// those alone. Everything else in a batch body is lanes (calls, the rewritten methods).
    fn scalar(&self, e: &Expr) -> bool {
        match e {
            Expr::Lit(_) => true,
            Expr::Paren(p) => self.scalar(&p.expr),
            Expr::Unary(u) => self.scalar(&u.expr),
            Expr::Binary(b) => self.scalar(&b.left) && self.scalar(&b.right),
            Expr::Field(f) => self.scalar(&f.base),
            Expr::Index(i) => self.scalar(&i.expr),
            Expr::Path(p) => p
                .path
                .get_ident()
                .is_some_and(|i| i == "self" || self.scalars.contains(&i.to_string())),
            _ => false,
        }
    }

    /// `e` as lanes: spread over them if it is a scalar.
    fn lanes(&self, e: &Expr) -> Expr {
        if self.scalar(e) {
            parse_quote!(Self::lanes(#e))
        } else {
            e.clone()
        }
    }
}

/// The names a `let` pattern binds (identifiers, and those in array patterns).
fn bound(p: &Pat, out: &mut Vec<String>) {
    match p {
        Pat::Ident(i) => out.push(i.ident.to_string()),
        Pat::Slice(s) => s.elems.iter().for_each(|p| bound(p, out)),
        Pat::Type(t) => bound(&t.pat, out),
        _ => {}
    }
}

impl VisitMut for Rewrite {
    // Const generic arguments (`{ Self::wide_lanes(K) }`) are not lane arithmetic.
    fn visit_generic_argument_mut(&mut self, _: &mut GenericArgument) {}

    fn visit_local_mut(&mut self, local: &mut syn::Local) {
        visit_mut::visit_local_mut(self, local);
        if local.init.as_ref().is_some_and(|i| self.scalar(&i.expr)) {
            let mut names = Vec::new();
            bound(&local.pat, &mut names);
            self.scalars.extend(names);
        }
    }

    fn visit_expr_mut(&mut self, e: &mut Expr) {
        visit_mut::visit_expr_mut(self, e);
        if self.scalar(e) {
            return;
        }
        let new: Expr = match e {
            Expr::Binary(b) => {
                let method = match b.op {
                    BinOp::Add(_) => quote!(add),
                    BinOp::Sub(_) => quote!(sub),
                    BinOp::Mul(_) => quote!(mul),
                    BinOp::Div(_) => quote!(div),
                    _ => return,
                };
                let (l, r) = (self.lanes(&b.left), self.lanes(&b.right));
                parse_quote!(z.#method(#l, #r))
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                let x = &u.expr;
                parse_quote!(z.neg(#x))
            }
            Expr::Call(c) if is_mul_add_lanes(&c.func) => {
                let args = c.args.iter().map(|a| self.lanes(a));
                parse_quote!(z.mul_add(#(#args),*))
            }
            _ => return,
        };
        *e = new;
    }
}

/// Whether `f` is `Self::mul_add_lanes_with::<…>`, the dispatched body's fused multiply-add
/// of lanes (fused in every copy that runs this body).
fn is_mul_add_lanes(f: &Expr) -> bool {
    let Expr::Path(p) = f else {
        return false;
    };
    let segments: Vec<String> = p
        .path
        .segments
        .iter()
        .map(|s| s.ident.to_string())
        .collect();
    segments == ["Self", "mul_add_lanes_with"]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rewrite(lines: impl Fn(usize) -> String) -> Option<String> {
        let body: String = (0..3).map(lines).collect();
        token_body(&body.parse().unwrap()).map(|t| t.to_string())
    }

    #[test]
    fn lane_operators_become_token_methods_and_scalars_stay() {
        let head = "let g = self.gravity; let [p0, p1] = self.payload; let k = g * -2.0;";
        let out = rewrite(|i| {
            let pre = if i == 0 { head } else { "" };
            format!("{pre} let t{i} = Self::mul_add_lanes_with::<_, WIDE>(Lanes::from(x), Lanes::from(-2.5_f64), Lanes::from(y)) + -z{i} * (p0 * k);")
        })
        .unwrap();
        assert!(
            out.contains("let k = g * - 2.0 ;"),
            "scalar arithmetic stays"
        );
        assert!(out.contains("z . add (z . mul_add (Lanes :: from (x) , Lanes :: from (- 2.5_f64) , Lanes :: from (y)) , z . mul (z . neg (z0) , Self :: lanes ((p0 * k))))"), "{}", &out[..600]);
        assert!(!out.contains(" + "));
    }

    #[test]
    fn const_generic_arguments_are_left_alone() {
        let out = rewrite(|i| format!("let t{i} = Self::f::<{{ K * 2 }}>(a{i}) + b;")).unwrap();
        assert!(out.contains("{ K * 2 }"));
    }
}
