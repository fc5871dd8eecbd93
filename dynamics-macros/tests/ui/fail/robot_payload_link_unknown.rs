dynamics_macros::robot! {
    pub struct Arm;
    runtime_parameters: true,
    payload_link: "gripper",
    joint revolute shoulder {
        screw: [0, 0, 1, 0, 0, 0],
        link upper_arm { home: { xyz: [0, 0, 0.5] }, mass: 2.0, inertia: [0.02, 0.02, 0.01, 0, 0, 0] },
    },
}

fn main() {}
