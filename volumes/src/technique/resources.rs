//! What a variant prepares: its pipelines, layouts and thickness texture (the view-sized
//! buffers are `mod.rs`'s `ensure_buffers`).

use super::*;
use gpu::wgsl::Def;

const VOLUMES_WGSL: &str = include_str!("../shaders/volumes.wgsl");
const COPY_WGSL: &str = include_str!("../shaders/copy.wgsl");
const SCENE_DISTANCE_WGSL: &str = include_str!("../shaders/scene_distance.wgsl");

/// The clear of the full-screen copies' targets (which the copies then overwrite): opaque
/// black, not [`pass::CLEAR_BLACK`]'s transparent black.
pub(super) const CLEAR_OPAQUE_BLACK: Load<wgpu::Color> = Load::Clear(wgpu::Color::BLACK);

/// Premultiplied "over" on rgb; the destination's alpha is kept. (Not wgpu's
/// `PREMULTIPLIED_ALPHA_BLENDING`, which also blends alpha.)
pub(super) const PREMULTIPLIED_OVER_KEEP_ALPHA: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

impl VolumeTechnique {
    /// The pipelines, layouts and textures of the variant (per scene; rebuilt when
    /// `free_depth` or `fade_distance`, which specialise the volume pipeline, change).
    pub(super) fn create_resources(&self, ctx: &Context, scene: &GpuScene) -> Resources {
        let volume_layout = volume_layout(ctx);
        let copy_layout = bind::layout(
            ctx,
            "volumes copy",
            bind::ShaderStages::FRAGMENT,
            &[bind::texture_2d_unfilterable()], // copy_source
        );
        let (to_bytes_pipeline, resolve_pipeline) = self.copy_pipelines(ctx, &copy_layout);
        let (thickness_view, baked) = self.thickness_texture(ctx, &scene.scene);
        let (dummy_distance_view, dummy_depth_view) = unused_depth_views(ctx);
        Resources {
            baked,
            free_depth: self.settings.free_depth,
            fade_distance: self.settings.fade_distance,
            volume_pipeline: self.volume_pipeline(ctx, &volume_layout, self.buffer_format()),
            volume_layout,
            copy_layout,
            to_bytes_pipeline,
            resolve_pipeline,
            distance_pipeline: distance_pipeline(ctx, scene),
            thickness_view,
            dummy_distance_view,
            dummy_depth_view,
        }
    }

