//! Image tests on the `smoke` scene on the software adapter.
//!
//! **Primary figure: every variant against the ground truth**, the scene's participating
//! media (`truth::media`, what `truth::reference` renders) composited over the raster pass's
//! image of the volume-free scene (`truth::composite::with_reference_media`; the raster pass
//! rather than the CPU surfaces, so that shadow-map edges, which no volume technique owns,
//! stay out of the error). The 17 thesis variants draw the large volume only and are measured
//! on `smoke:particles=0`; the particle versions on the built-in `smoke` (24 particles).
//! Bounds are the measured values (comments) with about 1.5x headroom, and every variant
//! must beat, by a stated factor, the image without any volume: a variant that draws nothing
//! fails.
//!
//! **Second figure: the variant model** (`common::variant_model`: uniform spheres with
//! the variant's own opacity function and scale, exact path lengths). It isolates the GPU
//! geometry: the ray-traced sphere must match its own model to RMSE 0.002 from every eye
//! position with `fit_silhouette`, whatever the error of that model against the truth.

mod common;

use glam::Vec3;
use gpu::{HdrImage, Target};
use scene::foundation::RasterTechnique;
use scene::{Camera, GpuScene, Scene, Technique, View};
use std::collections::BTreeMap;
use volumes::VolumeSet;
use volumes::technique::{VolumeTechnique, all_variants};

const W: u32 = 96;
const H: u32 = 72;

fn smoke() -> Scene {
    scene::load("smoke").expect("the built-in smoke scene")
}

/// The large volume alone (what the 17 thesis variants draw).
fn single_smoke() -> Scene {
    scene::load("smoke:particles=0").expect("the built-in smoke scene")
}

/// A scene uploaded once, with its volume-free image (the raster pass), the distances of its
/// pixels and the ground truth, for one view.
struct Bench {
    scene: Scene,
    gpu_scene: GpuScene,
    target: Target,
    view: View,
    base: HdrImage,
    distances: Vec<f32>,
    truth: HdrImage,
    mask: Vec<bool>,
}

/// Metrics of one image against one truth.
#[derive(Clone, Copy, Debug)]
struct Error {
    rmse: f64,
    flip_masked: f64,
    non_finite: usize,
}

impl Bench {
    fn new(scene: Scene, camera: Camera, time: f32) -> Self {
        let ctx = testkit::context();
        let gpu_scene = GpuScene::new(ctx, &scene).expect("upload");
        let target = Target::new(ctx, W, H).expect("target");
        let view = View {
            camera,
            time,
            width: W,
            height: H,
        };
        let empty = HdrImage::new(W, H);
        let mut bench = Bench {
            scene,
            gpu_scene,
            target,
            view,
            base: empty.clone(),
            distances: vec![],
            truth: empty,
            mask: vec![],
        };
        bench.base = bench.render(&mut RasterTechnique);
        // The raster pass writes each pixel's distance from the eye into alpha: the distances
        // that belong to exactly these pixels (the BVH's can differ on silhouette pixels, see
        // `bvh_distances_agree_with_the_raster_pass`).
        bench.distances = bench
            .base
            .pixels
            .iter()
            .map(|p| {
                if p[3] >= 0.5 * scene::BACKGROUND_DISTANCE {
                    f32::INFINITY
                } else {
                    p[3]
                }
            })
            .collect();
        let (s, c) = (&bench.scene, &bench.view.camera);
        bench.truth =
            truth::composite::with_reference_media(s, c, time, &bench.base, &bench.distances);
        bench.mask = common::volume_mask(s, c, time, W, H, &bench.distances, VolumeSet::All);
        bench
    }

    fn render(&mut self, technique: &mut dyn Technique) -> HdrImage {
        let ctx = testkit::context();
        let (view, target) = (&self.view, &self.target);
        testkit::submit(ctx, &mut self.gpu_scene, view.time, |frame, gpu_scene| {
            technique
                .prepare(frame, gpu_scene)
                .unwrap_or_else(|e| panic!("{}: prepare: {e}", technique.id()));
            technique
                .render(frame, gpu_scene, view, target)
                .unwrap_or_else(|e| panic!("{}: render: {e}", technique.id()));
        });
        target.read(ctx).expect("read back")
    }

