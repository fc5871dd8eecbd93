#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/broken_inertia.urdf")]
pub struct Broken;

fn main() {}
