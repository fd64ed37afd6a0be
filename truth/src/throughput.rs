//! Rays per second of the reference's BVH (`scene::bvh::SceneBvh`, built by obvhs), measured
//! as ray-tracing papers and Mitsuba's benchmarks measure a traversal: fixed sets of rays cast
//! one at a time on every thread of rayon's pool, each set timed apart.
//!
//! Five sets, of one ray (or photon) per pixel of the image:
//!
//! - *coherent closest-hit*: one camera ray through each pixel centre (`Camera::ray`), what the
//!   reference's eye pass starts with;
//! - *incoherent closest-hit*: rays from points uniform in the scene's bounds in directions
//!   uniform on the sphere, like the photons of the light pass;
//! - *coherent any-hit*: from the first surface of each camera ray that meets one (pushed off
//!   it as the reference pushes), to the scene's first light: shadow rays as the eye pass casts
//!   them from a diffuse first surface (this set starts on every kind of surface, and casts
//!   none for a pixel that sees the background or a scene without lights);
//! - *incoherent any-hit*: segments between two points uniform in the scene's bounds;
//! - *photon paths*, closest-hit: the light pass's own rays ([`crate::reference::photon_rays`]),
//!   every segment of the caustic photons the reference traces, as many photons as pixels (a
//!   few rays each; none in a scene without a caustic caster). Photons refracted into a glass
//!   object cross it from inside, the hard case of a BVH over a closed mesh, and these are most
//!   of a reference render's rays.
//!
//! The rays are made once, before any is timed; each set is cast `rounds` times and each
//! round's rate kept, so a table can give the median and the spread.

use crate::reference::{ReferenceOptions, SplitMix64};
use glam::Vec3;
use rayon::prelude::*;
use scene::bvh::SceneBvh;
use scene::{Camera, Scene};
use std::time::Instant;

/// What a ray asks of the BVH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// The nearest hit (`SceneBvh::closest_hit`).
    Closest,
    /// Whether anything lies on the segment (`SceneBvh::any_hit`): a shadow ray.
    Any,
}

/// One ray of a set: origin, unit direction, largest distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestRay {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_max: f32,
}

/// A named set of rays and the query they make.
#[derive(Clone, Debug)]
pub struct RaySet {
    pub name: &'static str,
    pub query: Query,
    pub rays: Vec<TestRay>,
}

/// The five sets of the module documentation for `camera` at `width` x `height` (random points
/// and directions from `seed`; the photon paths those of a reference rendered with `options`).
pub fn ray_sets(
    scene: &Scene,
    bvh: &SceneBvh,
    camera: &Camera,
    (width, height): (u32, u32),
    (seed, options): (u32, &ReferenceOptions),
) -> Vec<RaySet> {
    let camera_rays: Vec<TestRay> = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (origin, dir) = camera.ray(x as f32 + 0.5, y as f32 + 0.5, width, height);
            TestRay {
                origin,
                dir,
                t_max: f32::INFINITY,
            }
        })
        .collect();
    let count = camera_rays.len();
    let shadow_rays = shadow_rays(scene, bvh, &camera_rays);
    let mut random = SplitMix64::new(seed as u64);
    let (low, high) = bvh.bounds();
    let mut point =
        || low + (high - low) * Vec3::new(random.next_f32(), random.next_f32(), random.next_f32());
    let (mut scattered, mut segments) = (Vec::with_capacity(count), Vec::with_capacity(count));
    for _ in 0..count {
        let (a, b) = (point(), point());
        scattered.push(TestRay {
            origin: a,
            dir: Vec3::ZERO,
            t_max: f32::INFINITY,
        });
        let length = (b - a).length();
        segments.push(TestRay {
            origin: a,
            dir: (b - a).normalize_or(Vec3::X),
            t_max: length.max(f32::MIN_POSITIVE),
        });
    }
    for ray in &mut scattered {
        ray.dir = uniform_direction(random.next_f32(), random.next_f32());
    }
    vec![
        RaySet {
            name: "coherent closest-hit (camera rays)",
            query: Query::Closest,
            rays: camera_rays,
        },
        RaySet {
            name: "incoherent closest-hit (random rays in the bounds)",
            query: Query::Closest,
            rays: scattered,
        },
        RaySet {
            name: "coherent any-hit (first surfaces to the first light)",
            query: Query::Any,
            rays: shadow_rays,
        },
        RaySet {
            name: "incoherent any-hit (random segments in the bounds)",
            query: Query::Any,
            rays: segments,
        },
        RaySet {
            name: "photon paths (the light pass's rays)",
            query: Query::Closest,
            rays: photon_paths(scene, count as u64, options),
        },
    ]
}

