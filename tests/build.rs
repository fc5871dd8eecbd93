//! Generates the dynamics of every robot the comparison tests compile: the shipped robots,
//! the reference URDFs, and seeded random chains (f64 and f32), all through one build.rs.

use dynamics_gen::{Options, Scalar};
use dynamics_model::random::{random_chain, random_mimics, random_tree, ChainSpec};
use dynamics_model::{load, LoadOptions, Robot};
use std::fmt::Write as _;
use std::path::PathBuf;

include!("src/tree_spec.rs");

#[derive(Clone)]
struct Case {
    module: String,
    spec: String,
    robot: Robot,
    scalar: Scalar,
    no_std: bool,
    friction: Option<dynamics_gen::options::Friction>,
    /// Generated with run-time parameters (gravity, a payload on the end effector's link):
    /// registered twice, with their defaults and with [`PAYLOAD`].
    runtime: bool,
    /// Generated without run-time CPU dispatch (`cpu_dispatch: false`): see [`PORTABLE`].
    portable: bool,
}

/// A copy of the case `module` named `<prefix><module>`, for a second generation of it.
fn variant(cases: &[Case], module: &str, prefix: &str) -> Case {
    let case = cases
        .iter()
        .find(|c| c.module == module)
        .unwrap_or_else(|| panic!("no case {module}"));
    Case {
        module: format!("{prefix}{module}"),
        ..case.clone()
    }
}

/// The cases generated a second time without run-time CPU dispatch, as modules
/// `portable_<case>`: every other std case calls its AVX-512 or AVX2 copy on a CPU that has
/// either (such as this project's machines, and most x86-64 CPUs), so these keep the portable
/// code under every comparison test: a chain, the Panda, a floating tree with its derivative
/// functions (a `std` one: `no_std` code has no dispatch to leave out), and f32.
const PORTABLE: &[&str] = &[
    "shipped_ur5",
    "urdf_panda",
    "tree_207_f64",
    "random_104_f32",
];

/// The cases generated a second time in f32 (std, dispatched), as modules `f32_<case>`: the
/// arms and the quadruped the benchmark times, so that `cargo bench` sets f32 beside f64 on
/// the same robot (`bench_f32!` in benches/dynamics.rs); Solo-12's four alike legs are
/// computed in the lanes of `[f32; 4]` packs. Every comparison test runs on them as on the others;
/// they have no derivative functions ([`WITHOUT_DERIVATIVES`], for compile time: the f32
/// derivatives are compiled and tested on the random f32 chains and trees, `random_104_f32`
/// and others).
const F32: &[&str] = &["urdf_ur5", "urdf_panda", "urdf_rand7", "tree_solo12"];

/// The dispatched cases whose AVX-512 and AVX2 copies are run side by side
/// (`tests/dispatched_copies.rs`): each module gets `dispatched_copies_differ`, which may call
/// the copies directly, as only code in the module can.
const COPIES: &[&str] = &[
    "shipped_ur5",
    "urdf_panda",
    "tree_solo12",
    "tree_talos_upper_body",
    "random_104_f32",
    "f32_tree_solo12",
];

/// The batch cases whose AVX2 bodies of instructions (`dynamics-gen/src/emit/zmm.rs`) are
/// called directly (`tests/dispatched_copies.rs`), as a CPU with AVX-512 runs them through the
/// public functions only for some `B`: each module gets `batch_copies_differ`. The Panda's
/// forward dynamics (a body of 1,000–2,500 operations: AVX-512 and AVX2 bodies of
/// instructions beside the vectoriser's) and inverse dynamics (250–1,000 operations with a
/// vector result: an AVX2 body of instructions alone, `zmm::AVX2_MIN_OPS`) with `B` = 4 and
/// 8. Solo-12's forward dynamics, on lanes in those two copies alone, runs its AVX2
/// instructions through the public functions with `B` = 4 (`tests/generated_batch.rs`).
const BATCH_COPIES: &[(&str, &[&str], &[usize])] = &[(
    "urdf_panda",
    &["forward_dynamics", "inverse_dynamics"],
    &[4, 8],
)];

/// The cases generated with the `*_from_sin_cos` variants (`sin_cos_variants: true`), each
/// with `sin_cos_variants_differ` (`tests/sin_cos_variants.rs`): a chain with its derivative
/// functions, a floating tree, f32 `no_std`, and mimic joints (whose angles with a
/// multiplier or an offset the variants still compute from `q`).
const SIN_COS: &[&str] = &[
    "urdf_panda",
    "tree_solo12",
    "shipped_ur5_f32_no_std",
    "mimic_301_f64",
];

/// The cases generated a second time with run-time parameters, as modules `runtime_<case>`:
/// a chain, a floating tree with its derivative functions, f32 `no_std`, and the
/// Lagrangian route. Each is registered with the parameters' defaults (against the robot)
/// and with [`PAYLOAD`] (against the robot carrying it, `Spec::Payload`), so every
/// comparison test runs on both.
const RUNTIME: &[&str] = &[
    "shipped_ur5",
    "tree_208_f64",
    "shipped_pendulum_f32_no_std",
    "lagrangian_shipped_ur5",
];

