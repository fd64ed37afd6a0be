// ---------------------------------------------------------------------------------------------
// Refractor height maps on camera-facing billboards (Dancsik and Minarik, section 6); imports
// gpu::prelude, scene::shading, gpu::distance_map and height_maps::search (given the height
// maps bound here) and height_maps::billboard_box.
//
// Each piece is drawn as the bounding box of its proxy, turned about the vertical axis to face
// the eye. A fragment casts the eye ray into the box and searches the kind's height map from
// outside (search_from_outside); a miss is discarded, a hit writes its own depth. At the hit the
// ray splits by Fresnel: the reflected ray takes the diffuse environment (one distance
// impostor of the diffuse scene, as refractor-maps' tracer); the refracted ray takes it at
// once (REFRACTION_SINGLE) or first leaves the piece through the second search
// (exit_from_inside, REFRACTION_DOUBLE), chords that meet the surface beyond the critical
// angle reflecting on.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{fresnel_dielectric, reflect_dir, refract_dir}
#import gpu::distance_map
#import scene::shading::{camera, objects, specular_event, specular_shade}
#import height_maps::search::{Steps, HeightBounds, Billboard, billboard_facing, dir_to_plane, to_plane, dir_to_world, search_from_outside, exit_from_inside}
#import height_maps::billboard_box::{BillboardOut, BillboardTargets, billboard_out, faces_eye, frag_depth_of}

struct PieceGpu {
    // World centre now; w: the kind's layer in height_maps.
    centre: vec4f,
    // The kind's bounds: half width, v min, v max, height.
    bounds: vec4f,
    // x: scene object index.
    object: vec4u,
};

struct BillboardParams {
    // xyz: reference point of the environment impostor (world).
    env_reference: vec4f,
    // The searches' steps: linear bracket, binary halvings (a Steps; flat, since a uniform
    // block's member after a struct must start on 16 bytes).
    linear_steps: u32,
    binary_steps: u32,
    // REFRACTION_SINGLE or REFRACTION_DOUBLE; Hit() steps in the environment impostor; chords
    // followed inside a piece.
    refraction: u32,
    env_iterations: u32,
    chords: u32,
    _pad: u32,
};

@group(2) @binding(0) var<uniform> params: BillboardParams;
@group(2) @binding(1) var<storage, read> pieces: array<PieceGpu>;
@group(2) @binding(2) var height_maps: texture_2d_array<f32>;
@group(2) @binding(3) var env_map: texture_cube<f32>;
@group(2) @binding(4) var env_sampler: sampler;

const REFRACTION_SINGLE: u32 = 0u;
const REFRACTION_DOUBLE: u32 = 1u;
// Ray origins are pushed off the surface they start on by this much (metres).
const SURFACE_OFFSET: f32 = 1e-4;

fn search_steps() -> Steps {
    return Steps(params.linear_steps, params.binary_steps);
}

fn piece_bounds(p: u32) -> HeightBounds {
    let b = pieces[p].bounds;
    return HeightBounds(b.x, b.y, b.z, b.w);
}

fn piece_layer(p: u32) -> i32 {
    return i32(pieces[p].centre.w);
}

// Radiance of the diffuse environment arriving at `o` from direction `d`.
fn environment(o: vec3f, d: vec3f) -> vec3f {
    var l = distance_map::hit(o - params.env_reference.xyz, d, env_map, env_sampler, 3u, distance_map::HIT_FALSE_POSITION,
                params.env_iterations).xyz;
    if (dot(l, l) < 1e-12) { l = d; }
    return textureSampleLevel(env_map, env_sampler, l, 0.0).rgb;
}

@vertex
fn billboard_vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) piece: u32) -> BillboardOut {
    return billboard_out(vertex, piece, pieces[piece].centre.xyz, piece_bounds(piece));
}

// The refracted share of a ray inside piece p from `point` along `dir`, leaving it: up to
// params.chords chords, each exit refracting out (its Fresnel-reflected share going on inside).
fn leave_piece(p: u32, b: Billboard, point: vec3f, dir: vec3f, ior: f32) -> vec3f {
    let hb = piece_bounds(p);
    let layer = piece_layer(p);
    var origin = point;
    var d = dir;
    var share = 1.0;
    var color = vec3f(0.0);
    for (var s = 0u; s < params.chords; s++) {
        let e = exit_from_inside(height_maps, layer, hb, to_plane(b, origin), dir_to_plane(b, d), search_steps());
        if (!e.found) {
            // Not inside the proxy after all (the entry's offset left it): the ray goes on.
            color += share * environment(origin, d);
            break;
        }
        let exit_point = origin + d * e.t;
        var n = dir_to_world(b, e.normal);
        if (dot(n, d) < 0.0) { n = -n; }
        let out = refract_dir(d, -n, ior);
        let f = select(1.0, fresnel_dielectric(dot(d, n), 1.0 / ior), out.w > 0.5);
        if (out.w > 0.5) {
            color += share * (1.0 - f) * environment(exit_point + n * SURFACE_OFFSET, out.xyz);
        }
        share *= f;
        d = reflect_dir(d, -n);
        origin = exit_point - n * SURFACE_OFFSET;
    }
    return color;
}

@fragment
fn billboard_fs(in: BillboardOut) -> BillboardTargets {
    let eye = camera.eye.xyz;
    // Only the faces toward the eye search (each pixel of the box once).
    if (!faces_eye(in.face_normal, in.world, eye)) { discard; }
    let p = in.piece;
    let dir = normalize(in.world - eye);
    let b = billboard_facing(pieces[p].centre.xyz, eye);
    let h = search_from_outside(height_maps, piece_layer(p), piece_bounds(p), to_plane(b, eye), dir_to_plane(b, dir),
                             search_steps());
    if (!h.found) { discard; }
    let point = eye + dir * h.t;
    var n = dir_to_world(b, h.normal);
    if (dot(n, dir) > 0.0) { n = -n; }
    let object = pieces[p].object.x;
    let e = specular_event(object, n, point, eye, dir);
    let reflected = environment(point + e.normal * SURFACE_OFFSET, e.reflected);
    var refracted = vec3f(0.0);
    if (!e.is_metal && e.refracted.w > 0.5) {
        let inside = point - e.normal * SURFACE_OFFSET;
        if (params.refraction == REFRACTION_DOUBLE) {
            refracted = leave_piece(p, b, inside, e.refracted.xyz, objects[object].material.y);
        } else {
            refracted = environment(inside, e.refracted.xyz);
        }
    }
    var out: BillboardTargets;
    out.color = vec4f(specular_shade(e, reflected, refracted), distance(point, eye));
    out.depth = frag_depth_of(camera.view_proj, point);
    return out;
}
