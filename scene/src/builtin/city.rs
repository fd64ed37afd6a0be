//! The `city` scene: a grid of building hulls along a street, for interior mapping.
//!
//! Hulls are 20 x 40 x 20 m (object space x and z in [-10, 10], y in [0, 40]); building 1 is
//! a cylinder and building 2 a sphere. `rooms_per_building` sets each hull's room size
//! ([`Building::room_size`]): `n x 2n x n` rooms with `n = cbrt(rooms / 2)` (fractional room
//! counts are allowed: the last room along an axis is then partial). The room grid starts at
//! the hull's object-space bounding-box minimum.
//!
//! # Real interiors (`interiors=1`, the default)
//!
//! So that the CPU reference has ground truth for interior mapping, the box buildings beside
//! the start of the street (grid columns 0 and 1, rows 0 and 1; at most three buildings) get
//! real geometry when `rooms_per_building <= 100000` (larger counts would give hundreds of
//! thousands of triangles per building; those scenes stay hull-only and build quickly):
//!
//! * the hull becomes a facade **with window holes** (object named `... (box, window
//!   holes)`, role `building`, `building` set): on the four side faces, a point is a window
//!   when its room-unit coordinate along the face's horizontal axis has a fractional part in
//!   `[WINDOW_SIDE, 1 - WINDOW_SIDE]` and its room-unit height one in `[WINDOW_SILL,
//!   WINDOW_TOP]`. Texture coordinates are those of `mesh::cuboid`'s faces, so an interior
//!   mapping technique can draw the closed bounding box in its place and agree texel for
//!   texel.
//! * four objects of room planes spanning the hull's inside (role `building`, `building`
//!   unset, so a technique that replaces interiors skips them): floors (`y = k ry + 1 cm`,
//!   texture "interior floor"), ceilings (`y = k ry - 1 cm`, "interior ceiling"), walls
//!   `x = const` ("interior wall x") and walls `z = const` ("interior wall z"), with texture
//!   coordinates in room units (`interior_mapping::rooms::plane_uv`): one texture per room
//!   face. The two-centimetre slab lets floors and ceilings carry different textures.
//!
//! Interior mapping (the `interior-mapping` crate) must produce the same window pattern and
//! textures; its tests check that its generators agree with this file.

use super::textures::{checker_texture, from_texels};
use crate::mesh::{cuboid, cylinder, quad, uv_sphere};
use crate::{
    Building, Camera, CameraPath, Light, Material, Mesh, Object, Roles, Scene, SceneError, Texture,
};
use glam::{Mat4, Vec2, Vec3};

/// Horizontal margin of a window in its room cell (room units).
pub const WINDOW_SIDE: f32 = 0.2;
/// Window sill height in its room cell (room units).
pub const WINDOW_SILL: f32 = 0.3;
/// Window top in its room cell (room units).
pub const WINDOW_TOP: f32 = 0.85;
/// Half the thickness of the floor slabs (metres).
pub const SLAB_HALF: f32 = 0.01;
/// Largest `rooms_per_building` that still gets real interiors.
pub const MAX_REAL_ROOMS: f32 = 100_000.0;
/// Resolution of the interior textures.
pub const ROOM_TEXTURE_SIZE: u32 = 64;

