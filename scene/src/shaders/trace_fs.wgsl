// The tracer's eye pass: each specular object's rasterized fragment traces its tree of rays
// (scene::trace).
#import scene::shading::SceneVertexOut
#import scene::trace::trace_pixel

@fragment
fn trace_fs(in: SceneVertexOut) -> @location(0) vec4f {
    return trace_pixel(in);
}
