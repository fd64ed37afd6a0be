//! Image tests on the `smoke` scene on the software adapter: every variant against the CPU
//! ground truth (`volumes::ground_truth`: the exact spheres composited over the raster pass's
//! image with the variant's own opacity function), with stated bounds, and the thesis's
//! claims.
//!
//! Two versions of the scene: the built-in `smoke` (its large volume, density 0.6 over 3 m,
//! saturates to opaque in the core) and "thin smoke", the same scene with the large volume's
//! density set to 0.2, where the posts and the ground stay visible through the volume and the
//! way they fade into it is measured.
//!
//! Bounds (RMSE on linear RGB over the whole 96x72 image; FLIP over the pixels whose ray
//! crosses a volume; observed values are in README.md, the bounds have headroom of about 1.5x):
//!
//! | variant | RMSE | masked FLIP |
//! | --- | --- | --- |
//! | `raytraced-sphere-*` (and particles) | 0.002 | 0.02 |
//! | `raytraced-thickness` | 0.03 | 0.2 |
//! | `raytraced-constant` | 0.05 | 0.3 |
//! | `raytraced-linear` | 0.06 | 0.45 |
//! | `slices-*`, `slices-*-float` | 0.03 | 0.25 |
//! | `billboard` | 0.06 | 0.35 |

use glam::Vec3;
use gpu::{GpuTimer, HdrImage, Target};
use scene::techniques::RasterTechnique;
use scene::{Camera, Frame, GpuScene, Scene, Technique, View};
use std::collections::BTreeMap;
use std::sync::OnceLock;
use volumes::ground_truth::{self, TruthSpec};
use volumes::technique::{VolumeTechnique, all_variants};

const W: u32 = 96;
const H: u32 = 72;

fn ctx() -> &'static gpu::Context {
    static CTX: OnceLock<gpu::Context> = OnceLock::new();
    CTX.get_or_init(|| gpu::Context::new().unwrap_or_else(|e| panic!("the image tests need a GPU adapter: {e}")))
}

fn smoke() -> Scene {
    scene::load("smoke").expect("the built-in smoke scene")
}

fn thin_smoke() -> Scene {
    let mut s = smoke();
    for v in s.volumes.iter_mut().filter(|v| !v.particle) {
        v.density = 0.2;
    }
    s
}

/// A scene uploaded once, with its volume-free image (the raster pass) and the distances of
/// its pixels, for one view.
struct Bench {
    scene: Scene,
    gpu_scene: GpuScene,
    target: Target,
    timer: GpuTimer,
    view: View,
    base: HdrImage,
    distances: Vec<f32>,
}

impl Bench {
    fn new(scene: Scene, camera: Camera, time: f32) -> Self {
        let ctx = ctx();
        let gpu_scene = GpuScene::new(ctx, &scene).expect("upload");
        let target = Target::new(ctx, W, H).expect("target");
        let timer = GpuTimer::new(ctx, 16);
        let view = View { camera, time, width: W, height: H };
        let mut bench = Bench { scene, gpu_scene, target, timer, view, base: HdrImage::new(W, H), distances: vec![] };
        bench.base = bench.render(&mut RasterTechnique);
        // The raster pass writes each pixel's distance from the eye into alpha: the distances
        // that belong to exactly these pixels (the BVH's can differ on silhouette pixels, see
        // `bvh_distances_agree_with_the_raster_pass`).
        bench.distances = bench
            .base
            .pixels
            .iter()
            .map(|p| if p[3] >= 0.5 * scene::BACKGROUND_DISTANCE { f32::INFINITY } else { p[3] })
            .collect();
        bench
    }

