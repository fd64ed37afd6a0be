// ---------------------------------------------------------------------------------------------
// Many-object multi-bounce ray tracing (Dancsik and Minarik, sections 4.1-4.2 and 6): the
// tracer's bindings (@group(2), 0..6) and its paths, for the entry points that import it
// (trace_fs.wgsl; a technique's own passes over the same bindings, such as refractor-maps'
// photons). The per-object search is scene::pieces' piece_hit, piece_hit_normal and chord,
// which the search's module overrides (scene::multi_object::ObjectSearch).
//
// The specular objects are drawn with scene_vs: rasterization finds the first hit. From there
// each pixel follows the tree of reflected and refracted rays depth first (an explicit stack),
// splitting by Fresnel at every interface, until a ray has met `depth` interfaces:
//   - a ray inside a piece finds its exit by the search's chord();
//   - a ray outside finds the next piece through the board grid (nearest_piece), each candidate
//     searched from outside by the search's piece_hit(), or over every piece (the slow
//     exact-visibility search), or not at all (single bounce);
//   - a ray that finds no piece, or has met `depth` interfaces, takes the radiance of the
//     diffuse environment: Hit() in one distance impostor of the diffuse scene (rgb radiance +
//     distance, captured each frame from env_reference without the specular objects). A ray
//     inside glass at the depth bound leaves without splitting again (leave_piece).
// ---------------------------------------------------------------------------------------------
#define_import_path scene::trace

#import gpu::prelude::{fresnel_dielectric, fresnel_nk, reflect_dir, refract_dir}
#import gpu::distance_map
#import scene::shading::{MATERIAL_METAL, SceneVertexOut, camera, objects}
#import scene::pieces::{chord, piece_hit_normal, piece_object}
#import scene::grid_search::{GRID_EMPTY, Grid, PieceHit, nearest_piece, nearest_piece_brute}

struct TracerParams {
    // xyz: reference point of the environment impostor (world).
    env_reference: vec4f,
    grid: Grid,
    // Interfaces a path may meet (1 = the first surface only).
    depth: u32,
    // SEARCH_NONE, SEARCH_GRID or SEARCH_ALL.
    search: u32,
    // Occupied grid cells examined per ray (1: the paper's first non-empty square).
    max_cells: u32,
    piece_count: u32,
    // Refinement steps of Hit() in the environment impostor.
    env_iterations: u32,
    _pad_a: u32,
    _pad_b: u32,
    _pad_c: u32,
};

@group(2) @binding(0) var<uniform> tracer: TracerParams;
// @binding(1): the piece table (scene::pieces), @binding(2): the grid's cells (scene::grid_search).
// The piece of each scene object (GRID_EMPTY for a diffuse one).
@group(2) @binding(3) var<storage, read> piece_of_object: array<u32>;
@group(2) @binding(4) var env_sampler: sampler;
@group(2) @binding(5) var env_map: texture_cube<f32>;

const SEARCH_NONE: u32 = 0u;
const SEARCH_GRID: u32 = 1u;
const SEARCH_ALL: u32 = 2u;
// Deepest tree the stack holds (the depth parameter's maximum) and the stack size it needs.
const MAX_DEPTH: u32 = 8u;
const STACK_SIZE: u32 = 10u;
// Ray origins are pushed off the surface they start on by this much (metres).
const SURFACE_OFFSET: f32 = 1e-4;

// Radiance of the diffuse environment arriving at `o` from direction `d`.
fn environment(o: vec3f, d: vec3f) -> vec3f {
    var l = distance_map::hit(o - tracer.env_reference.xyz, d, env_map, env_sampler, 3u, distance_map::HIT_FALSE_POSITION,
                tracer.env_iterations).xyz;
    if (dot(l, l) < 1e-12) { l = d; }
    return textureSampleLevel(env_map, env_sampler, l, 0.0).rgb;
}

// The next piece along an outside ray, per the search mode.
fn next_piece(o: vec3f, d: vec3f, skip: u32) -> PieceHit {
    if (tracer.search == SEARCH_ALL) {
        return nearest_piece_brute(tracer.piece_count, o, d, skip);
    }
    return nearest_piece(tracer.grid, o, d, skip, tracer.max_cells);
}

struct PathRay {
    origin: vec3f,
    dir: vec3f,
    weight: vec3f,
    // Interfaces met so far.
    depth: u32,
    // The piece the ray travels inside, or GRID_EMPTY outside.
    inside: u32,
    // The piece an outside ray just left (not searched: the paper's N - 1 searches).
    skip: u32,
};

fn path_ray(origin: vec3f, dir: vec3f, weight: vec3f, depth: u32, inside: u32, skip: u32) -> PathRay {
    var r: PathRay;
    r.origin = origin;
    r.dir = dir;
    r.weight = weight;
    r.depth = depth;
    r.inside = inside;
    r.skip = skip;
    return r;
}

var<private> stack: array<PathRay, STACK_SIZE>;
var<private> stack_top: u32 = 0u;

