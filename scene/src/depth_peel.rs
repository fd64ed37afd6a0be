//! Depth peeling: N layers of depth + normal of the scene as uploaded, seen from a camera.
//!
//! The peeler draws a [`GpuScene`]'s objects (those an [`ObjectFilter`] selects) with the
//! scene's own vertex stage `scene_vs`, so each object is placed by its transform at the
//! scene's current time ([`GpuScene::set_time`]), exactly where the raster pass draws it.
//!
//! Layer 0 holds the nearest surface at each pixel, layer k the nearest surface strictly
//! behind layer k-1: pass k compares each fragment's clip depth with layer k-1's depth texture
//! (read with `textureLoad`) and discards it unless it lies more than
//! [`DepthPeeler::epsilon`] behind, then keeps the nearest survivor with an ordinary depth test.
//! Both faces are drawn (no culling), so a closed object gives its front and back surfaces in
//! successive layers.
//!
//! Per layer the peeler produces, in three 2D-array textures with one array layer per peel
//! layer:
//!
//! - colour ([`DepthPeeler::FORMAT`], `Rgba32Float`): `xyz` = the interpolated vertex normal,
//!   normalised, in world space (the object's normal matrix applied) and as stored in the mesh
//!   (not flipped toward the viewer, so a closed mesh with outward normals gives outward
//!   normals on back surfaces too); `w` = the Euclidean distance from the eye to the surface
//!   point (not the clip depth). Empty texels are `(0, 0, 0, 0)`: a visible surface always has
//!   `w > 0`.
//! - surface ([`DepthPeeler::FORMAT`]): `x` = the object's index in the scene (as a float,
//!   exact below 2^24), `yz` = the interpolated texture coordinates, `w` = 1; empty texels are
//!   `(0, 0, 0, 0)`. With the normal and the distance this is what a technique needs to shade
//!   the surface at any layer (`surface_albedo`, `specular_event` of `scene.wgsl`).
//! - depth ([`gpu::DEPTH_FORMAT`]): the clip-space depth in [0, 1] of the same fragment; empty
//!   texels hold the clear value 1.
//!
//! With [`DepthPeeler::count_layers`] the peeler first counts the view's depth complexity on
//! the GPU and peels only that many layers (at most its `layers`): the paper's section 2.2
//! ([`crate::layer_count`]).
//!
//! Shader: the peel fragment stage below, importing `scene::shading` ([`crate::SHADING`]),
//! drawn with `scene_vs` ([`crate::SCENE_VS_WGSL`]); camera at `@group(0)`, scene at
//! `@group(1)`, the peel's uniform (layer, epsilon) and the previous layer's depth at
//! `@group(2)`.

use glam::{Mat4, Vec3};
use gpu::pass;
use gpu::wgpu;
use gpu::{Context, GpuError, Uniform, bind};

use crate::layer_count::LayerCounter;
use crate::{Frame, GpuScene, ObjectFilter, scene_pipeline_with};

const PEEL_WGSL: &str = r#"
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole}
struct Peel {
    layer: u32,
    epsilon: f32,
    _pad: vec2u,
};

@group(2) @binding(0) var<uniform> peel: Peel;
@group(2) @binding(1) var previous_depth: texture_depth_2d;

// Drawn with scene_vs, whose position is @invariant: re-rasterising the same triangle in the
// next pass gives bit-identical depth.
struct PeelTargets {
    @location(0) normal_distance: vec4f,
    @location(1) surface: vec4f,
};

@fragment
fn peel_fs(in: SceneVertexOut) -> PeelTargets {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    if (peel.layer > 0u) {
        // Keep only what lies strictly behind the previous layer (an empty texel there holds
        // depth 1, so everything is discarded and this layer stays empty too).
        let previous = textureLoad(previous_depth, vec2i(in.clip.xy), 0);
        if (in.clip.z <= previous + peel.epsilon) {
            discard;
        }
    }
    return PeelTargets(
        vec4f(normalize(in.normal), distance(in.world, camera.eye.xyz)),
        vec4f(f32(in.object), in.uv, 1.0),
    );
}
"#;

/// The uniform block of one peel pass (matches `Peel` in the shader).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PeelUniforms {
    layer: u32,
    epsilon: f32,
    _pad: [u32; 2],
}

