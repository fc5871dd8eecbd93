//! The generated `jacobian_space_dot`, `jacobian_body_dot` against the reference's closed
//! forms (Exercise 8.6 brackets, `dynamics_reference::jacobian_*_dot`) on every compiled f64
//! robot: chains, trees, floating bases and mimic joints, at seeded random states.
//! ‖x − y‖∞ ≤ 1e-10·‖y‖∞ + 1e-12.

use dynamics_model::random::Rng;
use dynamics_tests::CASES;

#[test]
fn generated_jacobian_rates_equal_the_reference() {
    let mut worst = 0.0f64;
    let mut count = 0;
    for case in CASES.iter().filter(|c| c.scalar == "f64") {
        let robot = case.spec.robot();
        let mut rng = Rng::new(86);
        for _ in 0..4 {
            // On a floating base q[3..7] is a quaternion of any non-zero length.
            let q: Vec<f64> = (0..robot.nq()).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let qd: Vec<f64> = (0..robot.nv()).map(|_| rng.uniform(-2.0, 2.0)).collect();
            for (what, ours, reference) in [
                (
                    "J̇_s",
                    case.imp.jacobian_space_dot(&q, &qd),
                    dynamics_reference::jacobian_space_dot(&robot, &q, &qd),
                ),
                (
                    "J̇_b",
                    case.imp.jacobian_body_dot(&q, &qd),
                    dynamics_reference::jacobian_body_dot(&robot, &q, &qd),
                ),
            ] {
                let what = format!("{} {what}", case.module);
                let (err, scale) = dynamics_tests::assert_close(
                    &what,
                    ours.as_slice(),
                    reference.as_slice(),
                    1e-10,
                    1e-12,
                );
                worst = worst.max(err / scale.max(1e-300));
            }
            count += 1;
        }
    }
    assert!(count > 40, "{count} states");
    println!("generated J̇ vs reference J̇: worst relative error {worst:e} over {count} states");
}
