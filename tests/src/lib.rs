//! Shared harness of the comparison tests: every robot generated and compiled by this
//! crate's build.rs, behind one object-safe interface, and the reference model it came from.

use dynamics_model::random::{random_chain, ChainSpec};
use dynamics_model::{LoadOptions, Robot};
use nalgebra::{DMatrix, DVector, Matrix4};

/// Where a compiled case's robot comes from (so the tests can load the same model).
#[derive(Clone, Copy, Debug)]
pub enum Spec {
    /// A shipped robot by name.
    Shipped(&'static str),
    /// `tests/data/robots/<name>.urdf` with the given tip link.
    Urdf(&'static str, &'static str),
    /// `random_chain(seed, dof)` with 30 % prismatic joints.
    Random(u64, usize),
    /// `random_tree(seed, tree_spec(dof, floating))`.
    Tree(u64, usize, bool),
    /// `tests/data/robots/trees/<name>.urdf`, with or without a floating base.
    UrdfTree(&'static str, bool),
    /// `random_mimics(random_tree(seed, tree_spec(dof, floating)), seed, 0.4)`: a random tree
    /// with mimic joints.
    TreeMimic(u64, usize, bool),
    /// `tests/data/robots/trees/<name>.urdf` with mimic joints (fixed base), compared with
    /// `data/reference/trees/<name>.json`.
    UrdfMimic(&'static str),
    /// `actuated(random_tree(seed, tree_spec(dof, floating)), seed)` (armature, damping and
    /// Coulomb friction on every joint), generated with friction in the dynamics: Coulomb
    /// (`None`) or smoothed with this ε.
    Actuated(u64, usize, bool, Option<f64>),
    /// `tests/data/robots/panda.urdf` (tip `panda_hand`) with `panda_armature`, compared with
    /// Pinocchio's `model.armature` numbers.
    PandaArmature,
    /// A robot generated with run-time parameters, evaluated with the gravity `values[..3]`
    /// and a payload on the end effector's link (mass `values[3]`, centre of mass
    /// `values[4..7]`, inertia about it `values[7..13]` as `[xx, yy, zz, xy, xz, yz]`):
    /// [`with_payload`] of the inner robot.
    Payload(&'static Spec, [f64; 13]),
}

/// `robot` with gravity `values[..3]` and the payload of `values[3..]` (see
/// [`Spec::Payload`]) added to link `link`'s spatial inertia, numerically in the model.
pub fn with_payload(robot: &Robot, link: usize, values: &[f64; 13]) -> Robot {
    let at = |k: usize| values[k];
    let mut r = robot.with_payload(
        link,
        values[3],
        [4, 5, 6].map(at),
        [7, 8, 9, 10, 11, 12].map(at),
    );
    r.gravity = nalgebra::Vector3::new(values[0], values[1], values[2]);
    r
}

include!("tree_spec.rs");

impl Spec {
    /// Loads the robot model.
    pub fn robot(&self) -> Robot {
        match *self {
            Spec::Shipped(name) => dynamics_model::load(name, &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e}")),
            Spec::Urdf(name, tip) => {
                let path = data_dir().join(format!("robots/{name}.urdf"));
                let options = LoadOptions {
                    tip: Some(tip.to_string()),
                    ..Default::default()
                };
                dynamics_model::load_file(&path, &options).unwrap_or_else(|e| panic!("{e}"))
            }
            Spec::Random(seed, dof) => random_chain(
                seed,
                ChainSpec {
                    dof,
                    prismatic: 0.3,
                },
            ),
            Spec::UrdfTree(name, floating) => {
                let path = data_dir().join(format!("robots/trees/{name}.urdf"));
                let options = LoadOptions {
                    floating_base: floating,
                    ..Default::default()
                };
                dynamics_model::load_file(&path, &options).unwrap_or_else(|e| panic!("{e}"))
            }
            Spec::Tree(seed, dof, floating) => with_leaf_frames(
                dynamics_model::random::random_tree(seed, tree_spec(dof, floating)),
            ),
            Spec::TreeMimic(seed, dof, floating) => {
                with_leaf_frames(dynamics_model::random::random_mimics(
                    dynamics_model::random::random_tree(seed, tree_spec(dof, floating)),
                    seed,
                    0.4,
                ))
            }
            Spec::Actuated(seed, dof, floating, _) => actuated(
                dynamics_model::random::random_tree(seed, tree_spec(dof, floating)),
                seed,
            ),
            Spec::PandaArmature => panda_armature(Spec::Urdf("panda", "panda_hand").robot()),
            Spec::UrdfMimic(name) => {
                let path = data_dir().join(format!("robots/trees/{name}.urdf"));
                dynamics_model::load_file(&path, &LoadOptions::default())
                    .unwrap_or_else(|e| panic!("{e}"))
            }
            Spec::Payload(inner, values) => {
                let robot = inner.robot();
                let link = robot
                    .end_effector
                    .parent
                    .expect("the end effector is on a link");
                with_payload(&robot, link, &values)
            }
        }
    }
}

impl Spec {
    /// The joint friction the generated `inverse_dynamics` and `forward_dynamics` include
    /// (zero but for [`Spec::Actuated`]), by the reference's `friction_forces`.
    pub fn friction_in_dynamics(&self, robot: &Robot, qd: &[f64]) -> nalgebra::DVector<f64> {
        match *self {
            Spec::Actuated(.., eps) => dynamics_reference::friction_forces(robot, qd, eps),
            Spec::Payload(inner, _) => inner.friction_in_dynamics(robot, qd),
            _ => nalgebra::DVector::zeros(robot.nv()),
        }
    }
}

/// `tests/data` of this repository.
pub fn data_dir() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data")
}

/// The JSON file `data/reference/<path>` (Pinocchio's and the Modern Robotics library's
/// numbers; `data/reference/README.md` says how each was made), naming the file if it is
/// missing or not JSON.
pub fn reference_json(path: &str) -> serde_json::Value {
    let file = data_dir().join("reference").join(path);
    let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// A generated robot, evaluated through f64 slices whatever its scalar type.
pub trait GeneratedDynamics: Sync {
    /// The number of joint coordinates (mimic joints not counted).
    fn dof(&self) -> usize;
    /// The length of q.
    fn nq(&self) -> usize;
    /// The length of ν, ν̇ and τ.
    fn nv(&self) -> usize;
    /// The joint names.
    fn joint_names(&self) -> Vec<&'static str>;
    /// `M(q)`.
    fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64>;
    /// `start` after `mass_matrix_lower_into(q, start)` (in the case's scalar type).
    fn mass_matrix_lower_into(&self, q: &[f64], start: &DMatrix<f64>) -> DMatrix<f64>;
    /// `c(q, q̇)`.
    fn coriolis(&self, q: &[f64], qd: &[f64]) -> DVector<f64>;
    /// `g(q)`.
    fn gravity(&self, q: &[f64]) -> DVector<f64>;
    /// `τ(q, q̇, q̈)`.
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64>;
    /// `q̈(q, q̇, τ)`.
    fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64]) -> DVector<f64>;
    /// `K(q, q̇)`.
    fn kinetic_energy(&self, q: &[f64], qd: &[f64]) -> f64;
    /// `P(q)`.
    fn potential_energy(&self, q: &[f64]) -> f64;
    /// `Ṁ(q, q̇)`.
    fn mass_matrix_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    /// `J̇_s(q, q̇)`.
    fn jacobian_space_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    /// `J̇_b(q, q̇)`.
    fn jacobian_body_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    /// `T_{0,n+1}(q)` as a homogeneous matrix.
    fn end_effector_pose(&self, q: &[f64]) -> Matrix4<f64>;
    /// `J_s(q)`, 6×nv.
    fn jacobian_space(&self, q: &[f64]) -> DMatrix<f64>;
    /// `J_b(q)`, 6×nv.
    fn jacobian_body(&self, q: &[f64]) -> DMatrix<f64>;
    /// `C(q, q̇)`.
    fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    /// `(M, h)`.
    fn mass_matrix_and_bias(&self, q: &[f64], qd: &[f64]) -> (DMatrix<f64>, DVector<f64>);
    /// `J_bᵀ F_tip`.
    fn end_effector_forces(&self, q: &[f64], f_tip: &[f64]) -> DVector<f64>;
    /// `τ` with a tip wrench.
    fn inverse_dynamics_with_tip(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        f_tip: &[f64],
    ) -> DVector<f64>;
    /// `q̈` with a tip wrench.
    fn forward_dynamics_with_tip(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        f_tip: &[f64],
    ) -> DVector<f64>;
    /// `Λ(q)`.
    fn task_space_mass_matrix(&self, q: &[f64]) -> Option<DMatrix<f64>>;
    /// `η(q, q̇)`.
    fn task_space_bias(&self, q: &[f64], qd: &[f64]) -> Option<DVector<f64>>;
    /// `(q̈, λ)` under the constraints `a` (K×nv, K = 1, 2 or 3) with `a_dot_qd = Ȧq̇`.
    fn constrained_forward_dynamics(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        a: &DMatrix<f64>,
        a_dot_qd: &[f64],
    ) -> Option<(DVector<f64>, DVector<f64>)>;
    /// `τ_f(q̇)`.
    fn friction(&self, qd: &[f64]) -> DVector<f64>;
    /// `FRAME_NAMES` (empty without named frames).
    fn frame_names(&self) -> Vec<&'static str>;
    /// `frame_poses(q)` as homogeneous matrices.
    fn frame_poses(&self, q: &[f64]) -> Vec<Matrix4<f64>>;
    /// `frame_jacobians_space(q)`.
    fn frame_jacobians_space(&self, q: &[f64]) -> Vec<DMatrix<f64>>;
    /// `frame_jacobians_body(q)`.
    fn frame_jacobians_body(&self, q: &[f64]) -> Vec<DMatrix<f64>>;
}

/// The derivative functions of a generated robot, through f64 slices (only the cases
/// generated with them: [`DERIVATIVE_CASES`]).
pub trait GeneratedDerivatives: Sync {
    /// `(∂τ/∂q, ∂τ/∂q̇)`.
    fn inverse_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>);
    /// `(τ, ∂τ/∂q, ∂τ/∂q̇)`.
    fn inverse_dynamics_with_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> (DVector<f64>, DMatrix<f64>, DMatrix<f64>);
    /// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)`.
    fn forward_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>);
    /// `(q̈, ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)`.
    fn forward_dynamics_with_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
    ) -> (DVector<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>);
    /// `M⁻¹(q)`.
    fn mass_matrix_inverse(&self, q: &[f64]) -> DMatrix<f64>;
    /// `∂g/∂q`.
    fn gravity_derivative(&self, q: &[f64]) -> DMatrix<f64>;
}

