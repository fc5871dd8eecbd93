//! Argument checks shared by the public functions.

use dynamics_model::Robot;

/// Panics (a programming error, not a user-input error) when `x` does not have one entry per
/// joint of `robot`; `name` is the argument's name for the message.
pub(crate) fn joint_vector(robot: &Robot, name: &str, x: &[f64]) {
    assert!(
        x.len() == robot.dof(),
        "dynamics-reference: `{name}` has {} entries but robot `{}` has {} joints; pass one value per joint, root to tip",
        x.len(),
        robot.name,
        robot.dof()
    );
}
