//! The per-pixel ray cast of interior mapping (van Dongen, section 5.2.1-5.2.2 and 5.4.3):
//! a ray against three families of regularly spaced planes (walls `x = const`, floors and
//! ceilings `y = const`, walls `z = const`), nearest hit chosen, in constant time.
//!
//! This is the Rust twin of `shaders/interior.wgsl` (same algorithm, same constants, same
//! names with a `room_` / `cast_rooms` prefix); `tests/conformance.rs` runs the WGSL in a
//! compute shader and compares it with this code, `tests/rooms_properties.rs` checks it
//! against a brute-force search over all planes in a large range.
//!
//! Coordinates are the building's object space shifted so that the room grid starts at the
//! origin: plane `k` of family `a` lies at `(k + offset(a, k)) * room_size[a]`, where the
//! offset is zero for regular rooms and a per-plane hash in `[-m, m]` (`m < 0.5`) for the
//! displaced-walls variant (section 5.4.3).
//!
//! The paper finds the next plane as `ceil(y / d) * d` (looking up) or one lower (looking
//! down). We work in room units `u = p / room_size` and take, for a ray going up, the first
//! plane strictly beyond `u + ROOM_EPS`; the epsilon keeps a point lying on a plane (a facade
//! that coincides with a wall plane) from hitting that very plane at `t = 0`.
//!
//! Displaced walls: with `|offset| <= m < 0.5`, the first displaced plane beyond `u` is one
//! of the two planes `k_a = floor(u + eps - m) + 1` and `k_a + 1` (proof: plane `k_a + 1` is
//! at least `k_a + 1 - m > u + eps + 1 - 2m > u + eps`). The paper checks "the current and
//! the previous wall" (`floor(u) + 1` and `floor(u)`); that pair misses the case where the
//! current wall was displaced backwards past the pixel, which two-sided offsets allow, so we
//! choose the pair by `u - m` instead: still two checks, constant cost, never a skipped wall.
//!
//! # Cube-map interiors (the engine baseline)
//!
//! [`cubemap_room`] is what games ship instead (Unreal's `InteriorCubemap` material function):
//! the room the ray enters is one box of the grid; the ray is intersected with that box from
//! inside (`gpu::prelude::box_project`, the parallax correction of reflection probes, with
//! the probe at the room's centre) and a pre-rendered cube map of a room is looked up toward the
//! exit point. Per-room variation picks one of several cube maps and mirrors each horizontal
//! axis by a hash of the room. On the regular grid it finds exactly the plane `cast_rooms`
//! finds (tests/rooms_properties.rs); it cannot express displaced walls.

use glam::{IVec3, Vec3};
use gpu::prelude::{BIG, box_project, hash_to_unit, pcg_hash};

/// Family index of the planes `x = const` (walls, textured with the "ZY" wall texture).
pub const FAMILY_X: u32 = 0;
/// Family index of the planes `y = const` (floors seen from above, ceilings from below).
pub const FAMILY_Y: u32 = 1;
/// Family index of the planes `z = const` (walls, textured with the "XY" wall texture).
pub const FAMILY_Z: u32 = 2;
/// A plane closer than this (in room units) ahead of the start point is not hit.
pub const ROOM_EPS: f32 = 1e-4;
/// Direction components (in room units) below this magnitude are parallel to that family.
pub const ROOM_FLAT: f32 = 1e-20;
/// Largest allowed displacement of a plane, in rooms (must stay below 0.5, see module docs).
pub const MAX_DISPLACEMENT: f32 = 0.45;

/// The nearest plane hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoomHit {
    /// [`FAMILY_X`], [`FAMILY_Y`] or [`FAMILY_Z`].
    pub family: u32,
    /// Ray parameter of the hit (`origin + t * dir`); [`BIG`] when `dir` is zero.
    pub t: f32,
    /// The hit point, with its coordinate along the hit family snapped onto the plane.
    pub point: Vec3,
    /// Integer index of the room the ray is in when it reaches the plane.
    pub room: IVec3,
    /// Index `k` of the plane that was hit.
    pub plane: i32,
}

