//! The WGSL sources of the passes, and the LDI bindings they share.

use super::*;

/// The LDI functions (the twin of [`crate::march`]).
pub const LDI_WGSL: &str = include_str!("../shaders/ldi.wgsl");
/// Photon and receiver structs shared by the photon passes.
pub const PHOTON_WGSL: &str = include_str!("../shaders/photon.wgsl");
/// The splat kernel and weights (also run by the conformance test).
pub const SPLAT_WGSL: &str = include_str!("../shaders/splat.wgsl");
pub(super) const TRANSFER_WGSL: &str = include_str!("../shaders/transfer.wgsl");
pub(super) const GATHER_WGSL: &str = include_str!("../shaders/gather.wgsl");
pub(super) const LINES_WGSL: &str = include_str!("../shaders/lines.wgsl");
pub(super) const REDUCE_WGSL: &str = include_str!("../shaders/reduce.wgsl");
pub(super) const DDA_WGSL: &str = include_str!("../shaders/dda.wgsl");
pub(super) const RESOLVE_WGSL: &str = include_str!("../shaders/resolve.wgsl");
pub(super) const APPLY_WGSL: &str = include_str!("../shaders/apply.wgsl");
pub(super) const SPECULAR_WGSL: &str = include_str!("../shaders/specular.wgsl");
pub(super) const SHADOW_MASK_WGSL: &str = include_str!("../shaders/shadow_mask.wgsl");
pub(super) const SHADOWED_WGSL: &str = include_str!("../shaders/shadowed.wgsl");
/// A photon beam on the image: the twin of [`crate::shafts`]'s `beam_band` and
/// `beam_fragment` (pure functions; run by the conformance test).
pub const BEAM_WGSL: &str = include_str!("../shaders/beam.wgsl");
/// God-ray bands and their blur (after [`BEAM_WGSL`]).
pub(super) const SHAFTS_WGSL: &str = include_str!("../shaders/shafts.wgsl");
/// The froxel grid (the twin of [`crate::shafts`]'s slices and integration).
pub const FROXELS_WGSL: &str = include_str!("../shaders/froxels.wgsl");
pub(super) const COMPOSITE_WGSL: &str = include_str!("../shaders/composite.wgsl");

/// The LDI bindings of the technique's passes (`@group(2)`), and the material kind ldi.wgsl
/// asks for, from the scene's materials (0 diffuse, 1 metal, 2 glass: `MATERIAL_*`).
pub const LDI_BINDINGS_WGSL: &str = r#"
#import scene::shading::objects
@group(2) @binding(0) var<uniform> ldi: LdiParams;
@group(2) @binding(1) var ldi_layers: texture_2d_array<f32>;
@group(2) @binding(2) var ldi_surfaces: texture_2d_array<f32>;
@group(2) @binding(3) var refractor_layers: texture_2d_array<f32>;
@group(2) @binding(4) var refractor_surfaces: texture_2d_array<f32>;

fn ldi_kind(object: u32) -> u32 {
    return u32(objects[object].material.x);
}
"#;

/// Photon buffers, line rows and transfer maps: 32-bit float (the irradiance buffer adds
/// many photons per pixel).
pub(super) const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
