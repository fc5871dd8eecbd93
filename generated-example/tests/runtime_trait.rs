//! Controllers generic over robots: every generated struct implements
//! `dynamics_runtime::Dynamics`, and the trait's functions and constants are the inherent ones.

use dynamics_runtime::Dynamics;
use generated_example::{pendulum::Pendulum, ur5::Ur5};
use nalgebra::SVector;

/// Computed-torque control `τ = M(q) q̈_d + c(q, q̇) + g(q)`, for any robot.
fn computed_torque<R: Dynamics<f64, N, N>, const N: usize>(
    robot: &R,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    qdd: &SVector<f64, N>,
) -> SVector<f64, N> {
    robot.mass_matrix(q) * qdd + robot.coriolis(q, qd) + robot.gravity(q)
}

/// Joint positions clamped to the robot's limits.
fn clamp<R: Dynamics<f64, N, N>, const N: usize>(q: &SVector<f64, N>) -> SVector<f64, N> {
    SVector::from_fn(|i, _| q[i].clamp(R::POSITION_LIMITS[i][0], R::POSITION_LIMITS[i][1]))
}

fn check<R: Dynamics<f64, N, N>, const N: usize>(robot: &R) {
    let q = SVector::<f64, N>::from_fn(|i, _| 0.3 * i as f64 - 0.7);
    let qd = SVector::<f64, N>::from_fn(|i, _| 0.5 - 0.2 * i as f64);
    let qdd = SVector::<f64, N>::from_fn(|i, _| 0.1 * i as f64);
    let tau = computed_torque(robot, &q, &qd, &qdd);
    let direct = robot.inverse_dynamics(&q, &qd, &qdd);
    assert!((tau - direct).amax() <= 1e-12 * direct.amax().max(1.0));
    let back = robot.forward_dynamics(&q, &qd, &tau);
    assert!((back - qdd).amax() <= 1e-9);
    assert_eq!(R::JOINT_NAMES.len(), N);
    assert_eq!(R::VELOCITY_LIMITS.len(), N);
    assert_eq!(R::EFFORT_LIMITS.len(), N);
    let far = SVector::<f64, N>::repeat(100.0);
    let clamped = clamp::<R, N>(&far);
    for i in 0..N {
        assert!(clamped[i] <= R::POSITION_LIMITS[i][1]);
    }
}

#[test]
#[allow(clippy::approx_constant)] // the URDF's 3.14159265359, as written, not π
fn generated_robots_implement_the_runtime_trait() {
    check(&Ur5);
    check(&Pendulum);
    assert_eq!(<Ur5 as Dynamics<f64, 6, 6>>::JOINT_NAMES, &Ur5::JOINT_NAMES);
    // The UR5's limits come from its URDF as written: elbow ±3.14159265359 rad, effort
    // 150 and 28 N·m, velocity 3.15 and 3.2 rad/s.
    assert_eq!(Ur5::POSITION_LIMITS[2], [-3.14159265359, 3.14159265359]);
    assert_eq!(Ur5::VELOCITY_LIMITS, [3.15, 3.15, 3.15, 3.2, 3.2, 3.2]);
    assert_eq!(Ur5::EFFORT_LIMITS[0], 150.0);
    assert_eq!(Ur5::EFFORT_LIMITS[5], 28.0);
    // The pendulum's file gives no limits.
    assert_eq!(
        Pendulum::POSITION_LIMITS[0],
        [f64::NEG_INFINITY, f64::INFINITY]
    );
}
