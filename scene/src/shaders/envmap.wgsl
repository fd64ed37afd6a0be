// Classic environment mapping (the baseline): the specular object looks up a cube map taken
// from its centre with the reflected / refracted direction alone, as if the environment were
// infinitely far. One refraction only (the ray is not followed through the object).

@group(2) @binding(0) var env_map: texture_cube<f32>;
@group(2) @binding(1) var env_sampler: sampler;

fn sample_env(dir: vec3f) -> vec3f {
    return textureSampleLevel(env_map, env_sampler, dir, 0.0).rgb;
}

@fragment
fn envmap_fs(in: SceneVertexOut) -> @location(0) vec4f {
    let eye = camera.eye.xyz;
    let v = normalize(in.world - eye);
    let n = facing_normal(in.normal, in.world, eye);
    let o = objects[in.object];
    let cos_i = -dot(v, n);
    let reflected = sample_env(reflect_dir(v, n));
    var color: vec3f;
    if (o.material.x == MATERIAL_METAL) {
        color = fresnel_nk(cos_i, o.n.xyz, o.k.xyz) * reflected;
    } else {
        // Entering when the authored (outward) normal faces the viewer.
        let entering = dot(normalize(in.normal), v) < 0.0;
        let eta_rel = select(1.0 / o.material.y, o.material.y, entering);
        let f = fresnel_dielectric(cos_i, eta_rel);
        let t = refract_dir(v, n, 1.0 / eta_rel);
        let refracted = select(reflected, sample_env(t.xyz), t.w > 0.5);
        color = f * reflected + (1.0 - f) * refracted;
    }
    return vec4f(color, distance(in.world, eye));
}
