// Localized environment mapping with distance impostors (paper sections 3 and 4): the module
// impostors::localized, whose entry points are localized_fs.wgsl's. Its lookups add
// caustic_radiance_at(l), none here: the caustic variants override it (impostors::caustic).
//
// Specular objects are drawn with scene_vs; each pixel of an object traces its reflected (and
// for glass its refracted) ray with Hit() in the object's distance impostor and looks the
// radiance up in the direction of the hit approximation l:
//   mode 0 (classic):   lookup direction R itself (what envmap/classic does);
//   mode 1 (localized): one interface: metals F * I(Hit(x, R)); glass F * I(reflected) +
//                       (1 - F) * I(refracted), refraction at the visible surface only
//                       (like envmap.wgsl), the refracted ray looked up from x;
//   mode 2 (double):    glass rays go through the object: Hit() in the refractor map (the
//                       object's own distance + normal impostor from its centre) gives the exit
//                       point and its normal, the ray refracts out there (Fresnel split: the
//                       internally reflected share is followed for up to MAX_SEGMENTS chords)
//                       and the localized lookup continues in the environment impostor.
// With lookup 1 (box projected) every lookup of modes 1 and 2 is the engine's parallax-corrected
// cube map instead of Hit(): the ray is intersected with a proxy box (the room's bounds) and the
// map, captured at `reference` (the probe), is looked up toward the exit point (box_project of
// the prelude); the distances are unused. Lookup 2: a box-projected variant on a scene with no
// proxy box falls back to the direction lookup.
#define_import_path impostors::localized

#import gpu::prelude::{box_project, fresnel_dielectric, reflect_dir, refract_dir}
#import gpu::distance_map

struct ImpostorParams {
    // Reference point of the environment impostor (world), w unused.
    reference: vec4f,
    // Reference point of the refractor map (the object's centre when it was made), w unused.
    refractor_center: vec4f,
    // 0 classic, 1 localized, 2 double refraction.
    mode: u32,
    // HIT_SECANT or HIT_FALSE_POSITION.
    method: u32,
    iterations: u32,
    // Channel of env_distance holding the distance: 3 packed (alpha), 0 split.
    distance_channel: u32,
    // Iterations of Hit() inside the refractor map.
    refractor_iterations: u32,
    // LOOKUP_HIT or LOOKUP_BOX.
    lookup: u32,
    _pad_b: u32,
    _pad_c: u32,
    // Proxy box of the box-projected lookup (world), w unused.
    proxy_min: vec4f,
    proxy_max: vec4f,
};

@group(2) @binding(0) var env_radiance: texture_cube<f32>;
@group(2) @binding(1) var env_distance: texture_cube<f32>;
@group(2) @binding(2) var env_sampler: sampler;
@group(2) @binding(3) var<uniform> params: ImpostorParams;
@group(2) @binding(4) var refractor_map: texture_cube<f32>;

const MODE_CLASSIC: u32 = 0u;
const MODE_LOCALIZED: u32 = 1u;
const MODE_DOUBLE: u32 = 2u;
const LOOKUP_HIT: u32 = 0u;
const LOOKUP_BOX: u32 = 1u;
const LOOKUP_DIRECTION: u32 = 2u;
// Chords followed inside a refractor (exit attempts); the energy still inside after the last
// one is dropped, as a depth-bounded ray tracer drops it.
const MAX_SEGMENTS: u32 = 3u;
// Ray origins are pushed off the surface they start on by this much (metres).
const SURFACE_OFFSET: f32 = 1e-4;

// Incoming radiance at world point `origin` from direction `dir`, via the environment impostor.
fn env_lookup(origin: vec3f, dir: vec3f) -> vec3f {
    var lookup = dir;
    if (params.mode == MODE_CLASSIC || params.lookup == LOOKUP_DIRECTION) {
        lookup = dir;
    } else if (params.lookup == LOOKUP_BOX) {
        lookup = box_project(origin, dir, params.reference.xyz, params.proxy_min.xyz,
                             params.proxy_max.xyz).xyz;
    } else {
        let x = origin - params.reference.xyz;
        lookup = distance_map::hit(x, dir, env_distance, env_sampler, params.distance_channel,
                     params.method, params.iterations).xyz;
        // l at the reference point itself: any direction sees the same (ratio 0) - use R.
        if (dot(lookup, lookup) < 1e-12) { lookup = dir; }
    }
    // Plus the caustic on the surface seen there (caustic variants; zero otherwise).
    return textureSampleLevel(env_radiance, env_sampler, lookup, 0.0).rgb + caustic_radiance_at(lookup);
}

// One chord inside a refractor: from `pos` (world, inside) along `dir` to the exit point found
// by Hit() in the refractor map, with the stored outward normal there, the Fresnel reflectance
// of the exit and the refracted (w = 1) or, on total internal reflection, reflected (w = 0)
// direction out of refract_dir.
struct Chord {
    exit_point: vec3f,
    // Outward unit normal at the exit (turned to agree with dir).
    normal: vec3f,
    out: vec4f,
    fresnel: f32,
};

fn refractor_chord(pos: vec3f, dir: vec3f, ior: f32) -> Chord {
    let c = params.refractor_center.xyz;
    // Exit point: Hit() inside the refractor map (the object's surface seen from its centre).
    let h = distance_map::hit(pos - c, dir, refractor_map, env_sampler, 3u, distance_map::HIT_FALSE_POSITION,
                params.refractor_iterations);
    var l = h.xyz;
    if (dot(l, l) < 1e-12) { l = dir; }
    let stored = textureSampleLevel(refractor_map, env_sampler, l, 0.0);
    // The stored normal points outward; the ray leaves, so the facing normal is -N1.
    var n1 = stored.xyz;
    let n1_len = length(n1);
    n1 = select(dir, n1 / n1_len, n1_len > 1e-6);
    if (dot(n1, dir) < 0.0) { n1 = -n1; }
    var chord: Chord;
    chord.exit_point = c + h.xyz;
    chord.normal = n1;
    chord.fresnel = fresnel_dielectric(-dot(dir, -n1), 1.0 / ior);
    chord.out = refract_dir(dir, -n1, ior);
    return chord;
}

// Radiance carried out of a refractor along the refracted ray entering at `x` (world) with
// direction `t` inside glass of index `ior`.
fn through_refractor(x: vec3f, t: vec3f, ior: f32) -> vec3f {
    var pos = x;
    var dir = t;
    var weight = 1.0;
    var color = vec3f(0.0);
    for (var s = 0u; s < MAX_SEGMENTS; s++) {
        let chord = refractor_chord(pos, dir, ior);
        if (chord.out.w > 0.5) {
            color += weight * (1.0 - chord.fresnel) *
                env_lookup(chord.exit_point + chord.out.xyz * SURFACE_OFFSET, chord.out.xyz);
        }
        // Total internal reflection gives f = 1: all of it stays inside.
        weight *= select(chord.fresnel, 1.0, chord.out.w <= 0.5);
        dir = reflect_dir(dir, -chord.normal);
        pos = chord.exit_point - chord.normal * SURFACE_OFFSET;
    }
    return color;
}

virtual fn caustic_radiance_at(l: vec3f) -> vec3f {
    // The caustic radiance of the surface the impostor shows in direction l: none without
    // caustics (impostors::caustic overrides this).
    return vec3f(0.0);
}
