//! The camera: a pinhole or an orthographic view, its rays, and how light tracing reaches its
//! image.

use super::sample_keys;
use glam::{Mat4, Vec2, Vec3};

/// A camera: eye, target, up, and either a pinhole's vertical field of view in degrees or an
/// orthographic view's height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// The pinhole's vertical field of view; unused by an orthographic camera.
    pub fov_y_deg: f32,
    /// `Some(h)`: an orthographic camera whose view is `2 h` high in world units (glTF's
    /// `ymag`), every ray parallel to the view direction and starting on the plane through
    /// `eye` across it; the width follows the image's aspect. `None`: the pinhole at `eye`.
    pub orthographic: Option<f32>,
}

impl Camera {
    pub const NEAR: f32 = 0.01;
    pub const FAR: f32 = 1000.0;

    /// The camera's orthonormal frame `(forward, right, up)`, built robustly: `up` is only a
    /// hint, and when it is zero, not finite or parallel to the view direction (a top-down
    /// camera with up +Y, a skewed glTF camera node) the world's +Y stands in for it, or +Z
    /// when the camera looks along Y. Every renderer (`view`, `ray_dir`, the techniques that
    /// face billboards to the camera) builds its frame here, so none of them can produce a
    /// NaN ray from a camera that `Scene::validate` accepts.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        let hint = if self.up.is_finite() {
            self.up
        } else {
            Vec3::ZERO
        };
        let mut right = forward.cross(hint);
        // Relative test: |forward x up| = sin(angle) |up|.
        if !(right.length_squared() > 1e-10 * hint.length_squared().max(f32::MIN_POSITIVE)) {
            let fallback = if forward.y.abs() < 0.999 {
                Vec3::Y
            } else {
                Vec3::Z
            };
            right = forward.cross(fallback);
        }
        let right = right.normalize();
        (forward, right, right.cross(forward))
    }

    /// World to view matrix (right-handed, looking down -Z), from [`Camera::basis`].
    pub fn view(&self) -> Mat4 {
        let (forward, _, up) = self.basis();
        glam::camera::rh::view::look_to_mat4(self.eye, forward, up)
    }
    /// Perspective (or orthographic) projection with depth in [0, 1] (wgpu convention).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        if let Some(h) = self.orthographic {
            let w = h * aspect;
            return glam::camera::rh::proj::directx::orthographic(
                -w,
                w,
                -h,
                h,
                Self::NEAR,
                Self::FAR,
            );
        }
        glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect,
            Self::NEAR,
            Self::FAR,
        )
    }
    pub fn view_proj(&self, width: u32, height: u32) -> Mat4 {
        self.projection(width as f32 / height as f32) * self.view()
    }
    /// The ray through pixel (x, y), `(origin, unit direction)`: the eye and
    /// [`Camera::ray_dir`] for a pinhole, a point of the plane through the eye and the view
    /// direction for an orthographic camera.
    pub fn ray(&self, x: f32, y: f32, width: u32, height: u32) -> (Vec3, Vec3) {
        let Some(h) = self.orthographic else {
            return (self.eye, self.ray_dir(x, y, width, height));
        };
        let (forward, right, up) = self.basis();
        let aspect = width as f32 / height as f32;
        let sx = (2.0 * x / width as f32 - 1.0) * h * aspect;
        let sy = (1.0 - 2.0 * y / height as f32) * h;
        (self.eye + sx * right + sy * up, forward)
    }
    /// World-space unit direction through pixel (x, y) given in pixels; pixel centres are
    /// at (i + 0.5, j + 0.5) and row 0 is the top, exactly as the rasterizer samples. An
    /// orthographic camera's rays all go along its view direction (their origins differ:
    /// [`Camera::ray`]).
    pub fn ray_dir(&self, x: f32, y: f32, width: u32, height: u32) -> Vec3 {
        let (forward, right, up) = self.basis();
        if self.orthographic.is_some() {
            return forward;
        }
        let tan_half = (self.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = width as f32 / height as f32;
        let sx = (2.0 * x / width as f32 - 1.0) * tan_half * aspect;
        let sy = (1.0 - 2.0 * y / height as f32) * tan_half;
        (forward + sx * right + sy * up).normalize()
    }
    /// Pixel coordinates (continuous) of a world point, or None behind the camera (behind
    /// the plane through an orthographic camera's eye).
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<Vec2> {
        self.project_with(&self.view_proj(width, height), p, width, height)
    }
    /// [`Camera::project`] with the camera's [`Camera::view_proj`] made once by the caller:
    /// for a light pass that projects millions of points.
    pub fn project_with(&self, view_proj: &Mat4, p: Vec3, width: u32, height: u32) -> Option<Vec2> {
        let clip = *view_proj * p.extend(1.0);
        let behind = match self.orthographic {
            Some(_) => self.basis().0.dot(p - self.eye) <= 0.0,
            None => clip.w <= 1e-6,
        };
        if behind {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * width as f32,
            (1.0 - ndc.y) * 0.5 * height as f32,
        ))
    }
    /// Where light leaving `p` toward the camera ends, `(unit direction, distance)`: the eye
    /// of a pinhole; for an orthographic camera, the eye's plane, straight back along the
    /// view direction. Light tracing connects its photons to the image along it.
    #[inline]
    pub fn toward_camera(&self, p: Vec3) -> (Vec3, f32) {
        match self.orthographic {
            Some(_) => {
                let forward = self.basis().0;
                (-forward, forward.dot(p - self.eye))
            }
            None => {
                let to_eye = self.eye - p;
                let d = to_eye.length();
                (to_eye / d, d)
            }
        }
    }
    /// The image's pixels as light tracing sees them (see [`Film`]).
    pub fn film(&self, width: u32, height: u32) -> Film {
        let aspect = width as f32 / height as f32;
        let half = match self.orthographic {
            Some(h) => h,
            None => (self.fov_y_deg.to_radians() * 0.5).tan(),
        };
        Film {
            pixel_area: (2.0 * half) * (2.0 * half) * aspect / (width as f32 * height as f32),
            orthographic: self.orthographic.is_some(),
        }
    }
    /// Whether the scene's view is orthographic (see [`Camera::orthographic`]).
    pub fn is_orthographic(&self) -> bool {
        self.orthographic.is_some()
    }
}