/// Renders `layers` depth layers of a [`GpuScene`]; see the module documentation for what each
/// layer holds. Create once per size and layer count, then call [`DepthPeeler::peel`] per
/// frame.
pub struct DepthPeeler {
    width: u32,
    height: u32,
    layers: u32,
    epsilon: f32,
    color: wgpu::Texture,
    surface: wgpu::Texture,
    depth: wgpu::Texture,
    color_layer_views: Vec<wgpu::TextureView>,
    surface_layer_views: Vec<wgpu::TextureView>,
    depth_layer_views: Vec<wgpu::TextureView>,
    color_array_view: wgpu::TextureView,
    surface_array_view: wgpu::TextureView,
    depth_array_view: wgpu::TextureView,
    pipeline: wgpu::RenderPipeline,
    uniforms: Vec<Uniform<PeelUniforms>>,
    bind_groups: Vec<wgpu::BindGroup>,
    /// Set by [`DepthPeeler::count_layers`]: the passes past the view's depth complexity draw
    /// nothing.
    counter: Option<LayerCounter>,
}

impl DepthPeeler {
    /// Format of the normal + distance layers.
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
    /// Default separation in clip depth between successive layers: a few ulps of depth
    /// values near 1. Re-rasterising the same triangle gives bit-identical depth (the position
    /// of `scene_vs` is `@invariant`), so this only guards against drivers that differ between
    /// passes.
    pub const DEFAULT_EPSILON: f32 = 2e-7;

    /// Creates the layer textures (`width` x `height`, `layers` array layers) and the pipeline
    /// on `gpu_scene`'s bindings (every `GpuScene` has the same layouts, so the peeler can peel
    /// any of them). Fails on a size over the adapter's limits or a layer count of 0 or over
    /// `max_texture_array_layers`.
    pub fn new(
        ctx: &Context,
        gpu_scene: &GpuScene,
        width: u32,
        height: u32,
        layers: u32,
    ) -> Result<Self, GpuError> {
        ctx.check_size(width, height)?;
        let max_layers = ctx.device.limits().max_texture_array_layers;
        if layers == 0 || layers > max_layers {
            return Err(GpuError::InvalidInput(format!(
                "depth peeling needs 1 to {max_layers} layers on this adapter, not {layers}"
            )));
        }
        ctx.validated(|| Self::create(ctx, gpu_scene, width, height, layers))
    }

    fn create(ctx: &Context, gpu_scene: &GpuScene, width: u32, height: u32, layers: u32) -> Self {
        let layer_texture = |label| {
            gpu::render_texture(
                ctx,
                label,
                (width, height, layers),
                Self::FORMAT,
                wgpu::TextureUsages::COPY_SRC,
            )
        };
        let color = layer_texture("depth peel layers");
        let surface = layer_texture("depth peel surfaces");
        let depth = gpu::depth_texture(ctx, width, height, layers, "depth peel depth");
        // Layer 0 compares against nothing, but its bind group still needs a depth view.
        let unused_depth = gpu::depth_texture(ctx, 1, 1, 1, "depth peel unused depth");
        let unused_depth_view = unused_depth.create_view(&Default::default());
        let array_view = |texture: &wgpu::Texture| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("depth peel layers"),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let color_layer_views: Vec<_> = (0..layers).map(|l| gpu::layer_view(&color, l)).collect();
        let surface_layer_views: Vec<_> =
            (0..layers).map(|l| gpu::layer_view(&surface, l)).collect();
        let depth_layer_views: Vec<_> = (0..layers).map(|l| gpu::layer_view(&depth, l)).collect();

        let peel_layout = bind::layout(
            ctx,
            "depth peel",
            wgpu::ShaderStages::FRAGMENT,
            &[
                bind::uniform(), // @binding(0) var<uniform> peel: Peel;
                bind::depth_texture(wgpu::TextureViewDimension::D2), // @binding(1) var previous_depth: texture_depth_2d;
            ],
        );
        let uniforms: Vec<_> = (0..layers)
            .map(|layer| {
                Uniform::new(
                    ctx,
                    "depth peel layer",
                    &PeelUniforms {
                        layer,
                        epsilon: Self::DEFAULT_EPSILON,
                        _pad: [0; 2],
                    },
                )
            })
            .collect();
        let bind_groups = (0..layers as usize)
            .map(|l| {
                let previous = if l == 0 {
                    &unused_depth_view
                } else {
                    &depth_layer_views[l - 1]
                };
                bind::group(
                    ctx,
                    "depth peel layer",
                    &peel_layout,
                    &[uniforms[l].binding(), bind::view(previous)],
                )
            })
            .collect();

        let module = crate::shader(ctx, "depth peel", PEEL_WGSL);
        let layout = gpu_scene.pipeline_layout_with(ctx, &[&peel_layout]);
        let pipeline = scene_pipeline_with(
            ctx,
            "depth peel",
            &layout,
            &module,
            "peel_fs",
            &[
                pass::color_target(Self::FORMAT, None),
                pass::color_target(Self::FORMAT, None),
            ],
            (true, wgpu::CompareFunction::Less),
        );

        Self {
            width,
            height,
            layers,
            epsilon: Self::DEFAULT_EPSILON,
            color_array_view: array_view(&color),
            surface_array_view: array_view(&surface),
            depth_array_view: array_view(&depth),
            color,
            surface,
            depth,
            color_layer_views,
            surface_layer_views,
            depth_layer_views,
            pipeline,
            uniforms,
            bind_groups,
            counter: None,
        }
    }

