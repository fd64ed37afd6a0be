// The localized lookup's entry points (impostors::localized): the specular objects shaded
// through their impostors, and the refractor map of double refraction. A caustic variant
// composes this file with impostors::caustic overriding the lookups' caustics.
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole, objects, specular_event, specular_shade}
#import impostors::localized::{MODE_DOUBLE, SURFACE_OFFSET, env_lookup, params, through_refractor}

@fragment
fn localized_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let eye = camera.eye.xyz;
    let v = normalize(in.world - eye);
    let e = specular_event(in.object, in.normal, in.world, eye, v);
    let reflected = env_lookup(in.world, e.reflected);
    var refracted = reflected;
    if (e.refracted.w > 0.5) {
        if (params.mode == MODE_DOUBLE && e.entering) {
            let o = objects[in.object];
            refracted = through_refractor(in.world - e.normal * SURFACE_OFFSET, e.refracted.xyz, o.material.y);
        } else {
            refracted = env_lookup(in.world, e.refracted.xyz);
        }
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(in.world, eye));
}

// Refractor map: the object's own surface seen from its centre (camera.eye): outward unit
// normal and distance. Drawn without culling and with the nearest surface kept (depth test).
@fragment
fn refractor_map_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return vec4f(normalize(in.normal), distance(in.world, camera.eye.xyz));
}
