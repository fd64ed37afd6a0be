//! The light pass of the reference: its camera normalisation (light tracing of direct light
//! must reproduce the eye pass's direct lighting) and its energy (the power a glass sphere
//! focuses onto the floor must match the Fresnel transmission of the sphere integrated in
//! closed form).

use glam::{Mat4, Vec2, Vec3};
use gpu::prelude::{fresnel_dielectric, ray_sphere, reflect_dir, refract_dir};
use scene::mesh::{quad, uv_sphere};
use scene::{Camera, CameraPath, Light, Material, Object, Roles, Scene};
use truth::reference::{PhotonSetup, ReferenceOptions, light_trace, render};

fn scene_with(objects: Vec<Object>, light: Vec3, intensity: Vec3, camera: Camera) -> Scene {
    Scene {
        name: "photons".into(),
        objects,
        textures: vec![],
        lights: vec![Light {
            name: "light".into(),
            position: light,
            intensity,
            kind: scene::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

fn floor(half: f32, albedo: Vec3) -> Object {
    Object::new(
        "floor",
        quad(
            Vec3::new(-half, 0.0, half),
            Vec3::X * 2.0 * half,
            Vec3::NEG_Z * 2.0 * half,
            Vec2::ONE,
        ),
        Material::Diffuse {
            albedo,
            texture: None,
            cutout: None,
        },
        Mat4::IDENTITY,
    )
}

/// Checks the importance W = 1 / (A_pix cos^3 theta_c) of the light-to-camera connection.
///
/// A plane lit directly by a point light, rendered twice: by the eye pass (direct lighting,
/// exact) and by the light pass with zero-bounce landings allowed (photons emitted over the
/// plane's bounding cone, here the whole sphere because the light is inside it). A wide
/// field of view makes cos^3 theta_c fall to ~0.5 in the corners, so a wrong power of the
/// cosine or a wrong pixel area shows up in the blocks (cos theta_c is 0.71 in the corners,
/// so cos^4 instead of cos^3 would be off by 29% there). Noise: over seeds 1-6 the 16x16
/// blocks were within 3.2% (the far, top row is the noisiest) and the whole image within
/// 0.4%; tolerances are 6% per block and 1% on the whole image.
#[test]
fn light_tracing_matches_direct_lighting() {
    light_tracing_matches_direct_lighting_for(Camera {
        eye: Vec3::new(0.0, 3.0, 2.5),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 70.0,
        orthographic: None,
    });
}

/// The same check for an orthographic camera, whose importance is `1 / A_pix` with the
/// pixel's area in the world, whatever the distance (`scene::Film::importance`): a missing or
/// extra `cos^3` or `d^2` would be off by a factor of 2 or more here (the plane is 2.4 to 5.4 m
/// from the view's plane, seen at 50 degrees from its normal).
#[test]
fn light_tracing_matches_direct_lighting_through_an_orthographic_camera() {
    light_tracing_matches_direct_lighting_for(Camera {
        eye: Vec3::new(0.0, 3.0, 2.5),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 45.0,
        orthographic: Some(1.5),
    });
}

fn light_tracing_matches_direct_lighting_for(camera: Camera) {
    let scene = scene_with(
        vec![floor(10.0, Vec3::new(0.5, 0.4, 0.3))],
        Vec3::new(0.3, 1.5, 0.2),
        Vec3::new(5.0, 5.0, 5.0),
        camera,
    );
    let size = 64;
    let direct = render(
        &scene,
        &camera,
        0.0,
        size,
        size,
        &ReferenceOptions {
            photons: 0,
            ..Default::default()
        },
    );
    let opts = ReferenceOptions {
        photons: 2_000_000,
        ..Default::default()
    };
    let setup = PhotonSetup {
        targets: vec![0],
        min_specular_bounces: 0,
    };
    let lt = light_trace(&scene, &camera, 0.0, size, size, &opts, &setup);
    assert!(
        direct.object_ids.iter().all(|&i| i == 0),
        "the plane must fill the view"
    );

    let block = 16;
    let (mut sum_d, mut sum_l) = (Vec3::ZERO, Vec3::ZERO);
    let mut worst = 0.0f32;
    for by in 0..size / block {
        for bx in 0..size / block {
            let (mut d, mut l) = (Vec3::ZERO, Vec3::ZERO);
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let p = direct.image.get(x, y);
                    d += Vec3::new(p[0], p[1], p[2]);
                    l += lt.radiance[(y * size + x) as usize];
                }
            }
            let rel = ((l - d) / d).abs().max_element();
            worst = worst.max(rel);
            assert!(
                rel < 0.06,
                "block ({bx}, {by}): light tracing {l:?} vs direct {d:?}"
            );
            sum_d += d;
            sum_l += l;
        }
    }
    let rel = ((sum_l - sum_d) / sum_d).abs().max_element();
    println!("whole image: light tracing / direct - 1 = {rel:.2e}; worst 16x16 block {worst:.2e}");
    assert!(
        rel < 0.01,
        "whole image: light tracing {sum_l:?} vs direct {sum_d:?}"
    );
    // Half the photons leave upward; the rest land on the plane (nothing else to hit).
    assert!(lt.photons_stored > 200_000);
}

const R: f32 = 0.5;
const CENTER: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const LIGHT: Vec3 = Vec3::new(0.0, 4.0, 0.0);
const FLOOR_HALF: f32 = 100.0;

/// The fraction of a photon's power that reaches the floor from direction `d` at the
/// analytic sphere, following the full Fresnel tree to `max_depth` interactions, counting
/// only landings after at least one interaction (like the reference's caustic photons).
fn to_floor(o: Vec3, d: Vec3, depth: u32, max_depth: u32, ior: f32) -> f64 {
    let s = ray_sphere(o, d, CENTER, R);
    let t = if s.x <= s.y {
        if s.x > 1e-4 {
            Some(s.x)
        } else if s.y > 1e-4 {
            Some(s.y)
        } else {
            None
        }
    } else {
        None
    };
    let Some(t) = t else {
        // Leaves the sphere for good: lands if it goes down onto the floor.
        if depth == 0 || d.y >= 0.0 {
            return 0.0;
        }
        let p = o - d * (o.y / d.y);
        return (p.x.abs() <= FLOOR_HALF && p.z.abs() <= FLOOR_HALF) as u32 as f64;
    };
    if depth >= max_depth {
        return 0.0;
    }
    let p = o + d * t;
    let n = (p - CENTER) / R;
    let front = d.dot(n) < 0.0;
    let n = if front { n } else { -n };
    let eta_rel = if front { ior } else { 1.0 / ior };
    let f = fresnel_dielectric((-d).dot(n).clamp(0.0, 1.0), eta_rel) as f64;
    let refl = to_floor(
        p + n * 1e-4,
        reflect_dir(d, n).normalize(),
        depth + 1,
        max_depth,
        ior,
    );
    let tr = refract_dir(d, n, 1.0 / eta_rel);
    if tr.w == 0.0 || f >= 1.0 {
        return refl;
    }
    f * refl + (1.0 - f) * to_floor(p - n * 1e-4, tr.truncate(), depth + 1, max_depth, ior)
}

/// Energy of the caustic: a glass sphere (ior 1.5, radius 0.5) 1 m above a 200 m floor, a
/// point light 3 m above the sphere's centre.
///
/// Expected deposited power: `I * integral over the sphere's cone of T(w) dw`, where `T` is
/// the closed-form Fresnel tree above (the leading term is the two-interface transmittance
/// (1 - F1)(1 - F2); internal reflections and the outer reflections that go down add the
/// rest). The cone is axially symmetric, so `dw = 2 pi sin(a) da` and a midpoint rule over
/// the angle a from the axis does it.
///
/// Tolerance 1.5%: Monte Carlo noise is ~0.1% (400k photons, each landing with the same
/// power or not at all); the tessellated sphere (64 x 128) is inscribed in the analytic one
/// and its silhouette is up to 3e-4 m smaller, which removes ~0.1% of the disk, at its rim
/// where the transmittance is small anyway.
#[test]
fn caustic_power_matches_fresnel_transmission() {
    let ior = 1.5;
    let intensity = Vec3::new(10.0, 20.0, 30.0);
    let sphere = Object::new(
        "glass",
        uv_sphere(R, 64, 128),
        Material::glass(ior),
        Mat4::from_translation(CENTER),
    )
    .with_roles(Roles::REFRACTOR | Roles::CAUSTIC_CASTER);
    let camera = Camera {
        eye: Vec3::new(0.0, 3.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let scene = scene_with(
        vec![floor(FLOOR_HALF, Vec3::splat(0.5)), sphere],
        LIGHT,
        intensity,
        camera,
    );
    let opts = ReferenceOptions {
        photons: 400_000,
        max_depth: 8,
        ..Default::default()
    };
    let lt = light_trace(
        &scene,
        &camera,
        0.0,
        32,
        32,
        &opts,
        &PhotonSetup::caustics(&scene),
    );

    let dist = (CENTER - LIGHT).length();
    let a_max = (R / dist).asin();
    let steps = 20_000;
    let (mut expected, mut two_interfaces) = (0.0f64, 0.0f64);
    for i in 0..steps {
        let a = (i as f64 + 0.5) / steps as f64 * a_max as f64;
        let d = Vec3::new(a.sin() as f32, -a.cos() as f32, 0.0);
        let dw = 2.0 * std::f64::consts::PI * a.sin() * (a_max as f64 / steps as f64);
        expected += to_floor(LIGHT, d, 0, opts.max_depth, ior) * dw;
        // The leading term alone, for the report: (1 - F1)(1 - F2) at the two interfaces.
        let s = ray_sphere(LIGHT, d, CENTER, R);
        if s.x <= s.y {
            let n1 = (LIGHT + d * s.x - CENTER) / R;
            let c1 = (-d).dot(n1).clamp(0.0, 1.0);
            let f1 = fresnel_dielectric(c1, ior) as f64;
            let t = refract_dir(d, n1, 1.0 / ior).truncate();
            let p1 = LIGHT + d * s.x;
            let s2 = ray_sphere(p1 - n1 * 1e-4, t, CENTER, R);
            let n2 = -(p1 + t * s2.y - CENTER) / R;
            let f2 = fresnel_dielectric((-t).dot(n2).clamp(0.0, 1.0), 1.0 / ior) as f64;
            two_interfaces += (1.0 - f1) * (1.0 - f2) * dw;
        }
    }
    let solid_angle = 2.0 * std::f64::consts::PI * (1.0 - (a_max as f64).cos());
    println!(
        "sphere cone {solid_angle:.5} sr; mean transmission to the floor {:.5} \
         (two-interface term alone {:.5})",
        expected / solid_angle,
        two_interfaces / solid_angle
    );
    for c in 0..3 {
        let want = intensity[c] as f64 * expected;
        let got = lt.deposited[0][c] as f64;
        println!(
            "channel {c}: deposited {got:.5} W, expected {want:.5} W, ratio {:.5}",
            got / want
        );
        assert!(
            (got / want - 1.0).abs() < 0.015,
            "channel {c}: deposited {got} W, expected {want} W"
        );
    }
    // Everything was emitted into the sphere's bounding cone, I * Omega.
    let omega = lt.emitted[0].x as f64 / intensity.x as f64;
    assert!(
        (omega / solid_angle - 1.0).abs() < 1e-3,
        "cone {omega} sr vs {solid_angle} sr"
    );
    assert!(lt.photons_stored > 0, "the camera sees the caustic");
}

/// Caustic photons follow mirrors too, and two casters with overlapping cones are not counted
/// twice: the same mirror sphere split into two objects (its upper and lower halves, whose
/// bounding cones overlap) deposits the same power as the whole sphere.
#[test]
fn overlapping_caster_cones_are_not_double_counted() {
    let whole = uv_sphere(R, 32, 64);
    let half = |upper: bool| {
        let mut m = whole.clone();
        let rows = m.indices.len() / 3;
        let keep: Vec<u32> = (0..rows)
            .filter(|&t| {
                let c = (0..3)
                    .map(|k| m.positions[m.indices[3 * t + k] as usize].y)
                    .sum::<f32>();
                (c > 0.0) == upper
            })
            .flat_map(|t| m.indices[3 * t..3 * t + 3].to_vec())
            .collect();
        m.indices = keep;
        m
    };
    let camera = Camera {
        eye: Vec3::new(0.0, 3.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let place = Mat4::from_translation(CENTER);
    // A light off to the side so that both halves are seen and reflect down onto the floor.
    let light = Vec3::new(2.0, 2.0, 0.5);
    let mirror = Material::perfect_mirror;
    let one = scene_with(
        vec![
            floor(FLOOR_HALF, Vec3::splat(0.5)),
            Object::new("whole", whole.clone(), mirror(), place),
        ],
        light,
        Vec3::ONE,
        camera,
    );
    let two = scene_with(
        vec![
            floor(FLOOR_HALF, Vec3::splat(0.5)),
            Object::new("upper", half(true), mirror(), place),
            Object::new("lower", half(false), mirror(), place),
        ],
        light,
        Vec3::ONE,
        camera,
    );
    let opts = ReferenceOptions {
        photons: 300_000,
        ..Default::default()
    };
    let a = light_trace(
        &one,
        &camera,
        0.0,
        16,
        16,
        &opts,
        &PhotonSetup::caustics(&one),
    )
    .deposited[0]
        .x;
    let b = light_trace(
        &two,
        &camera,
        0.0,
        16,
        16,
        &opts,
        &PhotonSetup::caustics(&two),
    )
    .deposited[0]
        .x;
    println!("whole sphere {a:.5} W, two halves {b:.5} W");
    assert!(a > 0.0);
    assert!((b / a - 1.0).abs() < 0.02, "whole {a} W vs halves {b} W");
}
