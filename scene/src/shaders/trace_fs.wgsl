// The tracer's eye pass: each specular object's rasterized fragment traces its tree of rays
// (scene::trace).
#import scene::shading::{SceneVertexOut, in_cutout_hole}
#import scene::trace::trace_pixel

@fragment
fn trace_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return trace_pixel(in);
}
