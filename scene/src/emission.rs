//! Where caustic photons are emitted: cones from each point light toward each caustic
//! caster's bounding sphere, the photon budget split between them, and the balance-heuristic
//! weight of a photon drawn in one of several overlapping cones.
//!
//! The CPU reference's light pass (`truth::reference`, whose module docs derive the
//! estimator) and the GPU ray tracer (`raytracer`) emit through the same cones with the same
//! budgets, so their caustics estimate the same integral with the same variance per photon.
//!
//! For each light and caster the caster's bounding sphere (`center_at`,
//! `bounding_radius_at`) seen from the light subtends a cone of half-angle `theta_max`,
//! `sin theta_max = R / D`, solid angle `Omega = 2 pi (1 - cos theta_max)` (the whole sphere,
//! `4 pi`, if the light is inside it). `N_j` photons are drawn uniformly in cone `j`, the
//! budget split in proportion to the power each cone receives, `(I_r + I_g + I_b) Omega_j`. A
//! photon drawn in direction `w` carries `Phi = I / sum_{j : w in cone j} (N_j / Omega_j)`
//! (Veach's balance heuristic, one-sample form): `I Omega_j / N_j` where cones do not overlap.

use crate::technique::{Declared, ParamValue};
use crate::{Param, Roles, Scene};
use glam::Vec3;
use std::f32::consts::PI;

/// Photons per pixel of a light pass scaled to its image: 4 million over 256 x 256, the density
/// at which the caustic under `cornell-sphere`'s glass sphere is smooth (the reference's
/// default, `truth::reference::ReferenceOptions::for_image`, and the GPU tracer's).
pub const PHOTONS_PER_PIXEL: u64 = 61;
/// The fewest photons an image-scaled light pass traces (small test images).
pub const MIN_PHOTONS: u64 = 100_000;

/// The image-scaled photon count of a `width` x `height` image: [`PHOTONS_PER_PIXEL`] per
/// pixel, at least [`MIN_PHOTONS`].
pub fn photons_for_image(width: u32, height: u32) -> u64 {
    (PHOTONS_PER_PIXEL * width as u64 * height as u64).max(MIN_PHOTONS)
}

/// The parameter by which every family that emits photons from a light-view raster (one
/// photon per pixel) chooses where in its pixel a photon leaves: `jittered_emission` in
/// scene.wgsl (README.md, "Jittered emission").
pub const PHOTON_JITTER_PARAM: &str = "photon_jitter";
/// [`PHOTON_JITTER_PARAM`]'s help line.
const PHOTON_JITTER_HELP: &str = "1: each photon leaves from a random point of its pixel \
     (stratified jittered emission: noise, not moire rings); 0: from the pixel centre";

/// The parameter by which a family that splats photons chooses each photon's kernel: widened
/// to the footprint of its lattice cell on the receiver (`lightmap::Footprint` for light maps)
/// or the fixed splat radius. Footprints measure the cell from the landing points of the
/// photon's lattice neighbours, so they need the lattice: they and [`PHOTON_JITTER_PARAM`] do
/// not mix well (the jitter makes the measured cells noisy).
pub const PHOTON_FOOTPRINT_PARAM: &str = "photon_footprint";
/// [`PHOTON_FOOTPRINT_PARAM`]'s help line.
const PHOTON_FOOTPRINT_HELP: &str = "1: each photon's splat widened to the footprint of its \
     lattice cell on the receiver (photon differentials by finite differences); 0: the fixed \
     splat radius";

/// The declared [`PHOTON_JITTER_PARAM`] at its current `value`.
pub fn jitter_param(value: bool) -> Param {
    Param::new(
        PHOTON_JITTER_PARAM,
        f64::from(u8::from(value)),
        (0.0, 1.0),
        true,
        PHOTON_JITTER_HELP,
    )
}

/// The declared [`PHOTON_FOOTPRINT_PARAM`] at its current `value`.
pub fn footprint_param(value: bool) -> Param {
    Param::new(
        PHOTON_FOOTPRINT_PARAM,
        f64::from(u8::from(value)),
        (0.0, 1.0),
        true,
        PHOTON_FOOTPRINT_HELP,
    )
}

/// [`PHOTON_JITTER_PARAM`] declared once in a family's [`crate::Settings`], on the switch
/// `setting` finds.
pub const fn jitter_declared<S>(setting: fn(&mut S) -> Option<&mut dyn ParamValue>) -> Declared<S> {
    Declared::new(PHOTON_JITTER_PARAM, (0.0, 1.0), PHOTON_JITTER_HELP, setting)
}

/// [`PHOTON_FOOTPRINT_PARAM`] declared once in a family's [`crate::Settings`], on the switch
/// `setting` finds.
pub const fn footprint_declared<S>(
    setting: fn(&mut S) -> Option<&mut dyn ParamValue>,
) -> Declared<S> {
    Declared::new(
        PHOTON_FOOTPRINT_PARAM,
        (0.0, 1.0),
        PHOTON_FOOTPRINT_HELP,
        setting,
    )
}

