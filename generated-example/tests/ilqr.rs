//! The iLQR solver on the generated derivatives (the problem of `examples/ilqr_ur5.rs`): the
//! linearised Euler step equals central differences of the step itself, and the reaching
//! problem converges, its cost never increasing, to rest at the goal.

use generated_example::ilqr::{self, Cost, Gains, Iteration};
use generated_example::ur5::Ur5;
use nalgebra::{SMatrix, SVector};

type X = SVector<f64, 12>;
type U = SVector<f64, 6>;
const H: f64 = 0.01;

fn step(x: &X, u: &U) -> ilqr::Linearised<12, 6> {
    ilqr::semi_implicit_euler::<6, 12>(H, x, u, &|q, qd, tau| {
        Ur5.forward_dynamics_with_derivatives(q, qd, tau)
    })
    .expect("12 = 2 · 6")
}

#[test]
fn linearised_step_equals_central_differences() {
    let x = X::from_fn(|i, _| 0.3 - 0.17 * i as f64);
    let u = U::from_fn(|i, _| 2.0 + 3.0 * i as f64);
    let (_, a, b) = step(&x, &u);
    let e = 1e-6;
    let mut worst = 0.0f64;
    for j in 0..12 {
        let mut dx = X::zeros();
        dx[j] = e;
        let col = (step(&(x + dx), &u).0 - step(&(x - dx), &u).0) / (2.0 * e);
        worst = worst.max((col - a.column(j)).amax() / (1.0 + a.amax()));
    }
    for j in 0..6 {
        let mut du = U::zeros();
        du[j] = e;
        let col = (step(&x, &(u + du)).0 - step(&x, &(u - du)).0) / (2.0 * e);
        worst = worst.max((col - b.column(j)).amax() / (1.0 + b.amax()));
    }
    assert!(worst < 1e-7, "linearisation off by {worst:e}");
    assert!(
        ilqr::semi_implicit_euler::<6, 10>(H, &SVector::zeros(), &u, &|q, qd, tau| {
            Ur5.forward_dynamics_with_derivatives(q, qd, tau)
        })
        .is_none()
    );
}

#[test]
fn reaching_converges_to_rest_at_the_goal() {
    const STEPS: usize = 150;
    let goal_q = SVector::<f64, 6>::from([0.8, -1.2, 1.5, -0.6, 0.9, 0.3]);
    let mut goal = X::zeros();
    goal.fixed_rows_mut::<6>(0).copy_from(&goal_q);
    let cost = Cost {
        goal,
        u_ref: Ur5.gravity(&goal_q),
        running: X::zeros(),
        control: U::repeat(1e-3),
        terminal: X::from_fn(|i, _| if i < 6 { 1e4 } else { 1e3 }),
    };
    let mut xs = vec![X::zeros(); STEPS + 1];
    let mut us = vec![Ur5.gravity(&SVector::zeros()); STEPS];
    for k in 0..STEPS {
        xs[k + 1] = step(&xs[k], &us[k]).0;
    }
    let initial = cost.total(&xs, &us);
    let mut scratch = vec![(SMatrix::zeros(), SMatrix::zeros()); STEPS];
    let mut gains = vec![Gains::default(); STEPS];
    let mut history = vec![Iteration::default(); 100];
    let ran = ilqr::solve(
        &step,
        &cost,
        &mut xs,
        &mut us,
        &mut scratch,
        &mut gains,
        &mut history,
        1e-6,
    )
    .expect("buffers fit");
    assert!(ran < 100, "no convergence in 100 iterations");
    let costs: Vec<f64> = std::iter::once(initial)
        .chain(history[..ran].iter().map(|i| i.cost))
        .collect();
    assert!(
        costs.windows(2).all(|w| w[1] <= w[0]),
        "cost increased: {costs:?}"
    );
    let last = costs[ran];
    assert!(last < 1e-3 * initial, "cost {initial} -> {last}");
    let end = xs[STEPS];
    assert!((end.fixed_rows::<6>(0) - goal_q).amax() < 5e-3, "{end}");
    assert!(end.fixed_rows::<6>(6).amax() < 1e-2, "{end}");
    // The stored trajectory is the rollout of the stored controls.
    let mut x = xs[0];
    for (k, u) in us.iter().enumerate() {
        assert!((x - xs[k]).amax() < 1e-12);
        x = step(&x, u).0;
    }
    // Wrong buffer sizes are an error, not a panic.
    assert_eq!(
        ilqr::solve(
            &step,
            &cost,
            &mut xs[..10],
            &mut us,
            &mut scratch,
            &mut gains,
            &mut history,
            1e-6
        ),
        Err(ilqr::IlqrError::Buffers)
    );
}
