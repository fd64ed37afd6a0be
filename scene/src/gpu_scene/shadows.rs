//! Distance shadow maps: the lights' cube and fitted layers, the casters' own maps, and the fitting.

use super::*;

/// Distance shadow maps for the scene's lights, laid out as the shared scene binds them: six
/// cube-array layers per light (used by lights inside the scene) and one fitted 2D layer per
/// light (lights outside it; 1 texel when no light is), `R32Float` distances from the light.
pub(super) struct ShadowTextures {
    pub(super) cubes: wgpu::Texture,
    pub(super) face_views: Vec<wgpu::TextureView>,
    pub(super) depth_views: Vec<wgpu::TextureView>,
    pub(super) cube_view: wgpu::TextureView,
    pub(super) fitted_views: Vec<wgpu::TextureView>,
    pub(super) fitted_array_view: wgpu::TextureView,
}

impl ShadowTextures {
    /// The cube maps' distances, layer by layer (six per light), read back.
    pub(super) fn read(&self, ctx: &Context) -> Result<Vec<Vec<u8>>, gpu::GpuError> {
        (0..self.cubes.depth_or_array_layers())
            .map(|layer| gpu::read_texture_bytes(ctx, &self.cubes, layer, 4))
            .collect()
    }

    pub(super) fn new(
        ctx: &Context,
        lights: usize,
        any_fitted: bool,
        size: u32,
        label: &str,
    ) -> Self {
        let layers = 6 * lights.max(1) as u32;
        let cubes = gpu::render_texture(
            ctx,
            label,
            (size, size, layers),
            SHADOW_FORMAT,
            wgpu::TextureUsages::COPY_SRC,
        );
        let depth = gpu::depth_texture(ctx, size, size, 6, label);
        let fitted_size = if any_fitted { size } else { 1 };
        let fitted = gpu::render_texture(
            ctx,
            label,
            (fitted_size, fitted_size, lights.max(1) as u32),
            SHADOW_FORMAT,
            wgpu::TextureUsages::empty(),
        );
        Self {
            face_views: (0..layers).map(|l| gpu::layer_view(&cubes, l)).collect(),
            depth_views: (0..6).map(|l| gpu::layer_view(&depth, l)).collect(),
            cube_view: cubes.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::CubeArray),
                ..Default::default()
            }),
            fitted_views: (0..lights.max(1) as u32)
                .map(|l| gpu::layer_view(&fitted, l))
                .collect(),
            fitted_array_view: fitted.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            cubes,
        }
    }
}

/// Shadow maps of a chosen set of casters, at the scene's shadow-map resolution and in its
/// layout, for a technique that needs visibility other than the scene's: an engine's light,
/// for one, that transparent surfaces do not shadow (`ObjectFilter::Except(glass)`). The
/// technique draws them when it needs them ([`Self::render`], every face: its own time) and
/// binds [`Self::cube_view`] and [`Self::fitted_view`] where `light_visibility_in` (scene.wgsl)
/// reads them; the scene's own maps are [`GpuScene::shadow_views`].
pub struct CasterShadowMaps {
    pub(super) maps: ShadowTextures,
    pub(super) filter: ObjectFilter,
}

impl CasterShadowMaps {
    /// Maps for `scene`'s lights whose casters are the objects `filter` selects.
    pub fn new(ctx: &Context, scene: &GpuScene, filter: ObjectFilter) -> Self {
        let size = scene.shadows.cubes.width();
        let any_fitted = scene.fitted.iter().any(Option::is_some);
        let label = "caster shadow maps";
        Self {
            maps: ShadowTextures::new(ctx, scene.scene.lights.len(), any_fitted, size, label),
            filter,
        }
    }

    /// Draws every light's maps (all faces) with the scene at its current time.
    pub fn render(&self, frame: &mut Frame, scene: &GpuScene) {
        scene.render_shadow_faces(frame, &self.maps, &self.filter, None);
    }

    /// The cube maps' distances, layer by layer (six per light), read back (tests).
    pub fn read(&self, ctx: &Context) -> Result<Vec<Vec<u8>>, gpu::GpuError> {
        self.maps.read(ctx)
    }

    /// The cube maps, one cube per light (`texture_cube_array<f32>`).
    pub fn cube_view(&self) -> &wgpu::TextureView {
        &self.maps.cube_view
    }

    /// The fitted 2D maps, one layer per light (`texture_2d_array<f32>`).
    pub fn fitted_view(&self) -> &wgpu::TextureView {
        &self.maps.fitted_array_view
    }
}

