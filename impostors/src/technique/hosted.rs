//! The specular objects over a frame that already holds everything else: what
//! [`crate::ImpostorPass`] records in a renderer's own frame. The harness's `render` runs the
//! same steps (`regenerate_stale`, `impostor_groups`, `lookup`) with `scene::GpuScene` as the
//! host, after drawing the diffuse scene and the caustics itself.

use super::*;

impl scene::hosted::DrawOver for Impostor {
    /// The specular objects of `objects` drawn over `color` and `depth` (targets of the
    /// formats of [`Impostor::for_targets`], holding a renderer's frame): their environment
    /// impostors asked of `host` (regenerated as they move), then the lookup, depth-tested
    /// against what is there, as `view` sees it. Caustic variants (their photons need the
    /// scene's lights) and the box-projected probes (their proxy is the scene's room) refuse.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        (objects, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let s = &self.settings;
        if s.caustics.is_some() || s.lookup == Lookup::BoxProjected {
            return Err(scene::TechniqueError::Unsupported(format!(
                "{} reads the scene's lights or its room: it renders whole frames only",
                self.id
            )));
        }
        let (settings, id) = (self.settings.clone(), self.id.clone());
        let state = self
            .state
            .as_mut()
            .ok_or(scene::TechniqueError::NotPrepared(id))?;
        regenerate_stale(frame, objects, host, state, &settings, false);
        let groups = impostor_groups(frame.gpu, objects, state, &settings);
        let camera = objects.camera_bind_group(frame.gpu, view.view_proj(), view.eye());
        let label = self.id.as_str();
        let groups = (&groups[..], &[][..]);
        lookup(
            frame,
            objects,
            (color, depth),
            state,
            &camera,
            groups,
            label,
        );
        Ok(())
    }
}
