//! The resolve: the eye pass's radiance plus the mean of the photon sum, drawn as a full-screen
//! triangle into a colour target and, for a renderer's frame, the primary hits' depth into its
//! depth target.
//!
//! The harness's targets take the colour alone (`fs_main`, alpha 1). A renderer's take the
//! colour in their own format (`fs_with_depth`) and the depth its projection gives each pixel's
//! first hit, so what the renderer draws after the tracer (overlays, gizmos, other passes) is
//! hidden behind the traced surfaces as behind its own.

use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use gpu::bind::{self, Uniform};
use gpu::{Context, TargetFormats, wgpu};

const RESOLVE_WGSL: &str = r#"
#import gpu::fullscreen::FullscreenOut
struct ResolveParams {
    // width, height, 1 when photons were traced, frames the photon sum holds.
    size: vec4u,
    // The projection's z row acting on view-space z: depth = (x z + y) / (z z + w).
    depth_of_z: vec4f,
    // The depth of a pixel that sees no surface (the projection's far limit, clamped).
    background_depth: vec4f,
};
@group(0) @binding(0) var<uniform> resolve: ResolveParams;
@group(0) @binding(1) var<storage, read> eye_radiance: array<vec4f>;
@group(0) @binding(2) var<storage, read> photon_counts: array<u32>;

// At or beyond this the eye pass found no first hit (it writes tracer.wgsl's INFINITY, 3.4e38).
const NO_HIT_DEPTH: f32 = 1e30;

// The fixed-point photon sum of channel c of pixel p (tracer.wgsl's add_fixed: 2^32 units per
// unit of radiance, so the high word counts whole units).
fn photon_radiance(p: u32, c: u32) -> f32 {
    let i = 2u * (3u * p + c);
    return f32(photon_counts[i + 1u]) + f32(photon_counts[i]) / 4294967296.0;
}

fn pixel_of(position: vec4f) -> u32 {
    let x = min(u32(position.x), resolve.size.x - 1u);
    let y = min(u32(position.y), resolve.size.y - 1u);
    return y * resolve.size.x + x;
}

fn radiance_of(p: u32) -> vec3f {
    var l = eye_radiance[p].rgb;
    if (resolve.size.z == 1u) {
        let frames = f32(max(resolve.size.w, 1u));
        l += vec3f(photon_radiance(p, 0u), photon_radiance(p, 1u), photon_radiance(p, 2u)) / frames;
    }
    return l;
}

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    return vec4f(radiance_of(pixel_of(in.position)), 1.0);
}

struct ColorAndDepth {
    @location(0) color: vec4f,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_with_depth(in: FullscreenOut) -> ColorAndDepth {
    let p = pixel_of(in.position);
    // The eye pass's w: the first hit's depth along the view direction (positive ahead).
    let view_depth = eye_radiance[p].w;
    var depth = resolve.background_depth.x;
    if (view_depth < NO_HIT_DEPTH) {
        let z = -view_depth;
        let m = resolve.depth_of_z;
        depth = clamp((m.x * z + m.y) / (m.z * z + m.w), 0.0, 1.0);
    }
    return ColorAndDepth(vec4f(radiance_of(p), 1.0), depth);
}
"#;

/// The resolve's uniform block (`ResolveParams` above).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct ResolveParamsGpu {
    pub size: [u32; 4],
    pub depth_of_z: [f32; 4],
    pub background_depth: [f32; 4],
}

impl ResolveParamsGpu {
    /// A `width` x `height` frame whose photon sum holds `frames` frames (`photons`: whether
    /// any were traced), its depth by `projection`.
    pub fn new((width, height): (u32, u32), photons: bool, frames: u32, projection: &Mat4) -> Self {
        let (z, w) = (projection.z_axis, projection.w_axis);
        let depth_of_z = [z.z, w.z, z.w, w.w];
        Self {
            size: [width, height, photons as u32, frames],
            depth_of_z,
            background_depth: [background_depth(depth_of_z), 0.0, 0.0, 0.0],
        }
    }
}

