// The section-5 driver's pieces drawn from their meshes: the rasterized fragment is the first hit
// (refractor distance maps), shaded by scene::environment_pieces.
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole}
#import scene::environment_pieces::{piece_of_object, shade_piece}

@fragment
fn environment_piece_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return shade_piece(piece_of_object[in.object], in.world, in.normal, camera.eye.xyz);
}
