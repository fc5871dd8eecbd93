//! The URDF loader (being written).

use crate::error::ModelError;
use crate::load::LoadOptions;
use crate::robot::Robot;

/// Parses a URDF file; `file` names it in errors.
pub fn from_str(_text: &str, file: &str, _options: &LoadOptions) -> Result<Robot, ModelError> {
    Err(ModelError::Io {
        file: file.into(),
        message: "the URDF loader is not written yet".into(),
    })
}
