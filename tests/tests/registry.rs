//! Every registered technique on every built-in scene it supports, at a tiny size: it must
//! prepare, render and produce finite pixels (NaN or infinity is always a defect).

use testkit::{Shot, context};

#[test]
fn every_technique_renders_finite_pixels_on_every_supported_scene() {
    let size = 32;
    let mut failures = Vec::new();
    for info in scene::builtin::builtin_scenes() {
        let scene = scene::load(info.name).unwrap();
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
                    info.name
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
