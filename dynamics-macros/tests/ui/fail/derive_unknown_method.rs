#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "robots/ur5.urdf", method = "euler_lagrange")]
pub struct Ur5;

fn main() {}
