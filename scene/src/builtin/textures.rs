//! Texture helpers shared by the built-in scenes (every scene file may use them; they use no
//! scene file).

use crate::Texture;

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
