//! The tracer's images against the CPU reference.
//!
//! * `raytracer/whitted` equals the reference rendered without caustic photons on every
//!   built-in scene at the start, middle and end of its camera path, within the bound the
//!   README states ([`WHITTED_MAX_RMSE`], [`WHITTED_MAX_DIFFERENT`]): the same rays, the same
//!   triangle test, the same shading, so what differs is float rounding (GPU fused
//!   multiply-adds, `pow`/`exp`/`tan` of the shader library) and the rare pixel whose ray meets
//!   a shared edge and is assigned the neighbouring triangle.
//! * `raytracer/caustics` matches the whole reference within the noise of the two photon sets,
//!   and its caustic converges to the reference's as the photon count grows.
//! * Both hold under a spot and a sun too (`scene::builtin::LIGHT_VARIANTS`), and through an
//!   orthographic camera (`scene::builtin::CAMERA_VARIANTS`), and through an alpha cut-out's holes
//!   (`scene::builtin::CUTOUT_VARIANTS`).
//! * No image has a NaN or infinite pixel.

use gpu::HdrImage;
use raytracer::{RayTracer, Variant};
use scene::Technique;
use testkit::Shot;

const SIZE: u32 = 64;

/// Largest RMSE of a whitted image against the photon-free reference (measured worst: see
/// the README's evidence).
const WHITTED_MAX_RMSE: f64 = 2e-3;
/// Largest fraction of pixels differing from the reference by more than
/// [`PIXEL_TOLERANCE`] in any channel (relative to max(1, value)).
const WHITTED_MAX_DIFFERENT: f64 = 0.005;
const PIXEL_TOLERANCE: f32 = 1e-3;

fn rmse(a: &HdrImage, b: &HdrImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| ((p[c] - q[c]) as f64).powi(2)).sum::<f64>())
        .sum();
    (sum / (3 * a.pixels.len()) as f64).sqrt()
}

/// Fraction of pixels off by more than the tolerance, and the largest difference.
fn differing(a: &HdrImage, b: &HdrImage) -> (f64, f32) {
    let mut count = 0;
    let mut largest = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (0..3)
            .map(|c| (p[c] - q[c]).abs() / q[c].abs().max(1.0))
            .fold(0.0f32, f32::max);
        largest = largest.max(d);
        if d > PIXEL_TOLERANCE {
            count += 1;
        }
    }
    (count as f64 / a.pixels.len() as f64, largest)
}

fn render(variant: Variant, params: &[(&str, f64)], spec: &str, time: f32, size: u32) -> HdrImage {
    let scene = scene::load(spec).unwrap();
    let mut tracer = RayTracer::new(variant);
    for (name, value) in params {
        tracer.set_param(name, *value).unwrap();
    }
    let _lock = testkit::gpu_lock();
    testkit::render(&mut tracer, &scene, Shot::along_path(&scene, time, size))
}

#[test]
fn whitted_equals_the_reference_without_photons_on_every_built_in_scene() {
    let mut report = Vec::new();
    let names = scene::builtin::builtin_scenes().into_iter().map(|i| i.name);
    let variants = scene::builtin::LIGHT_VARIANTS
        .into_iter()
        .chain(scene::builtin::CAMERA_VARIANTS)
        .chain(scene::builtin::CUTOUT_VARIANTS);
    for spec in names.chain(variants) {
        let scene = scene::load(spec).unwrap();
        for time in scene::technique::check_times(scene.camera_path.duration()) {
            let shot = Shot::along_path(&scene, time, SIZE);
            let reference = testkit::reference(spec, &scene, shot, 0).image;
            let image = render(Variant::Whitted, &[], spec, time, SIZE);
            assert_eq!(
                image.non_finite_count(),
                0,
                "{spec} at t {time}: NaN pixels"
            );
            let e = rmse(&image, &reference);
            let (fraction, largest) = differing(&image, &reference);
            report.push(format!(
                "{spec} t {time}: RMSE {e:.2e}, {:.3}% of pixels off by > {PIXEL_TOLERANCE}, largest {largest:.2e}",
                100.0 * fraction
            ));
            assert!(
                e <= WHITTED_MAX_RMSE && fraction <= WHITTED_MAX_DIFFERENT,
                "{spec} at t {time}: RMSE {e} (bound {WHITTED_MAX_RMSE}), {fraction} of pixels \
                 differ (bound {WHITTED_MAX_DIFFERENT})"
            );
        }
    }
    println!("{}", report.join("\n"));
}

