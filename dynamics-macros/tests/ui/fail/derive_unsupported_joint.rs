#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/unsupported_joint.urdf")]
pub struct Planar;

fn main() {}
