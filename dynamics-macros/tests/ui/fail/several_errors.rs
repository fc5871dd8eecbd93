// Every problem of the model is reported at once, each on its own tokens.
dynamics_macros::robot! {
    pub struct Arm;
    joint revolute shoulder {
        screw: [0, 0, 1.5, 0, 0, 0],
        link upper_arm { home: { xyz: [0, 0, 0.5] }, mass: 2.0, inertia: [0.01, 0.01, 0.03, 0, 0, 0] },
    },
    joint prismatic slide {
        axis: [1, 0, 0],
        link carriage { home: { xyz: [0, 0, 0.5] }, mass: -1, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
    },
}

fn main() {}
