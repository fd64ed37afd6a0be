//! The volume techniques of thesis section 6.3 behind the workspace's `Technique` trait.
//!
//! Where things are: `variants.rs` (what a variant is, and the lists), `settings.rs` (its
//! parameters), `placement.rs` (the volumes of a frame placed for drawing), `passes.rs` (the
//! passes below, each a method stating what it reads and writes), `resources.rs` (what a
//! variant prepares); this file, [`VolumeTechnique`], whose `render` orders the passes.
//!
//! One frame:
//!
//! 1. (ray-traced volumes, unless `free_depth`; billboards and slices only with
//!    `depth_prepass`) the depth pre-pass of 6.3.3: the scene's distance from the eye into an
//!    R16Float texture, timed as the span `scene-depth`;
//! 2. the diffuse scene with `GpuScene::raster` into an Rgba16Float colour buffer, with the
//!    target's depth buffer;
//! 3. (8-bit slices) a full-screen copy of that colour into an Rgba8Unorm buffer: from here the
//!    slices blend at 8 bits per channel, as in a 2008 frame buffer;
//! 4. the volumes, sorted back to front, as camera-facing quads in one instanced draw, timed
//!    as the span `volumes`: billboards and slices depth-tested against the scene, ray-traced
//!    billboards without depth test reading the scene distance instead;
//! 5. a full-screen resolve of the colour buffer into the target (alpha 1).
//!
//! The target is `Rgba32Float`, which is not blendable without `FLOAT32_BLENDABLE` (the shared
//! context does not request it); the Rgba16Float buffer of steps 2-5 is the thesis's "floating
//! point colour buffer" (16 bits were enough, 6.3.2).

use crate::path_length::{
    OpacityFn, PATH_LENGTH, Primitive, THICKNESS_TEXTURE_SIZE, bake_thickness,
};
use glam::Vec3;
use gpu::pass::{self, Load};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Target, bind};
use scene::Settings as _;
use scene::technique::{Declared, not_prepared, set_checked, setting_if};
use scene::{
    BACKGROUND_DISTANCE, Camera, Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene,
    Technique, TechniqueResult, View, Volume,
};

mod passes;
mod placement;
mod resources;
mod settings;
mod variants;

pub(crate) use passes::VolumeDraw;
use passes::*;
pub use placement::*;
use resources::*;
pub(crate) use resources::{unused_depth_views, upload_thickness, volume_layout};
pub use settings::*;
pub use variants::*;

/// One variant of the volume techniques.
pub struct VolumeTechnique {
    variant: Variant,
    settings: Settings,
    gpu: Option<Resources>,
    buffers: Option<FrameBuffers>,
}

/// The thickness texture baked from one volume of the scene (see [`bake_thickness`]).
struct Baked {
    /// Index in `Scene::volumes` of the volume it was baked from.
    volume: usize,
    /// The opacity scale that turns the texture back into that volume's opacity.
    scale: f32,
}

struct Resources {
    baked: Option<Baked>,
    /// The `free_depth` the volume pipeline was specialised for.
    free_depth: bool,
    /// The `fade_distance` the depth-fade pipeline was specialised for (override `FADE`).
    fade_distance: f32,
    volume_layout: wgpu::BindGroupLayout,
    copy_layout: wgpu::BindGroupLayout,
    volume_pipeline: wgpu::RenderPipeline,
    to_bytes_pipeline: Option<wgpu::RenderPipeline>,
    resolve_pipeline: wgpu::RenderPipeline,
    distance_pipeline: wgpu::RenderPipeline,
    thickness_view: wgpu::TextureView,
    dummy_distance_view: wgpu::TextureView,
    dummy_depth_view: wgpu::TextureView,
}

struct FrameBuffers {
    width: u32,
    height: u32,
    scene_color_view: wgpu::TextureView,
    bytes_view: Option<wgpu::TextureView>,
    distance_view: wgpu::TextureView,
    distance_depth_view: wgpu::TextureView,
    to_bytes_bind_group: Option<wgpu::BindGroup>,
    resolve_bind_group: wgpu::BindGroup,
}

impl VolumeTechnique {
    /// The technique of `variant` with the default parameters (`billboard_scale`
    /// [`DEFAULT_BILLBOARD_SCALE`], `fit_silhouette`, `free_depth` and `depth_prepass` off).
    pub fn new(variant: Variant) -> Self {
        let settings = Settings {
            method: variant.method,
            billboard_scale: DEFAULT_BILLBOARD_SCALE,
            fit_silhouette: false,
            free_depth: false,
            depth_prepass: false,
            fade_distance: DEFAULT_FADE_DISTANCE,
        };
        Self {
            variant,
            settings,
            gpu: None,
            buffers: None,
        }
    }

    /// The variant this technique renders.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// Billboard, slices and the thickness-texture primitive read the thickness texture.
    fn uses_texture(&self) -> bool {
        !matches!(self.variant.method, Method::Raytraced(p) if p != Primitive::Texture)
    }

    fn is_raytraced(&self) -> bool {
        matches!(self.variant.method, Method::Raytraced(_))
    }

    /// Ray-traced volumes and depth-fade particles read the scene depth in the fragment
    /// shader instead of being depth tested.
    fn reads_scene_depth(&self) -> bool {
        self.is_raytraced() || self.variant.method == Method::DepthFade
    }