/// `city` with `buildings` hulls of `rooms_per_building` rooms each; `interiors` 1 gives the
/// buildings beside the start of the street real rooms (see the module documentation), 0 none.
pub fn city(
    buildings: usize,
    rooms_per_building: f32,
    interiors: f32,
) -> Result<Scene, SceneError> {
    check_params(buildings, rooms_per_building, interiors)?;
    // Hull 20 x 40 x 20 m; rooms split it into n x n^2 x n (more floors than rooms per side
    // would be odd, so rooms are distributed in proportion to the hull's extent).
    let hull = Vec3::new(20.0, 40.0, 20.0);
    let per_axis = (rooms_per_building / 2.0).cbrt().max(1.0);
    let room_size = hull / Vec3::new(per_axis, 2.0 * per_axis, per_axis);
    let spacing = 32.0;
    let columns = (buildings as f32).sqrt().ceil() as usize;
    let facade = 0;
    let real_interiors = interiors == 1.0 && rooms_per_building <= MAX_REAL_ROOMS;
    let mut objects = vec![Object::new(
        "ground",
        quad(
            Vec3::new(-spacing, 0.0, spacing),
            Vec3::X * spacing * (columns as f32 + 1.0),
            Vec3::NEG_Z * spacing * (columns as f32 + 1.0),
            Vec2::splat(columns as f32 + 1.0),
        ),
        Material::diffuse(0.3, 0.3, 0.3),
        Mat4::IDENTITY,
    )];
    let facade_material = Material::Diffuse {
        albedo: Vec3::splat(0.8),
        texture: Some(facade),
        cutout: None,
    };
    for b in 0..buildings {
        let (col, row) = (b % columns, b / columns);
        let at = Vec3::new(col as f32 * spacing, 0.0, -(row as f32) * spacing);
        let lo = Vec3::new(-hull.x * 0.5, 0.0, -hull.z * 0.5);
        let hi = Vec3::new(hull.x * 0.5, hull.y, hull.z * 0.5);
        let with_rooms = real_interiors && b != 1 && b != 2 && col < 2 && row < 2;
        let (mesh, shape) = match b {
            1 => (cylinder(hull.x * 0.5, hull.y, 32), "cylinder"),
            2 => (uv_sphere(hull.x * 0.5, 16, 32), "sphere"),
            _ if with_rooms => (facade_with_windows(lo, hi, room_size), "box, window holes"),
            _ => (cuboid(lo, hi), "box"),
        };
        let lift = if shape == "sphere" {
            Vec3::Y * hull.x * 0.5
        } else {
            Vec3::ZERO
        };
        let transform = Mat4::from_translation(at + lift);
        let mut o = Object::new(
            &format!("building {b} ({shape})"),
            mesh,
            facade_material.clone(),
            transform,
        )
        .with_roles(Roles::BUILDING);
        o.building = Some(Building { room_size });
        objects.push(o);
        if with_rooms {
            objects.extend(room_plane_objects(b, (lo, hi), room_size, transform));
        }
    }
    let street_x = spacing * 0.5;
    let depth = spacing * (columns as f32 - 1.0).max(1.0);
    let cam = |z: f32| Camera {
        eye: Vec3::new(street_x, 6.0, spacing * 0.8 - z),
        target: Vec3::new(street_x - 3.0, 12.0, -z - 60.0),
        up: Vec3::Y,
        fov_y_deg: 60.0,
        orthographic: None,
    };
    let n = ROOM_TEXTURE_SIZE;
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![
            checker_texture("facade", 64, 8, [170, 165, 150], [60, 70, 90]),
            room_texture("interior floor", RoomSurface::Floor, n),
            room_texture("interior ceiling", RoomSurface::Ceiling, n),
            room_texture("interior wall x", RoomSurface::WallX, n),
            room_texture("interior wall z", RoomSurface::WallZ, n),
        ],
        lights: vec![Light {
            name: "sun-like light".into(),
            position: Vec3::new(250.0, 400.0, 300.0),
            intensity: Vec3::splat(4.0e5),
            kind: crate::LightKind::Point,
        }],
        camera: cam(0.0),
        camera_path: CameraPath {
            keys: vec![(0.0, cam(0.0)), (4.0, cam(depth))],
        },
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.35, 0.45, 0.6),
    })
}

/// `city`'s parameters checked: 2..=[`super::MAX_BUILDINGS`] buildings, 1..=1e8 rooms per
/// building, interiors 0 or 1.
fn check_params(
    buildings: usize,
    rooms_per_building: f32,
    interiors: f32,
) -> Result<(), SceneError> {
    if !(2..=super::MAX_BUILDINGS).contains(&buildings) {
        return Err(SceneError::BadParam(format!(
            "buildings={buildings} is not in 2..={}",
            super::MAX_BUILDINGS
        )));
    }
    if !(1.0..=1e8).contains(&rooms_per_building) {
        return Err(SceneError::BadParam(format!(
            "rooms_per_building={rooms_per_building} is not in 1..=1e8"
        )));
    }
    if interiors != 0.0 && interiors != 1.0 {
        return Err(SceneError::BadParam(format!(
            "interiors={interiors} is not 0 or 1"
        )));
    }
    Ok(())
}

/// The real interior of building `b` (hull `lo`..`hi`, placed by `transform`): its floors,
/// ceilings and the two families of walls, each one object with its room texture.
fn room_plane_objects(
    b: usize,
    (lo, hi): (Vec3, Vec3),
    room_size: Vec3,
    transform: Mat4,
) -> Vec<Object> {
    let mut objects = Vec::new();
    for (family, name, texture) in [
        (1u32, "floors", 1usize),
        (4, "ceilings", 2),
        (0, "walls x", 3),
        (2, "walls z", 4),
    ] {
        let mesh = room_planes(lo, hi, room_size, family);
        let material = Material::Diffuse {
            albedo: Vec3::ONE,
            texture: Some(texture),
            cutout: None,
        };
        objects.push(
            Object::new(&format!("building {b} {name}"), mesh, material, transform)
                .with_roles(Roles::BUILDING),
        );
    }
    objects
}

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
    let (x, y, z) = (
        Vec3::new(s.x, 0.0, 0.0),
        Vec3::new(0.0, s.y, 0.0),
        Vec3::new(0.0, 0.0, s.z),
    );
    let mut parts = vec![
        quad(lo, x, z, Vec2::ONE),
        quad(lo + y + z, x, -z, Vec2::ONE),
    ];
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
            mesh.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
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
    crate::mesh::merge(&parts)
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
            mesh.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        } else {
            mesh.indices
                .extend([base, base + 2, base + 1, base, base + 3, base + 2]);
        }
    }
    mesh
}

