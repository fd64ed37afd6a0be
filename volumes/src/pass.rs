//! Soft volumes as one pass of a renderer's own frame: ray-traced spheres (thesis 6.3.3)
//! blended over the renderer's colour target and clipped by its depth buffer, which the pass
//! samples (the "depth that already exists for other reasons": the `free_depth` variant).
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - its colour target, of any blendable format (`Rgba8Unorm`, `Rgba8UnormSrgb`,
//!   `Bgra8Unorm(Srgb)`, `Rgba16Float`, …; `Rgba32Float` where the device has
//!   `FLOAT32_BLENDABLE`), with `RENDER_ATTACHMENT`;
//! - its depth buffer after its opaque geometry, of a depth format the pass can sample
//!   (`Depth32Float`, `Depth24Plus`, `Depth16Unorm`, …) with `TEXTURE_BINDING`: conventional
//!   depth in [0, 1], cleared to 1 (not reversed z), not multisampled;
//! - its camera: the view and projection matrices (`gpu::EyeView`);
//! - the volumes ([`SoftVolume`]) and a `CommandEncoder` to record into.
//!
//! The harness's ray-traced sphere variants with `free_depth` (`volumes/raytraced-sphere`,
//! `volumes/particles-raytraced-sphere`) record the same pass through the same code
//! (`VolumeTechnique::record_volumes`): the pass is the technique.

use crate::technique::{
    GlobalsGpu, Method, Variant, VolumeDraw, VolumeSet, VolumeTechnique, placed_volumes_facing,
    unused_depth_views, upload_thickness, volume_layout,
};
use crate::{OpacityFn, Primitive};
use glam::Vec3;
use gpu::{Context, EyeView, Frame, GpuError, wgpu};
use scene::Technique as _;

/// One volume as the renderer describes it: a ball of uniform medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftVolume {
    /// World-space centre.
    pub center: Vec3,
    /// Radius (world units).
    pub radius: f32,
    /// Linear RGB radiance of the medium where it is opaque.
    pub color: Vec3,
    /// Extinction per world unit: seen through its centre the ball lets `exp(-2 radius
    /// density)` of the light behind it through.
    pub density: f32,
}

/// The soft-volume pass, made once for the renderer's colour format.
pub struct SoftVolumePass {
    technique: VolumeTechnique,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    thickness: wgpu::TextureView,
    unused_distance: wgpu::TextureView,
    format: wgpu::TextureFormat,
}

impl SoftVolumePass {
    /// The pass for colour targets of `color_format`: an error naming the format where the
    /// device cannot blend into it.
    pub fn new(ctx: &Context, color_format: wgpu::TextureFormat) -> Result<Self, GpuError> {
        let flags = ctx.format_features(color_format).flags;
        if !flags.contains(wgpu::TextureFormatFeatureFlags::BLENDABLE) {
            return Err(GpuError::InvalidInput(format!(
                "soft volumes blend over the colour target, and this device cannot blend into \
                 {color_format:?} (Rgba32Float needs FLOAT32_BLENDABLE; Rgba16Float and the \
                 8-bit formats blend everywhere)"
            )));
        }
        let mut technique = VolumeTechnique::new(Variant {
            method: Method::Raytraced(Primitive::Sphere),
            opacity: OpacityFn::Log,
            set: VolumeSet::All,
        });
        technique
            .set_param("free_depth", 1.0)
            .expect("every ray-traced variant declares free_depth");
        ctx.validated(|| {
            let layout = volume_layout(ctx);
            let pipeline = technique.volume_pipeline(ctx, &layout, color_format);
            // A ray-traced sphere reads no thickness texture; the layout binds one.
            let thickness = upload_thickness(ctx, &crate::path_length::thickness_texels());
            let (unused_distance, _) = unused_depth_views(ctx);
            Self {
                technique,
                layout,
                pipeline,
                thickness,
                unused_distance,
                format: color_format,
            }
        })
    }

    /// The colour format the pass was made for.
    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Records the volumes, back to front, blended over `color` where they are in front of
    /// the surfaces of `depth` (span "volumes" where the frame's timer measures). Both views
    /// are of the renderer's own textures, `view.width` x `view.height`.
    pub fn draw(
        &self,
        frame: &mut Frame,
        view: &EyeView,
        volumes: &[SoftVolume],
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) {
        let volumes: Vec<scene::Volume> = volumes.iter().map(scene_volume).collect();
        let eye = view.eye();
        let placed = placed_volumes_facing(&volumes, VolumeSet::All, eye, view.basis(), 0.0);
        if placed.is_empty() {
            return;
        }
        let view_proj = view.view_proj();
        let globals = GlobalsGpu {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            viewport: [view.width as f32, view.height as f32, 0.0, 0.0],
        };
        let records: Vec<_> = placed
            .iter()
            .map(|v| self.technique.volume_record(v, &volumes))
            .collect();
        let draw = VolumeDraw {
            pipeline: &self.pipeline,
            layout: &self.layout,
            thickness: &self.thickness,
            distance: &self.unused_distance,
            depth,
            color,
            depth_test: None,
        };
        self.technique
            .record_volumes(frame, &draw, &globals, &records);
    }
}

/// The scene crate's volume of a renderer's ball (uniform, still, not a particle).
fn scene_volume(v: &SoftVolume) -> scene::Volume {
    scene::Volume {
        name: String::new(),
        center: v.center,
        radius: v.radius,
        color: v.color,
        density: v.density,
        profile: scene::DensityProfile::UNIFORM,
        particle: false,
        motion: scene::Motion::default(),
    }
}
