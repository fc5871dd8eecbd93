//! Macro-generated dynamics against the reference implementation (dynamics-reference) on the
//! shipped robots, and the inline pendulum against its closed forms (seed case §4.1).

use dynamics_macros::Dynamics;
use dynamics_model::{load_file, LoadOptions, Robot};
use nalgebra::{DMatrix, DVector, SMatrix, SVector, Vector2, Vector6};
use std::path::Path;

#[derive(Dynamics)]
#[dynamics(file = "../robots/ur5.urdf")]
struct Ur5;

#[derive(Dynamics)]
#[dynamics(file = "../robots/mr_ur5.toml")]
struct MrUr5;

#[derive(Dynamics)]
#[dynamics(file = "../robots/rand7.toml")]
struct Rand7;

/// The UR5 by the Lagrangian route.
#[derive(Dynamics)]
#[dynamics(file = "../robots/ur5.urdf", method = "lagrangian")]
struct Ur5Lagrangian;

#[derive(Dynamics)]
#[dynamics(file = "../tests/data/robots/panda.urdf")]
struct Panda;

dynamics_macros::robot! {
    /// robots/pendulum.toml, inline.
    pub struct Pendulum;
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
}

dynamics_macros::robot! {
    /// robots/pendulum.toml, inline, by the Lagrangian route.
    pub struct PendulumLagrangian;
    gravity: [0.0, 0.0, -10.0],
    method: lagrangian,
    joint revolute joint1 {
        screw: [0, 0, 1, 0, 0, 0],
        link arm { home: { xyz: [1, 0, 0] }, mass: 2.0, inertia: [4, 4, 4, 0, 0, 0] },
    },
    joint revolute joint2 {
        screw: [1, 0, 0, 0, 0, 0],
        link pendulum { home: { xyz: [0, 0, -1] }, mass: 2.0, inertia: [4, 4, 0, 0, 0, 0] },
    },
    end_effector bob { home: { xyz: [0, 0, 0] } },
}

dynamics_macros::robot! {
    /// robots/pendulum.toml, inline, with run-time gravity and a payload on its first link.
    pub struct PendulumPayload;
    gravity: [0.0, 0.0, -10.0],
    runtime_parameters: true,
    payload_link: arm,
    joint revolute joint1 {
        screw: [0, 0, 1, 0, 0, 0],
        link arm { home: { xyz: [1, 0, 0] }, mass: 2.0, inertia: [4, 4, 4, 0, 0, 0] },
    },
    joint revolute joint2 {
        screw: [1, 0, 0, 0, 0, 0],
        link pendulum { home: { xyz: [0, 0, -1] }, mass: 2.0, inertia: [4, 4, 0, 0, 0, 0] },
    },
    end_effector bob { home: { xyz: [0, 0, 0] } },
}

/// The UR5 with run-time gravity and a payload on the end effector's link: the struct
/// declares the fields the generated methods read.
#[derive(Dynamics, Clone, Copy, Debug)]
#[dynamics(file = "../robots/ur5.urdf", runtime_parameters)]
struct Ur5Payload {
    gravity: [f64; 3],
    payload_mass: f64,
    payload_com: [f64; 3],
    payload_inertia: [f64; 6],
}

impl Default for Ur5Payload {
    fn default() -> Self {
        Self {
            gravity: Self::DEFAULT_GRAVITY,
            payload_mass: 0.0,
            payload_com: [0.0; 3],
            payload_inertia: [0.0; 6],
        }
    }
}

/// The UR5 with the `*_from_sin_cos` variants.
#[derive(Dynamics)]
#[dynamics(file = "../robots/ur5.urdf", sin_cos_variants)]
struct Ur5SinCos;