    /// From the next [`DepthPeeler::peel`] on, counts the view's depth complexity first and
    /// peels only that many layers (section 2.2 of Krüger et al.; the module
    /// [`crate::layer_count`]); the layers past it are cleared, as empty. Peel `gpu_scene`
    /// (or one with the same objects) from then on. Fails where the adapter lacks
    /// `INDIRECT_FIRST_INSTANCE` (the peeler then peels every layer, as before).
    pub fn count_layers(&mut self, ctx: &Context, gpu_scene: &GpuScene) -> Result<(), GpuError> {
        self.counter = Some(LayerCounter::new(
            ctx,
            gpu_scene,
            self.width,
            self.height,
            self.layers,
        )?);
        Ok(())
    }

    /// The depth complexity the last submitted peel counted (`None` without
    /// [`DepthPeeler::count_layers`]): read back, for tests and diagnostics.
    pub fn counted_complexity(&self, ctx: &Context) -> Option<Result<u32, GpuError>> {
        self.counter.as_ref().map(|c| c.complexity(ctx))
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of layers peeled by [`DepthPeeler::peel`].
    pub fn layers(&self) -> u32 {
        self.layers
    }

    /// Clip-depth separation required between successive layers.
    pub fn epsilon(&self) -> f32 {
        self.epsilon
    }

    /// Sets the clip-depth separation between layers (default [`Self::DEFAULT_EPSILON`]);
    /// surfaces closer than this behind a layer are skipped. Takes effect at the next
    /// [`DepthPeeler::peel`].
    pub fn set_epsilon(&mut self, epsilon: f32) {
        self.epsilon = epsilon;
    }

    /// Records the `layers` peel passes of the objects `filter` selects into `frame.encoder`,
    /// timed as the span "depth peel". Objects are where [`GpuScene::set_time`] last put
    /// them: call it (in this frame or an earlier submitted one) before peeling. `view_proj`
    /// maps world to clip space with depth in [0, 1] (e.g. `Camera::view_proj`, or
    /// `glam::camera::rh::proj::directx::perspective(..)` times
    /// `glam::camera::rh::view::look_at_mat4(..)`); `eye` is the camera position that the
    /// distances in `w` are measured from.
    ///
    /// The epsilon goes through `queue.write_buffer`, which takes effect at the next submit;
    /// peeling twice with the same peeler before a submit keeps only the second peel anyway
    /// (same layer textures).
    ///
    /// Fails with [`GpuError::InvalidInput`] on a non-finite matrix or eye, or a filter naming
    /// an object the scene does not have.
    pub fn peel(
        &self,
        frame: &mut Frame<'_>,
        gpu_scene: &GpuScene,
        filter: &ObjectFilter,
        view_proj: Mat4,
        eye: Vec3,
    ) -> Result<(), GpuError> {
        if !view_proj.is_finite() || !eye.is_finite() {
            return Err(GpuError::InvalidInput(
                "depth peeling needs a finite view-projection matrix and eye position".into(),
            ));
        }
        let count = gpu_scene.scene.objects.len();
        let listed: &[usize] = match filter {
            ObjectFilter::Only(list) | ObjectFilter::Except(list) => list,
            ObjectFilter::All | ObjectFilter::Diffuse => &[],
        };
        if let Some(bad) = listed.iter().find(|&&i| i >= count) {
            return Err(GpuError::InvalidInput(format!(
                "depth peeling selects object {bad}, but the scene has {count} objects"
            )));
        }
        let ctx = frame.gpu;
        for (layer, uniform) in self.uniforms.iter().enumerate() {
            uniform.write(
                ctx,
                &PeelUniforms {
                    layer: layer as u32,
                    epsilon: self.epsilon,
                    _pad: [0; 2],
                },
            );
        }
        let camera = gpu_scene.camera_bind_group(ctx, view_proj, eye);
        if let Some(counter) = &self.counter {
            if counter.draws() != gpu_scene.draws.len() {
                return Err(GpuError::InvalidInput(format!(
                    "the depth peeler counts layers for a scene of {} objects, not {}",
                    counter.draws(),
                    gpu_scene.draws.len()
                )));
            }
            let writes = frame.timer.render_pass("depth peel");
            counter.count(
                frame.encoder,
                gpu_scene,
                filter,
                &camera,
                &self.depth_layer_views[0],
                writes,
            );
        }
        for layer in 0..self.layers as usize {
            let writes = frame.timer.render_pass("depth peel");
            let mut pass = pass::begin(
                frame.encoder,
                "depth peel layer",
                &[
                    pass::color(&self.color_layer_views[layer], pass::CLEAR_BLACK),
                    pass::color(&self.surface_layer_views[layer], pass::CLEAR_BLACK),
                ],
                Some(pass::depth(&self.depth_layer_views[layer], pass::CLEAR_FAR)),
                writes,
            );
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, gpu_scene.bind_group(), &[]);
            pass.set_bind_group(2, &self.bind_groups[layer], &[]);
            match &self.counter {
                Some(counter) => gpu_scene.draw_objects_indirect(
                    &mut pass,
                    filter,
                    counter.args(),
                    counter.layer_offset(layer as u32),
                ),
                None => gpu_scene.draw_objects(&mut pass, filter),
            }
        }
        Ok(())
    }

