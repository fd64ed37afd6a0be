#define_import_path scene::medium
// ---------------------------------------------------------------------------------------------
// A homogeneous scattering medium in an axis-aligned box (scene::medium, its Rust twin): the
// box clipping, Beer-Lambert transmittance and the Henyey-Greenstein phase function. Pure
// functions of a `Medium` value (the module scene::medium); scene.wgsl holds the medium in
// `scene_info.medium` and `scene_medium()` returns it.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{PI, ray_box}

// The medium within this distance of the eye is not counted (scene::medium::EYE_CLEARANCE).
const EYE_CLEARANCE: f32 = 0.1;

struct Medium {
    // xyz: the box's lower corner; w: 1 when the scene has a medium, 0 when not.
    min: vec4f,
    // xyz: the upper corner; w: Henyey-Greenstein asymmetry g.
    max: vec4f,
    // rgb: scattering coefficient sigma_s per metre.
    scattering: vec4f,
    // rgb: absorption coefficient sigma_a per metre.
    absorption: vec4f,
};

fn medium_present(m: Medium) -> bool {
    return m.min.w > 0.5;
}

fn medium_extinction(m: Medium) -> vec3f {
    return m.scattering.rgb + m.absorption.rgb;
}

// The part (t0, t1) of o + t d, t in [0, t_max], inside the box; t0 >= t1 when there is none
// (and always when the scene has no medium).
fn medium_clip(m: Medium, o: vec3f, d: vec3f, t_max: f32) -> vec2f {
    if (!medium_present(m)) { return vec2f(0.0); }
    let t = ray_box(o, d, m.min.xyz, m.max.xyz);
    let t0 = max(t.x, 0.0);
    let t1 = min(t.y, t_max);
    if (t.x > t.y || t0 >= t1) { return vec2f(0.0); }
    return vec2f(t0, t1);
}

fn transmittance_of(extinction: vec3f, length: f32) -> vec3f {
    return exp(-extinction * length);
}

// Beer-Lambert transmittance along o + t d (unit d), t in [0, t_max].
fn medium_transmittance(m: Medium, o: vec3f, d: vec3f, t_max: f32) -> vec3f {
    let t = medium_clip(m, o, d, t_max);
    return transmittance_of(medium_extinction(m), max(t.y - t.x, 0.0));
}

// Transmittance of the segment from a to b.
fn medium_transmittance_between(m: Medium, a: vec3f, b: vec3f) -> vec3f {
    let len = length(b - a);
    if (len <= 0.0) { return vec3f(1.0); }
    return medium_transmittance(m, a, (b - a) / len, len);
}

// Henyey-Greenstein (per steradian), cos_theta between the direction light travels in and the
// direction it leaves in.
fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = max(1.0 + g * g - 2.0 * g * clamp(cos_theta, -1.0, 1.0), 1e-12);
    return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}
