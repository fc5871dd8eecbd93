dynamics_macros::robot! {
    pub struct Arm;
    payload_link: "upper_arm",
    joint revolute shoulder {
        screw: [0, 0, 1, 0, 0, 0],
        link upper_arm { home: { xyz: [0, 0, 0.5] }, mass: 2.0, inertia: [0.02, 0.02, 0.01, 0, 0, 0] },
    },
}

fn main() {}
