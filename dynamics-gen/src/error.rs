//! Errors of the generator.

use dynamics_model::ModelError;

/// Anything that can go wrong generating code.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The robot description could not be read, parsed or validated.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The struct name is not a Rust identifier in UpperCamelCase.
    #[error("`{name}` is not a valid struct name: {hint} (--name / .name())")]
    InvalidName {
        /// The name given.
        name: String,
        /// What is wrong and the fix.
        hint: String,
    },
    /// The nalgebra or dynamics-runtime path is not a Rust path.
    #[error(
        "`{path}` is not a valid Rust path for a crate (nalgebra, dynamics-runtime); give one like `::nalgebra` or `crate::na`"
    )]
    InvalidPath {
        /// The path given.
        path: String,
    },
    /// A `functions` selection that cannot be generated.
    #[error("functions: {problem}; fix: {fix} (--functions / .functions() / functions(..))")]
    InvalidFunctions {
        /// What is wrong.
        problem: String,
        /// The fix.
        fix: String,
    },
    /// A friction smoothing ε that is not a positive finite velocity.
    #[error("friction smoothing ε = {eps} is not a velocity > 0; fix: give ε in rad/s or m/s, like 0.01 (--friction-smoothing / .friction_smoothing() / friction_smoothing = ..)")]
    InvalidFrictionSmoothing {
        /// The value given.
        eps: f64,
    },
    /// Run-time parameters that cannot be generated as asked.
    #[error("runtime parameters of robot `{robot}`: {problem}; fix: {fix} (--runtime-parameters / --payload-link, .runtime_parameters() / .payload_link(), runtime_parameters / payload_link = ..)")]
    InvalidRuntimeParameters {
        /// The robot's name.
        robot: String,
        /// What is wrong.
        problem: String,
        /// The fix.
        fix: String,
    },
    /// The robot has no movable joint.
    #[error("robot `{robot}` has no movable joint: there are no dynamics to generate")]
    NoJoints {
        /// The robot's name.
        robot: String,
    },
    /// Writing the generated file failed.
    #[error("{path}: cannot write the generated file: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// `equations` cannot print this robot's dynamics in closed form.
    #[error("equations of robot `{robot}`: {problem}; {fix}")]
    Equations {
        /// The robot's name.
        robot: String,
        /// What stands in the way.
        problem: String,
        /// The fix.
        fix: String,
    },
    /// A bug in the generator.
    #[error("internal error in dynamics-gen (please report): {0}")]
    Internal(String),
}
