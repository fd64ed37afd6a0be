// Refractor map of a kind (after the prelude and scene.wgsl): its representative's own surface
// seen from its centre (camera.eye): outward unit normal in rgb, distance in alpha. Drawn
// without culling and with the depth test, so the nearest surface in each direction is kept.
@fragment
fn refractor_map_fs(in: SceneVertexOut) -> @location(0) vec4f {
    return vec4f(normalize(in.normal), distance(in.world, camera.eye.xyz));
}
