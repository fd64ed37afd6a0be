//! The exact tracer as one pass of a renderer's own frame: the yardstick drawn into the
//! renderer's colour and depth targets, from its camera, so that it can set its own frame
//! beside the exact one (or beside a technique's) in its own window.
//!
//! What the renderer provides:
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - its world as a [`scene::Scene`]: every triangle, material and light, in the reference's
//!   shading model (the design's materials: diffuse, glass, metal). Unlike the techniques'
//!   passes, which ask the renderer to draw its world ([`gpu::DrawScene`]), the tracer must
//!   hold the world itself: a ray may meet any triangle from any direction, so no view the
//!   renderer could draw serves it. The world is the tracer's only copy (a BVH and tables built
//!   from it); no `scene::GpuScene` is uploaded;
//! - its colour target, of any renderable format (written in linear radiance, as the other
//!   passes write: an `*Srgb` format encodes it), and its depth target, of any depth format,
//!   both with `RENDER_ATTACHMENT`. The pass covers the whole frame: the first hit's depth by
//!   the renderer's own projection (conventional or reversed, perspective or orthographic)
//!   goes into the depth target, so what the renderer draws after it is hidden as behind its
//!   own surfaces;
//! - its camera ([`gpu::EyeView`]): a rigid view and a centred perspective or orthographic
//!   projection with square pixels (a jittered or off-centre projection is refused by name);
//! - the time of the world's motion and morphs, and a frame to record into
//!   (`gpu::Frame::untimed` where it is not timed).
//!
//! Frames of an unchanged view (camera, time, size) add up their caustic photons, as in the
//! harness: a still camera's caustics converge. One pass draws one view per submission: its
//! uniforms and per-pixel buffers are the pass's own, so two views in one submission (a split
//! screen) need two passes.

use crate::resolve::{Resolve, ResolveParamsGpu};
use crate::tracer::{GpuTracer, RayCounts, TracerSettings, Traversal};
use glam::Mat3;
use gpu::{Context, EyeView, Frame, TargetFormats, wgpu};
use scene::technique::{TechniqueError, TechniqueResult};
use scene::{Camera, Scene, View};

/// The tracer's pass, made once for a renderer's formats and world.
pub struct TracerPass {
    world: Scene,
    tracer: GpuTracer,
    resolve: Resolve,
    formats: TargetFormats,
}

impl TracerPass {
    /// The pass tracing `world` into targets of `formats`: an error naming a format the device
    /// cannot render into, or what the world lacks.
    pub fn new(
        ctx: &Context,
        world: Scene,
        formats: TargetFormats,
        settings: TracerSettings,
    ) -> TechniqueResult<Self> {
        formats.check(ctx)?;
        world.validate()?;
        let tracer =
            ctx.validated(|| GpuTracer::new(ctx, &world, 0.0, settings, Traversal::Bvh))??;
        let resolve = ctx.validated(|| Resolve::new(ctx, formats, true))?;
        Ok(Self {
            world,
            tracer,
            resolve,
            formats,
        })
    }

    /// The world the pass traces.
    pub fn world(&self) -> &Scene {
        &self.world
    }

    /// Traces `world` from now on (its BVH and tables built anew; the photon sum restarts).
    pub fn set_world(&mut self, ctx: &Context, world: Scene) -> TechniqueResult<()> {
        world.validate()?;
        let settings = self.tracer.settings();
        self.tracer =
            ctx.validated(|| GpuTracer::new(ctx, &world, 0.0, settings, Traversal::Bvh))??;
        self.world = world;
        Ok(())
    }

    /// The formats the pass was made for.
    pub fn formats(&self) -> TargetFormats {
        self.formats
    }

    /// What a frame traces (the depth bound, the photons).
    pub fn settings(&self) -> TracerSettings {
        self.tracer.settings()
    }

    /// Traces with `settings` from the next frame on (the photon sum restarts).
    pub fn set_settings(&mut self, settings: TracerSettings) {
        self.tracer.set_settings(settings);
    }

    /// The rays the last frame cast (after its submission finished).
    pub fn ray_counts(&self, ctx: &Context) -> Result<RayCounts, gpu::GpuError> {
        self.tracer.ray_counts(ctx)
    }

    /// Records one frame of the world at `time` seen by `view` into `color` and `depth` (views
    /// of the renderer's textures, `view.width` x `view.height`, of the pass's formats): the
    /// eye pass, the light pass where the settings trace photons, and the resolve (spans "eye",
    /// "photons" and "resolve" where the frame's timer measures).
    pub fn draw(
        &mut self,
        frame: &mut Frame,
        view: &EyeView,
        time: f32,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let size = (view.width, view.height);
        let traced = View {
            camera: camera_of(view)?,
            time,
            width: view.width,
            height: view.height,
        };
        self.tracer.trace(frame, &self.world, &traced, size)?;
        let (radiance, photon_sum, last) = self.tracer.last_frame();
        // The depth by the renderer's own projection: its near and far planes, its convention.
        let params = ResolveParamsGpu::new(size, last.size[2] == 1, last.size[3], &view.projection);
        self.resolve.bind(frame.gpu, radiance, photon_sum);
        frame.span("resolve", |frame| {
            let resolve = &self.resolve;
            resolve.draw(frame.gpu, frame.encoder, &params, color, Some(depth));
        });
        Ok(())
    }
}

/// How far from exact a renderer's matrices may be and still be read as a rigid view and a
/// centred projection (relative, single precision's few ulps over a chain of products).
const TOLERANCE: f32 = 1e-3;

