//! The volumes of a frame placed for drawing: camera-facing billboard axes, back-to-front
//! order, the records the volume pass reads, the billboards' extent, and the thickness
//! texture baked from the first volume (`bake`).

use super::*;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GlobalsGpu {
    pub(crate) view_proj: [[f32; 4]; 4],
    pub(crate) inv_view_proj: [[f32; 4]; 4],
    pub(crate) eye: [f32; 4],
    pub(crate) viewport: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct VolumeGpu {
    pub(super) center: [f32; 4],
    pub(super) right: [f32; 4],
    pub(super) up: [f32; 4],
    pub(super) normal: [f32; 4],
    pub(super) color: [f32; 4],
}

/// A volume placed for one frame, with its camera-facing billboard axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedVolume {
    /// Index of the volume in `Scene::volumes`.
    pub index: usize,
    /// World-space centre at the frame's time (motion applied).
    pub center: Vec3,
    /// Radius of the bounding sphere (metres).
    pub radius: f32,
    /// Linear RGB radiance of the medium where it is opaque (`Volume::color`).
    pub color: Vec3,
    /// [`opacity_scale`] with the logarithmic function; [`VolumeTechnique`] recomputes it
    /// for its own function.
    pub density: f32,
    /// Unit billboard right axis, in the plane (the camera's right made perpendicular to the
    /// normal).
    pub right: Vec3,
    /// Unit billboard up axis, in the plane.
    pub up: Vec3,
    /// Unit billboard normal, from the centre toward the eye.
    pub normal: Vec3,
    /// Distance from the eye to the centre (the sort key).
    pub distance: f32,
}

/// The volumes of `set` at `time`, with billboards facing `camera`'s eye, sorted back to
/// front (farthest centre first). A billboard's normal points from its centre to the eye;
/// its right axis is the camera's right made perpendicular to that normal, so billboards
/// keep the camera's roll. With the eye at the centre the normal is the camera's backward
/// axis.
pub fn placed_volumes(
    volumes: &[Volume],
    set: VolumeSet,
    camera: &Camera,
    time: f32,
) -> Vec<PlacedVolume> {
    placed_volumes_facing(volumes, set, camera.eye, camera.basis(), time)
}

/// [`placed_volumes`] for an eye at `eye` whose (forward, right, up) axes are `basis`: what a
/// renderer with a camera of its own passes ([`crate::SoftVolumePass`]).
pub fn placed_volumes_facing(
    volumes: &[Volume],
    set: VolumeSet,
    eye: Vec3,
    (forward, cam_right, cam_up): (Vec3, Vec3, Vec3),
    time: f32,
) -> Vec<PlacedVolume> {
    let mut out: Vec<PlacedVolume> = volumes
        .iter()
        .enumerate()
        .filter(|(_, v)| set.includes(v))
        .map(|(index, v)| {
            let center = v.center + v.motion.offset(time);
            let to_eye = eye - center;
            let distance = to_eye.length();
            let normal = if distance > 1e-6 * v.radius.max(1e-6) {
                to_eye / distance
            } else {
                -forward
            };
            let mut right = cam_right - normal * cam_right.dot(normal);
            if right.length_squared() < 1e-8 {
                right = cam_up.cross(normal);
            }
            let right = right.normalize();
            let up = normal.cross(right);
            let density = opacity_scale(v, OpacityFn::Log);
            PlacedVolume {
                index,
                center,
                radius: v.radius,
                color: v.color,
                density,
                right,
                up,
                normal,
                distance,
            }
        })
        .collect();
    out.sort_by(|a, b| b.distance.total_cmp(&a.distance));
    out
}

impl VolumeTechnique {
    /// The thickness texture: baked from the first volume of the variant's set as seen from
    /// the scene's default camera at time 0 (the artist's view), or the plain sphere profile
    /// when the set is empty.
    pub(super) fn bake(&self, scene: &Scene) -> (Vec<u8>, Option<Baked>) {
        if !self.uses_texture() {
            return (crate::path_length::thickness_texels(), None);
        }
        let placed = placed_volumes(&scene.volumes, self.variant.set, &scene.camera, 0.0);
        let Some(first) = placed.iter().min_by_key(|p| p.index) else {
            return (crate::path_length::thickness_texels(), None);
        };
        let volume = &scene.volumes[first.index];
        let (texels, scale) = bake_thickness(
            volume,
            [first.right, first.up, first.normal],
            self.variant.opacity,
        );
        (
            texels,
            Some(Baked {
                volume: first.index,
                scale,
            }),
        )
    }
}

/// Beyond this ratio of eye distance to radius a fitted billboard covers the silhouette;
/// closer, the ray-traced pass draws a screen-filling quad.
pub(super) const FIT_MIN_DISTANCE: f32 = 1.05;

impl VolumeTechnique {
    /// The GPU record of a placed volume: billboard half size (metres) and whether to draw a
    /// screen-filling quad instead.
    pub(crate) fn volume_record(&self, v: &PlacedVolume, volumes: &[Volume]) -> VolumeGpu {
        let (half_size, screen) = billboard_extent(
            v,
            self.settings.billboard_scale,
            self.settings.fit_silhouette && self.is_raytraced(),
        );
        let baked = self
            .gpu
            .as_ref()
            .and_then(|r| r.baked.as_ref())
            .filter(|b| b.volume == v.index);
        let scale = match baked {
            Some(b) if self.uses_texture() => b.scale,
            _ => volumes
                .get(v.index)
                .map_or(v.density, |s| opacity_scale(s, self.variant.opacity)),
        };
        VolumeGpu {
            center: v.center.extend(v.radius).to_array(),
            right: v.right.extend(scale).to_array(),
            up: v.up.extend(half_size).to_array(),
            normal: v.normal.extend(if screen { 1.0 } else { 0.0 }).to_array(),
            color: v.color.extend(1.0).to_array(),
        }
    }
}

/// Half size (metres) of a volume's billboard, and whether a screen-filling quad replaces it.
/// Without `fit`: `scale * R` (thesis). With `fit`: the plane through the centre facing the eye
/// meets the silhouette cone of the sphere at radius `R D / sqrt(D^2 - R^2)` (D the eye
/// distance); 1% more covers it. Closer than `FIT_MIN_DISTANCE` (1.05) R (or inside) no billboard
/// through the centre can cover the sphere, so the whole screen is drawn.
pub fn billboard_extent(v: &PlacedVolume, scale: f32, fit: bool) -> (f32, bool) {
    let r = v.radius;
    if !fit {
        return (scale * r, false);
    }
    let d = v.distance;
    if d < FIT_MIN_DISTANCE * r {
        return (scale * r, true);
    }
    let cover = 1.01 * r * d / (d * d - r * r).sqrt();
    (cover.max(scale * r), false)
}
