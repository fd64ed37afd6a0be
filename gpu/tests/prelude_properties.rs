//! Property tests of the Rust twins in `gpu::prelude` (the WGSL versions are held to these by
//! `prelude_conformance.rs`). Tolerances are stated per property; they cover f32 rounding of
//! the twin, not approximation error (the Fresnel properties hold for the seeds'
//! approximation exactly, up to rounding).

use glam::{DVec3, Vec2, Vec3};
use gpu::prelude::*;
use proptest::prelude::*;

/// Uniformly distributed unit vector (no rejection).
fn unit_vec() -> impl Strategy<Value = Vec3> {
    (-1.0f32..=1.0, 0.0f32..std::f32::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    })
}

fn vec3_in(lo: f32, hi: f32) -> impl Strategy<Value = Vec3> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A unit direction with each component zeroed (as +0.0 or -0.0) with probability 1/3.
fn direction_with_zeros() -> impl Strategy<Value = Vec3> {
    (unit_vec(), [0u8..6, 0u8..6, 0u8..6]).prop_map(|(d, mask)| {
        let mut d = d;
        for a in 0..3 {
            match mask[a] {
                0 => d[a] = 0.0,
                1 => d[a] = -0.0,
                _ => {}
            }
        }
        if d.abs().max_element() < 1e-3 {
            d = Vec3::new(0.0, -1.0, 0.0);
        }
        d / d.length()
    })
}

/// Incident direction and normal with `dot(i, n) < 0` (the normal faces the incoming ray).
fn incident_and_normal() -> impl Strategy<Value = (Vec3, Vec3)> {
    (unit_vec(), unit_vec())
        .prop_filter("not tangent", |(i, n)| i.dot(*n).abs() > 1e-4)
        .prop_map(|(i, n)| if i.dot(n) > 0.0 { (-i, n) } else { (i, n) })
}

/// Relative index `eta` spanning both sides of 1.
fn eta() -> impl Strategy<Value = f32> {
    prop_oneof![0.2f32..1.0, 1.0f32..5.0]
}

fn sin_between(a: Vec3, n: Vec3) -> f64 {
    a.as_dvec3().cross(n.as_dvec3()).length()
}

