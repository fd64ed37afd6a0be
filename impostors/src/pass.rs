//! A distance impostor as one pass of a renderer's own frame: one glass or metal object,
//! reflecting and refracting the renderer's world through its environment impostor (paper
//! sections 3-4), drawn over the renderer's colour and depth targets in their formats.
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - the object: its mesh (`gpu::HostedMesh`: positions, normals, triangle indices, in the
//!   object's frame), its material ([`Surface`]) and its index among the renderer's objects
//!   ([`SpecularObject`]); where it stands each frame (`set_position`);
//! - its world drawn on request, [`gpu::DrawScene`]: everything but the object, from the
//!   object's centre, into the faces of the impostor (`Rgba16Float`, radiance in rgb and the
//!   distance from the centre in alpha; depth `Depth32Float`), six views each frame;
//! - its colour and depth targets (any renderable colour format, any depth format), holding
//!   its frame already (the pass writes rgb and depth; the renderer's alpha is kept), and its
//!   camera ([`gpu::EyeView`]).
//!
//! The pass is the technique's own code: `Impostor::draw_over` runs the steps the harness's
//! `impostors/false-position-4` and `impostors/double-refraction` run in their frames (the
//! impostors drawn through `gpu::DrawScene`, the lookup), with `scene::GpuScene` as the host
//! there.

use crate::technique::{Impostor, Mode, Settings};
use glam::Vec3;
use gpu::{HostedMesh, TargetFormats};
pub use scene::hosted::Surface;
use scene::hosted::{HostedPass, HostedPiece};
use scene::{Technique as _, TechniqueResult};

/// The renderer's specular object.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecularObject {
    /// Its triangles in its own frame (the impostor is taken from the centre of their bounds,
    /// moved by [`ImpostorPass::set_position`]).
    pub mesh: HostedMesh,
    /// Its material.
    pub surface: Surface,
    /// Its index among the renderer's objects: the one its [`gpu::DrawScene`] leaves out of
    /// the impostor.
    pub host_index: usize,
}

/// How rays leave the object.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImpostorLookup {
    /// Reflection and refraction at the visible surface, each localized by `Hit()` in the
    /// environment impostor (false position, 4 iterations: `impostors/false-position-4`).
    Localized,
    /// Glass: the refracted ray searched to its exit in the object's own refractor map,
    /// refracted out, then `Hit()` in the impostor (`impostors/double-refraction`).
    DoubleRefraction,
}

/// The distance-impostor pass of one object, made for a renderer's target formats: a
/// [`HostedPass`] (its `draw`) of the [`Impostor`] technique, placed by `set_position`.
pub struct ImpostorPass(HostedPass<Impostor>);

impl ImpostorPass {
    /// The pass of `object` for targets of `formats`, with impostors of `resolution` texels
    /// a side: prepares the maps (the refractor map of double refraction is drawn now). The
    /// impostor is asked of the renderer every frame (the default `regen_threshold` of 0).
    pub fn new(
        ctx: &gpu::Context,
        object: &SpecularObject,
        lookup: ImpostorLookup,
        formats: TargetFormats,
        resolution: u32,
    ) -> TechniqueResult<Self> {
        let (id, mode) = match lookup {
            ImpostorLookup::Localized => ("impostors/false-position-4", Mode::Localized),
            ImpostorLookup::DoubleRefraction => {
                ("impostors/double-refraction", Mode::DoubleRefraction)
            }
        };
        let settings = Settings {
            mode,
            ..Settings::default()
        };
        let mut technique =
            Impostor::new(id, "distance impostor pass", settings).for_targets(formats);
        technique.set_param("resolution", resolution as f64)?;
        let material = object.surface.into();
        let object = HostedPiece {
            mesh: &object.mesh,
            material,
            host_index: object.host_index,
            position: Vec3::ZERO,
        };
        HostedPass::new(ctx, formats, &[object], technique).map(Self)
    }
}

impl ImpostorPass {
    /// Moves the object by `offset` from where its mesh puts it, from the next frame on.
    pub fn set_position(&mut self, offset: Vec3) {
        self.0.set_position_of(0, offset);
    }
}

scene::hosted_pass_deref!(ImpostorPass, Impostor);
