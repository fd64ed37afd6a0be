// The shared raster pass: diffuse surfaces shaded like the reference; specular objects drawn
// as plain grey diffuse when `specular_as_diffuse` is set (the `raster` technique).
// Output: rgb = radiance, a = distance from the eye (so any view is also a distance impostor).
#import scene::shading::{MATERIAL_DIFFUSE, SceneVertexOut, camera, geometric_facing_normal, in_cutout_hole, object_emission, objects, shade_diffuse_ng, shading_normal, surface_albedo}

const PLAIN_GREY: vec3f = vec3f(0.7);

@fragment
fn raster_fs(in: SceneVertexOut) -> @location(0) vec4f {
    let eye = camera.eye.xyz;
    // Derivatives first: naga's discard ends the invocation, so none may follow it.
    let ng = geometric_facing_normal(in.world, eye);
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let n = shading_normal(in.normal, ng);
    var albedo = surface_albedo(in.object, in.uv);
    if (objects[in.object].material.x != MATERIAL_DIFFUSE) {
        albedo = PLAIN_GREY;
    }
    let radiance = shade_diffuse_ng(in.world, n, ng, albedo) + object_emission(in.object);
    return vec4f(radiance, distance(in.world, eye));
}

// Shadow pass: distance from the light (camera.eye) to the nearest surface.
@fragment
fn shadow_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return vec4f(distance(in.world, camera.eye.xyz), 0.0, 0.0, 0.0);
}