/// The tracer's camera of a renderer's view: the eye and axes of its view matrix, and the field
/// of view (perspective) or half height (orthographic) of its projection. A projection of
/// another kind (off-centre, jittered, skewed, with pixels that are not square for its size)
/// or a view that is not a rigid motion is refused in one sentence.
pub fn camera_of(view: &EyeView) -> TechniqueResult<Camera> {
    let refuse = |what: &str| {
        Err(TechniqueError::Unsupported(format!(
            "the ray tracer's pass traces {what}"
        )))
    };
    if view.width == 0 || view.height == 0 {
        return refuse("a view of at least one pixel");
    }
    if !(view.view.is_finite() && view.projection.is_finite()) {
        return refuse("a view whose matrices are finite");
    }
    let rotation = Mat3::from_mat4(view.view);
    let off_rigid = (rotation.transpose() * rotation - Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .any(|e| e.abs() > TOLERANCE);
    if off_rigid || rotation.determinant() < 0.0 {
        return refuse("a rigid view matrix (a rotation and a translation, no scale or mirror)");
    }
    let p = view.projection;
    let small = |x: f32| x.abs() <= TOLERANCE;
    let perspective = small(p.z_axis.w + 1.0) && small(p.w_axis.w);
    let orthographic = small(p.z_axis.w) && small(p.w_axis.w - 1.0);
    // Exactly centred: a sub-pixel jitter (a few 1e-4 at 1920 pixels) must not pass.
    let zero = |x: f32| x.abs() <= 1e-7;
    let centred = zero(p.z_axis.x) && zero(p.z_axis.y) && zero(p.w_axis.x) && zero(p.w_axis.y);
    let unskewed = small(p.y_axis.x) && small(p.x_axis.y) && small(p.x_axis.w) && small(p.y_axis.w);
    if !(perspective || orthographic) || !centred || !unskewed {
        return refuse(
            "a centred perspective or orthographic projection (glam's `perspective` or \
             `orthographic`, not off-centre or jittered)",
        );
    }
    if !(p.y_axis.y > 0.0 && p.x_axis.x > 0.0) {
        return refuse(
            "a projection that keeps the view's x right and y up (this one mirrors an axis: \
             flip the image after the pass instead)",
        );
    }
    let aspect = view.width as f32 / view.height as f32;
    if ((p.y_axis.y / p.x_axis.x) / aspect - 1.0).abs() > TOLERANCE {
        return refuse(&format!(
            "square pixels: the projection's aspect ratio must be the targets' {}x{}",
            view.width, view.height
        ));
    }
    let (forward, _, up) = view.basis();
    let eye = view.eye();
    Ok(Camera {
        eye,
        target: eye + forward,
        up,
        fov_y_deg: (2.0 * (1.0 / p.y_axis.y).atan()).to_degrees(),
        orthographic: orthographic.then(|| 1.0 / p.y_axis.y),
    })
}

/// A renderer's view of the world's `camera` at `width` x `height`: its view matrix and
/// projection, as `scene::Camera` makes them (what the tests and the examples hand the pass).
pub fn eye_view_of(camera: &Camera, width: u32, height: u32) -> EyeView {
    EyeView {
        view: camera.view(),
        projection: camera.projection(width as f32 / height as f32),
        width,
        height,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};

    fn camera(orthographic: Option<f32>) -> Camera {
        Camera {
            eye: Vec3::new(0.3, 1.2, 4.0),
            target: Vec3::new(-0.2, 0.4, 0.0),
            up: Vec3::Y,
            fov_y_deg: 38.0,
            orthographic,
        }
    }

    /// A camera's own matrices give the camera back: its eye, axes and field of view or half
    /// height (the pass and the harness then trace the same rays).
    #[test]
    fn a_cameras_matrices_give_it_back() {
        for orthographic in [None, Some(1.7)] {
            let original = camera(orthographic);
            let back = camera_of(&eye_view_of(&original, 160, 90)).unwrap();
            assert!(back.eye.abs_diff_eq(original.eye, 1e-5), "{back:?}");
            let (f, r, u) = original.basis();
            let (bf, br, bu) = back.basis();
            for (a, b) in [(f, bf), (r, br), (u, bu)] {
                assert!(a.abs_diff_eq(b, 1e-5), "{a} against {b}");
            }
            match orthographic {
                Some(h) => assert!((back.orthographic.unwrap() - h).abs() < 1e-5),
                None => {
                    assert!(back.orthographic.is_none());
                    assert!((back.fov_y_deg - 38.0).abs() < 1e-3, "{}", back.fov_y_deg);
                }
            }
        }
    }

    /// Views the tracer's camera cannot represent are refused with what it traces.
    #[test]
    fn views_it_cannot_trace_are_refused() {
        let good = eye_view_of(&camera(None), 160, 90);
        let jittered = EyeView {
            projection: Mat4::from_translation(Vec3::new(0.3 / 160.0, 0.0, 0.0)) * good.projection,
            ..good
        };
        let scaled = EyeView {
            view: Mat4::from_scale(Vec3::splat(2.0)) * good.view,
            ..good
        };
        let stretched = EyeView { width: 90, ..good };
        let empty = EyeView { height: 0, ..good };
        for (view, says) in [
            (jittered, "centred"),
            (scaled, "rigid"),
            (stretched, "square pixels"),
            (empty, "one pixel"),
        ] {
            let error = camera_of(&view).unwrap_err().to_string();
            assert!(error.contains(says), "{error}");
        }
    }
}
