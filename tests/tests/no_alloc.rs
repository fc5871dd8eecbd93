//! Zero heap allocations per call: a counting global allocator around calls of every
//! generated function of every generated robot. Only the calling thread's allocations
//! count: the test harness's own threads allocate while a test runs (a run under load
//! once counted 4 of theirs against a robot).

use nalgebra::SVector;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

thread_local! {
    /// Allocations made by this thread (no destructor, constant initialiser: usable inside
    /// the allocator).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

/// This thread's allocations so far.
fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

static CHECKED: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator and only counts.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

macro_rules! no_alloc {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {{
        use dynamics_tests::generated::$m::Robot;
        let q = SVector::<$s, $nq>::from_fn(|i, _| 0.3 + 0.1 * i as $s);
        let qd = SVector::<$s, $nv>::from_fn(|i, _| 0.5 - 0.2 * i as $s);
        let x = SVector::<$s, $nv>::from_fn(|i, _| 0.7 * i as $s - 1.0);
        let before = allocations();
        for _ in 0..3 {
            black_box(Robot::DEFAULT.mass_matrix(black_box(&q)));
            // In a frame of its own: one more matrix per robot in this function's frame
            // overflowed the test thread's stack in unoptimised builds.
            #[inline(never)]
            fn lower_into(q: &SVector<$s, $nq>) {
                let mut lower = nalgebra::SMatrix::<$s, $nv, $nv>::zeros();
                Robot::DEFAULT.mass_matrix_lower_into(black_box(q), &mut lower);
                black_box(&lower);
            }
            lower_into(&q);
            black_box(Robot::DEFAULT.coriolis(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.gravity(black_box(&q)));
            black_box(Robot::DEFAULT.inverse_dynamics(
                black_box(&q),
                black_box(&qd),
                black_box(&x),
            ));
            black_box(Robot::DEFAULT.forward_dynamics(
                black_box(&q),
                black_box(&qd),
                black_box(&x),
            ));
            black_box(Robot::DEFAULT.kinetic_energy(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.potential_energy(black_box(&q)));
            black_box(Robot::DEFAULT.mass_matrix_dot(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.jacobian_space_dot(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.jacobian_body_dot(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.end_effector_pose(black_box(&q)));
            black_box(Robot::DEFAULT.jacobian_space(black_box(&q)));
            black_box(Robot::DEFAULT.jacobian_body(black_box(&q)));
            let f = SVector::<$s, 6>::from_fn(|i, _| 0.2 * i as $s - 0.4);
            black_box(Robot::DEFAULT.friction(black_box(&qd)));
            black_box(Robot::DEFAULT.coriolis_matrix(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.mass_matrix_and_bias(black_box(&q), black_box(&qd)));
            black_box(Robot::DEFAULT.end_effector_forces(black_box(&q), black_box(&f)));
            black_box(Robot::DEFAULT.inverse_dynamics_with_tip(&q, &qd, &x, black_box(&f)));
            black_box(Robot::DEFAULT.forward_dynamics_with_tip(&q, &qd, &x, black_box(&f)));
            black_box(Robot::DEFAULT.task_space_mass_matrix(black_box(&q)));
            black_box(Robot::DEFAULT.task_space_bias(black_box(&q), black_box(&qd)));
            let a = nalgebra::SMatrix::<$s, 1, $nv>::from_fn(|_, j| 0.3 * j as $s + 0.1);
            let adq = SVector::<$s, 1>::new(0.2);
            black_box(Robot::DEFAULT.constrained_forward_dynamics(
                &q,
                &qd,
                &x,
                black_box(&a),
                &adq,
            ));
        }
        let after = allocations();
        assert_eq!(after - before, 0, "{} allocated", stringify!($m));
        CHECKED.fetch_add(1, Ordering::SeqCst);
    }};
}

macro_rules! no_alloc_frames {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {{
        use dynamics_tests::generated::$m::Robot;
        let q = SVector::<$s, $nq>::from_fn(|i, _| 0.3 + 0.1 * i as $s);
        let before = allocations();
        for _ in 0..3 {
            black_box(Robot::DEFAULT.frame_poses(black_box(&q)));
            black_box(Robot::DEFAULT.frame_jacobians_space(black_box(&q)));
            black_box(Robot::DEFAULT.frame_jacobians_body(black_box(&q)));
        }
        let after = allocations();
        assert_eq!(after - before, 0, "{} allocated", stringify!($m));
        FRAMES_CHECKED.fetch_add(1, Ordering::SeqCst);
    }};
}

static FRAMES_CHECKED: AtomicUsize = AtomicUsize::new(0);

macro_rules! no_alloc_batch {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {{
        use dynamics_tests::generated::$m::Robot;
        let qs = [SVector::<$s, $nq>::from_fn(|i, _| 0.3 + 0.1 * i as $s); 4];
        let qds = [SVector::<$s, $nv>::from_fn(|i, _| 0.5 - 0.2 * i as $s); 4];
        let xs = [SVector::<$s, $nv>::from_fn(|i, _| 0.7 * i as $s - 1.0); 4];
        let before = allocations();
        for _ in 0..3 {
            black_box(Robot::DEFAULT.inverse_dynamics_batch(&qs, &qds, black_box(&xs)));
            black_box(Robot::DEFAULT.forward_dynamics_batch(&qs, &qds, black_box(&xs)));
            black_box(Robot::DEFAULT.mass_matrix_batch(black_box(&qs)));
            black_box(Robot::DEFAULT.gravity_batch(black_box(&qs)));
        }
        let after = allocations();
        assert_eq!(after - before, 0, "{} allocated in a batch", stringify!($m));
        BATCH_CHECKED.fetch_add(1, Ordering::SeqCst);
    }};
}

static BATCH_CHECKED: AtomicUsize = AtomicUsize::new(0);

#[test]
fn generated_functions_never_allocate() {
    dynamics_tests::with_cases!(no_alloc);
    // Every generated module once (a file with run-time parameters is registered twice in
    // CASES, as `module` and `module+payload`).
    let modules = dynamics_tests::CASES
        .iter()
        .filter(|c| !c.module.contains('+'))
        .count();
    assert_eq!(CHECKED.load(Ordering::SeqCst), modules);
    // In the same test (one thread for all the checks).
    dynamics_tests::with_frame_cases!(no_alloc_frames);
    assert!(FRAMES_CHECKED.load(Ordering::SeqCst) >= 6);
    dynamics_tests::with_batch_cases!(no_alloc_batch);
    assert!(BATCH_CHECKED.load(Ordering::SeqCst) >= 10);
    // The counter works: a Vec does allocate.
    let before = allocations();
    black_box(vec![1u8; 16]);
    assert!(allocations() > before);
}
