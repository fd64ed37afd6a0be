//! The reference's single scattering in a homogeneous medium (`truth::scattering`):
//!
//! - a medium that does nothing (no scattering, no absorption) leaves the image the same bit for
//!   bit (without a medium the new code paths do not run at all: `Option::None` skips them);
//! - a purely absorbing medium is Beer-Lambert over the chord the eye's ray crosses;
//! - the two estimators agree: photon beams light-traced straight from the light (no specular
//!   event) carry the same in-scattered light as the eye pass's direct in-scattering, which
//!   integrates the same quantity by quadrature along the eye's rays (an independent check of
//!   the beams' normalisation: importance, phase function, both transmittances);
//!   `EYE_CLEARANCE` keeps both estimators off the eye's first 10 cm; both through a pinhole
//!   and through an orthographic camera;
//! - the beam estimate on `murky-pool` converges as the photon count grows (run with
//!   `--nocapture` for the table the README quotes), and is deterministic.

use glam::{Mat4, Vec2, Vec3};
use scene::mesh::quad;
use scene::{Camera, CameraPath, Light, Material, Medium, Object, Scene};
use truth::reference::{self, PhotonSetup, ReferenceOptions};

fn slab_scene(medium: Option<Medium>) -> Scene {
    let floor = Object::new(
        "floor",
        quad(
            Vec3::new(-10.0, 0.0, 10.0),
            Vec3::X * 20.0,
            Vec3::NEG_Z * 20.0,
            Vec2::splat(20.0),
        ),
        Material::diffuse(0.6, 0.6, 0.6),
        Mat4::IDENTITY,
    );
    let camera = Camera {
        eye: Vec3::new(0.0, 1.5, 4.0),
        target: Vec3::new(0.0, 0.8, 0.0),
        up: Vec3::Y,
        fov_y_deg: 55.0,
        orthographic: None,
    };
    Scene {
        name: "slab".into(),
        objects: vec![floor],
        textures: vec![],
        lights: vec![Light {
            name: "lamp".into(),
            position: Vec3::new(0.4, 3.0, -0.5),
            intensity: Vec3::splat(20.0),
            kind: scene::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium,
        background: Vec3::ZERO,
    }
}

fn medium(scattering: f32, absorption: f32, anisotropy: f32) -> Medium {
    Medium {
        name: "slab".into(),
        min: Vec3::new(-1.0, 0.3, -1.5),
        max: Vec3::new(1.2, 1.6, 0.5),
        scattering: Vec3::splat(scattering),
        absorption: Vec3::new(absorption, absorption * 0.5, absorption * 0.25),
        anisotropy,
    }
}

const SIZE: u32 = 48;

fn eye_only() -> ReferenceOptions {
    ReferenceOptions {
        photons: 0,
        ..ReferenceOptions::default()
    }
}

#[test]
fn a_medium_that_does_nothing_changes_nothing() {
    let camera = slab_scene(None).camera;
    let opts = ReferenceOptions {
        photons: 20_000,
        ..ReferenceOptions::default()
    };
    let clear = reference::render(&slab_scene(None), &camera, 0.0, SIZE, SIZE, &opts);
    let idle = reference::render(
        &slab_scene(Some(medium(0.0, 0.0, 0.3))),
        &camera,
        0.0,
        SIZE,
        SIZE,
        &opts,
    );
    assert_eq!(clear.image.pixels, idle.image.pixels);
}

#[test]
fn an_absorbing_medium_is_beer_lambert_over_the_eyes_chord() {
    let m = medium(0.0, 0.7, 0.0);
    let scene = slab_scene(Some(m.clone()));
    let camera = scene.camera;
    let clear = reference::render(&slab_scene(None), &camera, 0.0, SIZE, SIZE, &eye_only());
    let murky = reference::render(&scene, &camera, 0.0, SIZE, SIZE, &eye_only());
    let bvh = scene::bvh::SceneBvh::build(&scene, 0.0);
    let mut checked = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let i = (y * SIZE + x) as usize;
            let dir = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, SIZE, SIZE);
            let Some(hit) = bvh.closest_hit(camera.eye, dir, f32::INFINITY) else {
                continue;
            };
            // The floor's light also crosses the medium on its way down.
            let p = camera.eye + dir * hit.t;
            let light = scene.lights[0].position;
            let t_eye = m.transmittance(camera.eye, dir, hit.t);
            let t_light = m.transmittance_between(p, light);
            let want = Vec3::from_slice(&clear.image.pixels[i][..3]) * t_eye * t_light;
            let got = Vec3::from_slice(&murky.image.pixels[i][..3]);
            assert!(
                (got - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-3),
                "pixel {x},{y}: {got} vs {want}"
            );
            checked += (t_eye.x < 0.99) as usize;
        }
    }
    assert!(
        checked > 200,
        "only {checked} pixels see through the medium"
    );
}

