// Kinematic trees through `#[derive(Dynamics)]`: a two-armed torso on a fixed base, and the
// Solo-12 quadruped on a floating base (q = (p, quat, θ), ν = (ω_b, v_b, θ̇)).
use dynamics_macros::Dynamics;
use nalgebra::SVector;

#[derive(Dynamics)]
#[dynamics(file = "dynamics-macros/tests/ui/fixtures/branches.urdf")]
pub struct TwoArms;

#[derive(Dynamics)]
#[dynamics(file = "tests/data/robots/trees/solo12.urdf", floating_base)]
pub struct Solo;

// The feet in a chosen order (default: every leaf link of the file), with only the frames'
// functions (the whole of Solo-12's code is `Solo`'s: compiled twice, it was most of this
// test's time).
#[derive(Dynamics)]
#[dynamics(
    file = "tests/data/robots/trees/solo12.urdf",
    floating_base,
    frames(HR_FOOT, FL_FOOT),
    functions(frame_poses, frame_jacobians_body),
    no_runtime_trait
)]
pub struct SoloFeet;

// Only what a foot-contact controller needs: smaller code, faster builds.
#[derive(Dynamics)]
#[dynamics(
    file = "tests/data/robots/trees/solo12.urdf",
    floating_base,
    functions(gravity, frame_poses, frame_jacobians_body),
    no_runtime_trait
)]
pub struct SoloContacts;

fn main() {
    assert_eq!((TwoArms::NQ, TwoArms::NV), (TwoArms::DOF, TwoArms::DOF));
    assert_eq!((Solo::DOF, Solo::NQ, Solo::NV), (12, 19, 18));
    let mut q = SVector::<f64, 19>::zeros();
    q[6] = 1.0; // the identity quaternion (x, y, z, w)
    let v = SVector::<f64, 18>::zeros();
    // At rest, level, the base rows of g are the weight: force (m·9.81 up) in the base frame.
    let g = Solo.gravity(&q);
    assert!(g[5] > 0.0 && g[3].abs() < 1e-12 && g[4].abs() < 1e-12);
    let a = Solo.forward_dynamics(&q, &v, &g);
    assert!(a.norm() < 1e-9);
    let m = Solo.mass_matrix(&q);
    assert_eq!(m[(6, 9)], 0.0); // front-left and front-right hips: different branches
    // Feet: the default frames are the four leaf links; at the home pose the feet lie below
    // the base, and each foot's Jacobian has columns for the base and its own leg only.
    assert_eq!(Solo::FRAME_NAMES.len(), 4);
    assert_eq!(SoloFeet::FRAME_NAMES, ["HR_FOOT", "FL_FOOT"]);
    let feet = SoloFeet.frame_poses(&q);
    assert!(feet.iter().all(|f| f.translation.z < -0.1));
    assert!(feet[0].translation.x < 0.0 && feet[1].translation.x > 0.0);
    let contacts = SoloContacts.frame_jacobians_body(&q);
    assert_eq!(contacts.len(), 4);
    assert_eq!(SoloContacts.gravity(&q), g);
    let j = SoloFeet.frame_jacobians_body(&q);
    assert!((0..6).all(|c| j[1].column(c).norm() > 0.0));
    assert!((9..18).all(|c| j[1].column(c).norm() == 0.0)); // not on the front-left leg
}
