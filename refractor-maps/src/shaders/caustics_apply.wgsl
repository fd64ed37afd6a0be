// Caustics (section 7), the light maps applied: the receiver (the chessboard) adds
// albedo / pi * E, E = the power per texel of both light maps (static pieces, moving piece)
// over the texel's area on the surface. Imports gpu::prelude, scene::shading,
// scene::chart and scene::receiver. Drawn over the finished image (depth equal,
// additive).
#import gpu::prelude::PI
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole, surface_albedo}
#import scene::chart::{Chart, signed_axis, chart_uv}
#import scene::receiver::{world_to_local, normal_to_local, texel_area, light_map_power}

struct ReceiverParams {
    chart: Chart,
    object: u32,
    // Light-map side (texels).
    side: f32,
    _pad0: u32,
    _pad1: u32,
};

@group(2) @binding(0) var<uniform> receiver: ReceiverParams;
@group(2) @binding(1) var static_light_map: texture_2d<f32>;
@group(2) @binding(2) var moving_light_map: texture_2d<f32>;
@group(2) @binding(3) var light_map_sampler: sampler;

@fragment
fn caustics_apply_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let c = receiver.chart;
    let n = normal_to_local(in.object, in.normal);
    // Photons land on the lit side of the chart's face only (the side the eye must see).
    let seen = dot(in.normal, camera.eye.xyz - in.world) > 0.0;
    if (in.object != receiver.object || signed_axis(n) != c.axes.z || !seen) {
        return vec4f(0.0);
    }
    let uv = chart_uv(c, world_to_local(in.object, in.world));
    let power = light_map_power(static_light_map, light_map_sampler, receiver.side, c, uv)
        + light_map_power(moving_light_map, light_map_sampler, receiver.side, c, uv);
    let irradiance = power / texel_area(c, in.object, n);
    return vec4f(surface_albedo(in.object, in.uv) / PI * irradiance, 0.0);
}
