//! The generated inverse dynamics needs fewer operations than Featherstone's commonly cited
//! RNEA count (93n − 69 multiplications, 81n − 66 additions) on the UR5, rand7 and the Panda.

use dynamics_gen::expand::expand;
use dynamics_model::LoadOptions;

#[test]
fn inverse_dynamics_beats_featherstones_rnea_count() {
    let panda = dynamics_tests::data_dir().join("robots/panda.urdf");
    let robots = [
        dynamics_model::load("ur5", &LoadOptions::default()).expect("ur5"),
        dynamics_model::load("rand7", &LoadOptions::default()).expect("rand7"),
        dynamics_model::load_file(&panda, &LoadOptions::default()).expect("panda"),
    ];
    for robot in &robots {
        let d = expand(robot);
        let n = robot.dof();
        let id = d.graph.op_counts(&d.inverse_dynamics);
        let (mul_f, add_f) = (93 * n - 69, 81 * n - 66);
        println!(
            "{}: n = {n}; inverse_dynamics {id}; Featherstone {mul_f} mul, {add_f} add; \
             M {}; c {}; g {}; q̈ {}",
            robot.name,
            d.graph.op_counts(&d.mass_matrix),
            d.graph.op_counts(&d.coriolis),
            d.graph.op_counts(&d.gravity),
            d.graph.op_counts(&d.forward_dynamics),
        );
        assert!(id.mul < mul_f, "{}: {} mul ≥ {mul_f}", robot.name, id.mul);
        assert!(
            id.add_sub < add_f,
            "{}: {} add ≥ {add_f}",
            robot.name,
            id.add_sub
        );
    }
}
