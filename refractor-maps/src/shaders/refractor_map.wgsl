// Refractor map of a kind (imports scene::shading): its representative's own surface seen from
// its centre (camera.eye): outward unit normal in rgb, distance in alpha. Drawn without culling
// and with the depth test, so the nearest surface in each direction is kept.
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole}

@fragment
fn refractor_map_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return vec4f(normalize(in.normal), distance(in.world, camera.eye.xyz));
}
