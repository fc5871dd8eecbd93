/// How the compiled random trees are drawn (shared by build.rs and the harness through
/// `include!`): a quarter of the joints prismatic, four in ten bodies starting a branch.
pub fn tree_spec(dof: usize, floating: bool) -> dynamics_model::random::TreeSpec {
    dynamics_model::random::TreeSpec {
        dof,
        prismatic: 0.25,
        branching: 0.4,
        floating,
    }
}

/// A named frame on every leaf link of a compiled random tree, and one on the base, at
/// fixed poses off the link origins (shared by build.rs and the harness).
pub fn with_leaf_frames(mut robot: dynamics_model::Robot) -> dynamics_model::Robot {
    let n = robot.dof();
    let leaves = (0..n).filter(|&i| robot.links.iter().all(|l| l.parent != Some(i)));
    robot.frames = leaves
        .map(Some)
        .chain([None])
        .enumerate()
        .map(|(k, parent)| {
            let x = 0.05 * (k as f64 + 1.0);
            dynamics_model::Frame {
                name: format!("frame_{k}"),
                parent,
                home: dynamics_model::lie::xyz_rpy([x, -0.04, 0.1], [0.3, -x, 0.7]),
            }
        })
        .collect();
    robot
}
