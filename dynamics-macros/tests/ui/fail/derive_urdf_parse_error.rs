#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/malformed.urdf")]
pub struct Malformed;

fn main() {}