/// The surfaces of a room.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RoomSurface {
    Floor,
    Ceiling,
    WallX,
    WallZ,
}

/// sRGB colour of a room surface at texture coordinate (s, t) in [0, 1)^2 (t = 0 at the
/// top row): planks, a ceiling with a lamp, striped wallpapers with a skirting board.
/// `interior_mapping::textures` has the same function.
pub fn room_texel(surface: RoomSurface, s: f32, t: f32) -> [u8; 3] {
    let edge = s.min(1.0 - s).min(t.min(1.0 - t));
    match surface {
        RoomSurface::Floor => {
            if edge < 0.03 {
                [70, 50, 35]
            } else if ((t * 8.0).floor() as i32) % 2 == 0 {
                [150, 105, 60]
            } else {
                [130, 90, 52]
            }
        }
        RoomSurface::Ceiling => {
            if (s - 0.5).abs() < 0.1 && (t - 0.5).abs() < 0.1 {
                [255, 250, 225]
            } else if edge < 0.03 {
                [160, 160, 150]
            } else {
                [225, 225, 215]
            }
        }
        RoomSurface::WallX | RoomSurface::WallZ => {
            let (base, stripe) = if surface == RoomSurface::WallX {
                ([180, 190, 140], [155, 165, 118])
            } else {
                ([195, 150, 140], [170, 125, 118])
            };
            if t > 0.92 {
                [90, 70, 50]
            } else if edge < 0.02 {
                [120, 120, 110]
            } else if ((s * 6.0).floor() as i32) % 2 == 0 {
                base
            } else {
                stripe
            }
        }
    }
}

/// A room texture of `size` x `size` texels sampled at texel centres.
pub fn room_texture(name: &str, surface: RoomSurface, size: u32) -> Texture {
    let at = |k: u32| (k as f32 + 0.5) / size as f32;
    from_texels(name, size, |i, j| room_texel(surface, at(i), at(j)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_city_has_real_interiors_and_large_counts_build_quickly() {
        let s = city(16, 1000.0, 1.0).unwrap();
        let holed: Vec<_> = s
            .objects
            .iter()
            .filter(|o| o.name.contains("window holes"))
            .collect();
        assert_eq!(holed.len(), 3);
        assert!(s.objects.iter().any(|o| o.name == "building 0 floors"));
        let start = std::time::Instant::now();
        let big = city(16, 4.0e6, 1.0).unwrap();
        assert!(start.elapsed().as_secs_f32() < 1.0);
        assert!(big.objects.iter().all(|o| !o.name.contains("window holes")));
        let none = city(16, 1000.0, 0.0).unwrap();
        assert_eq!(none.objects.len(), 17);
        s.validate().unwrap();
    }

    /// Triangles wind counter-clockwise seen from where their normal points (the reference
    /// decides the lit side by the geometric normal).
    #[test]
    fn interior_meshes_wind_with_their_normals() {
        let (lo, hi) = (Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 40.0, 10.0));
        let room = Vec3::new(2.3, 2.6, 2.9);
        let mut meshes = vec![facade_with_windows(lo, hi, room)];
        meshes.extend([0, 1, 2, 4].map(|f| room_planes(lo, hi, room, f)));
        for mesh in meshes {
            for t in mesh.indices.chunks(3) {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                let face = (b - a).cross(c - a);
                assert!(
                    face.length() > 1e-9 && face.dot(mesh.normals[t[0] as usize]) > 0.0,
                    "triangle {t:?}"
                );
            }
        }
    }

    #[test]
    fn facade_holes_are_windows() {
        let (lo, hi) = (Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 40.0, 10.0));
        let room = Vec3::new(2.5, 2.5, 2.5);
        let m = facade_with_windows(lo, hi, room);
        // Total area = box area minus window area (8 x 16 windows of 0.6 x 0.55 rooms per face).
        let area: f32 = m
            .indices
            .chunks(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let windows = 4.0 * 8.0 * 16.0 * (0.6 * 2.5) * (0.55 * 2.5);
        let full = 2.0 * (20.0 * 40.0 * 2.0 + 20.0 * 20.0);
        assert!(
            (area - (full - windows)).abs() < 0.5,
            "area {area} vs {}",
            full - windows
        );
    }
}
