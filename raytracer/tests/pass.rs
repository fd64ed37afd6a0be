//! The tracer as a pass of a renderer's own frame (`raytracer::pass::TracerPass`).
//!
//! * Into float targets it draws the harness's image to float rounding (the same trace, the
//!   same resolve arithmetic, the camera read back from the renderer's matrices), keeps the renderer's alpha, and writes each pixel's depth as the
//!   renderer's projection puts the first surface its pixel ray meets (found here on the CPU,
//!   through the scene's BVH): conventional and reversed, perspective and orthographic.
//! * Into `Rgba8UnormSrgb` and `Depth24Plus` (a typical renderer's targets) it draws the same
//!   image, encoded to sRGB by the format.
//! * What it cannot draw into is refused in a sentence.

use gpu::{Context, EyeView, Frame, HdrImage, TargetFormats, wgpu};
use raytracer::pass::{TracerPass, eye_view_of};
use raytracer::{RayTracer, TracerSettings, Variant};
use scene::Scene;
use scene::bvh::SceneBvh;
use testkit::Shot;

const SIZE: u32 = 48;
const SPEC: &str = "cornell-sphere";

/// A renderer's colour and depth textures (read back by the test).
struct MyTargets {
    color: wgpu::Texture,
    depth: wgpu::Texture,
}

impl MyTargets {
    fn new(ctx: &Context, formats: TargetFormats) -> Self {
        let copy = wgpu::TextureUsages::COPY_SRC;
        let texture =
            |label, format| gpu::render_texture(ctx, label, (SIZE, SIZE, 1), format, copy);
        Self {
            color: texture("my colour", formats.color),
            depth: texture("my depth", formats.depth),
        }
    }

    /// Clears the colour to `alpha`-transparent grey: what was there before the pass.
    fn clear(&self, ctx: &Context, alpha: f64) {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        let view = self.color.create_view(&Default::default());
        let grey = wgpu::Color {
            r: 0.5,
            g: 0.5,
            b: 0.5,
            a: alpha,
        };
        drop(gpu::pass::begin(
            &mut encoder,
            "clear",
            &[gpu::pass::color(&view, gpu::pass::Load::Clear(grey))],
            None,
            None,
        ));
        ctx.queue.submit([encoder.finish()]);
    }
}

/// One frame of `pass` from `view` at time 0 into `targets`.
fn draw(ctx: &Context, pass: &mut TracerPass, view: &EyeView, targets: &MyTargets) {
    let color = targets.color.create_view(&Default::default());
    let depth = targets.depth.create_view(&Default::default());
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    Frame::untimed(ctx, &mut encoder, |frame| {
        pass.draw(frame, view, 0.0, &color, &depth)
    })
    .expect("the pass draws");
    ctx.queue.submit([encoder.finish()]);
}

fn world() -> Scene {
    scene::load(SPEC).unwrap()
}

/// The depth `view`'s projection gives the first surface each pixel's ray meets
/// (`background` where none).
fn expected_depth(
    world: &Scene,
    camera: &scene::Camera,
    view: &EyeView,
    background: f32,
) -> Vec<f32> {
    let bvh = SceneBvh::build(world, 0.0);
    let (forward, _, _) = camera.basis();
    let mut depths = Vec::new();
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (origin, dir) = camera.ray(x as f32 + 0.5, y as f32 + 0.5, SIZE, SIZE);
            let depth = match bvh.closest_hit(origin, dir, f32::INFINITY) {
                Some(hit) => {
                    let view_z = -(hit.t * dir.dot(forward));
                    let clip = view.projection * glam::Vec4::new(0.0, 0.0, view_z, 1.0);
                    (clip.z / clip.w).clamp(0.0, 1.0)
                }
                None => background,
            };
            depths.push(depth);
        }
    }
    depths
}

