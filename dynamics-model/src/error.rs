//! Errors of the model: reading, parsing and validating a robot.
//!
//! Every message names the file (when there is one), the link or joint, the field, what is
//! wrong and how to fix it.

use std::fmt;

/// What part of a robot a validation error is about.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Subject {
    /// The robot as a whole (gravity, sizes of the lists, the chain's structure).
    Robot,
    /// A joint: its position in the chain (0-based, when known) and its name.
    Joint {
        /// 0-based index among the movable joints, when the joint is one of them.
        index: Option<usize>,
        /// The joint's name.
        name: String,
    },
    /// A link (body): its position in the chain (0-based, when known) and its name.
    Link {
        /// 0-based index among the moving links, when the link is one of them.
        index: Option<usize>,
        /// The link's name.
        name: String,
    },
    /// The end-effector frame {n+1}.
    EndEffector,
    /// A named frame ([`crate::Robot::frames`]).
    Frame(String),
}

impl fmt::Display for Subject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Subject::Robot => write!(f, "robot"),
            Subject::Joint { name, .. } => write!(f, "joint `{name}`"),
            Subject::Link { name, .. } => write!(f, "link `{name}`"),
            Subject::EndEffector => write!(f, "end effector"),
            Subject::Frame(name) => write!(f, "frame `{name}`"),
        }
    }
}

/// One thing wrong with a robot description.
#[derive(Clone, Debug, PartialEq)]
pub struct Invalid {
    /// The file the robot came from, if any.
    pub file: Option<String>,
    /// The link, joint or part of the robot that is wrong.
    pub subject: Subject,
    /// The field (e.g. `inertia`, `screw`, `origin.rpy`).
    pub field: String,
    /// What is wrong, with the numbers.
    pub problem: String,
    /// How to fix it.
    pub fix: String,
}

impl Invalid {
    /// A new error about `subject`'s `field`.
    pub fn new(
        subject: Subject,
        field: impl Into<String>,
        problem: impl Into<String>,
        fix: impl Into<String>,
    ) -> Self {
        Self {
            file: None,
            subject,
            field: field.into(),
            problem: problem.into(),
            fix: fix.into(),
        }
    }

    /// The same error, attributed to `file`.
    pub fn in_file(mut self, file: impl Into<String>) -> Self {
        self.file = Some(file.into());
        self
    }
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{file}: ")?;
        }
        write!(
            f,
            "{}: field `{}`: {}",
            self.subject, self.field, self.problem
        )?;
        if !self.fix.is_empty() {
            write!(f, "; fix: {}", self.fix)?;
        }
        Ok(())
    }
}

/// Anything that can go wrong turning a description into a valid [`crate::Robot`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The file could not be read.
    #[error("{file}: cannot read the robot file: {message}")]
    Io {
        /// The path as given (resolved, when it was relative).
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The file is not well-formed TOML or XML, or does not follow the schema.
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// 1-based line (0 when unknown).
        line: usize,
        /// 1-based column (0 when unknown).
        column: usize,
        /// What the parser said.
        message: String,
    },
    /// The description parses but describes an invalid or unsupported robot.
    #[error("{}", join(.0))]
    Invalid(Vec<Invalid>),
    /// A loader option that does not apply to this file or has an invalid value.
    #[error("{file}: {message}")]
    BadOption {
        /// The file.
        file: String,
        /// What is wrong, and the fix.
        message: String,
    },
    /// A robot name that is neither a file nor a shipped robot.
    #[error("unknown robot `{name}`: not a file, and not a shipped robot (shipped: {})", .known.join(", "))]
    UnknownRobot {
        /// What was asked for.
        name: String,
        /// The shipped robots' names.
        known: Vec<String>,
    },
}

impl ModelError {
    /// A single validation error.
    pub fn invalid(e: Invalid) -> Self {
        ModelError::Invalid(vec![e])
    }

    /// The validation errors, if this is [`ModelError::Invalid`].
    pub fn errors(&self) -> &[Invalid] {
        match self {
            ModelError::Invalid(v) => v,
            _ => &[],
        }
    }

    /// Attributes every validation error that has no file yet to `file`.
    pub fn in_file(self, file: &str) -> Self {
        match self {
            ModelError::Invalid(v) => ModelError::Invalid(
                v.into_iter()
                    .map(|e| if e.file.is_none() { e.in_file(file) } else { e })
                    .collect(),
            ),
            other => other,
        }
    }
}

fn join(v: &[Invalid]) -> String {
    v.iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}
