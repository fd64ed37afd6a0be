//! The pinhole camera as the light pass sees it.

use super::*;

/// The pinhole camera as the light pass sees it: where a point lands on the image and
/// what one pixel's importance is.
pub(super) struct Eye<'a> {
    pub(super) camera: Camera,
    /// Media between a landed photon and the eye attenuate it, as they attenuate the eye
    /// pass's view of the same point.
    pub(super) media: &'a Media,
    /// So does the scattering medium.
    pub(super) medium: Option<&'a Medium>,
    pub(super) forward: Vec3,
    pub(super) width: u32,
    pub(super) height: u32,
    /// Area of one pixel on the image plane at unit distance.
    pub(super) pixel_area: f32,
}

impl<'a> Eye<'a> {
    pub(super) fn new(
        camera: &Camera,
        width: u32,
        height: u32,
        media: &'a Media,
        medium: Option<&'a Medium>,
    ) -> Self {
        let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = width as f32 / height as f32;
        Eye {
            camera: *camera,
            media,
            medium,
            forward: (camera.target - camera.eye).normalize(),
            width,
            height,
            pixel_area: (2.0 * tan_half) * (2.0 * tan_half) * aspect
                / (width as f32 * height as f32),
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
        let to_eye = self.camera.eye - s.p;
        let d2 = to_eye.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let w_c = to_eye / d2.sqrt();
        let cos_surface = s.ng.dot(w_c); // eye on the lit side?
        let cos_camera = self.forward.dot(-w_c); // cos theta_c
        if cos_surface <= 0.0 || cos_camera <= 0.0 {
            return None;
        }
        let px = self.camera.project(s.p, self.width, self.height)?;
        if !(px.x >= 0.0 && px.y >= 0.0 && px.x < self.width as f32 && px.y < self.height as f32) {
            return None;
        }
        let (x, y) = (
            (px.x as u32).min(self.width - 1),
            (px.y as u32).min(self.height - 1),
        );
        *rays += 1;
        let origin = s.above();
        let seg = self.camera.eye - origin;
        let len = seg.length();
        if bvh.any_hit(origin, seg / len, len) {
            return None;
        }
        // Irradiance measured with the shading normal, like the direct term.
        let w_i = -photon_dir;
        let cos_i_g = s.ng.dot(w_i).max(1e-6);
        let correction = (s.ns.dot(w_i).max(0.0) / cos_i_g).min(MAX_SHADING_CORRECTION);
        let importance = 1.0 / (self.pixel_area * cos_camera * cos_camera * cos_camera);
        let seen = self.media.transmittance(self.camera.eye, -w_c, d2.sqrt())
            * self.medium.map_or(Vec3::ONE, |m| {
                m.transmittance(self.camera.eye, -w_c, d2.sqrt())
            });
        let value =
            power * albedo * FRAC_1_PI * (correction * cos_surface / d2 * importance * seen);
        Some(((y * self.width + x) as usize, value))
    }
}
