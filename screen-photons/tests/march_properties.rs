//! Property tests of the screen-space march (`screen_photons::march`, the twin of
//! `shaders/ldi.wgsl`) over exact LDIs of random spheres.

use glam::Vec3;
use proptest::prelude::*;
use scene::Camera;
use screen_photons::march::{self, Eye, Ldi, RayState, Side, Sphere, Test};
use testkit::strategies::{unit_vector, vec3_in};

const W: u32 = 48;
const H: u32 = 36;
const TOLERANCE: f32 = 0.03;
const THICKNESS: f32 = 0.1;

fn eye() -> Eye {
    let cam = Camera {
        eye: Vec3::new(0.0, 0.5, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    Eye {
        view_proj: cam.view_proj(W, H),
        position: cam.eye,
        width: W,
        height: H,
    }
}

/// One to four spheres around the origin, the first specular (glass), the others diffuse.
fn spheres() -> impl Strategy<Value = Vec<Sphere>> {
    prop::collection::vec((vec3_in(-1.5, 1.5), 0.2f32..1.0), 1..5).prop_map(|list| {
        list.into_iter()
            .enumerate()
            .map(|(i, (centre, radius))| Sphere {
                centre,
                radius,
                object: i as u32,
                specular: i == 0,
            })
            .collect()
    })
}

fn state(side: Side) -> RayState {
    RayState {
        side,
        t_skip: TOLERANCE,
    }
}

fn sides() -> impl Strategy<Value = Side> {
    prop_oneof![Just(Side::Outside), Just(Side::Inside), Just(Side::Any)]
}

/// A glass sphere of radius 1.2 at the origin and its exact LDI (4 layers).
const GLASS_RADIUS: f32 = 1.2;
fn glass_sphere_ldi(eye: &Eye) -> Ldi {
    let glass = [Sphere {
        centre: Vec3::ZERO,
        radius: GLASS_RADIUS,
        object: 0,
        specular: true,
    }];
    Ldi::of_spheres(eye, 4, &glass)
}

/// How squarely the glass sphere's surface point `p` faces the eye (cosine), and whether it
/// projects inside 95% of the screen.
fn facing_and_on_screen(eye: &Eye, p: Vec3) -> (f32, bool) {
    let c = eye.view_proj * p.extend(1.0);
    let facing = p.normalize().dot((eye.position - p).normalize());
    (facing, c.x.abs() < 0.95 * c.w && c.y.abs() < 0.95 * c.w)
}

/// `hit` is the first sample past the exact crossing at `exact` (samples are even on the
/// screen, not along the ray), give or take what the depth changes over a pixel (the LDI
/// holds pixel centres' depths; a pixel is about 0.13 wide at the glass sphere).
fn assert_first_sample_past(seg: &march::Segment, hit: &march::Hit, exact: f32, ray: u32) {
    let before = seg.t_at(seg.fraction(hit.step.max(1) - 1));
    let slack = 0.15;
    assert!(
        before - slack <= exact && exact <= hit.t + slack,
        "ray {ray}: crossing {exact} not in [{before}, {}]",
        hit.t
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// The line march returns a sample of the first run of samples at which some layer lies
    /// within the tolerance of the ray (the layer nearest in distance there): the run's first,
    /// or a later one reached while the gap shrinks. The DDA returns the brute-force first
    /// sample of the thickness test, stopping there.
    #[test]
    fn the_first_hit_is_the_nearest_sample_within_the_test(
        spheres in spheres(),
        origin in vec3_in(-2.0, 2.0),
        dir in unit_vector(),
        side in sides(),
    ) {
        let eye = eye();
        let ldi = Ldi::of_spheres(&eye, 6, &spheres);
        let Some(seg) = march::clip(&eye, origin, dir, (0.0, 12.0), 2.0 * TOLERANCE) else {
            return Ok(());
        };
        let st = state(side);
        let (lines, tested) = march::march_lines(&ldi, &eye, &seg, TOLERANCE, st);
        prop_assert_eq!(tested, seg.steps);
        prop_assert_eq!(lines, march::first_hit_brute(&ldi, &eye, &seg, Test::Tolerance(TOLERANCE), st));
        if let Some(h) = lines {
            let texel = ldi.get(h.x, h.y, h.layer);
            let d = seg.distance(&eye, h.t);
            prop_assert!((d - texel.distance).abs() < TOLERANCE);
            prop_assert!(march::side_ok(&texel, dir, side));
            // The first run of hits starts at `first`; the march moved on from there only
            // while the gap shrank, and stopped where it does not shrink any more.
            let gap_at = |k: u32| {
                march::test_sample(&ldi, &eye, &seg, k, Test::Tolerance(TOLERANCE), st).map(|o| {
                    (seg.distance(&eye, o.t) - ldi.get(o.x, o.y, o.layer).distance).abs()
                })
            };
            let first = (0..seg.steps).find(|&k| gap_at(k).is_some()).unwrap();
            prop_assert!(first <= h.step);
            for k in first..h.step {
                prop_assert!(gap_at(k + 1).unwrap() < gap_at(k).unwrap());
            }
            if h.step + 1 < seg.steps {
                prop_assert!(gap_at(h.step + 1).is_none_or(|g| g >= gap_at(h.step).unwrap()));
            }
            // No other layer at that sample is nearer in distance and also allowed.
            for l in 0..ldi.layers {
                let other = ldi.get(h.x, h.y, l);
                if other.distance > 0.0 && march::side_ok(&other, dir, side) {
                    prop_assert!((d - other.distance).abs() >= (d - texel.distance).abs());
                }
            }
        }
        let (dda, steps) = march::march_dda(&ldi, &eye, &seg, THICKNESS, st);
        prop_assert_eq!(dda, march::first_hit_brute(&ldi, &eye, &seg, Test::Thickness(THICKNESS), st));
        prop_assert_eq!(steps, dda.map_or(seg.steps, |h| h.step + 1));
    }

    /// Every sample of a clipped segment lies on the screen, the count stays within the row
    /// buffer's width, and the ends are inside the view frustum: a ray leaving the screen ends
    /// there, one wholly outside it is not marched at all.
    #[test]
    fn rays_leaving_the_screen_terminate(
        origin in vec3_in(-8.0, 8.0),
        dir in unit_vector(),
        spacing in 0.01f32..1.0,
    ) {
        let eye = eye();
        let Some(seg) = march::clip(&eye, origin, dir, (0.0, 50.0), spacing) else {
            // Wholly outside: no point of the ray projects inside the frustum.
            for i in 0..=200 {
                let p = origin + dir * (i as f32 * 0.25);
                let c = eye.view_proj * p.extend(1.0);
                let inside = c.w > 0.0 && c.x.abs() < c.w * 0.999 && c.y.abs() < c.w * 0.999
                    && c.z > 1e-3 * c.w && c.z < c.w * 0.999;
                prop_assert!(!inside, "point {} of a rejected ray is in view", p);
            }
            return Ok(());
        };
        prop_assert!(seg.steps >= 1 && seg.steps <= march::max_steps(&eye));
        prop_assert!(seg.t_start >= 0.0 && seg.t_start < seg.t_end && seg.t_end <= 50.0);
        for p in [seg.p_start, seg.p_end] {
            prop_assert!(p.x >= -1e-2 && p.x <= W as f32 + 1e-2 && p.y >= -1e-2 && p.y <= H as f32 + 1e-2, "{}", p);
        }
        for k in 0..seg.steps {
            let (x, y) = seg.pixel(&eye, k);
            prop_assert!(x < W && y < H);
            let t = seg.t_at(seg.fraction(k));
            prop_assert!(t >= seg.t_start - 1e-3 * seg.t_end.abs().max(1.0) && t <= seg.t_end + 1e-3 * seg.t_end.abs().max(1.0));
        }
    }

    /// A ray refracted into one glass sphere finds its way out in layer 1 (the monotone rule
    /// holds for a convex refractor), within a sample's travel of the exact exit.
    #[test]
    fn a_convex_refractor_keeps_the_layers_monotone(
        x in 14u32..34, y in 10u32..26, ior in 1.1f32..2.4,
    ) {
        let eye = eye();
        let ldi = glass_sphere_ldi(&eye);
        let front = ldi.get(x, y, 0);
        prop_assume!(front.distance > 0.0);
        let view = eye.pixel_ray(x, y);
        let p = eye.position + view * front.distance;
        let dir = gpu::prelude::refract_dir(view, front.normal, 1.0 / ior).truncate();
        let exact = gpu::prelude::ray_sphere(p, dir, Vec3::ZERO, GLASS_RADIUS).y;
        let seg = march::clip(&eye, p, dir, (0.0, 12.0), 2.0 * TOLERANCE).unwrap();
        prop_assert!(march::monotone_holds(&ldi, &eye, &seg, 1, THICKNESS, TOLERANCE));
        let hit = march::march_monotone(&ldi, &eye, &seg, 1, TOLERANCE).expect("an exit");
        let step = (seg.t_end - seg.t_start) / seg.steps as f32;
        prop_assert!((hit.t - exact).abs() <= 2.0 * step + 0.05, "t {} exact {} step {}", hit.t, exact, step);
    }
}

/// The other half of the paper's stop rule: a ray inside a glass sphere that leaves through
/// the half facing the eye never passes behind layer 1; it comes out in front of layer 0, and
/// the monotone march stops there, in layer 0, at the first sample past the exact exit.
#[test]
fn a_ray_leaving_through_the_front_stops_at_the_current_layer() {
    let eye = eye();
    let ldi = glass_sphere_ldi(&eye);
    let mut rays = 0;
    for i in 0..200 {
        // From a point inside, towards a point on the front half (seen from the eye).
        let a = i as f32 * 0.7;
        let origin = Vec3::new(0.5 * a.cos(), 0.4 * (1.3 * a).sin(), -0.6);
        let to_eye = (eye.position - Vec3::ZERO).normalize();
        let aim = (to_eye + Vec3::new((2.1 * a).cos(), (1.7 * a).sin(), 0.0) * 0.8).normalize();
        let dir = (aim * GLASS_RADIUS - origin).normalize();
        let exact = gpu::prelude::ray_sphere(origin, dir, Vec3::ZERO, GLASS_RADIUS).y;
        let exit = origin + dir * exact;
        let Some(seg) = march::clip(&eye, origin, dir, (0.0, 12.0), 2.0 * TOLERANCE) else {
            continue;
        };
        // Only exits in view, on the half facing the eye.
        let (facing, on_screen) = facing_and_on_screen(&eye, exit);
        if !on_screen || facing < 0.3 {
            continue;
        }
        rays += 1;
        let hit = march::march_monotone(&ldi, &eye, &seg, 1, TOLERANCE).expect("an exit");
        assert_eq!(hit.layer, 0, "ray {i}: stopped in layer {}", hit.layer);
        assert_first_sample_past(&seg, &hit, exact, i);
    }
    assert!(rays > 50, "{rays}");
}

/// Two glass spheres, a small one in front of a large one: rays refracted into the large one
/// that bend behind the small one meet the small one's back in layer 1, not their own exit.
/// The monotone rule reads the wrong layer there, and `monotone_holds` counts it.
#[test]
fn monotone_layer_violations_are_counted() {
    let eye = eye();
    let glass = [
        Sphere {
            centre: Vec3::new(0.0, 0.0, 1.5),
            radius: 0.35,
            object: 0,
            specular: true,
        },
        Sphere {
            centre: Vec3::new(0.3, 0.0, -1.0),
            radius: 1.4,
            object: 1,
            specular: true,
        },
    ];
    let ldi = Ldi::of_spheres(&eye, 6, &glass);
    let single = Ldi::of_spheres(&eye, 6, &glass[1..]);
    let (mut violations, mut rays, mut single_violations) = (0, 0, 0);
    for y in 0..H {
        for x in 0..W {
            let front = ldi.get(x, y, 0);
            if front.distance <= 0.0 || front.object != 1 {
                continue;
            }
            let view = eye.pixel_ray(x, y);
            let p = eye.position + view * front.distance;
            let dir = gpu::prelude::refract_dir(view, front.normal, 1.0 / 1.8).truncate();
            let Some(seg) = march::clip(&eye, p, dir, (0.0, 12.0), 2.0 * TOLERANCE) else {
                continue;
            };
            rays += 1;
            violations += !march::monotone_holds(&ldi, &eye, &seg, 1, THICKNESS, TOLERANCE) as u32;
            single_violations +=
                !march::monotone_holds(&single, &eye, &seg, 1, THICKNESS, TOLERANCE) as u32;
        }
    }
    println!("{violations} of {rays} rays violate the monotone-layer assumption");
    assert!(rays > 100);
    assert!(violations > 0, "no ray crossed behind the small sphere");
    assert_eq!(single_violations, 0, "the large sphere alone is convex");
}

/// Where a sample spans much less than the tolerance, the line march's hit is the sample
/// nearest the surface, not the first sample within the tolerance (which lies up to a
/// tolerance before it): over rays into a glass sphere seen on a fine screen, the hit is within
/// two samples' travel of the exact crossing, and it is for every ray.
#[test]
fn the_line_march_hits_near_the_crossing_on_a_fine_screen() {
    let cam = Camera {
        eye: Vec3::new(0.0, 0.5, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let (w, h) = (256, 192);
    let eye = Eye {
        view_proj: cam.view_proj(w, h),
        position: cam.eye,
        width: w,
        height: h,
    };
    let glass = [Sphere {
        centre: Vec3::ZERO,
        radius: 1.0,
        object: 0,
        specular: true,
    }];
    let ldi = Ldi::of_spheres(&eye, 4, &glass);
    let tolerance = 0.1;
    let st = RayState {
        side: Side::Outside,
        t_skip: 0.0,
    };
    let mut rng = 0x2545_f491_u32;
    let mut unit = || {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        rng as f32 / u32::MAX as f32
    };
    let (mut rays, mut far_first, mut worst) = (0, 0, 0.0f32);
    for _ in 0..400 {
        // From a point around the sphere towards a point on its front half.
        let origin = Vec3::new(unit() * 6.0 - 3.0, unit() * 4.0 - 2.0, unit() * 3.0 - 1.0);
        let target = Vec3::new(unit() - 0.5, unit() - 0.5, 0.5).normalize() * 0.9;
        let dir = (target - origin).normalize();
        let exact = gpu::prelude::ray_sphere(origin, dir, Vec3::ZERO, 1.0).x;
        if !(exact > 0.2) || origin.length() < 1.05 {
            continue;
        }
        let Some(seg) = march::clip(&eye, origin, dir, (0.0, 12.0), 2.0 * tolerance) else {
            continue;
        };
        let Some(hit) = march::march_lines(&ldi, &eye, &seg, tolerance, st).0 else {
            continue;
        };
        let step = (seg.t_end - seg.t_start) / seg.steps as f32;
        let first = (0..seg.steps)
            .find_map(|k| march::test_sample(&ldi, &eye, &seg, k, Test::Tolerance(tolerance), st))
            .unwrap();
        rays += 1;
        worst = worst.max((hit.t - exact).abs() / step);
        far_first += ((first.t - exact).abs() > 2.0 * step) as u32;
    }
    println!(
        "{rays} rays; worst miss {worst:.2} samples; the first sample of the run over 2 samples off for {far_first}"
    );
    assert!(rays > 100);
    assert!(worst <= 2.0, "a hit {worst} samples from the crossing");
    // The test has teeth: the run's first sample would fail it for many rays.
    assert!(far_first > rays / 4, "{far_first} of {rays}");
}

/// Section 5's in-out test: shadow rays through a solid sphere whose faces' tolerance windows
/// the samples step over (a tolerance of 1e-5 m) are still stopped, inside the sphere, by the
/// in-out test over the layer pair (front face, back face); rays passing clear of it are not.
/// The tolerance test alone stops almost none of them: the in-out test is what finds them.
#[test]
fn the_in_out_test_stops_shadow_rays_inside_a_solid() {
    let eye = eye();
    let solid = [Sphere {
        centre: Vec3::new(0.2, -0.1, 0.0),
        radius: 1.0,
        object: 0,
        specular: false,
    }];
    let ldi = Ldi::of_spheres(&eye, 4, &solid);
    let tolerance = 1e-5;
    let (mut through, mut stopped, mut by_tolerance, mut clear, mut false_hits) = (0, 0, 0, 0, 0);
    for i in 0..300 {
        let a = i as f32 * 0.37;
        let origin = Vec3::new(2.5 * a.cos(), 1.5 * (0.7 * a).sin(), -1.5 + (1.3 * a).cos());
        let aim =
            solid[0].centre + Vec3::new((1.9 * a).sin(), (2.3 * a).cos(), (0.9 * a).sin()) * 1.4;
        let dir = (aim - origin).normalize();
        let Some(seg) = march::clip(&eye, origin, dir, (0.0, 12.0), 0.5) else {
            continue;
        };
        let chord = gpu::prelude::ray_sphere(origin, dir, solid[0].centre, 1.0);
        let hit = march::march_shadow(&ldi, &eye, &seg, tolerance, 0.0);
        let any = RayState {
            side: Side::Any,
            t_skip: 0.0,
        };
        let tolerance_only = (0..seg.steps).any(|k| {
            march::test_sample(&ldi, &eye, &seg, k, Test::Tolerance(tolerance), any).is_some()
        });
        // Samples inside the sphere, kept off its faces by a pixel's footprint (0.15).
        let inside = (0..seg.steps)
            .map(|k| seg.t_at(seg.fraction(k)))
            .filter(|&t| chord.x > 0.0 && t > chord.x + 0.15 && t < chord.y - 0.15)
            .count();
        let closest = (solid[0].centre - origin).dot(dir).max(0.0);
        let miss = (origin + dir * closest - solid[0].centre).length();
        if inside >= 2 {
            through += 1;
            stopped += hit.is_some_and(|h| h.t >= chord.x - 0.15 && h.t <= chord.y + 0.15) as u32;
            by_tolerance += tolerance_only as u32;
        } else if miss > 1.2 {
            clear += 1;
            false_hits += hit.is_some() as u32;
        }
    }
    println!(
        "{through} rays through: {stopped} stopped ({by_tolerance} by the tolerance test alone); \
         {clear} clear: {false_hits} stopped"
    );
    assert!(
        through > 50 && clear > 30,
        "{through} through, {clear} clear"
    );
    assert_eq!(stopped, through);
    assert_eq!(false_hits, 0);
    assert!(by_tolerance * 4 < through, "{by_tolerance} of {through}");
}

/// A ray reflected inside a glass sphere (total internal reflection at its back) is still
/// between layers 0 and 1: marched between them it stops at its next crossing, the first
/// sample past it (give or take a pixel's depth change). The paper's numbering (the third
/// intersection in layer 2) would read layers 1 and 2: the reflected ray turns towards the
/// eye, so it is in front of layer 1 at its first tested sample and stops there.
#[test]
fn a_ray_reflected_inside_stays_between_the_same_layers() {
    let eye = eye();
    let ldi = glass_sphere_ldi(&eye);
    let (mut rays, mut at_once, mut lost) = (0, 0, 0);
    for i in 0..200 {
        let a = i as f32 * 0.61;
        // A point on the back half, a ray arriving from inside, reflected there.
        let away = (Vec3::ZERO - eye.position).normalize();
        let n = (away + Vec3::new(a.cos(), (1.7 * a).sin(), 0.0) * 0.7).normalize();
        let p = n * GLASS_RADIUS;
        let incoming = (p - Vec3::new(0.3 * (2.3 * a).sin(), 0.3 * a.cos(), 0.0)).normalize();
        let dir = incoming - 2.0 * incoming.dot(n) * n;
        let exact = gpu::prelude::ray_sphere(p, dir, Vec3::ZERO, GLASS_RADIUS).y;
        let Some(seg) = march::clip(&eye, p, dir, (0.0, 12.0), 2.0 * TOLERANCE) else {
            continue;
        };
        // Away from the silhouette (the crossing projects within 0.87 of the disc's radius:
        // over a pixel inside it), where the ray can cross out of the disc between samples.
        let (facing, on_screen) = facing_and_on_screen(&eye, p + dir * exact);
        if exact < 0.3 || facing.abs() < 0.5 || !on_screen {
            continue;
        }
        rays += 1;
        let Some(hit) = march::march_monotone(&ldi, &eye, &seg, 1, TOLERANCE) else {
            lost += 1;
            continue;
        };
        assert_first_sample_past(&seg, &hit, exact, i);
        let numbered = march::march_monotone(&ldi, &eye, &seg, 2, TOLERANCE);
        at_once += numbered.is_some_and(|h| h.t < exact * 0.5) as u32;
    }
    println!(
        "{rays} reflected rays, {lost} lost; the paper's numbering stops {at_once} of them \
         half-way or sooner"
    );
    assert!(rays > 50, "{rays}");
    assert_eq!(lost, 0, "{lost} of {rays} rays found no crossing");
    assert!(at_once * 2 > rays, "{at_once} of {rays}");
}
