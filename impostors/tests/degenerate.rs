//! Degenerate input: every variant renders finite pixels without panicking.
//!
//! - the reference point on a wall (`sphere_x = 1`, beyond the spec's declared range, so built
//!   through the API: the sphere's centre lies in the green wall, the map reads distance 0
//!   toward it) and in a corner-like spot near two walls;
//! - IOR 1.0 (no refraction: the straight-through direction, F = 0);
//! - IOR 0.75 (glass-0.75: total internal reflection at the entry for grazing view rays, and
//!   inside the refractor for double refraction);
//! - k large (a metal with n = 0.2 and the largest k the scene accepts, 10: F ~ 1 at every
//!   angle);
//! - stale maps (regen_threshold large, the object moved 0.5 m from the reference point).
//!
//! Rays parallel to a wall and origins on walls are covered by the Rust twin's property test
//! (`hit_properties::never_negative_never_nan`), which the GPU version matches
//! (`gpu_conformance`).

mod common;

use glam::Vec3;
use scene::Material;

fn check_all(scene: &scene::Scene, label: &str, times: &[f32], threshold: Option<f64>) {
    let _g = common::gpu_lock();
    for mut t in impostors::techniques() {
        if !t.supports(scene) {
            continue;
        }
        t.set_param("resolution", 32.0).unwrap();
        // The room probe (`box-projected`) is captured once and has no threshold.
        let regenerates = t.params().iter().any(|p| p.name == "regen_threshold");
        if let (Some(v), true) = (threshold, regenerates) {
            t.set_param("regen_threshold", v).unwrap();
        }
        let image = common::render_frames(t.as_mut(), scene, times, 48);
        assert_eq!(
            image.non_finite_count(),
            0,
            "{} on {label}: non-finite pixels",
            t.id()
        );
        assert!(
            image
                .pixels
                .iter()
                .all(|p| p[..3].iter().all(|&c| c >= 0.0)),
            "{} on {label}: negative radiance",
            t.id()
        );
    }
}

fn with_sphere_material(spec: &str, material: Material) -> scene::Scene {
    let mut scene = scene::load(spec).unwrap();
    let sphere = scene
        .objects
        .iter()
        .position(|o| o.name == "sphere")
        .unwrap();
    scene.objects[sphere].material = material;
    scene
}

#[test]
fn reference_point_on_a_wall() {
    for material in ["mirror", "glass-1.5"] {
        let scene = scene::builtin::cornell::cornell_sphere(material, 1.0).unwrap();
        check_all(
            &scene,
            &format!("{material}, centre on the wall"),
            &[0.0],
            None,
        );
    }
}

#[test]
fn ior_one_and_total_internal_reflection() {
    let scene = with_sphere_material("cornell-sphere", Material::glass(1.0));
    check_all(&scene, "glass ior 1.0", &[0.0], None);
    let scene = scene::load("cornell-sphere:material=glass-0.75").unwrap();
    check_all(&scene, "glass-0.75", &[0.0], None);
    let scene = scene::load("cornell-box:material=glass-0.75").unwrap();
    check_all(&scene, "cornell-box glass-0.75", &[0.0], None);
}

#[test]
fn extinction_very_large() {
    let scene = with_sphere_material(
        "cornell-box",
        Material::Metal {
            n: Vec3::splat(0.2),
            k: Vec3::splat(*Material::METAL_K_RANGE.end()),
        },
    );
    check_all(&scene, "k = 10", &[0.0], None);
}

#[test]
fn stale_maps_far_from_the_object() {
    let scene = scene::load("cornell-box:material=glass-1.5").unwrap();
    check_all(&scene, "stale glass", &[0.0, 1.0], Some(100.0));
}
