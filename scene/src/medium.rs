//! A homogeneous participating medium that scatters: the water of `murky-pool`, where light
//! through the waves makes shafts (Krüger, Bürger and Westermann, section 3.2).
//!
//! The medium fills an axis-aligned box with constant scattering `sigma_s` and absorption
//! `sigma_a` coefficients (per metre, per channel; extinction `sigma_t = sigma_s + sigma_a`)
//! and scatters with the Henyey-Greenstein phase function of asymmetry `g`. Surfaces inside
//! the box stay surfaces: the medium is what lies between them. Unlike a [`crate::Volume`]
//! (emission-absorption, bounded by a sphere, for the volume techniques), it emits nothing: it
//! attenuates every path through it (Beer-Lambert) and scatters light into the eye's rays.
//!
//! These functions are the Rust twin of `shaders/medium.wgsl` (the WGSL module `scene::medium`,
//! which [`crate::SHADING`] imports): the same box clipping (the prelude's `ray_box`),
//! transmittance and phase function, checked against each other by the conformance test
//! `scene/tests/medium_conformance.rs`. The reference (`truth`) integrates with them and every
//! technique is measured against that.

use crate::SceneError;
use glam::{Vec2, Vec3};
use gpu::prelude::ray_box;

/// `shaders/medium.wgsl`: the WGSL twin of this module, the WGSL module `scene::medium`
/// (`scene::shading` imports it).
pub const MEDIUM_WGSL: &str = include_str!("shaders/medium.wgsl");
/// [`MEDIUM_WGSL`] as the module `scene::medium`.
pub static MEDIUM: gpu::wgsl::Module =
    gpu::wgsl::Module::new(MEDIUM_WGSL, "scene/src/shaders/medium.wgsl", &[]);

/// A homogeneous, scattering medium in an axis-aligned box.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    pub name: String,
    /// The box's lower corner (world, metres).
    pub min: Vec3,
    /// The box's upper corner.
    pub max: Vec3,
    /// Scattering coefficient `sigma_s` per metre, per channel.
    pub scattering: Vec3,
    /// Absorption coefficient `sigma_a` per metre, per channel.
    pub absorption: Vec3,
    /// Henyey-Greenstein asymmetry `g` in `(-1, 1)`: 0 scatters evenly, toward 1 forward.
    pub anisotropy: f32,
}

/// The largest `|g|` accepted: past it the phase function's peak (`(1 + g) / (4 pi (1 - g)^2)`)
/// is too narrow for any renderer's sampling of it.
pub const MAX_ANISOTROPY: f32 = 0.95;

/// The medium scatters light into the eye only from beyond this distance (metres), as if the
/// camera sat in a 10 cm housing; it attenuates from the eye on. Every renderer keeps it (the
/// reference's estimators, the god rays, the froxels' first slice): a photon beam passing the
/// eye at distance `h` adds about `1 / h` to every pixel it crosses, so without it the beam
/// estimate's variance has no bound (a beam that passed 3 mm from the swimmer's eye lit a
/// pixel of `murky-pool` 20 times its converged value at 80 000 photons).
pub const EYE_CLEARANCE: f32 = 0.1;

/// The largest coefficient accepted (per metre): 1000 makes a millimetre of the medium opaque.
pub const MAX_COEFFICIENT: f32 = 1000.0;

impl Medium {
    /// Extinction `sigma_t = sigma_s + sigma_a` per metre.
    pub fn extinction(&self) -> Vec3 {
        self.scattering + self.absorption
    }

    /// Finite numbers, a non-empty box, coefficients in `[0, MAX_COEFFICIENT]`, `|g| <=
    /// MAX_ANISOTROPY`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let finite = self.min.is_finite()
            && self.max.is_finite()
            && self.scattering.is_finite()
            && self.absorption.is_finite()
            && self.anisotropy.is_finite();
        let bad = |what: &str| {
            Err(SceneError::Invalid(format!(
                "medium \"{}\" {what}",
                self.name
            )))
        };
        if !finite {
            return bad("is not finite");
        }
        if !self.min.cmplt(self.max).all() {
            return bad("has an empty box (min must be below max on every axis)");
        }
        let in_range = |c: Vec3| c.min_element() >= 0.0 && c.max_element() <= MAX_COEFFICIENT;
        if !in_range(self.scattering) || !in_range(self.absorption) {
            return bad(&format!(
                "needs scattering and absorption in [0, {MAX_COEFFICIENT}] per metre"
            ));
        }
        if self.anisotropy.abs() > MAX_ANISOTROPY {
            return bad(&format!(
                "has anisotropy {} outside [-{MAX_ANISOTROPY}, {MAX_ANISOTROPY}]",
                self.anisotropy
            ));
        }
        Ok(())
    }

    /// Whether `p` lies in the box (boundary included).
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The part `[t0, t1]` of `origin + t dir`, `t` in `[0, t_max]`, inside the box, or `None`
    /// (`dir` need not be unit length: `t` is in its units).
    #[inline]
    pub fn clip(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Vec2> {
        let t = ray_box(origin, dir, self.min, self.max);
        let (t0, t1) = (t.x.max(0.0), t.y.min(t_max));
        (t.x <= t.y && t0 < t1).then_some(Vec2::new(t0, t1))
    }

    /// Length of `origin + t dir` (unit `dir`), `t` in `[0, t_max]`, inside the box.
    #[inline]
    pub fn length_inside(&self, origin: Vec3, dir: Vec3, t_max: f32) -> f32 {
        self.clip(origin, dir, t_max).map_or(0.0, |t| t.y - t.x)
    }

    /// Beer-Lambert transmittance along `origin + t dir` (unit `dir`), `t` in `[0, t_max]`.
    pub fn transmittance(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Vec3 {
        transmittance_of(self.extinction(), self.length_inside(origin, dir, t_max))
    }

    /// Transmittance of the straight segment from `a` to `b`.
    pub fn transmittance_between(&self, a: Vec3, b: Vec3) -> Vec3 {
        let d = b - a;
        let len = d.length();
        if len <= 0.0 {
            return Vec3::ONE;
        }
        self.transmittance(a, d / len, len)
    }

    /// The uniform block of `shaders/medium.wgsl` (`Medium`).
    pub fn gpu(medium: Option<&Medium>) -> MediumGpu {
        match medium {
            None => MediumGpu::zeroed_none(),
            Some(m) => MediumGpu {
                min: m.min.extend(1.0).to_array(),
                max: m.max.extend(m.anisotropy).to_array(),
                scattering: m.scattering.extend(0.0).to_array(),
                absorption: m.absorption.extend(0.0).to_array(),
            },
        }
    }
}

/// `exp(-sigma_t * length)` per channel.
#[inline]
pub fn transmittance_of(extinction: Vec3, length: f32) -> Vec3 {
    // A grey medium (water, smoke) needs one exponential, not three: the same bits.
    if extinction.x == extinction.y && extinction.y == extinction.z {
        return Vec3::splat((-extinction.x * length).exp());
    }
    Vec3::new(
        (-extinction.x * length).exp(),
        (-extinction.y * length).exp(),
        (-extinction.z * length).exp(),
    )
}

/// The Henyey-Greenstein phase function (per steradian, integrates to 1 over the sphere):
/// `(1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^(3/2))`, `cos_theta` the cosine between the
/// direction light travels in and the direction it leaves in.
#[inline]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = (1.0 + g * g - 2.0 * g * cos_theta.clamp(-1.0, 1.0)).max(1e-12);
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * denom * denom.sqrt())
}