/// Mean radiance over the image (all channels).
fn mean(image: &HdrImage) -> f64 {
    let sum: f64 = image
        .pixels
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) as f64)
        .sum();
    sum / (3 * image.pixels.len()) as f64
}

/// The GPU's caustics differ from the reference's no more than the reference differs from
/// itself with another seed (the noise of two photon sets of the same size), and carry the
/// same light (the mean radiance of the image, where photon noise averages out).
#[test]
fn caustics_match_the_reference_within_photon_noise() {
    for spec in [
        "cornell-sphere",
        "hu-qin",
        "pool",
        "murky-pool",
        "cornell-sphere:light=spot",
        "pool:light=sun",
        "murky-pool:light=sun",
        "cornell-sphere:camera=orthographic",
        "cornell-box:camera=orthographic,light=spot",
    ] {
        let scene = scene::load(spec).unwrap();
        let duration = scene.camera_path.duration();
        for time in [0.0, duration] {
            let shot = Shot::along_path(&scene, time, SIZE);
            let options = truth::reference::ReferenceOptions::for_image(SIZE, SIZE);
            let reference = testkit::reference(spec, &scene, shot, options.photons);
            let other_seed = truth::reference::render(
                &scene,
                &shot.camera,
                time,
                SIZE,
                SIZE,
                &truth::reference::ReferenceOptions {
                    seed: options.seed ^ 0x9e37_79b9,
                    ..options
                },
            );
            // 16 frames of a sixteenth of the reference's photons each: its density.
            let image = render(Variant::Caustics, &[("converge", 16.0)], spec, time, SIZE);
            assert_eq!(image.non_finite_count(), 0, "{spec}: NaN pixels");
            let mask = Some(reference.mask.as_slice());
            let (gpu, _) = truth::metrics::compare(&image, &reference.image, mask);
            let (noise, _) = truth::metrics::compare(&other_seed.image, &reference.image, mask);
            let (m_gpu, m_ref) = (mean(&image), mean(&reference.image));
            println!(
                "{spec} t {time}: GPU FLIP {:.4} RMSE {:.4}; reference with another seed FLIP \
                 {:.4} RMSE {:.4}; mean radiance GPU {m_gpu:.5}, reference {m_ref:.5}",
                gpu.flip_mean, gpu.rmse, noise.flip_mean, noise.rmse
            );
            assert!(
                gpu.flip_mean <= 1.25 * noise.flip_mean + 0.003,
                "{spec} at t {time}: FLIP {} against the reference, whose own noise is {}",
                gpu.flip_mean,
                noise.flip_mean
            );
            assert!(
                (m_gpu - m_ref).abs() <= 0.02 * m_ref,
                "{spec} at t {time}: mean radiance {m_gpu} vs the reference's {m_ref}"
            );
        }
    }
}

/// The density the tracer defaults to is the reference's.
#[test]
fn the_default_photon_density_is_the_references() {
    assert_eq!(
        raytracer::tracer::PHOTONS_PER_PIXEL,
        truth::reference::PHOTONS_PER_PIXEL
    );
    for (w, h) in [(16, 16), (64, 64), (256, 256), (1024, 512)] {
        assert_eq!(
            raytracer::tracer::photons_for_image(w, h),
            truth::reference::ReferenceOptions::for_image(w, h).photons
        );
    }
}

/// The caustic converges: against a reference with many photons, the error falls as the GPU's
/// photon count grows (about as 1 / sqrt(photons) while it is above the reference's own noise).
#[test]
fn caustics_converge_as_the_photon_count_grows() {
    let spec = "cornell-sphere";
    let scene = scene::load(spec).unwrap();
    let shot = Shot::along_path(&scene, 0.0, SIZE);
    let reference = testkit::reference(spec, &scene, shot, 4_000_000).image;
    let errors: Vec<(f64, f64)> = [25_000.0, 100_000.0, 400_000.0, 1_600_000.0]
        .iter()
        .map(|&n| {
            let image = render(
                Variant::Caustics,
                &[("photons", n), ("converge", 1.0)],
                spec,
                0.0,
                SIZE,
            );
            (n, rmse(&image, &reference))
        })
        .collect();
    println!("photons, RMSE against 4M reference photons: {errors:?}");
    for pair in errors.windows(2) {
        assert!(
            pair[1].1 < pair[0].1,
            "more photons, larger error: {errors:?}"
        );
    }
    assert!(
        errors[3].1 < 0.5 * errors[0].1,
        "64 times the photons should at least halve the error: {errors:?}"
    );
}