    fn render(&mut self, technique: &mut dyn Technique) -> HdrImage {
        let ctx = ctx();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut frame = Frame { gpu: ctx, encoder: &mut encoder, timer: &mut self.timer };
            self.gpu_scene.set_time(&mut frame, self.view.time);
            technique
                .prepare(&mut frame, &self.gpu_scene)
                .unwrap_or_else(|e| panic!("{}: prepare: {e}", technique.id()));
            technique
                .render(&mut frame, &self.gpu_scene, &self.view, &self.target)
                .unwrap_or_else(|e| panic!("{}: render: {e}", technique.id()));
        }
        self.timer.submit_and_collect(ctx, encoder).expect("submit");
        self.target.read(ctx).expect("read back")
    }

    fn truth(&self, spec: TruthSpec) -> HdrImage {
        ground_truth::composite(&self.scene, &self.view.camera, self.view.time, &self.base, &self.distances, spec)
    }

    fn mask(&self, spec: TruthSpec) -> Vec<bool> {
        let c = &self.view.camera;
        ground_truth::volume_mask(&self.scene, c, self.view.time, W, H, &self.distances, spec.set)
    }

    /// (RMSE, masked FLIP, non-finite pixels) of technique `id` (with `params`) against its
    /// ground truth, and its image.
    fn measure(&mut self, id: &str, params: &[(&str, f64)]) -> (f64, f64, usize, HdrImage) {
        let variant = all_variants().into_iter().find(|v| v.id() == id).unwrap_or_else(|| panic!("no variant {id}"));
        let mut technique = VolumeTechnique::new(variant);
        for (k, v) in params {
            technique.set_param(k, *v).unwrap();
        }
        let image = self.render(&mut technique);
        let spec = ground_truth::spec_for(id).unwrap();
        let truth = self.truth(spec);
        let (m, _) = scene::metrics::compare(&image, &truth, Some(&self.mask(spec)));
        (m.rmse, m.flip_mean_masked, m.nan_pixels, image)
    }
}

fn bound(id: &str) -> (f64, f64) {
    let name = id.trim_start_matches("volumes/").trim_start_matches("particles-");
    if name.starts_with("raytraced-sphere") {
        (0.002, 0.02)
    } else if name == "raytraced-thickness" {
        (0.03, 0.2)
    } else if name == "raytraced-constant" {
        (0.05, 0.3)
    } else if name == "raytraced-linear" {
        (0.06, 0.45)
    } else if name.starts_with("slices") {
        (0.03, 0.25)
    } else {
        (0.06, 0.35)
    }
}

/// Every variant on thin smoke: finite, within its bounds; the thesis's claims hold.
#[test]
fn thin_smoke_against_ground_truth() {
    let scene = thin_smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    let mut rmse: BTreeMap<String, f64> = BTreeMap::new();
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for variant in all_variants() {
        let id = variant.id();
        let (e, flip, non_finite, _) = bench.measure(&id, &[]);
        report.push(format!("{id}: RMSE {e:.5}, masked FLIP {flip:.4}"));
        let (max_rmse, max_flip) = bound(&id);
        if non_finite != 0 {
            failures.push(format!("{id}: {non_finite} non-finite pixels"));
        }
        if !(e <= max_rmse && flip <= max_flip) {
            failures.push(format!("{id}: RMSE {e:.5} (bound {max_rmse}), masked FLIP {flip:.4} (bound {max_flip})"));
        }
        rmse.insert(id.trim_start_matches("volumes/").to_string(), e);
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));

    // Thesis 6.4.1: the ray-traced volumes are smooth where even 79 slices are not; here the
    // exact sphere beats every slice count by an order of magnitude.
    for n in [5, 9, 19, 39, 79] {
        for suffix in ["", "-float"] {
            let slices = rmse[&format!("slices-{n}{suffix}")];
            assert!(
                rmse["raytraced-sphere-log"] * 10.0 < slices,
                "sphere {} vs slices-{n}{suffix} {slices}",
                rmse["raytraced-sphere-log"]
            );
        }
    }
    // Any volume beats the plain billboard; the thickness texture beats the constant and
    // linear primitives (6.4.1: the linear volume "shows very clear corners").
    for other in ["slices-5", "slices-79-float", "raytraced-constant", "raytraced-thickness", "raytraced-sphere-log"] {
        assert!(rmse[other] < rmse["billboard"], "{other} {} vs billboard {}", rmse[other], rmse["billboard"]);
    }
    assert!(rmse["raytraced-thickness"] < rmse["raytraced-constant"]);
    assert!(rmse["raytraced-constant"] < rmse["raytraced-linear"]);
    assert!(rmse["particles-raytraced-sphere-log"] * 10.0 < rmse["particles-billboard"]);
}

