//! Texture helpers shared by the built-in scenes (every scene file may use them; they use no
//! scene file).

use crate::mesh::quad;
use crate::{Material, Object, Texture};
use glam::{Mat4, Vec2, Vec3};

/// A `size` x `size` sRGB RGBA8 texture (alpha 255) whose texel `(i, j)` (row `j` from the
/// top) has the sRGB colour `texel(i, j)`.
pub fn from_texels(name: &str, size: u32, texel: impl Fn(u32, u32) -> [u8; 3]) -> Texture {
    let mut rgba8 = Vec::with_capacity((size * size * 4) as usize);
    for j in 0..size {
        for i in 0..size {
            let c = texel(i, j);
            rgba8.extend_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
    Texture {
        name: name.to_string(),
        width: size,
        height: size,
        rgba8,
    }
}

/// Checkerboard texture, sRGB RGBA8, `cells` x `cells` squares.
pub fn checker_texture(name: &str, size: u32, cells: u32, a: [u8; 3], b: [u8; 3]) -> Texture {
    from_texels(name, size, |i, j| {
        if (i * cells / size + j * cells / size) % 2 == 0 {
            a
        } else {
            b
        }
    })
}

/// The floor and checker wall the bunny and Hu and Qin's scenes stand in front of: the floor
/// y = 0, 6 m wide, from z = `near_z` back `depth` metres (to the wall); the wall 6 x 3 m at
/// z = `wall_z` facing +z, textured with [`wall_checker`] (texture 0) repeated 3 x 1.5 times:
/// 0.25 m cells.
pub fn floor_and_checker_wall(near_z: f32, depth: f32, wall_z: f32) -> [Object; 2] {
    let floor = quad(
        Vec3::new(-3.0, 0.0, near_z),
        Vec3::X * 6.0,
        Vec3::NEG_Z * depth,
        Vec2::ONE,
    );
    let wall = quad(
        Vec3::new(-3.0, 0.0, wall_z),
        Vec3::X * 6.0,
        Vec3::Y * 3.0,
        Vec2::new(3.0, 1.5),
    );
    let checker = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    [
        Object::new(
            "floor",
            floor,
            Material::diffuse(0.6, 0.6, 0.58),
            Mat4::IDENTITY,
        ),
        Object::new("checker wall", wall, checker, Mat4::IDENTITY),
    ]
}

/// The wall's checker: 8 x 8 cells, light beige and dark blue-grey, 64 texels square.
pub fn wall_checker() -> Texture {
    checker_texture("wall checker", 64, 8, [210, 205, 190], [70, 80, 110])
}
