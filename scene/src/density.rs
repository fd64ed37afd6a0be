//! The density field of a [`Volume`]: defined here and nowhere else, so that the CPU
//! reference (`truth::media` integrates it along rays) and any GPU technique that reads the
//! field (a calibration, a baked thickness texture) evaluate the same function.
//!
//! A volume's extinction coefficient (per metre) at a point `x` at local position
//! `q = (x - c) / R` is
//!
//! ```text
//! sigma(x) = density * (1 - |q|^2)^k * (1 + a n(f q))      (|q| < 1, else 0)
//! ```
//!
//! with `k`, `a`, `f` the volume's [`DensityProfile`] and `n` the deterministic value noise
//! [`noise`] in [-1, 1]. The medium emits its `color` per unit optical depth and absorbs (no
//! scattering); how the reference integrates that along a ray, and how accurately, is
//! documented in `truth::media`.

use crate::{DensityProfile, Volume};
use glam::Vec3;

/// Deterministic 3D value noise in [-1, 1]: two octaves of hashed lattice values blended
/// with the quintic fade `6t^5 - 15t^4 + 10t^3` (continuous second derivatives, so the
/// midpoint rule's error bound holds across lattice cells).
pub fn noise(q: Vec3) -> f32 {
    let second = value_noise(2.0 * q + Vec3::new(17.31, 5.17, 9.73));
    (value_noise(q) + 0.5 * second) / 1.5
}

/// One octave: trilinear interpolation of lattice values in [-1, 1] with the quintic fade.
fn value_noise(q: Vec3) -> f32 {
    if !q.is_finite() {
        return 0.0;
    }
    let base = q.floor();
    let f = q - base;
    let w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let (i, j, k) = (base.x as i32, base.y as i32, base.z as i32);
    let v = |di: i32, dj: i32, dk: i32| lattice_value(i + di, j + dj, k + dk);
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(v(0, 0, 0), v(1, 0, 0), w.x);
    let x10 = lerp(v(0, 1, 0), v(1, 1, 0), w.x);
    let x01 = lerp(v(0, 0, 1), v(1, 0, 1), w.x);
    let x11 = lerp(v(0, 1, 1), v(1, 1, 1), w.x);
    lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z)
}

/// A hashed value in [-1, 1] per lattice point (the MurmurHash3 finaliser of the packed
/// coordinates: platform-independent integer arithmetic, so every machine gets the same
/// texture).
fn lattice_value(i: i32, j: i32, k: i32) -> f32 {
    let mut h = (i as u32).wrapping_mul(0x8da6_b343)
        ^ (j as u32).wrapping_mul(0xd816_3841)
        ^ (k as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^= h >> 16;
    (h >> 8) as f32 * (2.0 / 16_777_216.0) - 1.0
}

impl DensityProfile {
    /// The profile's factor at local position `q` (units of the radius, centre at 0):
    /// `(1 - |q|^2)^k (1 + a n(f q))`, 0 outside the unit ball.
    pub fn shape(&self, q: Vec3) -> f32 {
        let r2 = q.length_squared();
        if r2.is_nan() || r2 >= 1.0 {
            return 0.0;
        }
        let falloff = if self.falloff > 0.0 {
            (1.0 - r2).powf(self.falloff)
        } else {
            1.0
        };
        let texture = if self.noise > 0.0 {
            1.0 + self.noise * noise(q * self.noise_frequency)
        } else {
            1.0
        };
        (falloff * texture).max(0.0)
    }
}

impl Volume {
    /// Extinction coefficient (per metre) at world point `p` at `time`.
    pub fn extinction_at(&self, p: Vec3, time: f32) -> f32 {
        let center = self.center + self.motion.offset(time);
        self.density * self.profile.shape((p - center) / self.radius)
    }
}

/// Optical depth of the chord at distance `b` from the centre of a ball of radius `r`,
/// centre extinction `density` and falloff exponent `k` in {0, 1, 2} without noise (closed
/// forms for the tests and for calibrating techniques: `integral (h^2 - s^2)^k ds / R^2k`
/// over `|s| <= h = sqrt(R^2 - b^2)`). `None` for other `k` or a noisy profile.
pub fn chord_optical_depth(density: f32, r: f32, profile: &DensityProfile, b: f32) -> Option<f32> {
    if profile.noise != 0.0 {
        return None;
    }
    let h2 = (r * r - b * b).max(0.0);
    let h = h2.sqrt();
    let k = profile.falloff;
    let shape = if k == 0.0 {
        2.0 * h
    } else if k == 1.0 {
        4.0 / 3.0 * h * h2 / (r * r)
    } else if k == 2.0 {
        16.0 / 15.0 * h * h2 * h2 / (r * r * r * r)
    } else {
        return None;
    };
    Some(density * shape)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Motion;

    fn ball(density: f32, profile: DensityProfile) -> Volume {
        Volume {
            name: "ball".into(),
            center: Vec3::new(0.3, -0.2, 0.1),
            radius: 1.3,
            color: Vec3::new(0.9, 0.6, 0.3),
            density,
            profile,
            particle: false,
            motion: Motion::default(),
        }
    }

    #[test]
    fn noise_is_bounded_and_not_flat() {
        let mut lo: f32 = 1.0;
        let mut hi: f32 = -1.0;
        for i in 0..4000 {
            let q = Vec3::new(
                i as f32 * 0.137,
                (i as f32 * 0.071).sin() * 3.0,
                i as f32 * -0.053,
            );
            let n = noise(q);
            assert!((-1.0..=1.0).contains(&n), "{n}");
            lo = lo.min(n);
            hi = hi.max(n);
        }
        assert!(hi - lo > 1.0, "range {lo}..{hi}");
        assert_eq!(noise(Vec3::splat(f32::NAN)), 0.0);
    }

    #[test]
    fn validate_names_the_problem() {
        let mut v = ball(1.0, DensityProfile::UNIFORM);
        assert!(v.validate().is_ok());
        v.profile.noise = 2.0;
        assert!(
            v.validate()
                .unwrap_err()
                .to_string()
                .contains("noise in [0, 1]")
        );
        v.profile.noise = 0.5;
        v.density = -1.0;
        assert!(
            v.validate()
                .unwrap_err()
                .to_string()
                .contains("density >= 0")
        );
        v.density = f32::NAN;
        assert!(
            v.validate()
                .unwrap_err()
                .to_string()
                .contains("is not finite")
        );
    }
}
