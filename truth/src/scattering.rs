//! Single scattering in the scene's homogeneous medium ([`scene::Medium`]): the ground truth of
//! light shafts.
//!
//! Radiance arriving at the eye along a ray that crosses the medium over `[a, b]` (clipped at its
//! first surface) is
//!
//! ```text
//! L = T(a, b) L_behind + integral_a^b T(a, t) sigma_s integral_S2 p(w_i . -d) L_i(x(t), w_i) dw_i dt
//! ```
//!
//! with `T` the Beer-Lambert transmittance `exp(-sigma_t len)` and `p` the Henyey-Greenstein
//! phase function. `L_i` is the light arriving at `x(t)` straight from a light (no
//! specular event) or after one or more specular events (through the water's surface): single
//! scattering, both ways, and nothing scattered twice. The reference splits it the way it
//! splits surface lighting:
//!
//! * **Direct in-scattering** is integrated along every eye-pass ray ([`direct_inscatter`]):
//!   per light, a midpoint rule over the equiangular parameter of the segment (Kulla and
//!   Fajardo 2012: `t = Delta + D tan theta`, where the light lies at distance `D` from the
//!   ray's line, at `Delta` along it), which turns the `1 / d^2` of the light into a constant
//!   and leaves a smooth integrand; [`INSCATTER_STEPS`] steps per light, each with a shadow
//!   ray (every surface blocks it, glass included, as for surfaces) and the medium's
//!   transmittance toward the light.
//! * **In-scattering after specular events** cannot be found from the eye (its shadow rays hit
//!   the glass), so it is light-traced: every caustic photon's path segments inside the medium
//!   are *photon beams* (Jarosz, Nowrouzezahrai, Sadeghi and Jensen 2011). A beam of flux `Phi`
//!   at its start scatters toward the eye, per unit length `ds` at `x(s)`, the intensity
//!   `Phi T_beam(s) sigma_s p(w . w_c) ds`, which reaches the pinhole as irradiance
//!   `T_eye / d^2` times that; with the pixel importance `W = 1 / (A_pix cos^3 theta_c)` of
//!   the caustic photons (`reference`'s derivation), pixel `j` receives
//!
//!   ```text
//!   dI_j = Phi T_beam(s) sigma_s p(w . w_c) T_eye(s) W / d(s)^2 ds      (x(s) seen in pixel j)
//!   ```
//!
//!   An orthographic camera's film gathers the parallel light straight back along its view
//!   direction, `W / d^2` becoming `1 / A_pix` with `A_pix` the pixel's area in the world
//!   (`scene::Film::importance`).
//!
//!   [`BeamSplatter::splat`] integrates this along each beam by the midpoint rule, at least
//!   two steps per pixel the beam crosses on the image, each step added to the pixel it
//!   projects into: the estimate is deterministic (the photons are), unbiased as the photon
//!   count grows, and far less noisy than photon points, because each beam lights every pixel
//!   it crosses (`truth/tests/reference_scattering.rs` shows the convergence).
//!
//! Neither estimator counts the medium within [`EYE_CLEARANCE`] of the eye (its rays'
//! in-scattering starts there; their transmittance at the eye): beams passing the eye closer
//! would make the beam estimate's variance unbounded. With it, `murky-pool`'s beams converge
//! as `1 / sqrt(photons)`. Direct in-scattering on a secondary ray (reflected, refracted)
//! starts at its origin.
//!
//! A point `x(s)` is seen in its pixel when it lies in front of the surface the pixel's centre
//! ray meets (its view-space depth below that surface's): the reference's own primary hits,
//! sampled at pixel centres as every surface is. Beams seen only through a specular surface are
//! left out, as caustics seen through one are. Photons are attenuated by the medium on every
//! segment, and so are the eye's rays and the shadow rays of direct lighting.

use crate::offset_epsilon;
use glam::{Mat4, Vec2, Vec3};
use scene::bvh::SceneBvh;
use scene::medium::{EYE_CLEARANCE, henyey_greenstein, transmittance_of};
use scene::{Camera, Film, Medium, Scene};

/// Midpoint steps per light of the direct in-scattering along one ray segment.
pub const INSCATTER_STEPS: u32 = 64;

/// Largest number of steps along one beam (a beam passing next to the eye projects across the
/// whole image; its steps are spread thinner past this).
pub const MAX_BEAM_STEPS: u32 = 16384;

