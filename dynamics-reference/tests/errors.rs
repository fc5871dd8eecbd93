//! Failures are reported, not panicked: a mass matrix that is not positive definite, and the
//! messages of misuse.

use dynamics_model::lie::twist;
use dynamics_model::Robot;
use dynamics_reference as dr;
use nalgebra::{DMatrix, Matrix4, Matrix6, Vector3, Vector6};

/// Two revolute joints about z; link 2 is massless, so joint 2 moves nothing and row 2 of M
/// is zero.
fn robot_with_massless_tip() -> Robot {
    let z = Vector3::z();
    let s1 = twist(&z, &Vector3::zeros());
    let s2 = twist(&z, &(-z.cross(&Vector3::new(1.0, 0.0, 0.0))));
    let mut m01 = Matrix4::identity();
    m01[(0, 3)] = 0.5;
    let mut m12 = Matrix4::identity();
    m12[(0, 3)] = 0.5;
    let g1 = Matrix6::from_diagonal(&Vector6::new(0.1, 0.1, 0.1, 1.0, 1.0, 1.0));
    Robot::from_mr_lists(
        &[m01, m12, Matrix4::identity()],
        &[g1, Matrix6::zeros()],
        &[s1, s2],
        Vector3::new(0.0, 0.0, -9.81),
    )
    .expect("a massless link is a valid model")
}

#[test]
fn forward_dynamics_reports_a_singular_mass_matrix() {
    let robot = robot_with_massless_tip();
    let q = [0.3, -0.2];
    let m = dr::mass_matrix(&robot, &q);
    assert_eq!(m[(1, 1)], 0.0);
    let err = dr::forward_dynamics(
        &robot,
        &q,
        &[0.0, 0.0],
        &[1.0, 0.0],
        &robot.gravity,
        &Vector6::zeros(),
    )
    .unwrap_err();
    assert_eq!(
        err,
        dr::ReferenceError::MassMatrixNotPositiveDefinite {
            q: q.to_vec(),
            step: None
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("not positive definite") && text.contains("positive mass"),
        "{text}"
    );
}

#[test]
fn trajectory_reports_the_failing_row() {
    let robot = robot_with_massless_tip();
    let err = dr::forward_dynamics_trajectory(
        &robot,
        &[0.0, 0.0],
        &[0.0, 0.0],
        &DMatrix::zeros(3, 2),
        &robot.gravity,
        &DMatrix::zeros(3, 6),
        0.01,
        4,
    )
    .unwrap_err();
    assert!(matches!(
        err,
        dr::ReferenceError::MassMatrixNotPositiveDefinite { step: Some(0), .. }
    ));
    assert!(err.to_string().contains("trajectory row 0"));
}

#[test]
#[should_panic(expected = "`qd` has 1 entries but robot `robot` has 2 joints")]
fn wrong_length_names_the_argument() {
    let robot = robot_with_massless_tip();
    dr::inverse_dynamics(
        &robot,
        &[0.0, 0.0],
        &[0.0],
        &[0.0, 0.0],
        &robot.gravity,
        &Vector6::zeros(),
    );
}

#[test]
#[should_panic(
    expected = "`qdd` has 3 entries but robot `random_tree_3` has a floating base and 3 joints, so nv = 9"
)]
fn wrong_length_on_a_floating_base_names_the_argument_and_nv() {
    let robot = dynamics_model::random::random_tree(
        3,
        dynamics_model::random::TreeSpec {
            dof: 3,
            prismatic: 0.0,
            branching: 0.5,
            floating: true,
        },
    );
    let q = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.1, 0.2, 0.3];
    dr::inverse_dynamics(
        &robot,
        &q,
        &[0.0; 9],
        &[0.0; 3],
        &robot.gravity,
        &Vector6::zeros(),
    );
}

#[test]
#[should_panic(
    expected = "`q` has 9 entries but robot `random_tree_3` has a floating base and 3 joints, so nq = 10"
)]
fn configuration_of_the_wrong_length_on_a_floating_base() {
    let robot = dynamics_model::random::random_tree(
        3,
        dynamics_model::random::TreeSpec {
            dof: 3,
            prismatic: 0.0,
            branching: 0.5,
            floating: true,
        },
    );
    dr::mass_matrix(&robot, &[0.0; 9]);
}

#[test]
#[should_panic(expected = "the base quaternion [0.0, 0.0, 0.0, 0.0] is zero")]
fn zero_quaternion_is_refused() {
    let robot = dynamics_model::random::random_tree(
        3,
        dynamics_model::random::TreeSpec {
            dof: 1,
            prismatic: 0.0,
            branching: 0.0,
            floating: true,
        },
    );
    dr::mass_matrix(&robot, &[0.0; 8]);
}