/// Into float targets: the harness's image to float rounding, the renderer's alpha kept, and the
/// depth of the first surface by the renderer's projection, for a pinhole and an orthographic
/// camera.
#[test]
fn into_float_targets_it_draws_the_harness_image_and_the_first_surfaces_depth() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    for spec in [SPEC, "cornell-sphere:camera=orthographic"] {
        let world = scene::load(spec).unwrap();
        let shot = Shot::default_camera(&world, 0.0, SIZE);
        let harness = testkit::render(&mut RayTracer::new(Variant::Whitted), &world, shot);
        let formats = TargetFormats::new(wgpu::TextureFormat::Rgba32Float, gpu::DEPTH_FORMAT);
        let targets = MyTargets::new(ctx, formats);
        targets.clear(ctx, 0.25);
        let view = eye_view_of(&world.camera, SIZE, SIZE);
        let mut pass = TracerPass::new(ctx, world.clone(), formats, TracerSettings::default())
            .expect("the pass is made");
        draw(ctx, &mut pass, &view, &targets);

        let color = gpu::read_texture_f32x4(ctx, &targets.color, 0).unwrap();
        let mut different = 0;
        for (i, (mine, theirs)) in color.iter().zip(&harness.pixels).enumerate() {
            let off = (0..3).any(|c| (mine[c] - theirs[c]).abs() > 1e-5 * theirs[c].max(1.0));
            different += off as usize;
            assert_eq!(mine[3], 0.25, "{spec}: pixel {i}'s alpha was not kept");
        }
        // The camera read back from the renderer's matrices is the scene's to a few ulps: the
        // same rays to float rounding, but a ray that grazes an edge may take the neighbouring
        // triangle (the whitted bound against the reference allows 0.5 % such pixels).
        assert!(
            different <= (SIZE * SIZE) as usize / 200,
            "{spec}: {different} pixels differ from the harness's"
        );
        let depth = gpu::read_texture_f32(ctx, &targets.depth, 0).unwrap();
        let expected = expected_depth(&world, &world.camera, &view, 1.0);
        let off = depth
            .iter()
            .zip(&expected)
            .filter(|(d, e)| (*d - *e).abs() > 1e-5)
            .count();
        // A pixel whose ray grazes an edge may meet the neighbouring triangle in one traversal
        // and not the other (the README's whitted bound allows 0.5 % such pixels).
        assert!(
            off <= (SIZE * SIZE) as usize / 200,
            "{spec}: {off} of {} depths differ from the first surface's",
            depth.len()
        );
    }
}

/// A reversed projection (infinite far plane, depth 1 at the near plane): the background at
/// depth 0, the surfaces where that projection puts them; then the same view through a
/// conventional projection, the background at 1.
#[test]
fn a_reversed_projection_gets_its_own_depth() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let mut world = world();
    // The walls taken away: the sphere and the tall box against the background.
    world.objects.retain(|o| !o.name.contains("wall"));
    let camera = world.camera;
    let view = EyeView {
        projection: glam::camera::rh::proj::directx::perspective_infinite_reverse(
            camera.fov_y_deg.to_radians(),
            1.0,
            0.05,
        ),
        ..eye_view_of(&camera, SIZE, SIZE)
    };
    let formats = TargetFormats::new(wgpu::TextureFormat::Rgba16Float, gpu::DEPTH_FORMAT);
    let targets = MyTargets::new(ctx, formats);
    let mut pass = TracerPass::new(ctx, world.clone(), formats, TracerSettings::default()).unwrap();
    draw(ctx, &mut pass, &view, &targets);
    let depth = gpu::read_texture_f32(ctx, &targets.depth, 0).unwrap();
    let expected = expected_depth(&world, &camera, &view, 0.0);
    let background = expected.iter().filter(|&&e| e == 0.0).count();
    assert!(background > 0, "the view should see some background");
    for (i, (d, e)) in depth.iter().zip(&expected).enumerate() {
        assert!(
            (d - e).abs() <= 1e-5 * e.max(1e-3) + 1e-9,
            "pixel {i}: {d} against {e}"
        );
    }
    // The same open view through a conventional projection: the background at depth 1.
    let conventional = eye_view_of(&camera, SIZE, SIZE);
    draw(ctx, &mut pass, &conventional, &targets);
    let depth = gpu::read_texture_f32(ctx, &targets.depth, 0).unwrap();
    let expected = expected_depth(&world, &camera, &conventional, 1.0);
    assert_eq!(
        depth.iter().filter(|&&d| d == 1.0).count(),
        background,
        "the background is where the reversed view found it"
    );
    for (i, (d, e)) in depth.iter().zip(&expected).enumerate() {
        assert!((d - e).abs() <= 1e-5, "pixel {i}: {d} against {e}");
    }
}

