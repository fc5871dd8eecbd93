dynamics_macros::robot! {
    pub struct Arm;
    joint revolute shoulder {
        screw: [0, 0, 1, 0, 0, 0],
        home: { xyz: [0, 0, 0.5] },
        mass: 2.0,
        inertia: [0.02, 0.02, 0.01, 0, 0, 0],
        mass: 3.0,
    },
}

fn main() {}
