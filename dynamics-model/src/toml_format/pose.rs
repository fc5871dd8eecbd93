//! Poses and fixed-size arrays of a TOML robot file.
//!
//! A pose `T = [[R, p], [0, 1]]` is written either as a 4×4 matrix (a list of four rows) or
//! as a table `{ xyz = [x, y, z], rpy = [roll, pitch, yaw] }` with
//! `R = Rz(yaw) Ry(pitch) Rx(roll)` (URDF's convention, [`crate::lie::xyz_rpy`]); a missing
//! `xyz` or `rpy` is zero.

use super::schema::PoseSpec;
use crate::error::{Invalid, Subject};
use crate::lie::xyz_rpy;
use nalgebra::{Matrix4, Vector3};

/// Reads the pose in `value` (field `field` of `subject`).
pub(crate) fn pose(
    subject: &Subject,
    field: &str,
    value: &toml::Value,
) -> Result<Matrix4<f64>, Invalid> {
    const FIX: &str = "write the pose as `{ xyz = [x, y, z], rpy = [roll, pitch, yaw] }` or as a 4×4 matrix `[[r11, r12, r13, x], [r21, r22, r23, y], [r31, r32, r33, z], [0, 0, 0, 1]]`";
    match value {
        toml::Value::Array(rows) => {
            if rows.len() != 4 {
                return Err(Invalid::new(
                    subject.clone(),
                    field,
                    format!("a 4×4 matrix needs 4 rows, found {}", rows.len()),
                    FIX,
                ));
            }
            let mut t = Matrix4::zeros();
            for (i, row) in rows.iter().enumerate() {
                let row = match row {
                    toml::Value::Array(r) if r.len() == 4 => r,
                    toml::Value::Array(r) => {
                        return Err(Invalid::new(
                            subject.clone(),
                            field,
                            format!(
                                "row {} of the 4×4 matrix has {} numbers, expected 4",
                                i + 1,
                                r.len()
                            ),
                            FIX,
                        ))
                    }
                    _ => {
                        return Err(Invalid::new(
                            subject.clone(),
                            field,
                            format!("row {} of the 4×4 matrix is not a list of numbers", i + 1),
                            FIX,
                        ))
                    }
                };
                for (j, x) in row.iter().enumerate() {
                    t[(i, j)] = number(x).ok_or_else(|| {
                        Invalid::new(
                            subject.clone(),
                            field,
                            format!(
                                "entry ({}, {}) of the 4×4 matrix is not a number",
                                i + 1,
                                j + 1
                            ),
                            FIX,
                        )
                    })?;
                }
            }
            Ok(t)
        }
        toml::Value::Table(_) => {
            let spec: PoseSpec = value.clone().try_into().map_err(|e: toml::de::Error| {
                Invalid::new(subject.clone(), field, e.message().trim().to_string(), FIX)
            })?;
            let xyz = match &spec.xyz {
                Some(v) => array::<3>(subject, &format!("{field}.xyz"), v)?,
                None => [0.0; 3],
            };
            let rpy = match &spec.rpy {
                Some(v) => array::<3>(subject, &format!("{field}.rpy"), v)?,
                None => [0.0; 3],
            };
            Ok(xyz_rpy(xyz, rpy))
        }
        _ => Err(Invalid::new(
            subject.clone(),
            field,
            format!("expected a pose, found a {}", value.type_str()),
            FIX,
        )),
    }
}

/// A TOML integer or float as `f64`.
fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// `v` as an array of exactly `N` numbers.
pub(crate) fn array<const N: usize>(
    subject: &Subject,
    field: &str,
    v: &[f64],
) -> Result<[f64; N], Invalid> {
    <[f64; N]>::try_from(v).map_err(|_| {
        Invalid::new(
            subject.clone(),
            field,
            format!("expected {N} numbers, found {}", v.len()),
            format!("give exactly {N} numbers: {}", layout(field, N)),
        )
    })
}

/// `v` as a 3-vector.
pub(crate) fn vector3(subject: &Subject, field: &str, v: &[f64]) -> Result<Vector3<f64>, Invalid> {
    array::<3>(subject, field, v).map(Vector3::from)
}

/// What the numbers of an array field mean, for messages.
fn layout(field: &str, n: usize) -> &'static str {
    let last = field.rsplit('.').next().unwrap_or(field);
    match (last, n) {
        ("screw", 6) => "[ωx, ωy, ωz, vx, vy, vz]",
        ("inertia", 6) => "[ixx, iyy, izz, ixy, ixz, iyz]",
        ("limits", 2) => "[lower, upper]",
        ("rpy", 3) => "[roll, pitch, yaw] in rad",
        ("xyz", 3) | ("com", 3) | ("point", 3) => "[x, y, z] in m",
        ("axis", 3) => "the direction [x, y, z]",
        ("gravity", 3) => "[gx, gy, gz] in m/s²",
        ("box", 3) => "[w, l, h]: edge lengths along x, y, z",
        ("cylinder", 2) => "[r, h]: radius, height along z",
        ("ellipsoid", 3) => "[a, b, c]: semi-axes along x, y, z",
        ("plate", 2) => "[w, l]: edge lengths along x, y",
        _ => "see the format's documentation",
    }
}
