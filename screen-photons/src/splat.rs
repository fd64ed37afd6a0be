//! The energy splat of a receiver point (section 3.1): the Rust twin of `splat_kernel` and
//! `splat_weight` in `shaders/splat.wgsl`.
//!
//! A photon of flux `Phi` that lands at `C` lights the surface around it with irradiance
//! `Phi k(d)`, `d` the distance from `C` on the splat's plane and `k` the cone kernel of
//! radius `s`, `k(d) = 3 / (pi s^2) max(0, 1 - d / s)`: the paper's `s - d` (equation 1),
//! normalised so that `k` integrates to 1 over the plane and the splat carries exactly the
//! photon's flux. Each pixel the splat covers casts its view ray onto the plane (the
//! receiver's tangent plane for oriented splats, the plane facing the eye for sprites).

use glam::{Vec2, Vec3};

/// `splat_kernel` and `splat_weight` in WGSL (no bindings): the module
/// `screen_photons::splat_weight` ([`WEIGHT`]).
pub const WEIGHT_WGSL: &str = include_str!("shaders/splat_weight.wgsl");
/// [`WEIGHT_WGSL`] as a module, which the splat pass and the conformance test import.
pub static WEIGHT: gpu::wgsl::Module = gpu::wgsl::Module::new(
    WEIGHT_WGSL,
    "screen-photons/src/shaders/splat_weight.wgsl",
    &[],
);
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

/// A lattice cell's width in cone radii of its photon's footprint (`FOOTPRINT_CELLS`).
pub const FOOTPRINT_CELLS: f32 = 2.0;
/// The widest footprint in splat radii (`MAX_FOOTPRINT_SPLATS`).
pub const MAX_FOOTPRINT_SPLATS: f32 = 8.0;

/// A footprint's radius matrix `M` (xx, xy, yy) for splat radius `s` and the photon's lattice
/// cell with edges `ex`, `ey` in the receiver's tangent basis (`footprint_matrix` in
/// splat_weight.wgsl, which derives it).
pub fn footprint_matrix(s: f32, ex: Vec2, ey: Vec2) -> [f32; 3] {
    let c2 = FOOTPRINT_CELLS * FOOTPRINT_CELLS;
    let m = [
        s * s + c2 * (ex.x * ex.x + ey.x * ey.x),
        c2 * (ex.x * ex.y + ey.x * ey.y),
        s * s + c2 * (ex.y * ex.y + ey.y * ey.y),
    ];
    let reach = footprint_reach(m);
    let most = MAX_FOOTPRINT_SPLATS * s;
    if reach > most {
        let shrink = (most / reach).powi(2);
        return m.map(|v| v * shrink);
    }
    m
}

/// A footprint's reach: the semi-major axis of its ellipse, the square root of `M`'s larger
/// eigenvalue (`footprint_reach`): the splat's quad must hold a sphere this wide.
pub fn footprint_reach(m: [f32; 3]) -> f32 {
    let half_trace = 0.5 * (m[0] + m[2]);
    let half_gap = 0.5 * (m[0] - m[2]);
    (half_trace + (half_gap * half_gap + m[1] * m[1]).sqrt()).sqrt()
}

/// The footprint's kernel at offset `u` (tangent basis) from the receiver point
/// (`footprint_kernel`).
pub fn footprint_kernel(u: Vec2, m: [f32; 3]) -> f32 {
    let det = m[0] * m[2] - m[1] * m[1];
    let q2 = (m[2] * u.x * u.x - 2.0 * m[1] * u.x * u.y + m[0] * u.y * u.y) / det;
    3.0 / (PI * det.sqrt()) * (1.0 - q2.sqrt()).max(0.0)
}

/// The tangent of unit normal `n` the footprint's basis `(t, n x t)` starts from
/// (`footprint_tangent`, Duff et al. 2017).
pub fn footprint_tangent(n: Vec3) -> Vec3 {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ratio of the largest to the smallest sum of the footprints of a lattice with edges
    /// `ex`, `ey`, over one cell.
    fn lattice_ripple(ex: Vec2, ey: Vec2, m: [f32; 3]) -> (f32, f32) {
        let sum = |at: Vec2| -> f32 {
            let mut total = 0.0;
            for j in -12..=12 {
                for i in -12..=12 {
                    total += footprint_kernel(at - ex * i as f32 - ey * j as f32, m);
                }
            }
            total
        };
        let sums: Vec<f32> = (0..8)
            .flat_map(|b| (0..8).map(move |a| ex * (a as f32 / 8.0) + ey * (b as f32 / 8.0)))
            .map(sum)
            .collect();
        let lo = sums.iter().copied().fold(f32::MAX, f32::min);
        let hi = sums.iter().copied().fold(0.0, f32::max);
        (hi / lo, lo * ex.perp_dot(ey).abs())
    }

    #[test]
    fn without_a_cell_the_footprint_is_the_cone() {
        let m = footprint_matrix(0.3, Vec2::ZERO, Vec2::ZERO);
        for d in [0.0, 0.1, 0.29, 0.31] {
            let u = Vec2::new(d * 0.6, d * 0.8);
            assert!((footprint_kernel(u, m) - kernel(d, 0.3)).abs() < 1e-4);
        }
    }

    #[test]
    fn a_footprint_conserves_flux_within_its_reach() {
        // A cell at 45 degrees to the basis, where the ellipse reaches farthest beyond its
        // diagonal terms: the disc of the reach (what the splat's quad holds) keeps all of it.
        let m = footprint_matrix(0.02, Vec2::new(0.2, 0.2), Vec2::new(-0.03, 0.03));
        let reach = footprint_reach(m);
        assert!(
            reach > 1.3 * m[0].max(m[2]).sqrt(),
            "the test's cell is not tilted"
        );
        let n = 600;
        let step = 2.0 * reach / n as f32;
        let mut total = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let u = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * step - reach;
                if u.length() <= reach {
                    total += footprint_kernel(u, m) as f64;
                }
            }
        }
        let total = total * (step * step) as f64;
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }

    #[test]
    fn a_stretched_lattice_of_footprints_sums_to_nearly_flat() {
        // Cells stretched 6 to 1 and sheared, the long edge 2.4 splat radii.
        let (ex, ey) = (Vec2::new(0.12, 0.02), Vec2::new(-0.01, 0.02));
        let (ripple, level) = lattice_ripple(ex, ey, footprint_matrix(0.05, ex, ey));
        assert!(ripple < 1.04, "footprints ripple by {ripple}");
        assert!((level - 1.0).abs() < 0.04, "level {level}");
        // Fixed cones of the splat radius draw the lattice's rows.
        let (fixed, _) = lattice_ripple(ex, ey, footprint_matrix(0.05, Vec2::ZERO, Vec2::ZERO));
        assert!(fixed > 10.0, "fixed splats ripple by only {fixed}");
    }

    #[test]
    fn the_tangent_is_orthonormal_to_the_normal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.8, 0.2).normalize(),
        ] {
            let t = footprint_tangent(n);
            assert!(
                (t.length() - 1.0).abs() < 1e-5 && t.dot(n).abs() < 1e-5,
                "{n}: {t}"
            );
        }
    }

    #[test]
    fn a_cell_across_a_fold_is_capped() {
        let m = footprint_matrix(0.01, Vec2::new(5.0, 5.0), Vec2::new(0.0, 0.01));
        assert!((footprint_reach(m) - MAX_FOOTPRINT_SPLATS * 0.01).abs() < 1e-5);
    }

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
