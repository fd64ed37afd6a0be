//! The refractors over a frame that already holds everything else: what
//! [`crate::RefractorPass`] records in a renderer's own frame. The harness's `render` runs the
//! same steps (`State::regenerate`, `front_back`, `lookup`) with `scene::GpuScene` as the host,
//! after drawing the diffuse scene itself.

use super::*;

impl scene::hosted::DrawOver for Refraction {
    /// The specular objects of `objects` drawn over `color` and `depth` (targets of the
    /// formats of [`Refraction::for_targets`], holding a renderer's frame): their environment
    /// maps asked of `host`, the front and back buffers, the refraction, seen by `view`.
    /// Variants with nearby geometry, caustics, the engine's probe or the thickness proxy
    /// need the scene's objects, lights or colour and refuse.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        (objects, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let s = &self.settings;
        if s.nearby.is_some() || s.room_probe || s.variant == Variant::ThicknessProxy {
            return Err(TechniqueError::Unsupported(format!(
                "{} reads the scene's nearby objects, probe or colour: it renders whole frames \
                 only",
                self.id
            )));
        }
        let params: Vec<ParamsGpu> = match &self.state {
            Some(state) => state
                .maps
                .iter()
                .map(|m| self.params_gpu(objects, m.object, state.room_probe))
                .collect(),
            None => return Err(not_prepared(self)),
        };
        let (variant, format) = (self.settings.variant, self.formats.color);
        let Some(state) = self.state.as_mut() else {
            return Err(TechniqueError::NotPrepared(self.id.clone()));
        };
        let ctx = frame.gpu;
        state.ensure_screen(ctx, view.width, view.height);
        let eye = Eye {
            view_proj: view.view_proj(),
            position: view.eye(),
            forward: view.basis().0,
            width: view.width,
            height: view.height,
        };
        state.write_frame_params(ctx, &eye, &params);
        let state = &*state;
        frame.span("regenerate", |frame| {
            state.regenerate(frame, objects, host, None)
        });
        let camera = objects.camera_bind_group(ctx, eye.view_proj, eye.position);
        if variant.needs_buffers() {
            frame.span("buffers", |frame| state.front_back(frame, objects, &camera));
        }
        let main = RasterTarget {
            color,
            depth,
            format,
            clear: false,
        };
        frame.span("lookup", |frame| {
            state.lookup(frame, objects, &camera, &main)
        });
        Ok(())
    }
}
