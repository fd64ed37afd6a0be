//! Property tests of the path-length twins in `volumes::path_length` (the WGSL versions are
//! held to these by `conformance.rs`). Tolerances cover f32 rounding only; they are stated
//! per property.

use glam::{Vec2, Vec3};
use gpu::prelude::ray_sphere;
use proptest::prelude::*;
use testkit::strategies::{unit_vector, vec3_in};
use volumes::path_length::*;

/// A ray aimed near a sphere: origin anywhere around it, direction toward a point of the
/// sphere's bounding box (so that most rays hit), plus the sphere.
fn ray_and_sphere() -> impl Strategy<Value = (Vec3, Vec3, Vec3, f32)> {
    (
        vec3_in(-5.0, 5.0),
        0.05f32..3.0,
        vec3_in(-8.0, 8.0),
        vec3_in(-1.2, 1.2),
        unit_vector(),
    )
        .prop_map(|(c, r, o, aim, fallback)| {
            let d = (c + aim * r - o).normalize_or(fallback);
            (o, d, c, r)
        })
}

/// A ray from outside or inside aimed at a point inside the sphere: it always hits.
fn ray_hitting_sphere() -> impl Strategy<Value = (Vec3, Vec3, Vec3, f32)> {
    (
        vec3_in(-5.0, 5.0),
        0.05f32..3.0,
        vec3_in(-8.0, 8.0),
        vec3_in(-1.0, 1.0),
        unit_vector(),
    )
        .prop_map(|(c, r, o, aim, fallback)| {
            let d = (c + aim.clamp_length_max(0.98) * r - o).normalize_or(fallback);
            (o, d, c, r)
        })
}

/// A float at most 8 ulps from 1.
fn near_one() -> impl Strategy<Value = f32> {
    (-8i32..=8).prop_map(|k| f32::from_bits((1.0f32.to_bits() as i32 + k) as u32))
}

fn scene_distance() -> impl Strategy<Value = f32> {
    prop_oneof![
        0.0f32..20.0,
        Just(f32::INFINITY),
        Just(gpu::prelude::BIG),
        -1.0f32..0.0
    ]
}

fn opacity_kind() -> impl Strategy<Value = u32> {
    prop_oneof![Just(OPACITY_LINEAR), Just(OPACITY_LOG), Just(OPACITY_SQRT)]
}

