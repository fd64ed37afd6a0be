//! The exact soft volume, on the CPU: the ground truth the volume techniques are measured
//! against.
//!
//! The foundation's reference renderer leaves volumes out (it only flags the pixels whose
//! primary ray crosses one). This module composites the scene's volumes over an image of the
//! scene without them (the reference image, or in tests the raster pass), per pixel:
//!
//! * the primary ray through the pixel centre (`Camera::ray_dir`, the reference's ray) and
//!   the distance `t_scene` to the first surface along it (the BVH's closest hit, or
//!   infinity);
//! * for every volume of the technique's set, the exact path length inside its sphere, from
//!   `max(t_near, 0)` (the eye may be inside) to `min(t_far, t_scene)`:
//!   [`sphere_path_length`];
//! * its opacity by the *same* path-length-to-opacity function as the variant under test
//!   ([`OpacityFn`]: linear, logarithmic or square root, thesis figure 6.21), so that the
//!   error measures the geometry (billboard, slices, primitive, depth source), not the choice
//!   of function;
//! * the volumes composited back to front along the ray (sorted by the midpoint of each
//!   visible segment) with the `over` operator: `c = c (1 - a) + colour a`.
//!
//! A volume is a uniform medium bounded by a sphere (`scene::Volume`), with its `motion`
//! applied at `time`. Overlapping volumes are composited as separate layers (what a particle
//! system does), not as one medium of summed density.

use crate::path_length::{OpacityFn, sphere_path_length};
use crate::technique::all_variants;
use glam::Vec3;
use gpu::HdrImage;
use gpu::prelude::ray_sphere;
use scene::bvh::SceneBvh;
use scene::{Camera, Scene, Volume};

/// Which volumes of a scene a variant draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolumeSet {
    /// The large volumes (`particle == false`): the thesis's "simple, large particle" that its
    /// 17 tests analyse.
    Single,
    /// Every volume (the particle-system versions).
    All,
}

impl VolumeSet {
    pub fn includes(self, v: &Volume) -> bool {
        match self {
            VolumeSet::Single => !v.particle,
            VolumeSet::All => true,
        }
    }
}

/// What the ground truth of one variant is: its opacity function and its volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TruthSpec {
    pub opacity: OpacityFn,
    pub set: VolumeSet,
}

/// The ground-truth specification of a technique id of this crate (`None` for other ids).
pub fn spec_for(technique_id: &str) -> Option<TruthSpec> {
    all_variants().into_iter().find(|v| v.id() == technique_id).map(|v| TruthSpec { opacity: v.opacity, set: v.set })
}

/// Per pixel (row 0 at the top), the distance along the primary ray through the pixel centre
/// to the first surface of the scene at `time`, `f32::INFINITY` where it sees none. These are
/// the reference's primary hits.
pub fn primary_distances(scene: &Scene, camera: &Camera, time: f32, width: u32, height: u32) -> Vec<f32> {
    let bvh = SceneBvh::build(scene, time);
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let dir = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, width, height);
            out.push(bvh.closest_hit(camera.eye, dir, f32::INFINITY).map_or(f32::INFINITY, |h| h.t));
        }
    }
    out
}

/// A volume placed at `time`.
struct Sphere {
    center: Vec3,
    radius: f32,
    color: Vec3,
    density: f32,
}

fn spheres(scene: &Scene, set: VolumeSet, time: f32) -> Vec<Sphere> {
    scene
        .volumes
        .iter()
        .filter(|v| set.includes(v))
        .map(|v| Sphere {
            center: v.center + v.motion.offset(time),
            radius: v.radius,
            color: v.color,
            density: v.density,
        })
        .collect()
}

/// The radiance behind the volumes, `behind`, seen through every volume of `spec` along the
/// ray `(eye, dir)` whose first surface is at `t_scene`.
pub fn composite_ray(
    scene: &Scene,
    time: f32,
    eye: Vec3,
    dir: Vec3,
    t_scene: f32,
    behind: Vec3,
    spec: TruthSpec,
) -> Vec3 {
    composite_with(&spheres(scene, spec.set, time), eye, dir, t_scene, behind, spec.opacity)
}

fn composite_with(spheres: &[Sphere], eye: Vec3, dir: Vec3, t_scene: f32, behind: Vec3, opacity: OpacityFn) -> Vec3 {
    // (midpoint of the visible segment, opacity, colour)
    let mut layers: Vec<(f32, f32, Vec3)> = Vec::new();
    for s in spheres {
        let len = sphere_path_length(eye, dir, s.center, s.radius, t_scene);
        if len <= 0.0 {
            continue;
        }
        let t = ray_sphere(eye, dir, s.center, s.radius);
        let mid = 0.5 * (t.x.max(0.0) + t.y.min(t_scene));
        layers.push((mid, opacity.opacity(len, s.density), s.color));
    }
    layers.sort_by(|a, b| b.0.total_cmp(&a.0));
    layers.iter().fold(behind, |c, &(_, a, colour)| c * (1.0 - a) + colour * a)
}

/// `base` (the scene without volumes, e.g. the reference image) with the volumes of `spec`
/// composited over it; `distances` are the primary-hit distances ([`primary_distances`]).
/// Alpha is kept from `base`.
///
/// # Panics
/// If `distances` does not have one entry per pixel of `base`.
pub fn composite(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    base: &HdrImage,
    distances: &[f32],
    spec: TruthSpec,
) -> HdrImage {
    let (w, h) = (base.width, base.height);
    assert_eq!(distances.len(), (w * h) as usize, "ground_truth::composite: one distance per pixel");
    let spheres = spheres(scene, spec.set, time);
    let mut out = base.clone();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let dir = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, w, h);
            let p = base.pixels[i];
            let c = composite_with(&spheres, camera.eye, dir, distances[i], Vec3::new(p[0], p[1], p[2]), spec.opacity);
            out.pixels[i] = [c.x, c.y, c.z, p[3]];
        }
    }
    out
}

/// [`composite`] with the distances computed here.
pub fn render(scene: &Scene, camera: &Camera, time: f32, base: &HdrImage, spec: TruthSpec) -> HdrImage {
    let distances = primary_distances(scene, camera, time, base.width, base.height);
    composite(scene, camera, time, base, &distances, spec)
}

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
    let spheres = spheres(scene, set, time);
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let dir = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, width, height);
            let t_scene = distances[(y * width + x) as usize];
            out.push(spheres.iter().any(|s| sphere_path_length(camera.eye, dir, s.center, s.radius, t_scene) > 0.0));
        }
    }
    out
}

/// The hook for the harness: if `technique_id` is one of this crate's variants, composites
/// its ground-truth volumes over `reference` (the volume-free reference image of `scene`
/// seen by `camera` at `time`) and returns true; otherwise leaves it and returns false.
pub fn apply_to_reference(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    technique_id: &str,
    reference: &mut HdrImage,
) -> bool {
    let Some(spec) = spec_for(technique_id) else { return false };
    *reference = render(scene, camera, time, reference, spec);
    true
}