/// Independent f64 slab test with explicit handling of zero direction components.
fn ray_box_f64(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> Option<(f64, f64)> {
    let (o, d, lo, hi) = (o.as_dvec3(), d.as_dvec3(), lo.as_dvec3(), hi.as_dvec3());
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
        } else {
            let (ta, tb) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Distance from `p` to the surface of the box (0 on the surface, positive elsewhere).
fn box_surface_distance(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    let outside = (lo - p).max(p - hi).max(DVec3::ZERO);
    if outside.max_element() > 0.0 {
        outside.length()
    } else {
        (p - lo).min(hi - p).min_element()
    }
}

/// The checks shared by the two ray_box properties.
fn check_ray_box(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> Result<(), TestCaseError> {
    let t = ray_box(o, d, lo, hi);
    prop_assert!(
        !t.is_nan(),
        "NaN {} from o {} d {} box {}..{}",
        t,
        o,
        d,
        lo,
        hi
    );
    match ray_box_f64(o, d, lo, hi) {
        Some((t0, t1)) if (t1 - t0) > 1e-4 => {
            prop_assert!(t.x <= t.y, "missed, exact ({}, {})", t0, t1)
        }
        None => prop_assert!(
            t == MISS || (t.y - t.x) <= 1e-4,
            "hit {} but the exact test misses",
            t
        ),
        _ => {}
    }
    if t.x <= t.y {
        for ti in [t.x, t.y] {
            prop_assert!(ti.is_finite(), "infinite hit parameter {} for d {}", ti, d);
            let p = (o + ti * d).as_dvec3();
            let err = box_surface_distance(p, lo.as_dvec3(), hi.as_dvec3());
            let tol = 1e-4 * (1.0 + o.length() as f64 + ti.abs() as f64);
            prop_assert!(err <= tol, "t {} is {} off the box", ti, err);
        }
    }
    Ok(())
}

proptest! {
    /// Snell's law: eta sin_i = sin_t, a unit transmitted direction on the far side of the
    /// surface, in the plane of incidence. Tolerance 1e-4 absolute on sines, 1e-5 on lengths;
    /// cases within 1e-3 of the critical angle are left to the TIR property.
    #[test]
    fn refract_obeys_snells_law((i, n) in incident_and_normal(), eta in eta()) {
        let sin_i = sin_between(i, n);
        let s = eta as f64 * sin_i;
        prop_assume!(s < 1.0 - 1e-3);
        let r = refract_dir(i, n, eta);
        prop_assert_eq!(r.w, 1.0);
        let t = r.truncate();
        prop_assert!((t.length() - 1.0).abs() < 1e-5, "|t| = {}", t.length());
        prop_assert!((sin_between(t, n) - s).abs() < 1e-4, "eta sin_i {} sin_t {}", s, sin_between(t, n));
        prop_assert!(t.dot(n) < 0.0, "transmitted ray must cross the surface");
        let plane_normal = i.cross(n).normalize_or_zero();
        prop_assert!(t.dot(plane_normal).abs() < 1e-4, "t leaves the plane of incidence");
    }

    /// Total internal reflection happens exactly when eta sin_i > 1 (cases within 1e-4 of 1
    /// are rounding-sensitive and skipped); it returns the mirror direction with flag 0.
    #[test]
    fn refract_reports_tir_exactly_when_eta_sin_exceeds_one((i, n) in incident_and_normal(), eta in eta()) {
        let s = eta as f64 * sin_between(i, n);
        prop_assume!((s - 1.0).abs() > 1e-4);
        let r = refract_dir(i, n, eta);
        if s > 1.0 {
            prop_assert_eq!(r.w, 0.0);
            prop_assert!((r.truncate() - reflect_dir(i, n)).length() < 1e-6);
            prop_assert!((r.truncate().length() - 1.0).abs() < 1e-5);
        } else {
            prop_assert_eq!(r.w, 1.0);
        }
    }

    /// fresnel_nk lies in [0, 1] (1e-6 rounding allowance) for any cosine, is 1 at grazing
    /// incidence and ((n-1)^2 + k^2) / ((n+1)^2 + k^2) at normal incidence (rel 1e-6).
    #[test]
    fn fresnel_nk_is_a_reflectance(cos in -1.0f32..2.0, n in vec3_in(0.01, 10.0), k in vec3_in(0.0, 20.0)) {
        let f = fresnel_nk(cos, n, k);
        for c in 0..3 {
            prop_assert!(f[c] >= 0.0 && f[c] <= 1.0 + 1e-6, "F = {} for cos {}", f[c], cos);
        }
        let grazing = fresnel_nk(0.0, n, k);
        prop_assert!((grazing - Vec3::ONE).abs().max_element() < 1e-6, "grazing F = {}", grazing);
        let normal = fresnel_nk(1.0, n, k);
        let exact = ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k);
        prop_assert!((normal - exact).abs().max_element() <= 1e-6 * exact.max_element().max(1e-3), "normal F {} vs {}", normal, exact);
    }

    /// fresnel_dielectric lies in [0, 1], is 1 at grazing incidence and (eta-1)^2/(eta+1)^2 at
    /// normal incidence, for eta on both sides of 1 (abs 1e-6).
    #[test]
    fn fresnel_dielectric_is_a_reflectance(cos in -1.0f32..2.0, eta in prop_oneof![0.1f32..1.0, 1.0f32..10.0]) {
        let f = fresnel_dielectric(cos, eta);
        prop_assert!((0.0..=1.0 + 1e-6).contains(&f), "F = {} for cos {} eta {}", f, cos, eta);
        prop_assert!((fresnel_dielectric(0.0, eta) - 1.0).abs() < 1e-6);
        let exact = (eta - 1.0).powi(2) / (eta + 1.0).powi(2);
        prop_assert!((fresnel_dielectric(1.0, eta) - exact).abs() < 1e-6, "normal F {} vs {}", fresnel_dielectric(1.0, eta), exact);
    }

    /// Reciprocity: the reflectance seen from the incident side equals the one seen from the
    /// transmitted side, fresnel_dielectric(cos_i, eta) == fresnel_dielectric(cos_t, 1/eta).
    /// Abs 1e-4 (cos_i >= 0.05 keeps the round trip of the cosine well-conditioned).
    #[test]
    fn fresnel_dielectric_is_reciprocal(cos_i in 0.05f32..=1.0, eta in eta()) {
        let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
        prop_assume!(sin2_t < 1.0);
        let cos_t = (1.0 - sin2_t).sqrt();
        let there = fresnel_dielectric(cos_i, eta);
        let back = fresnel_dielectric(cos_t, 1.0 / eta);
        prop_assert!((there - back).abs() < 1e-4, "F({}, {}) = {} but F({}, {}) = {}", cos_i, eta, there, cos_t, 1.0 / eta, back);
    }

    /// Beyond the critical angle (eta < 1) the dielectric reflectance is exactly 1.
    #[test]
    fn fresnel_dielectric_is_one_under_tir(cos_i in 0.0f32..=1.0, eta in 0.1f32..1.0) {
        prop_assume!((1.0 - cos_i * cos_i) / (eta * eta) >= 1.0);
        prop_assert_eq!(fresnel_dielectric(cos_i, eta), 1.0);
    }

    /// Direction -> (face, u, v) -> direction gives the same direction (1e-5 after
    /// normalisation); face is an integer in 0..6 and (u, v) lies in [0, 1]^2.
    #[test]
    fn cube_addressing_round_trips_from_directions(d in vec3_in(-10.0, 10.0)) {
        prop_assume!(d.length() > 1e-3);
        let fuv = cube_dir_to_face_uv(d);
        prop_assert!(fuv.x.fract() == 0.0 && (0.0..6.0).contains(&fuv.x));
        prop_assert!((0.0..=1.0).contains(&fuv.y) && (0.0..=1.0).contains(&fuv.z), "uv {}", fuv);
        let back = cube_face_uv_to_dir(fuv.x as u32, fuv.y, fuv.z);
        prop_assert!((back.normalize() - d.normalize()).length() < 1e-5, "{} -> {} -> {}", d, fuv, back);
    }

    /// (face, u, v) -> direction -> (face, u, v) is the identity away from face edges
    /// (u, v in [0.001, 0.999], where the face is unambiguous); abs 1e-5 on u, v.
    #[test]
    fn cube_addressing_round_trips_from_texels(face in 0u32..6, u in 0.001f32..0.999, v in 0.001f32..0.999) {
        let fuv = cube_dir_to_face_uv(cube_face_uv_to_dir(face, u, v));
        prop_assert_eq!(fuv.x, face as f32);
        prop_assert!((fuv.y - u).abs() < 1e-5 && (fuv.z - v).abs() < 1e-5, "({} {} {}) -> {}", face, u, v, fuv);
    }

    /// Octahedral encoding round-trips unit vectors (1e-5), lands in [-1, 1]^2, and decoding
    /// then encoding an interior point of the square gives it back (1e-5).
    #[test]
    fn oct_encoding_round_trips(n in unit_vec(), e in (-0.999f32..0.999, -0.999f32..0.999)) {
        let code = oct_encode(n);
        prop_assert!(code.abs().max_element() <= 1.0, "code {}", code);
        let back = oct_decode(code);
        prop_assert!((back - n).length() < 1e-5, "{} -> {} -> {}", n, code, back);
        let e = Vec2::new(e.0, e.1);
        let m = oct_decode(e);
        prop_assert!((m.length() - 1.0).abs() < 1e-5);
        prop_assert!((oct_encode(m) - e).length() < 1e-5, "{} -> {} -> {}", e, m, oct_encode(m));
    }

    /// Both ray_sphere parameters are points on the sphere (distance error at most
    /// 1e-5 (1 + |o - c|^2 / r)); a miss happens only when the exact (f64) discriminant is
    /// negative or within rounding of 0. Half of the rays are aimed at the sphere.
    #[test]
    fn ray_sphere_hits_lie_on_the_sphere(
        o in vec3_in(-5.0, 5.0), center in vec3_in(-2.0, 2.0), r in 0.1f32..3.0,
        random_dir in unit_vec(), aim_offset in unit_vec(), aim_scale in 0.0f32..1.0, aimed in any::<bool>(),
    ) {
        let aim = center + aim_offset * r * aim_scale - o;
        let d = if aimed && aim.length() > 1e-3 { aim.normalize() } else { random_dir };
        let t = ray_sphere(o, d, center, r);
        let oc = (o - center).as_dvec3();
        let tol = 1e-5 * (1.0 + oc.length_squared() / r as f64);
        if t.x <= t.y {
            for ti in [t.x, t.y] {
                let p = (o + ti * d).as_dvec3();
                let err = ((p - center.as_dvec3()).length() - r as f64).abs();
                prop_assert!(err <= tol, "t {} is {} off the sphere", ti, err);
            }
        } else {
            prop_assert_eq!(t, MISS);
            let b = oc.dot(d.as_dvec3());
            let disc = b * b - (oc.length_squared() - (r as f64).powi(2));
            prop_assert!(disc < 8.0 * f32::EPSILON as f64 * (b * b + oc.length_squared()), "missed with discriminant {}", disc);
            prop_assert!(!aimed || aim.length() <= 1e-3 || aim_scale >= 0.999, "an aimed ray missed");
        }
    }

    /// ray_box never returns NaN, agrees with an f64 slab test on hit or miss (unless the
    /// interval is degenerate, within 1e-4), and its parameters are finite points on the box
    /// surface (within 1e-4 (1 + |o| + |t|)); zero direction components (+0 and -0) included.
    #[test]
    fn ray_box_hits_lie_on_the_box(
        o in vec3_in(-6.0, 6.0), lo in vec3_in(-3.0, 3.0), size in vec3_in(0.05, 4.0), d in direction_with_zeros(),
    ) {
        check_ray_box(o, d, lo, lo + size)?;
    }

    /// box_project from inside the proxy box: the exit point (probe + xyz) lies on the box
    /// surface, ahead of x on the ray at the returned t, and no other point of the box's
    /// surface along the ray lies farther (it is the *exit*); tolerance 1e-4 (1 + |x| + t).
    #[test]
    fn box_project_exits_the_proxy_box_along_the_ray(
        lo in vec3_in(-3.0, 0.0), size in vec3_in(0.1, 4.0), a in vec3_in(0.001, 0.999),
        b in vec3_in(0.0, 1.0), r in direction_with_zeros(),
    ) {
        let hi = lo + size;
        let x = lo + size * a;
        let probe = lo + size * b;
        let l = box_project(x, r, probe, lo, hi);
        prop_assert!(!l.is_nan(), "NaN {}", l);
        prop_assert!(l.w > 0.0, "inside the box the ray always exits ahead: {}", l);
        let exit = probe + l.truncate();
        let tol = 1e-4 * (1.0 + x.length() as f64 + l.w as f64);
        prop_assert!(box_surface_distance(exit.as_dvec3(), lo.as_dvec3(), hi.as_dvec3()) <= tol,
            "exit {} is off the box", exit);
        let on_ray = (x + r * l.w - exit).length() as f64;
        prop_assert!(on_ray <= tol, "exit {} is {} off the ray", exit, on_ray);
        let (_, t_far) = ray_box_f64(x, r, lo, hi).expect("x is inside");
        prop_assert!((t_far - l.w as f64).abs() <= tol, "t {} but the exact exit is {}", l.w, t_far);
    }

    /// What parallax correction is for: in a box-shaped room the lookup direction from any
    /// probe sees exactly the wall point the reflected ray hits (the f64 exit point), so the
    /// lookup is exact; a plain direction lookup is exact only from the probe itself.
    #[test]
    fn box_project_sees_the_wall_point_the_ray_hits(
        lo in vec3_in(-3.0, 0.0), size in vec3_in(0.5, 4.0), a in vec3_in(0.05, 0.95),
        b in vec3_in(0.05, 0.95), r in unit_vec(),
    ) {
        let hi = lo + size;
        let (x, probe) = (lo + size * a, lo + size * b);
        let (_, t_far) = ray_box_f64(x, r, lo, hi).expect("x is inside");
        let wall = x.as_dvec3() + r.as_dvec3() * t_far;
        let l = box_project(x, r, probe, lo, hi).truncate().as_dvec3().normalize();
        let want = (wall - probe.as_dvec3()).normalize();
        prop_assert!(l.dot(want) > 1.0 - 1e-6, "lookup {} sees {} not the wall point {}", l, want, wall);
    }

    /// From the probe itself the correction changes nothing (the lookup direction is r), and
    /// with the proxy pushed to infinity it tends to the direction-only lookup.
    #[test]
    fn box_project_reduces_to_the_direction_lookup(
        lo in vec3_in(-3.0, 0.0), size in vec3_in(0.5, 4.0), a in vec3_in(0.05, 0.95),
        offset in vec3_in(-0.5, 0.5), r in unit_vec(),
    ) {
        let hi = lo + size;
        let probe = lo + size * a;
        let l = box_project(probe, r, probe, lo, hi).truncate().normalize();
        prop_assert!(l.dot(r) > 1.0 - 1e-5, "from the probe: {} vs r {}", l, r);
        let far = box_project(probe + offset, r, probe, Vec3::splat(-1e4), Vec3::splat(1e4));
        prop_assert!(far.truncate().normalize().dot(r) > 1.0 - 1e-6, "far proxy: {}", far);
    }

    /// Outside the box, a ray that misses it or has it behind falls back to (r, -1); never NaN.
    #[test]
    fn box_project_falls_back_outside_the_box(
        lo in vec3_in(-3.0, 0.0), size in vec3_in(0.1, 4.0), x in vec3_in(-8.0, 8.0),
        probe in vec3_in(-3.0, 3.0), r in direction_with_zeros(),
    ) {
        let hi = lo + size;
        let l = box_project(x, r, probe, lo, hi);
        prop_assert!(!l.is_nan());
        match ray_box_f64(x, r, lo, hi) {
            Some((t0, t1)) if t1 > 1e-4 && t1 - t0 > 1e-4 => prop_assert!(l.w > 0.0, "exit at {} missed", t1),
            Some((_, t1)) if t1 < -1e-4 => prop_assert!(l == r.extend(-1.0), "box behind: {}", l),
            None => {
                // The f32 slab test may graze an edge the f64 one misses (a degenerate interval).
                let t = ray_box(x, r, lo, hi);
                prop_assert!(l == r.extend(-1.0) || t.y - t.x <= 1e-4, "box missed: {}", l)
            }
            _ => {}
        }
    }

    /// A ray lying in a slab's boundary plane (origin exactly on the plane, zero direction
    /// component, +0 or -0) gives no NaN and the closed box's answer, as above.
    #[test]
    fn ray_box_in_a_boundary_plane_is_not_nan(
        o in vec3_in(-6.0, 6.0), lo in vec3_in(-3.0, 3.0), size in vec3_in(0.05, 4.0), d in unit_vec(),
        axis in 0usize..3, on_hi in any::<bool>(), negative_zero in any::<bool>(),
    ) {
        let hi = lo + size;
        let (mut o, mut d) = (o, d);
        o[axis] = if on_hi { hi[axis] } else { lo[axis] };
        d[axis] = if negative_zero { -0.0 } else { 0.0 };
        prop_assume!(d.length() > 1e-3);
        let d = d / d.length();
        check_ray_box(o, d, lo, hi)?;
    }
}

// ---------------------------------------------------------------------------------------------
// grid_walk: the 2D DDA through square cells on the xz plane
// ---------------------------------------------------------------------------------------------

/// The whole walk: (cell, t_enter, t_exit) per visited cell, at most `limit` cells.
fn walk_cells(
    o: Vec3,
    d: Vec3,
    min: Vec2,
    size: f32,
    count: glam::IVec2,
    limit: usize,
) -> Vec<(glam::IVec2, f32, f32)> {
    let mut w = grid_walk(o, d, min, size, count);
    let mut out = Vec::new();
    while !w.done() && out.len() < limit {
        out.push((w.cell, w.t_enter, w.t_exit));
        w = grid_walk_next(w, count);
    }
    out
}

/// The f64 parameter interval of the ray inside cell `c` (clipped to t >= 0), if any.
fn cell_interval(o: Vec3, d: Vec3, min: Vec2, size: f32, c: glam::IVec2) -> Option<(f64, f64)> {
    let lo = Vec3::new(min.x + size * c.x as f32, -1e6, min.y + size * c.y as f32);
    let hi = lo + Vec3::new(size, 2e6, size);
    let (t0, t1) = ray_box_f64(o, d, lo, hi)?;
    let t0 = t0.max(0.0);
    (t1 > t0).then_some((t0, t1))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// The walk visits cells in ray order: intervals follow each other without gaps (to
    /// rounding), cells change by one step along one axis, and it ends within nx + nz + 1
    /// cells. It visits exactly the cells the ray crosses by more than 1e-4 (1 + t) (an f64
    /// slab test per cell), except cells it only grazes.
    #[test]
    fn grid_walk_visits_the_crossed_cells_in_ray_order(
        o in vec3_in(-12.0, 12.0), d in direction_with_zeros(), min in (-6.0f32..0.0, -6.0f32..0.0),
        size in 0.2f32..2.0, count in (1i32..10, 1i32..10),
    ) {
        let (min, count) = (Vec2::new(min.0, min.1), glam::IVec2::new(count.0, count.1));
        let cells = walk_cells(o, d, min, size, count, 64);
        prop_assert!(cells.len() <= (count.x + count.y + 1) as usize, "{} cells", cells.len());
        for pair in cells.windows(2) {
            let ((a, _, a_exit), (b, b_enter, _)) = (pair[0], pair[1]);
            prop_assert!((b_enter - a_exit).abs() <= 1e-4 * (1.0 + a_exit.abs()), "gap {} -> {}", a_exit, b_enter);
            prop_assert_eq!((b - a).abs().element_sum(), 1, "{} -> {}", a, b);
        }
        for &(c, t0, t1) in &cells {
            prop_assert!(t0.is_finite() && t1 >= t0 - 1e-4 * (1.0 + t0.abs()), "{} [{}, {}]", c, t0, t1);
        }
        for i in 0..count.x {
            for j in 0..count.y {
                let c = glam::IVec2::new(i, j);
                let visited = cells.iter().any(|&(v, _, _)| v == c);
                if let Some((t0, t1)) = cell_interval(o, d, min, size, c) {
                    if t1 - t0 > 1e-4 * (1.0 + t1) {
                        prop_assert!(visited, "crossed cell {} [{}, {}] not visited: {:?}", c, t0, t1, cells);
                    }
                } else if visited {
                    let &(_, t0, t1) = cells.iter().find(|&&(v, _, _)| v == c).unwrap();
                    prop_assert!(t1 - t0 <= 1e-4 * (1.0 + t1.abs()), "cell {} visited [{}, {}] but not crossed", c, t0, t1);
                }
            }
        }
    }

    /// A ray missing the grid's rectangle, or with it behind, gives a finished walk.
    #[test]
    fn grid_walk_outside_is_done(
        o in vec3_in(-12.0, 12.0), d in direction_with_zeros(), size in 0.2f32..2.0, n in 1i32..10,
    ) {
        let (min, count) = (Vec2::splat(-1.0), glam::IVec2::splat(n));
        let hi = min + size * count.as_vec2();
        let hit = ray_box_f64(o, d, Vec3::new(min.x, -1e6, min.y), Vec3::new(hi.x, 1e6, hi.y));
        prop_assume!(match hit { None => true, Some((_, t1)) => t1 < -1e-4 });
        prop_assert!(grid_walk(o, d, min, size, count).done());
    }
}