    fn error(&self, image: &HdrImage, truth: &HdrImage) -> Error {
        let (m, _) = truth::metrics::compare(image, truth, Some(&self.mask));
        Error {
            rmse: m.rmse,
            flip_masked: m.flip_mean_masked,
            non_finite: m.nan_pixels,
        }
    }

    /// Renders technique `id` with `params`.
    fn image(&mut self, id: &str, params: &[(&str, f64)]) -> HdrImage {
        let variant = all_variants()
            .into_iter()
            .find(|v| v.id() == id)
            .unwrap_or_else(|| panic!("no variant {id}"));
        let mut technique = VolumeTechnique::new(variant);
        for (k, v) in params {
            technique.set_param(k, *v).unwrap();
        }
        self.render(&mut technique)
    }

    /// Renders `technique` again without preparing it (a parameter changed after prepare).
    fn render_prepared(&mut self, technique: &mut dyn Technique) -> HdrImage {
        let ctx = testkit::context();
        let (view, target) = (&self.view, &self.target);
        testkit::submit(ctx, &mut self.gpu_scene, view.time, |frame, gpu_scene| {
            technique
                .render(frame, gpu_scene, view, target)
                .unwrap_or_else(|e| panic!("{}: render: {e}", technique.id()));
        });
        target.read(ctx).expect("read back")
    }

    /// Technique `id` against the ground truth (the primary figure), and its image.
    fn measure(&mut self, id: &str, params: &[(&str, f64)]) -> (Error, HdrImage) {
        let image = self.image(id, params);
        (self.error(&image, &self.truth), image)
    }

    /// Technique `id` against its own variant model (the second figure).
    fn measure_model(&mut self, id: &str, params: &[(&str, f64)]) -> Error {
        let image = self.image(id, params);
        let spec = common::spec_for(id).unwrap();
        let (s, c, t) = (&self.scene, &self.view.camera, self.view.time);
        let model = common::variant_model(s, c, t, &self.base, &self.distances, spec);
        self.error(&image, &model)
    }

    /// The image without any volume against the ground truth: what drawing nothing scores.
    fn nothing(&self) -> Error {
        self.error(&self.base, &self.truth)
    }
}

/// (RMSE, masked FLIP) bounds against the ground truth at 96x72: the measured values (in
/// the comments, `--nocapture` prints them) times about 1.5, except where that would let an
/// empty image pass (drawing nothing scores RMSE 0.110, FLIP 0.696 on `smoke:particles=0` and
/// 0.163, 0.716 on `smoke`): there the bound sits between the measured value and nothing's.
fn bound(id: &str) -> (f64, f64) {
    match id.trim_start_matches("volumes/") {
        "billboard" => (0.043, 0.30),               // 0.0290, 0.197
        "raytraced-constant" => (0.105, 0.62),      // 0.0986, 0.518
        "raytraced-linear" => (0.032, 0.28),        // 0.0215, 0.189
        "raytraced-sphere-log" => (0.09, 0.60),     // 0.0603, 0.416
        "raytraced-sphere-linear" => (0.055, 0.44), // 0.0369, 0.294
        "raytraced-sphere-sqrt" => (0.10, 0.62),    // 0.0699, 0.453
        "raytraced-thickness" => (0.015, 0.18),     // 0.0099, 0.119
        "particles-billboard" => (0.058, 0.33),     // 0.0388, 0.216
        "particles-slices-9" | "particles-slices-9-float" => (0.041, 0.26), // 0.0271, 0.173
        "particles-raytraced-sphere-log" => (0.14, 0.62), // 0.0945, 0.431
        "particles-raytraced-thickness" => (0.041, 0.27), // 0.0276, 0.178
        "depth-fade" => (0.048, 0.35),              // 0.0318, 0.231
        "particles-depth-fade" => (0.061, 0.35),    // 0.0408, 0.232
        // 8-bit and float, 5 to 79 slices: 0.0091-0.0118, 0.106-0.160.
        name if name.starts_with("slices-") => (0.018, 0.24),
        _ => panic!("no bound for {id}"),
    }
}