    /// The volume pass: the variant's fragment entry, specialised by override constants
    /// (slices, opacity function, primitive, depth source, fade distance), blended
    /// premultiplied over a colour target of `format` (the work buffer's, or a renderer's
    /// own: [`crate::SoftVolumePass`]).
    pub(crate) fn volume_pipeline(
        &self,
        ctx: &Context,
        volume_layout: &wgpu::BindGroupLayout,
        format: wgpu::TextureFormat,
    ) -> wgpu::RenderPipeline {
        let module = scene::shader_importing(ctx, "volumes", VOLUMES_WGSL, &[&PATH_LENGTH]);
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("volumes"),
                bind_group_layouts: &[Some(volume_layout)],
                immediate_size: 0,
            });
        let (fragment_entry, primitive) = match self.variant.method {
            Method::Billboard => ("billboard_fs", Primitive::Sphere),
            Method::Slices { .. } => ("slice_fs", Primitive::Sphere),
            Method::Raytraced(p) => ("raytraced_fs", p),
            Method::DepthFade => ("depth_fade_fs", Primitive::Sphere),
        };
        let constants = [
            ("SLICES", self.slice_count() as f64),
            ("OPACITY", self.variant.opacity.code() as f64),
            ("PRIMITIVE", primitive.code() as f64),
            (
                "DEPTH_SOURCE",
                if self.reads_depth_buffer() { 1.0 } else { 0.0 },
            ),
            ("FADE", self.settings.fade_distance as f64),
        ];
        let options = wgpu::PipelineCompilationOptions {
            constants: &constants,
            zero_initialize_workgroup_memory: true,
        };
        let depth_stencil = (!self.reads_scene_depth())
            .then(|| pass::depth_state(false, wgpu::CompareFunction::Less));
        let blend = Some(PREMULTIPLIED_OVER_KEEP_ALPHA);
        ctx.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("volumes"),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("volume_vs"),
                    compilation_options: options.clone(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment_entry),
                    compilation_options: options,
                    targets: &[pass::color_target(format, blend)],
                }),
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil,
                multisample: Default::default(),
                multiview_mask: None,
                cache: ctx.pipeline_cache(),
            })
    }

    /// The full-screen copies: into the 8-bit buffer (8-bit slices only) and the resolve into
    /// the HDR target.
    pub(super) fn copy_pipelines(
        &self,
        ctx: &Context,
        copy_layout: &wgpu::BindGroupLayout,
    ) -> (Option<wgpu::RenderPipeline>, wgpu::RenderPipeline) {
        let [keep_alpha, opaque] = [true, false].map(|keep| [("COPY_ALPHA", Def::Bool(keep))]);
        let copy = |label, defs| gpu::wgsl::Shader::new(label, COPY_WGSL).with_defs(defs);
        let layouts = [Some(copy_layout)];
        let to_bytes = (self.buffer_format() == BYTE_BUFFER_FORMAT).then(|| {
            let label = "volumes to 8-bit";
            let shader = copy(label, &keep_alpha);
            gpu::fullscreen::pipeline(ctx, label, shader, &layouts, BYTE_BUFFER_FORMAT, None)
        });
        let label = "volumes resolve";
        let shader = copy(label, &opaque);
        let resolve =
            gpu::fullscreen::pipeline(ctx, label, shader, &layouts, gpu::HDR_FORMAT, None);
        (to_bytes, resolve)
    }

    /// The thickness texture (the alpha of the billboard texture), read through the shared
    /// bilinear clamp-to-edge sampler, and what it was baked from.
    pub(super) fn thickness_texture(
        &self,
        ctx: &Context,
        scene: &Scene,
    ) -> (wgpu::TextureView, Option<Baked>) {
        let (texels, baked) = self.bake(scene);
        (upload_thickness(ctx, &texels), baked)
    }
}

/// The thickness texture of `texels` (`THICKNESS_TEXTURE_SIZE` squared, RGBA8).
pub(crate) fn upload_thickness(ctx: &Context, texels: &[u8]) -> wgpu::TextureView {
    let size = THICKNESS_TEXTURE_SIZE;
    let thickness = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("volumes thickness texture"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        texels,
    );
    thickness.create_view(&Default::default())
}

/// The volume pass's bindings.
pub(crate) fn volume_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    use wgpu::TextureViewDimension::D2;
    let fragment = bind::ShaderStages::FRAGMENT;
    let both = bind::ShaderStages::VERTEX_FRAGMENT;
    bind::layout_with_stages(
        ctx,
        "volumes",
        &[
            (both, bind::uniform()),                     // globals
            (both, bind::storage(true)),                 // volumes
            (fragment, bind::texture_2d()),              // thickness_texture
            (fragment, bind::sampler()),                 // thickness_sampler
            (fragment, bind::texture_2d_unfilterable()), // scene_distance_texture
            (fragment, bind::depth_texture(D2)),         // scene_depth_texture
        ],
    )
}

/// The depth pre-pass: the scene's distance from the eye into an R16Float target.
pub(super) fn distance_pipeline(ctx: &Context, scene: &GpuScene) -> wgpu::RenderPipeline {
    let label = "volumes scene distance";
    let module = scene::shader(ctx, label, SCENE_DISTANCE_WGSL);
    let layout = scene.pipeline_layout_with(ctx, &[]);
    let entry = "scene_distance_fs";
    scene::scene_pipeline(ctx, label, &layout, &module, entry, DISTANCE_FORMAT)
}

/// 1 x 1 distance and depth views bound where a variant reads neither (the layout has both).
pub(crate) fn unused_depth_views(ctx: &Context) -> (wgpu::TextureView, wgpu::TextureView) {
    let distance = ctx
        .device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("volumes unused distance"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DISTANCE_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default());
    let depth =
        gpu::depth_texture(ctx, 1, 1, 1, "volumes unused depth").create_view(&Default::default());
    (distance, depth)
}