/// Implements [`GeneratedDerivatives`] for the generated `$m::Robot`.
#[macro_export]
macro_rules! derivatives_adapter {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
        impl $crate::GeneratedDerivatives for $m::Robot {
            fn inverse_dynamics_derivatives(
                &self,
                q: &[f64],
                qd: &[f64],
                qdd: &[f64],
            ) -> (DMatrix<f64>, DMatrix<f64>) {
                let (a, b) = $m::Robot::inverse_dynamics_derivatives(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                );
                (to_dm(&a), to_dm(&b))
            }
            fn inverse_dynamics_with_derivatives(
                &self,
                q: &[f64],
                qd: &[f64],
                qdd: &[f64],
            ) -> (DVector<f64>, DMatrix<f64>, DMatrix<f64>) {
                let (t, a, b) = $m::Robot::inverse_dynamics_with_derivatives(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                );
                (to_d(t), to_dm(&a), to_dm(&b))
            }
            fn forward_dynamics_derivatives(
                &self,
                q: &[f64],
                qd: &[f64],
                tau: &[f64],
            ) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
                let (a, b, c) = $m::Robot::forward_dynamics_derivatives(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(tau),
                );
                (to_dm(&a), to_dm(&b), to_dm(&c))
            }
            fn forward_dynamics_with_derivatives(
                &self,
                q: &[f64],
                qd: &[f64],
                tau: &[f64],
            ) -> (DVector<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
                let (x, a, b, c) = $m::Robot::forward_dynamics_with_derivatives(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(tau),
                );
                (to_d(x), to_dm(&a), to_dm(&b), to_dm(&c))
            }
            fn mass_matrix_inverse(&self, q: &[f64]) -> DMatrix<f64> {
                to_dm(&$m::Robot::mass_matrix_inverse(self, &to_s::<$s, $nq>(q)))
            }
            fn gravity_derivative(&self, q: &[f64]) -> DMatrix<f64> {
                to_dm(&$m::Robot::gravity_derivative(self, &to_s::<$s, $nq>(q)))
            }
        }
    };
}