/// Spurious edges: over the volume's pixels, the energy of the luminance steps between
/// adjacent pixels that the truth does not have (`max(0, step^2 - true step^2)`: squared, so
/// that a hard step of height h scores h^2 and the same change spread over n pixels h^2 / n),
/// summed separately for vertical
/// steps (pixel to the one below: horizontal lines, such as where the ground cuts a
/// billboard) and horizontal steps (pixel to the one on its right: vertical lines, such as a
/// post's silhouette cutting through the volume). A volume that fades into the geometry as
/// the true medium does scores near zero in both.
fn spurious_edges(image: &HdrImage, truth: &HdrImage, mask: &[bool]) -> (f64, f64) {
    let lum = |img: &HdrImage, i: usize| {
        let p = img.pixels[i];
        0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
    };
    let spurious = |i: usize, j: usize| {
        if !(mask[i] || mask[j]) {
            return 0.0;
        }
        let step = lum(image, j) - lum(image, i);
        let true_step = lum(truth, j) - lum(truth, i);
        (step * step - true_step * true_step).max(0.0)
    };
    let (w, h) = (image.width as usize, image.height as usize);
    let (mut lines, mut silhouettes) = (0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if y + 1 < h {
                lines += spurious(i, i + w);
            }
            if x + 1 < w {
                silhouettes += spurious(i, i + 1);
            }
        }
    }
    (lines, silhouettes)
}

/// The engine baseline against the thesis's reason for ray-traced volumes, on the large
/// volume cut by the ground and crossed by posts. The plain billboard's depth test draws a
/// hard line where the ground cuts its plane; the depth fade softens that line, but makes
/// everything within the fade distance *behind* the billboard plane show through with a hard
/// silhouette (the posts), so it trades one intersection artefact for another; the ray-traced
/// thickness volume has neither. With `fade_distance = 0` the fade is the billboard's depth
/// test again. Measured values (96 x 72) at the assertions.
#[test]
fn depth_fade_trades_the_ground_line_for_post_silhouettes() {
    // The side view at the end of the camera path, where the ground and the log cut the
    // billboard plane in sight (at t = 0 the log hides the ground line).
    let scene = single_smoke();
    let camera = scene.camera_at(2.0);
    let mut bench = Bench::new(scene, camera, 2.0);
    let mut edges = |id: &str, params: &[(&str, f64)]| {
        let image = bench.image(id, params);
        spurious_edges(&image, &bench.truth, &bench.mask)
    };
    let billboard = edges("volumes/billboard", &[]);
    let fade = edges("volumes/depth-fade", &[]);
    let hard = edges("volumes/depth-fade", &[("fade_distance", 0.0)]);
    let thickness = edges("volumes/raytraced-thickness", &[]);
    let slices = edges("volumes/slices-19-float", &[]);
    println!(
        "spurious edges (horizontal lines, vertical lines): billboard {billboard:.3?}, \
         depth-fade {fade:.3?} (fade 0: {hard:.3?}), raytraced-thickness {thickness:.3?}, \
         slices-19-float {slices:.3?}"
    );
    assert!(
        (hard.0 - billboard.0).abs() <= 0.05 * billboard.0
            && (hard.1 - billboard.1).abs() <= 0.05 * billboard.1,
        "a zero fade is the depth test: {hard:?} vs billboard {billboard:?}"
    );
    // Measured (96 x 72, t = 2, fade 1 R): horizontal-line energy billboard 1.257, depth fade
    // 1.072 (-15%); vertical lines 6.706 and 7.189 (+7%); ray-traced thickness 0.406 and
    // 0.432, slices-19-float 0.444 and 0.464.
    assert!(
        fade.0 < 0.9 * billboard.0,
        "ground line: depth fade {fade:?} vs billboard {billboard:?}"
    );
    assert!(
        fade.1 > billboard.1,
        "post silhouettes: depth fade {fade:?} vs billboard {billboard:?}"
    );
    let total = |e: (f64, f64)| e.0 + e.1;
    assert!(
        total(thickness) < 0.25 * total(fade).min(total(billboard)),
        "ray-traced thickness {thickness:?} vs depth fade {fade:?} and billboard {billboard:?}"
    );
}

