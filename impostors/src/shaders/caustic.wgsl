// Caustics with distance impostors (paper section 5): the module impostors::caustic, over
// impostors::localized's and impostors::lightmap's bindings; its entry points are
// caustic_passes.wgsl's.
//
// 1. The caustic generator is drawn from the light (camera.eye = light) into a small
//    *caustic map*; each pixel is one photon: the light ray refracts (glass: in, then out
//    through the refractor map) or reflects (metal) at x, and Hit() in the environment
//    impostor gives the direction l of the photon's landing point from the reference point.
// 2. Two ways to turn photons into caustic radiance:
//    - light maps (the paper): caustic_uv_fs stores the landing point's light-map address
//      (atlas uv and chart, read through the *receiver cube*, this code's uvmap) and the
//      photon power; splat_quads.wgsl adds a Gaussian quad per photon into the light-map
//      atlas with additive blending; lightmap_apply_fs adds albedo / pi * E to the diffuse
//      surfaces.
//    - compute grid (modern): caustic_map_fs stores the landing point; splat.wgsl adds the
//      photons with atomics into a per-face grid indexed by the landing point's direction
//      from the reference point; caustic_apply_fs adds albedo / pi * E where the reference
//      point sees the surface.
// 3. Reflections and refractions see the caustics too (paper figure 11): env_lookup adds
//    caustic_radiance_at(l), which reads the caustic at the surface the impostor shows in
//    direction l (receiver cube: albedo, chart, texel area, cosine).
#define_import_path impostors::caustic

#import gpu::prelude::{PI, cube_dir_to_face_uv, reflect_dir}
#import gpu::distance_map
#import scene::shading::{BACKGROUND_DISTANCE, SceneVertexOut, emission_jitter, jittered_emission, objects, specular_event}
#import scene::chart::chart_uv
#import scene::receiver::{world_to_local, light_map_power}
#import impostors::localized::{MAX_SEGMENTS, MODE_DOUBLE, SURFACE_OFFSET, env_distance, env_sampler, params, refractor_chord}
#import impostors::lightmap::charts

