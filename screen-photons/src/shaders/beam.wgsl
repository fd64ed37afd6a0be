// ---------------------------------------------------------------------------------------------
// A photon beam on the image (section 3.2): the part drawn, and what its band adds at a pixel.
// The twin of `src/shafts.rs` (`beam_band`, `beam_fragment`), with the same arguments: pure
// functions of the view (`ShaftView`), the medium and a `Beam`. No
// early returns: lavapipe (Mesa 22.3) crashed in the band pass's fragment stage with them, as
// in refractor-maps' photon_fs (its README, "llvmpipe"). The reverse happens too:
// `medium_clip` written with selects made it crash ("stack smashing") in the froxel passes,
// so that one keeps its returns.
// ---------------------------------------------------------------------------------------------
#define_import_path screen_photons::beam

#import scene::medium::{EYE_CLEARANCE, Medium, henyey_greenstein, medium_clip, medium_extinction, medium_transmittance, transmittance_of}
#import scene::shading::CAMERA_NEAR

// A photon ray of one march round, for the light shafts (section 3.2): written by the resolve.
struct Beam {
    // xyz: where the photon left its last specular surface; w: 1 for a beam, 0 for none.
    origin: vec4f,
    // xyz: unit direction; w: length to its first hit (or to where it leaves the scene).
    dir: vec4f,
    // rgb: flux at the origin (W); w: how the photon ended there: 1 on a diffuse surface, 2
    // where it left the scene's box (the view lost it), 0 at a specular surface (it goes on).
    power: vec4f,
};

struct ShaftView {
    view_proj: mat4x4f,
    // xyz: the eye; w: a pixel's area on the image plane at unit distance.
    eye: vec4f,
    // xyz: the view direction; w: the blur's standard deviation (pixels).
    forward: vec4f,
    // width, height, beams, blur direction (0: along x, 1: along y).
    size: vec4u,
};

const BAND_HALF_WIDTH: f32 = 1.0;

struct BeamBand {
    s_start: f32,
    s_end: f32,
    s_enter: f32,
    p_start: vec2f,
    p_end: vec2f,
    x_major: bool,
    ok: bool,
};

fn shaft_pixel_of_clip(shaft: ShaftView, c: vec4f) -> vec2f {
    let size = vec2f(shaft.size.xy);
    return vec2f((c.x / c.w + 1.0) * 0.5 * size.x, (1.0 - c.y / c.w) * 0.5 * size.y);
}

// The part of beam b drawn, seen by `shaft`, in the medium m: inside the medium, in front of the near plane, projected.
fn beam_band(shaft: ShaftView, m: Medium, b: Beam) -> BeamBand {
    var band: BeamBand;
    let inside = medium_clip(m, b.origin.xyz, b.dir.xyz, b.dir.w);
    let near = 2.0 * CAMERA_NEAR;
    let z0 = dot(b.origin.xyz - shaft.eye.xyz, shaft.forward.xyz);
    let dz = dot(b.dir.xyz, shaft.forward.xyz);
    var s0 = inside.x;
    var s1 = inside.y;
    var in_front = true;
    if (abs(dz) < 1e-9) {
        in_front = z0 > near;
    } else {
        let s_near = (near - z0) / dz;
        if (dz > 0.0) { s0 = max(s0, s_near); } else { s1 = min(s1, s_near); }
    }
    band.s_start = s0;
    band.s_end = s1;
    band.s_enter = inside.x;
    band.p_start = shaft_pixel_of_clip(shaft, shaft.view_proj * vec4f(b.origin.xyz + b.dir.xyz * s0, 1.0));
    band.p_end = shaft_pixel_of_clip(shaft, shaft.view_proj * vec4f(b.origin.xyz + b.dir.xyz * s1, 1.0));
    let d = abs(band.p_end - band.p_start);
    band.x_major = d.x >= d.y;
    band.ok = b.origin.w > 0.5 && inside.x < inside.y && in_front && s0 < s1
        && all(abs(band.p_start) < vec2f(1e7)) && all(abs(band.p_end) < vec2f(1e7));
    return band;
}

// What the band of b adds at the pixel centre `pixel`; `surface` is the distance to the
// pixel's first surface.
fn beam_fragment(shaft: ShaftView, m: Medium, b: Beam, band: BeamBand, pixel: vec2f, surface: f32) -> vec3f {
    let c0 = shaft.view_proj * vec4f(b.origin.xyz, 1.0);
    let cd = shaft.view_proj * vec4f(b.dir.xyz, 0.0);
    var major = pixel.y;
    var size = f32(shaft.size.y);
    var sgn = -1.0;
    var a0 = c0.y;
    var ad = cd.y;
    if (band.x_major) {
        major = pixel.x;
        size = f32(shaft.size.x);
        sgn = 1.0;
        a0 = c0.x;
        ad = cd.x;
    }
    let ndc = sgn * (2.0 * major / size - 1.0);
    let denom = ad - ndc * cd.w;
    let solvable = abs(denom) >= 1e-20;
    let safe = select(1.0, denom, solvable);
    let s = (ndc * c0.w - a0) / safe;
    let ds_dpixel = abs((c0.w * ad - a0 * cd.w) / (safe * safe) * 2.0 / size);
    let x = b.origin.xyz + b.dir.xyz * s;
    let p = shaft_pixel_of_clip(shaft, c0 + cd * s);
    let across = select(pixel.x - p.x, pixel.y - p.y, band.x_major);
    let tent = max(1.0 - abs(across) / BAND_HALF_WIDTH, 0.0) / BAND_HALF_WIDTH;
    let to_eye = shaft.eye.xyz - x;
    let d = length(to_eye);
    let w_c = to_eye / max(d, 1e-30);
    let cos_camera = dot(shaft.forward.xyz, -w_c);
    let ok = band.ok && solvable && s >= band.s_start && s <= band.s_end && tent > 0.0 && d >= EYE_CLEARANCE
        && d < surface && cos_camera > 0.0;
    var l = vec3f(0.0);
    if (ok) {
        let importance = 1.0 / (shaft.eye.w * cos_camera * cos_camera * cos_camera);
        let along_beam = transmittance_of(medium_extinction(m), s - band.s_enter);
        let toward_eye = medium_transmittance(m, x, w_c, d);
        let phase = henyey_greenstein(dot(b.dir.xyz, w_c), m.max.w);
        l = b.power.rgb * along_beam * m.scattering.rgb * toward_eye
            * (phase * importance / (d * d) * ds_dpixel * tent);
    }
    return l;
}

