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

use glam::{IVec3, Vec3};
use gpu::prelude::{BIG, hash_to_unit};

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