    /// Where the scene depth is read from: the depth buffer (depth fade, as engines do, and
    /// ray-traced volumes with `free_depth`) or the thesis's distance texture.
    fn reads_depth_buffer(&self) -> bool {
        self.variant.method == Method::DepthFade
            || (self.is_raytraced() && self.settings.free_depth)
    }

    fn slice_count(&self) -> u32 {
        match self.variant.method {
            Method::Slices { count, .. } => count,
            _ => 1,
        }
    }

    fn buffer_format(&self) -> wgpu::TextureFormat {
        match self.variant.method {
            Method::Slices {
                float_buffer: false,
                ..
            } => BYTE_BUFFER_FORMAT,
            _ => FLOAT_BUFFER_FORMAT,
        }
    }

    fn renders_distance(&self) -> bool {
        if self.variant.method == Method::DepthFade {
            false
        } else if self.is_raytraced() {
            !self.settings.free_depth
        } else {
            self.settings.depth_prepass
        }
    }

    fn ensure_buffers(&mut self, ctx: &Context, width: u32, height: u32) -> TechniqueResult<()> {
        if self
            .buffers
            .as_ref()
            .is_some_and(|b| b.width == width && b.height == height)
        {
            return Ok(());
        }
        let res = self.gpu.as_ref().ok_or_else(|| not_prepared(self))?;
        let texture = |label: &str, format: wgpu::TextureFormat| {
            ctx.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let scene_color_view = texture("volumes scene colour (Rgba16Float)", FLOAT_BUFFER_FORMAT);
        let bytes_view = (self.buffer_format() == BYTE_BUFFER_FORMAT)
            .then(|| texture("volumes colour (Rgba8Unorm)", BYTE_BUFFER_FORMAT));
        let distance_view = texture("volumes scene distance (R16Float)", DISTANCE_FORMAT);
        let distance_depth_view =
            gpu::depth_texture(ctx, width, height, 1, "volumes depth pre-pass depth")
                .create_view(&Default::default());
        let copy_bind_group = |view: &wgpu::TextureView| {
            bind::group(ctx, "volumes copy", &res.copy_layout, &[bind::view(view)])
        };
        let to_bytes_bind_group = bytes_view
            .as_ref()
            .map(|_| copy_bind_group(&scene_color_view));
        let resolve_bind_group = copy_bind_group(bytes_view.as_ref().unwrap_or(&scene_color_view));
        self.buffers = Some(FrameBuffers {
            width,
            height,
            scene_color_view,
            bytes_view,
            distance_view,
            distance_depth_view,
            to_bytes_bind_group,
            resolve_bind_group,
        });
        Ok(())
    }
}

/// Default billboard half size in units of the volume radius: "the sphere is made only
/// slightly smaller than the billboard" (6.3.3).
pub const DEFAULT_BILLBOARD_SCALE: f32 = 1.1;
/// Default fade distance of the depth-fade particles, in units of the volume radius.
pub const DEFAULT_FADE_DISTANCE: f32 = 1.0;

impl Technique for VolumeTechnique {
    fn id(&self) -> String {
        self.variant.id()
    }

    /// The default compare shows one variant of each method and precision (billboard; 9,
    /// 19 and 39 slices; 19 float slices; three opacity functions of the ray-traced sphere)
    /// and three particle variants; the other slice counts and opacity functions are for
    /// `harness sweep` (or `compare --all-variants`).
    fn representative(&self) -> bool {
        let exhaustive = [
            "slices-5",
            "slices-79",
            "slices-5-float",
            "slices-9-float",
            "slices-39-float",
            "slices-79-float",
            "raytraced-linear",
            "raytraced-sphere-linear",
            "raytraced-sphere-sqrt",
            "particles-slices-9-float",
            "particles-raytraced-sphere-log",
        ];
        let id = self.id();
        !exhaustive.iter().any(|v| id == format!("volumes/{v}"))
    }

    fn description(&self) -> String {
        self.variant.description()
    }

    fn params(&self) -> Vec<Param> {
        self.settings.params()
    }

    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id(), &mut self.settings, name, value)
    }

    fn supports(&self, scene: &Scene) -> bool {
        scene.volumes.iter().any(|v| self.variant.set.includes(v))
    }

    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        self.buffers = None;
        let resources = ctx.validated(|| self.create_resources(ctx, scene))?;
        self.gpu = Some(resources);
        Ok(())
    }

    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if self.gpu.as_ref().is_some_and(|r| {
            r.free_depth != self.settings.free_depth
                || r.fade_distance != self.settings.fade_distance
        }) {
            // `free_depth` or `fade_distance` changed after prepare: respecialise the pipelines.
            self.gpu = Some(ctx.validated(|| self.create_resources(ctx, scene))?);
            self.buffers = None;
        }
        self.ensure_buffers(ctx, target.width, target.height)?;
        let res = self.gpu.as_ref().ok_or_else(|| not_prepared(self))?;
        let buffers = self.buffers.as_ref().expect("ensure_buffers made them");
        let passes = FramePasses {
            scene,
            view,
            target,
            res,
            buffers,
        };
        if self.renders_distance() {
            frame.span("scene-depth", |frame| passes.scene_distance(frame));
        }
        passes.diffuse_scene(frame);
        passes.to_bytes(frame);
        self.draw_volumes(frame, &passes);
        passes.resolve(frame);
        Ok(())
    }
}
