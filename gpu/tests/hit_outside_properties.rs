//! Properties of the search from outside (`gpu::distance_map::hit_from_outside`, Dancsik and
//! Minarik section 4.1: a ray against an object represented by its refractor distance map)
//! on objects whose map is exact: ellipsoids centred at the reference point (star-shaped and
//! convex from it, so the map holds every surface point). What a non-star-shaped piece (the
//! chess knight) does to the search is measured where the meshes are, not here.
//!
//! Stated claims (each a test below):
//! - `a_ray_missing_the_box_has_no_hit`: a ray whose line misses the bounding box, or has it
//!   behind, gives `None`.
//! - `clear_misses_are_rejected`: a ray that crosses the box but passes the ellipsoid at more
//!   than the epsilon gives `None` (the found surface point is off the ray by at least that
//!   distance).
//! - `hits_are_on_the_ray_ahead_and_near_the_surface`: whenever a hit is reported, its `d` is
//!   finite and >= 0, its point is on the ray, and the ellipsoid's surface in its direction
//!   within the epsilon.
//! - `convex_hit_rate_and_error`: 20k rays from outside aimed at points well inside ellipsoids
//!   of semi-axes 0.2-2 (inside 0.9 of it in its own metric: no grazing rays), epsilon 1e-3 of
//!   the size, false position: the share found and the error of the found entry against the
//!   exact one, printed for 8 and 16 iterations. Measured: 8 iterations find 97.61%, 95.61%
//!   of those within 1e-3 of the size; 16 find 98.91%, all within 1e-3. Asserted for 16: at
//!   least 98.5% found, 99.9% of them within 1e-3, none on the exit side. The 1.1% never found (as at 32 iterations)
//!   are flat ellipsoids crossed through their thin side: the search starts at the far box
//!   point (overshooting), its guesses overshoot too, every step is then backward and the
//!   clamp to `d >= 0` pins it at the box point, off the surface: a failure of running
//!   `Hit()` from outside, measured here and left as the paper has it.

use glam::Vec3;
use gpu::distance_map::{Method, hit_from_outside};
use proptest::prelude::*;

/// An ellipsoid centred at the reference point with semi-axes `a`: its exact distance map.
fn ellipsoid(a: Vec3) -> impl Fn(Vec3) -> f32 {
    move |dir: Vec3| {
        let u = dir.normalize();
        1.0 / (u / a).length()
    }
}

/// The exact entry parameter of the ray `y + R d` into the ellipsoid (f64), if it hits.
fn exact_entry(a: Vec3, y: Vec3, r: Vec3) -> Option<f64> {
    let (a, y, r) = (a.as_dvec3(), y.as_dvec3(), r.as_dvec3());
    let (o, d) = (y / a, r / a);
    let (qa, qb, qc) = (d.dot(d), 2.0 * o.dot(d), o.dot(o) - 1.0);
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return None;
    }
    let t = (-qb - disc.sqrt()) / (2.0 * qa);
    (t >= 0.0).then_some(t)
}

const EPSILON: f32 = 1e-3;

/// Whether the ray's line misses the box `[-a, a]` (or has it behind) by a margin, in f64.
fn box_clearly_missed(a: Vec3, y: Vec3, r: Vec3) -> bool {
    let (a, y, r) = (a.as_dvec3(), y.as_dvec3(), r.as_dvec3());
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if r[k].abs() < 1e-9 {
            if y[k].abs() > a[k] - 1e-4 {
                return true;
            }
            continue;
        }
        let (ta, tb) = ((-a[k] - y[k]) / r[k], (a[k] - y[k]) / r[k]);
        t0 = t0.max(ta.min(tb));
        t1 = t1.min(ta.max(tb));
    }
    t1 < t0 - 1e-4 || t1 < -1e-4
}

