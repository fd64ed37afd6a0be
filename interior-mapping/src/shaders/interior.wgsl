#define_import_path interior_mapping::rooms
// ---------------------------------------------------------------------------------------------
// Interior mapping ray cast (van Dongen 2008, sections 5.2.1-5.2.2, 5.4.3): the WGSL twin of
// interior-mapping/src/rooms.rs (same algorithm, same constants; see its docs): the module
// interior_mapping::rooms, importing gpu::prelude. Grid space: plane k of family a at (k + offset) * size[a].
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{BIG, box_project, hash_to_unit, pcg_hash}

const FAMILY_X: u32 = 0u;
const FAMILY_Y: u32 = 1u;
const FAMILY_Z: u32 = 2u;
const ROOM_EPS: f32 = 1e-4;
const ROOM_FLAT: f32 = 1e-20;

struct RoomHit {
    family: u32,
    t: f32,
    point: vec3f,
    room: vec3i,
    plane: i32,
};

struct NextPlane {
    k: i32,
    t: f32,
};

fn room_plane_offset(axis: u32, k: i32, amount: f32, seed: u32) -> f32 {
    if (amount == 0.0) { return 0.0; }
    let h = hash_to_unit(bitcast<u32>(k) * 3u + axis + seed);
    return amount * (2.0 * h - 1.0);
}

fn room_plane_pos(axis: u32, k: i32, amount: f32, seed: u32) -> f32 {
    return f32(k) + room_plane_offset(axis, k, amount, seed);
}

// The next plane of one family: for a ray going up the first plane strictly beyond
// u + ROOM_EPS among the two candidates floor(u + eps - m) + 1 and the one after it.
fn room_next_plane(axis: u32, u: f32, du: f32, m: f32, seed: u32) -> NextPlane {
    var r: NextPlane;
    if (abs(du) < ROOM_FLAT) {
        r.k = 0;
        r.t = BIG;
        return r;
    }
    var k: i32;
    if (du > 0.0) {
        k = i32(floor(u + ROOM_EPS - m)) + 1;
        if (!(room_plane_pos(axis, k, m, seed) > u + ROOM_EPS)) { k += 1; }
    } else {
        k = i32(ceil(u - ROOM_EPS + m)) - 1;
        if (!(room_plane_pos(axis, k, m, seed) < u - ROOM_EPS)) { k -= 1; }
    }
    r.k = k;
    r.t = (room_plane_pos(axis, k, m, seed) - u) / du;
    return r;
}

fn room_index(axis: u32, u: f32, m: f32, seed: u32) -> i32 {
    let k = i32(floor(u + m));
    if (room_plane_pos(axis, k, m, seed) <= u) { return k; }
    return k - 1;
}

// Nearest of the three plane families along origin + t * dir (grid space); ties go to the
// lower family index.
fn cast_rooms(origin: vec3f, dir: vec3f, size: vec3f, disp: vec3f, seed: u32) -> RoomHit {
    let u = origin / size;
    let du = dir / size;
    let px = room_next_plane(FAMILY_X, u.x, du.x, disp.x, seed);
    let py = room_next_plane(FAMILY_Y, u.y, du.y, disp.y, seed);
    let pz = room_next_plane(FAMILY_Z, u.z, du.z, disp.z, seed);
    var family = FAMILY_X;
    var best = px;
    if (py.t < best.t) { family = FAMILY_Y; best = py; }
    if (pz.t < best.t) { family = FAMILY_Z; best = pz; }
    var hit: RoomHit;
    hit.family = family;
    hit.t = best.t;
    hit.plane = best.k;
    var point = origin + best.t * dir;
    let uh = u + best.t * du;
    var room = vec3i(0);
    for (var a = 0u; a < 3u; a++) {
        if (a == family) {
            room[a] = select(best.k, best.k - 1, du[a] > 0.0);
        } else {
            room[a] = room_index(a, uh[a], disp[a], seed);
        }
    }
    if (best.t < BIG) {
        point[family] = room_plane_pos(family, best.k, disp[family], seed) * size[family];
    }
    hit.point = point;
    hit.room = room;
    return hit;
}

// Texture coordinates on a plane of `family` from room-unit coordinates (repeat addressing).
fn plane_uv(family: u32, u: vec3f) -> vec2f {
    if (family == FAMILY_X) { return vec2f(u.z, -u.y); }
    if (family == FAMILY_Y) { return vec2f(u.x, u.z); }
    return vec2f(u.x, -u.y);
}

// ---------------------------------------------------------------------------------------------
// Cube-map interiors (the engine baseline): twin of rooms.rs `cubemap_room` (see its docs).
// ---------------------------------------------------------------------------------------------

const MIRROR_X_BIT: u32 = 256u;
const MIRROR_Z_BIT: u32 = 512u;

struct CubemapHit {
    t: f32,
    point: vec3f,
    family: u32,
    room: vec3i,
    lookup: vec3f,
    atlas: u32,
};

// The hash of a room (grid index, building seed): the varied rooms' lights and atlas tints
// and the cube-map interiors' choice and mirroring.
fn room_hash(room: vec3i, seed: u32) -> u32 {
    let r = bitcast<vec3u>(room);
    return pcg_hash(r.x * 73856093u ^ r.y * 19349663u ^ r.z * 83492791u ^ pcg_hash(seed));
}

// The room face a direction from the room's centre leaves by (largest component, ties to the
// lower axis).
fn dominant_family(d: vec3f) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) { return FAMILY_X; }
    if (a.y >= a.z) { return FAMILY_Y; }
    return FAMILY_Z;
}

fn cubemap_room(origin: vec3f, dir: vec3f, size: vec3f, variants: u32, seed: u32) -> CubemapHit {
    let u = origin / size;
    let du = dir / size;
    let ahead = select(sign(du) * ROOM_EPS, vec3f(0.0), abs(du) < vec3f(ROOM_FLAT));
    let room = floor(u + ahead);
    let local = u - room;
    let exit = box_project(local, du, vec3f(0.5), vec3f(0.0), vec3f(1.0));
    var t = exit.w;
    var lookup = exit.xyz;
    if (exit.w < 0.0) {
        t = BIG;
        lookup = du;
    }
    let family = dominant_family(lookup);
    var point = origin + t * dir;
    if (t < BIG) {
        let face = room[family] + select(0.0, 1.0, lookup[family] > 0.0);
        point[family] = face * size[family];
    }
    var hit: CubemapHit;
    hit.t = t;
    hit.point = point;
    hit.family = family;
    hit.room = vec3i(room);
    hit.atlas = 0u;
    if (variants > 1u) {
        let h = room_hash(hit.room, seed);
        hit.atlas = h % variants;
        if ((h & MIRROR_X_BIT) != 0u) { lookup.x = -lookup.x; }
        if ((h & MIRROR_Z_BIT) != 0u) { lookup.z = -lookup.z; }
    }
    hit.lookup = lookup;
    return hit;
}
