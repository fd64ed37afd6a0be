// Radiance along a ray leaving the refractor, for the variants without nearby geometry: the
// environment map in the ray's direction (the paper's distant environment), or the room
// probe where the ray leaves its proxy box (the engine's parallax-corrected lookup).
#import gpu::prelude::box_project

fn outgoing_radiance(origin: vec3f, dir: vec3f) -> vec3f {
    if (params.probe.w > 0.5) {
        let l = box_project(origin, dir, params.probe.xyz, params.box_min.xyz, params.box_max.xyz);
        return env_lookup(l.xyz);
    }
    return env_lookup(dir);
}
