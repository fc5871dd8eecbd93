#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "robots/ur5.urdf", method = "lagrangian")]
pub struct Ur5;

fn main() {}
