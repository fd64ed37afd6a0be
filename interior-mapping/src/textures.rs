//! The interior textures: floors, ceilings, two wallpapers (the `city` scene's own
//! `scene::builtin::city::room_texel`, so a technique at 64 texels samples exactly what the
//! reference's room planes carry), tinted variants for the per-room atlas (section 5.4.2)
//! and the animated furniture sprite (section 5.2.4); and the pre-rendered room cube maps of
//! the engine baseline (cube-map interiors), one per tinted variant.

use scene::Texture;

pub use scene::builtin::city::{RoomSurface, room_texel, room_texture};

/// Number of tinted variants per surface in the atlas (variant 0 is the plain texture).
pub const VARIANTS: u32 = 4;
/// Number of animation frames of the furniture sprite.
pub const FURNITURE_FRAMES: u32 = 4;
/// Array layer of surface `s` (0 floor, 1 ceiling, 2 wall x, 3 wall z) in variant `v`.
pub fn layer(surface: u32, variant: u32) -> u32 {
    variant * 4 + surface
}
/// First array layer of the furniture frames.
pub const FURNITURE_LAYER: u32 = VARIANTS * 4;

const SURFACES: [RoomSurface; 4] = [
    RoomSurface::Floor,
    RoomSurface::Ceiling,
    RoomSurface::WallX,
    RoomSurface::WallZ,
];
const TINTS: [[f32; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.1, 0.85, 0.75],
    [0.75, 0.9, 1.15],
    [0.85, 1.1, 0.8],
];

/// An opaque RGBA8 texel: sRGB colour `c` times the atlas variant's `tint`.
fn tinted(c: [u8; 3], tint: &[f32; 3]) -> [u8; 4] {
    let channel = |k: usize| (c[k] as f32 * tint[k]).round().clamp(0.0, 255.0) as u8;
    [channel(0), channel(1), channel(2), 255]
}

/// RGBA8 (sRGB) texel of the furniture sprite frame `f`: a seated figure beside a table, the
/// figure's arm moving from frame to frame; alpha 0 outside the figure.
pub fn furniture_texel(frame: u32, s: f32, t: f32) -> [u8; 4] {
    let head = ((s - 0.38).powi(2) + (t - 0.38).powi(2)).sqrt() < 0.07;
    let body = (s - 0.38).abs() < 0.08 && t > 0.45 && t < 0.75;
    let legs = (s - 0.38).abs() < 0.06 && (0.75..0.97).contains(&t);
    let arm_y = 0.5 + 0.04 * frame as f32;
    let arm = s > 0.38 && s < 0.58 && (t - arm_y).abs() < 0.025;
    let table = s > 0.55
        && s < 0.85
        && ((t - 0.6).abs() < 0.025
            || ((s - 0.6).abs() < 0.02 || (s - 0.8).abs() < 0.02) && t > 0.6 && t < 0.97);
    if head {
        [220, 180, 150, 255]
    } else if body || arm {
        [60, 80, 150, 255]
    } else if legs {
        [40, 40, 50, 255]
    } else if table {
        [110, 70, 40, 255]
    } else {
        [0, 0, 0, 0]
    }
}

/// All layers (`layer(surface, variant)` then the furniture frames) at `size` x `size`, RGBA8
/// sRGB, layer-major.
pub fn texture_layers(size: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let at = |i: u32| (i as f32 + 0.5) / size as f32;
    for tint in TINTS.iter().take(VARIANTS as usize) {
        for surface in SURFACES {
            for j in 0..size {
                for i in 0..size {
                    out.extend_from_slice(&tinted(room_texel(surface, at(i), at(j)), tint));
                }
            }
        }
    }
    for f in 0..FURNITURE_FRAMES {
        for j in 0..size {
            for i in 0..size {
                out.extend_from_slice(&furniture_texel(f, at(i), at(j)));
            }
        }
    }
    out
}

/// The four plain room textures as scene textures (what the polygon baseline adds).
pub fn scene_textures(size: u32) -> Vec<Texture> {
    [
        "interior floor",
        "interior ceiling",
        "interior wall x",
        "interior wall z",
    ]
    .iter()
    .zip(SURFACES)
    .map(|(name, s)| room_texture(name, s, size))
    .collect()
}

/// The one texture of `interior-mapping/single-texture` (section 5.3.2, "reading the colours of all
/// walls and ceilings from a single texture"): the four plain surfaces of
/// [`texture_layers`] as tiles of a `2 size` x `2 size` RGBA8 image, surface `s` at tile
/// column `s % 2`, row `s / 2`.
pub fn single_atlas(size: u32) -> Vec<u8> {
    let layers = texture_layers(size);
    let (n, side) = (size as usize, 2 * size as usize);
    let mut out = vec![0u8; side * side * 4];
    for s in 0..4 {
        let (x0, y0) = ((s % 2) * n, (s / 2) * n);
        for j in 0..n {
            let src = ((s * n + j) * n) * 4;
            let dst = ((y0 + j) * side + x0) * 4;
            out[dst..dst + n * 4].copy_from_slice(&layers[src..src + n * 4]);
        }
    }
    out
}

/// Faces of the room cube maps, in cube-layer order (+X, -X, +Y, -Y, +Z, -Z).
const CUBE_FACES: u32 = 6;

/// The room cube maps of the cube-map interiors: `variants` cube maps of `size` x `size`
/// faces, RGBA8 sRGB, cube after cube and face after face (the layers of a 2D array texture,
/// addressed with `gpu::prelude::cube_dir_to_face_uv`), cube `v`
/// tinted as layer variant `v` of [`texture_layers`]. Each is the unit room (floor, ceiling,
/// two wall families, the thesis's textures one per face) seen from its centre: per texel the
/// ray from the centre leaves the room box on a face, whose texture is read there; the same
/// picture as rasterizing the room's six quads into a cube, which is how an engine's artist
/// bakes it (lighting is applied at run time, see the crate README).
pub fn room_cube_layers(size: u32, variants: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity((size * size * CUBE_FACES * variants * 4) as usize);
    let at = |i: u32| (i as f32 + 0.5) / size as f32;
    for tint in TINTS.iter().cycle().take(variants as usize) {
        for face in 0..CUBE_FACES {
            for j in 0..size {
                for i in 0..size {
                    let d = gpu::prelude::cube_face_uv_to_dir(face, at(i), at(j));
                    let (surface, s, t) = room_surface_seen(d);
                    out.extend_from_slice(&tinted(room_texel(surface, s, t), tint));
                }
            }
        }
    }
    out
}

/// The room surface seen from the centre of the unit room in direction `d` and its texture
/// coordinate in [0, 1)^2 (`rooms::plane_uv` of the exit point, the face chosen as
/// `rooms::cubemap_room` chooses it).
pub fn room_surface_seen(d: glam::Vec3) -> (RoomSurface, f32, f32) {
    use crate::rooms::{FAMILY_X, FAMILY_Y, dominant_family};
    let exit = glam::Vec3::splat(0.5) + d * (0.5 / d.abs().max_element());
    let family = dominant_family(d);
    let surface = match family {
        FAMILY_X => RoomSurface::WallX,
        FAMILY_Y if d.y > 0.0 => RoomSurface::Ceiling,
        FAMILY_Y => RoomSurface::Floor,
        _ => RoomSurface::WallZ,
    };
    let uv = crate::rooms::plane_uv(family, exit);
    (surface, uv.x - uv.x.floor(), uv.y - uv.y.floor())
}
