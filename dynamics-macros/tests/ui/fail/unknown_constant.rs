dynamics_macros::robot! {
    pub struct Arm;
    joint revolute shoulder {
        screw: [0, 0, 1, 0, 0, 0],
        limits: [-pi / 2, PI / 2],
        link upper_arm { home: { rpy: [0, HALF_PI, 0] }, mass: 2.0, inertia: [0.02, 0.02, 0.01, 0, 0, 0] },
    },
}

fn main() {}
