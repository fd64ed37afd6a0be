//! A full-screen triangle pass: the vertex stage every image-space pass shares.

/// Vertex stage of a full-screen triangle; the fragment receives `uv` with (0,0) at the top
/// left of the image, matching texel addressing (row 0 is the top).
pub const FULLSCREEN_VS_WGSL: &str = r#"
struct FullscreenOut {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

@vertex
fn fullscreen_vs(@builtin(vertex_index) index: u32) -> FullscreenOut {
    let xy = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    var out: FullscreenOut;
    out.position = vec4f(xy * 2.0 - 1.0, 0.0, 1.0);
    out.uv = vec2f(xy.x, 1.0 - xy.y);
    return out;
}
"#;

/// Builds a full-screen render pipeline from a fragment shader `fs_main` written against the
/// prelude and `FullscreenOut` (the vertex stage is prepended).
pub fn pipeline(
    ctx: &crate::Context,
    label: &str,
    fragment_source: &str,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    let source = format!("{FULLSCREEN_VS_WGSL}\n{fragment_source}");
    let module = crate::shader(ctx, crate::wgsl::Shader::new(label, &source));
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
                module: &module,
                entry_point: Some("fullscreen_vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// Records the full-screen draw (three vertices, no buffers).
pub fn draw(pass: &mut wgpu::RenderPass<'_>) {
    pass.draw(0..3, 0..1);
}
