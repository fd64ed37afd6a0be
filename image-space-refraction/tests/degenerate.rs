//! Degenerate input gives finite pixels on the GPU: an index of refraction of 1 (nothing
//! bends), below 1 (light leaves the glass more easily than it enters: total internal
//! reflection on entry), a large one (total internal reflection at the exit), a mirror (no
//! refraction at all), and a deforming refractor along its whole path, for every variant.

use testkit::{Shot, render};

#[test]
fn every_variant_renders_finite_pixels_in_degenerate_cases() {
    let _lock = testkit::gpu_lock();
    let scenes = [
        "hu-qin:ior=1",
        "hu-qin:ior=0.5",
        "hu-qin:ior=2.5",
        "hu-qin:refractor=morph",
        "cornell-sphere:material=mirror",
    ];
    for spec in scenes {
        let scene = scene::load(spec).unwrap();
        let duration = scene.camera_path.duration();
        for mut t in image_space_refraction::techniques() {
            if let Some(c) = t.params().iter().find(|p| p.name == "photon_buffer") {
                t.set_param(c.name, 32.0).unwrap();
            }
            for f in [0.0, 0.5, 1.0] {
                let image = render(
                    t.as_mut(),
                    &scene,
                    Shot::along_path(&scene, f * duration, 40),
                );
                assert_eq!(
                    image.non_finite_count(),
                    0,
                    "{} on {spec} at t = {}: NaN or infinite pixels",
                    t.id(),
                    f * duration
                );
            }
        }
    }
}