/// The depth a projection gives the farthest view-space z (the limit toward -infinity, clamped
/// to [0, 1]): 1 for a conventional projection, 0 for a reversed one.
fn background_depth([a, _b, c, d]: [f32; 4]) -> f32 {
    let limit = if c != 0.0 {
        // Perspective: (a z + b) / (c z + d) tends to a / c.
        a / c
    } else if -a / d > 0.0 {
        // Orthographic: a z + b grows without bound as z goes to -infinity.
        1.0
    } else {
        0.0
    };
    if limit.is_finite() {
        limit.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The resolve's pipeline for one kind of target, with its uniform and bind group.
pub(crate) struct Resolve {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: Uniform<ResolveParamsGpu>,
    group: Option<wgpu::BindGroup>,
    writes_depth: bool,
}

impl Resolve {
    /// The colour-only resolve of the harness's targets ([`TargetFormats::HDR`], alpha 1), or
    /// with `depth` the resolve into a renderer's colour and depth formats.
    pub fn new(ctx: &Context, formats: TargetFormats, depth: bool) -> Self {
        let layout = bind::layout(
            ctx,
            "ray tracer resolve",
            wgpu::ShaderStages::FRAGMENT,
            &[bind::uniform(), bind::storage(true), bind::storage(true)],
        );
        let output = gpu::fullscreen::Output {
            entry: if depth { "fs_with_depth" } else { "fs_main" },
            color: formats.color_target(),
            depth: depth.then(|| {
                gpu::pass::depth_state_for(formats.depth, true, wgpu::CompareFunction::Always)
            }),
        };
        let shader = gpu::wgsl::Shader::new("ray tracer resolve", RESOLVE_WGSL);
        let layouts = [Some(&layout)];
        let pipeline =
            gpu::fullscreen::pipeline_into(ctx, "ray tracer resolve", shader, &layouts, output);
        Self {
            layout,
            pipeline,
            params: Uniform::new(ctx, "ray tracer resolve", &ResolveParamsGpu::zeroed()),
            group: None,
            writes_depth: depth,
        }
    }

    /// Binds the eye pass's radiance and the photon sum (after the tracer made them anew).
    pub fn bind(&mut self, ctx: &Context, radiance: &wgpu::Buffer, photon_sum: &wgpu::Buffer) {
        self.group = Some(bind::group(
            ctx,
            "ray tracer resolve",
            &self.layout,
            &[
                self.params.binding(),
                radiance.as_entire_binding(),
                photon_sum.as_entire_binding(),
            ],
        ));
    }

    /// Records the resolve of a frame of `params` into `color` and, where this resolve writes
    /// depth, `depth`.
    pub fn draw(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        params: &ResolveParamsGpu,
        color: &wgpu::TextureView,
        depth: Option<&wgpu::TextureView>,
    ) {
        let group = self
            .group
            .as_ref()
            .expect("the tracer binds its buffers before any frame is resolved");
        self.params.write(ctx, params);
        // Every pixel is written (a full-screen triangle, depth test Always): the colour's
        // alpha is kept where the formats keep it, and the depth's clear is the background's.
        let background = gpu::pass::Load::Clear(params.background_depth[0]);
        let depth = depth
            .filter(|_| self.writes_depth)
            .map(|view| gpu::pass::depth(view, background));
        let mut pass = gpu::pass::begin(
            encoder,
            "ray tracer resolve",
            &[gpu::pass::color(color, gpu::pass::Load::Keep)],
            depth,
            None,
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        gpu::fullscreen::draw(&mut pass);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A conventional projection's far limit is depth 1 and a reversed one's 0, perspective
    /// (finite or infinite far plane) or orthographic (clamped).
    #[test]
    fn the_background_lies_at_the_projections_far_limit() {
        let conventional = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
        let reversed = glam::camera::rh::proj::directx::perspective_infinite_reverse(1.0, 1.0, 0.1);
        let ortho = glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0);
        // Near and far swapped: reversed depth, finite.
        let reversed_ortho =
            glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 10.0, 0.1);
        let reversed_finite = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 100.0, 0.1);
        let of = |p: &Mat4| ResolveParamsGpu::new((4, 4), false, 1, p).background_depth[0];
        assert_eq!(of(&conventional), 1.0);
        assert_eq!(of(&reversed), 0.0);
        assert_eq!(of(&ortho), 1.0);
        assert_eq!(of(&reversed_ortho), 0.0);
        assert_eq!(of(&reversed_finite), 0.0);
    }
}
