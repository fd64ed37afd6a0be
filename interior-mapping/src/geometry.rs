//! Real room geometry for the `interior/polygons` baseline: a facade with a window hole per
//! room cell and planes spanning the hull's inside (floors, ceilings, two wall families),
//! textured per room. The same generators as the `city` scene's real interiors
//! (`scene/src/city.rs`, which is private to `scene`); `tests/scene_agreement.rs` checks
//! that both give identical meshes and textures.

use glam::{Vec2, Vec3};
use scene::Mesh;
use scene::mesh::quad;

/// Horizontal margin of a window in its room cell (room units).
pub const WINDOW_SIDE: f32 = 0.2;
/// Window sill height in its room cell (room units).
pub const WINDOW_SILL: f32 = 0.3;
/// Window top in its room cell (room units).
pub const WINDOW_TOP: f32 = 0.85;
/// Half the thickness of the floor slabs (metres).
pub const SLAB_HALF: f32 = 0.01;

/// Whether a point with room-unit coordinates `h` (along the face) and `v` (height) is in a
/// window.
pub fn is_window(h: f32, v: f32) -> bool {
    let (fh, fv) = (h - h.floor(), v - v.floor());
    (WINDOW_SIDE..=1.0 - WINDOW_SIDE).contains(&fh) && (WINDOW_SILL..=WINDOW_TOP).contains(&fv)
}

/// Breakpoints in [0, 1] (face parameter) where the window pattern changes along an axis
/// whose room-unit coordinate runs from `g0` (at 0) to `g1` (at 1).
fn breaks(g0: f32, g1: f32, a: f32, b: f32) -> Vec<f32> {
    let (lo, hi) = (g0.min(g1), g0.max(g1));
    let mut out = vec![0.0, 1.0];
    let mut k = lo.floor() - 1.0;
    while k <= hi + 1.0 {
        for e in [k + a, k + b] {
            if e > lo && e < hi {
                out.push((e - g0) / (g1 - g0));
            }
        }
        k += 1.0;
    }
    out.sort_by(f32::total_cmp);
    out.dedup();
    out
}

/// The closed box `lo..hi` (faces and texture coordinates as `mesh::cuboid`) with a window
/// hole in every room cell of the four side faces.
pub fn facade_with_windows(lo: Vec3, hi: Vec3, room: Vec3) -> Mesh {
    let s = hi - lo;
    let (x, y, z) = (Vec3::new(s.x, 0.0, 0.0), Vec3::new(0.0, s.y, 0.0), Vec3::new(0.0, 0.0, s.z));
    let mut parts = vec![quad(lo, x, z, Vec2::ONE), quad(lo + y + z, x, -z, Vec2::ONE)];
    // (corner, edge u, edge v = +y) exactly as mesh::cuboid's side faces.
    for (o, u) in [(lo, z), (lo + x + z, -z), (lo + x, -x), (lo + z, x)] {
        let axis = if u.x != 0.0 { 0 } else { 2 };
        let g = |p: Vec3| (p[axis] - lo[axis]) / room[axis];
        let su = breaks(g(o), g(o + u), WINDOW_SIDE, 1.0 - WINDOW_SIDE);
        let gy = |p: Vec3| (p.y - lo.y) / room.y;
        let sv = breaks(gy(o), gy(o + y), WINDOW_SILL, WINDOW_TOP);
        let mut mesh = Mesh::default();
        let n = u.cross(y).normalize();
        let mut push = |s0: f32, s1: f32, r0: f32, r1: f32| {
            let base = mesh.positions.len() as u32;
            for (s, r) in [(s0, r0), (s1, r0), (s1, r1), (s0, r1)] {
                mesh.positions.push(o + s * u + r * y);
                mesh.normals.push(n);
                mesh.uvs.push(Vec2::new(s, 1.0 - r));
            }
            mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        };
        for rv in sv.windows(2) {
            let vm = gy(o + 0.5 * (rv[0] + rv[1]) * y);
            let fv = vm - vm.floor();
            if !(WINDOW_SILL..=WINDOW_TOP).contains(&fv) {
                push(0.0, 1.0, rv[0], rv[1]);
                continue;
            }
            for ru in su.windows(2) {
                let hm = g(o + 0.5 * (ru[0] + ru[1]) * u);
                if !is_window(hm, vm) {
                    push(ru[0], ru[1], rv[0], rv[1]);
                }
            }
        }
        parts.push(mesh);
    }
    scene::mesh::merge(&parts)
}

/// The room planes of one family inside the box `lo..hi`: 0 walls x, 2 walls z, 1 floors
/// (1 cm above the plane), 4 ceilings (1 cm below). Texture coordinates in room units.
pub fn room_planes(lo: Vec3, hi: Vec3, room: Vec3, family: u32) -> Mesh {
    let axis = if family == 4 { 1 } else { family as usize };
    let mut mesh = Mesh::default();
    let count = ((hi[axis] - lo[axis]) / room[axis]).ceil() as i32;
    for k in 0..=count {
        let mut c = lo[axis] + k as f32 * room[axis];
        match family {
            1 => c += SLAB_HALF,
            4 => c -= SLAB_HALF,
            _ => {}
        }
        let inside = match family {
            1 => c < hi[axis] - SLAB_HALF,
            4 => c > lo[axis] + SLAB_HALF && c < hi[axis] && k > 0,
            _ => k > 0 && c < hi[axis] - 1e-4,
        };
        if !inside {
            continue;
        }
        let (a1, a2) = match axis {
            0 => (2, 1),
            1 => (0, 2),
            _ => (0, 1),
        };
        let base = mesh.positions.len() as u32;
        let mut normal = Vec3::ZERO;
        normal[axis] = 1.0;
        for (s, t) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
            let mut p = Vec3::ZERO;
            p[axis] = c;
            p[a1] = if s == 0 { lo[a1] } else { hi[a1] };
            p[a2] = if t == 0 { lo[a2] } else { hi[a2] };
            let u = (p - lo) / room;
            let uv = match axis {
                0 => Vec2::new(u.z, -u.y),
                1 => Vec2::new(u.x, u.z),
                _ => Vec2::new(u.x, -u.y),
            };
            mesh.positions.push(p);
            mesh.normals.push(normal);
            mesh.uvs.push(uv);
        }
        // Wind counter-clockwise seen from where the normal points (corners run along a1
        // then a2, and a1 x a2 is -normal for the x and y families).
        if axis == 2 {
            mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        } else {
            mesh.indices.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
        }
    }
    mesh
}

