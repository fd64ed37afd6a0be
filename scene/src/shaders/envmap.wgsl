// Classic environment mapping (the baseline): the specular object looks up a cube map taken
// from its centre with the reflected / refracted direction alone, as if the environment were
// infinitely far. One refraction only (the ray is not followed through the object).
#import scene::shading::{SceneVertexOut, camera, in_cutout_hole, specular_event, specular_shade}

@group(2) @binding(0) var env_map: texture_cube<f32>;
@group(2) @binding(1) var env_sampler: sampler;

fn sample_env(dir: vec3f) -> vec3f {
    return textureSampleLevel(env_map, env_sampler, dir, 0.0).rgb;
}

@fragment
fn envmap_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let eye = camera.eye.xyz;
    let v = normalize(in.world - eye);
    let e = specular_event(in.object, in.normal, in.world, eye, v);
    let reflected = sample_env(e.reflected);
    var refracted = reflected;
    if (e.refracted.w > 0.5) {
        refracted = sample_env(e.refracted.xyz);
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(in.world, eye));
}