/// Progressive caustics: the frames of one view add up to one image of all their photons. 16
/// frames of a sixteenth of the photons match one frame of all of them as closely as two photon
/// sets of that size match each other (the mean radiance equal, no frame counted twice or
/// lost), and each further frame brings the image closer to the reference.
#[test]
fn frames_of_one_view_add_up_to_one_image_of_all_their_photons() {
    let spec = "cornell-sphere";
    let scene = scene::load(spec).unwrap();
    let shot = Shot::along_path(&scene, 0.0, SIZE);
    let reference = testkit::reference(spec, &scene, shot, 4_000_000).image;
    let all = raytracer::tracer::photons_for_image(SIZE, SIZE) as f64;
    let at_once = render(
        Variant::Caustics,
        &[("photons", all), ("converge", 1.0)],
        spec,
        0.0,
        SIZE,
    );
    let errors: Vec<(f64, f64)> = [1.0, 4.0, 16.0]
        .iter()
        .map(|&k| {
            let image = render(Variant::Caustics, &[("converge", k)], spec, 0.0, SIZE);
            (k, rmse(&image, &reference))
        })
        .collect();
    let sixteen = render(Variant::Caustics, &[("converge", 16.0)], spec, 0.0, SIZE);
    println!(
        "frames, RMSE against 4M reference photons: {errors:?}; all photons at once {:.5}; \
         mean radiance at once {:.5}, in 16 frames {:.5}",
        rmse(&at_once, &reference),
        mean(&at_once),
        mean(&sixteen)
    );
    assert!(
        errors[0].1 > errors[1].1 && errors[1].1 > errors[2].1,
        "more frames, larger error: {errors:?}"
    );
    assert!(
        (mean(&sixteen) - mean(&at_once)).abs() <= 0.01 * mean(&at_once),
        "16 frames carry the light of one frame of all their photons"
    );
    assert!(
        errors[2].1 <= 1.25 * rmse(&at_once, &reference),
        "16 frames of 1/16 are as close as all photons at once: {errors:?}"
    );
}

/// The tracer casts the reference's rays: the eye pass's closest-hit and shadow rays, counted
/// on the GPU, equal the reference's own counts.
#[test]
fn the_eye_pass_casts_the_references_rays() {
    for spec in ["cornell-sphere", "chess", "murky-pool"] {
        let scene = scene::load(spec).unwrap();
        let shot = Shot::along_path(&scene, 0.0, SIZE);
        let reference = testkit::reference(spec, &scene, shot, 0);
        let mut tracer = RayTracer::new(Variant::Whitted);
        let _lock = testkit::gpu_lock();
        testkit::render(&mut tracer, &scene, shot);
        let counts = tracer
            .tracer()
            .unwrap()
            .ray_counts(testkit::context())
            .unwrap();
        let s = reference.stats;
        println!("{spec}: GPU {counts:?}, reference {s:?}");
        let near = |a: u64, b: u64| (a as f64 - b as f64).abs() <= 1e-3 * b as f64;
        assert!(
            near(counts.camera, s.camera_rays) && near(counts.shadow, s.shadow_rays),
            "{spec}: GPU rays {counts:?} vs reference {s:?}"
        );
    }
}