fn push(r: PathRay) {
    // Negligible weights are not followed (nor would they change the image).
    if (stack_top < STACK_SIZE && max(r.weight.x, max(r.weight.y, r.weight.z)) > 1e-4) {
        stack[stack_top] = r;
        stack_top++;
    }
}

// A ray meeting piece p's surface at `point` with outward normal `n_out`: push its reflected
// and (glass) refracted continuations.
fn scatter(r: PathRay, p: u32, point: vec3f, n_out: vec3f) {
    let o = objects[piece_object(p)];
    let entering = dot(r.dir, n_out) < 0.0;
    let n = select(-n_out, n_out, entering);
    let cos_i = -dot(r.dir, n);
    let depth = r.depth + 1u;
    let reflected = reflect_dir(r.dir, n);
    if (o.material.x == MATERIAL_METAL) {
        let f = fresnel_nk(cos_i, o.n.xyz, o.k.xyz);
        push(path_ray(point + n * SURFACE_OFFSET, reflected, r.weight * f, depth, GRID_EMPTY, p));
        return;
    }
    let eta_rel = select(1.0 / o.material.y, o.material.y, entering);
    let f = fresnel_dielectric(cos_i, eta_rel);
    let refracted = refract_dir(r.dir, n, 1.0 / eta_rel);
    // Reflection stays on the side the ray came from.
    push(path_ray(point + n * SURFACE_OFFSET, reflected, r.weight * f, depth,
                  select(p, GRID_EMPTY, entering), p));
    if (refracted.w > 0.5) {
        push(path_ray(point - n * SURFACE_OFFSET, refracted.xyz, r.weight * (1.0 - f), depth,
                      select(GRID_EMPTY, p, entering), p));
    }
}

// Radiance of one popped ray's own contribution (the environment it reaches), its
// continuations pushed.
fn follow(r: PathRay) -> vec3f {
    if (r.inside != GRID_EMPTY) {
        if (r.depth >= tracer.depth) {
            return r.weight * leave_piece(r);
        }
        let c = chord(r.inside, r.origin, r.dir);
        scatter(r, r.inside, c.exit_point, c.normal);
        return vec3f(0.0);
    }
    if (r.depth >= tracer.depth || tracer.search == SEARCH_NONE) {
        return r.weight * environment(r.origin, r.dir);
    }
    let h = next_piece(r.origin, r.dir, r.skip);
    if (h.piece == GRID_EMPTY) {
        return r.weight * environment(r.origin, r.dir);
    }
    let point = r.origin + r.dir * h.hit.w;
    // The ray comes from outside: the outward normal must face it (a map's filtered normal
    // can point along the ray at a silhouette or where the piece is not star-shaped).
    var n_out = piece_hit_normal(h.piece, r.origin, r.dir, h.hit);
    if (dot(n_out, r.dir) > 0.0) { n_out = -n_out; }
    scatter(r, h.piece, point, n_out);
    return vec3f(0.0);
}

// A ray inside glass at the depth bound leaves without splitting again: up to
// EXIT_CHORDS chords (the internally reflected share goes on to the next), the refracted
// share of each exit taking the diffuse environment (as impostors/double-refraction does).
const EXIT_CHORDS: u32 = 3u;

fn leave_piece(r: PathRay) -> vec3f {
    let ior = objects[piece_object(r.inside)].material.y;
    var origin = r.origin;
    var dir = r.dir;
    var share = 1.0;
    var color = vec3f(0.0);
    for (var s = 0u; s < EXIT_CHORDS; s++) {
        let c = chord(r.inside, origin, dir);
        let out = refract_dir(dir, -c.normal, ior);
        let f = select(1.0, fresnel_dielectric(dot(dir, c.normal), 1.0 / ior), out.w > 0.5);
        if (out.w > 0.5) {
            color += share * (1.0 - f) * environment(c.exit_point + c.normal * SURFACE_OFFSET, out.xyz);
        }
        share *= f;
        dir = reflect_dir(dir, -c.normal);
        origin = c.exit_point - c.normal * SURFACE_OFFSET;
    }
    return color;
}

// The colour of the pixel whose first interface is the rasterized fragment `in` of a piece
// (its world point and interpolated normal), and in alpha its distance from the eye.
fn trace_pixel(in: SceneVertexOut) -> vec4f {
    let eye = camera.eye.xyz;
    let dir = normalize(in.world - eye);
    let p = piece_of_object[in.object];
    // The first interface from the rasterized surface and its interpolated normal (turned
    // outward: the eye may be inside the glass).
    let n_out = normalize(in.normal);
    var color = vec3f(0.0);
    stack_top = 0u;
    let first = path_ray(eye, dir, vec3f(1.0), 0u, GRID_EMPTY, GRID_EMPTY);
    scatter(first, p, in.world, n_out);
    // Every node of a tree of depth MAX_DEPTH at most.
    for (var visited = 0u; visited < 512u && stack_top > 0u; visited++) {
        stack_top--;
        color += follow(stack[stack_top]);
    }
    return vec4f(color, distance(in.world, eye));
}