/// Into a typical renderer's `Rgba8UnormSrgb` and `Depth24Plus`: the harness's image, encoded
/// to sRGB by the format (within one step of the CPU's encoding of the float image).
#[test]
fn into_srgb8_and_depth24_it_draws_the_same_image() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let world = world();
    let shot = Shot::default_camera(&world, 0.0, SIZE);
    let harness: HdrImage = testkit::render(&mut RayTracer::new(Variant::Whitted), &world, shot);
    let formats = TargetFormats::new(
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Depth24Plus,
    );
    let copy = wgpu::TextureUsages::COPY_SRC;
    let color = gpu::render_texture(ctx, "my colour", (SIZE, SIZE, 1), formats.color, copy);
    let depth = gpu::render_texture(ctx, "my depth", (SIZE, SIZE, 1), formats.depth, copy);
    let targets = MyTargets { color, depth };
    let mut pass = TracerPass::new(ctx, world.clone(), formats, TracerSettings::default()).unwrap();
    draw(
        ctx,
        &mut pass,
        &eye_view_of(&world.camera, SIZE, SIZE),
        &targets,
    );
    let mine = gpu::read_texture_bytes(ctx, &targets.color, 0, 4).unwrap();
    let theirs = harness.to_srgb8();
    for (i, (m, t)) in mine.chunks(4).zip(theirs.chunks(3)).enumerate() {
        for c in 0..3 {
            assert!(m[c].abs_diff(t[c]) <= 1, "pixel {i}: {m:?} against {t:?}");
        }
    }
}

/// A colour format it cannot render into, a depth format without depth, and a camera it
/// cannot trace are refused in a sentence that names them.
#[test]
fn what_it_cannot_draw_is_refused() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let not_renderable = TargetFormats::new(wgpu::TextureFormat::Rgb9e5Ufloat, gpu::DEPTH_FORMAT);
    let no_depth = TargetFormats::new(
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::R32Float,
    );
    for formats in [not_renderable, no_depth] {
        let refusal = TracerPass::new(ctx, world(), formats, TracerSettings::default());
        let error = refusal.err().expect("refused").to_string();
        assert!(
            error.contains("Rgb9e5Ufloat") || error.contains("R32Float"),
            "{error}"
        );
    }
    let formats = TargetFormats::new(wgpu::TextureFormat::Rgba8Unorm, gpu::DEPTH_FORMAT);
    let targets = MyTargets::new(ctx, formats);
    let mut pass = TracerPass::new(ctx, world(), formats, TracerSettings::default()).unwrap();
    let view = eye_view_of(&world().camera, SIZE, SIZE);
    let off_centre = EyeView {
        projection: glam::Mat4::from_translation(glam::Vec3::new(0.5 / SIZE as f32, 0.0, 0.0))
            * view.projection,
        ..view
    };
    let color = targets.color.create_view(&Default::default());
    let depth = targets.depth.create_view(&Default::default());
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    // The sentence `draw` refuses `view` with.
    let mut refused = |view: &EyeView, what: &str| -> String {
        let refusal = Frame::untimed(ctx, &mut encoder, |frame| {
            pass.draw(frame, view, 0.0, &color, &depth)
        });
        refusal.expect_err(what).to_string()
    };
    let error = refused(&off_centre, "an off-centre projection is refused");
    assert!(
        error.contains("centred perspective or orthographic"),
        "{error}"
    );
    // A view whose per-pixel buffers no device binds: refused before anything is allocated.
    let huge = eye_view_of(&world().camera, 1 << 16, 1 << 16);
    let error = refused(&huge, "a view too large is refused");
    assert!(error.contains("storage binding limit"), "{error}");
    // A projection that mirrors y (a renderer drawing y down).
    let mirrored = EyeView {
        projection: glam::Mat4::from_scale(glam::Vec3::new(1.0, -1.0, 1.0)) * view.projection,
        ..view
    };
    let error = refused(&mirrored, "a mirroring projection is refused");
    assert!(error.contains("mirrors an axis"), "{error}");
}