/// `fade_distance` set after `prepare` takes effect in the next frame (the pipeline is
/// specialised again), as a fresh technique with that value renders it.
#[test]
fn fade_distance_changed_after_prepare_is_used() {
    let mut bench = Bench::new(single_smoke(), single_smoke().camera, 0.0);
    let variant = all_variants()
        .into_iter()
        .find(|v| v.id() == "volumes/depth-fade")
        .unwrap();
    let mut technique = VolumeTechnique::new(variant);
    let soft = bench.render(&mut technique);
    technique.set_param("fade_distance", 0.0).unwrap();
    let changed = bench.render_prepared(&mut technique);
    let fresh = bench.image("volumes/depth-fade", &[("fade_distance", 0.0)]);
    assert_eq!(changed.pixels, fresh.pixels, "the changed fade is not used");
    assert_ne!(
        changed.pixels, soft.pixels,
        "a zero fade must differ from the default"
    );
}

/// Every variant's RMSE must be below this share of the RMSE of drawing nothing (measured:
/// 0.08-0.90; 1.0 is an empty image).
const BEATS_NOTHING: f64 = 0.95;

/// Every variant against the ground truth: finite, within its bound, far better than drawing
/// nothing; the thesis's claims that hold against the true medium.
#[test]
fn every_variant_against_the_reference() {
    let mut single = Bench::new(single_smoke(), single_smoke().camera, 0.0);
    let mut all = Bench::new(smoke(), smoke().camera, 0.0);
    let nothing = [
        (VolumeSet::Single, single.nothing()),
        (VolumeSet::All, all.nothing()),
    ];
    println!(
        "nothing drawn: single {:?}, all {:?}",
        nothing[0].1, nothing[1].1
    );
    let mut rmse: BTreeMap<String, f64> = BTreeMap::new();
    let mut failures = Vec::new();
    for variant in all_variants() {
        let id = variant.id();
        let bench = if variant.set == VolumeSet::Single {
            &mut single
        } else {
            &mut all
        };
        let (e, _) = bench.measure(&id, &[]);
        let none = nothing.iter().find(|(s, _)| *s == variant.set).unwrap().1;
        println!(
            "{id}: RMSE {:.5}, masked FLIP {:.4} ({:.2} of nothing)",
            e.rmse,
            e.flip_masked,
            e.rmse / none.rmse
        );
        let (max_rmse, max_flip) = bound(&id);
        if e.non_finite != 0 {
            failures.push(format!("{id}: {} non-finite pixels", e.non_finite));
        }
        if !(e.rmse <= max_rmse && e.flip_masked <= max_flip) {
            failures.push(format!(
                "{id}: RMSE {:.5} (bound {max_rmse}), FLIP {:.4} (bound {max_flip})",
                e.rmse, e.flip_masked
            ));
        }
        if e.rmse.is_nan() || e.rmse >= BEATS_NOTHING * none.rmse {
            failures.push(format!(
                "{id}: RMSE {:.5} is not below {BEATS_NOTHING} x nothing's {:.5}",
                e.rmse, none.rmse
            ));
        }
        rmse.insert(id.trim_start_matches("volumes/").to_string(), e.rmse);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    check_claims(&rmse);
}

/// The thesis's claims (6.4.1, 6.4.3) as they hold against the true, textured medium.
fn check_claims(rmse: &BTreeMap<String, f64>) {
    let less = |a: &str, b: &str| {
        assert!(
            rmse[a] < rmse[b],
            "{a} {} must beat {b} {}",
            rmse[a],
            rmse[b]
        )
    };
    // 6.4.1: "of the volume primitives the one using the thickness texture appears to be the
    // best choice" (measured 0.0099 against 0.021-0.099 for the untextured primitives).
    for other in [
        "raytraced-constant",
        "raytraced-linear",
        "raytraced-sphere-log",
        "raytraced-sphere-linear",
        "raytraced-sphere-sqrt",
    ] {
        less("raytraced-thickness", other);
    }
    // Any volume with the texture beats the plain billboard's hard edges (6.4.1).
    for n in [5, 9, 19, 39, 79] {
        less(&format!("slices-{n}-float"), "billboard");
        less(&format!("slices-{n}"), "billboard");
    }
    less("raytraced-thickness", "billboard");
    // 6.3.2, figure 6.15: 79 slices round visibly in an 8-bit buffer, not in a float one.
    less("slices-79-float", "slices-79");
    less(
        "particles-raytraced-thickness",
        "particles-raytraced-sphere-log",
    );
    // The engine baseline: the depth fade treats each particle as a sheet at its centre, so
    // where geometry stands near that plane it removes opacity the true medium has in front of
    // it; the thesis's thickness volume is more accurate (0.0099 against 0.0318; particles
    // 0.0276 against 0.0408), and on this scene even the hard billboard is (0.0290).
    less("raytraced-thickness", "depth-fade");
    less("particles-raytraced-thickness", "particles-depth-fade");
    less("billboard", "depth-fade");
    less("particles-raytraced-thickness", "particles-billboard");
}

/// The second figure: the ray-traced sphere is exact in its own model (uniform sphere, its
/// opacity function): the GPU path (ray-sphere, depth clipping, compositing) is right.
#[test]
fn sphere_matches_its_own_model() {
    let mut single = Bench::new(single_smoke(), single_smoke().camera, 0.0);
    let mut all = Bench::new(smoke(), smoke().camera, 0.0);
    for id in [
        "volumes/raytraced-sphere-log",
        "volumes/raytraced-sphere-linear",
        "volumes/raytraced-sphere-sqrt",
    ] {
        let e = single.measure_model(id, &[]);
        assert!(e.rmse <= 0.002 && e.flip_masked <= 0.02, "{id}: {e:?}");
    }
    let e = all.measure_model("volumes/particles-raytraced-sphere-log", &[]);
    assert!(e.rmse <= 0.002 && e.flip_masked <= 0.02, "particles: {e:?}");
}

/// Same inputs, same image: the technique and the truth are deterministic.
#[test]
fn same_image_twice() {
    let mut bench = Bench::new(single_smoke(), single_smoke().camera, 0.0);
    for id in ["volumes/raytraced-thickness", "volumes/slices-9"] {
        let a = bench.image(id, &[]);
        let b = bench.image(id, &[]);
        assert_eq!(a.pixels, b.pixels, "{id}");
    }
    let again = Bench::new(single_smoke(), single_smoke().camera, 0.0);
    assert_eq!(bench.truth.pixels, again.truth.pixels);
}

/// Thesis 6.3.2: with an 8-bit colour buffer every slice's small contribution is rounded, and
/// the rounding grows with the slice count (figure 6.15); the float buffer does not band.
/// Measured as the difference between each 8-bit variant and its float twin over the volume,
/// in 8-bit steps, and as the number of distinct values along the volume's smooth gradient.
#[test]
fn eight_bit_slices_band() {
    let scene = single_smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    let mask = bench.mask.clone();
    let mut deviation = BTreeMap::new();
    for n in [5, 79] {
        let bytes = bench.image(&format!("volumes/slices-{n}"), &[]);
        let float = bench.image(&format!("volumes/slices-{n}-float"), &[]);
        let (mut sum, mut count) = (0.0f64, 0usize);
        for ((b, f), &m) in bytes.pixels.iter().zip(&float.pixels).zip(&mask) {
            if m {
                for c in 0..3 {
                    sum += ((b[c] - f[c]) as f64 * 255.0).powi(2);
                }
                count += 3;
            }
        }
        deviation.insert(n, (sum / count as f64).sqrt());
    }
    println!("8-bit vs float RMS deviation in 8-bit steps: {deviation:?}");
    assert!(
        deviation[&79] > 1.5 * deviation[&5],
        "rounding must grow with the slice count: {deviation:?}"
    );
    assert!(
        deviation[&79] > 1.0,
        "79 slices at 8 bits must be off by more than one step: {deviation:?}"
    );
}

/// The eye inside the large volume (and exactly at its centre): every variant stays finite.
/// The billboards cannot cover the view from inside (a known failure, README), so only
/// finiteness is asserted.
#[test]
fn camera_inside_the_volume_is_finite() {
    let scene = single_smoke();
    let v = scene.volumes.iter().find(|v| !v.particle).unwrap().clone();
    for eye in [v.center + Vec3::new(0.3, 0.15, 0.45), v.center] {
        let camera = Camera {
            eye,
            target: eye + Vec3::new(0.2, -0.3, -1.0),
            ..scene.camera
        };
        let mut bench = Bench::new(scene.clone(), camera, 0.0);
        for variant in all_variants() {
            let id = variant.id();
            for params in [&[][..], &[("free_depth", 1.0)][..]] {
                if !params.is_empty() && !id.contains("raytraced") {
                    continue;
                }
                let (e, _) = bench.measure(&id, params);
                assert_eq!(e.non_finite, 0, "{id} {params:?} with the eye at {eye}");
            }
        }
    }
}

/// `fit_silhouette` (not in the thesis) removes the camera-inside failure of the ray-traced
/// sphere: from inside, from next to the volume and from the default view it matches its own
/// model (the second figure: the uniform sphere it draws, exactly).
#[test]
fn fitted_billboards_fix_the_close_camera() {
    let scene = single_smoke();
    let v = scene.volumes.iter().find(|v| !v.particle).unwrap().clone();
    let eyes = [
        scene.camera.eye,
        v.center + Vec3::new(0.3, 0.15, 0.45),
        v.center,
        v.center + Vec3::new(0.0, 0.2, 1.0).normalize() * v.radius * 1.2,
    ];
    for eye in eyes {
        let camera = Camera {
            eye,
            target: eye + Vec3::new(0.2, -0.3, -1.0),
            ..scene.camera
        };
        let mut bench = Bench::new(scene.clone(), camera, 0.0);
        for id in [
            "volumes/raytraced-sphere-log",
            "volumes/particles-raytraced-sphere-log",
        ] {
            for free_depth in [0.0, 1.0] {
                let e =
                    bench.measure_model(id, &[("fit_silhouette", 1.0), ("free_depth", free_depth)]);
                assert_eq!(e.non_finite, 0);
                assert!(
                    e.rmse <= 0.002,
                    "{id} free_depth={free_depth} eye {eye}: {e:?}"
                );
            }
        }
    }
}

/// The ground truth's own primary distances (BVH closest hits through pixel centres) agree
/// with what the raster pass draws, but for a few silhouette pixels.
#[test]
fn bvh_distances_agree_with_the_raster_pass() {
    for eye in [None, Some(Vec3::new(0.3, 1.15, 0.45))] {
        let scene = single_smoke();
        let camera = match eye {
            Some(e) => Camera {
                eye: e,
                target: e + Vec3::new(0.2, -0.3, -1.0),
                ..scene.camera
            },
            None => scene.camera,
        };
        let bench = Bench::new(scene, camera, 0.0);
        let bvh = truth::composite::primary_distances(&bench.scene, &camera, 0.0, W, H);
        let agree = bvh
            .iter()
            .zip(&bench.distances)
            .filter(|(a, b)| {
                (a.is_infinite() && b.is_infinite()) || (*a - *b).abs() <= 1e-3 * a.abs().max(1.0)
            })
            .count();
        let n = bvh.len();
        assert!(
            agree as f64 >= 0.99 * n as f64,
            "{agree} of {n} pixels agree"
        );
    }
}

/// The depth "already there" (free_depth = 1, read from the raster pass's depth buffer) and
/// the thesis's R16Float distance pre-pass give the same picture.
#[test]
fn free_depth_matches_the_depth_prepass() {
    let scene = single_smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    for id in [
        "volumes/raytraced-sphere-log",
        "volumes/raytraced-thickness",
    ] {
        let (e0, a) = bench.measure(id, &[]);
        let (e1, b) = bench.measure(id, &[("free_depth", 1.0)]);
        let (e0, e1) = (e0.rmse, e1.rmse);
        let (m, _) = truth::metrics::compare(&a, &b, None);
        assert!(
            m.rmse < 1e-3,
            "{id}: the two depth sources differ by RMSE {}",
            m.rmse
        );
        assert!((e0 - e1).abs() < 1e-3, "{id}: {e0} vs {e1}");
    }
}

/// Particles move with the scene time; the technique follows them (against its own model).
#[test]
fn particles_follow_the_scene_time() {
    let scene = smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 1.5);
    let e = bench.measure_model("volumes/particles-raytraced-sphere-log", &[]);
    assert_eq!(e.non_finite, 0);
    assert!(e.rmse <= 0.002 && e.flip_masked <= 0.02, "{e:?}");
}