/// The regressor functions of a generated robot, through f64 slices (the cases generated
/// with them: [`REGRESSOR_CASES`]).
pub trait GeneratedRegressor: Sync {
    /// `Y(q, q̇, q̈)`, nv × N_PARAMETERS.
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64>;
    /// The robot's own standard parameters π.
    fn inertial_parameters(&self) -> DVector<f64>;
    /// `Y_b(q, q̇, q̈)`, nv × N_BASE_PARAMETERS.
    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64>;
    /// The base parameters of `pi`.
    fn base_parameters(&self, pi: &[f64]) -> DVector<f64>;
    /// `PARAMETER_NAMES`.
    fn parameter_names(&self) -> Vec<&'static str>;
}

/// Implements [`GeneratedRegressor`] for the generated `$m::Robot`.
#[macro_export]
macro_rules! regressor_adapter {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
        impl $crate::GeneratedRegressor for $m::Robot {
            fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64> {
                to_dm(&$m::Robot::regressor(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                ))
            }
            fn inertial_parameters(&self) -> DVector<f64> {
                to_d($m::Robot::inertial_parameters(self))
            }
            fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64> {
                to_dm(&$m::Robot::base_regressor(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                ))
            }
            fn base_parameters(&self, pi: &[f64]) -> DVector<f64> {
                to_d($m::Robot::base_parameters(
                    self,
                    &to_s::<$s, { $m::Robot::N_PARAMETERS }>(pi),
                ))
            }
            fn parameter_names(&self) -> Vec<&'static str> {
                $m::Robot::PARAMETER_NAMES.to_vec()
            }
        }
    };
}

