//! The reference's primary rays over another renderer's image: for tests that want the ground
//! truth of one part of a scene (its participating media) without the CPU's surfaces, so that
//! differences no technique of that kind owns (shadow-map edges of the shared raster pass)
//! stay out of the error.
//!
//! [`with_reference_media`] composites exactly the reference's media ([`Media`]) along the
//! primary ray through each pixel centre over an image of the scene without volumes, clipped at
//! per-pixel surface distances: [`primary_distances`] (the reference's own primary hits) or
//! the raster pass's (its alpha channel).

use crate::media::Media;
use glam::Vec3;
use gpu::HdrImage;
use scene::bvh::SceneBvh;
use scene::{Camera, Scene};

/// Per pixel (row 0 at the top), the distance along the primary ray through the pixel centre
/// to the first surface of the scene at `time`, `f32::INFINITY` where it sees none. These are
/// the reference's primary hits.
pub fn primary_distances(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
) -> Vec<f32> {
    let bvh = SceneBvh::build(scene, time);
    primary_hits(&bvh, camera, width, height, |t, _| t)
}

/// Per pixel (row 0 at the top), `f(t, dir)` of the primary ray through the pixel centre,
/// `dir` its direction and `t` the distance to its first surface (`f32::INFINITY` where it
/// sees none).
pub fn primary_hits(
    bvh: &SceneBvh,
    camera: &Camera,
    width: u32,
    height: u32,
    f: impl Fn(f32, Vec3) -> f32,
) -> Vec<f32> {
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let (origin, dir) = camera.ray(x as f32 + 0.5, y as f32 + 0.5, width, height);
            let t = bvh
                .closest_hit(origin, dir, f32::INFINITY)
                .map_or(f32::INFINITY, |h| h.t);
            out.push(f(t, dir));
        }
    }
    out
}

/// Applies `f(pixel index, primary ray origin, primary ray direction, base radiance)` to every
/// pixel of `base` (alpha kept).
pub fn per_pixel(
    camera: &Camera,
    base: &HdrImage,
    f: impl Fn(usize, Vec3, Vec3, Vec3) -> Vec3,
) -> HdrImage {
    let (w, h) = (base.width, base.height);
    let mut out = base.clone();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let (origin, dir) = camera.ray(x as f32 + 0.5, y as f32 + 0.5, w, h);
            let p = base.pixels[i];
            let c = f(i, origin, dir, Vec3::new(p[0], p[1], p[2]));
            out.pixels[i] = [c.x, c.y, c.z, p[3]];
        }
    }
    out
}

/// `base` (an image of the scene without volumes) seen through the scene's media along each
/// primary ray, clipped at `distances` ([`primary_distances`], or the raster pass's): what
/// [`crate::reference`] does to the primary rays of its pixels. Every volume of the scene is
/// included.
///
/// # Panics
/// If `distances` does not have one entry per pixel of `base`.
pub fn with_reference_media(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    base: &HdrImage,
    distances: &[f32],
) -> HdrImage {
    assert_eq!(
        distances.len(),
        base.pixels.len(),
        "with_reference_media: one distance per pixel"
    );
    let media = Media::new(scene, time);
    per_pixel(camera, base, |i, origin, dir, behind| {
        media.composite(origin, dir, distances[i], behind)
    })
}
