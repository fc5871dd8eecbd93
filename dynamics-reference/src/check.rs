//! Argument checks shared by the public functions.

use dynamics_model::Robot;

/// Panics (a programming error, not a user-input error) when the configuration `q` does not
/// have `robot.nq()` entries; `name` is the argument's name for the message.
pub(crate) fn configuration(robot: &Robot, name: &str, q: &[f64]) {
    if robot.base.floating {
        assert!(
            q.len() == robot.nq(),
            "dynamics-reference: `{name}` has {} entries but robot `{}` has a floating base and {} joints{}, so nq = {}; \
             pass the base position p (3), its quaternion (x, y, z, w) (4), then one value per joint in the robot's joint order",
            q.len(),
            robot.name,
            robot.n_coordinates(),
            mimic_note(robot),
            robot.nq()
        );
    } else {
        joint_vector(robot, name, q);
    }
}

/// Panics when a velocity, acceleration or force vector `x` does not have `robot.nv()`
/// entries; `name` is the argument's name for the message.
pub(crate) fn velocity(robot: &Robot, name: &str, x: &[f64]) {
    if robot.base.floating {
        assert!(
            x.len() == robot.nv(),
            "dynamics-reference: `{name}` has {} entries but robot `{}` has a floating base and {} joints{}, so nv = {}; \
             pass the base's six entries (angular first, in the base frame), then one value per joint in the robot's joint order",
            x.len(),
            robot.name,
            robot.n_coordinates(),
            mimic_note(robot),
            robot.nv()
        );
    } else {
        joint_vector(robot, name, x);
    }
}

/// The fixed-base case of both checks: one entry per joint.
fn joint_vector(robot: &Robot, name: &str, x: &[f64]) {
    assert!(
        x.len() == robot.n_coordinates(),
        "dynamics-reference: `{name}` has {} entries but robot `{}` has {} joints{}; pass one value per joint, in the robot's joint order (root to tip on a chain)",
        x.len(),
        robot.name,
        robot.n_coordinates(),
        mimic_note(robot)
    );
}

/// ` (not counting its N mimic joints, which follow their leaders)`, or nothing.
fn mimic_note(robot: &Robot) -> String {
    match robot.dof() - robot.n_coordinates() {
        0 => String::new(),
        k => format!(" (not counting its {k} mimic joints, which follow their leaders)"),
    }
}