dynamics_macros::robot! {
    /// robots/pendulum.toml, inline, with the `*_from_sin_cos` variants.
    pub struct PendulumSinCos;
    gravity: [0.0, 0.0, -10.0],
    sin_cos_variants: true,
    joint revolute joint1 {
        screw: [0, 0, 1, 0, 0, 0],
        link arm { home: { xyz: [1, 0, 0] }, mass: 2.0, inertia: [4, 4, 4, 0, 0, 0] },
    },
    joint revolute joint2 {
        screw: [1, 0, 0, 0, 0, 0],
        link pendulum { home: { xyz: [0, 0, -1] }, mass: 2.0, inertia: [4, 4, 0, 0, 0, 0] },
    },
    end_effector bob { home: { xyz: [0, 0, 0] } },
}

/// Both front ends' `sin_cos_variants`: each variant fed `sin_cos(q)` gives its function's
/// bits.
#[test]
fn sin_cos_variants_from_both_macros_equal_the_functions() {
    let mut rng = Lcg(5);
    for _ in 0..32 {
        let q: SVector<f64, 6> = rng.vector(3.0);
        let qd: SVector<f64, 6> = rng.vector(2.0);
        let qdd: SVector<f64, 6> = rng.vector(2.0);
        let r = Ur5SinCos;
        let (s, c) = r.sin_cos(&q);
        // The sines and cosines themselves (2 ulp of 1 at most).
        assert!((s - q.map(f64::sin)).amax() <= 5e-16 && (c - q.map(f64::cos)).amax() <= 5e-16);
        assert_eq!(
            r.inverse_dynamics_from_sin_cos(&q, &s, &c, &qd, &qdd),
            r.inverse_dynamics(&q, &qd, &qdd)
        );
        assert_eq!(r.mass_matrix_from_sin_cos(&q, &s, &c), r.mass_matrix(&q));
        assert_eq!(
            r.jacobian_body_from_sin_cos(&q, &s, &c),
            r.jacobian_body(&q)
        );
        assert_eq!(
            r.end_effector_pose_from_sin_cos(&q, &s, &c),
            r.end_effector_pose(&q)
        );
        let q: Vector2<f64> = rng.vector(3.0);
        let qd: Vector2<f64> = rng.vector(2.0);
        let p = PendulumSinCos;
        let (s, c) = p.sin_cos(&q);
        assert_eq!(
            p.coriolis_from_sin_cos(&q, &s, &c, &qd),
            p.coriolis(&q, &qd)
        );
        assert_eq!(p.gravity_from_sin_cos(&q, &s, &c), p.gravity(&q));
    }
}

fn load(file: &str) -> Robot {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(file);
    load_file(&path, &LoadOptions::default()).unwrap()
}

/// ‖x − y‖∞ / (‖y‖∞ + 1e-3), asserting the project's tolerance.
fn check(x: &[f64], y: &[f64], what: &str) -> f64 {
    assert_eq!(x.len(), y.len());
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        err <= 1e-9 * scale + 1e-12,
        "{what}: error {err:e} at scale {scale:e}"
    );
    err / scale.max(1e-300)
}

/// Deterministic pseudo-random numbers in [−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn vector<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::from_fn(|_, _| scale * self.next())
    }
}

