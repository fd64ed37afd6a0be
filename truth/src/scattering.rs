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
//!   it crosses (`truth/tests/reference_scattering.rs` shows the convergence). Most of a beam's
//!   steps land off the image or behind the surface its pixel sees: the image's edges bound
//!   the steps taken before any is evaluated, and each step's pixel and depth come from the
//!   beam's affine clip coordinates before anything else is computed.
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
use glam::{Mat4, Vec2, Vec3, Vec4};
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
    /// A pinhole inside the medium's box: then the whole way from a point of the medium to
    /// the eye lies in the box (it is convex), and its length is the distance.
    eye_in_medium: bool,
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
            eye_in_medium: !camera.is_orthographic() && medium.contains(camera.eye),
        }
    }

    /// Adds the beam `origin + s dir`, `s` in `[0, length]`, of flux `power` at `origin`, to
    /// `image` (one radiance per pixel). Returns the number of steps of its midpoint rule, those
    /// off the image included (they are skipped unevaluated).
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
        let line = self.line(origin, dir);
        let sigma_t = m.extinction();
        let g = m.anisotropy;
        for i in line.steps_on_image(span, ds, steps) {
            let s = span.x + (i as f32 + 0.5) * ds;
            // Most steps of a beam lie behind a surface or off the image: the pixel and depth
            // tests come first, on the line's affine clip coordinates.
            let Some(pixel) = self.visible_pixel(&line, s) else {
                continue;
            };
            let x = origin + dir * s;
            let (w_c, d) = self.camera.toward_camera(x);
            if !(d >= EYE_CLEARANCE) {
                continue;
            }
            let cos_camera = self.forward.dot(-w_c);
            if cos_camera <= 0.0 {
                continue;
            }
            let importance = self.film.importance(cos_camera, d);
            // Beer-Lambert along the beam up to x, then from x to the eye: one exponential.
            let to_eye = match self.eye_in_medium {
                true => d,
                false => m.length_inside(x, w_c, d),
            };
            let travelled = (s - inside.x) + to_eye;
            let attenuation = transmittance_of(sigma_t, travelled);
            let phase = henyey_greenstein(dir.dot(w_c), g);
            image[pixel] += power * attenuation * m.scattering * (phase * importance * ds);
        }
        steps
    }

    /// The line `origin + s dir` as the image sees it (see [`BeamLine`]).
    fn line(&self, origin: Vec3, dir: Vec3) -> BeamLine {
        BeamLine {
            clip0: self.view_proj * origin.extend(1.0),
            clip_ds: self.view_proj * dir.extend(0.0),
            depth0: self.forward.dot(origin - self.camera.eye),
            depth_ds: self.forward.dot(dir),
        }
    }

    /// The pixel the line's point at `s` is seen in, when it projects onto the image and lies
    /// in front of that pixel's surface.
    fn visible_pixel(&self, line: &BeamLine, s: f32) -> Option<usize> {
        let p = self.pixel_coordinates(line.clip0 + line.clip_ds * s)?;
        let i = crate::pixel_at(p, self.width, self.height)?;
        let depth = line.depth0 + line.depth_ds * s;
        (depth < self.depths[i]).then_some(i)
    }

    /// Pixel coordinates (continuous) of `x`, as [`Camera::project`] computes them, or `None`
    /// behind a pinhole's eye (its callers have cut the beam at the near plane, which also
    /// keeps it in front of an orthographic camera's plane).
    fn project(&self, x: Vec3) -> Option<Vec2> {
        self.pixel_coordinates(self.view_proj * x.extend(1.0))
    }

    /// Pixel coordinates of the clip-space point `clip`, `None` behind a pinhole's eye.
    fn pixel_coordinates(&self, clip: Vec4) -> Option<Vec2> {
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

/// A beam's line `origin + s dir` as the image sees it: the clip coordinates and the view depth
/// of its points are affine in `s` (a projection is linear in homogeneous coordinates), so a
/// step finds its pixel and depth with a few multiply-adds, and the image's edges bound the
/// steps worth taking.
struct BeamLine {
    clip0: Vec4,
    clip_ds: Vec4,
    depth0: f32,
    depth_ds: f32,
}

impl BeamLine {
    /// Steps (of `steps` over `span`, `ds` apart) whose midpoints may project onto the image:
    /// each edge of the view volume, `|x| <= w`, `|y| <= w`, `w >= 0` in clip space, bounds
    /// `s` on one side. The bounds are widened by [`EDGE_SLACK`] and two steps, so that every
    /// step the per-step test would accept lies within them whatever the rounding: they only
    /// skip work, the per-step test decides.
    fn steps_on_image(&self, span: Vec2, ds: f32, steps: u32) -> std::ops::Range<u32> {
        let (c, dc) = (self.clip0, self.clip_ds);
        // The view volume widened: |x| <= w (1 + slack) + slack, the same for y, and w >= -slack.
        let (w0, w1) = (
            c.w * (1.0 + EDGE_SLACK) + EDGE_SLACK,
            dc.w * (1.0 + EDGE_SLACK),
        );
        let edges = [
            (w0 - c.x, w1 - dc.x),
            (w0 + c.x, w1 + dc.x),
            (w0 - c.y, w1 - dc.y),
            (w0 + c.y, w1 + dc.y),
            (c.w + EDGE_SLACK, dc.w),
        ];
        // Each edge keeps the s where a + b s >= 0.
        let (mut lo, mut hi) = (span.x, span.y);
        for (a, b) in edges {
            if b > 0.0 {
                lo = lo.max(-a / b);
            } else if b < 0.0 {
                hi = hi.min(-a / b);
            } else if a < 0.0 {
                return 0..0;
            }
        }
        if !(lo <= hi) {
            return 0..0;
        }
        let index = |s: f32| (s - span.x) / ds - 0.5;
        let first = (index(lo).floor() - 2.0).clamp(0.0, steps as f32) as u32;
        let end = (index(hi).ceil() + 3.0).clamp(0.0, steps as f32) as u32;
        first..end
    }
}

/// How far [`BeamLine::steps_on_image`] widens the view volume, relative to `w` and absolute
/// (clip units): far more than the rounding of a step's clip coordinates.
const EDGE_SLACK: f32 = 1e-3;

/// Per pixel (row 0 at the top), the view-space depth of the first surface on the pixel's
/// centre ray, infinite where it meets none: what [`BeamSplatter`] hides beams behind.
pub fn view_depths(bvh: &SceneBvh, camera: &Camera, width: u32, height: u32) -> Vec<f32> {
    let forward = camera.basis().0;
    crate::composite::primary_hits(bvh, camera, width, height, |t, dir| t * dir.dot(forward))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const WIDTH: u32 = 48;
    const HEIGHT: u32 = 32;

    /// The beam estimate as the module's comment writes it, step by step with nothing shared
    /// and nothing skipped: every step projected through the whole matrix, its two
    /// transmittances apart. What [`BeamSplatter::splat`] must add up to, to rounding.
    fn splat_step_by_step(
        b: &BeamSplatter,
        (origin, dir, length): (Vec3, Vec3, f32),
        power: Vec3,
        image: &mut [Vec3],
    ) {
        let m = b.medium;
        let Some(inside) = m.clip(origin, dir, length) else {
            return;
        };
        let Some(span) = b.in_front_of_eye(origin, dir, inside) else {
            return;
        };
        let steps = b.steps(origin, dir, span);
        let ds = (span.y - span.x) / steps as f32;
        for i in 0..steps {
            let s = span.x + (i as f32 + 0.5) * ds;
            let x = origin + dir * s;
            let (w_c, d) = b.camera.toward_camera(x);
            let cos_camera = b.forward.dot(-w_c);
            if !(d >= EYE_CLEARANCE) || cos_camera <= 0.0 {
                continue;
            }
            let Some(pixel) = b.project(x).and_then(|p| crate::pixel_at(p, WIDTH, HEIGHT)) else {
                continue;
            };
            if !(cos_camera * d < b.depths[pixel]) {
                continue;
            }
            let importance = b.film.importance(cos_camera, d);
            let beam = transmittance_of(m.extinction(), s - inside.x);
            let seen = m.transmittance(x, w_c, d);
            let phase = henyey_greenstein(dir.dot(w_c), m.anisotropy);
            image[pixel] += power * beam * m.scattering * seen * (phase * importance * ds);
        }
    }

    fn medium() -> Medium {
        Medium {
            name: "test".into(),
            min: Vec3::new(-2.0, -1.5, -2.0),
            max: Vec3::new(2.0, 1.0, 2.5),
            scattering: Vec3::new(0.3, 0.5, 0.7),
            absorption: Vec3::new(0.2, 0.1, 0.05),
            anisotropy: 0.4,
        }
    }

    prop_compose! {
        /// A pinhole or orthographic camera somewhere in or around the medium.
        fn camera()(
            eye in prop::array::uniform3(-3.0f32..3.0),
            target in prop::array::uniform3(-1.0f32..1.0),
            fov in 20.0f32..100.0,
            orthographic in prop::option::weighted(0.3, 0.5f32..3.0),
        ) -> Camera {
            Camera {
                eye: Vec3::from(eye),
                target: Vec3::from(target) * 4.0 - Vec3::from(eye) * 0.1,
                up: Vec3::Y,
                fov_y_deg: fov,
                orthographic,
            }
        }
    }

    prop_compose! {
        /// A beam starting anywhere near the medium, in any direction.
        fn beam()(
            origin in prop::array::uniform3(-4.0f32..4.0),
            dir in prop::array::uniform3(-1.0f32..1.0),
            length in 0.01f32..12.0,
        ) -> (Vec3, Vec3, f32) {
            (Vec3::from(origin), Vec3::from(dir).normalize_or(Vec3::X), length)
        }
    }

    proptest! {
        /// Skipping the steps off the image skips none that lands on it.
        #[test]
        fn every_step_on_the_image_is_within_the_steps_taken(camera in camera(), beam in beam()) {
            let m = medium();
            let depths = vec![f32::INFINITY; (WIDTH * HEIGHT) as usize];
            let b = BeamSplatter::new(&m, &camera, WIDTH, HEIGHT, &depths);
            let (origin, dir, length) = beam;
            let Some(span) = m.clip(origin, dir, length).and_then(|s| b.in_front_of_eye(origin, dir, s)) else {
                return Ok(());
            };
            let steps = b.steps(origin, dir, span);
            let ds = (span.y - span.x) / steps as f32;
            let taken = b.line(origin, dir).steps_on_image(span, ds, steps);
            for i in 0..steps {
                let x = origin + dir * (span.x + (i as f32 + 0.5) * ds);
                let on_image = b.project(x).and_then(|p| crate::pixel_at(p, WIDTH, HEIGHT)).is_some();
                prop_assert!(!on_image || taken.contains(&i), "step {i} of {steps} is on the image, outside {taken:?}");
            }
        }

        /// The splat equals the step-by-step estimate: every pixel to rounding, but for at most
        /// two per beam (a step on a pixel's edge that rounds to the other side moves its
        /// share to the neighbour; one on a surface appears or vanishes).
        #[test]
        fn the_splat_is_the_step_by_step_estimate(
            camera in camera(),
            beams in prop::collection::vec(beam(), 1..8),
            surface in 0.5f32..8.0,
        ) {
            let m = medium();
            // Two pixels in three see a surface at `surface`, the rest see nothing.
            let depths: Vec<f32> = (0..WIDTH * HEIGHT)
                .map(|i| if i % 3 == 0 { f32::INFINITY } else { surface })
                .collect();
            let b = BeamSplatter::new(&m, &camera, WIDTH, HEIGHT, &depths);
            let mut fast = vec![Vec3::ZERO; depths.len()];
            let mut slow = vec![Vec3::ZERO; depths.len()];
            let power = Vec3::new(1.0, 0.8, 0.6);
            for &beam in &beams {
                b.splat(beam.0, beam.1, beam.2, power, &mut fast);
                splat_step_by_step(&b, beam, power, &mut slow);
            }
            let differing = fast
                .iter()
                .zip(&slow)
                .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-4 * a.max(**b).max_element() + 1e-30)
                .count();
            prop_assert!(differing <= 2 * beams.len(), "{differing} pixels differ");
            // Without surfaces no step can vanish: a step rounded across a pixel's edge keeps
            // its share, so the totals agree to rounding.
            let open = vec![f32::INFINITY; depths.len()];
            let b = BeamSplatter::new(&m, &camera, WIDTH, HEIGHT, &open);
            let (mut fast, mut slow) = (vec![Vec3::ZERO; open.len()], vec![Vec3::ZERO; open.len()]);
            for &beam in &beams {
                b.splat(beam.0, beam.1, beam.2, power, &mut fast);
                splat_step_by_step(&b, beam, power, &mut slow);
            }
            let total = |image: &[Vec3]| image.iter().map(|v| v.as_dvec3()).sum::<glam::DVec3>();
            let (fast, slow) = (total(&fast), total(&slow));
            prop_assert!((fast - slow).abs().max_element() <= 1e-4 * slow.max_element() + 1e-30, "{fast} against {slow}");
        }
    }

    /// A beam that leaves the image through its right edge: the steps taken stop soon after
    /// it (the others are never evaluated), hold every step on the image, and light it.
    #[test]
    fn a_beam_leaving_the_image_is_stepped_only_on_it() {
        let m = medium();
        let camera = Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 20.0,
            orthographic: None,
        };
        let depths = vec![f32::INFINITY; (WIDTH * HEIGHT) as usize];
        let b = BeamSplatter::new(&m, &camera, WIDTH, HEIGHT, &depths);
        // Along +x from the view's centre: the image ends at x ~ 0.79, the medium at x = 2.
        let (origin, dir) = (Vec3::ZERO, Vec3::X);
        let span = m.clip(origin, dir, 10.0).unwrap();
        let steps = b.steps(origin, dir, span);
        let ds = (span.y - span.x) / steps as f32;
        let taken = b.line(origin, dir).steps_on_image(span, ds, steps);
        let on_image: Vec<u32> = (0..steps)
            .filter(|&i| {
                let x = origin + dir * (span.x + (i as f32 + 0.5) * ds);
                b.project(x)
                    .is_some_and(|p| p.x >= 0.0 && p.x < WIDTH as f32)
            })
            .collect();
        assert!(on_image.len() > 10 && on_image.iter().all(|i| taken.contains(i)));
        assert!(
            taken.start == 0 && taken.end < steps / 2 && taken.end <= on_image.len() as u32 + 4,
            "{taken:?} of {steps} steps, {} on the image",
            on_image.len()
        );
        let mut image = vec![Vec3::ZERO; depths.len()];
        b.splat(origin, dir, 10.0, Vec3::ONE, &mut image);
        let lit = image.iter().filter(|v| v.max_element() > 0.0).count();
        assert!(lit >= WIDTH as usize / 2 - 2, "{lit} pixels lit");
    }
}
