//! The inline grammar against the TOML files of the same robots: one core, identical impls.

use super::*;
use dynamics_model::{load_file, LoadOptions, Robot};
use std::path::Path;

fn robots_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots")
}

fn inline_robot(tokens: TokenStream) -> Robot {
    match inline::parse(tokens).map(|p| p.robot) {
        Ok(Ok((r, _))) => r,
        Ok(Err(e)) | Err(e) => panic!("{e}"),
    }
}

fn inline_errors(tokens: TokenStream) -> Vec<String> {
    match inline::parse(tokens).map(|p| p.robot) {
        Ok(Ok(_)) => panic!("expected errors"),
        Ok(Err(e)) | Err(e) => e.into_iter().map(|e| e.to_string()).collect(),
    }
}

fn same_impl(inline: &Robot, file: &str, name: &str) {
    let from_file = load_file(&robots_dir().join(file), &LoadOptions::default()).unwrap();
    let options = Options {
        name: Some(name.into()),
        ..Options::default()
    };
    let a = crate::generate_impl(inline, &options)
        .unwrap()
        .impl_block
        .to_string();
    let b = crate::generate_impl(&from_file, &options)
        .unwrap()
        .impl_block
        .to_string();
    assert!(a == b, "impl blocks differ for {file}");
    // Not vacuous: the robots' numbers are the file's.
    assert_eq!(inline.m_list(), from_file.m_list());
    assert_eq!(inline.g_list(), from_file.g_list());
    assert_eq!(inline.s_list(), from_file.s_list());
    assert_eq!(inline.joint_names(), from_file.joint_names());
}

#[test]
fn pendulum_inline_equals_pendulum_toml() {
    let robot = inline_robot(quote! {
        pub struct Pendulum;
        name: "pendulum",
        gravity: [0.0, 0.0, -10.0],
        joint revolute joint1 {
            screw: [0, 0, 1, 0, 0, 0],
            link arm { home: { xyz: [1, 0, 0] }, mass: 2.0, inertia: [4, 4, 4, 0, 0, 0] },
        },
        joint revolute joint2 {
            screw: [1, 0, 0, 0, 0, 0],
            link pendulum { home: { xyz: [0, 0, -1] }, mass: 2.0, inertia: [4, 4, 0, 0, 0, 0] },
        },
        end_effector bob { home: { xyz: [0, 0, 0] } },
    });
    same_impl(&robot, "pendulum.toml", "Pendulum");
}

/// Named parameters: `parameters: { … }` and string expressions where numbers go, as in the
/// TOML file of the same robot, with the same parameters kept for `equations --symbolic`.
#[test]
fn planar2r_inline_parameters_equal_planar2r_toml() {
    let robot = inline_robot(quote! {
        pub struct Planar2r;
        name: "planar2r",
        gravity: [0, "-g", 0],
        parameters: { m1: 2.0, m2: 1.5, L1: 1.0, L2: 0.8, g: 9.81 },
        joint revolute joint1 {
            axis: [0, 0, 1],
            point: [0, 0, 0],
            link link1 { home: { xyz: ["L1", 0, 0] }, mass: "m1", inertia: [0, 0, 0, 0, 0, 0] },
        },
        joint revolute joint2 {
            axis: [0, 0, 1],
            point: ["L1", 0, 0],
            link link2 { home: { xyz: ["L2", 0, 0] }, mass: "m2", inertia: [0, 0, 0, 0, 0, 0] },
        },
        end_effector tip {},
    });
    same_impl(&robot, "planar2r.toml", "Planar2r");
    let file = load_file(&robots_dir().join("planar2r.toml"), &LoadOptions::default()).unwrap();
    // The same parameters and values (robot! lists them in alphabetical order), and the
    // same fields kept for `equations --symbolic`.
    let pairs = |p: &dynamics_model::parameters::Parameters| {
        let mut v: Vec<(String, f64)> = p.names.iter().cloned().zip(p.values.clone()).collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    };
    assert_eq!(pairs(&robot.parameters), pairs(&file.parameters));
    let kept = |p: &dynamics_model::parameters::Parameters| {
        (
            p.gravity.is_some(),
            p.screws.len(),
            p.homes.len(),
            p.inertias.len(),
            p.elsewhere.len(),
        )
    };
    assert_eq!(kept(&robot.parameters), (true, 1, 2, 2, 0));
    assert_eq!(kept(&robot.parameters), kept(&file.parameters));
    let errors = inline_errors(quote! {
        pub struct Bad;
        parameters: { m1: 2.0 },
        joint revolute j { axis: [0, 0, 1], point: [0, 0, 0], link l { home: { xyz: [0, 0, 0] }, mass: "m2", inertia: [1, 1, 1, 0, 0, 0] } },
    });
    assert!(
        errors
            .iter()
            .any(|e| e.contains("`m2` is not a declared parameter (declared: m1; or add `m2: VALUE` to `parameters: { … }`)")),
        "{errors:?}"
    );
    // Without `parameters:` at all, the advice is in the macro's spelling too.
    let errors = inline_errors(quote! {
        pub struct Bad;
        joint revolute j { axis: [0, 0, 1], point: [0, 0, 0], link l { home: { xyz: [0, 0, 0] }, mass: "m2", inertia: [1, 1, 1, 0, 0, 0] } },
    });
    assert!(
        errors
            .iter()
            .any(|e| e.contains("add `parameters: { m2: VALUE }`") && !e.contains("[parameters]")),
        "{errors:?}"
    );
}

