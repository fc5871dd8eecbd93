//! The keys of the `robot!` grammar: which key goes where and what value it takes. The
//! vocabulary is the TOML format's ([`dynamics_model::toml_format`]), key for key.

/// What a key's value must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    /// One number.
    Num,
    /// A list of numbers.
    Nums,
    /// A list of rows of numbers.
    Matrix,
    /// A pose: a 4×4 matrix or `{ xyz: [..], rpy: [..] }`.
    Pose,
    /// `{ box: [w, l, h] }`, `{ cylinder: [r, h] }`, `{ sphere: r }`, …
    Shape,
    /// `com` or `origin`.
    About,
    /// A name or string.
    Name,
    /// `{ joint: LEADER, multiplier: m, offset: o }`.
    Mimic,
    /// Named parameters: `{ m1: 2.0, L1: 1.0 }`.
    Params,
}

impl Type {
    /// How to write a value of this type, for messages.
    pub fn example(self) -> &'static str {
        match self {
            Type::Num => "a number (or a string expression over the `parameters`, `\"L1/2\"`)",
            Type::Nums => "a list of numbers `[a, b, …]` (entries may be string expressions over the `parameters`)",
            Type::Matrix => "a matrix `[[…], …]` (rows)",
            Type::Pose => "a pose: `{ xyz: [x, y, z], rpy: [roll, pitch, yaw] }` or a 4×4 matrix `[[r11, r12, r13, x], …, [0, 0, 0, 1]]`",
            Type::Shape => "a shape: `{ box: [w, l, h] }`, `{ cylinder: [r, h] }`, `{ sphere: r }`, `{ ellipsoid: [a, b, c] }`, `{ plate: [w, l] }` or `{ disc: r }`",
            Type::About => "`com` or `origin`",
            Type::Name => "a name or a string",
            Type::Mimic => "a mimic: `{ joint: LEADER, multiplier: m, offset: o }` (multiplier and offset optional)",
            Type::Params => "named parameters: `{ m1: 2.0, L1: 1.0 }` (used as string expressions where numbers go: `mass: \"m1\"`)",
        }
    }
}

/// Top-level keys (besides `joint` and `end_effector` blocks).
pub const ROBOT_KEYS: &[(&str, Type)] = &[
    ("name", Type::Name),
    ("description", Type::Name),
    ("gravity", Type::Nums),
    ("parameters", Type::Params),
    // Not TOML keys but generation options: how the dynamics are derived (`newton_euler` or
    // `lagrangian`), run-time gravity and payload (`true`), the payload's link, run-time CPU
    // dispatch (`false` turns it off), the `*_from_sin_cos` variants (`true`).
    ("method", Type::Name),
    ("runtime_parameters", Type::Name),
    ("payload_link", Type::Name),
    ("cpu_dispatch", Type::Name),
    ("sin_cos_variants", Type::Name),
];

/// Keys of a joint (the `[[joint]]` table).
pub const JOINT_KEYS: &[(&str, Type)] = &[
    ("screw", Type::Nums),
    ("axis", Type::Nums),
    ("point", Type::Nums),
    ("limits", Type::Nums),
    ("velocity_limit", Type::Num),
    ("effort_limit", Type::Num),
    ("damping", Type::Num),
    ("friction", Type::Num),
    ("rotor_inertia", Type::Num),
    ("gear_ratio", Type::Num),
    ("mimic", Type::Mimic),
];

/// Inertial keys of a link or of one of its bodies.
pub const BODY_KEYS: &[(&str, Type)] = &[
    ("frame", Type::Pose),
    ("mass", Type::Num),
    ("density", Type::Num),
    ("shape", Type::Shape),
    ("com", Type::Nums),
    ("inertia", Type::Nums),
    ("inertia_about", Type::About),
    ("spatial_inertia", Type::Matrix),
];

/// `home` of a link, and of the end effector.
pub const HOME: (&str, Type) = ("home", Type::Pose);

/// Shapes and whether they take a list (`true`) or one number.
pub const SHAPES: &[(&str, bool)] = &[
    ("box", true),
    ("cylinder", true),
    ("sphere", false),
    ("ellipsoid", true),
    ("plate", true),
    ("disc", false),
];

/// The type of `key` among `keys`.
pub fn lookup(keys: &[(&str, Type)], key: &str) -> Option<Type> {
    keys.iter().find(|(k, _)| *k == key).map(|(_, t)| *t)
}

/// The names of `keys`, for messages.
pub fn names(keys: &[(&str, Type)]) -> String {
    keys.iter()
        .map(|(k, _)| format!("`{k}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