/// `raytracer/ray-query`: where the adapter offers wgpu's experimental ray queries (lavapipe
/// from Mesa 25, `cargo xtask test` runs this test on it too), its image equals the BVH
/// tracer's up to the rays that meet a shared edge (the hardware's watertight test may pick the
/// neighbouring triangle) and float rounding, and it casts the same rays; elsewhere `prepare`
/// refuses with the one-sentence reason the harness prints when it skips the variant.
#[test]
fn ray_queries_trace_what_the_bvh_traces_or_are_refused_with_the_reason() {
    let ctx = testkit::context();
    let supported = ctx
        .features()
        .contains(gpu::wgpu::Features::EXPERIMENTAL_RAY_QUERY);
    // `cargo xtask test` runs this test again on a driver with ray queries and says so.
    if std::env::var_os("RAYTRACER_EXPECT_RAY_QUERY").is_some() {
        assert!(
            supported,
            "RAYTRACER_EXPECT_RAY_QUERY is set but {} offers no ray queries",
            ctx.summary
        );
    }
    let specs = ["cornell-sphere", "hu-qin:refractor=morph", "smoke", "chess"];
    // With an alpha cut-out the geometry is not opaque: the shader confirms each candidate.
    for spec in specs.into_iter().chain(scene::builtin::CUTOUT_VARIANTS) {
        let scene = scene::load(spec).unwrap();
        let time = scene.camera_path.duration();
        let mut ray_query = RayTracer::new(Variant::RayQuery);
        if !supported {
            let _lock = testkit::gpu_lock();
            let gpu_scene = scene::GpuScene::new(ctx, &scene).unwrap();
            let mut timer = gpu::GpuTimer::new(ctx, 8);
            let err = scene::runner::prepare(ctx, &mut timer, &mut ray_query, &gpu_scene)
                .err()
                .expect("ray queries without the feature must be refused");
            let message = err.to_string();
            assert!(
                message.contains("EXPERIMENTAL_RAY_QUERY"),
                "the reason names the feature: {message}"
            );
            println!("{spec}: ray queries refused on {}: {message}", ctx.summary);
            continue;
        }
        let shot = Shot::along_path(&scene, time, SIZE);
        let mut bvh = RayTracer::new(Variant::Caustics);
        let (a, b, counts_a, counts_b) = {
            let _lock = testkit::gpu_lock();
            let a = testkit::render(&mut ray_query, &scene, shot);
            let counts_a = ray_query.tracer().unwrap().ray_counts(ctx).unwrap();
            let b = testkit::render(&mut bvh, &scene, shot);
            let counts_b = bvh.tracer().unwrap().ray_counts(ctx).unwrap();
            (a, b, counts_a, counts_b)
        };
        assert_eq!(a.non_finite_count(), 0, "{spec}: NaN pixels");
        let e = rmse(&a, &b);
        let (fraction, largest) = differing(&a, &b);
        println!(
            "{spec} t {time}: ray queries vs BVH: RMSE {e:.2e}, {:.3}% of pixels off, largest \
             {largest:.2e}; rays {counts_a:?} vs {counts_b:?}",
            100.0 * fraction
        );
        assert!(
            e <= 5e-3 && fraction <= 0.01,
            "{spec}: ray-query image differs from the BVH tracer's: RMSE {e}, {fraction} of pixels"
        );
        let near = |x: u64, y: u64| (x as f64 - y as f64).abs() <= 2e-3 * y.max(1) as f64;
        assert!(
            near(counts_a.camera, counts_b.camera) && near(counts_a.shadow, counts_b.shadow),
            "{spec}: rays {counts_a:?} vs {counts_b:?}"
        );
    }
}

/// Emission as the reference has it: seen directly and through the glass and the mirror,
/// lighting nothing; `whitted` equals the photon-free reference within the same bounds.
#[test]
fn emission_equals_the_reference() {
    for spec in ["cornell-sphere", "cornell-box"] {
        let mut scene = scene::load(spec).unwrap();
        for (name, glow) in [
            ("back wall", glam::Vec3::new(0.9, 0.5, 0.2)),
            ("floor", glam::Vec3::new(0.0, 0.1, 0.3)),
        ] {
            let o = scene.objects.iter_mut().find(|o| o.name == name).unwrap();
            o.emission = glow;
        }
        let key = format!("{spec} (glowing wall and floor)");
        let shot = Shot::along_path(&scene, 0.0, SIZE);
        let reference = testkit::reference(&key, &scene, shot, 0).image;
        let plain = testkit::reference(spec, &scene::load(spec).unwrap(), shot, 0).image;
        let mut tracer = RayTracer::new(Variant::Whitted);
        let image = {
            let _lock = testkit::gpu_lock();
            testkit::render(&mut tracer, &scene, shot)
        };
        let e = rmse(&image, &reference);
        let (fraction, largest) = differing(&image, &reference);
        println!(
            "{key}: RMSE {e:.2e}, {:.3}% of pixels off, largest {largest:.2e}; the glow changes \
             the reference by RMSE {:.3}",
            100.0 * fraction,
            rmse(&plain, &reference)
        );
        assert!(rmse(&plain, &reference) > 0.1, "{key}: no glow to see");
        assert!(
            e <= WHITTED_MAX_RMSE && fraction <= WHITTED_MAX_DIFFERENT,
            "{key}: RMSE {e}, {fraction} of pixels differ"
        );
    }
}