/// One compiled robot.
pub struct Case {
    /// Its module name.
    pub module: &'static str,
    /// Its model.
    pub spec: Spec,
    /// `"f64"` or `"f32"`.
    pub scalar: &'static str,
    /// The generated code.
    pub imp: &'static dyn GeneratedDynamics,
}

macro_rules! adapter {
    ($m:ident, $nq:literal, $nv:literal, $s:ty) => {
        adapter!($m, $nq, $nv, $s, {
            fn frame_names(&self) -> Vec<&'static str> {
                Vec::new()
            }
            fn frame_poses(&self, _: &[f64]) -> Vec<Matrix4<f64>> {
                Vec::new()
            }
            fn frame_jacobians_space(&self, _: &[f64]) -> Vec<DMatrix<f64>> {
                Vec::new()
            }
            fn frame_jacobians_body(&self, _: &[f64]) -> Vec<DMatrix<f64>> {
                Vec::new()
            }
        });
    };
    ($m:ident, $nq:literal, $nv:literal, $s:ty, frames) => {
        adapter!($m, $nq, $nv, $s, {
            fn frame_names(&self) -> Vec<&'static str> {
                $m::Robot::FRAME_NAMES.to_vec()
            }
            fn frame_poses(&self, q: &[f64]) -> Vec<Matrix4<f64>> {
                $m::Robot::frame_poses(self, &to_s::<$s, $nq>(q))
                    .iter()
                    .map(homogeneous)
                    .collect()
            }
            fn frame_jacobians_space(&self, q: &[f64]) -> Vec<DMatrix<f64>> {
                $m::Robot::frame_jacobians_space(self, &to_s::<$s, $nq>(q))
                    .iter()
                    .map(|j| DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64))
                    .collect()
            }
            fn frame_jacobians_body(&self, q: &[f64]) -> Vec<DMatrix<f64>> {
                $m::Robot::frame_jacobians_body(self, &to_s::<$s, $nq>(q))
                    .iter()
                    .map(|j| DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64))
                    .collect()
            }
        });
    };
    ($m:ident, $nq:literal, $nv:literal, $s:ty, { $($frames:tt)* }) => {
        impl $crate::GeneratedDynamics for $m::Robot {
            fn dof(&self) -> usize {
                $m::Robot::DOF
            }
            fn nq(&self) -> usize {
                $m::Robot::NQ
            }
            fn nv(&self) -> usize {
                $m::Robot::NV
            }
            fn joint_names(&self) -> Vec<&'static str> {
                $m::Robot::JOINT_NAMES.to_vec()
            }
            fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
                let m = $m::Robot::mass_matrix(self, &to_s::<$s, $nq>(q));
                DMatrix::from_fn($nv, $nv, |i, j| m[(i, j)] as f64)
            }
            fn mass_matrix_lower_into(&self, q: &[f64], start: &DMatrix<f64>) -> DMatrix<f64> {
                let mut m =
                    nalgebra::SMatrix::<$s, $nv, $nv>::from_fn(|i, j| start[(i, j)] as $s);
                $m::Robot::mass_matrix_lower_into(self, &to_s::<$s, $nq>(q), &mut m);
                DMatrix::from_fn($nv, $nv, |i, j| m[(i, j)] as f64)
            }
            fn coriolis(&self, q: &[f64], qd: &[f64]) -> DVector<f64> {
                to_d($m::Robot::coriolis(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                ))
            }
            fn gravity(&self, q: &[f64]) -> DVector<f64> {
                to_d($m::Robot::gravity(self, &to_s::<$s, $nq>(q)))
            }
            fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64> {
                to_d($m::Robot::inverse_dynamics(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                ))
            }
            fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64]) -> DVector<f64> {
                to_d($m::Robot::forward_dynamics(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(tau),
                ))
            }
            fn kinetic_energy(&self, q: &[f64], qd: &[f64]) -> f64 {
                $m::Robot::kinetic_energy(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd)).to_f64()
            }
            fn potential_energy(&self, q: &[f64]) -> f64 {
                $m::Robot::potential_energy(self, &to_s::<$s, $nq>(q)).to_f64()
            }
            fn mass_matrix_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
                let m = $m::Robot::mass_matrix_dot(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd));
                DMatrix::from_fn($nv, $nv, |i, j| m[(i, j)] as f64)
            }
            fn jacobian_space_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
                let j = $m::Robot::jacobian_space_dot(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd));
                DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64)
            }
            fn jacobian_body_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
                let j = $m::Robot::jacobian_body_dot(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd));
                DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64)
            }
            fn end_effector_pose(&self, q: &[f64]) -> Matrix4<f64> {
                homogeneous(&$m::Robot::end_effector_pose(self, &to_s::<$s, $nq>(q)))
            }
            fn jacobian_space(&self, q: &[f64]) -> DMatrix<f64> {
                let j = $m::Robot::jacobian_space(self, &to_s::<$s, $nq>(q));
                DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64)
            }
            fn jacobian_body(&self, q: &[f64]) -> DMatrix<f64> {
                let j = $m::Robot::jacobian_body(self, &to_s::<$s, $nq>(q));
                DMatrix::from_fn(6, $nv, |r, c| j[(r, c)] as f64)
            }
            fn friction(&self, qd: &[f64]) -> DVector<f64> {
                to_d($m::Robot::friction(self, &to_s::<$s, $nv>(qd)))
            }
            fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
                let m = $m::Robot::coriolis_matrix(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd));
                DMatrix::from_fn($nv, $nv, |i, j| m[(i, j)] as f64)
            }
            fn mass_matrix_and_bias(&self, q: &[f64], qd: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
                let (m, h) =
                    $m::Robot::mass_matrix_and_bias(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd));
                (DMatrix::from_fn($nv, $nv, |i, j| m[(i, j)] as f64), to_d(h))
            }
            fn end_effector_forces(&self, q: &[f64], f_tip: &[f64]) -> DVector<f64> {
                to_d($m::Robot::end_effector_forces(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, 6>(f_tip),
                ))
            }
            fn inverse_dynamics_with_tip(
                &self,
                q: &[f64],
                qd: &[f64],
                qdd: &[f64],
                f_tip: &[f64],
            ) -> DVector<f64> {
                to_d($m::Robot::inverse_dynamics_with_tip(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(qdd),
                    &to_s::<$s, 6>(f_tip),
                ))
            }
            fn forward_dynamics_with_tip(
                &self,
                q: &[f64],
                qd: &[f64],
                tau: &[f64],
                f_tip: &[f64],
            ) -> DVector<f64> {
                to_d($m::Robot::forward_dynamics_with_tip(
                    self,
                    &to_s::<$s, $nq>(q),
                    &to_s::<$s, $nv>(qd),
                    &to_s::<$s, $nv>(tau),
                    &to_s::<$s, 6>(f_tip),
                ))
            }
            fn task_space_mass_matrix(&self, q: &[f64]) -> Option<DMatrix<f64>> {
                $m::Robot::task_space_mass_matrix(self, &to_s::<$s, $nq>(q))
                    .map(|l| DMatrix::from_fn(6, 6, |i, j| l[(i, j)] as f64))
            }
            fn task_space_bias(&self, q: &[f64], qd: &[f64]) -> Option<DVector<f64>> {
                $m::Robot::task_space_bias(self, &to_s::<$s, $nq>(q), &to_s::<$s, $nv>(qd))
                    .map(to_d)
            }
            fn constrained_forward_dynamics(
                &self,
                q: &[f64],
                qd: &[f64],
                tau: &[f64],
                a: &DMatrix<f64>,
                a_dot_qd: &[f64],
            ) -> Option<(DVector<f64>, DVector<f64>)> {
                fn call<const K: usize>(
                    r: &$m::Robot,
                    q: &[f64],
                    qd: &[f64],
                    tau: &[f64],
                    a: &DMatrix<f64>,
                    a_dot_qd: &[f64],
                ) -> Option<(DVector<f64>, DVector<f64>)> {
                    let a = nalgebra::SMatrix::<$s, K, $nv>::from_fn(|i, j| <$s>::from_f64(a[(i, j)]));
                    $m::Robot::constrained_forward_dynamics::<K>(
                        r,
                        &to_s::<$s, $nq>(q),
                        &to_s::<$s, $nv>(qd),
                        &to_s::<$s, $nv>(tau),
                        &a,
                        &to_s::<$s, K>(a_dot_qd),
                    )
                    .map(|(x, l)| (to_d(x), to_d(l)))
                }
                match a.nrows() {
                    1 => call::<1>(self, q, qd, tau, a, a_dot_qd),
                    2 => call::<2>(self, q, qd, tau, a, a_dot_qd),
                    3 => call::<3>(self, q, qd, tau, a, a_dot_qd),
                    k => panic!("constrained_forward_dynamics: K = {k} not instantiated"),
                }
            }
            $($frames)*
        }
    };
}

