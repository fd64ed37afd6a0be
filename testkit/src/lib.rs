//! What every test and example of the workspace needs and no technique should carry: one GPU
//! context per process (with a lock that keeps lavapipe's threads from being oversubscribed),
//! "render technique T on scene S at time t", the reference of the same view (cached per
//! process), PNG/strip writing with the workspace's conventions, and the proptest strategies
//! the property tests share ([`strategies`]).
//!
//! A dev-dependency only: technique crates lifted into someone's renderer never compile it.

pub mod gltf;
pub mod gpu_time;
pub mod section5;
pub mod strategies;
use gpu::{Context, GpuTimer, HdrImage, Target};
use scene::{Camera, Frame, GpuScene, Scene, Technique, View, runner};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, OnceLock};

/// The process's GPU context (lavapipe on CI); a missing adapter panics with its one-line
/// reason (how to install the software driver).
pub fn context() -> &'static Context {
    static CTX: OnceLock<Context> = OnceLock::new();
    CTX.get_or_init(|| {
        Context::new().unwrap_or_else(|e| panic!("these tests need a GPU adapter: {e}"))
    })
}

/// Serialises the GPU work of the tests of one binary (they run on parallel threads): on a
/// small machine lavapipe's own threads are oversubscribed otherwise.
pub fn gpu_lock() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// Records one submission through `f`, with the scene moved to `time` first, submits it and
/// returns the timer's spans (name, milliseconds).
pub fn submit(
    ctx: &Context,
    gpu_scene: &mut GpuScene,
    time: f32,
    f: impl FnOnce(&mut Frame, &GpuScene),
) -> Vec<(String, f64)> {
    let mut timer = GpuTimer::new(ctx, 64);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut frame = Frame {
            gpu: ctx,
            encoder: &mut encoder,
            timer: &mut timer,
        };
        gpu_scene.set_time(&mut frame, time);
        f(&mut frame, gpu_scene);
    }
    timer.submit_and_collect(ctx, encoder).expect("submit")
}

/// One frame of a test: the camera, the time along the scene's path and the image size.
#[derive(Clone, Copy, Debug)]
pub struct Shot {
    pub camera: Camera,
    pub time: f32,
    pub size: u32,
}

impl Shot {
    /// The scene's camera path at `time` (its default camera for a still scene).
    pub fn along_path(scene: &Scene, time: f32, size: u32) -> Self {
        Self {
            camera: scene.camera_at(time),
            time,
            size,
        }
    }

    /// The scene's default camera with the scene at `time`.
    pub fn default_camera(scene: &Scene, time: f32, size: u32) -> Self {
        Self {
            camera: scene.camera,
            time,
            size,
        }
    }

    pub fn view(&self) -> View {
        View {
            camera: self.camera,
            time: self.time,
            width: self.size,
            height: self.size,
        }
    }
}

/// Renders `technique` on `scene`: prepares it at the first shot's time, renders every shot
/// in turn (a map made at an earlier time is reused when the technique allows it), the last
/// one as many times as the technique takes to converge (`Technique::frames_to_converge`, as
/// the harness renders an error frame), and returns the last image, with the harness's own
/// steps (`scene::runner`). Errors, GPU validation errors included, fail the test. Tests that
/// run in parallel hold [`gpu_lock`] around it.
pub fn render_shots(technique: &mut dyn Technique, scene: &Scene, shots: &[Shot]) -> HdrImage {
    let first = shots.first().expect("at least one shot");
    let ctx = context();
    let mut gpu_scene = GpuScene::new(ctx, scene).expect("scene uploads");
    let target = Target::new(ctx, first.size, first.size).expect("target");
    let mut timer = GpuTimer::new(ctx, 64);
    // The harness's own steps (scene::runner): what a test renders is what compare measures.
    runner::update_scene(ctx, &mut timer, &mut gpu_scene, first.time).expect("scene update");
    runner::prepare(ctx, &mut timer, technique, &gpu_scene).expect("prepare");
    let last = shots.len() - 1;
    for (i, shot) in shots.iter().enumerate() {
        let repeats = match i == last {
            true => technique.frames_to_converge().max(1),
            false => 1,
        };
        for _ in 0..repeats {
            runner::render_frame(
                ctx,
                &mut timer,
                technique,
                &mut gpu_scene,
                &shot.view(),
                &target,
            )
            .expect("render");
        }
    }
    target.read(ctx).expect("read back")
}

