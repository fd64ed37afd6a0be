//! One-line colour and depth attachments, render passes and pipeline pieces, so that a
//! technique's pass reads as "draw into this view, clearing it" rather than as a page of
//! descriptor fields.

/// How an attachment starts the pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Load<T> {
    /// Keep what the attachment holds (drawing on top of an earlier pass).
    Keep,
    /// Clear to a value first.
    Clear(T),
}

impl<T> Load<T> {
    fn op(self) -> wgpu::LoadOp<T> {
        match self {
            Load::Keep => wgpu::LoadOp::Load,
            Load::Clear(v) => wgpu::LoadOp::Clear(v),
        }
    }
}

/// Clears colour to transparent black.
pub const CLEAR_BLACK: Load<wgpu::Color> = Load::Clear(wgpu::Color::TRANSPARENT);
/// Clears depth to the far plane.
pub const CLEAR_FAR: Load<f32> = Load::Clear(1.0);

/// A colour attachment of `view`, stored at the end of the pass.
pub fn color(
    view: &wgpu::TextureView,
    load: Load<wgpu::Color>,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: load.op(),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// A depth attachment of `view` (no stencil), stored at the end of the pass.
pub fn depth(
    view: &wgpu::TextureView,
    load: Load<f32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: load.op(),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// Begins a render pass; `timestamps` is what [`crate::GpuTimer::render_pass`] returns for a
/// timed span (`None` for an untimed pass).
pub fn begin<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    colors: &[Option<wgpu::RenderPassColorAttachment<'_>>],
    depth: Option<wgpu::RenderPassDepthStencilAttachment<'_>>,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: colors,
        depth_stencil_attachment: depth,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// A colour target of a pipeline, writing every channel.
pub fn color_target(
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format,
        blend,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// The depth state of a pipeline on [`crate::DEPTH_FORMAT`].
pub fn depth_state(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    depth_state_for(crate::DEPTH_FORMAT, write, compare)
}

/// [`depth_state`] on a depth attachment of `format` (a renderer's own: `Depth24Plus`, …).
pub fn depth_state_for(
    format: wgpu::TextureFormat,
    write: bool,
    compare: wgpu::CompareFunction,
) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// Adds rgb and keeps the destination's alpha: accumulating light into an HDR target whose
/// alpha holds something else (the distance in a distance map, a count).
pub const ADD_RGB_KEEP_ALPHA: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};