#[test]
fn supports_scenes_with_volumes_only() {
    let smoke = smoke();
    let cornell = scene::load("cornell-sphere").unwrap();
    let mut particles_only = smoke.clone();
    particles_only.volumes.retain(|v| v.particle);
    for t in volumes::techniques() {
        assert!(t.supports(&smoke), "{}", t.id());
        assert!(!t.supports(&cornell), "{}", t.id());
        assert_eq!(
            t.supports(&particles_only),
            t.id().contains("particles-"),
            "{}",
            t.id()
        );
    }
}

#[test]
fn parameters_are_declared_and_checked() {
    for mut t in volumes::techniques() {
        let params = t.params();
        assert!(!params.is_empty(), "{}", t.id());
        for p in &params {
            t.set_param(p.name, p.default).unwrap();
            assert!(t.set_param(p.name, p.max + 1.0).is_err());
        }
        assert!(t.set_param("no-such-parameter", 0.0).is_err());
    }
}

/// The same technique instance renders targets of different sizes (buffers follow the target).
#[test]
fn follows_the_target_size() {
    let scene = single_smoke();
    let ctx = testkit::context();
    let mut gpu_scene = GpuScene::new(ctx, &scene).unwrap();
    let variant = all_variants()
        .into_iter()
        .find(|v| v.id() == "volumes/slices-9")
        .unwrap();
    let mut technique = VolumeTechnique::new(variant);
    for (i, (w, h)) in [(48u32, 32u32), (64, 64), (48, 32)].into_iter().enumerate() {
        let target = Target::new(ctx, w, h).unwrap();
        let view = View {
            camera: scene.camera,
            time: 0.0,
            width: w,
            height: h,
        };
        testkit::submit(ctx, &mut gpu_scene, 0.0, |frame, gpu_scene| {
            if i == 0 {
                technique.prepare(frame, gpu_scene).unwrap();
            }
            technique.render(frame, gpu_scene, &view, &target).unwrap();
        });
        assert_eq!(target.read(ctx).unwrap().non_finite_count(), 0);
    }
}

/// Every technique id of the crate has a variant model (the second figure of these tests).
#[test]
fn every_variant_has_a_variant_model() {
    let ids: Vec<String> = volumes::techniques().iter().map(|t| t.id()).collect();
    assert!(!ids.is_empty());
    for id in &ids {
        assert!(common::spec_for(id).is_some(), "{id} has a variant model");
    }
}