macro_rules! compare {
    ($name:ident, $ty:ident, $file:expr, $n:literal) => {
        #[test]
        fn $name() {
            let robot = load($file);
            let g = robot.gravity;
            let mut rng = Lcg(17);
            let mut worst: f64 = 0.0;
            for _ in 0..5 {
                let q: SVector<f64, $n> = rng.vector(3.0);
                let qd: SVector<f64, $n> = rng.vector(2.0);
                let qdd: SVector<f64, $n> = rng.vector(2.0);
                let tau: SVector<f64, $n> = rng.vector(20.0);
                let m: SMatrix<f64, $n, $n> = $ty.mass_matrix(&q);
                let m_ref: DMatrix<f64> = dynamics_reference::mass_matrix(&robot, q.as_slice());
                worst = worst.max(check(m.as_slice(), m_ref.as_slice(), "M"));
                let c_ref: DVector<f64> =
                    dynamics_reference::vel_quadratic_forces(&robot, q.as_slice(), qd.as_slice());
                worst = worst.max(check(
                    $ty.coriolis(&q, &qd).as_slice(),
                    c_ref.as_slice(),
                    "c",
                ));
                let g_ref = dynamics_reference::gravity_forces(&robot, q.as_slice(), &g);
                worst = worst.max(check($ty.gravity(&q).as_slice(), g_ref.as_slice(), "g"));
                let id_ref = dynamics_reference::inverse_dynamics(
                    &robot,
                    q.as_slice(),
                    qd.as_slice(),
                    qdd.as_slice(),
                    &g,
                    &Vector6::zeros(),
                );
                worst = worst.max(check(
                    $ty.inverse_dynamics(&q, &qd, &qdd).as_slice(),
                    id_ref.as_slice(),
                    "ID",
                ));
                // The regressor: τ = Y π = Y_b π_base (no armature on these robots).
                let pi = $ty.inertial_parameters();
                let y = $ty.regressor(&q, &qd, &qdd);
                worst = worst.max(check((y * pi).as_slice(), id_ref.as_slice(), "Y π"));
                let yb = $ty.base_regressor(&q, &qd, &qdd);
                let pb = $ty.base_parameters(&pi);
                worst = worst.max(check((yb * pb).as_slice(), id_ref.as_slice(), "Y_b π_b"));
                let fd_ref = dynamics_reference::forward_dynamics(
                    &robot,
                    q.as_slice(),
                    qd.as_slice(),
                    tau.as_slice(),
                    &g,
                    &Vector6::zeros(),
                )
                .unwrap();
                worst = worst.max(check(
                    $ty.forward_dynamics(&q, &qd, &tau).as_slice(),
                    fd_ref.as_slice(),
                    "FD",
                ));
            }
            assert_eq!($ty::JOINT_NAMES.to_vec(), robot.joint_names());
            eprintln!("{}: worst relative error {worst:e}", $file);
        }
    };
}

compare!(ur5_urdf_matches_reference, Ur5, "robots/ur5.urdf", 6);
compare!(mr_ur5_matches_reference, MrUr5, "robots/mr_ur5.toml", 6);
compare!(rand7_matches_reference, Rand7, "robots/rand7.toml", 7);
compare!(
    panda_matches_reference,
    Panda,
    "tests/data/robots/panda.urdf",
    7
);
compare!(
    inline_pendulum_matches_reference,
    Pendulum,
    "robots/pendulum.toml",
    2
);
compare!(
    lagrangian_ur5_matches_reference,
    Ur5Lagrangian,
    "robots/ur5.urdf",
    6
);
compare!(
    lagrangian_inline_pendulum_matches_reference,
    PendulumLagrangian,
    "robots/pendulum.toml",
    2
);

/// Seed case §4.1: M = [[8 + 6 s2², 2 c2], [2 c2, 6]],
/// c = (12 s2 c2 q̇1 q̇2 − 2 s2 q̇2², −6 s2 c2 q̇1²), g = (0, 20 s2).
#[test]
fn inline_pendulum_matches_closed_forms() {
    let mut rng = Lcg(5);
    for _ in 0..10 {
        let q: Vector2<f64> = rng.vector(3.0);
        let qd: Vector2<f64> = rng.vector(2.0);
        let (s2, c2) = q[1].sin_cos();
        let m = [8.0 + 6.0 * s2 * s2, 2.0 * c2, 2.0 * c2, 6.0];
        check(Pendulum.mass_matrix(&q).as_slice(), &m, "M");
        let c = [
            12.0 * s2 * c2 * qd[0] * qd[1] - 2.0 * s2 * qd[1] * qd[1],
            -6.0 * s2 * c2 * qd[0] * qd[0],
        ];
        check(Pendulum.coriolis(&q, &qd).as_slice(), &c, "c");
        check(Pendulum.gravity(&q).as_slice(), &[0.0, 20.0 * s2], "g");
    }
    assert_eq!(Pendulum::DOF, 2);
    assert_eq!(Pendulum::JOINT_NAMES, ["joint1", "joint2"]);
}

