#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "robots/ur5.urdf", scalar = "f16", colour = "red")]
pub struct Ur5;

#[derive(dynamics_macros::Dynamics)]
pub struct NoFile;

fn main() {}
