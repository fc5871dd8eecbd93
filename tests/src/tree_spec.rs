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