/// Every segment of `photons` caustic photons, as the reference's light pass traces them.
fn photon_paths(scene: &Scene, photons: u64, options: &ReferenceOptions) -> Vec<TestRay> {
    crate::reference::photon_rays(scene, 0.0, photons, options)
        .into_iter()
        .map(|(origin, dir)| TestRay {
            origin,
            dir,
            t_max: f32::INFINITY,
        })
        .collect()
}

/// From each camera ray's first surface to the first light (none where the scene has no
/// light or the ray no surface).
fn shadow_rays(scene: &Scene, bvh: &SceneBvh, camera_rays: &[TestRay]) -> Vec<TestRay> {
    let Some(light) = scene.lights.first() else {
        return Vec::new();
    };
    camera_rays
        .iter()
        .filter_map(|r| {
            let hit = bvh.closest_hit(r.origin, r.dir, r.t_max)?;
            let facing = if hit.geometric_normal.dot(r.dir) < 0.0 {
                hit.geometric_normal
            } else {
                -hit.geometric_normal
            };
            let origin = hit.position + facing * crate::offset_epsilon(hit.position);
            let (dir, t_max) = light.shadow_ray(origin)?;
            Some(TestRay { origin, dir, t_max })
        })
        .collect()
}

/// A set's rays cast `rounds` times: the rays, how many hit, and each round's seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct Throughput {
    pub name: &'static str,
    pub query: Query,
    pub rays: usize,
    pub hits: usize,
    pub round_seconds: Vec<f64>,
}

impl Throughput {
    /// Millions of rays per second of each round, slowest first.
    pub fn mrays_per_second(&self) -> Vec<f64> {
        let mut rates: Vec<f64> = self
            .round_seconds
            .iter()
            .map(|s| self.rays as f64 / s / 1e6)
            .collect();
        rates.sort_by(f64::total_cmp);
        rates
    }

    /// The median round's rate (millions of rays per second).
    pub fn median(&self) -> f64 {
        let rates = self.mrays_per_second();
        rates.get(rates.len() / 2).copied().unwrap_or(0.0)
    }
}

/// Rays per task: enough that rayon's scheduling is a small share, few enough to balance.
const CHUNK: usize = 1024;

/// Casts `set` `rounds` times on rayon's current pool.
pub fn measure(bvh: &SceneBvh, set: &RaySet, rounds: u32) -> Throughput {
    let cast = |r: &TestRay| match set.query {
        Query::Closest => bvh.closest_hit(r.origin, r.dir, r.t_max).is_some(),
        Query::Any => bvh.any_hit(r.origin, r.dir, r.t_max),
    };
    let mut hits = 0;
    let mut round_seconds = Vec::new();
    for _ in 0..rounds.max(1) {
        let start = Instant::now();
        hits = set
            .rays
            .par_chunks(CHUNK)
            .map(|chunk| chunk.iter().filter(|r| cast(r)).count())
            .sum();
        round_seconds.push(start.elapsed().as_secs_f64().max(1e-9));
    }
    Throughput {
        name: set.name,
        query: set.query,
        rays: set.rays.len(),
        hits,
        round_seconds,
    }
}