/// The objects photons are aimed at: caustic casters by role, and every specular object.
pub fn caustic_casters(scene: &Scene) -> Vec<usize> {
    (0..scene.objects.len())
        .filter(|&i| {
            let o = &scene.objects[i];
            o.roles.contains(Roles::CAUSTIC_CASTER) || o.material.is_specular()
        })
        .collect()
}

/// One cone of photon directions: from a light toward a target's bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    pub light: usize,
    pub axis: Vec3,
    /// `1 - cos theta_max` (2 for the whole sphere), kept apart for precision.
    pub one_minus_cos: f32,
    pub solid_angle: f32,
    /// Photons drawn in this cone.
    pub photons: u64,
}

impl Emitter {
    /// Whether direction `w` lies inside the cone.
    pub fn contains(&self, w: Vec3) -> bool {
        self.one_minus_cos >= 2.0 || 1.0 - w.dot(self.axis) <= self.one_minus_cos
    }

    /// Uniform direction in the cone from two uniform numbers in [0, 1):
    /// `cos theta = 1 - u (1 - cos theta_max)`, `phi = 2 pi v`.
    pub fn sample(&self, u: f32, v: f32) -> Vec3 {
        let omc = u * self.one_minus_cos; // 1 - cos theta
        let cos_t = 1.0 - omc;
        let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
        let phi = 2.0 * PI * v;
        let (t, b) = self.axis.any_orthonormal_pair();
        (self.axis * cos_t + (t * phi.cos() + b * phi.sin()) * sin_t).normalize()
    }
}

/// The cones of `scene` at `time` toward `targets`, sharing `photons` in all.
pub fn emitters(scene: &Scene, time: f32, targets: &[usize], photons: u64) -> Vec<Emitter> {
    let mut out = Vec::new();
    for (li, light) in scene.lights.iter().enumerate() {
        if light.intensity.max_element() <= 0.0 {
            continue;
        }
        for &ti in targets {
            let Some(object) = scene.objects.get(ti) else {
                continue;
            };
            if object.mesh.indices.is_empty() {
                continue;
            }
            let center = object.center_at(time);
            let radius = object.bounding_radius_at(time) * (1.0 + 1e-4) + 1e-6;
            let to = center - light.position;
            let dist = to.length();
            let (axis, one_minus_cos) = if dist <= radius {
                (Vec3::Y, 2.0)
            } else {
                let sin2 = (radius / dist) * (radius / dist);
                (to / dist, sin2 / (1.0 + (1.0 - sin2).sqrt()))
            };
            out.push(Emitter {
                light: li,
                axis,
                one_minus_cos,
                solid_angle: 2.0 * PI * one_minus_cos,
                photons: 0,
            });
        }
    }
    // Split the budget in proportion to the power into each cone.
    let weight =
        |e: &Emitter| scene.lights[e.light].intensity.element_sum() as f64 * e.solid_angle as f64;
    let total: f64 = out.iter().map(weight).sum();
    if total > 0.0 {
        for e in &mut out {
            e.photons = ((photons as f64 * weight(e) / total).round() as u64).max(1);
        }
    }
    out
}

/// The sampling density `sum_j N_j / Omega_j` over the cones of `emitters[drawn]`'s light
/// that contain `w` (the balance heuristic's denominator): a photon drawn in cone `drawn` in
/// direction `w` carries `I / density`.
pub fn balance_density(emitters: &[Emitter], drawn: usize, w: Vec3) -> f32 {
    let e = &emitters[drawn];
    let mut density = e.photons as f32 / e.solid_angle;
    for (oj, o) in emitters.iter().enumerate() {
        if oj != drawn && o.light == e.light && o.contains(w) {
            density += o.photons as f32 / o.solid_angle;
        }
    }
    density
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cone sampling: every direction inside the cone, and uniform in solid angle (the mean
    /// of cos theta over a uniform cone is 1 - (1 - cos theta_max) / 2).
    #[test]
    fn cone_samples_are_uniform_inside_the_cone() {
        for (axis, omc) in [
            (Vec3::new(0.3, -1.0, 0.2).normalize(), 0.05f32),
            (Vec3::Z, 1.2),
            (Vec3::Y, 2.0),
        ] {
            let e = Emitter {
                light: 0,
                axis,
                one_minus_cos: omc,
                solid_angle: 2.0 * PI * omc,
                photons: 1,
            };
            let n = 200_000u32;
            let mut mean_cos = 0.0f64;
            for i in 0..n {
                // A Hammersley set: deterministic and uniform.
                let u = (i as f32 + 0.5) / n as f32;
                let v = i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
                let w = e.sample(u, v);
                assert!((w.length() - 1.0).abs() < 1e-5);
                assert!(e.contains(w) || 1.0 - w.dot(axis) <= omc * (1.0 + 1e-4) + 1e-6);
                mean_cos += w.dot(axis) as f64;
            }
            mean_cos /= n as f64;
            let want = 1.0 - omc as f64 / 2.0;
            assert!(
                (mean_cos - want).abs() < 3e-3 * omc as f64 + 1e-4,
                "{mean_cos} vs {want}"
            );
        }
    }
}
