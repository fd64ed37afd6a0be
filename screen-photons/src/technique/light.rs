//! The light's view of the casters: the scene's box, the casters' sphere, the view matrix.

use super::*;

/// A box holding every object's bounding sphere at `time`.
pub(super) fn scene_box(scene: &Scene, time: f32) -> (Vec3, Vec3) {
    scene.objects.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), o| {
            let (c, r) = (o.center_at(time), Vec3::splat(o.bounding_radius_at(time)));
            (lo.min(c - r), hi.max(c + r))
        },
    )
}

/// The bounding sphere of the caustic casters (specular objects and those with the
/// `CAUSTIC_CASTER` role) at `time`.
pub fn casters_sphere(scene: &Scene, time: f32) -> (Vec3, f32) {
    let casters: Vec<_> = scene
        .objects
        .iter()
        .filter(|o| o.material.is_specular() || o.roles.contains(scene::Roles::CAUSTIC_CASTER))
        .collect();
    let (lo, hi) = casters.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), o| {
            let (c, r) = (o.center_at(time), o.bounding_radius_at(time));
            (lo.min(c - Vec3::splat(r)), hi.max(c + Vec3::splat(r)))
        },
    );
    let centre = (lo + hi) * 0.5;
    let radius = casters
        .iter()
        .map(|o| (o.center_at(time) - centre).length() + o.bounding_radius_at(time))
        .fold(0.0, f32::max);
    (centre, radius)
}

/// The casters' bounding sphere at `time` when `light` lies outside it (a transfer map is one
/// view from the light, which cannot hold casters around it: the reference emits over the
/// whole sphere there), else why not.
pub fn light_outside_casters(
    scene: &Scene,
    light: &scene::Light,
    time: f32,
) -> TechniqueResult<(Vec3, f32)> {
    let (centre, radius) = casters_sphere(scene, time);
    if centre.is_finite() && light.position.distance(centre) > radius * 1.05 {
        return Ok((centre, radius));
    }
    Err(TechniqueError::Unsupported(format!(
        "light \"{}\" lies inside the bounding sphere of the caustic casters (centre {centre}, \
         radius {radius:.3} m): a transfer map is one view from the light and cannot hold casters \
         around it",
        light.name
    )))
}

/// The light's view of the casters' sphere (`scene::lightmap::LightView`): its matrix, the
/// transfer uniform, and the photon spacing at the sphere's centre.
pub(super) fn light_view(
    light: &scene::Light,
    centre: Vec3,
    radius: f32,
    grid: u32,
    jitter: bool,
) -> (Mat4, TransferParamsGpu, f32) {
    let view = scene::lightmap::LightView::of_sphere(light.position, centre, radius, grid);
    let params = TransferParamsGpu {
        light: light.position.extend(1.0).to_array(),
        intensity: light.intensity.extend(0.0).to_array(),
        axis: view.axis.extend(view.pixel_area).to_array(),
        jitter: jitter as u32,
        _pad: [0; 3],
    };
    (view.view_proj, params, view.spacing())
}