/// Offset of plane `k` of family `axis` in rooms: 0 when `amount` is 0, else in
/// `[-amount, amount]` from a hash of (k, axis, seed).
pub fn room_plane_offset(axis: u32, k: i32, amount: f32, seed: u32) -> f32 {
    if amount == 0.0 {
        return 0.0;
    }
    let h = hash_to_unit(
        (k as u32)
            .wrapping_mul(3)
            .wrapping_add(axis)
            .wrapping_add(seed),
    );
    amount * (2.0 * h - 1.0)
}

/// Position of plane `k` of family `axis`, in room units.
pub fn room_plane_pos(axis: u32, k: i32, amount: f32, seed: u32) -> f32 {
    k as f32 + room_plane_offset(axis, k, amount, seed)
}

/// The next plane of one family along a ray: (index, ray parameter). `u` is the start
/// coordinate and `du` the direction component, both in room units; `m` the displacement
/// amount. A parallel family gives (0, [`BIG`]).
pub fn room_next_plane(axis: u32, u: f32, du: f32, m: f32, seed: u32) -> (i32, f32) {
    if du.abs() < ROOM_FLAT {
        return (0, BIG);
    }
    let k = if du > 0.0 {
        let k = (u + ROOM_EPS - m).floor() as i32 + 1;
        if room_plane_pos(axis, k, m, seed) > u + ROOM_EPS {
            k
        } else {
            k + 1
        }
    } else {
        let k = (u - ROOM_EPS + m).ceil() as i32 - 1;
        if room_plane_pos(axis, k, m, seed) < u - ROOM_EPS {
            k
        } else {
            k - 1
        }
    };
    (k, (room_plane_pos(axis, k, m, seed) - u) / du)
}

/// Index of the room containing coordinate `u` along `axis` (the largest k with plane k at or
/// below u).
pub fn room_index(axis: u32, u: f32, m: f32, seed: u32) -> i32 {
    let k = (u + m).floor() as i32;
    if room_plane_pos(axis, k, m, seed) <= u {
        k
    } else {
        k - 1
    }
}

/// Casts the ray `origin + t * dir` (grid space, `t >= 0`) against the three plane families
/// of rooms of size `room_size` whose planes are displaced by up to `displacement` rooms
/// per family (zero for the regular grid; each component at most [`MAX_DISPLACEMENT`]).
/// Ties go to the lower family index.
pub fn cast_rooms(
    origin: Vec3,
    dir: Vec3,
    room_size: Vec3,
    displacement: Vec3,
    seed: u32,
) -> RoomHit {
    let u = origin / room_size;
    let du = dir / room_size;
    let m = displacement;
    let planes = [
        room_next_plane(FAMILY_X, u.x, du.x, m.x, seed),
        room_next_plane(FAMILY_Y, u.y, du.y, m.y, seed),
        room_next_plane(FAMILY_Z, u.z, du.z, m.z, seed),
    ];
    let mut family = 0usize;
    if planes[1].1 < planes[family].1 {
        family = 1;
    }
    if planes[2].1 < planes[family].1 {
        family = 2;
    }
    let (plane, t) = planes[family];
    let mut point = origin + t * dir;
    let uh = u + t * du;
    let mut room = IVec3::ZERO;
    for axis in 0..3 {
        room[axis] = if axis == family {
            if du[axis] > 0.0 { plane - 1 } else { plane }
        } else {
            room_index(axis as u32, uh[axis], m[axis], seed)
        };
    }
    if t < BIG {
        point[family] = room_plane_pos(family as u32, plane, m[family], seed) * room_size[family];
    }
    RoomHit {
        family: family as u32,
        t,
        point,
        room,
        plane,
    }
}

/// Texture coordinates of a hit on a plane of `family` (in room units, repeat addressing:
/// one texture per room face). Walls `x`: (z, -y); floors/ceilings: (x, z); walls `z`:
/// (x, -y), so image row 0 is at the top of a wall. The real room geometry of the `city`
/// scene uses the same mapping.
pub fn plane_uv(family: u32, u: Vec3) -> glam::Vec2 {
    match family {
        FAMILY_X => glam::Vec2::new(u.z, -u.y),
        FAMILY_Y => glam::Vec2::new(u.x, u.z),
        _ => glam::Vec2::new(u.x, -u.y),
    }
}