fn axes() -> impl Strategy<Value = Vec3> {
    (0.2f32..2.0, 0.2f32..2.0, 0.2f32..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn unit() -> impl Strategy<Value = Vec3> {
    (-1.0f32..=1.0, 0.0f32..std::f32::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn a_ray_missing_the_box_has_no_hit(a in axes(), y in (-8.0f32..8.0, -8.0f32..8.0, -8.0f32..8.0), r in unit()) {
        let y = Vec3::new(y.0, y.1, y.2);
        // An independent f64 slab test, with a margin against rounding.
        prop_assume!(box_clearly_missed(a, y, r));
        let h = hit_from_outside(&ellipsoid(a), y, r, -a, a, Method::FalsePosition, 8, EPSILON);
        prop_assert!(h.is_none(), "{:?}", h);
    }

    #[test]
    fn clear_misses_are_rejected(a in axes(), dir in unit(), side in unit(), margin in 0.0f32..1.0) {
        // In the ellipsoid's own metric (space divided by `a`) a line passing the unit sphere
        // at 1 + m stays at least m min(a) from the ellipsoid in world space; choose
        // m >= 2 epsilon / min(a), so every point of the ray is farther than the epsilon from
        // the surface (the radial distance the search checks is larger still).
        let m = 2.0 * EPSILON / a.min_element() + margin;
        let d_scaled = (dir / a).normalize();
        let perp = (side - d_scaled * side.dot(d_scaled)).normalize_or(d_scaled.any_orthonormal_vector());
        let y_scaled = -d_scaled * 8.0 + perp * (1.0 + m);
        let (y, r) = (y_scaled * a, (d_scaled * a).normalize());
        let h = hit_from_outside(&ellipsoid(a), y, r, -a, a, Method::FalsePosition, 8, EPSILON);
        prop_assert!(h.is_none(), "{:?}", h);
    }

    #[test]
    fn hits_are_on_the_ray_ahead_and_near_the_surface(
        a in axes(), y in (-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0), r in unit(),
        iterations in 0u32..12, secant in any::<bool>(),
    ) {
        let y = Vec3::new(y.0, y.1, y.2);
        let method = if secant { Method::Secant } else { Method::FalsePosition };
        if let Some(h) = hit_from_outside(&ellipsoid(a), y, r, -a, a, method, iterations, EPSILON) {
            prop_assert!(h.d.is_finite() && h.d >= 0.0, "{:?}", h);
            prop_assert!((y + r * h.d - h.point).length() <= 1e-4 * (1.0 + h.d), "{:?}", h);
            // The ellipsoid's own surface in the point's direction, not the reported one.
            let surface = h.point.normalize() * ellipsoid(a)(h.point);
            prop_assert!((surface - h.point).length() <= EPSILON * (1.0 + 1e-4), "{:?}", h);
        }
    }
}

/// Share found and relative error of the found entry, for `iterations` false-position steps.
fn convex_rate(iterations: u32) -> (usize, usize, usize, Vec<f32>) {
    let h = |k: u32| gpu::prelude::hash_to_unit(k);
    let (mut found, mut close, mut total) = (0usize, 0usize, 0usize);
    let mut errors = Vec::new();
    for i in 0..20_000u32 {
        let k = i * 16;
        let a = Vec3::new(0.2 + 1.8 * h(k), 0.2 + 1.8 * h(k + 1), 0.2 + 1.8 * h(k + 2));
        // A target well inside the ellipsoid (inside 0.9 of it in its own metric).
        let inside = Vec3::new(h(k + 3), h(k + 4), h(k + 5)) * 2.0 - Vec3::ONE;
        let target = inside.clamp_length_max(0.9) * a;
        let from =
            (Vec3::new(h(k + 6), h(k + 7), h(k + 8)) * 2.0 - Vec3::ONE).normalize_or(Vec3::X);
        let y = target + from * (3.0 * a.max_element());
        let r = (target - y).normalize();
        let Some(exact) = exact_entry(a, y, r) else {
            continue;
        };
        total += 1;
        let epsilon = 1e-3 * a.max_element();
        let method = Method::FalsePosition;
        if let Some(hit) = hit_from_outside(&ellipsoid(a), y, r, -a, a, method, iterations, epsilon)
        {
            found += 1;
            let error = (hit.d as f64 - exact).abs() as f32 / a.max_element();
            errors.push(error);
            if error <= 1e-3 {
                close += 1;
            }
        }
    }
    errors.sort_by(f32::total_cmp);
    (found, close, total, errors)
}

#[test]
fn convex_hit_rate_and_error() {
    for iterations in [8, 16] {
        let (found, close, total, errors) = convex_rate(iterations);
        let q = |p: f64| errors[((errors.len() - 1) as f64 * p) as usize];
        println!(
            "search from outside, exact ellipsoid maps, false position {iterations}: {found} of \
             {total} found ({:.2}%), {close} within 1e-3 of the size ({:.2}% of found); relative \
             error p50 {:.2e}, p99 {:.2e}, max {:.2e}",
            100.0 * found as f64 / total as f64,
            100.0 * close as f64 / found.max(1) as f64,
            q(0.5),
            q(0.99),
            q(1.0)
        );
        if iterations == 16 {
            assert!(found * 1000 >= total * 985, "found {found} of {total}");
            assert!(
                close * 1000 >= found * 999,
                "{close} of {found} within 1e-3"
            );
            // Every found point is the entry, never the exit (a wrong root would be far off).
            let worst = errors.last().copied().unwrap_or(0.0);
            assert!(worst < 0.01, "a wrong root: relative error {worst}");
        }
    }
}
