// The caustic light on the visible diffuse surfaces: albedo / pi * E, E the irradiance the
// splats left at the pixel (drawn over the raster pass, depth equal, added).
#import gpu::prelude::PI
#import scene::shading::{SceneVertexOut, in_cutout_hole, surface_albedo}

@group(3) @binding(0) var irradiance: texture_2d<f32>;

@fragment
fn apply_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let e = textureLoad(irradiance, vec2u(in.clip.xy), 0).rgb;
    return vec4f(surface_albedo(in.object, in.uv) / PI * e, 0.0);
}