/// The room box a ray enters and where it leaves it: the cube-map interiors' intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubemapHit {
    /// Ray parameter of the exit (`origin + t * dir`); [`BIG`] when `dir` is zero.
    pub t: f32,
    /// The exit point (grid space), its coordinate along `family` snapped onto the room's face.
    pub point: Vec3,
    /// The family of the face the ray leaves by ([`FAMILY_X`], [`FAMILY_Y`], [`FAMILY_Z`]).
    pub family: u32,
    /// Integer index of the room.
    pub room: IVec3,
    /// The direction to look the room's cube map up in (from the room's centre, in room units,
    /// the per-room mirroring applied).
    pub lookup: Vec3,
    /// Which cube map of the atlas (0 without variation).
    pub atlas: u32,
}

/// Bit of a room's hash that mirrors its cube map along x (`MIRROR_Z_BIT`: along z).
pub const MIRROR_X_BIT: u32 = 1 << 8;
/// Bit of a room's hash that mirrors its cube map along z.
pub const MIRROR_Z_BIT: u32 = 1 << 9;

/// The hash of a room (grid index and building seed): it switches the varied rooms' lights and
/// picks their atlas tint (section 5.4, in `technique.wgsl`), and picks and mirrors the
/// cube-map interiors' room.
pub fn room_hash(room: IVec3, seed: u32) -> u32 {
    let r = room.as_uvec3();
    pcg_hash(
        r.x.wrapping_mul(73856093)
            ^ r.y.wrapping_mul(19349663)
            ^ r.z.wrapping_mul(83492791)
            ^ pcg_hash(seed),
    )
}

/// The family of the room face a direction from the room's centre leaves by: its largest
/// component, ties to the lower axis (as `cast_rooms`' ties).
pub fn dominant_family(d: Vec3) -> u32 {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        FAMILY_X
    } else if a.y >= a.z {
        FAMILY_Y
    } else {
        FAMILY_Z
    }
}

/// Cube-map interiors: the ray `origin + t * dir` (grid space, starting on or in the room it
/// enters) in rooms of size `room_size`. The room is the grid cell the ray is in just after
/// the start (a start on a plane belongs to the room ahead); the exit from that cell is
/// `box_project` with the probe at the cell's centre. With `variants > 1` the cube map is
/// chosen per room by hash, and each horizontal axis of the lookup mirrored by a hash bit.
pub fn cubemap_room(
    origin: Vec3,
    dir: Vec3,
    room_size: Vec3,
    variants: u32,
    seed: u32,
) -> CubemapHit {
    let u = origin / room_size;
    let du = dir / room_size;
    let ahead = Vec3::select(
        du.abs().cmplt(Vec3::splat(ROOM_FLAT)),
        Vec3::ZERO,
        du.signum() * ROOM_EPS,
    );
    let room = (u + ahead).floor();
    let local = u - room;
    let centre = Vec3::splat(0.5);
    let exit = box_project(local, du, centre, Vec3::ZERO, Vec3::ONE);
    let (t, mut lookup) = if exit.w < 0.0 {
        (BIG, du)
    } else {
        (exit.w, exit.truncate())
    };
    let family = dominant_family(lookup);
    let mut point = origin + t * dir;
    if t < BIG {
        let f = family as usize;
        let face = room[f] + if lookup[f] > 0.0 { 1.0 } else { 0.0 };
        point[f] = face * room_size[f];
    }
    let room = room.as_ivec3();
    let mut atlas = 0;
    if variants > 1 {
        let h = room_hash(room, seed);
        atlas = h % variants;
        if h & MIRROR_X_BIT != 0 {
            lookup.x = -lookup.x;
        }
        if h & MIRROR_Z_BIT != 0 {
            lookup.z = -lookup.z;
        }
    }
    CubemapHit {
        t,
        point,
        family,
        room,
        lookup,
        atlas,
    }
}
