//! The tests that run the generated code of the compiled test robots (`dynamics_tests::CASES`,
//! a table of every robot's functions), as one test binary. Each file was its own binary
//! before, and each linked all of the robots' code (372–476 MB at the test profile's
//! opt-level 0): ten copies, 3.9 GB of CI's disk and ten long links; this binary is 577 MB.
//! `no_alloc.rs` stays apart (its counting global allocator would count the other tests'
//! allocations).

mod generated_chapter8;
mod generated_derivatives;
mod generated_regressor;
mod generated_vs_reference;
mod jacobian_dot_vs_reference;
mod mimic;
mod pendulum_closed_forms;
mod pinocchio_jacobians;
mod reference_files;
mod tolerance;
mod trees_pinocchio;
