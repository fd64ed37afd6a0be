//! glTF 2.0 import and .glb export. (Being written.)
use crate::{Scene, SceneError};
use std::path::Path;
pub fn import(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::Gltf(path.display().to_string(), "not yet".into()))
}