/// A 2D shadow map for a light outside the scene: a perspective view from the light that just
/// holds the scene's bounding sphere (a cube face would cover the scene with few texels); for
/// a directional light, an orthographic view along its direction that holds the sphere.
#[derive(Clone, Copy, Debug)]
pub(super) struct FittedShadow {
    pub(super) view_proj: Mat4,
    pub(super) tan_half_fov: f32,
    /// An orthographic map's eye (behind the sphere, whence its distances are measured) and
    /// half width; `None` and 0 for a perspective map, whose eye is the light.
    pub(super) eye: Option<Vec3>,
    pub(super) half_width: f32,
}

impl FittedShadow {
    /// `None` when the light is inside (or near) the bounding sphere: it keeps its cube map.
    pub(super) fn for_light(light: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        let d = light.distance(center);
        if !(d > radius * 1.5) || radius <= 0.0 {
            return None;
        }
        let half = (radius / d).asin() * 1.02;
        let dir = (center - light) / d;
        let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let view = glam::camera::rh::view::look_at_mat4(light, center, up);
        let near = ((d - radius) * 0.9).max(0.01);
        let proj =
            glam::camera::rh::proj::directx::perspective(2.0 * half, 1.0, near, (d + radius) * 1.1);
        Some(Self {
            view_proj: proj * view,
            tan_half_fov: half.tan(),
            eye: None,
            half_width: 0.0,
        })
    }

    /// The map of a directional light travelling along `direction`: orthographic, holding the
    /// sphere, seen from an eye two radii behind its centre. The shadow pass stores the
    /// distance from that eye, which grows monotonically along every ray of the light through
    /// the sphere (each ray's closest point to the eye lies behind the sphere), so it orders
    /// the surfaces along the ray as a depth along the direction would.
    pub(super) fn for_direction(direction: Vec3, center: Vec3, radius: f32) -> Self {
        let radius = radius.max(1e-3);
        let half = radius * 1.02;
        let eye = center - direction * (2.0 * radius);
        let up = if direction.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = glam::camera::rh::view::look_to_mat4(eye, direction, up);
        let proj = glam::camera::rh::proj::directx::orthographic(
            -half,
            half,
            -half,
            half,
            0.5 * radius,
            3.5 * radius,
        );
        Self {
            view_proj: proj * view,
            tan_half_fov: 0.0,
            eye: Some(eye),
            half_width: half,
        }
    }
}

/// Whether a sphere (centre `c` relative to the light, radius `r`) may reach cube face `face`
/// (+X, -X, +Y, -Y, +Z, -Z, as `gpu::cube::cube_face_view_proj` orders them): the face sees the
/// directions whose largest component is its axis, `s p_a >= |p_b|` and `s p_a >= |p_c|`, four
/// half-spaces through the light; the sphere reaches the face unless it lies wholly outside
/// one of them. Conservative: a sphere near a corner may be said to reach a face it misses.
pub fn sphere_meets_cube_face(c: Vec3, r: f32, face: usize) -> bool {
    let axis = face / 2;
    let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
    let along = sign * c[axis];
    let reach = r * std::f32::consts::SQRT_2;
    (0..3)
        .filter(|&k| k != axis)
        .all(|k| along - c[k] >= -reach && along + c[k] >= -reach)
}

/// Bounding sphere of every object over its motion and deformation (centre of the box of all
/// world vertices at time 0 and of the morph targets placed there, radius grown by the
/// largest motion offset): a morphed vertex lies between its base and target positions.
pub(super) fn scene_bounding_sphere(scene: &Scene) -> (Vec3, f32) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let mut travel: f32 = 0.0;
    for o in &scene.objects {
        let world = o.world_at(0.0);
        let target = o.morph.iter().flat_map(|m| &m.positions);
        for p in o.mesh.positions.iter().chain(target) {
            let w = world.transform_point3(*p);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        travel = o
            .motion
            .keys
            .iter()
            .map(|(_, v)| v.length())
            .fold(travel, f32::max);
    }
    if !lo.is_finite() {
        return (Vec3::ZERO, 0.0);
    }
    let center = (lo + hi) * 0.5;
    (center, center.distance(hi) + travel)
}

/// Each light's fitted 2D shadow map, for directional lights and for point and spot lights
/// outside the scene's bounding sphere (`None`: the light is inside and uses its cube).
pub(super) fn fitted_shadows(scene: &Scene) -> Vec<Option<FittedShadow>> {
    let (center, radius) = scene_bounding_sphere(scene);
    scene
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Directional { direction } => {
                Some(FittedShadow::for_direction(direction, center, radius))
            }
            _ => FittedShadow::for_light(l.position, center, radius),
        })
        .collect()
}
