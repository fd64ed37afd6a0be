// ---------------------------------------------------------------------------------------------
// Pieces shaded with per-piece environment distance impostors and refractor maps (Dancsik and
// Minarik, section 5), after the gpu prelude + scene.wgsl + hit.wgsl + the layered Hit()
// (gpu::distance_map::layered_hit_wgsl) + pieces.wgsl. All pieces are drawn in one call with one bind group:
// piece p's environment impostor (rgb radiance, alpha distance from env_centres[p]) is cube p
// of `impostors`, the refractor map of its kind (outward normal, distance from its centre) is
// cube `kind` of `kind_maps`.
//
// A piece's pixel: reflection -> Hit() in its environment impostor; refraction -> through its
// refractor map (Hit() from inside for the exit, up to EXIT_CHORDS internal reflections), each
// exit ray -> Hit() in the environment impostor. These are the paper's "three intersections";
// the impostor holds multi-bounce radiance because the pieces were drawn into it env_depth
// times with this same shader (section 5.1). With a mover set (section 5.2), each lookup ray
// of another piece is also searched from outside in the moving piece's refractor map (section
// 4.1); when it meets the moving piece before the environment surface, the moving piece is
// shaded there: its reflection and the refraction through it looked up in the moving piece's
// own impostor (the searches 5-7 of the paper's figure 5; the reflected ray ignores the moving
// piece itself: figure 9's error 2). The same shader draws pieces into other pieces'
// impostors (camera.eye = the cube's centre): alpha is the distance from the eye, as a
// distance impostor needs.
// ---------------------------------------------------------------------------------------------

const NO_PIECE: u32 = 0xffffffffu;

struct EnvParams {
    // The moving piece other pieces search for, or NO_PIECE.
    mover: u32,
    // Hit() refinement steps in the refractor maps and in the impostors.
    iterations: u32,
    env_iterations: u32,
    // A search from outside is accepted within this distance of the ray (metres).
    epsilon: f32,
};

@group(2) @binding(0) var<uniform> env: EnvParams;
@group(2) @binding(1) var<storage, read> pieces: array<Piece>;
// Reference point of each piece's impostor (world; w unused).
@group(2) @binding(2) var<storage, read> env_centres: array<vec4f>;
@group(2) @binding(3) var<storage, read> piece_of_object: array<u32>;
@group(2) @binding(4) var map_sampler: sampler;
@group(2) @binding(5) var impostors: texture_cube_array<f32>;
@group(2) @binding(6) var kind_maps: texture_cube_array<f32>;

const SURFACE_OFFSET: f32 = 1e-4;
const EXIT_CHORDS: u32 = 3u;

fn kind_layer(p: u32) -> i32 {
    return i32(piece_kind(p));
}

// The outward unit normal (world) in piece p's refractor map at map-frame direction l.
fn map_normal(p: u32, l: vec3f, fallback: vec3f) -> vec3f {
    let n = from_map(p, textureSampleLevel(kind_maps, map_sampler, l, kind_layer(p), 0.0).xyz);
    let len = length(n);
    return select(fallback, n / len, len > 1e-6);
}

// Radiance and ray parameter of the surface piece p's impostor shows along o + t d.
fn impostor_lookup(p: u32, o: vec3f, d: vec3f) -> vec4f {
    let h = hit_layered(o - env_centres[p].xyz, d, impostors, i32(p), map_sampler, 3u,
                        HIT_FALSE_POSITION, env.env_iterations);
    var l = h.xyz;
    if (dot(l, l) < 1e-12) { l = d; }
    return vec4f(textureSampleLevel(impostors, map_sampler, l, i32(p), 0.0).rgb, h.w);
}

// The exit of a chord inside piece p from `origin` along d: (exit point, outward normal
// agreeing with d).
struct Exit {
    point: vec3f,
    normal: vec3f,
};

fn chord_exit(p: u32, origin: vec3f, d: vec3f) -> Exit {
    let R = to_map(p, d);
    let h = hit_layered(to_map(p, origin - pieces[p].centre.xyz), R, kind_maps, kind_layer(p),
                        map_sampler, 3u, HIT_FALSE_POSITION, env.iterations);
    var l = h.xyz;
    if (dot(l, l) < 1e-12) { l = R; }
    let n = map_normal(p, l, d);
    var e: Exit;
    e.point = origin + d * h.w;
    e.normal = select(-n, n, dot(n, d) >= 0.0);
    return e;
}