/// The UR5 of mr_ur5.toml, with every home as a 4×4 matrix and the screw axes as `screw`
/// (v = −ω × q computed by hand from the file's axis and point).
#[test]
fn ur5_inline_equals_mr_ur5_toml() {
    let robot = inline_robot(quote! {
        pub struct MrUr5;
        gravity: [0, 0, -9.81],
        joint revolute shoulder_pan_joint {
            screw: [0, 0, 1, 0, 0, 0],
            link shoulder_link {
                home: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.089159], [0, 0, 0, 1]],
                mass: 3.7, inertia: [0.010267495893, 0.010267495893, 0.00666, 0, 0, 0],
            },
        },
        joint revolute shoulder_lift_joint {
            screw: [0, 1, 0, -0.089159, 0, 0],
            link upper_arm_link {
                home: [[0, 0, 1, 0.28], [0, 1, 0, 0.13585], [-1, 0, 0, 0], [0, 0, 0, 1]],
                mass: 8.393, inertia: [0.22689067591, 0.22689067591, 0.0151074, 0, 0, 0],
            },
        },
        joint revolute elbow_joint {
            screw: [0, 1, 0, -0.089159, 0, 0.425],
            link forearm_link {
                home: [[1, 0, 0, 0], [0, 1, 0, -0.1197], [0, 0, 1, 0.395], [0, 0, 0, 1]],
                mass: 2.275, inertia: [0.049443313556, 0.049443313556, 0.004095, 0, 0, 0],
            },
        },
        joint revolute wrist_1_joint {
            screw: [0, 1, 0, -0.089159, 0, 0.81725],
            link wrist_1_link {
                home: [[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 0.14225], [0, 0, 0, 1]],
                mass: 1.219, inertia: [0.111172755531, 0.111172755531, 0.21942, 0, 0, 0],
            },
        },
        joint revolute wrist_2_joint {
            screw: [0, 0, -1, -0.10915, 0.81725, 0],
            link wrist_2_link {
                home: [[1, 0, 0, 0], [0, 1, 0, 0.093], [0, 0, 1, 0], [0, 0, 0, 1]],
                mass: 1.219, inertia: [0.111172755531, 0.111172755531, 0.21942, 0, 0, 0],
            },
        },
        joint revolute wrist_3_joint {
            screw: [0, 1, 0, 0.005491, 0, 0.81725],
            link wrist_3_link {
                home: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.09465], [0, 0, 0, 1]],
                mass: 0.1879, inertia: [0.0171364731454, 0.0171364731454, 0.033822, 0, 0, 0],
            },
        },
        end_effector ee_link {
            home: [[1, 0, 0, 0], [0, 0, 1, 0.0823], [0, -1, 0, 0], [0, 0, 0, 1]],
        },
    });
    same_impl(&robot, "mr_ur5.toml", "MrUr5");
}

#[test]
fn flat_link_keys_and_axis_point_equal_the_nested_form() {
    let flat = inline_robot(quote! {
        pub struct P;
        joint revolute a { axis: [0, 0, 2], point: [1, 2, 3], home: { rpy: [0, FRAC_PI_2, 0] },
            shape: { cylinder: [0.05, 2 * 0.2] }, density: 2700 },
    });
    let nested = inline_robot(quote! {
        pub struct P;
        joint revolute a { screw: [0, 0, 1, 2, -1, 0], link link1 {
            home: { xyz: [0, 0, 0], rpy: [0, 1.5707963267948966, 0] },
            shape: { cylinder: [0.05, 0.4] }, density: 2700.0 } },
    });
    assert_eq!(
        flat,
        Robot {
            source: flat.source.clone(),
            ..nested
        }
    );
    let m = 2700.0 * core::f64::consts::PI * 0.05 * 0.05 * 0.4;
    assert!((flat.links[0].inertia.mass() - m).abs() < 1e-12 * m);
}

