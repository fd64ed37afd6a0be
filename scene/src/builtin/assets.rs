//! Meshes of the crate's embedded assets (`assets/`, see `assets/README.md` for their sources,
//! licences and conversion), shared by the scenes that use them (every scene file may use
//! them; they use no scene file).

use crate::{Mesh, SceneError};

/// The bunny asset: one object whose mesh has height 1 and its base at y = 0.
const BUNNY_GLB: &[u8] = include_bytes!("../../assets/bunny.glb");

/// The Stanford bunny of `assets/bunny.glb` (3674 triangles, height 1, base at y = 0, centred
/// on x = z = 0), read with the glTF importer.
pub fn bunny_mesh() -> Result<Mesh, SceneError> {
    let asset = crate::gltf_io::import_slice(BUNNY_GLB, "assets/bunny.glb")?;
    Ok(asset
        .objects
        .into_iter()
        .next()
        .ok_or_else(|| SceneError::Invalid("assets/bunny.glb holds no mesh".into()))?
        .mesh)
}
