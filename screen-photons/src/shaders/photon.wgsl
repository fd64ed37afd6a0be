// ---------------------------------------------------------------------------------------------
// Photons and receiver points: the structs the photon passes share, and their helpers
// over the LDI (`screen_photons::ldi`). No bindings of its own: each pass file declares its
// @group(3).
// ---------------------------------------------------------------------------------------------
#define_import_path screen_photons::photon

#import screen_photons::ldi::{LdiHit, Segment, clip_segment, ldi_layers, scene_range}

// A photon after its last specular event so far: the transfer map's entry (section 2).
struct Photon {
    // xyz: where it left its last specular surface; w: 1 while it travels, 0 when it is done.
    origin: vec4f,
    // xyz: unit direction; w: 1 when it travels inside glass.
    dir: vec4f,
    // rgb: flux (W); w: specular events so far after the transfer map.
    power: vec4f,
};

// Where a photon ended on a diffuse surface: a receiver point (section 3).
struct Receiver {
    // xyz: the point; w: 1 = a photon landed, 0 = none.
    position: vec4f,
    // xyz: the surface normal facing the incoming photon.
    normal: vec4f,
    // rgb: flux (W).
    power: vec4f,
};

// A march's result in the hit buffer: x = ray parameter (0: no hit), y = layer, zw = pixel.
fn pack_hit(h: LdiHit) -> vec4f {
    return select(vec4f(0.0), vec4f(h.t, f32(h.layer), vec2f(h.pixel)), h.found);
}

fn photon_is_inside(p: Photon) -> bool {
    return p.dir.w > 0.5;
}

// The visible part of a photon ray, in view of the LDI's eye.
fn photon_segment(p: Photon) -> Segment {
    let range = scene_range(p.origin.xyz, p.dir.xyz);
    return clip_segment(p.origin.xyz, p.dir.xyz, range.x, range.y);
}

// The distance to the first surface seen in pixel (x, y) (infinite where there is none).
fn surface_distance(x: u32, y: u32) -> f32 {
    let d = textureLoad(ldi_layers, vec2u(x, y), 0, 0).w;
    return select(1e30, d, d > 0.0);
}