/// A scalar type of generated code.
pub trait Real: Copy + 'static {
    /// From f64 (rounded for f32).
    fn from_f64(x: f64) -> Self;
    /// To f64 (exact).
    fn to_f64(self) -> f64;
}

impl Real for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
}

impl Real for f32 {
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
}

fn to_s<T: Real + nalgebra::Scalar, const N: usize>(x: &[f64]) -> nalgebra::SVector<T, N> {
    nalgebra::SVector::<T, N>::from_fn(|i, _| T::from_f64(x[i]))
}

fn homogeneous<T: Real + nalgebra::RealField>(x: &nalgebra::Isometry3<T>) -> Matrix4<f64> {
    let m = x.to_homogeneous();
    Matrix4::from_fn(|i, j| m[(i, j)].to_f64())
}

fn to_d<T: Real + nalgebra::Scalar, const N: usize>(x: nalgebra::SVector<T, N>) -> DVector<f64> {
    DVector::from_fn(N, |i, _| x[i].to_f64())
}

fn to_dm<T: Real + nalgebra::Scalar, const R: usize, const C: usize>(
    x: &nalgebra::SMatrix<T, R, C>,
) -> DMatrix<f64> {
    DMatrix::from_fn(R, C, |i, j| x[(i, j)].to_f64())
}