    /// All layers as one `D2Array` view of [`Self::FORMAT`] (normal, distance), for
    /// `texture_2d_array<f32>` bindings (unfilterable: read with `textureLoad` or a
    /// non-filtering sampler).
    pub fn layers_view(&self) -> &wgpu::TextureView {
        &self.color_array_view
    }

    /// All layers' surfaces (object index, texture coordinates, 1) as one `D2Array` view of
    /// [`Self::FORMAT`], like [`Self::layers_view`].
    pub fn surfaces_view(&self) -> &wgpu::TextureView {
        &self.surface_array_view
    }

    /// Reads one layer's surfaces back: `[object, u, v, 1]` per pixel (zero where empty).
    pub fn read_surface(&self, ctx: &Context, layer: u32) -> Result<Vec<[f32; 4]>, GpuError> {
        self.check_layer(layer)?;
        gpu::read_texture_f32x4(ctx, &self.surface, layer)
    }

    /// All layers' clip depths as one `D2Array` view, for `texture_depth_2d_array` bindings.
    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.depth_array_view
    }

    /// The normal + distance texture (one array layer per peel layer).
    pub fn layers_texture(&self) -> &wgpu::Texture {
        &self.color
    }

    /// The depth texture (one array layer per peel layer).
    pub fn depth_texture(&self) -> &wgpu::Texture {
        &self.depth
    }

    /// Reads one layer back: `[nx, ny, nz, distance]` per pixel, row 0 at the top.
    pub fn read_layer(&self, ctx: &Context, layer: u32) -> Result<Vec<[f32; 4]>, GpuError> {
        self.check_layer(layer)?;
        gpu::read_texture_f32x4(ctx, &self.color, layer)
    }

    /// Reads one layer's clip depth back (1 where the layer is empty), row 0 at the top.
    pub fn read_depth(&self, ctx: &Context, layer: u32) -> Result<Vec<f32>, GpuError> {
        self.check_layer(layer)?;
        gpu::read_texture_f32(ctx, &self.depth, layer)
    }

    fn check_layer(&self, layer: u32) -> Result<(), GpuError> {
        if layer >= self.layers {
            return Err(GpuError::InvalidInput(format!(
                "layer {layer} does not exist: the peeler has {} layers",
                self.layers
            )));
        }
        Ok(())
    }
}
