dynamics_macros::robot! {
    pub struct Arm;
    joint revolute shoulder {
        screw: [0, 0, 1, 0, 0, 0],
        link upper_arm { mass: 2.0, inertia: [0.02, 0.02, 0.01, 0, 0, 0] },
    },
    joint revolute elbow {
        link forearm { home: { xyz: [0, 0, 0.5] }, mass: 1.0, inertia: [0.01, 0.01, 0.005, 0, 0, 0] },
    },
}

fn main() {
    // The struct is still defined: no follow-on error here.
    let _ = Arm;
}
