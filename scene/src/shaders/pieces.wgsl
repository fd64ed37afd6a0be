// ---------------------------------------------------------------------------------------------
// The piece table the many-object shaders read (Rust: scene/src/multi_object/pieces.rs
// `PieceGpu`), and the answer of a per-object search from inside (`Chord`). The including
// shader declares `pieces: array<Piece>` at its own binding.
// ---------------------------------------------------------------------------------------------

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