/// The built-in (dense) smoke: the exact sphere stays within its bound, nothing is NaN.
#[test]
fn dense_smoke_against_ground_truth() {
    let scene = smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    for id in [
        "volumes/raytraced-sphere-log",
        "volumes/particles-raytraced-sphere-log",
        "volumes/slices-19",
        "volumes/billboard",
    ] {
        let (e, flip, non_finite, _) = bench.measure(id, &[]);
        let (max_rmse, max_flip) = bound(id);
        let max_rmse = if id.contains("sphere") { max_rmse } else { 2.0 * max_rmse };
        let max_flip = if id.contains("sphere") { max_flip } else { 1.5 * max_flip };
        assert_eq!(non_finite, 0, "{id}");
        assert!(e <= max_rmse && flip <= max_flip, "{id}: RMSE {e}, masked FLIP {flip}");
    }
}

/// Thesis 6.3.2: with an 8-bit colour buffer every slice's small contribution is rounded, and
/// the rounding grows with the slice count (figure 6.15); the float buffer does not band.
/// Measured as the difference between each 8-bit variant and its float twin over the volume,
/// in 8-bit steps, and as the number of distinct values along the volume's smooth gradient.
#[test]
fn eight_bit_slices_band() {
    let scene = thin_smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    let spec = ground_truth::spec_for("volumes/slices-5").unwrap();
    let mask = bench.mask(spec);
    let mut deviation = BTreeMap::new();
    for n in [5, 79] {
        let (_, _, _, bytes) = bench.measure(&format!("volumes/slices-{n}"), &[]);
        let (_, _, _, float) = bench.measure(&format!("volumes/slices-{n}-float"), &[]);
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
    assert!(deviation[&79] > 1.5 * deviation[&5], "rounding must grow with the slice count: {deviation:?}");
    assert!(deviation[&79] > 1.0, "79 slices at 8 bits must be off by more than one step: {deviation:?}");
}

/// The eye inside the large volume (and exactly at its centre): every variant stays finite.
/// The billboards cannot cover the view from inside (a known failure, README), so only
/// finiteness is asserted.
#[test]
fn camera_inside_the_volume_is_finite() {
    let scene = thin_smoke();
    let v = scene.volumes.iter().find(|v| !v.particle).unwrap().clone();
    for eye in [v.center + Vec3::new(0.3, 0.15, 0.45), v.center] {
        let camera = Camera { eye, target: eye + Vec3::new(0.2, -0.3, -1.0), ..scene.camera };
        let mut bench = Bench::new(scene.clone(), camera, 0.0);
        for variant in all_variants() {
            let id = variant.id();
            for params in [&[][..], &[("free_depth", 1.0)][..]] {
                if !params.is_empty() && !id.contains("raytraced") {
                    continue;
                }
                let (_, _, non_finite, _) = bench.measure(&id, params);
                assert_eq!(non_finite, 0, "{id} {params:?} with the eye at {eye}");
            }
        }
    }
}

/// `fit_silhouette` (not in the thesis) removes the camera-inside failure of the ray-traced
/// sphere: from inside, from next to the volume and from the default view it matches the
/// exact volume.
#[test]
fn fitted_billboards_fix_the_close_camera() {
    let scene = thin_smoke();
    let v = scene.volumes.iter().find(|v| !v.particle).unwrap().clone();
    let eyes = [
        scene.camera.eye,
        v.center + Vec3::new(0.3, 0.15, 0.45),
        v.center,
        v.center + Vec3::new(0.0, 0.2, 1.0).normalize() * v.radius * 1.2,
    ];
    for eye in eyes {
        let camera = Camera { eye, target: eye + Vec3::new(0.2, -0.3, -1.0), ..scene.camera };
        let mut bench = Bench::new(scene.clone(), camera, 0.0);
        for id in ["volumes/raytraced-sphere-log", "volumes/particles-raytraced-sphere-log"] {
            for free_depth in [0.0, 1.0] {
                let (e, _, non_finite, _) = bench.measure(id, &[("fit_silhouette", 1.0), ("free_depth", free_depth)]);
                assert_eq!(non_finite, 0);
                assert!(e <= 0.002, "{id} free_depth={free_depth} eye {eye}: RMSE {e}");
            }
        }
    }
}

/// The ground truth's own primary distances (BVH closest hits through pixel centres) agree
/// with what the raster pass draws, but for a few silhouette pixels.
#[test]
fn bvh_distances_agree_with_the_raster_pass() {
    for eye in [None, Some(Vec3::new(0.3, 1.15, 0.45))] {
        let scene = thin_smoke();
        let camera = match eye {
            Some(e) => Camera { eye: e, target: e + Vec3::new(0.2, -0.3, -1.0), ..scene.camera },
            None => scene.camera,
        };
        let bench = Bench::new(scene, camera, 0.0);
        let bvh = ground_truth::primary_distances(&bench.scene, &camera, 0.0, W, H);
        let agree = bvh
            .iter()
            .zip(&bench.distances)
            .filter(|(a, b)| (a.is_infinite() && b.is_infinite()) || (*a - *b).abs() <= 1e-3 * a.abs().max(1.0))
            .count();
        let n = bvh.len();
        assert!(agree as f64 >= 0.99 * n as f64, "{agree} of {n} pixels agree");
    }
}

/// The depth "already there" (free_depth = 1, read from the raster pass's depth buffer) and
/// the thesis's R16Float distance pre-pass give the same picture.
#[test]
fn free_depth_matches_the_depth_prepass() {
    let scene = thin_smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 0.0);
    for id in ["volumes/raytraced-sphere-log", "volumes/raytraced-thickness"] {
        let (e0, _, _, a) = bench.measure(id, &[]);
        let (e1, _, _, b) = bench.measure(id, &[("free_depth", 1.0)]);
        let (m, _) = scene::metrics::compare(&a, &b, None);
        assert!(m.rmse < 1e-3, "{id}: the two depth sources differ by RMSE {}", m.rmse);
        assert!((e0 - e1).abs() < 1e-3, "{id}: {e0} vs {e1}");
    }
}

