//! The WGSL sources of the passes, and the photon structs' module they share.

use super::*;

/// Photon and receiver structs shared by the photon passes: the module
/// `screen_photons::photon` ([`PHOTON`]).
pub const PHOTON_WGSL: &str = include_str!("../shaders/photon.wgsl");
/// [`PHOTON_WGSL`] as a module (no bindings; its helpers read the LDI).
pub static PHOTON: gpu::wgsl::Module = gpu::wgsl::Module::new(
    PHOTON_WGSL,
    "screen-photons/src/shaders/photon.wgsl",
    &[&crate::march::LDI],
);
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
/// God-ray bands and their blur (importing `screen_photons::beam`, [`crate::shafts::BEAM`]).
pub(super) const SHAFTS_WGSL: &str = include_str!("../shaders/shafts.wgsl");
/// The froxel grid (the twin of [`crate::shafts`]'s slices and integration).
pub const FROXELS_WGSL: &str = include_str!("../shaders/froxels.wgsl");
pub(super) const COMPOSITE_WGSL: &str = include_str!("../shaders/composite.wgsl");

/// Photon buffers, line rows and transfer maps: 32-bit float (the irradiance buffer adds
/// many photons per pixel).
pub(super) const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