/// The in-scattered light alone: the floor black, nothing behind.
fn black_slab(m: Medium) -> Scene {
    let mut scene = slab_scene(Some(m));
    scene.objects[0].material = Material::diffuse(0.0, 0.0, 0.0);
    scene
}

#[test]
fn beams_from_the_light_carry_what_the_eye_pass_integrates() {
    beams_carry_what_the_eye_pass_integrates(None);
}

/// The same through an orthographic camera 2.4 m high at the pinhole's eye: the beams reach
/// its film straight back along the view direction with importance `1 / A_pix` (pixel area in
/// the world), the eye pass's rays start on its plane. Measured: beams / eye pass 0.9987 to
/// 0.9991. The view holds the medium's whole box: 1.4 m high, where the image's edge cuts the
/// box (a silhouette too), the beams came out 0.45 to 0.55% below.
#[test]
fn beams_carry_what_the_eye_pass_integrates_through_an_orthographic_camera() {
    beams_carry_what_the_eye_pass_integrates(Some(1.2));
}

fn beams_carry_what_the_eye_pass_integrates(orthographic: Option<f32>) {
    for g in [0.0f32, 0.6] {
        let mut scene = black_slab(medium(0.4, 0.3, g));
        scene.camera.orthographic = orthographic;
        let camera = scene.camera;
        // Beams land in the pixel they project into (a box filter over the pixel): the eye
        // pass averages 16 rays per pixel to compare with that (with one ray per pixel centre
        // its sum was 3.5% below the beams', all of it at the box's silhouette).
        let area = ReferenceOptions {
            samples_per_pixel: 16,
            ..eye_only()
        };
        let marched = reference::render(&scene, &camera, 0.0, SIZE, SIZE, &area);
        let setup = PhotonSetup {
            targets: vec![0],
            min_specular_bounces: 0,
        };
        let opts = ReferenceOptions {
            photons: 2_000_000,
            ..ReferenceOptions::default()
        };
        let beams = reference::light_trace(&scene, &camera, 0.0, SIZE, SIZE, &opts, &setup);
        let sum = |v: &mut dyn Iterator<Item = Vec3>| v.fold(Vec3::ZERO, |a, b| a + b);
        let a = sum(&mut marched
            .image
            .pixels
            .iter()
            .map(|p| Vec3::from_slice(&p[..3])));
        let b = sum(&mut beams.beam_radiance.iter().copied());
        let ratio = b / a;
        println!("g = {g}: eye-pass in-scattering {a}, beams {b}, ratio {ratio}");
        assert!(a.min_element() > 1.0, "the medium scatters visibly: {a}");
        assert!(
            (ratio - Vec3::ONE).abs().max_element() < 0.005,
            "g = {g}: beams / eye pass = {ratio}"
        );
        // Pixel by pixel, away from the box's silhouette (where the pixel footprint and its
        // centre ray disagree), within the beams' noise.
        let (mut err, mut norm) = (0.0f64, 0.0f64);
        for (p, q) in marched.image.pixels.iter().zip(&beams.beam_radiance) {
            let p = Vec3::from_slice(&p[..3]);
            err += (p - *q).length_squared() as f64;
            norm += p.length_squared() as f64;
        }
        let relative = (err / norm).sqrt();
        println!("g = {g}: relative RMS difference per pixel {relative:.4}");
        assert!(relative < 0.06, "g = {g}: {relative}");
    }
}

#[test]
fn the_pool_beams_converge_and_repeat() {
    let scene = scene::load("murky-pool").unwrap();
    let camera = scene.camera_at(0.0);
    let size = 32;
    let setup = PhotonSetup::caustics(&scene);
    let beams = |photons: u64| {
        let opts = ReferenceOptions {
            photons,
            ..ReferenceOptions::default()
        };
        reference::light_trace(&scene, &camera, 0.0, size, size, &opts, &setup).beam_radiance
    };
    let best = beams(1_280_000);
    let mean = best.iter().fold(Vec3::ZERO, |a, b| a + *b) / best.len() as f32;
    assert!(mean.min_element() > 0.0, "the shafts are there: {mean}");
    let rms = |v: &[Vec3]| {
        (v.iter()
            .zip(&best)
            .map(|(a, b)| (*a - *b).length_squared() as f64)
            .sum::<f64>()
            / v.len() as f64)
            .sqrt()
    };
    println!("| photons | RMS difference to 1 280 000 photons (mean in-scattering {mean}) |");
    println!("| --- | --- |");
    let mut last = f64::INFINITY;
    for photons in [20_000u64, 80_000, 320_000] {
        let e = rms(&beams(photons));
        println!("| {photons} | {e:.5} |");
        // Monte Carlo: 4x the photons, half the error (against an estimate that has noise of
        // its own, so a little less than half).
        assert!(e < 0.7 * last, "{photons} photons: {e} after {last}");
        last = e;
    }
    assert_eq!(beams(20_000), beams(20_000), "deterministic");
}
