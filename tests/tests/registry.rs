//! Every registered technique on every built-in scene it supports, at a tiny size: it must
//! prepare, render and produce finite pixels (NaN or infinity is always a defect). Those
//! whose photons leave point lights refuse the spot- and sun-lit scenes with the reason.

use testkit::{Shot, context};

#[test]
fn every_technique_renders_finite_pixels_on_every_supported_scene() {
    let size = 32;
    let mut failures = Vec::new();
    let names = scene::builtin::builtin_scenes().into_iter().map(|i| i.name);
    for spec in names.chain(scene::builtin::LIGHT_VARIANTS) {
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
