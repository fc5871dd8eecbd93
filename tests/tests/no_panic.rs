//! No panic paths: every generated function of every generated robot, wrapped in a function
//! marked `#[no_panic]`, which fails to link if the optimiser cannot prove the wrapper never
//! panics. Meaningful in release builds only:
//! `cargo test --release -p dynamics-tests --test no_panic` (every test robot), or with
//! `--features sample-robots` (the README's and CI's command: a sample covering every kind of
//! robot and every generator option, `SAMPLE` in build.rs).
//!
//! The `no_std` variants are left out: the `libm::sinf`/`libm::sin` they call for angles
//! beyond the `joint_sin_cos` helper's range hold bounds checks in their argument reduction that the optimiser cannot prove unreachable, so `no_panic` rejects
//! them although the generated code itself has none.
//!
//! The AVX-512 and AVX2 copies of the dispatched functions, and the batch bodies kept out of
//! line, are `extern "C"` (a panic in one would abort, not unwind, which `#[no_panic]` cannot
//! see):
//! `dispatched_copies_have_no_panic_path` reads this test binary's machine code instead and
//! follows their calls.

#![allow(missing_docs)]

/// In a debug build the optimiser does not run, so `#[no_panic]` would reject every
/// function: the checks are compiled in release builds only. This placeholder says so in
/// `cargo test`'s output instead of a silent "0 tests".
#[cfg(debug_assertions)]
#[test]
fn no_panic_checks_run_only_in_release_builds_see_cargo_test_release() {
    eprintln!(
        "no_panic: skipped in this debug build; run `cargo test --release -p dynamics-tests --features sample-robots --test no_panic`"
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
                pub fn mass_matrix_lower_into(q: &Q, m: &mut SMatrix<$s, $nv, $nv>) {
                    Robot::DEFAULT.mass_matrix_lower_into(q, m)
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
                    let mut lower = SMatrix::<$s, $nv, $nv>::zeros();
                    mass_matrix_lower_into(&q, &mut lower);
                    e += lower[(0, 0)];
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

    /// The batch width: a whole AVX-512 register of `f64` states, so that the copies' bodies of
    /// instructions are compiled and their machine code read (`dispatched_copies_have_no_panic_path`):
    /// the AVX-512 ones 8 wide, the AVX2 ones 4 wide, called twice.
    const B: usize = 8;

    macro_rules! batch_wrappers {
        ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
            pub mod $m {
                use super::super::*;
                use dynamics_tests::generated::$m::Robot;
                type Q = SVector<$s, $nq>;
                type V = SVector<$s, $nv>;
                #[no_panic]
                pub fn inverse_dynamics_batch(q: &[Q; B], qd: &[V; B], qdd: &[V; B]) -> [V; B] {
                    Robot::DEFAULT.inverse_dynamics_batch(q, qd, qdd)
                }
                #[no_panic]
                pub fn forward_dynamics_batch(q: &[Q; B], qd: &[V; B], tau: &[V; B]) -> [V; B] {
                    Robot::DEFAULT.forward_dynamics_batch(q, qd, tau)
                }
                #[no_panic]
                pub fn mass_matrix_batch(q: &[Q; B]) -> [SMatrix<$s, $nv, $nv>; B] {
                    Robot::DEFAULT.mass_matrix_batch(q)
                }
                #[no_panic]
                pub fn gravity_batch(q: &[Q; B]) -> [V; B] {
                    Robot::DEFAULT.gravity_batch(q)
                }
                pub fn call() -> $s {
                    let qs: [Q; B] =
                        std::array::from_fn(|l| Q::from_fn(|i, _| 0.1 * (i + l) as $s + 0.05));
                    let vs: [V; B] =
                        std::array::from_fn(|l| V::from_fn(|i, _| 0.1 * (i * l) as $s));
                    inverse_dynamics_batch(&qs, &vs, &vs)[B - 1][0]
                        + forward_dynamics_batch(&qs, &vs, &vs)[B - 1][0]
                        + mass_matrix_batch(&qs)[B - 1][(0, 0)]
                        + gravity_batch(&qs)[B - 1][0]
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

    /// The AVX-512 and AVX2 copies of the dispatched functions (`emit/dispatch.rs`) are
    /// `extern "C"`: a panic in one would abort instead of unwinding, so the `#[no_panic]`
    /// wrappers above, which see unwinding only, pass whatever those copies hold. They are
    /// checked here on the machine code instead: from every `*_avx512` and `*_avx2` function
    /// of the generated code in this test binary, the calls and jumps into other functions (direct, or through the global offset
    /// table) are followed, transitively, and none may reach the panic machinery. (ELF only: Linux; elsewhere the wrappers above are
    /// the check.)
    #[cfg(all(target_arch = "x86_64", target_os = "linux"))]
    mod machine_code {
        use iced_x86::{Decoder, DecoderOptions, Mnemonic, OpKind};
        use object::{Object, ObjectSection, ObjectSymbol, ObjectSymbolTable, SymbolKind};
        use std::collections::HashMap;

        /// The functions of an executable, by address: `(start, end, demangled name)`.
        struct Functions {
            funcs: Vec<(u64, u64, String)>,
            /// Sections' `(address, bytes)`.
            code: Vec<(u64, Vec<u8>)>,
            /// The functions that the dynamic relocations put into the slots of the global
            /// offset table, by slot address (calls into a position-independent executable's
            /// own standard library go through it).
            got: HashMap<u64, u64>,
        }

        impl Functions {
            fn of_this_test_binary() -> Functions {
                let exe = std::env::current_exe().expect("the test binary's path");
                let bytes = std::fs::read(&exe).expect("reads the test binary");
                let file = object::File::parse(&*bytes).expect("parses the test binary");
                let mut funcs: Vec<(u64, u64, String)> = file
                    .symbols()
                    .filter(|s| s.kind() == SymbolKind::Text && s.size() > 0)
                    .filter_map(|s| {
                        let name = rustc_demangle::demangle(s.name().ok()?);
                        Some((s.address(), s.address() + s.size(), format!("{name:#}")))
                    })
                    .collect();
                funcs.sort();
                funcs.dedup_by_key(|f| f.0);
                let code = file
                    .sections()
                    .filter(|s| s.kind() == object::SectionKind::Text)
                    .filter_map(|s| Some((s.address(), s.data().ok()?.to_vec())))
                    .collect();
                let mut got = HashMap::new();
                let dynsym = file.dynamic_symbol_table();
                for (slot, r) in file.dynamic_relocations().into_iter().flatten() {
                    let target = match r.target() {
                        // An index into the dynamic symbol table.
                        object::RelocationTarget::Symbol(i) => dynsym
                            .as_ref()
                            .and_then(|t| t.symbol_by_index(i).ok())
                            .filter(|s| !s.is_undefined())
                            .map(|s| s.address().wrapping_add(r.addend() as u64)),
                        // R_X86_64_RELATIVE: the load address plus the addend.
                        object::RelocationTarget::Absolute => Some(r.addend() as u64),
                        _ => None,
                    };
                    if let Some(t) = target {
                        got.insert(slot, t);
                    }
                }
                Functions { funcs, code, got }
            }

            fn named(&self, pred: impl Fn(&str) -> bool) -> Vec<usize> {
                (0..self.funcs.len())
                    .filter(|&i| pred(&self.funcs[i].2))
                    .collect()
            }

            fn containing(&self, addr: u64) -> Option<usize> {
                match self.funcs.partition_point(|f| f.0 <= addr) {
                    0 => None,
                    i if addr < self.funcs[i - 1].1 => Some(i - 1),
                    _ => None,
                }
            }

            fn bytes(&self, f: usize) -> &[u8] {
                let (start, end, _) = self.funcs[f];
                self.code
                    .iter()
                    .find(|(a, d)| *a <= start && end <= a + d.len() as u64)
                    .map(|(a, d)| &d[(start - a) as usize..(end - a) as usize])
                    .unwrap_or(&[])
            }

            /// The first function of the panic machinery that `roots` reach through calls and
            /// jumps, as the chain of names from a root to it.
            fn panic_path(&self, roots: &[usize]) -> Option<Vec<&str>> {
                let mut parent: Vec<Option<usize>> = vec![None; self.funcs.len()];
                let mut seen = vec![false; self.funcs.len()];
                let mut stack = roots.to_vec();
                for &r in roots {
                    seen[r] = true;
                }
                while let Some(f) = stack.pop() {
                    if is_panic(&self.funcs[f].2) {
                        let mut path = vec![self.funcs[f].2.as_str()];
                        let mut at = f;
                        while let Some(p) = parent[at] {
                            path.push(self.funcs[p].2.as_str());
                            at = p;
                        }
                        path.reverse();
                        return Some(path);
                    }
                    let (start, end, _) = self.funcs[f];
                    let decoder = Decoder::with_ip(64, self.bytes(f), start, DecoderOptions::NONE);
                    for ins in decoder {
                        // Direct calls, jumps and conditional jumps, and calls and jumps
                        // through the global offset table.
                        let target = if ins.op0_kind() == OpKind::NearBranch64 {
                            ins.near_branch_target()
                        } else if matches!(ins.mnemonic(), Mnemonic::Call | Mnemonic::Jmp)
                            && ins.op0_kind() == OpKind::Memory
                            && ins.is_ip_rel_memory_operand()
                        {
                            match self.got.get(&ins.ip_rel_memory_address()) {
                                Some(&t) => t,
                                None => continue,
                            }
                        } else {
                            continue;
                        };
                        if (start..end).contains(&target) {
                            continue;
                        }
                        // Targets outside this executable (the C library's `sincos`) are not
                        // followed.
                        if let Some(g) = self.containing(target) {
                            if !seen[g] {
                                seen[g] = true;
                                parent[g] = Some(f);
                                stack.push(g);
                            }
                        }
                    }
                }
                None
            }
        }

        /// Rust's panic entry points (`core::panicking::*`, `std::panicking::*`, the
        /// `panic_cannot_unwind` of an `extern "C"` function's abort, the unwinder).
        fn is_panic(name: &str) -> bool {
            name.contains("panicking")
                || name.contains("rust_begin_unwind")
                || name.contains("rust_panic")
                || name.contains("_Unwind_")
        }

        /// A function with a panic path (a bounds check on a run-time index): the check
        /// must find it, or it proves nothing.
        #[inline(never)]
        fn panic_probe(v: &[f64; 4], i: usize) -> f64 {
            v[i]
        }

        #[test]
        fn dispatched_copies_have_no_panic_path() {
            let probe: fn(&[f64; 4], usize) -> f64 = std::hint::black_box(panic_probe);
            assert_eq!(probe(&[1.0, 2.0, 3.0, 4.0], 2), 3.0);
            let f = Functions::of_this_test_binary();
            let probe = f.named(|n| n.ends_with("machine_code::panic_probe"));
            assert_eq!(probe.len(), 1, "the probe function in the symbol table");
            let path = f.panic_path(&probe);
            assert!(
                path.is_some(),
                "the check does not see the probe's bounds-check panic"
            );
            // `has_avx512` and `has_avx2` are left out: they are the standard library's feature
            // detection, whose first call reads the environment (`std_detect`'s cache), and
            // `extern "C"`, so that their callers know they cannot unwind; the copies do not
            // call them.
            let copies = f.named(|n| {
                n.contains("::generated::")
                    && (n.contains("_avx512") || n.contains("_avx2"))
                    && !n.ends_with("has_avx512")
                    && !n.ends_with("has_avx2")
            });
            // The batch bodies the dispatch leaves alone (small functions) are `extern "C"`
            // parts too, `X_batch_out_of_line`, out of line (see `batch::out_of_line`), and so
            // are the dispatched functions' where no copy runs (`X_portable`: a batch
            // function's everywhere, a single-state one's compiled for a target without AVX2,
            // as this test binary is unless built with `-C target-cpu`).
            let out_of_line = f.named(|n| {
                n.contains("::generated::")
                    && (n.contains("_batch_out_of_line") || n.contains("_portable"))
            });
            assert!(
                !out_of_line.is_empty(),
                "no `_batch_out_of_line` body found in the test binary"
            );
            let single = out_of_line
                .iter()
                .filter(|&&c| !f.funcs[c].2.contains("_batch_"))
                .count();
            if !cfg!(any(
                target_feature = "avx512f",
                all(target_feature = "avx2", target_feature = "fma")
            )) {
                assert!(
                    single >= 100,
                    "only {single} out-of-line single-state `_portable` bodies found"
                );
            }
            for &c in &out_of_line {
                if let Some(path) = f.panic_path(&[c]) {
                    panic!("a panic path in an out-of-line body: {}", path.join(" -> "));
                }
            }
            eprintln!(
                "{} out-of-line bodies ({single} of single-state functions), no panic path",
                out_of_line.len()
            );
            if cfg!(target_feature = "avx512f") {
                // Compiled for AVX-512 (`-C target-cpu=native` on such a CPU): no dispatch,
                // no copies; the wrappers above checked the only code there is.
                assert!(copies.is_empty());
                return;
            }
            // Every robot and function of the std cases has two (batch and derivatives too):
            // the AVX-512 copy and, unless the binary is compiled with AVX2 and FMA, the AVX2 one.
            let avx2 = copies
                .iter()
                .filter(|&&c| f.funcs[c].2.contains("_avx2"))
                .count();
            assert!(
                copies.len() - avx2 >= 100,
                "only {} AVX-512 copies found in the test binary",
                copies.len() - avx2
            );
            if !cfg!(all(target_feature = "avx2", target_feature = "fma")) {
                assert!(
                    avx2 >= 100,
                    "only {avx2} AVX2 copies found in the test binary"
                );
            }
            for &c in &copies {
                if let Some(path) = f.panic_path(&[c]) {
                    panic!("a panic path in a dispatched copy: {}", path.join(" -> "));
                }
            }
            eprintln!(
                "{} AVX-512 and {avx2} AVX2 copies, no panic path",
                copies.len() - avx2
            );
        }
    }
}