/// Renders one shot of `technique` on `scene`.
pub fn render(technique: &mut dyn Technique, scene: &Scene, shot: Shot) -> HdrImage {
    render_shots(technique, scene, &[shot])
}

/// The reference image of `shot` with `photons` caustic photons (0: none; they only add light
/// under specular objects and cost most of the reference's time), computed once per process
/// for the same scene spec, shot and photon count.
pub fn reference(
    spec: &str,
    scene: &Scene,
    shot: Shot,
    photons: u64,
) -> truth::reference::ReferenceImage {
    // The whole camera (an orthographic one differs from a pinhole only in `orthographic`),
    // the time's and size's exact values and the photon count.
    type Key = (String, String, u64);
    static CACHE: OnceLock<Mutex<HashMap<Key, truth::reference::ReferenceImage>>> = OnceLock::new();
    let c = shot.camera;
    let view = format!("{c:?} time {:?} size {}", shot.time, shot.size);
    let key = (spec.to_string(), view, photons);
    let cache = CACHE.get_or_init(Default::default);
    if let Some(image) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return image.clone();
    }
    let options = truth::reference::ReferenceOptions {
        photons,
        ..Default::default()
    };
    let image = truth::reference::render(scene, &c, shot.time, shot.size, shot.size, &options);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, image.clone());
    image
}

/// The variant `id` among `techniques` (a crate's `techniques()`), or a panic naming it.
pub fn technique(techniques: Vec<Box<dyn Technique>>, id: &str) -> Box<dyn Technique> {
    techniques
        .into_iter()
        .find(|t| t.id() == id)
        .unwrap_or_else(|| panic!("no technique {id}"))
}

/// `target/<name>/` of the workspace, created: where tests write the images they make.
pub fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../target")
        .join(name);
    std::fs::create_dir_all(&dir).expect("output dir");
    dir
}

/// Writes `image` as an sRGB PNG (the workspace's convention: clamp, sRGB, no tone mapping).
pub fn save_png(image: &HdrImage, path: &Path) {
    let bytes = truth::metrics::to_srgb8(image);
    image::save_buffer(
        path,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )
    .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

/// Images side by side, each scaled up `scale` times (nearest), as one image.
pub fn strip(images: &[&HdrImage], scale: u32) -> HdrImage {
    let h = images.iter().map(|i| i.height).max().unwrap_or(0) * scale;
    let w: u32 = images.iter().map(|i| i.width * scale).sum();
    let mut strip = HdrImage::new(w, h);
    let mut x0 = 0;
    for img in images {
        for y in 0..img.height * scale {
            for x in 0..img.width * scale {
                strip.set(x0 + x, y, img.get(x / scale, y / scale));
            }
        }
        x0 += img.width * scale;
    }
    strip
}

/// The largest difference of one colour channel between two images of one size.
pub fn max_difference(a: &HdrImage, b: &HdrImage) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f32::max)
}

/// The summed absolute colour difference of `a` from `b`, over `b`'s summed radiance: how far
/// one image strays from another as a share of its light.
pub fn relative_difference(a: &HdrImage, b: &HdrImage) -> f32 {
    let total: f32 = b.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum();
    let diff: f32 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>())
        .sum();
    diff / total.max(f32::MIN_POSITIVE)
}

/// Pixels of `a` with a colour channel more than `threshold` from `b`'s.
pub fn pixels_differing(a: &HdrImage, b: &HdrImage, threshold: f32) -> usize {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (0..3).any(|c| (p[c] - q[c]).abs() > threshold))
        .count()
}
