//! Image error metrics against the reference: RMSE, PSNR, mean FLIP, the share of pixels with
//! FLIP > 0.1, the same FLIP mean over a mask, and the count of non-finite pixels.
//!
//! Definitions (every figure in the harness's tables comes from here):
//!
//! - **RMSE** is taken over the linear RGB channels (alpha ignored) of every pixel where both
//!   the test and the reference pixel are finite: `sqrt(sum (t - r)^2 / (3 * n_finite))`.
//!   Non-finite test pixels are excluded from it but counted in [`Metrics::nan_pixels`] (a NaN
//!   or infinite pixel is always a defect to report). If no pixel is finite, RMSE is NaN.
//! - **PSNR** is `20 * log10(peak / RMSE)` on linear RGB with `peak = 1.0` (the radiance that
//!   maps to white in the PNGs). Identical images give `+inf`; the harness writes that as `inf`
//!   in CSV/markdown and `null` in JSON (serde_json writes non-finite numbers as `null`).
//! - **FLIP** (NVIDIA's perceptual difference, via the `nv-flip` crate, LDR version) is
//!   computed on the sRGB8 images of [`to_srgb8`], i.e. exactly what the PNGs show, at the
//!   crate's default 67 pixels per degree. `flip_mean` is the mean over all pixels,
//!   `flip_over_0_1_pct` the percentage of pixels with FLIP > 0.1, `flip_mean_masked` the mean
//!   over the pixels where the mask is true (the pixels that show the technique's special
//!   objects in the reference). Without a mask, or with an empty mask, `flip_mean_masked` is
//!   NaN (an empty cell in CSV, `null` in JSON) and `masked_pixels` is 0.
//!   `flip_mean_silhouette` is the mean over the mask's [`silhouette_band`]: the masked pixels
//!   within a few pixels of an unmasked one, where image-space refraction techniques fail
//!   first (Hu and Qin's figure 11); NaN where that band is empty.

use gpu::HdrImage;

/// Error of a test image against the reference (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Root mean square error over linear RGB of the finite pixels.
    pub rmse: f64,
    /// `20 log10(1 / rmse)`; `+inf` for identical images.
    pub psnr_db: f64,
    /// Mean FLIP over all pixels, in [0, 1].
    pub flip_mean: f64,
    /// Mean FLIP over the masked pixels; NaN when there is no mask or it is empty.
    pub flip_mean_masked: f64,
    /// Mean FLIP over the mask's silhouette band ([`silhouette_band`]); NaN when it is empty.
    pub flip_mean_silhouette: f64,
    /// Percentage (0..100) of pixels with FLIP > 0.1.
    pub flip_over_0_1_pct: f64,
    /// Test pixels with a NaN or infinite channel.
    pub nan_pixels: usize,
    /// Pixels where the mask is true (0 without a mask).
    pub masked_pixels: usize,
}

/// Per-pixel FLIP values of one comparison (row 0 is the top).
#[derive(Clone, Debug, PartialEq)]
pub struct FlipMap {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

impl FlipMap {
    /// The error map coloured with the magma colour map (0 black .. 1 light yellow), RGB8,
    /// rows tightly packed: what `<technique>.flip.png` shows.
    pub fn to_magma_rgb8(&self) -> Vec<u8> {
        if self.values.is_empty() {
            return Vec::new();
        }
        let image = nv_flip::FlipImageFloat::with_data(self.width, self.height, &self.values);
        image.apply_color_lut(&nv_flip::magma_lut()).to_vec()
    }

