#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "robots/ur5.urdf", runtime_parameters)]
pub struct Ur5 {
    pub gravity: [f64; 3],
}

fn main() {}
