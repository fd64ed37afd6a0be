// ---------------------------------------------------------------------------------------------
// Caustics (Dancsik and Minarik, section 7): the photon map of each piece, over the tracer's
// bindings (scene::trace) with the refractor-map search, importing scene::chart and
// scene::receiver.
//
// Each piece is drawn from the light into its own tile of a photon map: rasterization finds
// where the light's ray meets the piece, then the photon refracts in (the Fresnel-transmitted
// share), leaves through the piece's refractor map (chord(), TIR chords reflect on; a mirror
// piece reflects it instead) and lands on the receiver's plane (the chessboard), whose
// light-map address is stored "in texture space". As in the paper, the photon does not meet
// other pieces on its way. splat_quads.wgsl (scene::lightmap::QuadSplatter) then adds a
// Gaussian quad per photon into the light map.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{fresnel_dielectric, ray_plane, reflect_dir, refract_dir}
#import scene::shading::{SceneVertexOut, emission_jitter, in_cutout_hole, jittered_emission, objects, specular_event}
#import scene::chart::{Chart, chart_uv}
#import scene::receiver::world_to_local
#import scene::trace::{SURFACE_OFFSET, piece_of_object}
#import scene::pieces::chord
#import scene::grid_search::GRID_EMPTY

struct PhotonParams {
    // The receiver's light-map chart (the only chart of the atlas).
    chart: Chart,
    // The receiver's plane in the world, dot(plane.xyz, x) = plane.w, plane.xyz facing the
    // pieces.
    plane: vec4f,
    // Receiver object, photon-map tile side (pixels), tiles per row, the chart's index.
    object: u32,
    tile: u32,
    tiles_per_row: u32,
    chart_index: u32,
    // 1: each photon leaves from a random point of its pixel (jittered_emission), 0: centre.
    jitter: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

struct PhotonTile {
    // Light position; w unused.
    light: vec4f,
    // Light intensity (W/sr).
    intensity: vec4f,
    // Unit axis of the tile's view; w: area of one tile pixel on the image plane at unit
    // distance, (2 tan(fov / 2) / tile)^2.
    axis: vec4f,
};

@group(3) @binding(0) var<uniform> photons: PhotonParams;
@group(3) @binding(1) var<storage, read> photon_tiles: array<PhotonTile>;

// Chords a refracted photon follows inside a piece before it is given up (a chord meeting
// the surface beyond the critical angle reflects on).
const PHOTON_CHORDS: u32 = 3u;

struct PhotonRay {
    origin: vec3f,
    dir: vec3f,
    // Share of the light's flux it carries (0: it did not leave the piece).
    weight: vec3f,
};

// The photon of the light ray that meets piece p at the rasterized fragment `in`, as it
// leaves the piece.
fn photon_through_piece(p: u32, in: SceneVertexOut, light: vec3f) -> PhotonRay {
    var r: PhotonRay;
    r.weight = vec3f(0.0);
    let e = specular_event(in.object, in.normal, in.world, light, normalize(in.world - light));
    if (e.is_metal) {
        r.origin = in.world + e.normal * SURFACE_OFFSET;
        r.dir = e.reflected;
        r.weight = e.reflectance;
        return r;
    }
    if (e.refracted.w < 0.5) { return r; }
    let ior = objects[in.object].material.y;
    var weight = vec3f(1.0 - e.reflectance.x);
    var origin = in.world - e.normal * SURFACE_OFFSET;
    var dir = e.refracted.xyz;
    for (var s = 0u; s < PHOTON_CHORDS; s++) {
        let c = chord(p, origin, dir);
        let out = refract_dir(dir, -c.normal, ior);
        if (out.w > 0.5) {
            r.weight = weight * (1.0 - fresnel_dielectric(dot(dir, c.normal), 1.0 / ior));
            r.origin = c.exit_point + c.normal * SURFACE_OFFSET;
            r.dir = out.xyz;
            return r;
        }
        dir = reflect_dir(dir, -c.normal);
        origin = c.exit_point - c.normal * SURFACE_OFFSET;
    }
    return r;
}

// Unclamped chart coordinates of object-space point `local`: (0, 0) to the chart's
// aspect-ratio corner inside it (chart_uv's `s` before its clamp).
fn chart_coords(c: Chart, local: vec3f) -> vec2f {
    return (vec2f(local[c.axes.x], local[c.axes.y]) - c.bounds.xy) / c.bounds.z;
}

struct PhotonTargets {
    // Light-map address: atlas uv, chart index, w = 1 (w = 0: no photon).
    @location(0) address: vec4f,
    // Photon power (W); w unused.
    @location(1) power: vec4f,
};

@fragment
fn photon_fs(pixel_in: SceneVertexOut) -> PhotonTargets {
    // Derivatives first: naga's discard ends the invocation, so none may follow it.
    let jitter = emission_jitter(pixel_in.clip.xy, 0u) * f32(photons.jitter);
    let in = jittered_emission(pixel_in, jitter);
    if (in_cutout_hole(pixel_in.object, pixel_in.uv)) { discard; }
    var out: PhotonTargets;
    out.address = vec4f(0.0);
    out.power = vec4f(0.0);
    let p = piece_of_object[in.object];
    if (p == GRID_EMPTY) { return out; }
    let pixel = vec2u(in.clip.xy);
    let t = photon_tiles[(pixel.y / photons.tile) * photons.tiles_per_row + pixel.x / photons.tile];
    let light = t.light.xyz;
    let r = photon_through_piece(p, in, light);
    if (max(r.weight.x, max(r.weight.y, r.weight.z)) <= 0.0) { return out; }
    // The photon hit: the receiver's plane, from its lit side, inside its chart.
    if (dot(r.dir, photons.plane.xyz) >= 0.0) { return out; }
    let s = ray_plane(r.origin, r.dir, photons.plane.xyz, photons.plane.w);
    if (s <= 0.0) { return out; }
    let local = world_to_local(photons.object, r.origin + r.dir * s);
    let c = photons.chart;
    // Inside the chart: its projection of the landing point lies within the chart's extent
    // (chart_uv would clamp it onto the border).
    let span = c.rect.zw - c.rect.xy;
    let limit = span / max(span.x, span.y);
    let a = chart_coords(c, local);
    let inside = a.x >= 0.0 && a.y >= 0.0 && a.x <= limit.x && a.y <= limit.y;
    // Flux through this pixel: I * solid angle, solid angle = area * cos^3 off the axis.
    let cos_axis = dot(normalize(in.world - light), t.axis.xyz);
    let solid_angle = t.axis.w * cos_axis * cos_axis * cos_axis;
    // (No early return here: one made llvmpipe's fragment shader crash at draw time.)
    out.address = select(vec4f(0.0), vec4f(chart_uv(c, local), f32(photons.chart_index), 1.0), inside);
    out.power = select(vec4f(0.0), vec4f(t.intensity.rgb * solid_angle * r.weight, 0.0), inside);
    return out;
}