/// `robot` with gravity `g` and a payload (mass `m`, centre of mass `c` in the link's frame,
/// inertia `i` about it as `[xx, yy, zz, xy, xz, yz]`) added to link `link`, in the model.
fn with_payload(
    robot: &Robot,
    link: usize,
    g: [f64; 3],
    m: f64,
    c: [f64; 3],
    i: [f64; 6],
) -> Robot {
    let mut r = robot.with_payload(link, m, c, i);
    r.gravity = nalgebra::Vector3::from(g);
    r
}

macro_rules! compare_payload {
    ($name:ident, $ty:ident, $file:expr, $n:literal, $link:expr) => {
        #[test]
        fn $name() {
            let robot = load($file);
            let (g, m, c, i) = (
                [1.0, -2.0, -11.0],
                1.7,
                [0.05, -0.08, 0.12],
                [0.012, 0.015, 0.009, 0.002, -0.001, 0.003],
            );
            let link = $link(&robot);
            let changed = with_payload(&robot, link, g, m, c, i);
            let default = $ty::default();
            assert_eq!(
                default.gravity,
                [robot.gravity[0], robot.gravity[1], robot.gravity[2]]
            );
            assert_eq!(default.payload_mass, 0.0);
            let carrying = $ty {
                gravity: g,
                payload_mass: m,
                payload_com: c,
                payload_inertia: i,
            };
            let mut rng = Lcg(29);
            for _ in 0..5 {
                let q: SVector<f64, $n> = rng.vector(3.0);
                let qd: SVector<f64, $n> = rng.vector(2.0);
                let qdd: SVector<f64, $n> = rng.vector(2.0);
                let tau: SVector<f64, $n> = rng.vector(20.0);
                for (imp, r, what) in [
                    (default, &robot, "default"),
                    (carrying, &changed, "payload"),
                ] {
                    let gr = r.gravity;
                    let m_ref = dynamics_reference::mass_matrix(r, q.as_slice());
                    check(imp.mass_matrix(&q).as_slice(), m_ref.as_slice(), what);
                    let id_ref = dynamics_reference::inverse_dynamics(
                        r,
                        q.as_slice(),
                        qd.as_slice(),
                        qdd.as_slice(),
                        &gr,
                        &Vector6::zeros(),
                    );
                    check(
                        imp.inverse_dynamics(&q, &qd, &qdd).as_slice(),
                        id_ref.as_slice(),
                        what,
                    );
                    let g_ref = dynamics_reference::gravity_forces(r, q.as_slice(), &gr);
                    check(imp.gravity(&q).as_slice(), g_ref.as_slice(), what);
                    let fd_ref = dynamics_reference::forward_dynamics(
                        r,
                        q.as_slice(),
                        qd.as_slice(),
                        tau.as_slice(),
                        &gr,
                        &Vector6::zeros(),
                    )
                    .unwrap();
                    check(
                        imp.forward_dynamics(&q, &qd, &tau).as_slice(),
                        fd_ref.as_slice(),
                        what,
                    );
                    let y = imp.regressor(&q, &qd, &qdd);
                    check(
                        (y * imp.inertial_parameters()).as_slice(),
                        id_ref.as_slice(),
                        what,
                    );
                    let p_ref = dynamics_reference::potential_energy(r, q.as_slice(), &gr);
                    check(&[imp.potential_energy(&q)], &[p_ref], what);
                }
            }
        }
    };
}

compare_payload!(
    inline_pendulum_runtime_parameters_match_reference,
    PendulumPayload,
    "robots/pendulum.toml",
    2,
    |_: &Robot| 0
);
compare_payload!(
    derive_ur5_runtime_parameters_match_reference,
    Ur5Payload,
    "robots/ur5.urdf",
    6,
    |r: &Robot| r.end_effector.parent.unwrap()
);
