// The README's `robot!` example: the rotational pendulum of Modern Robotics Exercise 8.4.
use nalgebra::Vector2;

dynamics_macros::robot! {
    /// The rotational pendulum of Modern Robotics Exercise 8.4.
    pub struct Pendulum;
    gravity: [0, 0, -10],
    joint revolute joint1 {
        screw: [0, 0, 1, 0, 0, 0],
        link arm { home: { xyz: [1, 0, 0] }, mass: 2, inertia: [4, 4, 4, 0, 0, 0] },
    },
    joint revolute joint2 {
        axis: [1, 0, 0], point: [0, 0, 0],
        limits: [-PI / 2, PI / 2],
        link pendulum { home: { xyz: [0, 0, -1] }, mass: 2, inertia: [4, 4, 0, 0, 0, 0] },
    },
    end_effector bob { home: { xyz: [0, 0, 0] } },
}

fn main() {
    let robot = Pendulum;
    let q = Vector2::new(0.1, 0.2);
    let qd = Vector2::new(0.3, -0.4);
    let m = robot.mass_matrix(&q);
    let tau = robot.inverse_dynamics(&q, &qd, &Vector2::new(1.0, 2.0));
    let qdd = robot.forward_dynamics(&q, &qd, &tau);
    assert!((qdd - Vector2::new(1.0, 2.0)).amax() < 1e-9);
    println!(
        "{} joints {:?}: M = {m}",
        Pendulum::DOF,
        Pendulum::JOINT_NAMES
    );
}
