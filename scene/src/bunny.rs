//! The `refraction-bunny` scene. (Being written.)
use crate::{Scene, SceneError};
pub(crate) fn refraction_bunny(_ior: f32) -> Result<Scene, SceneError> {
    Err(SceneError::Invalid("refraction-bunny is not built yet".into()))
}
