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

/// The bytes of a pixel that is NaN or infinite in an HDR copy ([`rgbe`]): magenta with a zero
/// exponent, which no finite pixel encodes to (a zero exponent is black).
pub const RGBE_NON_FINITE: [u8; 4] = [255, 0, 255, 0];

/// Ward's shared-exponent encoding of one linear RGB pixel (the Radiance `.hdr` format): three
/// 8-bit mantissas and one exponent byte, about 1 % relative precision over 2^-128..2^127.
/// Negative channels count as 0; a pixel with a NaN or infinite channel is
/// [`RGBE_NON_FINITE`]. Decode with `(m + 0.5) * 2^(e - 136)` per channel (`e` 0: black).
pub fn rgbe(p: [f32; 3]) -> [u8; 4] {
    if p.iter().any(|c| !c.is_finite()) {
        return RGBE_NON_FINITE;
    }
    let [r, g, b] = p.map(|c| c.max(0.0));
    let max = r.max(g).max(b);
    if max < 1e-38 {
        return [0; 4];
    }
    // max = f * 2^e with f in [0.5, 1): the mantissas are channel / 2^e * 256.
    let mut e = max.log2().floor() as i32 + 1;
    while max / 2f32.powi(e) >= 1.0 {
        e += 1;
    }
    while max / 2f32.powi(e) < 0.5 {
        e -= 1;
    }
    let e = e.clamp(-127, 127);
    // In f64: 256 / 2^e overflows f32 for the darkest exponents.
    let scale = 256.0 / 2f64.powi(e);
    let m = |c: f32| (c as f64 * scale).floor().clamp(0.0, 255.0) as u8;
    [m(r), m(g), m(b), (e + 128) as u8]
}

/// Standard base64 (RFC 4648, with padding).
pub fn base64(bytes: &[u8]) -> String {
    data_encoding::BASE64.encode(bytes)
}

/// Writes the HDR copy of an image that the HTML report reads for its exposure control: a
/// script `harnessHdr(width, height, "base64")` whose payload is the zlib-compressed RGBE
/// planes ([`rgbe`]: every pixel's first byte, then every second, third, fourth; rows top
/// first). A script, because a page opened from the file system may run scripts from beside
/// it but may not read the pixels of its images (they taint the canvas); planes, because
/// they compress about twice as well as interleaved bytes.
pub fn write_hdr_script(path: &Path, image: &HdrImage) -> Result<()> {
    use std::io::Write as _;
    ensure_parent(path)?;
    let n = image.pixels.len();
    let mut planes = vec![0u8; 4 * n];
    for (i, p) in image.pixels.iter().enumerate() {
        for (c, byte) in rgbe([p[0], p[1], p[2]]).into_iter().enumerate() {
            planes[c * n + i] = byte;
        }
    }
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(&planes)?;
    let script = format!(
        "harnessHdr({}, {}, \"{}\");\n",
        image.width,
        image.height,
        base64(&z.finish()?)
    );
    std::fs::write(path, script).with_context(|| format!("cannot write {}", path.display()))
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

    /// Ward's decoding, as the report's script does it.
    fn unrgbe(b: [u8; 4]) -> [f32; 3] {
        if b[3] == 0 {
            return [0.0; 3];
        }
        // In f64, as JavaScript decodes: 2^(e - 136) is below f32's range for the darkest.
        let s = 2f64.powi(b[3] as i32 - 136);
        [0, 1, 2].map(|c| ((b[c] as f64 + 0.5) * s) as f32)
    }

    #[test]
    fn rgbe_keeps_a_percent_over_the_whole_range_and_marks_non_finite_pixels() {
        for &v in &[
            2e-37f32, 1e-30, 1e-6, 0.003, 0.5, 0.999_999, 1.0, 1.5, 4.0, 1e4, 3e37,
        ] {
            for p in [[v, v, v], [v, 0.5 * v, 0.01 * v], [0.0, v, 0.0]] {
                let back = unrgbe(rgbe(p));
                let max = p.iter().cloned().fold(0.0, f32::max);
                for c in 0..3 {
                    // Each channel within half a mantissa step of the largest.
                    assert!((back[c] - p[c]).abs() <= max / 256.0, "{p:?} -> {back:?}");
                }
            }
        }
        assert_eq!(rgbe([0.0; 3]), [0; 4]);
        assert_eq!(rgbe([-1.0, 0.0, 0.0]), [0; 4]);
        assert_eq!(rgbe([f32::NAN, 0.0, 0.0]), RGBE_NON_FINITE);
        assert_eq!(rgbe([0.0, f32::INFINITY, 0.0]), RGBE_NON_FINITE);
        assert_eq!(rgbe([1.0, 1.0, 1.0])[3], 129, "1 = 0.5 * 2^1");
    }

    #[test]
    fn base64_matches_the_rfc_examples() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, coded) in cases {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
        assert_eq!(base64(&[0xff, 0xfe, 0x00]), "//4A");
    }

    #[test]
    fn hdr_scripts_carry_the_compressed_planes() {
        use std::io::Read as _;
        let dir = std::env::temp_dir().join(format!("harness-hdr-{}", std::process::id()));
        let mut img = HdrImage::new(3, 2);
        img.pixels[1] = [2.0, 0.5, 0.0, 1.0];
        img.pixels[4] = [f32::NAN, 0.0, 0.0, 1.0];
        let path = dir.join("a.hdr.js");
        write_hdr_script(&path, &img).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let payload = text
            .strip_prefix("harnessHdr(3, 2, \"")
            .and_then(|t| t.strip_suffix("\");\n"))
            .unwrap();
        let alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let bits: Vec<u8> = payload
            .trim_end_matches('=')
            .chars()
            .map(|c| alphabet.find(c).unwrap() as u8)
            .collect();
        let bytes: Vec<u8> = bits
            .chunks(4)
            .flat_map(|q| {
                let n = q.iter().fold(0u32, |n, &b| n << 6 | b as u32) << (6 * (4 - q.len()));
                n.to_be_bytes()[1..q.len()].to_vec()
            })
            .collect();
        let mut planes = Vec::new();
        flate2::read::ZlibDecoder::new(&bytes[..])
            .read_to_end(&mut planes)
            .unwrap();
        assert_eq!(planes.len(), 4 * 6);
        let pixel = |i: usize| [planes[i], planes[6 + i], planes[12 + i], planes[18 + i]];
        assert_eq!(pixel(1), rgbe([2.0, 0.5, 0.0]));
        assert_eq!(pixel(4), RGBE_NON_FINITE);
        assert_eq!(pixel(0), [0; 4]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