/// The generated modules, [`CASES`] and [`DERIVATIVE_CASES`].
pub mod bench;

pub mod generated {
    #![allow(missing_docs)]
    use super::{homogeneous, to_d, to_dm, to_s, Real};
    use super::{Case, Spec};
    use nalgebra::{DMatrix, DVector, Matrix4};
    include!(concat!(env!("OUT_DIR"), "/cases.rs"));
}

pub use generated::{CASES, DERIVATIVE_CASES, REGRESSOR_CASES};

include!(concat!(env!("OUT_DIR"), "/with_cases.rs"));

/// The generated files' `joint_sin_cos` helper for each scalar type, `std` and `no_std`
/// (tests/trig.rs).
pub mod trig_kernels {
    #![allow(clippy::all)]
    include!(concat!(env!("OUT_DIR"), "/trig_kernels.rs"));
}

/// The values of `roots` of an expanded graph with the inputs `q`, `q̇`, `q̈` and `τ` (groups
/// `Q`, `QD`, `QDD`, `TAU`).
pub fn eval_graph(
    graph: &dynamics_gen::expr::ExprGraph,
    roots: &[dynamics_gen::expr::ExprId],
    state: [&[f64]; 4],
) -> Vec<f64> {
    use dynamics_gen::expand::{Q, QD, QDD, TAU};
    let [q, qd, qdd, tau] = state;
    graph.eval(roots, &|x: dynamics_gen::expr::Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => qd[i],
            QDD => qdd[i],
            TAU => tau[i],
            _ => f64::NAN,
        }
    })
}

