//! What the volume variants are measured against, on the CPU: shared by the tests
//! (`mod common;`) and the example (`#[path = "../tests/common/mod.rs"] mod common;`). It is not
//! part of the library, which depends on neither this nor the `truth` crate.
//!
//! **The ground truth** is the scene's reference (`truth::reference`), which renders the
//! volumes as participating media (`truth::media`: Beer-Lambert emission-absorption of the
//! density field defined in `scene::density`, independently of any technique). The harness
//! compares every `volumes/*` variant with that image; the crate does not implement
//! `Technique::ground_truth`. For tests that want the truth over the raster pass's image
//! instead of the CPU surfaces (so that shadow-map edges, which no volume technique owns, stay
//! out of the error), `truth::composite::with_reference_media` composites exactly the
//! reference's media for the primary ray of each pixel over a volume-free image.
//!
//! **The variant model** ([`variant_model`]) is a second, clearly separate figure: every
//! volume as a *uniform* sphere composited with the variant's own opacity function and its
//! calibrated scale (`technique::opacity_scale`), exact path lengths against the exact scene
//! depth. The error against it is the error of a variant's geometry alone (billboard, slices,
//! primitive, depth source, buffer precision); the error against the ground truth adds what
//! its model of the medium leaves out (the falloff, the texture, Beer-Lambert). Tests use it to
//! check the GPU paths; it is never the harness's error.
#![allow(dead_code)] // each test binary and the example use a part

use glam::Vec3;
use gpu::HdrImage;
use gpu::prelude::ray_sphere;
use scene::{Camera, Scene};
use truth::composite::per_pixel;
use volumes::path_length::{OpacityFn, sphere_path_length};
use volumes::technique::{VolumeSet, all_variants, opacity_scale};

/// Per pixel: whether the primary ray crosses a volume of `set` in front of its first
/// surface (the pixels a volume technique changes; use as the metrics mask).
pub fn volume_mask(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
    distances: &[f32],
    set: VolumeSet,
) -> Vec<bool> {
    let spheres = spheres(scene, set, time, OpacityFn::Log);
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let dir = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, width, height);
            let t_scene = distances[(y * width + x) as usize];
            out.push(
                spheres.iter().any(|s| {
                    sphere_path_length(camera.eye, dir, s.center, s.radius, t_scene) > 0.0
                }),
            );
        }
    }
    out
}

/// What the variant model of one variant is: its opacity function and its volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TruthSpec {
    pub opacity: OpacityFn,
    pub set: VolumeSet,
}

/// The variant-model specification of a technique id of this crate (`None` for other ids).
pub fn spec_for(technique_id: &str) -> Option<TruthSpec> {
    all_variants()
        .into_iter()
        .find(|v| v.id() == technique_id)
        .map(|v| TruthSpec {
            opacity: v.opacity,
            set: v.set,
        })
}

/// A volume of the variant model: a uniform sphere with the variant's opacity scale.
struct Sphere {
    center: Vec3,
    radius: f32,
    color: Vec3,
    scale: f32,
}

fn spheres(scene: &Scene, set: VolumeSet, time: f32, opacity: OpacityFn) -> Vec<Sphere> {
    scene
        .volumes
        .iter()
        .filter(|v| set.includes(v))
        .map(|v| Sphere {
            center: v.center + v.motion.offset(time),
            radius: v.radius,
            color: v.color,
            scale: opacity_scale(v, opacity),
        })
        .collect()
}

/// The variant model of `spec` composited over `base` (see the module documentation):
/// uniform spheres, the variant's opacity function, layers back to front (by the midpoint of
/// each visible segment) with `c = c (1 - a) + colour a`.
///
/// # Panics
/// If `distances` does not have one entry per pixel of `base`.
pub fn variant_model(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    base: &HdrImage,
    distances: &[f32],
    spec: TruthSpec,
) -> HdrImage {
    assert_eq!(
        distances.len(),
        base.pixels.len(),
        "variant_model: one distance per pixel"
    );
    let spheres = spheres(scene, spec.set, time, spec.opacity);
    per_pixel(camera, base, |i, origin, dir, behind| {
        layers(&spheres, origin, dir, distances[i], behind, spec.opacity)
    })
}

fn layers(
    spheres: &[Sphere],
    eye: Vec3,
    dir: Vec3,
    t_scene: f32,
    behind: Vec3,
    opacity: OpacityFn,
) -> Vec3 {
    // (midpoint of the visible segment, opacity, colour)
    let mut layers: Vec<(f32, f32, Vec3)> = Vec::new();
    for s in spheres {
        let len = sphere_path_length(eye, dir, s.center, s.radius, t_scene);
        if len <= 0.0 {
            continue;
        }
        let t = ray_sphere(eye, dir, s.center, s.radius);
        let mid = 0.5 * (t.x.max(0.0) + t.y.min(t_scene));
        layers.push((mid, opacity.opacity(len, s.scale), s.color));
    }
    layers.sort_by(|a, b| b.0.total_cmp(&a.0));
    layers
        .iter()
        .fold(behind, |c, &(_, a, colour)| c * (1.0 - a) + colour * a)
}
