//! Image files: PNG (sRGB transfer of the value clamped to [0, 1], no tone mapping, RGB8) and
//! EXR (linear RGBA f32, lossless, bit-exact), plus the object-id/mask side file of cached
//! references.

use anyhow::{Context as _, Result, bail};
use gpu::HdrImage;
use std::path::Path;

fn ensure_parent(path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    Ok(())
}

/// Writes tightly packed RGB8 rows as a PNG.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    ensure_parent(path)?;
    image::save_buffer(path, rgb, width, height, image::ExtendedColorType::Rgb8)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Writes an HDR image as PNG: sRGB of the clamped value (what FLIP compares).
pub fn write_png(path: &Path, image: &HdrImage) -> Result<()> {
    write_png_rgb8(
        path,
        image.width,
        image.height,
        &truth::metrics::to_srgb8(image),
    )
}

/// Writes an HDR image as EXR: linear RGBA f32, lossless.
pub fn write_exr(path: &Path, image: &HdrImage) -> Result<()> {
    ensure_parent(path)?;
    let w = image.width as usize;
    exr::prelude::write_rgba_file(path, w, image.height as usize, |x, y| {
        let p = image.pixels[y * w + x];
        (p[0], p[1], p[2], p[3])
    })
    .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))
}

/// Reads the first RGBA layer of an EXR as f32 (alpha 1 where the file has none).
pub fn read_exr(path: &Path) -> Result<HdrImage> {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |resolution, _| HdrImage::new(resolution.width() as u32, resolution.height() as u32),
        |img: &mut HdrImage, pos, (r, g, b, a): (f32, f32, f32, f32)| {
            img.set(pos.x() as u32, pos.y() as u32, [r, g, b, a]);
        },
    )
    .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Writes an image as PNG or EXR by the file's extension.
pub fn write_by_extension(path: &Path, image: &HdrImage) -> Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_lowercase)
        .as_deref()
    {
        Some("png") => write_png(path, image),
        Some("exr") => write_exr(path, image),
        _ => bail!(
            "cannot tell the image format of {}: use a .png or .exr name",
            path.display()
        ),
    }
}

const IDS_MAGIC: &[u8; 8] = b"HRNSIDS1";

/// Writes per-pixel object ids and mask: magic, width, height (u32 LE), ids (i32 LE), mask
/// (one byte each).
pub fn write_ids(path: &Path, width: u32, height: u32, ids: &[i32], mask: &[bool]) -> Result<()> {
    ensure_parent(path)?;
    let mut bytes = Vec::with_capacity(16 + ids.len() * 5);
    bytes.extend_from_slice(IDS_MAGIC);
    bytes.extend_from_slice(&width.to_le_bytes());
    bytes.extend_from_slice(&height.to_le_bytes());
    for id in ids {
        bytes.extend_from_slice(&id.to_le_bytes());
    }
    bytes.extend(mask.iter().map(|&m| m as u8));
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// Reads what [`write_ids`] wrote: (width, height, ids, mask).
pub fn read_ids(path: &Path) -> Result<(u32, u32, Vec<i32>, Vec<bool>)> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let bad = || anyhow::anyhow!("{} is not an id file", path.display());
    if bytes.len() < 16 || &bytes[..8] != IDS_MAGIC {
        return Err(bad());
    }
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
    let (w, h) = (u32_at(8), u32_at(12));
    let n = w as usize * h as usize;
    if bytes.len() != 16 + n * 5 {
        return Err(bad());
    }
    let ids = bytes[16..16 + 4 * n]
        .chunks_exact(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let mask = bytes[16 + 4 * n..].iter().map(|&b| b != 0).collect();
    Ok((w, h, ids, mask))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trips_exactly_and_png_is_written() {
        let dir = std::env::temp_dir().join(format!("harness-images-{}", std::process::id()));
        let mut img = HdrImage::new(5, 3);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = [i as f32 * 0.1234567, -1.5e-7, 3.0e4, 0.25 + i as f32];
        }
        img.pixels[7] = [f32::NAN, f32::INFINITY, 0.0, 1.0];
        let exr_path = dir.join("a.exr");
        write_exr(&exr_path, &img).unwrap();
        let back = read_exr(&exr_path).unwrap();
        assert_eq!((back.width, back.height), (5, 3));
        for (a, b) in img.pixels.iter().zip(&back.pixels) {
            for c in 0..4 {
                assert_eq!(a[c].to_bits(), b[c].to_bits());
            }
        }
        let png_path = dir.join("sub/a.png");
        write_by_extension(&png_path, &img).unwrap();
        let decoded = image::open(&png_path).unwrap().into_rgb8();
        assert_eq!(decoded.dimensions(), (5, 3));
        assert_eq!(decoded.into_raw(), truth::metrics::to_srgb8(&img));
        assert!(write_by_extension(&dir.join("a.jpg"), &img).is_err());

        let ids = vec![-1, 0, 1, 2, 3, 4];
        let mask = vec![false, true, true, false, false, true];
        write_ids(&dir.join("a.ids"), 3, 2, &ids, &mask).unwrap();
        assert_eq!(read_ids(&dir.join("a.ids")).unwrap(), (3, 2, ids, mask));
        std::fs::write(dir.join("b.ids"), b"garbage").unwrap();
        assert!(read_ids(&dir.join("b.ids")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