#[test]
fn errors_are_accumulated_and_name_the_field() {
    let errors = inline_errors(quote! {
        pub struct Bad;
        gravity: [0, 0, -9.81, 1],
        joint revolute { screw: [0, 0, 1, 0, 0], home: {}, mass: -1, inertia: [1, 1, 1, 0, 0, 0] },
        joint revolute { axis: [0, 0, 1], point: [0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 3, 0, 0, 0], masss: 1 },
    });
    let all = errors.join("\n");
    assert!(all.contains("unknown field `masss`"), "{all}");
    // The first pass stops at key-level errors; fix those and the model's errors appear.
    let errors = inline_errors(quote! {
        pub struct Bad;
        joint revolute { screw: [0, 0, 1, 0, 0], home: {}, mass: -1, inertia: [1, 1, 1, 0, 0, 0] },
        joint revolute { axis: [0, 0, 1], point: [0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 3, 0, 0, 0] },
    });
    let all = errors.join("\n");
    assert!(
        all.contains("joint `joint1`, `screw`: expected 6 numbers, found 5"),
        "{all}"
    );
    assert!(all.contains("link `link1`, `mass`"), "{all}");
    assert!(
        all.contains("link `link2`, `inertia`") && all.contains("triangle"),
        "{all}"
    );
}

/// Two arms on a torso on a floating pelvis, in TOML.
const TWO_ARMS: &str = r#"name = "TwoArms"

[base]
name = "pelvis"
floating = true
mass = 5
inertia = [0.05, 0.04, 0.03, 0, 0, 0]
com = [0, 0, 0.05]

[[joint]]
name = "torso_yaw"
type = "revolute"
axis = [0, 0, 1]
point = [0, 0, 0]

[joint.link]
name = "torso"
home = { xyz = [0, 0, 0.3] }
mass = 10
inertia = [0.3, 0.3, 0.1, 0, 0, 0]

[[joint]]
name = "left_shoulder"
type = "revolute"
parent = "torso"
axis = [0, 1, 0]
point = [0, 0.2, 0.5]

[joint.link]
name = "left_arm"
home = { xyz = [0, 0.2, 0.2] }
mass = 1
inertia = [0.01, 0.01, 0.002, 0, 0, 0]
com = [0, 0, -0.15]

[[joint]]
name = "right_shoulder"
type = "revolute"
parent = "torso"
axis = [0, 1, 0]
point = [0, -0.2, 0.5]

[joint.link]
name = "right_arm"
home = { xyz = [0, -0.2, 0.2] }
mass = 1
inertia = [0.01, 0.01, 0.002, 0, 0, 0]
com = [0, 0, -0.15]

[end_effector]
name = "hand"
parent = "left_arm"
home = { xyz = [0, 0, -0.3] }

[[frame]]
name = "right_hand"
parent = "right_arm"
home = { xyz = [0, 0, -0.3], rpy = [0, 0, 1.5] }

[[frame]]
name = "head"
parent = "torso"
"#;

#[test]
fn a_tree_on_a_floating_base_inline_equals_toml() {
    let inline = inline_robot(quote! {
        pub struct TwoArms;
        base pelvis {
            floating: true,
            mass: 5, inertia: [0.05, 0.04, 0.03, 0, 0, 0], com: [0, 0, 0.05],
        },
        joint revolute torso_yaw {
            axis: [0, 0, 1], point: [0, 0, 0],
            link torso { home: { xyz: [0, 0, 0.3] }, mass: 10, inertia: [0.3, 0.3, 0.1, 0, 0, 0] },
        },
        joint revolute left_shoulder {
            parent: torso,
            axis: [0, 1, 0], point: [0, 0.2, 0.5],
            link left_arm {
                home: { xyz: [0, 0.2, 0.2] }, mass: 1,
                inertia: [0.01, 0.01, 0.002, 0, 0, 0], com: [0, 0, -0.15],
            },
        },
        joint revolute right_shoulder {
            parent: "torso",
            axis: [0, 1, 0], point: [0, -0.2, 0.5],
            home: { xyz: [0, -0.2, 0.2] }, mass: 1,
            inertia: [0.01, 0.01, 0.002, 0, 0, 0], com: [0, 0, -0.15],
        },
        end_effector hand { parent: left_arm, home: { xyz: [0, 0, -0.3] } },
        frame right_hand { parent: link3, home: { xyz: [0, 0, -0.3], rpy: [0, 0, 1.5] } },
        frame "head" { parent: torso },
    });
    // The flat form names the link `link3`; the file names it `right_arm`.
    let toml = dynamics_model::toml_format::from_str(
        &TWO_ARMS.replace("\"right_arm\"", "\"link3\""),
        "two_arms.toml",
    )
    .unwrap();
    assert_eq!(
        inline,
        Robot {
            source: inline.source.clone(),
            ..toml
        }
    );
    assert_eq!(inline.parents(), [None, Some(0), Some(0)]);
    assert!(inline.base.floating);
    assert_eq!(inline.base.name, "pelvis");
    assert_eq!(inline.end_effector.parent, Some(1));
    let frames: Vec<(&str, Option<usize>)> = inline
        .frames
        .iter()
        .map(|f| (f.name.as_str(), f.parent))
        .collect();
    assert_eq!(frames, [("right_hand", Some(2)), ("head", Some(0))]);
}

