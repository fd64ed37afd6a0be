//! Every registered technique on every built-in scene it supports, at a tiny size: it must
//! prepare, render and produce finite pixels (NaN or infinity is always a defect). Those
//! whose photons leave point lights refuse the spot- and sun-lit scenes with the reason.

use testkit::{Shot, context};

#[test]
fn every_technique_renders_finite_pixels_on_every_supported_scene() {
    let size = 32;
    let mut failures = Vec::new();
    let names = scene::builtin::builtin_scenes().into_iter().map(|i| i.name);
    let variants = scene::builtin::LIGHT_VARIANTS
        .into_iter()
        .chain(scene::builtin::CUTOUT_VARIANTS);
    for spec in names.chain(variants) {
        let scene = scene::load(spec).unwrap();
        for mut technique in harness::registry() {
            if !technique.supports(&scene) || technique.id() == "reference" {
                continue;
            }
            if context().require(technique.required_features()).is_err() {
                continue;
            }
            let shot = Shot::default_camera(&scene, 0.0, size);
            let image = testkit::render(technique.as_mut(), &scene, shot);
            let bad = image.non_finite_count();
            if bad > 0 {
                failures.push(format!(
                    "{} on {}: {bad} non-finite pixels",
                    technique.id(),
                    spec
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The families whose papers emit photons from a point light leave the spot- and sun-lit
/// scenes out, and say why when asked to prepare them anyway; every other technique that
/// supports the point-lit scene supports its spot- or sun-lit variant.
#[test]
fn point_light_families_refuse_spot_and_sun_with_the_reason() {
    let point_only = |id: &str| {
        id.starts_with("screen-photons/")
            || (id.contains("caustic") && !id.starts_with("raytracer/"))
    };
    for (lit, point) in [
        ("pool:light=sun", "pool"),
        ("cornell-sphere:light=spot", "cornell-sphere"),
    ] {
        let (lit_scene, point_scene) = (scene::load(lit).unwrap(), scene::load(point).unwrap());
        let mut refused = 0;
        for mut technique in harness::registry() {
            let id = technique.id();
            if !technique.supports(&point_scene) || id == "reference" {
                continue;
            }
            if !point_only(&id) {
                assert!(technique.supports(&lit_scene), "{id} refuses {lit}");
                continue;
            }
            assert!(!technique.supports(&lit_scene), "{id} claims {lit}");
            if context().require(technique.required_features()).is_err() {
                continue;
            }
            let _lock = testkit::gpu_lock();
            let gpu_scene = scene::GpuScene::new(context(), &lit_scene).unwrap();
            let mut timer = gpu::GpuTimer::off();
            let err =
                scene::runner::prepare(context(), &mut timer, technique.as_mut(), &gpu_scene).err();
            let message = err.map(|e| e.to_string()).unwrap_or_default();
            assert!(
                message.contains("needs point lights") && message.contains("light \""),
                "{id} on {lit}: {message:?}"
            );
            refused += 1;
        }
        println!("{lit}: {refused} techniques refuse it with the reason");
        assert!(refused > 0);
    }
}

/// Emission is radiance of the surface, not a light: every technique shows a glowing wall
/// where it sees it, directly and in its mirror's reflections, and nothing else changes. The
/// cornell room's back wall glows; against the same room without the glow, each technique's
/// image grows on the wall and the sphere as the reference's does (half of the reference's
/// growth at least, on each; a fifth in the sphere for screen-space photons, which reflect only
/// what is on screen), and the floor, which the glow does not light, keeps its radiance.
#[test]
fn every_technique_shows_emission_directly_and_in_its_reflections() {
    let size = 48;
    let spec = "cornell-sphere:material=mirror";
    let plain = scene::load(spec).unwrap();
    let mut glowing = plain.clone();
    let wall = glowing
        .objects
        .iter()
        .position(|o| o.name == "back wall")
        .unwrap();
    glowing.objects[wall].emission = glam::Vec3::new(0.8, 0.4, 0.1);
    glowing.validate().unwrap();
    let shot = Shot::default_camera(&plain, 0.0, size);
    let before = testkit::reference(spec, &plain, shot, 0);
    let after = testkit::reference(&format!("{spec} (glowing wall)"), &glowing, shot, 0);
    let object_of = |i: usize| before.object_ids[i];
    let sphere = plain
        .objects
        .iter()
        .position(|o| o.material.is_specular())
        .unwrap() as i32;
    let floor = plain
        .objects
        .iter()
        .position(|o| o.name == "floor")
        .unwrap() as i32;
    // Mean growth of an image over the pixels showing `object`.
    let growth = |a: &gpu::HdrImage, b: &gpu::HdrImage, object: i32| {
        let (mut sum, mut n) = (0.0f64, 0);
        for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            if object_of(i) == object {
                sum += (0..3).map(|c| (q[c] - p[c]) as f64).sum::<f64>();
                n += 1;
            }
        }
        sum / n.max(1) as f64
    };
    let want_wall = growth(&before.image, &after.image, wall as i32);
    let want_sphere = growth(&before.image, &after.image, sphere);
    assert!(
        want_wall > 1.0 && want_sphere > 0.05,
        "{want_wall} {want_sphere}"
    );
    let mut checked = 0;
    for mut technique in harness::registry() {
        let id = technique.id();
        if !technique.supports(&plain) || id == "reference" {
            continue;
        }
        if context().require(technique.required_features()).is_err() {
            continue;
        }
        let a = testkit::render(technique.as_mut(), &plain, shot);
        let mut technique = harness::registry()
            .into_iter()
            .find(|t| t.id() == id)
            .unwrap();
        let b = testkit::render(technique.as_mut(), &glowing, shot);
        let (on_wall, on_sphere, on_floor) = (
            growth(&a, &b, wall as i32),
            growth(&a, &b, sphere),
            growth(&a, &b, floor),
        );
        println!(
            "{id}: wall +{on_wall:.3} (reference +{want_wall:.3}), sphere +{on_sphere:.3} \
             (reference +{want_sphere:.3}), floor {on_floor:+.2e}"
        );
        assert!(on_wall > 0.5 * want_wall, "{id}: the wall grows {on_wall}");
        // The raster technique draws the mirror as grey diffuse: no reflection to grow.
        // Screen-space photons reflect only what the eye's layers hold: of the glowing wall,
        // what the mirror shows toward the top of the view (measured: a third of the growth).
        let share = if id.starts_with("screen-photons/") {
            0.2
        } else {
            0.5
        };
        if id != "raster" {
            assert!(
                on_sphere > share * want_sphere,
                "{id}: its mirror grows {on_sphere}, the reference's {want_sphere}"
            );
        }
        assert!(
            on_floor.abs() < 1e-4,
            "{id}: the floor changes by {on_floor}"
        );
        checked += 1;
    }
    assert!(checked > 10, "{checked} techniques");
}

/// Through an orthographic camera only the exact renderers and the raster baseline draw the
/// scene; every other technique refuses it with the reason, before preparing anything
/// (`scene::orthographic_refusal`, which the harness's measuring engine asks first).
#[test]
fn only_the_exact_renderers_and_raster_take_an_orthographic_camera() {
    for spec in scene::builtin::CAMERA_VARIANTS {
        let scene = scene::load(spec).unwrap();
        assert!(scene.camera.is_orthographic(), "{spec}");
        for technique in harness::registry() {
            let id = technique.id();
            let exact = id == "reference" || id.starts_with("raytracer/") || id == "raster";
            match scene::orthographic_refusal(technique.as_ref(), &scene) {
                Ok(()) => assert!(exact, "{id} claims {spec}'s orthographic camera"),
                Err(e) => {
                    assert!(!exact, "{id} refuses {spec}: {e}");
                    let message = e.to_string();
                    assert!(
                        message.contains(&id) && message.contains("orthographic"),
                        "{id}: {message}"
                    );
                }
            }
        }
    }
}
