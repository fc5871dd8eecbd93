#[derive(dynamics_macros::Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/malformed.toml")]
pub struct Malformed;

fn main() {}
