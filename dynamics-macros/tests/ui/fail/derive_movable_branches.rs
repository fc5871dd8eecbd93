#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/branches.urdf")]
pub struct TwoArms;

fn main() {}
