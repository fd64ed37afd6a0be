//! Meshes of the crate's embedded assets (`assets/`, see `assets/README.md` for their sources,
//! licences and conversion), shared by the scenes that use them (every scene file may use
//! them; they use no scene file).

use crate::{Mesh, SceneError};

/// The bunny asset: one object whose mesh has height 1 and its base at y = 0.
#[cfg(feature = "gltf")]
const BUNNY_GLB: &[u8] = include_bytes!("../../assets/bunny.glb");

/// The Stanford bunny of `assets/bunny.glb` (3674 triangles, height 1, base at y = 0, centred
/// on x = z = 0), read with the glTF importer: without the `gltf` feature, an error naming it.
#[cfg(not(feature = "gltf"))]
pub fn bunny_mesh() -> Result<Mesh, SceneError> {
    Err(SceneError::Gltf(
        "assets/bunny.glb".into(),
        "this build of the scene crate has no glTF importer (enable its `gltf` feature)".into(),
    ))
}

/// The Stanford bunny of `assets/bunny.glb` (3674 triangles, height 1, base at y = 0, centred
/// on x = z = 0), read with the glTF importer.
#[cfg(feature = "gltf")]
pub fn bunny_mesh() -> Result<Mesh, SceneError> {
    let asset = crate::gltf_io::import_slice(BUNNY_GLB, "assets/bunny.glb")?;
    Ok(asset
        .objects
        .into_iter()
        .next()
        .ok_or_else(|| SceneError::Invalid("assets/bunny.glb holds no mesh".into()))?
        .mesh)
}
