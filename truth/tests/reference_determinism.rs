//! The reference is deterministic: the same seed gives the same bits, whatever the number of
//! threads; another seed gives another (but close) caustic.

use truth::reference::{ReferenceImage, ReferenceOptions, render};

fn render_in_pool(threads: usize, opts: &ReferenceOptions) -> ReferenceImage {
    let scene = scene::load("cornell-sphere").unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(&scene, &scene.camera, 0.0, 40, 32, opts))
}

fn bits(r: &ReferenceImage) -> Vec<u32> {
    r.image
        .pixels
        .iter()
        .flat_map(|p| p.map(f32::to_bits))
        .collect()
}

#[test]
fn same_seed_same_bits_on_one_or_two_threads() {
    let opts = ReferenceOptions {
        photons: 150_000,
        ..Default::default()
    };
    let a = render_in_pool(1, &opts);
    let b = render_in_pool(2, &opts);
    let c = render_in_pool(2, &opts);
    assert_eq!(bits(&a), bits(&b), "1 vs 2 threads");
    assert_eq!(bits(&b), bits(&c), "two runs on 2 threads");
    assert_eq!(a.object_ids, b.object_ids);
    assert_eq!(a.mask, b.mask);
    let counts = |r: &ReferenceImage| {
        (
            r.stats.camera_rays,
            r.stats.shadow_rays,
            r.stats.photon_rays,
            r.stats.photons_stored,
        )
    };
    assert_eq!(counts(&a), counts(&b));
    assert!(a.stats.photons_stored > 0 && a.stats.rays_per_second > 0.0);
    assert_eq!(a.image.non_finite_count(), 0);

    // Another seed moves the photons but not the eye pass; the caustic's total stays close.
    let d = render_in_pool(
        2,
        &ReferenceOptions {
            seed: opts.seed ^ 1,
            ..opts
        },
    );
    assert_ne!(bits(&a), bits(&d));
    let total = |r: &ReferenceImage| r.image.pixels.iter().map(|p| p[0] as f64).sum::<f64>();
    assert!((total(&a) / total(&d) - 1.0).abs() < 0.02);
}

/// Several samples per pixel: ids and mask still come from the centre ray, the image stays
/// close to the single-sample one (the scene is mostly smooth), and the camera ray count is
/// one centre ray plus the samples' trees.
#[test]
fn samples_per_pixel_average_around_the_centre() {
    let one = render_in_pool(
        2,
        &ReferenceOptions {
            photons: 0,
            ..Default::default()
        },
    );
    let four = render_in_pool(
        2,
        &ReferenceOptions {
            photons: 0,
            samples_per_pixel: 4,
            ..Default::default()
        },
    );
    assert_eq!(one.object_ids, four.object_ids);
    assert_eq!(one.mask, four.mask);
    assert!(four.stats.camera_rays > 4 * one.stats.camera_rays);
    let mean = |r: &ReferenceImage| {
        r.image.pixels.iter().map(|p| p[1] as f64).sum::<f64>() / r.image.pixels.len() as f64
    };
    assert!((mean(&one) / mean(&four) - 1.0).abs() < 0.05);
}

/// Timing the parts of a render (`render_profiled`) changes no bit of its image, on a scene
/// with caustics, one with volumes and one with a scattering medium (its beams), and its parts
/// lie within their phases.
#[test]
fn a_profiled_render_is_the_same_image() {
    use truth::reference::render_profiled;
    let opts = ReferenceOptions {
        photons: 60_000,
        ..Default::default()
    };
    for spec in ["cornell-sphere", "smoke", "murky-pool"] {
        let scene = scene::load(spec).unwrap();
        let plain = render(&scene, &scene.camera, 0.0, 32, 24, &opts);
        let (profiled, parts) = render_profiled(&scene, &scene.camera, 0.0, 32, 24, &opts);
        assert_eq!(bits(&plain), bits(&profiled), "{spec}");
        let phases = profiled.stats.phases;
        let slack = 1e-3;
        assert!(
            parts.direct_light_seconds + parts.eye_media_seconds <= phases.eye_seconds + slack,
            "{spec}: {parts:?} {phases:?}"
        );
        assert!(
            parts.connection_seconds + parts.beam_seconds <= phases.light_seconds + slack,
            "{spec}: {parts:?} {phases:?}"
        );
        if spec != "cornell-sphere" {
            assert!(parts.eye_media_seconds > 0.0, "{spec}: media untimed");
        }
    }
}