/// A direction uniform on the unit sphere from two numbers uniform in [0, 1): `z` uniform in
/// [-1, 1] (Archimedes) and the azimuth uniform.
fn uniform_direction(u: f32, v: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * v;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every set has one ray per pixel (the shadow rays: one per pixel that sees a surface and
    /// a light; the photon paths: a few per photon), unit directions and positive lengths;
    /// casting them finds what the BVH finds ray by ray; every round is kept.
    #[test]
    fn sets_are_what_they_say_and_measuring_counts_their_hits() {
        let scene = scene::load("cornell-sphere").unwrap();
        let bvh = SceneBvh::build(&scene, 0.0);
        let options = ReferenceOptions::default();
        let sets = ray_sets(&scene, &bvh, &scene.camera, (16, 12), (7, &options));
        assert_eq!(sets.len(), 5);
        for set in &sets {
            let expected = if set.name.contains("first light") {
                assert!(!set.rays.is_empty() && set.rays.len() <= 16 * 12);
                set.rays.len()
            } else if set.name.contains("photon") {
                // At least a segment per photon (light to caster), and more through the glass.
                assert!(set.rays.len() > 2 * 16 * 12, "{}", set.rays.len());
                set.rays.len()
            } else {
                16 * 12
            };
            assert_eq!(set.rays.len(), expected, "{}", set.name);
            for r in &set.rays {
                assert!((r.dir.length() - 1.0).abs() < 1e-4, "{}: {r:?}", set.name);
                assert!(r.t_max > 0.0, "{}: {r:?}", set.name);
            }
            let measured = measure(&bvh, set, 3);
            let hits = set
                .rays
                .iter()
                .filter(|r| match set.query {
                    Query::Closest => bvh.closest_hit(r.origin, r.dir, r.t_max).is_some(),
                    Query::Any => bvh.any_hit(r.origin, r.dir, r.t_max),
                })
                .count();
            assert_eq!(measured.hits, hits, "{}", set.name);
            assert_eq!(measured.round_seconds.len(), 3);
        }
        // Inside the closed box every camera ray and every random ray meets a wall.
        assert_eq!(measure(&bvh, &sets[0], 1).hits, 16 * 12);
        assert_eq!(measure(&bvh, &sets[1], 1).hits, 16 * 12);
    }

    /// The random rays' directions are uniform on the sphere (each axis's mean |component| is
    /// 1/2, the mean direction 0) and their origins uniform in the bounds (mean at the centre).
    #[test]
    fn random_rays_are_uniform() {
        let scene = scene::load("chess").unwrap();
        let bvh = SceneBvh::build(&scene, 0.0);
        let options = ReferenceOptions::default();
        let sets = ray_sets(&scene, &bvh, &scene.camera, (128, 128), (3, &options));
        let rays = &sets[1].rays;
        let n = rays.len() as f32;
        let mean_abs = rays.iter().map(|r| r.dir.abs()).sum::<Vec3>() / n;
        let mean = rays.iter().map(|r| r.dir).sum::<Vec3>() / n;
        assert!(mean_abs.abs_diff_eq(Vec3::splat(0.5), 0.01), "{mean_abs}");
        assert!(mean.abs_diff_eq(Vec3::ZERO, 0.02), "{mean}");
        let (low, high) = bvh.bounds();
        let centre = rays.iter().map(|r| r.origin).sum::<Vec3>() / n;
        let tolerance = (high - low).max_element() * 0.01;
        assert!(
            centre.abs_diff_eq((low + high) / 2.0, tolerance),
            "{centre}"
        );
        let segment_ends = sets[3].rays.iter().map(|r| r.origin + r.dir * r.t_max);
        let end_centre = segment_ends.sum::<Vec3>() / n;
        assert!(
            end_centre.abs_diff_eq((low + high) / 2.0, tolerance),
            "{end_centre}"
        );
    }

    /// The photon paths are the light pass's own segments: as many as the light pass of a
    /// reference with the same options traces (its rays less its connections to the eye), at
    /// the default depth and at another.
    #[test]
    fn photon_paths_replay_the_light_pass() {
        use crate::reference::{PhotonSetup, light_trace, photon_rays};
        let scene = scene::load("hu-qin").unwrap();
        for max_depth in [8, 2] {
            let options = ReferenceOptions {
                photons: 20_000,
                max_depth,
                ..ReferenceOptions::default()
            };
            let setup = PhotonSetup::caustics(&scene);
            let pass = light_trace(&scene, &scene.camera, 0.0, 32, 32, &options, &setup);
            let replayed = photon_rays(&scene, 0.0, options.photons, &options);
            assert_eq!(
                replayed.len() as u64,
                pass.segments,
                "max_depth {max_depth}"
            );
            assert!(
                pass.segments < pass.rays,
                "the connections are not segments"
            );
        }
    }
}