/// Beam steps per pixel the beam crosses on the image.
pub const BEAM_STEPS_PER_PIXEL: f32 = 2.0;

/// Direct single scattering of every light along `origin + t dir`, `t` in `span` (the part
/// inside the medium, clipped at the first surface) beyond `clearance` ([`EYE_CLEARANCE`] for
/// the eye's own rays, 0 for the others), attenuated from `span.x`: add `T(0, span.x)` times
/// this to the ray's radiance. Counts its shadow rays in `shadow_rays`.
#[allow(clippy::too_many_arguments)]
pub fn direct_inscatter(
    scene: &Scene,
    bvh: &SceneBvh,
    medium: &Medium,
    origin: Vec3,
    dir: Vec3,
    span: Vec2,
    clearance: f32,
    shadow_rays: &mut u64,
) -> Vec3 {
    let entry = span.x;
    let span = Vec2::new(span.x.max(clearance), span.y);
    if span.x >= span.y {
        return Vec3::ZERO;
    }
    let sigma_t = medium.extinction();
    let g = medium.anisotropy;
    let mut sum = Vec3::ZERO;
    for light in &scene.lights {
        if light.intensity.max_element() <= 0.0 {
            continue;
        }
        let along = (light.position - origin).dot(dir);
        let foot = origin + dir * along;
        let dist_to_line = foot.distance(light.position);
        // Equiangular parameter: theta in [theta_a, theta_b], t = along + D tan(theta), and
        // dt / d^2 = dtheta / D. A light on the ray's line (D ~ 0) takes uniform steps in t,
        // and so does a directional light, whose light has no 1 / d^2 to flatten.
        let directional = light.is_directional();
        let uniform = directional || dist_to_line < 1e-4 * offset_epsilon(light.position).max(1.0);
        let (theta_a, theta_b) = (
            ((span.x - along) / dist_to_line).atan(),
            ((span.y - along) / dist_to_line).atan(),
        );
        for i in 0..INSCATTER_STEPS {
            let f = (i as f32 + 0.5) / INSCATTER_STEPS as f32;
            let (t, weight) = if uniform {
                let dt = (span.y - span.x) / INSCATTER_STEPS as f32;
                let t = span.x + f * (span.y - span.x);
                let d2 = if directional {
                    1.0
                } else {
                    (origin + dir * t)
                        .distance_squared(light.position)
                        .max(1e-12)
                };
                (t, dt / d2)
            } else {
                let theta = theta_a + f * (theta_b - theta_a);
                let dtheta = (theta_b - theta_a) / INSCATTER_STEPS as f32;
                (along + dist_to_line * theta.tan(), dtheta / dist_to_line)
            };
            let x = origin + dir * t;
            let Some((l, len)) = light.shadow_ray(x) else {
                continue;
            };
            let factor = light.emission_factor(-l);
            if factor <= 0.0 {
                continue;
            }
            *shadow_rays += 1;
            if bvh.any_hit(x, l, len) {
                continue;
            }
            // Light travels along -l; it leaves toward the eye along -dir.
            let phase = henyey_greenstein((-l).dot(-dir), g);
            let toward_light = medium.transmittance(x, l, len);
            let toward_eye = transmittance_of(sigma_t, t - entry);
            sum += light.intensity
                * factor
                * medium.scattering
                * toward_light
                * toward_eye
                * (phase * weight);
        }
    }
    sum
}

/// Splats photon beams onto the eye's image (the pixel-importance estimator above).
pub struct BeamSplatter<'a> {
    medium: &'a Medium,
    camera: Camera,
    view_proj: Mat4,
    forward: Vec3,
    film: Film,
    width: u32,
    height: u32,
    /// Per pixel, the view-space depth of the surface the pixel's centre ray meets (infinite
    /// where it meets none).
    depths: &'a [f32],
}

impl<'a> BeamSplatter<'a> {
    /// `depths`: per pixel (row 0 at the top) the view-space depth of the first surface on the
    /// pixel's centre ray ([`view_depths`]).
    pub fn new(
        medium: &'a Medium,
        camera: &Camera,
        width: u32,
        height: u32,
        depths: &'a [f32],
    ) -> Self {
        BeamSplatter {
            medium,
            camera: *camera,
            view_proj: camera.view_proj(width, height),
            forward: camera.basis().0,
            film: camera.film(width, height),
            width,
            height,
            depths,
        }
    }

