// The depth pre-pass of thesis 6.3.3: the scene's distance from the eye per pixel, into an
// R16Float texture ("a 16 bit floating point texture is used here"). Imports scene::shading
// (SceneVertexOut, the camera at group 0); drawn with scene_vs (scene::SCENE_VS_WGSL).
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole}

@fragment
fn scene_distance_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return vec4f(distance(in.world, camera.eye.xyz), 0.0, 0.0, 0.0);
}
