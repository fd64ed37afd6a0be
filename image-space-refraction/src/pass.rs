//! Image-space refraction as one pass of a renderer's own frame: one glass object, its front
//! and back surfaces rasterized from the eye and the refracted rays followed through both
//! interfaces (Wyman's two-interface method, or Hu and Qin's section 2.1 search) to the
//! renderer's world around it, drawn over the renderer's colour and depth targets in their
//! formats.
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - the refractor: its mesh (`gpu::HostedMesh`, in the object's frame), its index of
//!   refraction and its index among the renderer's objects ([`Refractor`]); where it stands
//!   each frame (`set_position`);
//! - its world drawn on request, [`gpu::DrawScene`]: everything but the refractor, from the
//!   refractor's centre, into the six faces of its environment map (`Rgba16Float`, radiance in
//!   rgb and the distance from the centre in alpha; depth `Depth32Float`), each frame;
//! - its colour and depth targets (any renderable colour format, any depth format), holding
//!   its frame already (the pass writes rgb and depth; the renderer's alpha is kept), and its
//!   camera ([`gpu::EyeView`]).
//!
//! The pass is the technique's own code: `Refraction::draw_over` runs the steps the harness's
//! `image-space-refraction/two-interface-baseline` and `hu-qin` run in their frames (the
//! environment maps drawn through `gpu::DrawScene`, the front and back buffers, the
//! refraction), with `scene::GpuScene` as the host there.

use crate::technique::{Refraction, variant};
use gpu::{HostedMesh, TargetFormats};
use scene::hosted::{HostedPass, HostedPiece};
use scene::{Technique as _, TechniqueResult};

/// The renderer's glass object.
#[derive(Clone, Debug, PartialEq)]
pub struct Refractor {
    /// Its triangles in its own frame: a closed surface, normals outward.
    pub mesh: HostedMesh,
    /// Its index of refraction relative to the surrounding air.
    pub ior: f32,
    /// Its index among the renderer's objects: the one its [`gpu::DrawScene`] leaves out of
    /// the environment map.
    pub host_index: usize,
}

/// Where the refracted ray leaves the object.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// Wyman 2005: along the refracted ray by a thickness interpolated between the view
    /// ray's and the precomputed one along the normal (`two-interface-baseline`).
    Wyman,
    /// Hu and Qin 2006, section 2.1: the back or front buffer searched iteratively
    /// (`hu-qin`).
    HuQin,
}

/// The image-space refraction pass of one glass object, made for a renderer's formats: a
/// [`HostedPass`] (its `draw`) of the [`Refraction`] technique, placed by `set_position`.
pub struct RefractorPass(HostedPass<Refraction>);

impl RefractorPass {
    /// The pass of `refractor` for targets of `formats`, its environment map `resolution`
    /// texels a side, asked of the renderer every frame.
    pub fn new(
        ctx: &gpu::Context,
        refractor: &Refractor,
        exit: Exit,
        formats: TargetFormats,
        resolution: u32,
    ) -> TechniqueResult<Self> {
        let name = match exit {
            Exit::Wyman => "two-interface-baseline",
            Exit::HuQin => "hu-qin",
        };
        let mut technique = variant(name)
            .expect("the crate configures both variants")
            .for_targets(formats);
        technique.set_param("resolution", resolution as f64)?;
        let glass = scene::Material::Glass { ior: refractor.ior };
        let object = HostedPiece {
            mesh: &refractor.mesh,
            material: glass,
            host_index: refractor.host_index,
            position: glam::Vec3::ZERO,
        };
        HostedPass::new(ctx, formats, &[object], technique).map(Self)
    }
}

impl RefractorPass {
    /// Moves the object by `offset` from where its mesh puts it, from the next frame on.
    pub fn set_position(&mut self, offset: glam::Vec3) {
        self.0.set_position_of(0, offset);
    }
}

scene::hosted_pass_deref!(RefractorPass, Refraction);
