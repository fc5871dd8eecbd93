//! Robots built directly from the `pinocchio_model` entries of the Pinocchio tree references
//! (`tests/data/reference/trees/*.json`), and the map between Pinocchio's free-flyer vectors
//! and ours. Independent of any URDF loader: only the JSON's joint placements, axes, parents
//! and inertias are read.

use super::{mat4, mat_of, num, vec3, vec_of};
use dynamics_model::lie::{adjoint, rp_to_trans, twist};
use dynamics_model::{Base, EndEffector, Joint, JointKind, Link, Robot, SpatialInertia};
use nalgebra::{DMatrix, Matrix3, Matrix4, Vector3};
use serde_json::Value;

/// The body's inertia: `mass`, `com` and `inertia_about_com` (joint-frame axes) of one
/// `pinocchio_model` entry, as `G` in the joint frame.
fn entry_inertia(entry: &Value) -> SpatialInertia {
    let i_com = mat_of(&entry["inertia_about_com"]);
    let i_com = Matrix3::from_fn(|r, c| i_com[(r, c)]);
    let com = vec3(&entry["com"]);
    SpatialInertia::from_com_frame(
        num(&entry["mass"]),
        i_com,
        &rp_to_trans(&Matrix3::identity(), &com),
    )
}

/// The robot of a reference file: link frames = Pinocchio joint frames, `M_{λ(i),i}` = the
/// entry's `placement`, `S_i = [Ad_{M_{0i}}] (axis, 0)` (revolute) or `(0, axis)` (prismatic)
/// with the axis in the joint frame, `G_i` from mass, com and inertia about the com. On a
/// floating robot the `root_joint` entry is the base body (our free joint) and its children
/// are our root links. Gravity from the file; the end effector sits on the last link.
pub fn robot_from_pinocchio(file: &Value) -> Robot {
    let floating = file["floating"].as_bool().expect("floating");
    let entries = file["pinocchio_model"].as_array().expect("pinocchio_model");
    // Pinocchio index (0 = universe) → our link index; the first `skip` Pinocchio joints
    // (the universe, and the free flyer on a floating robot) are the base.
    let skip = if floating { 2 } else { 1 };
    let movable = if floating {
        &entries[1..]
    } else {
        &entries[..]
    };
    if floating {
        assert_eq!(entries[0]["kind"], "free_flyer");
        assert_eq!(mat4(&entries[0]["placement"]), Matrix4::identity());
    }
    let mut joints = Vec::new();
    let mut links = Vec::new();
    let mut m_0: Vec<Matrix4<f64>> = Vec::new(); // M_{0i}, the home poses
    for (i, e) in movable.iter().enumerate() {
        let p = e["parent_index"].as_u64().expect("parent_index") as usize;
        let parent = p.checked_sub(skip);
        assert!(parent.is_none_or(|p| p < i), "parents come first");
        let placement = mat4(&e["placement"]);
        let home = parent.map_or(Matrix4::identity(), |p| m_0[p]) * placement;
        m_0.push(home);
        let axis = Vector3::from_column_slice(&vec_of(&e["axis"]));
        let (kind, a) = match e["kind"].as_str().expect("kind") {
            "revolute" => (JointKind::Revolute, twist(&axis, &Vector3::zeros())),
            "prismatic" => (JointKind::Prismatic, twist(&Vector3::zeros(), &axis)),
            other => panic!("joint kind {other} is not read by these tests"),
        };
        assert_eq!(e["nq"], 1, "one-dof joints only");
        let name = e["name"].as_str().expect("name");
        joints.push(Joint::new(name, kind, adjoint(&home) * a));
        links.push(Link {
            name: name.to_string(),
            parent,
            home: placement,
            inertia: entry_inertia(e),
        });
    }
    let base = if floating {
        Base {
            name: file["urdf_root_link"]
                .as_str()
                .unwrap_or("base")
                .to_string(),
            inertia: entry_inertia(&entries[0]),
            floating: true,
        }
    } else {
        Base::fixed()
    };
    let n = joints.len();
    let robot = Robot {
        name: file["robot"].as_str().expect("robot").to_string(),
        source: "Pinocchio reference JSON".into(),
        base,
        joints,
        links,
        end_effector: EndEffector {
            name: "tip".into(),
            parent: n.checked_sub(1),
            home: Matrix4::identity(),
        },
        frames: Vec::new(),
        gravity: vec3(&file["gravity"]),
        runtime: dynamics_model::RuntimeParameters::default(),
        parameters: Default::default(),
    };
    robot.validate().expect("the reference robot is valid");
    assert_eq!(robot.nq(), file["nq"].as_u64().unwrap() as usize);
    assert_eq!(robot.nv(), file["nv"].as_u64().unwrap() as usize);
    robot
}

/// Pinocchio's velocity-like vector (`v`, `a`, `τ`: linear part of the base first) in our
/// order (angular first): entries 0..3 and 3..6 swap on a floating base.
pub fn to_ours(floating: bool, x: &[f64]) -> Vec<f64> {
    let mut y = x.to_vec();
    if floating {
        for k in 0..3 {
            y.swap(k, k + 3);
        }
    }
    y
}

/// Pinocchio's nv×nv matrix in our order: `P M Pᵀ`, rows and columns 0..3 and 3..6 swapped on
/// a floating base.
pub fn matrix_to_ours(floating: bool, m: &DMatrix<f64>) -> DMatrix<f64> {
    let mut y = m.clone();
    if floating {
        for k in 0..3 {
            y.swap_rows(k, k + 3);
            y.swap_columns(k, k + 3);
        }
    }
    y
}
