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

/// A rotor (gear ratio 5–60, rotor inertia 1e-6–1e-4 kg·m², so armatures of about 1e-4 to
/// 0.4), viscous damping (0–2) and Coulomb friction (0–3) on every joint of `robot`, drawn
/// from `seed` (shared by build.rs and the harness).
pub fn actuated(mut robot: dynamics_model::Robot, seed: u64) -> dynamics_model::Robot {
    let mut rng = dynamics_model::random::Rng::new(seed ^ 0xAC7);
    for joint in &mut robot.joints {
        joint.gear_ratio = rng.uniform(5.0, 60.0);
        joint.rotor_inertia = 10f64.powf(rng.uniform(-6.0, -4.0));
        joint.damping = rng.uniform(0.0, 2.0);
        joint.friction = rng.uniform(0.0, 3.0);
    }
    robot
}

/// The armature of the Panda case of `data/reference/panda.jacobians.json`: 0.1·(i + 1)
/// kg·m² on joint i (0-based).
pub fn panda_armature(mut robot: dynamics_model::Robot) -> dynamics_model::Robot {
    for (i, joint) in robot.joints.iter_mut().enumerate() {
        joint.rotor_inertia = 0.1 * (i as f64 + 1.0);
        joint.gear_ratio = 1.0;
    }
    robot
}
