//! The localized lookups' WGSL (sections 3 and 4): the module `impostors::localized`, which the
//! technique's pass and the caustic variants' passes import, and its entry points.

/// Localized environment mapping (sections 3 and 4): the module `impostors::localized`
/// ([`LOCALIZED`]); its lookups' caustics are a virtual function the caustic variants override.
pub const LOCALIZED_WGSL: &str = include_str!("shaders/localized.wgsl");
/// [`LOCALIZED_WGSL`] as a module.
pub static LOCALIZED: gpu::wgsl::Module = gpu::wgsl::Module::new(
    LOCALIZED_WGSL,
    "impostors/src/shaders/localized.wgsl",
    &[&scene::SHADING],
);
/// The localized pass's entry points (`localized_fs`, `refractor_map_fs`).
pub(crate) const LOCALIZED_FS_WGSL: &str = include_str!("shaders/localized_fs.wgsl");