/// `Medium` of medium.wgsl: `min.w` is 1 when the scene has a medium, `max.w` is `g`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MediumGpu {
    pub min: [f32; 4],
    pub max: [f32; 4],
    pub scattering: [f32; 4],
    pub absorption: [f32; 4],
}

impl MediumGpu {
    fn zeroed_none() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn water() -> Medium {
        Medium {
            name: "water".into(),
            min: Vec3::new(-2.0, -1.6, -3.0),
            max: Vec3::new(2.0, -0.1, 3.0),
            scattering: Vec3::splat(0.2),
            absorption: Vec3::new(0.1, 0.05, 0.02),
            anisotropy: 0.4,
        }
    }

    #[test]
    fn henyey_greenstein_integrates_to_one_and_is_isotropic_at_zero() {
        for g in [-0.9f32, -0.3, 0.0, 0.5, 0.9] {
            // Integral over the sphere: 2 pi * integral_{-1}^{1} p(mu) dmu, midpoint rule.
            let n = 200_000;
            let sum: f64 = (0..n)
                .map(|i| {
                    let mu = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                    henyey_greenstein(mu as f32, g) as f64
                })
                .sum::<f64>()
                * 2.0
                / n as f64
                * std::f64::consts::TAU;
            assert!((sum - 1.0).abs() < 1e-3, "g {g}: {sum}");
        }
        let iso = 1.0 / (4.0 * std::f32::consts::PI);
        assert!((henyey_greenstein(0.3, 0.0) - iso).abs() < 1e-7);
        assert!(henyey_greenstein(1.0, 0.6) > henyey_greenstein(-1.0, 0.6));
    }

    #[test]
    fn transmittance_is_beer_lambert_over_the_part_inside() {
        let m = water();
        // Straight down through the box at its centre: 1.5 m of medium.
        let t = m.transmittance(Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y, f32::INFINITY);
        let want = transmittance_of(m.extinction(), 1.5);
        assert!((t - want).abs().max_element() < 1e-6, "{t} vs {want}");
        // Stopped by a surface 0.5 m below the top: 0.5 m.
        let t = m.transmittance(Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y, 5.6);
        let want = transmittance_of(m.extinction(), 0.5);
        assert!((t - want).abs().max_element() < 1e-5, "{t} vs {want}");
        // From inside, sideways to the wall: 2 m.
        let t = m.transmittance_between(Vec3::new(0.0, -1.0, 0.0), Vec3::new(7.0, -1.0, 0.0));
        let want = transmittance_of(m.extinction(), 2.0);
        assert!((t - want).abs().max_element() < 1e-5, "{t} vs {want}");
        // Missing the box: nothing.
        assert_eq!(
            m.transmittance(Vec3::new(0.0, 5.0, 0.0), Vec3::Y, f32::INFINITY),
            Vec3::ONE
        );
        assert_eq!(
            m.transmittance_between(Vec3::ONE, Vec3::ONE),
            Vec3::ONE,
            "an empty segment"
        );
    }

    #[test]
    fn bad_media_are_refused() {
        let mut m = water();
        assert!(m.validate().is_ok());
        m.anisotropy = 0.99;
        assert!(m.validate().is_err());
        let mut m = water();
        m.scattering.x = -0.1;
        assert!(m.validate().is_err());
        let mut m = water();
        m.max.y = m.min.y;
        assert!(m.validate().is_err());
        let mut m = water();
        m.absorption.z = f32::NAN;
        assert!(m.validate().is_err());
    }

    #[test]
    fn the_gpu_block_says_whether_there_is_a_medium() {
        assert_eq!(Medium::gpu(None).min[3], 0.0);
        let g = Medium::gpu(Some(&water()));
        assert_eq!((g.min[3], g.max[3]), (1.0, 0.4));
    }
}