    /// Adds the beam `origin + s dir`, `s` in `[0, length]`, of flux `power` at `origin`, to
    /// `image` (one radiance per pixel). Returns the number of steps taken.
    pub fn splat(
        &self,
        origin: Vec3,
        dir: Vec3,
        length: f32,
        power: Vec3,
        image: &mut [Vec3],
    ) -> u32 {
        let m = self.medium;
        let Some(inside) = m.clip(origin, dir, length) else {
            return 0;
        };
        // Photons reach the medium attenuated by nothing else: the segment starts in air or
        // on a surface.
        let Some(span) = self.in_front_of_eye(origin, dir, inside) else {
            return 0;
        };
        let steps = self.steps(origin, dir, span);
        let ds = (span.y - span.x) / steps as f32;
        let sigma_t = m.extinction();
        let g = m.anisotropy;
        for i in 0..steps {
            let s = span.x + (i as f32 + 0.5) * ds;
            let x = origin + dir * s;
            let (w_c, d) = self.camera.toward_camera(x);
            if !(d >= EYE_CLEARANCE) {
                continue;
            }
            let cos_camera = self.forward.dot(-w_c);
            if cos_camera <= 0.0 {
                continue;
            }
            let Some(pixel) = self.pixel_of(x, cos_camera * d) else {
                continue;
            };
            let importance = self.film.importance(cos_camera, d);
            let beam = transmittance_of(sigma_t, s - inside.x);
            let seen = m.transmittance(x, w_c, d);
            let phase = henyey_greenstein(dir.dot(w_c), g);
            image[pixel] += power * beam * m.scattering * seen * (phase * importance * ds);
        }
        steps
    }

    /// The pixel `x` (at view depth `depth`) is seen in, when it lies in front of that pixel's
    /// surface.
    fn pixel_of(&self, x: Vec3, depth: f32) -> Option<usize> {
        let p = self.project(x)?;
        if !(p.x >= 0.0 && p.y >= 0.0 && p.x < self.width as f32 && p.y < self.height as f32) {
            return None;
        }
        let i = (p.y as u32).min(self.height - 1) * self.width + (p.x as u32).min(self.width - 1);
        let i = i as usize;
        (depth < self.depths[i]).then_some(i)
    }

    /// Pixel coordinates (continuous) of `x`, as [`Camera::project`] computes them, or `None`
    /// behind a pinhole's eye (its callers have cut the beam at the near plane, which also
    /// keeps it in front of an orthographic camera's plane).
    fn project(&self, x: Vec3) -> Option<Vec2> {
        let clip = self.view_proj * x.extend(1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.width as f32,
            (1.0 - ndc.y) * 0.5 * self.height as f32,
        ))
    }

    /// `span` cut to the part in front of the eye's near plane.
    fn in_front_of_eye(&self, origin: Vec3, dir: Vec3, span: Vec2) -> Option<Vec2> {
        let near = Camera::NEAR;
        let z0 = (origin - self.camera.eye).dot(self.forward);
        let dz = dir.dot(self.forward);
        let (mut a, mut b) = (span.x, span.y);
        if dz.abs() < 1e-12 {
            return (z0 > near).then_some(span);
        }
        let s_near = (near - z0) / dz;
        if dz > 0.0 {
            a = a.max(s_near);
        } else {
            b = b.min(s_near);
        }
        (a < b).then_some(Vec2::new(a, b))
    }

    /// Steps along `span`: [`BEAM_STEPS_PER_PIXEL`] per pixel of its projection.
    fn steps(&self, origin: Vec3, dir: Vec3, span: Vec2) -> u32 {
        let pixels = match (
            self.project(origin + dir * span.x),
            self.project(origin + dir * span.y),
        ) {
            (Some(a), Some(b)) => a.distance(b),
            _ => self.width.max(self.height) as f32,
        };
        let steps = (pixels * BEAM_STEPS_PER_PIXEL).ceil();
        if steps.is_finite() {
            (steps as u32).clamp(1, MAX_BEAM_STEPS)
        } else {
            MAX_BEAM_STEPS
        }
    }
}

/// Per pixel (row 0 at the top), the view-space depth of the first surface on the pixel's
/// centre ray, infinite where it meets none: what [`BeamSplatter`] hides beams behind.
pub fn view_depths(bvh: &SceneBvh, camera: &Camera, width: u32, height: u32) -> Vec<f32> {
    let forward = camera.basis().0;
    crate::composite::primary_hits(bvh, camera, width, height, |t, dir| t * dir.dot(forward))
}
