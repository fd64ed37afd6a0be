// The diffuse surfaces shaded like the raster pass (raster.wgsl: the reference's rules) with
// the screen-space visibility of the first four lights instead of their shadow maps.
#import gpu::prelude::PI
#import scene::shading::{SceneVertexOut, camera, geometric_facing_normal, in_cutout_hole, light_visibility, lights, object_emission, scene_info, shading_normal, surface_albedo}
#import screen_photons::ldi::ldi

@group(3) @binding(0) var<storage, read> shadow_mask: array<vec4f>;

@fragment
fn shadowed_fs(in: SceneVertexOut) -> @location(0) vec4f {
    let eye = camera.eye.xyz;
    // Derivatives first: naga's discard ends the invocation, so none may follow it.
    let ng = geometric_facing_normal(in.world, eye);
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let n = shading_normal(in.normal, ng);
    let albedo = surface_albedo(in.object, in.uv);
    let px = vec2u(in.clip.xy);
    let mask = shadow_mask[px.y * ldi.size.x + px.x];
    var sum = vec3f(0.0);
    for (var i = 0u; i < scene_info.light_count; i++) {
        let to_l = lights[i].position.xyz - in.world;
        let d2 = dot(to_l, to_l);
        let cos_l = dot(n, to_l) * inverseSqrt(d2);
        var v = 0.0;
        if (i < 4u) { v = mask[i]; } else { v = light_visibility(i, in.world, ng); }
        let lit = cos_l > 0.0 && dot(ng, to_l) > 0.0;
        sum += select(vec3f(0.0), albedo / PI * lights[i].intensity.rgb * cos_l / d2 * v, lit);
    }
    return vec4f(sum + object_emission(in.object), distance(in.world, eye));
}
