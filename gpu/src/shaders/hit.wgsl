#define_import_path gpu::distance_map
#import gpu::prelude::ray_box

// ---------------------------------------------------------------------------------------------
// Hit(): approximate ray hit against a distance impostor (Szirmay-Kalos et al. 2005, sections
// 2.1-2.2 and the Hit listing of section 3). Rust twin: gpu/src/distance_map.rs (same algorithm,
// same constants, same names); impostors/tests/gpu_conformance.rs compares the two.
//
// Coordinates are relative to the map's reference point o. The map's channel `channel` holds
// the distance from o of the surface seen in each direction (3: alpha of a packed
// radiance+distance map, 0: a separate distance texture). For a point y = x + R d the ratio
// g(d) = |y| / dist(y) is < 1 for an undershooting point (in front of the surface) and > 1 for
// an overshooting one; the hit is the root of g(d) = 1 (linear in d against a plane).
// ---------------------------------------------------------------------------------------------

// Floor of a distance read from the map (a reference point on a wall reads 0).
const HIT_DIST_EPSILON: f32 = 1e-6;
// Points this close to o have ratio 0 (certainly undershooting).
const HIT_MIN_LENGTH: f32 = 1e-6;
// Secant steps with |g_l - g_a| below this are skipped (the listing would divide by zero).
const HIT_DENOM_EPSILON: f32 = 1e-7;
// Upper clamp of the ray parameter (keeps a divergent secant finite).
const HIT_D_MAX: f32 = 1.0e5;

const HIT_SECANT: u32 = 0u;
const HIT_FALSE_POSITION: u32 = 1u;

fn hit_distance(map: texture_cube<f32>, smp: sampler, channel: u32, dir: vec3f) -> f32 {
    return textureSampleLevel(map, smp, dir, 0.0)[channel];
}

// g = |y| / |y'|: the accuracy of approximation point y (1 on the surface).
fn hit_ratio(map: texture_cube<f32>, smp: sampler, channel: u32, y: vec3f) -> f32 {
    let len = length(y);
    if (len < HIT_MIN_LENGTH) { return 0.0; }
    return len / max(hit_distance(map, smp, channel, y), HIT_DIST_EPSILON);
}

fn hit_clamp_d(d: f32) -> f32 {
    return min(max(d, 0.0), HIT_D_MAX);
}

// Approximate hit of the ray x + R d (x relative to the reference point, R unit length).
// Returns (l, d_l): the hit approximation l = x + R d_l, whose direction looks up the map.
fn hit(x: vec3f, R: vec3f, map: texture_cube<f32>, smp: sampler, channel: u32,
       method: u32, iterations: u32) -> vec4f {
    // |r|: r = R |r| is what classic environment mapping would show.
    let r_len = max(hit_distance(map, smp, channel, R), HIT_DIST_EPSILON);
    // First guess: the surface at r is perpendicular to R (eq. 2).
    let d_p = hit_clamp_d(r_len - dot(R, x));
    let g_p = hit_ratio(map, smp, channel, x + R * d_p);
    // Second guess: the surface is planar between r and p' (eq. 4).
    var d_l = hit_clamp_d(d_p + r_len * (1.0 - g_p));

    // Last undershooting and overshooting samples (false position); previous sample (secant).
    var has_under = g_p < 1.0;
    var has_over = !has_under;
    var d_under = d_p; var g_under = g_p;
    var d_over = d_p; var g_over = g_p;
    var d_prev = d_p; var g_prev = g_p;

    for (var i = 0u; i < iterations; i++) {
        let g_l = hit_ratio(map, smp, channel, x + R * d_l);
        var has_partner = true;
        var d_a: f32; var g_a: f32;
        if (method == HIT_SECANT) {
            d_a = d_prev; g_a = g_prev;
            d_prev = d_l; g_prev = g_l;
        } else if (g_l < 1.0) { // undershooting: pair with the last overshoot
            d_under = d_l; g_under = g_l;
            has_under = true;
            has_partner = has_over; d_a = d_over; g_a = g_over;
        } else {                // overshooting: pair with the last undershoot
            d_over = d_l; g_over = g_l;
            has_over = true;
            has_partner = has_under; d_a = d_under; g_a = g_under;
        }
        var step: f32;
        if (has_partner) {
            // Chord through l and the partner (eq. 6).
            let denom = g_l - g_a;
            step = select((d_l - d_a) * (1.0 - g_l) / denom, 0.0, abs(denom) < HIT_DENOM_EPSILON);
        } else {
            // Chord through l and the ideal point at infinity of r (slope 1/|r|).
            step = r_len * (1.0 - g_l);
        }
        d_l = hit_clamp_d(d_l + step);
    }
    return vec4f(x + R * d_l, d_l);
}

// ---------------------------------------------------------------------------------------------
// Search from outside (Dancsik and Minarik, section 4.1): the ray y + R d (relative to the map's
// reference point, R unit length) against the object the map represents. Rust twin:
// gpu/src/distance_map.rs `hit_from_outside` (see its docs). Intersect the bounding box
// [bmin, bmax]; run hit() from the far box point along -R; accept the result when the map's
// surface point in its direction lies within `epsilon` of the ray and ahead of y.
// Returns (point on the ray, d on the original ray), or (0, 0, 0, -1) for no hit.
// ---------------------------------------------------------------------------------------------

const HIT_NONE: vec4f = vec4f(0.0, 0.0, 0.0, -1.0);

fn hit_from_outside(y: vec3f, R: vec3f, map: texture_cube<f32>, smp: sampler, channel: u32,
                    bmin: vec3f, bmax: vec3f, method: u32, iterations: u32,
                    epsilon: f32) -> vec4f {
    let t = ray_box(y, R, bmin, bmax);
    if (t.x > t.y || t.y <= 0.0) { return HIT_NONE; }
    let x = y + R * t.y;
    let h = hit(x, -R, map, smp, channel, method, iterations);
    let d = t.y - h.w;
    let len = length(h.xyz);
    if (len < HIT_MIN_LENGTH || d < 0.0) { return HIT_NONE; }
    let surface = h.xyz / len * hit_distance(map, smp, channel, h.xyz);
    if (length(surface - h.xyz) > epsilon) { return HIT_NONE; }
    return vec4f(h.xyz, d);
}