/// The changed run-time parameters: gravity tilted and stronger than Earth's, and a
/// 1.7 kg payload off the link's axes with a full inertia about its centre of mass.
const PAYLOAD: [f64; 13] = [
    1.5, -2.0, -11.0, 1.7, 0.05, -0.08, 0.12, 0.012, 0.015, 0.009, 0.002, -0.001, 0.003,
];

/// The compiled cases without the derivative functions (the largest trees: their
/// derivatives are checked on the expression graph instead, tests/derivatives_pinocchio.rs,
/// and would make this crate slow to compile).
const WITHOUT_DERIVATIVES: &[&str] = &[
    "tree_g1_29dof",
    "tree_talos_upper_body",
    "tree_talos_upper_body_mimic",
    "tree_203_f32",
    "tree_205_f64",
    "mimic_302_f64",
    "mimic_304_f32",
    "lagrangian_shipped_rand7",
    "lagrangian_random_106_f32",
    "lagrangian_tree_208_f64",
    "lagrangian_actuated_401",
    "f32_urdf_ur5",
    "f32_urdf_panda",
    "f32_urdf_rand7",
    "f32_tree_solo12",
];

/// The cases whose batch functions (`*_batch`) the tests instantiate (`with_batch_cases!`):
/// a chain in f64 and f32 (std and no_std), a floating tree, mimic joints, armature and
/// friction, run-time parameters, the Lagrangian route, Solo-12 (floating), whose inverse
/// dynamics (1,310 operations) has AVX-512 and AVX2 bodies of instructions beside the
/// vectoriser's and whose forward dynamics (2,966) runs on lanes in the AVX-512 and AVX2
/// copies alone (per-state calls elsewhere), and the pendulum in f64, whose functions are too
/// small for the CPU dispatch (its vectorised batch bodies are out-of-line `extern "C"` parts,
/// which the `no_panic` test's machine-code check reads). Only these, the [`SAMPLE`] and
/// [`BATCH_COPIES`] are generated with the batch functions ([`with_batch`]); instantiating
/// them `B` wide for every robot made two test binaries take over ten CPU-minutes each, and
/// G1's (bodies up to 9,700 operations, five copies of each in a debug build, which does not
/// prune `if const` branches) took the CI run past its 90 minutes.
const BATCH: &[&str] = &[
    "shipped_ur5",
    "shipped_ur5_f32_no_std",
    "shipped_pendulum_f32_no_std",
    "shipped_pendulum",
    "urdf_panda",
    "random_104_f32",
    "tree_208_f64",
    "mimic_301_f64",
    "actuated_402",
    "runtime_shipped_ur5",
    "runtime_tree_208_f64",
    "lagrangian_shipped_ur5",
    "tree_solo12",
    "f32_tree_solo12",
];

/// The cases generated a second time by the Lagrangian route (`Method::Lagrangian`), as
/// modules `lagrangian_<case>`: chains, a floating tree, mimic joints, armature and friction,
/// f64 and f32, std and no_std. Every comparison test runs on them as on the others.
const LAGRANGIAN: &[&str] = &[
    "shipped_ur5",
    "shipped_pendulum_f32_no_std",
    "shipped_rand7",
    "random_104_f32",
    "random_106_f32",
    "tree_207_f64",
    "tree_208_f64",
    "mimic_301_f64",
    "actuated_401",
];

/// The cases compiled with the `sample-robots` feature, for the release `no_panic` test and
/// clippy in CI (the full set was about 290 MB of generated Rust, 210 MB since only the cases
/// that call them have the batch functions: its release build alone took 35 minutes of a
/// 2-core CI machine): every kind of robot and generator option
/// [`check_sample`] names, and every case a test, bench or example names.
const SAMPLE: &[&str] = &[
    "shipped_ur5",
    "shipped_pendulum",
    "shipped_ur5_f32_no_std",
    "urdf_ur5",
    "urdf_panda",
    "urdf_rand7",
    "urdf_double_pendulum",
    "random_104_f32",
    "tree_talos_upper_body",
    "tree_solo12",
    "tree_g1_29dof",
    "tree_208_f64",
    "mimic_301_f64",
    "actuated_401",
    "lagrangian_shipped_ur5",
    "runtime_shipped_ur5",
    "f32_urdf_ur5",
    "f32_urdf_panda",
    "f32_urdf_rand7",
    "f32_tree_solo12",
    "portable_shipped_ur5",
];

/// The random trees with armature and friction (in the dynamics) compiled as Rust: (seed,
/// bodies, floating base, Coulomb smoothing ε or exact).
pub const ACTUATED: &[(u64, usize, bool, Option<f64>)] =
    &[(401, 7, false, Some(0.05)), (402, 10, true, None)];

/// The random chains compiled as Rust: n = 1..12, every third joint prismatic on average.
pub const RANDOM: &[(u64, usize)] = &[
    (101, 1),
    (102, 2),
    (103, 3),
    (104, 4),
    (105, 5),
    (106, 6),
    (107, 7),
    (108, 8),
    (109, 9),
    (110, 10),
    (111, 11),
    (112, 12),
    (113, 3),
    (114, 6),
    (115, 7),
    (116, 12),
];

