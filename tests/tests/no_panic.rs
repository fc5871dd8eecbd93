//! No panic paths: every generated function of every generated robot, wrapped in a function
//! marked `#[no_panic]`, which fails to link if the optimiser cannot prove the wrapper never
//! panics. Meaningful in release builds only:
//! `cargo test --release -p dynamics-tests --test no_panic`.
//!
//! The `no_std` variants are left out: the `libm::sinf`/`libm::sin` they call for angles
//! beyond the `joint_sin_cos` helper's range hold bounds checks in their argument reduction that the optimiser cannot prove unreachable, so `no_panic` rejects
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
                    Robot::DEFAULT.mass_matrix(q)
                }
                #[no_panic]
                pub fn coriolis(q: &Q, qd: &V) -> V {
                    Robot::DEFAULT.coriolis(q, qd)
                }
                #[no_panic]
                pub fn gravity(q: &Q) -> V {
                    Robot::DEFAULT.gravity(q)
                }
                #[no_panic]
                pub fn inverse_dynamics(q: &Q, qd: &V, qdd: &V) -> V {
                    Robot::DEFAULT.inverse_dynamics(q, qd, qdd)
                }
                #[no_panic]
                pub fn forward_dynamics(q: &Q, qd: &V, tau: &V) -> V {
                    Robot::DEFAULT.forward_dynamics(q, qd, tau)
                }
                #[no_panic]
                pub fn kinetic_energy(q: &Q, qd: &V) -> $s {
                    Robot::DEFAULT.kinetic_energy(q, qd)
                }
                #[no_panic]
                pub fn potential_energy(q: &Q) -> $s {
                    Robot::DEFAULT.potential_energy(q)
                }
                #[no_panic]
                pub fn mass_matrix_dot(q: &Q, qd: &V) -> SMatrix<$s, $nv, $nv> {
                    Robot::DEFAULT.mass_matrix_dot(q, qd)
                }
                #[no_panic]
                pub fn jacobian_space_dot(q: &Q, qd: &V) -> SMatrix<$s, 6, $nv> {
                    Robot::DEFAULT.jacobian_space_dot(q, qd)
                }
                #[no_panic]
                pub fn jacobian_body_dot(q: &Q, qd: &V) -> SMatrix<$s, 6, $nv> {
                    Robot::DEFAULT.jacobian_body_dot(q, qd)
                }
                #[no_panic]
                pub fn end_effector_pose(q: &Q) -> nalgebra::Isometry3<$s> {
                    Robot::DEFAULT.end_effector_pose(q)
                }
                #[no_panic]
                pub fn jacobian_space(q: &Q) -> SMatrix<$s, 6, $nv> {
                    Robot::DEFAULT.jacobian_space(q)
                }
                #[no_panic]
                pub fn jacobian_body(q: &Q) -> SMatrix<$s, 6, $nv> {
                    Robot::DEFAULT.jacobian_body(q)
                }
                #[no_panic]
                pub fn friction(qd: &V) -> V {
                    Robot::DEFAULT.friction(qd)
                }
                #[no_panic]
                pub fn coriolis_matrix(q: &Q, qd: &V) -> SMatrix<$s, $nv, $nv> {
                    Robot::DEFAULT.coriolis_matrix(q, qd)
                }
                #[no_panic]
                pub fn mass_matrix_and_bias(q: &Q, qd: &V) -> (SMatrix<$s, $nv, $nv>, V) {
                    Robot::DEFAULT.mass_matrix_and_bias(q, qd)
                }
                #[no_panic]
                pub fn end_effector_forces(q: &Q, f: &SVector<$s, 6>) -> V {
                    Robot::DEFAULT.end_effector_forces(q, f)
                }
                #[no_panic]
                pub fn inverse_dynamics_with_tip(q: &Q, qd: &V, qdd: &V, f: &SVector<$s, 6>) -> V {
                    Robot::DEFAULT.inverse_dynamics_with_tip(q, qd, qdd, f)
                }
                #[no_panic]
                pub fn forward_dynamics_with_tip(q: &Q, qd: &V, tau: &V, f: &SVector<$s, 6>) -> V {
                    Robot::DEFAULT.forward_dynamics_with_tip(q, qd, tau, f)
                }
                #[no_panic]
                pub fn task_space_mass_matrix(q: &Q) -> Option<SMatrix<$s, 6, 6>> {
                    Robot::DEFAULT.task_space_mass_matrix(q)
                }
                #[no_panic]
                pub fn task_space_bias(q: &Q, qd: &V) -> Option<SVector<$s, 6>> {
                    Robot::DEFAULT.task_space_bias(q, qd)
                }
                #[no_panic]
                pub fn constrained_forward_dynamics_1(
                    q: &Q,
                    qd: &V,
                    tau: &V,
                    a: &SMatrix<$s, 1, $nv>,
                    adq: &SVector<$s, 1>,
                ) -> Option<(V, SVector<$s, 1>)> {
                    Robot::DEFAULT.constrained_forward_dynamics(q, qd, tau, a, adq)
                }
                #[no_panic]
                pub fn constrained_forward_dynamics_3(
                    q: &Q,
                    qd: &V,
                    tau: &V,
                    a: &SMatrix<$s, 3, $nv>,
                    adq: &SVector<$s, 3>,
                ) -> Option<(V, SVector<$s, 3>)> {
                    Robot::DEFAULT.constrained_forward_dynamics(q, qd, tau, a, adq)
                }
                pub fn extras() -> $s {
                    let q = Q::from_fn(|i, _| 0.1 * i as $s + 0.05);
                    let v = V::from_fn(|i, _| 0.1 * i as $s);
                    let f = SVector::<$s, 6>::from_fn(|i, _| 0.2 * i as $s);
                    let a1 = SMatrix::<$s, 1, $nv>::from_fn(|_, j| 0.3 * j as $s + 0.1);
                    let a3 = SMatrix::<$s, 3, $nv>::from_fn(|i, j| (i * j) as $s + 0.1);
                    let mut e = friction(&v)[0] + coriolis_matrix(&q, &v)[(0, 0)];
                    e += mass_matrix_and_bias(&q, &v).1[0] + end_effector_forces(&q, &f)[0];
                    e += inverse_dynamics_with_tip(&q, &v, &v, &f)[0];
                    e += forward_dynamics_with_tip(&q, &v, &v, &f)[0];
                    e += task_space_mass_matrix(&q).map_or(0.0, |l| l[(0, 0)]);
                    e += task_space_bias(&q, &v).map_or(0.0, |x| x[0]);
                    e += constrained_forward_dynamics_1(
                        &q,
                        &v,
                        &v,
                        &a1,
                        &SVector::<$s, 1>::new(0.1),
                    )
                    .map_or(0.0, |x| x.1[0]);
                    e +=
                        constrained_forward_dynamics_3(&q, &v, &v, &a3, &SVector::<$s, 3>::zeros())
                            .map_or(0.0, |x| x.1[0]);
                    e
                }
                pub fn call() -> $s {
                    let q = Q::from_fn(|i, _| 0.1 * i as $s + 0.05);
                    let v = V::from_fn(|i, _| 0.1 * i as $s);
                    let m = mass_matrix(&q);
                    let c = coriolis(&q, &v);
                    let g = gravity(&q);
                    let t = inverse_dynamics(&q, &v, &v);
                    let a = forward_dynamics(&q, &v, &t);
                    let p = end_effector_pose(&q);
                    let js = jacobian_space(&q);
                    let jb = jacobian_body(&q);
                    let e = kinetic_energy(&q, &v) + potential_energy(&q);
                    let e = e + mass_matrix_dot(&q, &v)[(0, 0)];
                    let e =
                        e + jacobian_space_dot(&q, &v)[(5, 0)] + jacobian_body_dot(&q, &v)[(5, 0)];
                    m[(0, 0)] + c[0] + g[0] + a[0] + p.translation.x + js[(5, 0)] + jb[(5, 0)] + e
                }
            }
        };
    }

    dynamics_tests::with_std_cases!(wrappers);

    macro_rules! frame_wrappers {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            pub mod $m {
                use super::super::*;
                use dynamics_tests::generated::$m::Robot;
                type Q = SVector<$s, $nq>;
                #[no_panic]
                pub fn frame_poses(q: &Q) -> [nalgebra::Isometry3<$s>; Robot::FRAME_NAMES.len()] {
                    Robot::DEFAULT.frame_poses(q)
                }
                #[no_panic]
                pub fn frame_jacobians_space(
                    q: &Q,
                ) -> [SMatrix<$s, 6, $nv>; Robot::FRAME_NAMES.len()] {
                    Robot::DEFAULT.frame_jacobians_space(q)
                }
                #[no_panic]
                pub fn frame_jacobians_body(
                    q: &Q,
                ) -> [SMatrix<$s, 6, $nv>; Robot::FRAME_NAMES.len()] {
                    Robot::DEFAULT.frame_jacobians_body(q)
                }
                pub fn call() -> $s {
                    let q = Q::from_fn(|i, _| 0.1 * i as $s + 0.05);
                    frame_poses(&q)[0].translation.x
                        + frame_jacobians_space(&q)[0][(5, 0)]
                        + frame_jacobians_body(&q)[0][(5, 0)]
                }
            }
        };
    }

    pub mod frames {
        dynamics_tests::with_frame_cases!(frame_wrappers);
    }

    macro_rules! derivative_wrappers {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            pub mod $m {
                use super::super::*;
                use dynamics_tests::generated::$m::Robot;
                type Q = SVector<$s, $nq>;
                type V = SVector<$s, $nv>;
                type M = SMatrix<$s, $nv, $nv>;
                #[no_panic]
                pub fn inverse_dynamics_derivatives(q: &Q, qd: &V, qdd: &V) -> (M, M) {
                    Robot::DEFAULT.inverse_dynamics_derivatives(q, qd, qdd)
                }
                #[no_panic]
                pub fn inverse_dynamics_with_derivatives(q: &Q, qd: &V, qdd: &V) -> (V, M, M) {
                    Robot::DEFAULT.inverse_dynamics_with_derivatives(q, qd, qdd)
                }
                #[no_panic]
                pub fn forward_dynamics_derivatives(q: &Q, qd: &V, tau: &V) -> (M, M, M) {
                    Robot::DEFAULT.forward_dynamics_derivatives(q, qd, tau)
                }
                #[no_panic]
                pub fn forward_dynamics_with_derivatives(q: &Q, qd: &V, tau: &V) -> (V, M, M, M) {
                    Robot::DEFAULT.forward_dynamics_with_derivatives(q, qd, tau)
                }
                #[no_panic]
                pub fn mass_matrix_inverse(q: &Q) -> M {
                    Robot::DEFAULT.mass_matrix_inverse(q)
                }
                #[no_panic]
                pub fn gravity_derivative(q: &Q) -> M {
                    Robot::DEFAULT.gravity_derivative(q)
                }
                pub fn call() -> $s {
                    let q = Q::from_fn(|i, _| 0.1 * i as $s + 0.05);
                    let v = V::from_fn(|i, _| 0.2 - 0.03 * i as $s);
                    inverse_dynamics_derivatives(&q, &v, &v).0[(0, 0)]
                        + inverse_dynamics_with_derivatives(&q, &v, &v).0[0]
                        + forward_dynamics_derivatives(&q, &v, &v).2[(0, 0)]
                        + forward_dynamics_with_derivatives(&q, &v, &v).0[0]
                        + mass_matrix_inverse(&q)[(0, 0)]
                        + gravity_derivative(&q)[(0, 0)]
                }
            }
        };
    }

    pub mod derivatives {
        dynamics_tests::with_derivative_cases!(derivative_wrappers);
    }

    macro_rules! batch_wrappers {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            pub mod $m {
                use super::super::*;
                use dynamics_tests::generated::$m::Robot;
                type Q = SVector<$s, $nq>;
                type V = SVector<$s, $nv>;
                #[no_panic]
                pub fn inverse_dynamics_batch(q: &[Q; 4], qd: &[V; 4], qdd: &[V; 4]) -> [V; 4] {
                    Robot::DEFAULT.inverse_dynamics_batch(q, qd, qdd)
                }
                #[no_panic]
                pub fn forward_dynamics_batch(q: &[Q; 4], qd: &[V; 4], tau: &[V; 4]) -> [V; 4] {
                    Robot::DEFAULT.forward_dynamics_batch(q, qd, tau)
                }
                #[no_panic]
                pub fn mass_matrix_batch(q: &[Q; 4]) -> [SMatrix<$s, $nv, $nv>; 4] {
                    Robot::DEFAULT.mass_matrix_batch(q)
                }
                #[no_panic]
                pub fn gravity_batch(q: &[Q; 4]) -> [V; 4] {
                    Robot::DEFAULT.gravity_batch(q)
                }
                pub fn call() -> $s {
                    let qs: [Q; 4] =
                        std::array::from_fn(|l| Q::from_fn(|i, _| 0.1 * (i + l) as $s + 0.05));
                    let vs: [V; 4] =
                        std::array::from_fn(|l| V::from_fn(|i, _| 0.1 * (i * l) as $s));
                    inverse_dynamics_batch(&qs, &vs, &vs)[3][0]
                        + forward_dynamics_batch(&qs, &vs, &vs)[3][0]
                        + mass_matrix_batch(&qs)[3][(0, 0)]
                        + gravity_batch(&qs)[3][0]
                }
            }
        };
    }

    pub mod batch {
        dynamics_tests::with_batch_std_cases!(batch_wrappers);
    }

    macro_rules! call_batch {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            assert!(batch::$m::call().is_finite());
        };
    }

    #[test]
    fn batch_functions_have_no_panic_path() {
        dynamics_tests::with_batch_std_cases!(call_batch);
    }

    macro_rules! call_derivatives {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            assert!(derivatives::$m::call().is_finite());
        };
    }

    #[test]
    fn derivative_functions_have_no_panic_path() {
        dynamics_tests::with_derivative_cases!(call_derivatives);
    }

    macro_rules! call {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            assert!($m::call().is_finite());
            assert!(!$m::extras().is_nan());
        };
    }

    macro_rules! call_frames {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            assert!(frames::$m::call().is_finite());
        };
    }

    #[test]
    fn frame_functions_have_no_panic_path() {
        dynamics_tests::with_frame_cases!(call_frames);
    }

    #[test]
    fn generated_functions_have_no_panic_path() {
        dynamics_tests::with_std_cases!(call);
    }
}
