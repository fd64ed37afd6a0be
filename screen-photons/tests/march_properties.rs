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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// The line march returns the first sample (smallest t) at which some layer lies within
    /// the tolerance of the ray, the layer nearest in distance there; no earlier sample has a
    /// layer within the tolerance. The DDA returns the brute-force first sample of the
    /// thickness test, stopping there.
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
            for k in 0..h.step {
                prop_assert!(march::test_sample(&ldi, &eye, &seg, k, Test::Tolerance(TOLERANCE), st).is_none());
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
        prop_assert!(seg.t0 >= 0.0 && seg.t0 < seg.t1 && seg.t1 <= 50.0);
        for p in [seg.p0, seg.p1] {
            prop_assert!(p.x >= -1e-2 && p.x <= W as f32 + 1e-2 && p.y >= -1e-2 && p.y <= H as f32 + 1e-2, "{}", p);
        }
        for k in 0..seg.steps {
            let (x, y) = seg.pixel(&eye, k);
            prop_assert!(x < W && y < H);
            let t = seg.t_at(seg.fraction(k));
            prop_assert!(t >= seg.t0 - 1e-3 * seg.t1.abs().max(1.0) && t <= seg.t1 + 1e-3 * seg.t1.abs().max(1.0));
        }
    }

    /// A ray refracted into one glass sphere finds its way out in layer 1 (the monotone rule
    /// holds for a convex refractor), within a sample's travel of the exact exit.
    #[test]
    fn a_convex_refractor_keeps_the_layers_monotone(
        x in 14u32..34, y in 10u32..26, ior in 1.1f32..2.4,
    ) {
        let eye = eye();
        let glass = [Sphere { centre: Vec3::ZERO, radius: 1.2, object: 0, specular: true }];
        let ldi = Ldi::of_spheres(&eye, 4, &glass);
        let front = ldi.get(x, y, 0);
        prop_assume!(front.distance > 0.0);
        let view = eye.pixel_ray(x, y);
        let p = eye.position + view * front.distance;
        let dir = gpu::prelude::refract_dir(view, front.normal, 1.0 / ior).truncate();
        let exact = gpu::prelude::ray_sphere(p, dir, Vec3::ZERO, 1.2).y;
        let seg = march::clip(&eye, p, dir, (0.0, 12.0), 2.0 * TOLERANCE).unwrap();
        prop_assert!(march::monotone_holds(&ldi, &eye, &seg, 1, THICKNESS, TOLERANCE));
        let hit = march::march_monotone(&ldi, &eye, &seg, 1).expect("an exit");
        let step = (seg.t1 - seg.t0) / seg.steps as f32;
        prop_assert!((hit.t - exact).abs() <= 2.0 * step + 0.05, "t {} exact {} step {}", hit.t, exact, step);
    }
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
