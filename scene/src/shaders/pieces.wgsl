// ---------------------------------------------------------------------------------------------
// The piece table the many-object shaders read (Rust: scene/src/multi_object/pieces.rs
// `PieceGpu`), at both drivers' @group(2) @binding(1), and the per-object search they call: a
// search (scene::multi_object::ObjectSearch: refractor distance maps, refractor height maps) is
// a module that overrides the three virtual functions below (`override fn
// scene::pieces::piece_hit`, ...), composed as an override of the driver's shader
// (gpu::wgsl::Shader::overriding), with its own bindings from @group(2)
// @binding(SEARCH_FIRST_BINDING). Without a search every piece is missed.
// ---------------------------------------------------------------------------------------------
#define_import_path scene::pieces

// The first @group(2) binding of a per-object search's own resources (Rust:
// scene::multi_object::SEARCH_FIRST_BINDING; the drivers' resources take 0..6).
const SEARCH_FIRST_BINDING: u32 = 6u;

struct Piece {
    // World centre now; w: kind (which refractor map).
    centre: vec4f,
    // Rows of the world -> map rotation (the kind's map is rendered in one piece's frame).
    to_map_x: vec4f,
    to_map_y: vec4f,
    to_map_z: vec4f,
    // Bounding box in the map's frame about the centre; box_min.w: object index.
    box_min: vec4f,
    box_max: vec4f,
};

@group(2) @binding(1) var<storage, read> pieces: array<Piece>;

// A world direction (or offset from the centre) in piece p's map frame.
fn to_map(p: u32, v: vec3f) -> vec3f {
    let pc = pieces[p];
    return vec3f(dot(pc.to_map_x.xyz, v), dot(pc.to_map_y.xyz, v), dot(pc.to_map_z.xyz, v));
}

// A map-frame direction of piece p in the world.
fn from_map(p: u32, v: vec3f) -> vec3f {
    let pc = pieces[p];
    return pc.to_map_x.xyz * v.x + pc.to_map_y.xyz * v.y + pc.to_map_z.xyz * v.z;
}

fn piece_kind(p: u32) -> u32 {
    return u32(pieces[p].centre.w);
}

fn piece_object(p: u32) -> u32 {
    return u32(pieces[p].box_min.w);
}

// Where a ray inside a piece leaves it (an ObjectSearch's chord()).
struct Chord {
    exit_point: vec3f,
    // Outward unit normal, turned to agree with the leaving ray.
    normal: vec3f,
};

virtual fn piece_hit(p: u32, o: vec3f, d: vec3f) -> vec4f {
    // The search from outside: (a payload of the search's own, t), t < 0 when piece p is
    // missed along o + t d.
    return vec4f(0.0, 0.0, 0.0, -1.0);
}

virtual fn piece_hit_normal(p: u32, o: vec3f, d: vec3f, hit: vec4f) -> vec3f {
    // The unit outward normal (world) at piece_hit's answer `hit`.
    return -d;
}

virtual fn chord(p: u32, origin: vec3f, dir: vec3f) -> Chord {
    // The search from inside: where the ray leaves piece p, and the outward normal there
    // (agreeing with the ray).
    return Chord(origin, dir);
}
