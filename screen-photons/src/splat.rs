//! The energy splat of a receiver point (section 3.1): the Rust twin of `splat_kernel` and
//! `splat_weight` in `shaders/splat.wgsl`.
//!
//! A photon of flux `Phi` that lands at `C` lights the surface around it with irradiance
//! `Phi k(d)`, `d` the distance from `C` on the splat's plane and `k` the cone kernel of
//! radius `s`, `k(d) = 3 / (pi s^2) max(0, 1 - d / s)`: the paper's `s - d` (equation 1),
//! normalised so that `k` integrates to 1 over the plane and the splat carries exactly the
//! photon's flux. Each pixel the splat covers casts its view ray onto the plane (the
//! receiver's tangent plane for oriented splats, the plane facing the eye for sprites).

use glam::Vec3;

/// `splat_kernel` and `splat_weight` in WGSL (no bindings): included by the splat pass and the
/// conformance test.
pub const WEIGHT_WGSL: &str = include_str!("shaders/splat_weight.wgsl");
use std::f32::consts::PI;

/// The cone kernel of radius `s` at distance `d`.
pub fn kernel(d: f32, s: f32) -> f32 {
    3.0 / (PI * s * s) * (1.0 - d / s).max(0.0)
}

/// The weight at a pixel whose unit view ray from `eye` is `view`, for the splat at `c` with
/// plane normal `n` and radius `s`: `(kernel, distance from the eye along the ray)`, or zeros
/// when the ray misses the plane (parallel, or the plane behind the eye).
pub fn weight(eye: Vec3, view: Vec3, c: Vec3, n: Vec3, s: f32) -> (f32, f32) {
    let denom = view.dot(n);
    if denom.abs() < 1e-6 {
        return (0.0, 0.0);
    }
    let tau = (c - eye).dot(n) / denom;
    if tau <= 0.0 {
        return (0.0, 0.0);
    }
    let x = eye + view * tau;
    (kernel(x.distance(c), s), tau)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernel integrates to 1 over its plane (midpoint rule on rings).
    #[test]
    fn the_kernel_conserves_flux() {
        for s in [0.01, 0.3, 2.0] {
            let n = 4000;
            let dr = s / n as f32;
            let total: f32 = (0..n)
                .map(|i| {
                    let r = (i as f32 + 0.5) * dr;
                    kernel(r, s) * 2.0 * PI * r * dr
                })
                .sum();
            assert!((total - 1.0).abs() < 1e-4, "s = {s}: {total}");
        }
    }

    #[test]
    fn a_ray_through_the_centre_has_the_peak_weight() {
        let eye = Vec3::new(0.0, 1.0, 3.0);
        let c = Vec3::new(0.2, 0.0, 0.0);
        let (w, tau) = weight(eye, (c - eye).normalize(), c, Vec3::Y, 0.5);
        assert!((w - kernel(0.0, 0.5)).abs() < 1e-4 && (tau - eye.distance(c)).abs() < 1e-5);
        // Parallel to the plane: nothing.
        assert_eq!(weight(eye, Vec3::X, c, Vec3::Y, 0.5), (0.0, 0.0));
    }
}
