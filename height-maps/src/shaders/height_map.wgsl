// The refractor height map of one kind (section 6): the representative piece drawn with an
// orthographic camera looking at its plane of symmetry (its mesh's z = 0 plane) from the front
// (+z); the nearest surface's distance from the plane (its map-frame z) and its map-frame
// normal. Texels that see no surface keep the clear value (height = -bounds.height). Imports
// scene::shading.
#import scene::shading::{SceneVertexOut, in_cutout_hole}

struct HeightMapPass {
    // World -> map frame, relative to the piece's centre (a rotation and a translation).
    to_map: mat4x4f,
};

@group(2) @binding(0) var<uniform> height_pass: HeightMapPass;

@fragment
fn height_map_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let q = height_pass.to_map * vec4f(in.world, 1.0);
    let n = normalize((height_pass.to_map * vec4f(in.normal, 0.0)).xyz);
    return vec4f(n, q.z);
}
