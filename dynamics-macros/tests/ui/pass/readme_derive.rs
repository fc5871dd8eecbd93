// The README's `#[derive(Dynamics)]` example: robot files, paths relative to Cargo.toml.
use dynamics_macros::Dynamics;
use nalgebra::SVector;

/// The UR5 of the shipped URDF.
#[derive(Dynamics)]
#[dynamics(file = "robots/ur5.urdf")]
pub struct Ur5;

/// The same arm in f32, with the Modern Robotics course's parameters (a TOML file).
#[derive(Dynamics)]
#[dynamics(file = "robots/mr_ur5.toml", scalar = "f32", gravity = [0, 0, -9.81])]
pub struct MrUr5;

/// A Panda with its last joint locked at 45° and the flange as end effector: 6 joints.
#[derive(Dynamics)]
#[dynamics(
    file = "tests/data/robots/panda.urdf",
    tip = "panda_link8",
    lock(panda_joint7 = FRAC_PI_4),
    nalgebra = ::nalgebra,
)]
pub struct Panda;

fn main() {
    let q = SVector::<f64, 6>::from_fn(|i, _| 0.1 * i as f64);
    let g = Ur5.gravity(&q);
    let g32 = MrUr5.gravity(&q.map(|x| x as f32));
    let m = Panda.mass_matrix(&SVector::<f64, 6>::zeros());
    println!("{g} {g32} {m} {:?}", Panda::JOINT_NAMES);
}