struct CausticParams {
    // Light position (w unused) and RGB intensity (W/sr).
    light: vec4f,
    intensity: vec4f,
    // Unit axis of the caustic map's view; w: area of one caustic-map pixel on the image plane
    // at unit distance, (2 tan(fov/2) / C)^2.
    axis: vec4f,
    // Face size of the accumulation grid, fixed-point scale of the accumulated power (units
    // per watt), caustic map size C, and 1 when reflections and refractions add caustics.
    grid: u32,
    scale: f32,
    size: u32,
    in_lookup: u32,
    // Light-map atlas side in texels; 1 when photons leave from a random point of their pixel
    // (jittered_emission in scene.wgsl), 0 from its centre.
    lightmap: f32,
    jitter: u32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(3) @binding(0) var<uniform> caustic: CausticParams;
@group(3) @binding(1) var<storage, read> caustic_grid: array<u32>;
// Receiver cube as six layers: (chart or -1, object, 1 / texel area on the surface, cosine of
// the surface to the reference point; 0 for non-diffuse surfaces), and the albedo.
@group(3) @binding(4) var receiver_info: texture_2d_array<f32>;
@group(3) @binding(5) var receiver_albedo: texture_2d_array<f32>;
@group(3) @binding(6) var light_map: texture_2d<f32>;
@group(3) @binding(7) var light_map_sampler: sampler;

struct Photon {
    // Direction of the landing point from the reference point, and its distance.
    l: vec3f,
    distance: f32,
    power: vec3f,
    alive: bool,
};

// Where this caustic-map pixel's photon leaves the generator: the pixel centre or, jittered, a
// random point of the pixel. Uniform control flow (derivatives).
fn emitted_photon(in: SceneVertexOut) -> SceneVertexOut {
    let jitter = emission_jitter(in.clip.xy, 0u) * f32(caustic.jitter);
    return jittered_emission(in, jitter);
}

// The photon through this caustic-map pixel: refraction or reflection at the generator's
// surface, Hit() in the environment impostor, and the flux the pixel carries.
fn trace_photon(in: SceneVertexOut) -> Photon {
    var photon: Photon;
    photon.alive = false;
    let light = caustic.light.xyz;
    let l_dir = normalize(in.world - light);
    let e = specular_event(in.object, in.normal, in.world, light, l_dir);
    let n = e.normal;
    let o = objects[in.object];
    var origin = in.world;
    var dir: vec3f;
    var weight = vec3f(1.0);
    if (e.is_metal) {
        dir = e.reflected;
        weight = e.reflectance;
    } else {
        let t = e.refracted;
        if (t.w < 0.5) { return photon; }
        weight = vec3f(1.0 - e.reflectance.x);
        dir = t.xyz;
        origin = in.world - n * SURFACE_OFFSET;
        if (e.entering && params.mode == MODE_DOUBLE) {
            // Out through the refractor: the first chord that leaves (TIR chords reflect on).
            var left = false;
            for (var s = 0u; s < MAX_SEGMENTS; s++) {
                let chord = refractor_chord(origin, dir, o.material.y);
                if (chord.out.w > 0.5) {
                    weight *= 1.0 - chord.fresnel;
                    origin = chord.exit_point + chord.out.xyz * SURFACE_OFFSET;
                    dir = chord.out.xyz;
                    left = true;
                    break;
                }
                dir = reflect_dir(dir, -chord.normal);
                origin = chord.exit_point - chord.normal * SURFACE_OFFSET;
            }
            if (!left) { return photon; }
        }
    }
    let x = origin - params.reference.xyz;
    var l = distance_map::hit(x, dir, env_distance, env_sampler, params.distance_channel, params.method,
                params.iterations).xyz;
    if (dot(l, l) < 1e-12) { l = dir; }
    let shown = textureSampleLevel(env_distance, env_sampler, l, 0.0)[params.distance_channel];
    if (shown >= 0.5 * BACKGROUND_DISTANCE) { return photon; } // leaves the scene
    // Flux through this pixel: I * solid angle, solid angle = area * cos^3 off the axis.
    let cos_axis = dot(l_dir, caustic.axis.xyz);
    let solid_angle = caustic.axis.w * cos_axis * cos_axis * cos_axis;
    photon.l = normalize(l);
    photon.distance = shown;
    photon.power = caustic.intensity.rgb * solid_angle * weight;
    photon.alive = true;
    return photon;
}

struct PhotonOut {
    // Grid path: landing point, w = 1. Light-map path: atlas uv, chart, w = 1. w = 0: none.
    address: vec4f,
    // Photon power (W), w unused.
    power: vec4f,
};

struct PhotonTargets {
    @location(0) address: vec4f,
    @location(1) power: vec4f,
};

// The receiver-cube texel (nearest) in direction `l` from the reference point.
fn receiver_texel(l: vec3f) -> vec3i {
    let fuv = cube_dir_to_face_uv(l);
    let size = i32(textureDimensions(receiver_info).x);
    let i = clamp(i32(fuv.y * f32(size)), 0, size - 1);
    let j = clamp(i32(fuv.z * f32(size)), 0, size - 1);
    return vec3i(i, j, i32(fuv.x));
}

// Receiver cube (rendered from the reference point with the environment impostor): what the
// caustic lookups need to know about the surface seen in each direction.
struct ReceiverTargets {
    @location(0) info: vec4f,
    @location(1) albedo: vec4f,
};

fn grid_power(face: u32, i: i32, j: i32) -> vec3f {
    let base = 3u * ((face * caustic.grid + u32(j)) * caustic.grid + u32(i));
    return vec3f(f32(caustic_grid[base]), f32(caustic_grid[base + 1u]), f32(caustic_grid[base + 2u])) / caustic.scale;
}

// Grid path: irradiance at the surface point d (relative to the reference point) whose normal
// makes cosine cos_s with d: power tent-filtered over 3 x 3 texels (weights 1 2 1,
// renormalised at the face's border), per area of the texel's footprint on the surface.
fn grid_irradiance(d: vec3f, cos_s: f32) -> vec3f {
    let dist = length(d);
    let fuv = cube_dir_to_face_uv(d);
    let face = u32(fuv.x);
    let g = f32(caustic.grid);
    let i0 = i32(floor(fuv.y * g));
    let j0 = i32(floor(fuv.z * g));
    var power = vec3f(0.0);
    var wsum = 0.0;
    for (var dj = -1; dj <= 1; dj++) {
        for (var di = -1; di <= 1; di++) {
            let i = i0 + di;
            let j = j0 + dj;
            let w = f32(2 - abs(di)) * f32(2 - abs(dj));
            if (i >= 0 && j >= 0 && i < i32(caustic.grid) && j < i32(caustic.grid)) {
                power += w * grid_power(face, i, j);
                wsum += w;
            }
        }
    }
    power /= max(wsum, 1.0);
    // Solid angle of the texel around this direction, and its footprint on the surface.
    let sc = 2.0 * (f32(i0) + 0.5) / g - 1.0;
    let tc = 2.0 * (f32(j0) + 0.5) / g - 1.0;
    let texel_solid_angle = (4.0 / (g * g)) / pow(1.0 + sc * sc + tc * tc, 1.5);
    let area = texel_solid_angle * dist * dist / max(cos_s, 0.05);
    return power / area;
}

// Caustic radiance of the surface the impostor shows in direction l, for reflections and
// refractions (light-map path).
fn caustic_radiance_lightmap(l: vec3f) -> vec3f {
    if (caustic.in_lookup == 0u) { return vec3f(0.0); }
    let t = receiver_texel(l);
    let info = textureLoad(receiver_info, t.xy, t.z, 0);
    let chart = i32(round(info.x));
    if (chart < 0 || info.w <= 0.0) { return vec3f(0.0); }
    let shown = textureSampleLevel(env_distance, env_sampler, l, 0.0)[params.distance_channel];
    let p = params.reference.xyz + normalize(l) * shown;
    let c = charts[chart];
    let uv = chart_uv(c, world_to_local(u32(round(info.y)), p));
    let albedo = textureLoad(receiver_albedo, t.xy, t.z, 0).rgb;
    let power = light_map_power(light_map, light_map_sampler, caustic.lightmap, c, uv);
    return albedo / PI * power * info.z;
}

// The same for the grid path.
fn caustic_radiance_grid(l: vec3f) -> vec3f {
    if (caustic.in_lookup == 0u) { return vec3f(0.0); }
    let t = receiver_texel(l);
    let info = textureLoad(receiver_info, t.xy, t.z, 0);
    if (info.w <= 0.0) { return vec3f(0.0); }
    let shown = textureSampleLevel(env_distance, env_sampler, l, 0.0)[params.distance_channel];
    let albedo = textureLoad(receiver_albedo, t.xy, t.z, 0).rgb;
    return albedo / PI * grid_irradiance(normalize(l) * shown, info.w);
}

override fn impostors::localized::caustic_radiance_at(l: vec3f) -> vec3f {
#ifdef CAUSTIC_GRID
    return caustic_radiance_grid(l);
#else
    return caustic_radiance_lightmap(l);
#endif
}
