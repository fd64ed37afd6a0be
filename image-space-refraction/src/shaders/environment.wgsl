// Radiance along a ray leaving the refractor, for the variants without nearby geometry: the
// environment map in the ray's direction (the paper's distant environment).
fn outgoing_radiance(origin: vec3f, dir: vec3f) -> vec3f {
    return env_lookup(dir);
}