/// Particles move with the scene time; the technique follows them.
#[test]
fn particles_follow_the_scene_time() {
    let scene = smoke();
    let camera = scene.camera;
    let mut bench = Bench::new(scene, camera, 1.5);
    let (e, flip, non_finite, _) = bench.measure("volumes/particles-raytraced-sphere-log", &[]);
    assert_eq!(non_finite, 0);
    assert!(e <= 0.002 && flip <= 0.02, "RMSE {e}, masked FLIP {flip}");
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
        assert_eq!(t.supports(&particles_only), t.id().contains("particles-"), "{}", t.id());
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
    let scene = thin_smoke();
    let ctx = ctx();
    let mut gpu_scene = GpuScene::new(ctx, &scene).unwrap();
    let mut timer = GpuTimer::new(ctx, 16);
    let variant = all_variants().into_iter().find(|v| v.id() == "volumes/slices-9").unwrap();
    let mut technique = VolumeTechnique::new(variant);
    for (i, (w, h)) in [(48u32, 32u32), (64, 64), (48, 32)].into_iter().enumerate() {
        let target = Target::new(ctx, w, h).unwrap();
        let view = View { camera: scene.camera, time: 0.0, width: w, height: h };
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut frame = Frame { gpu: ctx, encoder: &mut encoder, timer: &mut timer };
            gpu_scene.set_time(&mut frame, 0.0);
            if i == 0 {
                technique.prepare(&mut frame, &gpu_scene).unwrap();
            }
            technique.render(&mut frame, &gpu_scene, &view, &target).unwrap();
        }
        timer.submit_and_collect(ctx, encoder).unwrap();
        assert_eq!(target.read(ctx).unwrap().non_finite_count(), 0);
    }
}
