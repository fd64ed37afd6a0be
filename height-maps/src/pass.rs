//! Refractor height maps as one pass of a renderer's own frame: glass pieces, each
//! stood on a billboard turning to face the eye and searched in its height map (section 6),
//! drawn over the renderer's colour and depth targets in their formats.
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - the pieces ([`HeightPiece`]): each one's mesh (`gpu::HostedMesh`, in the piece's frame,
//!   its y axis up: the billboard turns about the vertical), its index of refraction and its
//!   index among the renderer's objects, and where it stands (`set_position_of` moves it;
//!   the renderer does not draw it); pieces with the same mesh share one height map;
//! - its world drawn on request, [`gpu::DrawScene`]: everything but the pieces, from the
//!   centre of the pieces' bounds, into the six faces of the environment impostor
//!   (`Rgba16Float`, radiance in rgb and the distance from the centre in alpha; depth
//!   `Depth32Float`), each frame;
//! - its colour and depth targets (any renderable colour format, any depth format), holding
//!   its frame already (the pass writes rgb and depth; the renderer's alpha is kept), and its
//!   camera ([`gpu::EyeView`]).
//!
//! The pass is the technique's own code: `HeightMaps::draw_over` runs the steps the harness's
//! `height-maps/single` and `height-maps/double-refraction` run in their frames (the
//! environment impostor drawn through `gpu::DrawScene`, the billboards), with
//! `scene::GpuScene` as the host there.

use crate::technique::{HeightMaps, Refraction, Settings};
use glam::Vec3;
use gpu::{HostedMesh, TargetFormats};
use scene::hosted::{HostedPass, HostedPiece};
use scene::{Technique as _, TechniqueResult};

/// One of the renderer's glass pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightPiece {
    /// Its triangles in its own frame, y up, with a plane of symmetry through the y axis (a
    /// lathed or mirrored piece: the height map holds the half in front of that plane).
    pub mesh: HostedMesh,
    /// Its index of refraction relative to the surrounding air.
    pub ior: f32,
    /// Its index among the renderer's objects: the one its [`gpu::DrawScene`] leaves out of
    /// the environment impostor.
    pub host_index: usize,
    /// Where it stands: the offset from where its mesh puts it.
    pub position: Vec3,
}

/// The height-map pass of some glass pieces, made for a renderer's formats: a [`HostedPass`]
/// (its `set_position_of` and `draw`) of the [`HeightMaps`] technique.
pub struct HeightMapPass(HostedPass<HeightMaps>);

impl HeightMapPass {
    /// The pass of `pieces` for targets of `formats`, with `refraction` after the first
    /// surface, height maps of `resolution` texels a side (one per mesh) and an environment
    /// impostor of `env_resolution`, asked of the renderer every frame.
    pub fn new(
        ctx: &gpu::Context,
        pieces: &[HeightPiece],
        refraction: Refraction,
        formats: TargetFormats,
        (resolution, env_resolution): (u32, u32),
    ) -> TechniqueResult<Self> {
        // The settings of the crate's variants `single` and `double-refraction`.
        let name = match refraction {
            Refraction::Single => "height-maps/single",
            Refraction::Double => "height-maps/double-refraction",
        };
        let settings = Settings {
            refraction,
            ..Settings::default()
        };
        let mut technique =
            HeightMaps::new(name, "height-map pass", true, settings).for_targets(formats);
        technique.set_param("resolution", resolution as f64)?;
        technique.set_param("env_resolution", env_resolution as f64)?;
        let hosted: Vec<HostedPiece> = pieces
            .iter()
            .map(|p| HostedPiece {
                mesh: &p.mesh,
                material: scene::Material::Glass { ior: p.ior },
                host_index: p.host_index,
                position: p.position,
            })
            .collect();
        HostedPass::new(ctx, formats, &hosted, technique).map(Self)
    }
}

scene::hosted_pass_deref!(HeightMapPass, HeightMaps);
