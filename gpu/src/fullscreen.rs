//! A full-screen triangle pass: the vertex stage every image-space pass shares.

/// The full-screen triangle as the module `gpu::fullscreen` ([`FULLSCREEN`]): the vertex
/// stage's output, `FullscreenOut`, which a fragment shader imports, and the vertex it makes.
/// The fragment receives `uv` with (0,0) at the top left of the image, matching texel
/// addressing (row 0 is the top).
pub const FULLSCREEN_WGSL: &str = r#"#define_import_path gpu::fullscreen

struct FullscreenOut {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

// Vertex `index` (0, 1, 2) of a triangle covering the view.
fn fullscreen_vertex(index: u32) -> FullscreenOut {
    let xy = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    var out: FullscreenOut;
    out.position = vec4f(xy * 2.0 - 1.0, 0.0, 1.0);
    out.uv = vec2f(xy.x, 1.0 - xy.y);
    return out;
}
"#;

/// [`FULLSCREEN_WGSL`] as a module (every shader may import it, as it may the prelude).
pub static FULLSCREEN: crate::wgsl::Module =
    crate::wgsl::Module::new(FULLSCREEN_WGSL, "gpu/src/fullscreen.rs", &[]);

/// The entry point of [`vertex_module`].
pub const VERTEX_ENTRY: &str = "fullscreen_vs";

/// The vertex stage of a full-screen triangle, a shader of its own: a pipeline takes its vertex
/// stage from [`vertex_module`] and its fragment stage from the caller's shader, which imports
/// `gpu::fullscreen::FullscreenOut`.
pub const FULLSCREEN_VS_WGSL: &str = r#"#import gpu::fullscreen::{FullscreenOut, fullscreen_vertex}

@vertex
fn fullscreen_vs(@builtin(vertex_index) index: u32) -> FullscreenOut {
    return fullscreen_vertex(index);
}
"#;

/// The shader module of [`FULLSCREEN_VS_WGSL`].
pub fn vertex_module(ctx: &crate::Context) -> wgpu::ShaderModule {
    crate::shader(
        ctx,
        crate::wgsl::Shader::new("full-screen triangle", FULLSCREEN_VS_WGSL),
    )
}

/// Builds a full-screen render pipeline from a fragment shader `fs_main` taking
/// `gpu::fullscreen::FullscreenOut` (its text, or a [`crate::wgsl::Shader`] with imports and
/// definitions) into one colour target of `format`, blended by `blend`; the vertex stage is
/// [`vertex_module`]'s.
pub fn pipeline<'s>(
    ctx: &crate::Context,
    label: &str,
    fragment: impl Into<crate::wgsl::Shader<'s>>,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    let output = Output {
        entry: "fs_main",
        color: crate::pass::color_target(format, blend),
        depth: None,
    };
    pipeline_into(ctx, label, fragment, bind_group_layouts, output)
}

/// What a full-screen pipeline writes: its fragment entry point, its colour target (a
/// renderer's formats: `TargetFormats::color_target`) and, for a fragment shader that writes
/// `@builtin(frag_depth)`, its depth state.
pub struct Output<'a> {
    pub entry: &'a str,
    pub color: Option<wgpu::ColorTargetState>,
    pub depth: Option<wgpu::DepthStencilState>,
}

/// [`pipeline`] with the fragment entry point, colour target and depth state of `output`.
pub fn pipeline_into<'s>(
    ctx: &crate::Context,
    label: &str,
    fragment: impl Into<crate::wgsl::Shader<'s>>,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    output: Output,
) -> wgpu::RenderPipeline {
    let vertex = vertex_module(ctx);
    let module = crate::shader(ctx, fragment.into());
    let layout = ctx
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts,
            immediate_size: 0,
        });
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &vertex,
                entry_point: Some(VERTEX_ENTRY),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(output.entry),
                compilation_options: Default::default(),
                targets: &[output.color],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: output.depth,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// Records the full-screen draw (three vertices, no buffers).
pub fn draw(pass: &mut wgpu::RenderPass<'_>) {
    pass.draw(0..3, 0..1);
}
