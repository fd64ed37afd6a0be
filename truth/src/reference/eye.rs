//! The camera as the light pass sees it.

use super::*;
use glam::Mat4;

/// The camera (pinhole or orthographic) as the light pass sees it: where a point lands on
/// the image, and what one pixel's importance is (`Film::importance`).
pub(super) struct Eye<'a> {
    pub(super) camera: Camera,
    /// Media between a landed photon and the eye attenuate it, as they attenuate the eye
    /// pass's view of the same point.
    pub(super) media: &'a Media,
    /// So does the scattering medium.
    pub(super) medium: Option<&'a Medium>,
    pub(super) forward: Vec3,
    /// The camera's view-projection, made once ([`Camera::project_with`]).
    view_proj: Mat4,
    pub(super) film: Film,
    pub(super) width: u32,
    pub(super) height: u32,
}

impl<'a> Eye<'a> {
    pub(super) fn new(
        camera: &Camera,
        width: u32,
        height: u32,
        media: &'a Media,
        medium: Option<&'a Medium>,
    ) -> Self {
        Eye {
            camera: *camera,
            media,
            medium,
            forward: camera.basis().0,
            view_proj: camera.view_proj(width, height),
            film: camera.film(width, height),
            width,
            height,
        }
    }

    /// The pixel index and radiance a photon of `power` landed at `s` adds (see the module
    /// docs for the derivation), or None if the eye does not see it.
    pub(super) fn connect(
        &self,
        bvh: &SceneBvh,
        s: &Surface,
        albedo: Vec3,
        photon_dir: Vec3,
        power: Vec3,
        rays: &mut u64,
    ) -> Option<(usize, Vec3)> {
        let (w_c, distance) = self.camera.toward_camera(s.p);
        if !(distance > 0.0) {
            return None;
        }
        let cos_surface = s.ng.dot(w_c); // camera on the lit side?
        let cos_camera = self.forward.dot(-w_c); // cos theta_c
        if cos_surface <= 0.0 || cos_camera <= 0.0 {
            return None;
        }
        let px = self
            .camera
            .project_with(&self.view_proj, s.p, self.width, self.height)?;
        let pixel = crate::pixel_at(px, self.width, self.height)?;
        *rays += 1;
        let origin = s.above();
        // The eye, or the point of an orthographic camera's film that sees s.p.
        let film = s.p + w_c * distance;
        let seg = film - origin;
        let len = seg.length();
        if bvh.any_hit(origin, seg / len, len) {
            return None;
        }
        // Irradiance measured with the shading normal, like the direct term.
        let w_i = -photon_dir;
        let cos_i_g = s.ng.dot(w_i).max(1e-6);
        let correction = (s.ns.dot(w_i).max(0.0) / cos_i_g).min(MAX_SHADING_CORRECTION);
        let importance = self.film.importance(cos_camera, distance);
        let seen = self.media.transmittance(film, -w_c, distance)
            * self
                .medium
                .map_or(Vec3::ONE, |m| m.transmittance(film, -w_c, distance));
        let value = power * albedo * FRAC_1_PI * (correction * cos_surface * importance * seen);
        Some((pixel, value))
    }
}