// The moving piece m met at `at` (outward normal n_out) by a ray along d: its reflection and
// the refraction through it, both looked up in its own impostor.
fn shade_mover(m: u32, at: vec3f, n_out: vec3f, d: vec3f) -> vec3f {
    let o = objects[piece_object(m)];
    let n = select(-n_out, n_out, dot(d, n_out) < 0.0);
    let cos_i = -dot(d, n);
    let reflected = impostor_lookup(m, at + n * SURFACE_OFFSET, reflect_dir(d, n)).rgb;
    if (o.material.x == MATERIAL_METAL) {
        return fresnel_nk(cos_i, o.n.xyz, o.k.xyz) * reflected;
    }
    let ior = o.material.y;
    let f = fresnel_dielectric(cos_i, ior);
    let into = refract_dir(d, n, 1.0 / ior);
    if (into.w < 0.5) { return reflected; }
    let e = chord_exit(m, at - n * SURFACE_OFFSET, into.xyz);
    let out = refract_dir(into.xyz, -e.normal, ior);
    var through = vec3f(0.0);
    if (out.w > 0.5) {
        let g = fresnel_dielectric(dot(into.xyz, e.normal), 1.0 / ior);
        through = (1.0 - g) * impostor_lookup(m, e.point + e.normal * SURFACE_OFFSET, out.xyz).rgb;
    }
    return f * reflected + (1.0 - f) * through;
}

// Radiance arriving at o from direction d, seen from piece p: its impostor, or the moving
// piece when one is set and the ray meets it first.
fn lookup(p: u32, o: vec3f, d: vec3f) -> vec3f {
    let seen = impostor_lookup(p, o, d);
    let m = env.mover;
    if (m == NO_PIECE || m == p) { return seen.rgb; }
    let pm = pieces[m];
    let h = hit_from_outside_layered(to_map(m, o - pm.centre.xyz), to_map(m, d), kind_maps,
                                     kind_layer(m), map_sampler, 3u, pm.box_min.xyz,
                                     pm.box_max.xyz, HIT_FALSE_POSITION, env.iterations,
                                     env.epsilon);
    if (h.w < 0.0 || h.w >= seen.w) { return seen.rgb; }
    return shade_mover(m, o + d * h.w, map_normal(m, h.xyz, -d), d);
}

// Radiance carried out of piece p along the refracted ray entering at x with direction t.
fn through_piece(p: u32, x: vec3f, t: vec3f, ior: f32) -> vec3f {
    var origin = x;
    var dir = t;
    var share = 1.0;
    var color = vec3f(0.0);
    for (var s = 0u; s < EXIT_CHORDS; s++) {
        let e = chord_exit(p, origin, dir);
        let out = refract_dir(dir, -e.normal, ior);
        let f = select(1.0, fresnel_dielectric(dot(dir, e.normal), 1.0 / ior), out.w > 0.5);
        if (out.w > 0.5) {
            color += share * (1.0 - f) * lookup(p, e.point + e.normal * SURFACE_OFFSET, out.xyz);
        }
        share *= f;
        dir = reflect_dir(dir, -e.normal);
        origin = e.point - e.normal * SURFACE_OFFSET;
    }
    return color;
}

@fragment
fn environment_piece_fs(in: SceneVertexOut) -> @location(0) vec4f {
    let p = piece_of_object[in.object];
    let eye = camera.eye.xyz;
    let v = normalize(in.world - eye);
    let e = specular_event(in.object, in.normal, in.world, eye, v);
    let reflected = lookup(p, in.world + e.normal * SURFACE_OFFSET, e.reflected);
    var refracted = reflected;
    if (e.refracted.w > 0.5) {
        if (e.entering) {
            refracted = through_piece(p, in.world - e.normal * SURFACE_OFFSET, e.refracted.xyz,
                                      objects[in.object].material.y);
        } else {
            refracted = lookup(p, in.world - e.normal * SURFACE_OFFSET, e.refracted.xyz);
        }
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(in.world, eye));
}
