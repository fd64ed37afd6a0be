//! What a reference render cost: its rays ([`ReferenceStats`]), its phases (BVH build, eye pass,
//! light pass), always measured, and inside them the parts a profiled render ([`render_profiled`]) times on every
//! thread: direct light with its shadow rays, the eye pass's media, the light pass's connections
//! to the eye and its photon beams.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// What a render cost. Every ray cast is counted once.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReferenceStats {
    /// Closest-hit rays of the eye pass: primary rays (plus one centre ray per pixel for ids
    /// when `samples_per_pixel > 1`) and every reflected or refracted ray.
    pub camera_rays: u64,
    /// Any-hit rays from diffuse points of the eye pass to the lights.
    pub shadow_rays: u64,
    /// Rays of the light pass: every photon path segment plus each landed photon's
    /// visibility ray to the eye.
    pub photon_rays: u64,
    /// Wall-clock seconds of the whole render (BVH build, eye pass, light pass).
    pub seconds: f64,
    /// The same split by phase.
    pub phases: RenderPhases,
    /// All rays above divided by `seconds`.
    pub rays_per_second: f64,
    /// Photons that landed on a diffuse surface after a specular interaction and were added
    /// to a pixel (visible to the eye).
    pub photons_stored: u64,
}

/// Wall-clock seconds of a render's phases (they add up to its `seconds`, to the bookkeeping
/// between them).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderPhases {
    /// The scene's BVH and media built for the frame's time.
    pub bvh_seconds: f64,
    /// The eye pass: camera rays, their specular chains, shadow rays, the media.
    pub eye_seconds: f64,
    /// The light pass: caustic photons and beams (0 without photons).
    pub light_seconds: f64,
}

/// The parts of a profiled render, each the thread-seconds spent in it divided by the render's
/// threads: the wall-clock share it takes when the threads are evenly busy. Each timed call
/// reads the clock twice, which a profiled render pays for (its `seconds` against an
/// unprofiled one's says how much).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderParts {
    /// Threads of the render (rayon's pool it ran in).
    pub threads: usize,
    /// Eye pass: direct light at diffuse points, its shadow rays to every light included.
    pub direct_light_seconds: f64,
    /// Eye pass: the volumes composited along each ray, and the scattering medium's
    /// transmittance and direct in-scattering (its shadow rays included).
    pub eye_media_seconds: f64,
    /// Light pass: each landed photon's visibility ray to the eye, and its splat.
    pub connection_seconds: f64,
    /// Light pass: the photon beams splatted through the scattering medium.
    pub beam_seconds: f64,
}

/// A part of a render [`PartClock`] times.
#[derive(Clone, Copy, Debug)]
pub(super) enum Part {
    DirectLight,
    EyeMedia,
    Connections,
    Beams,
}

/// Nanoseconds spent in each [`Part`], summed over threads; counts nothing when off.
pub(super) struct PartClock {
    on: bool,
    nanos: [AtomicU64; 4],
}

impl PartClock {
    pub(super) fn new(on: bool) -> Self {
        Self {
            on,
            nanos: Default::default(),
        }
    }

    /// Times `part` until the returned guard drops.
    pub(super) fn timer(&self, part: Part) -> PartTimer<'_> {
        PartTimer {
            clock: self,
            part,
            start: self.on.then(Instant::now),
        }
    }

    /// The parts, each per thread of `threads`.
    pub(super) fn parts(&self, threads: usize) -> RenderParts {
        let seconds = |part: Part| {
            self.nanos[part as usize].load(Ordering::Relaxed) as f64 * 1e-9 / threads as f64
        };
        RenderParts {
            threads,
            direct_light_seconds: seconds(Part::DirectLight),
            eye_media_seconds: seconds(Part::EyeMedia),
            connection_seconds: seconds(Part::Connections),
            beam_seconds: seconds(Part::Beams),
        }
    }
}

/// Adds the time since it was made to its part when it drops.
pub(super) struct PartTimer<'a> {
    clock: &'a PartClock,
    part: Part,
    start: Option<Instant>,
}

impl Drop for PartTimer<'_> {
    fn drop(&mut self) {
        if let Some(start) = self.start {
            let nanos = start.elapsed().as_nanos() as u64;
            self.clock.nanos[self.part as usize].fetch_add(nanos, Ordering::Relaxed);
        }
    }
}