/// The URDF trees of `data/robots/trees` with Pinocchio's numbers: (name, floating base).
pub const URDF_TREES: &[(&str, bool)] = &[
    ("talos_upper_body", false),
    ("solo12", true),
    ("g1_29dof", true),
];

/// The random trees compiled as Rust: (seed, bodies, floating base).
pub const TREES: &[(u64, usize, bool)] = &[
    (201, 4, false),
    (202, 9, true),
    (203, 14, false),
    (204, 6, true),
    (205, 18, true),
    (206, 11, false),
    (207, 3, true),
    (208, 8, true),
];

/// The random trees with mimic joints compiled as Rust: (seed, bodies, floating base); about
/// 40 % of the joints follow another ([`random_mimics`]).
pub const MIMIC_TREES: &[(u64, usize, bool)] = &[
    (301, 5, false),
    (302, 12, true),
    (303, 9, false),
    (304, 16, true),
];

/// The URDF trees with mimic joints of `data/robots/trees`, with Pinocchio's numbers.
pub const URDF_MIMIC: &[&str] = &["talos_upper_body_mimic"];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    let data = manifest.join("data/robots");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=data/robots");
    let mut cases = Vec::new();
    for name in ["ur5", "mr_ur5", "pendulum", "rand7"] {
        let robot = load(name, &LoadOptions::default()).expect("shipped robot loads");
        cases.push(Case {
            module: format!("shipped_{name}"),
            spec: format!("Spec::Shipped({name:?})"),
            robot,
            scalar: Scalar::F64,
            no_std: false,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for (name, tip) in [
        ("ur5", "tool0"),
        ("panda", "panda_hand_tcp"),
        ("double_pendulum", "link2"),
        ("rand7", "ee_link"),
        ("mr_ur5", "ee_link"),
    ] {
        let path = data.join(format!("{name}.urdf"));
        let options = LoadOptions {
            tip: Some(tip.to_string()),
            ..Default::default()
        };
        let robot = dynamics_model::load_file(&path, &options)
            .or_else(|_| dynamics_model::load_file(&path, &LoadOptions::default()))
            .expect("reference URDF loads");
        cases.push(Case {
            module: format!("urdf_{name}"),
            spec: format!("Spec::Urdf({name:?}, {:?})", robot.end_effector.name),
            robot,
            scalar: Scalar::F64,
            no_std: false,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for (k, &(seed, dof)) in RANDOM.iter().enumerate() {
        let spec = ChainSpec {
            dof,
            prismatic: 0.3,
        };
        let robot = random_chain(seed, spec);
        let scalar = if k % 2 == 0 { Scalar::F64 } else { Scalar::F32 };
        cases.push(Case {
            module: format!("random_{seed}_{}", scalar.as_str()),
            spec: format!("Spec::Random({seed}, {dof})"),
            robot,
            scalar,
            no_std: k % 4 == 1,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for (name, floating) in URDF_TREES {
        let path = data.join(format!("trees/{name}.urdf"));
        let options = LoadOptions {
            floating_base: *floating,
            ..Default::default()
        };
        let robot = dynamics_model::load_file(&path, &options).expect("tree URDF loads");
        cases.push(Case {
            module: format!("tree_{name}"),
            spec: format!("Spec::UrdfTree({name:?}, {floating})"),
            robot,
            scalar: Scalar::F64,
            no_std: false,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for (k, &(seed, dof, floating)) in TREES.iter().enumerate() {
        let robot = with_leaf_frames(random_tree(seed, tree_spec(dof, floating)));
        let scalar = if k % 3 == 2 { Scalar::F32 } else { Scalar::F64 };
        cases.push(Case {
            module: format!("tree_{seed}_{}", scalar.as_str()),
            spec: format!("Spec::Tree({seed}, {dof}, {floating})"),
            robot,
            scalar,
            no_std: k % 4 == 3,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for (k, &(seed, dof, floating)) in MIMIC_TREES.iter().enumerate() {
        let robot = with_leaf_frames(random_mimics(
            random_tree(seed, tree_spec(dof, floating)),
            seed,
            0.4,
        ));
        assert!(robot.has_mimic(), "tree {seed} has mimic joints");
        let scalar = if k == 3 { Scalar::F32 } else { Scalar::F64 };
        cases.push(Case {
            module: format!("mimic_{seed}_{}", scalar.as_str()),
            spec: format!("Spec::TreeMimic({seed}, {dof}, {floating})"),
            robot,
            scalar,
            no_std: k == 2,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for name in URDF_MIMIC {
        let path = data.join(format!("trees/{name}.urdf"));
        let robot =
            dynamics_model::load_file(&path, &LoadOptions::default()).expect("mimic URDF loads");
        cases.push(Case {
            module: format!("tree_{name}"),
            spec: format!("Spec::UrdfMimic({name:?})"),
            robot,
            scalar: Scalar::F64,
            no_std: false,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    for &(seed, dof, floating, eps) in ACTUATED {
        let robot = actuated(random_tree(seed, tree_spec(dof, floating)), seed);
        cases.push(Case {
            module: format!("actuated_{seed}"),
            spec: format!("Spec::Actuated({seed}, {dof}, {floating}, {eps:?})"),
            robot,
            scalar: Scalar::F64,
            no_std: false,
            friction: Some(match eps {
                None => dynamics_gen::options::Friction::Coulomb,
                Some(e) => dynamics_gen::options::Friction::Smooth(e),
            }),
            runtime: false,
            portable: false,
        });
    }
    {
        let path = data.join("panda.urdf");
        let options = LoadOptions {
            tip: Some("panda_hand".into()),
            ..Default::default()
        };
        let robot = dynamics_model::load_file(&path, &options).expect("panda loads");
        cases.push(Case {
            module: "urdf_panda_armature".into(),
            spec: "Spec::PandaArmature".into(),
            robot: panda_armature(robot),
            scalar: Scalar::F64,
            no_std: false,
            friction: None,
            runtime: false,
            portable: false,
        });
    }
    // The same robots in f32 and no_std as well.
    for name in ["ur5", "pendulum"] {
        let robot = load(name, &LoadOptions::default()).expect("shipped robot loads");
        cases.push(Case {
            module: format!("shipped_{name}_f32_no_std"),
            spec: format!("Spec::Shipped({name:?})"),
            robot,
            scalar: Scalar::F32,
            no_std: true,
            friction: None,
            runtime: false,
            portable: false,
        });
    }

    // The second generations of cases, in this order (RUNTIME names a Lagrangian case).
    for module in LAGRANGIAN {
        let case = variant(&cases, module, "lagrangian_");
        cases.push(case);
    }
    for module in RUNTIME {
        let case = Case {
            runtime: true,
            ..variant(&cases, module, "runtime_")
        };
        cases.push(case);
    }
    for module in F32 {
        let case = Case {
            scalar: Scalar::F32,
            ..variant(&cases, module, "f32_")
        };
        cases.push(case);
    }
    for module in PORTABLE {
        let case = Case {
            portable: true,
            ..variant(&cases, module, "portable_")
        };
        cases.push(case);
    }
    for module in BATCH {
        assert!(
            cases.iter().any(|c| c.module == *module),
            "BATCH names {module}, which is no case"
        );
    }
    for m in WITHOUT_DERIVATIVES.iter().chain(SAMPLE) {
        assert!(cases.iter().any(|c| c.module == *m), "no case {m}");
    }
    if std::env::var_os("CARGO_FEATURE_SAMPLE_ROBOTS").is_some() {
        cases.retain(|c| SAMPLE.contains(&c.module.as_str()));
        check_sample(&cases);
    }
    let mut registry = String::new();
    let mut list = String::new();
    let mut std_list = String::new();
    let mut frame_list = String::new();
    let mut modules = String::new();
    let mut derivative_registry = String::new();
    let mut derivative_list = String::new();
    let (mut batch_list, mut batch_std_list) = (String::new(), String::new());
    let mut regressor_registry = String::new();
    write_cases(&cases, &out);
    for case in &cases {
        let derivatives = !WITHOUT_DERIVATIVES.contains(&case.module.as_str());
        let file = format!("{}.rs", case.module);
        let (nq, nv) = (case.robot.nq(), case.robot.nv());
        let s = case.scalar.as_str();
        let frames = if case.robot.frames.is_empty() {
            ""
        } else {
            ", frames"
        };
        let mut copies = if COPIES.contains(&case.module.as_str()) {
            let code = std::fs::read_to_string(out.join(&file)).expect("written above");
            copies_helper(nq, nv, s, returns_written(&code, "mass_matrix_avx512"))
        } else {
            String::new()
        };
        if SIN_COS.contains(&case.module.as_str()) {
            copies += &sin_cos_helper(nq, nv, s);
        }
        if let Some((_, functions, widths)) =
            BATCH_COPIES.iter().find(|(m, _, _)| *m == case.module)
        {
            copies += &batch_copies_helper(nq, nv, s, functions, widths);
        }
        if BATCH.contains(&case.module.as_str()) {
            copies += &batch_instances(s);
        }
        writeln!(
            modules,
            "pub mod {m} {{ include!(concat!(env!(\"OUT_DIR\"), \"/{file}\")); {copies}}}\nadapter!({m}, {nq}, {nv}, {s}{frames});",
            m = case.module
        )
        .ok();
        // The values each case is registered with: the struct's default (the robot itself),
        // and for run-time parameters the changed ones as well.
        let m = &case.module;
        let mut instances = vec![(m.clone(), format!("{m}::Robot::DEFAULT"), case.spec.clone())];
        if case.runtime {
            let p: Vec<String> = PAYLOAD.iter().map(|x| format!("{x:?}")).collect();
            instances.push((
                format!("{m}+payload"),
                format!(
                    "{m}::Robot {{ gravity: [{}], payload_mass: {}, payload_com: [{}], payload_inertia: [{}] }}",
                    p[..3].join(", "),
                    p[3],
                    p[4..7].join(", "),
                    p[7..].join(", ")
                ),
                format!("Spec::Payload(&{}, {PAYLOAD:?})", case.spec),
            ));
        }
        if derivatives {
            writeln!(
                modules,
                "derivatives_adapter!({m}, {nq}, {nv}, {s});\nregressor_adapter!({m}, {nq}, {nv}, {s});",
                m = case.module
            )
            .ok();
            for (name, imp, _) in &instances {
                writeln!(regressor_registry, "    ({name:?}, &{imp}),").ok();
            }
            if !case.no_std {
                writeln!(
                    derivative_list,
                    "        $mac!({}, {nq}, {nv}, {s});",
                    case.module
                )
                .ok();
            }
            for (name, imp, _) in &instances {
                writeln!(derivative_registry, "    ({name:?}, &{imp}),").ok();
            }
        }
        writeln!(list, "        $mac!({}, {nq}, {nv}, {s});", case.module).ok();
        if BATCH.contains(&case.module.as_str()) {
            writeln!(
                batch_list,
                "        $mac!({}, {nq}, {nv}, {s});",
                case.module
            )
            .ok();
            if !case.no_std {
                writeln!(
                    batch_std_list,
                    "        $mac!({}, {nq}, {nv}, {s});",
                    case.module
                )
                .ok();
            }
        }
        if !case.no_std {
            writeln!(std_list, "        $mac!({}, {nq}, {nv}, {s});", case.module).ok();
        }
        if !case.robot.frames.is_empty() && !case.no_std {
            writeln!(
                frame_list,
                "        $mac!({}, {nq}, {nv}, {s});",
                case.module
            )
            .ok();
        }
        for (name, imp, spec) in &instances {
            writeln!(
                registry,
                "    Case {{ module: {name:?}, spec: {spec}, scalar: {s:?}, imp: &{imp} }},"
            )
            .ok();
        }
    }
    let all = format!(
        "{modules}\n/// Every compiled case.\npub const CASES: &[Case] = &[\n{registry}];\n/// The cases generated with the derivative functions: (module, functions).\npub const DERIVATIVE_CASES: &[(&str, &dyn super::GeneratedDerivatives)] = &[\n{derivative_registry}];\n/// The cases generated with the regressor functions: (module, functions).\npub const REGRESSOR_CASES: &[(&str, &dyn super::GeneratedRegressor)] = &[\n{regressor_registry}];\n"
    );
    std::fs::write(out.join("cases.rs"), all).expect("OUT_DIR is writable");
    let macro_list = format!(
        "/// Calls `$mac!(module, nq, nv, scalar)` for every generated robot.\n#[macro_export]\nmacro_rules! with_cases {{\n    ($mac:ident) => {{\n{list}    }};\n}}\n/// Calls `$mac!(module, nq, nv, scalar)` for every generated robot with std trigonometry.\n#[macro_export]\nmacro_rules! with_std_cases {{\n    ($mac:ident) => {{\n{std_list}    }};\n}}\n/// Calls `$mac!(module, nq, nv, scalar)` for every generated robot with named frames and std trigonometry.\n#[macro_export]\nmacro_rules! with_frame_cases {{\n    ($mac:ident) => {{\n{frame_list}    }};\n}}\n/// Calls `$mac!(module, nq, nv, scalar)` for every generated robot with the derivative functions and std trigonometry.\n#[macro_export]\nmacro_rules! with_derivative_cases {{\n    ($mac:ident) => {{\n{derivative_list}    }};\n}}\n/// Calls `$mac!(module, nq, nv, scalar)` for the robots whose batch functions are tested.\n#[macro_export]\nmacro_rules! with_batch_cases {{\n    ($mac:ident) => {{\n{batch_list}    }};\n}}\n/// [`with_batch_cases`] with std trigonometry.\n#[macro_export]\nmacro_rules! with_batch_std_cases {{\n    ($mac:ident) => {{\n{batch_std_list}    }};\n}}\n"
    );
    std::fs::write(out.join("with_cases.rs"), macro_list).expect("OUT_DIR is writable");

    // The `joint_sin_cos` helper as the generated files carry it, for each scalar and
    // `std`/`no_std`, behind a public wrapper (tests/trig.rs).
    let mut kernels = String::new();
    for (name, scalar, no_std) in [
        ("F64Std", Scalar::F64, false),
        ("F64NoStd", Scalar::F64, true),
        ("F32Std", Scalar::F32, false),
        ("F32NoStd", Scalar::F32, true),
    ] {
        let t = scalar.as_str();
        let helper = dynamics_gen::emit::trig::sin_cos_helper(scalar, no_std);
        writeln!(
            kernels,
            "/// The generated `joint_sin_cos` ({t}, no_std {no_std}).\n\
             pub struct {name};\n\
             impl {name} {{\n{helper}\n\
             /// Calls the helper, unpadded.\n\
             pub fn sin_cos<const K: usize>(x: [{t}; K]) -> ([{t}; K], [{t}; K]) {{ Self::joint_sin_cos::<K, K>(x) }}\n\
             /// Calls the helper with its multiply-adds fused, as the AVX-512 copy of a dispatched function does.\n\
             pub fn sin_cos_fused<const K: usize>(x: [{t}; K]) -> ([{t}; K], [{t}; K]) {{ Self::sin_cos_n::<K, K, true>(x, K) }}\n\
             /// Calls the helper, padded to `P` as the generated functions call it.\n\
             pub fn sin_cos_padded<const K: usize, const P: usize>(x: [{t}; K]) -> ([{t}; P], [{t}; P]) {{ Self::joint_sin_cos::<K, P>(x) }}\n\
             /// The padded length of `k` angles for the compilation target.\n\
             pub const fn lanes(k: usize) -> usize {{ Self::sin_cos_lanes(k) }}\n}}"
        )
        .expect("writing to a String");
    }
    std::fs::write(out.join("trig_kernels.rs"), kernels).expect("OUT_DIR is writable");
}

/// The generator's options for `case`.
fn options(case: &Case) -> Options {
    let derivatives = !WITHOUT_DERIVATIVES.contains(&case.module.as_str());
    let batch = with_batch(&case.module);
    let functions = (!derivatives || !batch).then(|| {
        dynamics_gen::options::FUNCTIONS
            .iter()
            .filter(|f| derivatives || (!f.contains("derivative") && **f != "mass_matrix_inverse"))
            .filter(|f| derivatives || (!f.contains("regressor") && !f.contains("parameters")))
            .filter(|f| batch || !f.ends_with("_batch"))
            .filter(|f| !f.starts_with("frame_") || !case.robot.frames.is_empty())
            .map(|f| f.to_string())
            .collect()
    });
    Options {
        name: Some("Robot".into()),
        scalar: case.scalar,
        no_std: case.no_std,
        friction: case.friction,
        functions,
        runtime_parameters: case.runtime,
        cpu_dispatch: !case.portable,
        sin_cos_variants: SIN_COS.contains(&case.module.as_str()),
        method: if case.module.contains("lagrangian_") {
            dynamics_gen::Method::Lagrangian
        } else {
            dynamics_gen::Method::NewtonEuler
        },
        ..Default::default()
    }
}

/// Generates every case into `out/<module>.rs`, on as many threads as the machine has cores
/// (at most 4), the largest robots first. On one thread the 66 cases took about 4 minutes of
/// a CI run, on its critical path: the test library waits for them.
fn write_cases(cases: &[Case], out: &std::path::Path) {
    let mut order: Vec<usize> = (0..cases.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(cases[k].robot.nv()));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get().min(4));
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&c) = order.get(k) else { break };
                let case = &cases[c];
                let code = dynamics_gen::generate_file(&case.robot, &options(case), &case.spec)
                    .unwrap_or_else(|e| panic!("{}: {e}", case.module));
                std::fs::write(out.join(format!("{}.rs", case.module)), code)
                    .expect("OUT_DIR is writable");
            });
        }
    });
}

/// Whether the case `module` is generated with the batch functions (`*_batch`): the cases
/// whose batch functions the tests call ([`BATCH`], [`BATCH_COPIES`]) and the [`SAMPLE`],
/// which holds the benches' robots and which the release `no_panic` test and clippy check.
/// The others leave them out: never called, their bodies (AVX-512 and AVX2 bodies of
/// instructions beside the vectoriser's) were 69 of the 300 MB of generated Rust this crate
/// compiles.
fn with_batch(module: &str) -> bool {
    BATCH.contains(&module)
        || SAMPLE.contains(&module)
        || BATCH_COPIES.iter().any(|(m, _, _)| *m == module)
}

/// Panics unless the [`SAMPLE`] of cases holds every kind of robot and every generator option
/// its doc comment names, so that it stays true when a list here changes.
fn check_sample(sample: &[Case]) {
    fn listed(list: &[&str], c: &Case) -> bool {
        list.contains(&c.module.as_str())
    }
    type Kind = (&'static str, fn(&Case) -> bool);
    let kinds: [Kind; 17] = [
        ("a serial chain", |c| c.robot.is_serial()),
        ("a tree", |c| !c.robot.is_serial() && !c.robot.base.floating),
        ("a floating base", |c| c.robot.base.floating),
        ("a floating base with derivative functions", |c| {
            c.robot.base.floating && !listed(WITHOUT_DERIVATIVES, c)
        }),
        ("mimic joints", |c| c.robot.has_mimic()),
        ("armature", |c| {
            c.robot.joints.iter().any(|j| j.armature() > 0.0)
        }),
        ("friction", |c| c.friction.is_some()),
        ("the Lagrangian route", |c| {
            c.module.starts_with("lagrangian_")
        }),
        ("run-time parameters", |c| c.runtime),
        ("f32 with std", |c| c.scalar == Scalar::F32 && !c.no_std),
        ("no_std", |c| c.no_std),
        ("code without CPU dispatch", |c| c.portable),
        ("named frames", |c| !c.robot.frames.is_empty()),
        ("the *_from_sin_cos variants", |c| listed(SIN_COS, c)),
        ("batch functions", |c| listed(BATCH, c)),
        ("dispatched copies compared", |c| listed(COPIES, c)),
        ("batch copies compared", |c| {
            BATCH_COPIES.iter().any(|(m, _, _)| *m == c.module)
        }),
    ];
    for (kind, has) in kinds {
        assert!(
            sample.iter().any(has),
            "SAMPLE in tests/build.rs has no case with {kind}: add one"
        );
    }
}

/// The source of `sin_cos_variants_differ` for a [`SIN_COS`] module: the inverse dynamics,
/// mass matrix, coriolis, gravity, forward dynamics (with `a` as τ) and kinetic energy at one
/// state, and their `*_from_sin_cos` variants with `sin_cos(q)`, as (entries compared, entries
/// whose bits differ, the largest difference relative to the largest entry of its function).
fn sin_cos_helper(nq: usize, nv: usize, s: &str) -> String {
    format!(
        r#"
/// Each function against its `*_from_sin_cos` variant fed `sin_cos(q)`, at one state.
pub fn sin_cos_variants_differ(q: &[f64], v: &[f64], a: &[f64]) -> (usize, usize, f64) {{
    let r = Robot::DEFAULT;
    let (q, v, a) = (crate::to_s::<{s}, {nq}>(q), crate::to_s::<{s}, {nv}>(v), crate::to_s::<{s}, {nv}>(a));
    let (sq, cq) = r.sin_cos(&q);
    let mut n = (0, 0, 0.0f64);
    let mut cmp = |x: &[{s}], y: &[{s}]| {{
        let scale = x.iter().fold(0.0, |m: f64, x| m.max(crate::Real::to_f64(x.abs())));
        for (x, y) in x.iter().zip(y) {{
            n.0 += 1;
            if x.to_bits() != y.to_bits() {{
                n.1 += 1;
                n.2 = n.2.max(crate::Real::to_f64((x - y).abs()) / scale.max(f64::MIN_POSITIVE));
            }}
        }}
    }};
    cmp(r.inverse_dynamics(&q, &v, &a).as_slice(), r.inverse_dynamics_from_sin_cos(&q, &sq, &cq, &v, &a).as_slice());
    cmp(r.mass_matrix(&q).as_slice(), r.mass_matrix_from_sin_cos(&q, &sq, &cq).as_slice());
    cmp(r.coriolis(&q, &v).as_slice(), r.coriolis_from_sin_cos(&q, &sq, &cq, &v).as_slice());
    cmp(r.gravity(&q).as_slice(), r.gravity_from_sin_cos(&q, &sq, &cq).as_slice());
    cmp(r.forward_dynamics(&q, &v, &a).as_slice(), r.forward_dynamics_from_sin_cos(&q, &sq, &cq, &v, &a).as_slice());
    cmp(&[r.kinetic_energy(&q, &v)], &[r.kinetic_energy_from_sin_cos(&q, &sq, &cq, &v)]);
    let (mut lower, mut given) = (::nalgebra::SMatrix::<{s}, {nv}, {nv}>::zeros(), ::nalgebra::SMatrix::<{s}, {nv}, {nv}>::zeros());
    r.mass_matrix_lower_into(&q, &mut lower);
    r.mass_matrix_lower_into_from_sin_cos(&q, &sq, &cq, &mut given);
    cmp(lower.as_slice(), given.as_slice());
    n
}}
/// `(nq, nv)` of this robot, for `sin_cos_variants_differ`'s arguments.
pub const SIN_COS_DIMS: (usize, usize) = ({nq}, {nv});
"#
    )
}

/// The closure `cmp(x, y)` of the generated comparisons: it counts into `n` the entries of
/// two `s` slices compared and those whose bits differ.
fn tally(s: &str) -> String {
    format!(
        "let mut cmp = |x: &[{s}], y: &[{s}]| {{
        for (x, y) in x.iter().zip(y) {{
            n.0 += 1;
            if x.to_bits() != y.to_bits() {{
                n.1 += 1;
            }}
        }}
    }};"
    )
}

/// The source of `batch_copies_differ` for a [`BATCH_COPIES`] module: each of `functions`'
/// batch AVX2 copy with `B` of `widths` at states around one, against its single-state AVX2
/// copy per state, as (entries compared, entries whose bits differ); `None` unless the CPU
/// has AVX2 and FMA, or where the binary has no AVX2 copy.
fn batch_copies_helper(
    nq: usize,
    nv: usize,
    s: &str,
    functions: &[&str],
    widths: &[usize],
) -> String {
    let mut calls = String::new();
    for f in functions {
        for b in widths {
            calls += &format!(
                r#"
    {{
        let lanes = |x: &[f64], n| -> Vec<f64> {{ x.iter().map(|x| x + 0.1 * n as f64).collect() }};
        let q: [nalgebra::SVector<{s}, {nq}>; {b}] = core::array::from_fn(|l| crate::to_s(&lanes(q, l)));
        let v: [nalgebra::SVector<{s}, {nv}>; {b}] = core::array::from_fn(|l| crate::to_s(&lanes(v, l)));
        let a: [nalgebra::SVector<{s}, {nv}>; {b}] = core::array::from_fn(|l| crate::to_s(&lanes(a, l)));
        // SAFETY: the CPU has AVX2 and FMA (checked above).
        let batch = unsafe {{ r.{f}_batch_avx2::<{b}>(&q, &v, &a) }};
        for l in 0..{b} {{
            // SAFETY: as above.
            cmp(batch[l].as_slice(), unsafe {{ r.{f}_avx2(&q[l], &v[l], &a[l]) }}.as_slice());
        }}
    }}"#
            );
        }
    }
    format!(
        r#"
/// Where this binary has the AVX2 copies: their batch bodies of instructions against their
/// single-state code, state by state.
#[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f"), not(all(target_feature = "avx2", target_feature = "fma"))))]
#[allow(unsafe_code)]
pub fn batch_copies_differ(q: &[f64], v: &[f64], a: &[f64]) -> Option<(usize, usize)> {{
    if !Robot::has_avx2() {{
        return None;
    }}
    let r = Robot::DEFAULT;
    let mut n = (0, 0);
    {tally}{calls}
    Some(n)
}}
/// `(nq, nv)` of this robot, for `batch_copies_differ`'s arguments.
pub const BATCH_COPIES_DIMS: (usize, usize) = ({nq}, {nv});
"#,
        tally = tally(s)
    )
}

/// The source of `batch_instances` for a [`BATCH`] module: the batch functions at the widths
/// the tests call them with (4 states, and a whole AVX-512 register), instantiated in this
/// library. The test profile (opt-level 0 for this crate, 1 before) shares generic instances
/// with the crates downstream, so the test binaries (`generated_batch`, `no_alloc`) compile
/// the small dispatching wrappers and call these bodies and copies, instead of compiling them
/// again each (they took about 20 CPU-minutes each).
fn batch_instances(s: &str) -> String {
    format!(
        r#"
/// Instantiates the batch functions at the widths the tests use (see tests/build.rs).
#[doc(hidden)]
pub fn batch_instances() {{
    fn keep<const B: usize>() {{
        use std::hint::black_box;
        black_box::<fn(&Robot, &[_; B], &[_; B], &[_; B]) -> [_; B]>(Robot::inverse_dynamics_batch::<B>);
        black_box::<fn(&Robot, &[_; B], &[_; B], &[_; B]) -> [_; B]>(Robot::forward_dynamics_batch::<B>);
        black_box::<fn(&Robot, &[_; B]) -> [_; B]>(Robot::mass_matrix_batch::<B>);
        black_box::<fn(&Robot, &[_; B]) -> [_; B]>(Robot::gravity_batch::<B>);
    }}
    keep::<4>();
    keep::<{{ 64 / ::core::mem::size_of::<{s}>() }}>();
}}
"#
    )
}

/// Whether the copy `copy` in the generated `code` returns its result in the struct's
/// `Written` union (a stored result of a tree: `dynamics-gen/src/emit/function.rs`,
/// `written_union_item`), whose `value` its caller reads.
fn returns_written(code: &str, copy: &str) -> bool {
    code.find(&format!("fn {copy}("))
        .and_then(|at| {
            let signature = &code[at..];
            signature
                .find('{')
                .map(|end| signature[..end].contains("Written<"))
        })
        .unwrap_or(false)
}

/// The source of `dispatched_copies_differ` for a [`COPIES`] module: the inverse dynamics,
/// mass matrix, forward dynamics (with `a` as τ), gravity and the mass matrix in place
/// (`mass_matrix_lower_into`) of its AVX-512 and its AVX2 copy
/// at one state, as (entries compared, entries whose bits differ); `None` unless the CPU has
/// both instruction sets, or where the binary has no AVX2 copy. `written`: the mass matrix's
/// copies return the struct's `Written` union ([`returns_written`]).
fn copies_helper(nq: usize, nv: usize, s: &str, written: bool) -> String {
    let value = if written { ".value" } else { "" };
    format!(
        r#"
/// Where this binary has both copies: the AVX-512 and the AVX2 copy at one state.
#[cfg(all(target_arch = "x86_64", not(target_feature = "avx512f"), not(all(target_feature = "avx2", target_feature = "fma"))))]
#[allow(unsafe_code)]
pub fn dispatched_copies_differ(q: &[f64], v: &[f64], a: &[f64]) -> Option<(usize, usize)> {{
    if !(Robot::has_avx512() && Robot::has_avx2()) {{
        return None;
    }}
    let r = Robot::DEFAULT;
    let (q, v, a) = (crate::to_s::<{s}, {nq}>(q), crate::to_s::<{s}, {nv}>(v), crate::to_s::<{s}, {nv}>(a));
    let mut n = (0, 0);
    {tally}
    // SAFETY: the CPU has the features both copies are compiled for (checked above).
    unsafe {{
        cmp(r.inverse_dynamics_avx512(&q, &v, &a).as_slice(), r.inverse_dynamics_avx2(&q, &v, &a).as_slice());
        cmp(r.mass_matrix_avx512(&q){value}.as_slice(), r.mass_matrix_avx2(&q){value}.as_slice());
        cmp(r.forward_dynamics_avx512(&q, &v, &a).as_slice(), r.forward_dynamics_avx2(&q, &v, &a).as_slice());
        cmp(r.gravity_avx512(&q).as_slice(), r.gravity_avx2(&q).as_slice());
        let (mut wide, mut mid) = (::nalgebra::SMatrix::<{s}, {nv}, {nv}>::zeros(), ::nalgebra::SMatrix::<{s}, {nv}, {nv}>::zeros());
        r.mass_matrix_lower_into_avx512(&q, &mut wide);
        r.mass_matrix_lower_into_avx2(&q, &mut mid);
        cmp(wide.as_slice(), mid.as_slice());
    }}
    Some(n)
}}
/// `(nq, nv)` of this robot, for `dispatched_copies_differ`'s arguments.
pub const COPIES_DIMS: (usize, usize) = ({nq}, {nv});
"#,
        tally = tally(s)
    )
}