/// A camera's pixels as light tracing sees them: how much a pixel's value gains from light
/// arriving along [`Camera::toward_camera`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Film {
    /// A pinhole's pixel area on the image plane at unit distance; an orthographic camera's
    /// in the world, on the plane through its eye.
    pub pixel_area: f32,
    pub orthographic: bool,
}

impl Film {
    /// The importance of one pixel for light arriving at `cos_camera` to the view direction
    /// from `distance` away, including the spreading of that light (the factor a
    /// light-tracing splat multiplies a point's intensity toward the camera by). A pinhole's
    /// is `1 / (A cos^3 d^2)`; an orthographic camera's film lies in the world and gathers
    /// parallel light, so its is `1 / A` whatever the distance.
    #[inline]
    pub fn importance(&self, cos_camera: f32, distance: f32) -> f32 {
        if self.orthographic {
            return 1.0 / self.pixel_area;
        }
        1.0 / (self.pixel_area * cos_camera * cos_camera * cos_camera) / (distance * distance)
    }
}

/// Keyframed camera for animated runs (`--frames N`): eye, target, fov and an orthographic
/// view's height are interpolated linearly between keys (which `Scene::validate` requires to
/// be all pinholes or all orthographic).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraPath {
    pub keys: Vec<(f32, Camera)>,
}

impl CameraPath {
    pub fn duration(&self) -> f32 {
        self.keys.last().map(|k| k.0).unwrap_or(0.0)
    }
    pub fn sample(&self, time: f32) -> Option<Camera> {
        sample_keys(&self.keys, time, |a, b, s| Camera {
            eye: a.eye.lerp(b.eye, s),
            target: a.target.lerp(b.target, s),
            // Opposite ups cross zero halfway: `Camera::basis` falls back there.
            up: a.up.lerp(b.up, s).normalize_or_zero(),
            fov_y_deg: a.fov_y_deg + (b.fov_y_deg - a.fov_y_deg) * s,
            orthographic: match (a.orthographic, b.orthographic) {
                (Some(ha), Some(hb)) => Some(ha + (hb - ha) * s),
                // Mixed keys, which validation refuses: the nearer key's.
                (ha, hb) => {
                    if s < 0.5 {
                        ha
                    } else {
                        hb
                    }
                }
            },
        })
    }
}
