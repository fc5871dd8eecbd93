#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "robots/no_such_robot.urdf")]
pub struct Missing;

fn main() {}