#[test]
fn a_base_with_bodies_and_no_floating_key_is_fixed() {
    let r = inline_robot(quote! {
        pub struct Bodies;
        base {
            body hip { shape: { box: [0.2, 0.3, 0.1] }, mass: 4 },
            body battery { mass: 1, inertia: [0, 0, 0, 0, 0, 0], frame: { xyz: [0, 0, 0.1] } },
        },
        joint revolute j { screw: [0, 0, 1, 0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 1, 0, 0, 0] },
    });
    assert_eq!(r.base.name, "base");
    assert!(!r.base.floating);
    assert_eq!(r.base.inertia.mass(), 5.0);
    assert!((r.base.inertia.com() - nalgebra::Vector3::new(0.0, 0.0, 0.02)).amax() < 1e-16);
}

#[test]
fn tree_and_base_key_errors_are_accumulated() {
    let all = inline_errors(quote! {
        pub struct Bad;
        base pelvis { floating: yes, masss: 1, floating: false, home: {} },
        base other {},
        joint revolute a { parent: [1], screw: [0, 0, 1, 0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 1, 0, 0, 0] },
        end_effector e { parent: 1, hom: {}, link x {} },
        frame { parent: a },
        frame g { home: {}, pose: {} },
    })
    .join("\n");
    for part in [
        "expected `true`",
        "unknown field `masss` in the base",
        "duplicate field `floating` in the base",
        "unknown field `home` in the base",
        "duplicate `base`",
        "expected a name or a string, found a list",
        "expected a name or a string, found a number",
        "unknown field `hom` in the end effector",
        "the end effector holds `parent` and `home` only",
        "a frame needs a name",
        "a frame needs `parent: LINK`",
        "unknown field `pose` in a frame",
    ] {
        assert!(all.contains(part), "`{part}` missing from:\n{all}");
    }
}

#[test]
fn tree_and_base_model_errors_name_the_field() {
    let all = inline_errors(quote! {
        pub struct Bad;
        base pelvis { floating: true, mass: -5, inertia: [1, 1, 1, 0, 0, 0] },
        joint revolute a { parent: nowhere, screw: [0, 0, 1, 0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 1, 0, 0, 0] },
        joint revolute b { parent: link3, screw: [0, 0, 1, 0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 1, 0, 0, 0] },
        joint revolute c { parent: pelvis, screw: [0, 0, 1, 0, 0, 0], home: {}, mass: 1, inertia: [1, 1, 1, 0, 0, 0] },
        end_effector e { parent: ghost },
        frame foot { parent: phantom },
    })
    .join("\n");
    for part in [
        "link `pelvis`, `mass`: the mass must be finite and ≥ 0",
        "joint `a`, `parent`: `nowhere` is neither the base nor a link",
        "joint `b`, `parent`: `link3` is the link of joint 3 `c`, which comes after this joint",
        "end effector, `parent`: `ghost` is neither the base nor a link",
        "frame `foot`, `parent`: `phantom` is neither the base nor a link",
    ] {
        assert!(all.contains(part), "`{part}` missing from:\n{all}");
    }
    // Joint c, which hangs from the base by name, is fine: it is only named in b's error.
    assert_eq!(all.matches("joint `c`").count(), 1, "{all}");
}

