//! Cube-map render targets rendered face by face (a one-layer 2D view per face, sampled back
//! through a cube view), and the per-face view-projection matrices that agree texel for texel
//! with the prelude's `cube_dir_to_face_uv`.

#[cfg(test)]
use glam::Vec4;
use glam::{Mat4, Vec3};

/// (s, t, m) axes of each face: sc = s.d, tc = t.d, ma = m.d for d = p - centre, in layer
/// order +X, -X, +Y, -Y, +Z, -Z (the Vulkan/D3D cube convention).
const FACE_AXES: [[Vec3; 3]; 6] = [
    [Vec3::NEG_Z, Vec3::NEG_Y, Vec3::X],
    [Vec3::Z, Vec3::NEG_Y, Vec3::NEG_X],
    [Vec3::X, Vec3::Z, Vec3::Y],
    [Vec3::X, Vec3::NEG_Z, Vec3::NEG_Y],
    [Vec3::X, Vec3::NEG_Y, Vec3::Z],
    [Vec3::NEG_X, Vec3::NEG_Y, Vec3::NEG_Z],
];

/// World -> clip matrix of cube face `face` seen from `center`, depth in [0, 1] from `near` to
/// `far`. NDC x = sc/ma and NDC y = -tc/ma, so texel (u, v) of the rendered face is exactly
/// the texel the prelude addresses for that direction. Faces differ in handedness: render
/// cube faces without back-face culling.
pub fn cube_face_view_proj(face: usize, center: Vec3, near: f32, far: f32) -> Mat4 {
    let [s, t, m] = FACE_AXES[face];
    let a = far / (far - near);
    let b = -far * near / (far - near);
    let rows = Mat4::from_cols(
        s.extend(0.0),
        (-t).extend(0.0),
        (a * m).extend(b),
        m.extend(0.0),
    )
    .transpose();
    rows * Mat4::from_translation(-center)
}

/// Normalised direction of the texel centre (i, j) of face `face` in a `size` x `size` face.
pub fn cube_texel_dir(face: u32, i: u32, j: u32, size: u32) -> Vec3 {
    let u = (i as f32 + 0.5) / size as f32;
    let v = (j as f32 + 0.5) / size as f32;
    crate::prelude::cube_face_uv_to_dir(face, u, v).normalize()
}

/// A cube map with a depth cube beside it, each face renderable on its own.
pub struct CubeTarget {
    pub size: u32,
    pub format: wgpu::TextureFormat,
    pub color: wgpu::Texture,
    pub depth: wgpu::Texture,
    /// One single-layer 2D view per face, for use as a colour attachment.
    pub face_views: Vec<wgpu::TextureView>,
    pub depth_face_views: Vec<wgpu::TextureView>,
    /// The whole map as a cube, for sampling.
    pub cube_view: wgpu::TextureView,
}

impl CubeTarget {
    /// GPU memory of a cube target of `size` texels per side and colour `format`: six colour
    /// faces and six depth faces ([`crate::DEPTH_FORMAT`]).
    pub fn bytes(size: u32, format: wgpu::TextureFormat) -> u64 {
        let texel = format.block_copy_size(None).unwrap_or(16) as u64 + 4;
        6 * size as u64 * size as u64 * texel
    }

    pub fn new(
        ctx: &crate::Context,
        size: u32,
        format: wgpu::TextureFormat,
        label: &str,
    ) -> Result<Self, crate::GpuError> {
        let max = ctx.device.limits().max_texture_dimension_2d;
        if size == 0 || size > max {
            return Err(crate::GpuError::SizeOverLimit {
                width: size,
                height: size,
                max,
            });
        }
        let color = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 6,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let depth = crate::depth_texture(ctx, size, size, 6, label);
        Ok(Self {
            size,
            format,
            face_views: (0..6).map(|f| crate::layer_view(&color, f)).collect(),
            depth_face_views: (0..6).map(|f| crate::layer_view(&depth, f)).collect(),
            cube_view: color.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::Cube),
                ..Default::default()
            }),
            color,
            depth,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Projecting a direction through a face matrix lands on the texel the prelude addresses.
    #[test]
    fn face_matrices_agree_with_prelude_addressing() {
        let center = Vec3::new(0.3, -0.2, 0.5);
        for k in 0..500u32 {
            let d = Vec3::new(
                crate::prelude::hash_to_unit(3 * k) * 2.0 - 1.0,
                crate::prelude::hash_to_unit(3 * k + 1) * 2.0 - 1.0,
                crate::prelude::hash_to_unit(3 * k + 2) * 2.0 - 1.0,
            );
            if d.length() < 1e-3 {
                continue;
            }
            let fuv = crate::prelude::cube_dir_to_face_uv(d);
            let clip = cube_face_view_proj(fuv.x as usize, center, 0.01, 100.0)
                * Vec4::from((center + d * 2.0, 1.0));
            let ndc = clip / clip.w;
            assert!((ndc.x - (2.0 * fuv.y - 1.0)).abs() < 1e-4, "u for {d}");
            assert!((ndc.y - (1.0 - 2.0 * fuv.z)).abs() < 1e-4, "v for {d}");
            assert!((0.0..=1.0).contains(&ndc.z));
        }
    }
}