    /// Mean FLIP value over all pixels.
    pub fn mean(&self) -> f64 {
        mean(self.values.iter().map(|&v| v as f64))
    }
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

/// The sRGB transfer (IEC 61966-2-1) and the 8-bit encoding live with the image type in
/// `gpu`, so an example's PNG is written without this crate; re-exported where the metrics
/// have always had them.
pub use gpu::{channel_to_srgb8, linear_to_srgb};

/// The image as sRGB8 RGB (alpha dropped), rows tightly packed, row 0 the top: the PNG's
/// pixels and FLIP's input.
pub fn to_srgb8(image: &HdrImage) -> Vec<u8> {
    image.to_srgb8()
}

/// Width of the silhouette band in pixels: 3% of the image's smaller side, at least 2.
pub fn silhouette_band_width(width: u32, height: u32) -> u32 {
    ((0.03 * width.min(height) as f32).round() as u32).max(2)
}

/// The masked pixels within [`silhouette_band_width`] pixels (Chebyshev distance) of an
/// unmasked pixel or of the image's border: the band along the silhouettes of the objects the
/// mask shows.
pub fn silhouette_band(mask: &[bool], width: u32, height: u32) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    let r = silhouette_band_width(width, height) as usize;
    // The square neighbourhood is separable: first "an unmasked pixel within r along the row"
    // (from running counts), then "such a pixel within r along the column". Outside the image
    // counts as unmasked. O(width x height) whatever the band's width.
    let mut near_row = vec![false; w * h];
    for y in 0..h {
        let unmasked: Vec<bool> = (0..w).map(|x| !mask[y * w + x]).collect();
        let mut count: usize = unmasked[..r.min(w)].iter().filter(|&&u| u).count();
        for x in 0..w {
            // count = unmasked pixels in [x - r, x + r] clipped to the row.
            if x + r < w && unmasked[x + r] {
                count += 1;
            }
            if x > r && unmasked[x - r - 1] {
                count -= 1;
            }
            near_row[y * w + x] = x < r || x + r >= w || count > 0;
        }
    }
    let mut band = vec![false; w * h];
    for x in 0..w {
        let mut count: usize = (0..r.min(h)).filter(|&y| near_row[y * w + x]).count();
        for y in 0..h {
            if y + r < h && near_row[(y + r) * w + x] {
                count += 1;
            }
            if y > r && near_row[(y - r - 1) * w + x] {
                count -= 1;
            }
            band[y * w + x] = mask[y * w + x] && (y < r || y + r >= h || count > 0);
        }
    }
    band
}

/// Compares `test` with `reference` (see the module documentation for the definitions).
///
/// # Panics
///
/// If the two images differ in size, or `mask` is not one entry per pixel: callers (the
/// harness) check both and report a sentence instead.
pub fn compare(test: &HdrImage, reference: &HdrImage, mask: Option<&[bool]>) -> (Metrics, FlipMap) {
    assert_eq!(
        (test.width, test.height),
        (reference.width, reference.height),
        "metrics::compare: test and reference differ in size"
    );
    let n = test.pixels.len();
    assert_eq!(
        reference.pixels.len(),
        n,
        "metrics::compare: reference pixel count"
    );
    if let Some(m) = mask {
        assert_eq!(
            m.len(),
            n,
            "metrics::compare: the mask needs one entry per pixel"
        );
    }

    let finite = |p: &[f32; 4]| p[..3].iter().all(|c| c.is_finite());
    let nan_pixels = test.pixels.iter().filter(|p| !finite(p)).count();
    let mut sum_sq = 0.0f64;
    let mut counted = 0usize;
    for (t, r) in test.pixels.iter().zip(&reference.pixels) {
        if finite(t) && finite(r) {
            for c in 0..3 {
                let d = t[c] as f64 - r[c] as f64;
                sum_sq += d * d;
            }
            counted += 1;
        }
    }
    let rmse = if counted == 0 {
        f64::NAN
    } else {
        (sum_sq / (3 * counted) as f64).sqrt()
    };
    let psnr_db = if rmse == 0.0 {
        f64::INFINITY
    } else {
        20.0 * (1.0 / rmse).log10()
    };

    let values = if n == 0 {
        Vec::new()
    } else {
        let (w, h) = (test.width, test.height);
        let r8 = nv_flip::FlipImageRgb8::with_data(w, h, &to_srgb8(reference));
        let t8 = nv_flip::FlipImageRgb8::with_data(w, h, &to_srgb8(test));
        nv_flip::flip(r8, t8, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
    };
    let map = FlipMap {
        width: test.width,
        height: test.height,
        values,
    };
    let flip_mean = map.mean();
    let over = map.values.iter().filter(|&&v| v > 0.1).count();
    let flip_over_0_1_pct = if n == 0 {
        f64::NAN
    } else {
        100.0 * over as f64 / n as f64
    };
    let (flip_mean_masked, masked_pixels) = match mask {
        Some(m) => {
            let masked = m.iter().filter(|&&b| b).count();
            let mean = mean(
                map.values
                    .iter()
                    .zip(m)
                    .filter(|(_, b)| **b)
                    .map(|(v, _)| *v as f64),
            );
            (mean, masked)
        }
        None => (f64::NAN, 0),
    };
    let flip_mean_silhouette = match mask {
        Some(m) => {
            let band = silhouette_band(m, test.width, test.height);
            mean(
                map.values
                    .iter()
                    .zip(&band)
                    .filter(|(_, b)| **b)
                    .map(|(v, _)| *v as f64),
            )
        }
        None => f64::NAN,
    };
    let metrics = Metrics {
        rmse,
        psnr_db,
        flip_mean,
        flip_mean_masked,
        flip_mean_silhouette,
        flip_over_0_1_pct,
        nan_pixels,
        masked_pixels,
    };
    (metrics, map)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_silhouette_band_is_the_masks_rim() {
        // A 6 x 6 block in a 10 x 10 image: the band (2 pixels wide at this size) is the
        // block's outer two rings; its 2 x 2 centre is not in it.
        let mask: Vec<bool> = (0..100)
            .map(|i| (2..8).contains(&(i % 10)) && (2..8).contains(&(i / 10)))
            .collect();
        assert_eq!(silhouette_band_width(10, 10), 2);
        let band = silhouette_band(&mask, 10, 10);
        assert_eq!(band.iter().filter(|&&b| b).count(), 36 - 4);
        assert!(!band[4 * 10 + 4] && !band[5 * 10 + 5] && band[2 * 10 + 2] && !band[0]);
        assert_eq!(silhouette_band_width(256, 200), 6);
    }

    #[test]
    fn the_silhouette_band_equals_its_definition() {
        // Pseudo-random masks against the definition checked pixel by pixel.
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            state >> 16
        };
        for (w, h) in [(13, 7), (64, 64), (100, 37)] {
            let mask: Vec<bool> = (0..w * h).map(|_| next() % 5 != 0).collect();
            let r = silhouette_band_width(w, h) as i64;
            let masked = |x: i64, y: i64| {
                x >= 0
                    && y >= 0
                    && x < w as i64
                    && y < h as i64
                    && mask[(y * w as i64 + x) as usize]
            };
            let band = silhouette_band(&mask, w, h);
            for y in 0..h as i64 {
                for x in 0..w as i64 {
                    let expected = masked(x, y)
                        && (-r..=r).any(|dy| (-r..=r).any(|dx| !masked(x + dx, y + dy)));
                    assert_eq!(
                        band[(y * w as i64 + x) as usize],
                        expected,
                        "{w}x{h} at {x},{y}"
                    );
                }
            }
        }
    }

    fn constant(w: u32, h: u32, v: [f32; 4]) -> HdrImage {
        HdrImage {
            width: w,
            height: h,
            pixels: vec![v; (w * h) as usize],
        }
    }

    fn gradient(w: u32, h: u32) -> HdrImage {
        let mut img = HdrImage::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
                img.set(x, y, [u, v, 0.5 * (u + v), 1.0]);
            }
        }
        img
    }

    #[test]
    fn identical_images_have_zero_error_and_infinite_psnr() {
        let a = gradient(32, 24);
        let (m, map) = compare(&a, &a, None);
        assert_eq!(m.rmse, 0.0);
        assert_eq!(m.psnr_db, f64::INFINITY);
        assert_eq!(m.flip_mean, 0.0);
        assert_eq!(m.flip_over_0_1_pct, 0.0);
        assert_eq!(m.nan_pixels, 0);
        assert!(m.flip_mean_masked.is_nan() && m.masked_pixels == 0);
        assert_eq!(map.values.len(), 32 * 24);
        // serde_json writes the non-finite figures as null, never as invalid JSON.
        let json = serde_json::json!({ "psnr_db": m.psnr_db, "masked": m.flip_mean_masked });
        assert_eq!(json.to_string(), r#"{"masked":null,"psnr_db":null}"#);
    }

    #[test]
    fn constant_offset_gives_that_rmse() {
        let r = constant(16, 16, [0.2, 0.4, 0.6, 1.0]);
        let t = constant(16, 16, [0.3, 0.5, 0.7, 0.0]); // alpha is ignored
        let (m, _) = compare(&t, &r, None);
        assert!((m.rmse - 0.1).abs() < 1e-6, "rmse {}", m.rmse);
        assert!((m.psnr_db - 20.0).abs() < 1e-4, "psnr {}", m.psnr_db);
        assert!(m.flip_mean > 0.0);

        // Offset in one channel only: rmse = d / sqrt(3).
        let t = constant(16, 16, [0.5, 0.4, 0.6, 1.0]);
        let (m, _) = compare(&t, &r, None);
        assert!((m.rmse - 0.3 / 3f64.sqrt()).abs() < 1e-6, "rmse {}", m.rmse);
    }

    #[test]
    fn non_finite_pixels_are_counted_and_excluded_from_rmse() {
        let r = constant(8, 8, [0.5; 4]);
        let mut t = r.clone();
        t.set(1, 1, [f32::NAN, 0.5, 0.5, 1.0]);
        t.set(2, 3, [0.5, f32::INFINITY, 0.5, 1.0]);
        t.set(7, 7, [0.5, 0.5, f32::NEG_INFINITY, 1.0]);
        let (m, _) = compare(&t, &r, None);
        assert_eq!(m.nan_pixels, 3);
        assert_eq!(m.rmse, 0.0);
        // NaN alpha alone is not counted: only RGB is compared.
        let mut t = r.clone();
        t.set(0, 0, [0.5, 0.5, 0.5, f32::NAN]);
        assert_eq!(compare(&t, &r, None).0.nan_pixels, 0);
    }

    #[test]
    fn mask_selects_the_pixels_of_the_masked_mean() {
        let (w, h) = (32, 32);
        let r = constant(w, h, [0.2; 4]);
        let mut t = r.clone();
        let mut mask = vec![false; (w * h) as usize];
        for y in 8..16 {
            for x in 8..16 {
                t.set(x, y, [1.0, 1.0, 1.0, 1.0]);
                mask[(y * w + x) as usize] = true;
            }
        }
        let (m, map) = compare(&t, &r, Some(&mask));
        assert_eq!(m.masked_pixels, 64);
        assert!(
            m.flip_mean_masked > m.flip_mean,
            "{} vs {}",
            m.flip_mean_masked,
            m.flip_mean
        );
        assert!(m.flip_over_0_1_pct > 0.0 && m.flip_over_0_1_pct < 100.0);
        assert_eq!(map.to_magma_rgb8().len(), (w * h * 3) as usize);
        // An empty mask gives NaN, reported as an empty cell.
        let none = vec![false; (w * h) as usize];
        let (m, _) = compare(&t, &r, Some(&none));
        assert!(m.flip_mean_masked.is_nan());
        assert_eq!(m.masked_pixels, 0);
    }

    #[test]
    fn srgb8_is_the_clamped_transfer_without_tone_mapping() {
        assert_eq!(channel_to_srgb8(0.0), 0);
        assert_eq!(channel_to_srgb8(1.0), 255);
        assert_eq!(channel_to_srgb8(7.5), 255);
        assert_eq!(channel_to_srgb8(-1.0), 0);
        assert_eq!(channel_to_srgb8(f32::NAN), 0);
        assert_eq!(channel_to_srgb8(f32::INFINITY), 255);
        assert_eq!(channel_to_srgb8(0.5), 188); // 0.7354 * 255 = 187.5 -> 188
        assert_eq!(channel_to_srgb8(0.002), 7); // linear segment: 0.02584 * 255 = 6.59
        let img = constant(2, 1, [0.0, 0.5, 1.0, 0.3]);
        assert_eq!(to_srgb8(&img), vec![0, 188, 255, 0, 188, 255]);
    }

    #[test]
    fn empty_image_does_not_panic() {
        let a = HdrImage::new(0, 0);
        let (m, map) = compare(&a, &a, None);
        assert!(m.rmse.is_nan() && map.values.is_empty() && map.to_magma_rgb8().is_empty());
    }
}
