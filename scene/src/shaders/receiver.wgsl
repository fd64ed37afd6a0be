#define_import_path scene::receiver
// Light-map receivers (src/lightmap.rs): object-space addressing of a diffuse object's surface
// and the light-map power read back from an atlas: the module scene::receiver, importing
// scene::shading and scene::chart.
// No bindings of its own: the light map is passed in, so every technique that splats photons
// into light maps (impostors' caustic maps, refractor-maps' photon hits) reads them with these
// functions.
#import scene::shading::objects
#import scene::chart::Chart

// World point -> object space: the linear part's inverse is the normal matrix transposed.
fn world_to_local(object: u32, p: vec3f) -> vec3f {
    let o = objects[object];
    let n3 = mat3x3f(o.normal_matrix[0].xyz, o.normal_matrix[1].xyz, o.normal_matrix[2].xyz);
    return transpose(n3) * (p - o.model[3].xyz);
}

// Object-space normal (up to scale) from a world normal: the model's linear part transposed.
fn normal_to_local(object: u32, n: vec3f) -> vec3f {
    let o = objects[object];
    let m3 = mat3x3f(o.model[0].xyz, o.model[1].xyz, o.model[2].xyz);
    return transpose(m3) * n;
}

// Area on the surface of one texel of chart `c`, where the surface's object-space normal is
// `local_normal`: the texel's projected square t^2 in object space, divided by the cosine to
// the chart's axis (the surface is tilted against the projection plane), scaled to world
// space. A surface element dA with unit normal n maps to |det M| |M^-T n| dA under the
// model's linear part M; the normal matrix N = M^-T gives |det M| = 1 / |det N|.
fn texel_area(c: Chart, object: u32, local_normal: vec3f) -> f32 {
    let n = normalize(local_normal);
    let o = objects[object];
    let nm = mat3x3f(o.normal_matrix[0].xyz, o.normal_matrix[1].xyz, o.normal_matrix[2].xyz);
    let axis = c.axes.z / 2u;
    let cos_axis = max(abs(n[axis]), 1e-3);
    let t = c.bounds.w;
    return t * t / cos_axis * length(nm * n) / abs(determinant(nm));
}

// Power per texel (W) of chart `c` at atlas `uv` in `light_map` (side `side` texels),
// bilinear, kept inside the chart's rectangle so no neighbour bleeds in.
fn light_map_power(light_map: texture_2d<f32>, light_map_sampler: sampler, side: f32, c: Chart,
                   uv: vec2f) -> vec3f {
    let half_texel = 0.5 / side;
    let inside = clamp(uv, c.rect.xy + half_texel, max(c.rect.zw - half_texel, c.rect.xy + half_texel));
    return textureSampleLevel(light_map, light_map_sampler, inside, 0.0).rgb;
}