/// `(‖x − y‖∞, ‖y‖∞)`.
pub fn max_error(x: &[f64], y: &[f64]) -> (f64, f64) {
    assert_eq!(x.len(), y.len(), "sizes differ");
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    (err, scale)
}

/// Asserts the acceptance criterion `‖x − y‖∞ ≤ rtol·‖y‖∞ + atol`, naming `what` on failure;
/// returns `(‖x − y‖∞, ‖y‖∞)`.
pub fn assert_close(what: &str, x: &[f64], y: &[f64], rtol: f64, atol: f64) -> (f64, f64) {
    let (err, scale) = max_error(x, y);
    assert!(
        err <= rtol * scale + atol,
        "{what}: error {err:e} > {rtol:e}·{scale:e} + {atol:e}\n got {x:?}\nwant {y:?}"
    );
    (err, scale)
}

/// A JSON array of numbers as a vector (the reference data files).
pub fn vecf(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Pinocchio's velocity index of our velocity index `k`. Pinocchio's free flyer orders the
/// base's linear part first (`v = (v_b, ω_b, θ̇)`, `τ = (f_b, m_b, τ_θ)`), ours the angular
/// part: with a floating base 0..3 ↔ 3..6, otherwise the same index.
pub fn pinocchio_index(k: usize, floating: bool) -> usize {
    match k {
        0..=2 if floating => k + 3,
        3..=5 if floating => k - 3,
        _ => k,
    }
}

/// A Pinocchio velocity-space vector (a JSON array) in our order ([`pinocchio_index`]).
pub fn from_pinocchio_order(v: &serde_json::Value, floating: bool) -> Vec<f64> {
    let x = vecf(v);
    (0..x.len())
        .map(|k| x[pinocchio_index(k, floating)])
        .collect()
}

/// A JSON matrix (a list of rows) as its entries, row-major.
pub fn rows(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().expect("rows").iter().flat_map(vecf).collect()
}

/// A matrix's entries, row-major.
pub fn row_major(m: &DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}