#[test]
fn mimic_in_the_inline_grammar() {
    let robot = inline_robot(quote! {
        pub struct Gripper;
        joint revolute wrist {
            screw: [0, 0, 1, 0, 0, 0],
            link palm { home: { xyz: [0, 0, 0.2] }, mass: 1.0, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
        },
        joint prismatic left {
            axis: [0, 1, 0],
            link left_finger { home: { xyz: [0, 0.02, 0.1] }, mass: 0.1, inertia: [0.001, 0.001, 0.001, 0, 0, 0] },
        },
        joint prismatic right {
            axis: [0, -1, 0],
            parent: palm,
            mimic: { joint: left, multiplier: 1.0, offset: 0.001 },
            link right_finger { home: { xyz: [0, -0.02, 0.1] }, mass: 0.1, inertia: [0.001, 0.001, 0.001, 0, 0, 0] },
        },
    });
    assert_eq!(robot.joint_names(), ["wrist", "left"]);
    assert_eq!(
        robot.joints[2].mimic,
        Some(dynamics_model::Mimic {
            leader: 1,
            multiplier: 1.0,
            offset: 0.001
        })
    );
    let errors = inline_errors(quote! {
        pub struct Gripper;
        joint revolute wrist {
            screw: [0, 0, 1, 0, 0, 0],
            mimic: { multiplier: 2 },
            link palm { home: { xyz: [0, 0, 0.2] }, mass: 1.0, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
        },
    });
    assert!(
        errors.iter().any(|e| e.contains("the joint it follows")),
        "{errors:?}"
    );
    let errors = inline_errors(quote! {
        pub struct Gripper;
        joint revolute wrist {
            screw: [0, 0, 1, 0, 0, 0],
            link palm { home: { xyz: [0, 0, 0.2] }, mass: 1.0, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
        },
        joint revolute other {
            screw: [0, 0, 1, 0, 0, 0],
            mimic: { joint: thumb },
            link finger { home: { xyz: [0, 0, 0.2] }, mass: 1.0, inertia: [0.01, 0.01, 0.01, 0, 0, 0] },
        },
    });
    assert!(
        errors
            .iter()
            .any(|e| e.contains("`mimic`") && e.contains("names no joint")),
        "{errors:?}"
    );
}

#[test]
fn rotor_and_friction_fields_reach_the_joints_and_the_mass_matrix() {
    let make = |rotor: TokenStream| {
        inline_robot(quote! {
            pub struct Arm;
            joint revolute j1 {
                screw: [0, 0, 1, 0, 0, 0],
                #rotor
                link arm { home: { xyz: [1, 0, 0] }, mass: 2.0, inertia: [4, 4, 4, 0, 0, 0] },
            },
        })
    };
    let plain = make(quote!());
    let geared = make(quote!(rotor_inertia: 0.01, gear_ratio: 10, damping: 0.5, friction: 1.5,));
    let joint = &geared.joints[0];
    assert_eq!((joint.damping, joint.friction), (0.5, 1.5));
    assert!(
        (joint.armature() - 1.0).abs() < 1e-15,
        "G² I_rotor = 100 · 0.01"
    );
    let m = |r: &Robot| {
        let d = crate::expand::expand(r);
        d.graph.eval(&d.mass_matrix, &|_| 0.3)[0]
    };
    assert!((m(&geared) - m(&plain) - 1.0).abs() < 1e-12);
}

#[test]
fn derive_snap_angles_option_is_read_and_checked() {
    let parse = |input: syn::DeriveInput| {
        let mut errors = value::Errors::default();
        let attr = derive::parse_attrs(&input, &mut errors);
        (
            attr.options.load.snap_angles,
            errors.take().map(|e| e.to_string()),
        )
    };
    let ok: syn::DeriveInput = syn::parse_quote! {
        #[dynamics(file = "arm.urdf", snap_angles = 1e-5)]
        struct Arm;
    };
    assert_eq!(parse(ok), (Some(1e-5), None));
    let wide: syn::DeriveInput = syn::parse_quote! {
        #[dynamics(file = "arm.urdf", snap_angles = 0.5)]
        struct Arm;
    };
    let (snap, error) = parse(wide);
    assert_eq!(snap, None);
    assert!(
        error.as_deref().is_some_and(
            |e| e.starts_with("`snap_angles` must be between 0 and 1e-2 rad, found 0.5")
        ),
        "{error:?}"
    );
}

#[test]
fn derive_friction_smoothing_takes_a_number() {
    let input: syn::DeriveInput = syn::parse_quote! {
        #[dynamics(file = "arm.urdf", friction_smoothing = 0.05)]
        struct Arm;
    };
    let mut errors = value::Errors::default();
    let attr = derive::parse_attrs(&input, &mut errors);
    assert!(errors.take().is_none());
    assert_eq!(
        attr.options.friction,
        Some(crate::options::Friction::Smooth(0.05))
    );
}
