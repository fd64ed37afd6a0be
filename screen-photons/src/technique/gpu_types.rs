//! The uniform blocks (each mirrors the WGSL struct of the same name) and the pipeline
//! helpers the passes share.

use super::*;

// ---------------------------------------------------------------------------------------------
// Uniform blocks (each mirrors the WGSL struct of the same name).
// ---------------------------------------------------------------------------------------------

/// `LdiParams` of ldi.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LdiParamsGpu {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// Width, height, layers, the longest line in samples.
    pub size: [u32; 4],
    /// Tolerance, thickness, t_skip, unused.
    pub tests: [f32; 4],
    pub bounds_min: [f32; 4],
    pub bounds_max: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct TransferParamsGpu {
    pub(super) light: [f32; 4],
    pub(super) intensity: [f32; 4],
    pub(super) axis: [f32; 4],
    pub(super) jitter: u32,
    pub(super) _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct BatchGpu {
    pub(super) first: u32,
    pub(super) rows: u32,
    pub(super) width: u32,
    pub(super) _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ModeGpu {
    pub(super) value: u32,
    pub(super) _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ResolveParamsGpu {
    pub(super) max_bounces: u32,
    pub(super) round: u32,
    pub(super) keep_beams: u32,
    pub(super) _pad: u32,
}

/// `ShaftView` of shafts.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ShaftViewGpu {
    pub(super) view_proj: [[f32; 4]; 4],
    pub(super) eye: [f32; 4],
    pub(super) forward: [f32; 4],
    pub(super) size: [u32; 4],
}

/// `FroxelParams` of froxels.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FroxelParamsGpu {
    pub(super) light_view_proj: [[f32; 4]; 4],
    pub(super) light: [f32; 4],
    pub(super) axis: [f32; 4],
    pub(super) grid: [u32; 4],
    pub(super) slices: [f32; 4],
    pub(super) prev_view_proj: [[f32; 4]; 4],
    pub(super) prev_eye: [f32; 4],
    pub(super) prev_slices: [f32; 4],
    pub(super) temporal: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SplatParamsGpu {
    pub(super) inv_view_proj: [[f32; 4]; 4],
    pub(super) forward: [f32; 4],
    pub(super) size: [f32; 4],
    pub(super) mode: u32,
    pub(super) lattice: u32,
    pub(super) _pad: [u32; 2],
}

/// The modules a pass may import beside the scene's: the LDI and its march
/// (`screen_photons::ldi`), the photon structs (`screen_photons::photon`), the splat weights
/// (`screen_photons::splat_weight`) and the photon beams (`screen_photons::beam`).
pub const PASS_MODULES: [&gpu::wgsl::Module; 4] = [
    &crate::march::LDI,
    &PHOTON,
    &crate::splat::WEIGHT,
    &crate::shafts::BEAM,
];

/// A pass's shader module: its own file, composed with the scene's modules and
/// [`PASS_MODULES`], the LDI bound at `@group(2)` ([`crate::march::LDI_DEFS`]).
pub(super) fn pass_shader(ctx: &Context, label: &str, own: &str) -> wgpu::ShaderModule {
    let shader = gpu::wgsl::Shader::new(label, own)
        .importing(&PASS_MODULES)
        .with_defs(&crate::march::LDI_DEFS);
    scene::shader_of(ctx, shader)
}

pub(super) fn compute_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    let module = pass_shader(ctx, label, own);
    gpu::compute::pipeline_with_layout(ctx, label, layout, &module, entry)
}

/// A pipeline whose vertex stage makes its own geometry (no vertex buffers, no depth).
pub(super) fn bufferless_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    (vs, fs): (&str, &str),
    topology: wgpu::PrimitiveTopology,
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    render_pipeline(
        ctx,
        label,
        layout,
        own,
        (vs, fs),
        topology,
        &[pass::color_target(MAP_FORMAT, blend)],
    )
}

/// [`bufferless_pipeline`] with the caller's targets. The vertex entry
/// [`gpu::fullscreen::VERTEX_ENTRY`] is the full-screen triangle's own shader.
pub(super) fn render_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    (vs, fs): (&str, &str),
    topology: wgpu::PrimitiveTopology,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let module = pass_shader(ctx, label, own);
    let fullscreen =
        (vs == gpu::fullscreen::VERTEX_ENTRY).then(|| gpu::fullscreen::vertex_module(ctx));
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: fullscreen.as_ref().unwrap_or(&module),
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets,
            }),
            primitive: wgpu::PrimitiveState {
                topology,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// Additive blending of every channel (irradiance accumulation).
pub(super) const ADD: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The target times the source, alpha kept: the image times the medium's transmittance.
pub(super) const MULTIPLY_RGB_KEEP_ALPHA: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::Src,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};