/// Rounding allowance for lengths of rays of this size.
fn tol(o: Vec3, c: Vec3, r: f32) -> f32 {
    2e-5 * ((o - c).length() + r + 1.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The depth fade is in [0, 1], 0 where the billboard is at or behind the scene, 1 once the
    /// scene is a fade distance behind it, non-decreasing in the gap, and linear in between
    /// (tolerance 1e-5); a zero fade is the plain depth test.
    #[test]
    fn depth_fade_replaces_the_depth_test_with_a_ramp(
        t_particle in 0.0f32..50.0, gap in -10.0f32..10.0, more in 0.0f32..5.0, fade in 0.01f32..5.0,
    ) {
        let t_scene = t_particle + gap;
        // The gap as the function sees it (after rounding of the sum).
        let gap = t_scene - t_particle;
        let f = depth_fade(t_particle, t_scene, fade);
        prop_assert!((0.0..=1.0).contains(&f), "fade {}", f);
        if gap <= 0.0 { prop_assert_eq!(f, 0.0); }
        if gap >= fade { prop_assert_eq!(f, 1.0); }
        if gap > 0.0 && gap < fade {
            prop_assert!((f - gap / fade).abs() <= 1e-5 * (1.0 + t_particle / fade), "{} vs {}", f, gap / fade);
        }
        prop_assert!(depth_fade(t_particle, t_scene + more, fade) >= f - 1e-6, "not monotone");
        let hard = depth_fade(t_particle, t_scene, 0.0);
        prop_assert_eq!(hard, if gap > 0.0 { 1.0 } else { 0.0 });
    }

    /// The visible length is never negative, never longer than the chord, and finite.
    #[test]
    fn sphere_length_within_chord((o, d, c, r) in ray_and_sphere(), s in scene_distance()) {
        let len = sphere_path_length(o, d, c, r, s);
        let t = ray_sphere(o, d, c, r);
        let chord = if t.x <= t.y { t.y - t.x } else { 0.0 };
        prop_assert!(len.is_finite() && len >= 0.0, "len {len}");
        prop_assert!(len <= chord + tol(o, c, r), "len {len} > chord {chord}");
    }

    /// Moving the scene back never shortens the visible path.
    #[test]
    fn sphere_length_monotone_in_scene_depth((o, d, c, r) in ray_and_sphere(), a in 0.0f32..20.0, b in 0.0f32..20.0) {
        let (near, far) = (a.min(b), a.max(b));
        prop_assert!(sphere_path_length(o, d, c, r, near) <= sphere_path_length(o, d, c, r, far));
    }

    /// A surface in front of the volume hides it entirely; one behind it shows the whole chord
    /// (eye outside the sphere).
    #[test]
    fn sphere_scene_in_front_or_behind((o, d, c, r) in ray_hitting_sphere(), k in 0.0f32..1.0, extra in 0.0f32..10.0) {
        let t = ray_sphere(o, d, c, r);
        prop_assume!(t.x <= t.y);
        let front = t.x.max(0.0);
        prop_assert_eq!(sphere_path_length(o, d, c, r, k * front), 0.0);
        if t.x >= 0.0 {
            let full = sphere_path_length(o, d, c, r, t.y + extra);
            prop_assert!((full - (t.y - t.x)).abs() <= tol(o, c, r), "full {full} chord {}", t.y - t.x);
            prop_assert_eq!(sphere_path_length(o, d, c, r, f32::INFINITY), full);
        }
    }

    /// With the eye inside the volume the path starts at the eye: min(t_far, t_scene).
    #[test]
    fn sphere_camera_inside(c in vec3_in(-5.0, 5.0), r in 0.1f32..3.0, p in vec3_in(-1.0, 1.0), d in unit_vector(), s in 0.0f32..10.0) {
        let o = c + p.clamp_length_max(0.95) * r;
        let t = ray_sphere(o, d, c, r);
        prop_assert!(t.x <= 0.0 && t.y >= 0.0);
        let len = sphere_path_length(o, d, c, r, s);
        prop_assert!((len - t.y.min(s)).abs() <= tol(o, c, r));
        prop_assert!(len <= 2.0 * r + tol(o, c, r));
        prop_assert!(s <= 0.0 || len > 0.0);
    }

    /// A ray tangent to the sphere sees (almost) nothing, and nothing non-finite.
    #[test]
    fn sphere_tangent_ray(c in vec3_in(-5.0, 5.0), r in 0.05f32..3.0, n in unit_vector(), d0 in unit_vector(), back in 0.0f32..10.0, s in scene_distance()) {
        let d = (d0 - n * d0.dot(n)).normalize_or(n.any_orthonormal_vector());
        let touch = c + n * r;
        let o = touch - d * back;
        let len = sphere_path_length(o, d, c, r, s);
        prop_assert!(len.is_finite() && len >= 0.0);
        // Two roundings make a tangent ray cut a thin chord. The origin and the difference
        // o - c are rounded in absolute coordinates, which moves the ray up to about
        // delta = 4 eps (|o| + |c| + back) toward the centre: a chord of 2 sqrt(2 r delta).
        // The discriminant b^2 - (|o - c|^2 - r^2) cancels two numbers of size back^2, and
        // |d| may be 1 + eps: 5 to 6 ulps of back^2, below 8 eps |o - c|^2. (A sphere far from
        // the origin with a small radius makes the first term dominate, a long `back` the
        // second: a reviewer's 50 million cases of 4 eps failed 34 times, 8 eps none of 100
        // million, the worst at 0.79 of the bound.)
        let eps = f32::EPSILON;
        let delta = 4.0 * eps * (o.length() + c.length() + back);
        let bound = 2.0 * (2.0 * r * delta + 8.0 * eps * (o - c).length_squared()).sqrt();
        prop_assert!(len <= bound, "tangent length {len} above {bound}");
    }

    /// The clipping interval: inside [0, t_back - t_front], monotone in the scene.
    #[test]
    fn visible_length_bounds(a in -10.0f32..10.0, b in -10.0f32..10.0, s in scene_distance(), s2 in 0.0f32..20.0) {
        let (front, back) = (a.min(b), a.max(b));
        let len = visible_length(front, back, s);
        prop_assert!(len >= 0.0 && len <= back - front);
        let (lo, hi) = (s.min(s2), s.max(s2));
        prop_assert!(visible_length(front, back, lo) <= visible_length(front, back, hi));
        if s <= front.max(0.0) { prop_assert_eq!(len, 0.0); }
    }

    /// Billboard half thicknesses are in [0, 1] and finite everywhere, including exactly on
    /// and just across the disc's edge (where the sphere profile takes sqrt of ~0).
    #[test]
    fn billboard_edges_are_finite(angle in 0.0f32..std::f32::consts::TAU, scale in prop_oneof![Just(1.0f32), near_one(), 0.0f32..2.0], tex in -1.0f32..2.0) {
        let uv = Vec2::new(angle.cos(), angle.sin()) * scale;
        for kind in [PRIMITIVE_CONSTANT, PRIMITIVE_LINEAR, PRIMITIVE_SPHERE, PRIMITIVE_TEXTURE] {
            let h = half_thickness(kind, uv, tex);
            prop_assert!(h.is_finite() && (0.0..=1.0).contains(&h), "kind {kind} uv {uv} h {h}");
        }
        let hs = half_thickness_sphere(uv);
        prop_assert!(hs.is_finite() && (0.0..=1.0).contains(&hs));
        if uv.length() > 1.0 + 1e-6 {
            prop_assert_eq!(half_thickness_constant(uv), 0.0);
            prop_assert_eq!(half_thickness_linear(uv), 0.0);
            prop_assert_eq!(hs, 0.0);
        }
    }

    /// Billboard primitives: [0, 2h], monotone, zero behind a closer surface, 2h when the
    /// surface is behind and the volume in front of the eye.
    #[test]
    fn billboard_length_properties(t_plane in -1.0f32..20.0, h in 0.0f32..3.0, s in scene_distance(), s2 in 0.0f32..25.0) {
        let len = billboard_path_length(t_plane, h, s);
        prop_assert!(len.is_finite() && len >= 0.0 && len <= 2.0 * h + 1e-5);
        let (lo, hi) = (s.min(s2), s.max(s2));
        prop_assert!(billboard_path_length(t_plane, h, lo) <= billboard_path_length(t_plane, h, hi));
        if s <= (t_plane - h).max(0.0) { prop_assert_eq!(len, 0.0); }
        if t_plane - h >= 0.0 && s >= t_plane + h {
            prop_assert!((len - 2.0 * h).abs() <= 1e-5 * (1.0 + t_plane), "len {len} 2h {}", 2.0 * h);
        }
    }

    /// Full billboard primitives on rays through the billboard quad, its edge included: finite,
    /// non-negative, at most 2R (billboards) and at most the chord (sphere).
    #[test]
    fn primitives_on_billboard_rays((o, _, c, r) in ray_and_sphere(), corner in (-1.1f32..1.1, -1.1f32..1.1), edge in 0u8..3, s in scene_distance(), tex in 0.0f32..1.0) {
        let to_eye = o - c;
        prop_assume!(to_eye.length() > 1e-3);
        let normal = to_eye.normalize();
        let right = normal.any_orthonormal_vector();
        let up = normal.cross(right);
        let mut q = Vec2::new(corner.0, corner.1);
        if edge == 0 { q = q.normalize_or(Vec2::X); } // exactly on the disc's edge
        let p = c + (right * q.x + up * q.y) * r;
        let d = (p - o).normalize();
        for prim in [Primitive::Constant, Primitive::Linear, Primitive::Sphere, Primitive::Texture] {
            let len = primitive_path_length(prim, o, d, c, r, [right, up, normal], tex, s);
            prop_assert!(len.is_finite() && len >= 0.0, "{prim:?} {len}");
            prop_assert!(len <= 2.0 * r + tol(o, c, r), "{prim:?} {len} > 2R");
        }
    }

    /// Opacity functions: in [0, 1], 0 at 0, `density` at one metre, monotone.
    #[test]
    fn opacity_properties(kind in opacity_kind(), a in 0.0f32..10.0, b in 0.0f32..10.0, density in 0.0f32..3.0) {
        let (lo, hi) = (a.min(b), a.max(b));
        let (flo, fhi) = (opacity_from_length(kind, lo, density), opacity_from_length(kind, hi, density));
        prop_assert!((0.0..=1.0).contains(&flo) && flo <= fhi);
        prop_assert_eq!(opacity_from_length(kind, 0.0, density), 0.0);
        prop_assert!((opacity_from_length(kind, 1.0, density) - density.min(1.0)).abs() <= 1e-6);
        prop_assert_eq!(opacity_from_length(kind, -a, density), 0.0);
    }

    /// Slices: each share is in [0, 1], and the slices from the front up to any slice
    /// composite to the opacity of the path to the far side of its slab; all of them to the
    /// opacity of the whole thickness.
    #[test]
    fn slice_shares_composite_to_the_path(kind in opacity_kind(), density in 0.0f32..2.0, h in 0.0f32..2.0, r in 0.1f32..2.0, n in prop_oneof![Just(5u32), Just(9), Just(19), Just(39), Just(79), 1u32..100], obliquity in 1.0f32..3.0) {
        let h = h.min(r);
        let delta = 2.0 * r / n as f32;
        let mut transmitted = 1.0f32;
        for k in 0..n {
            let near = -r + k as f32 * delta;
            let far = near + delta;
            let a = slice_alpha(kind, density, h, near, far, obliquity);
            prop_assert!((0.0..=1.0).contains(&a), "slice {k} alpha {a}");
            transmitted *= 1.0 - a;
            let l_far = (far + h).clamp(0.0, 2.0 * h) * obliquity;
            let want = opacity_from_length(kind, l_far, density);
            prop_assert!((1.0 - transmitted - want).abs() <= 2e-4, "slice {k}: stack {} want {want}", 1.0 - transmitted);
        }
        let whole = opacity_from_length(kind, 2.0 * h * obliquity, density);
        prop_assert!((1.0 - transmitted - whole).abs() <= 2e-4);
    }
}

/// Hand-picked edge cases: zero-size and degenerate inputs stay finite.
#[test]
fn degenerate_inputs_are_finite() {
    let o = Vec3::new(0.0, 0.0, 5.0);
    let c = Vec3::ZERO;
    // Eye exactly at the centre of the sphere.
    assert!((sphere_path_length(c, Vec3::X, c, 1.0, 10.0) - 1.0).abs() < 1e-6);
    // Ray parallel to the billboard plane: t_plane = -1, nothing visible.
    let b = billboard_coords(o, Vec3::X, c, Vec3::X, Vec3::Y, Vec3::Z, 1.0);
    assert_eq!(b.z, -1.0);
    assert_eq!(billboard_path_length(b.z, 1.0, 100.0), 0.0);
    // Zero thickness slices.
    assert_eq!(slice_alpha(OPACITY_LOG, 0.6, 0.0, -0.1, 0.1, 1.0), 0.0);
    // Scene exactly at the front of the sphere.
    assert_eq!(sphere_path_length(o, -Vec3::Z, c, 1.0, 4.0), 0.0);
    assert!((sphere_path_length(o, -Vec3::Z, c, 1.0, 5.0) - 1.0).abs() < 1e-5);
}
