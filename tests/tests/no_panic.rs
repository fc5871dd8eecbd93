//! No panic paths: every generated function of every generated robot, wrapped in a function
//! marked `#[no_panic]`, which fails to link if the optimiser cannot prove the wrapper never
//! panics. Meaningful in release builds only:
//! `cargo test --release -p dynamics-tests --test no_panic`.
//!
//! The `no_std` variants are left out: their `libm::sinf`/`libm::sin` argument reduction
//! holds bounds checks that the optimiser cannot prove unreachable, so `no_panic` rejects
//! them although the generated code itself has none.

#![allow(missing_docs)]

/// In a debug build the optimiser does not run, so `#[no_panic]` would reject every
/// function: the checks are compiled in release builds only. This placeholder says so in
/// `cargo test`'s output instead of a silent "0 tests".
#[cfg(debug_assertions)]
#[test]
fn no_panic_checks_run_only_in_release_builds_see_cargo_test_release() {
    eprintln!(
        "no_panic: skipped in this debug build; run `cargo test --release -p dynamics-tests --test no_panic`"
    );
}

#[cfg(not(debug_assertions))]
mod release {

    use nalgebra::{SMatrix, SVector};
    use no_panic::no_panic;

    macro_rules! wrappers {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            pub mod $m {
                use super::*;
                use dynamics_tests::generated::$m::Robot;
                type Q = SVector<$s, $nq>;
                type V = SVector<$s, $nv>;
                #[no_panic]
                pub fn mass_matrix(q: &Q) -> SMatrix<$s, $nv, $nv> {
                    Robot.mass_matrix(q)
                }
                #[no_panic]
                pub fn coriolis(q: &Q, qd: &V) -> V {
                    Robot.coriolis(q, qd)
                }
                #[no_panic]
                pub fn gravity(q: &Q) -> V {
                    Robot.gravity(q)
                }
                #[no_panic]
                pub fn inverse_dynamics(q: &Q, qd: &V, qdd: &V) -> V {
                    Robot.inverse_dynamics(q, qd, qdd)
                }
                #[no_panic]
                pub fn forward_dynamics(q: &Q, qd: &V, tau: &V) -> V {
                    Robot.forward_dynamics(q, qd, tau)
                }
                pub fn call() -> $s {
                    let q = Q::from_fn(|i, _| 0.1 * i as $s + 0.05);
                    let v = V::from_fn(|i, _| 0.1 * i as $s);
                    let m = mass_matrix(&q);
                    let c = coriolis(&q, &v);
                    let g = gravity(&q);
                    let t = inverse_dynamics(&q, &v, &v);
                    let a = forward_dynamics(&q, &v, &t);
                    m[(0, 0)] + c[0] + g[0] + a[0]
                }
            }
        };
    }

    dynamics_tests::with_std_cases!(wrappers);

    macro_rules! call {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            assert!($m::call().is_finite());
        };
    }

    #[test]
    fn generated_functions_have_no_panic_path() {
        dynamics_tests::with_std_cases!(call);
    }
}
