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

/// `count` cube maps in one texture (`6 * count` layers: cube `c`'s face `f` is layer
/// `6 c + f`), sampled through one `texture_cube_array` view, so one bind group (and one draw
/// call) can reach the maps of many objects. Faces are rendered one at a time with a shared
/// six-layer depth texture. Needs the adapter's cube-array support (the scene's shadow maps
/// need it too).
pub struct CubeArray {
    pub size: u32,
    pub count: u32,
    pub format: wgpu::TextureFormat,
    pub color: wgpu::Texture,
    /// One single-layer 2D view per face of every cube (`6 * count`), for colour attachments.
    pub face_views: Vec<wgpu::TextureView>,
    /// Depth views of the six faces, shared by all cubes.
    pub depth_face_views: Vec<wgpu::TextureView>,
    /// All cubes as one `CubeArray` view, for sampling.
    pub array_view: wgpu::TextureView,
}

impl CubeArray {
    /// GPU memory of `count` cubes of `size` texels per side in `format` (plus the shared
    /// depth faces).
    pub fn bytes(size: u32, count: u32, format: wgpu::TextureFormat) -> u64 {
        let texel = format.block_copy_size(None).unwrap_or(16) as u64;
        let face = size as u64 * size as u64;
        face * (6 * count as u64 * texel + 6 * 4)
    }

    pub fn new(
        ctx: &crate::Context,
        size: u32,
        count: u32,
        format: wgpu::TextureFormat,
        label: &str,
    ) -> Result<Self, crate::GpuError> {
        let limits = ctx.device.limits();
        if size == 0 || size > limits.max_texture_dimension_2d {
            return Err(crate::GpuError::SizeOverLimit {
                width: size,
                height: size,
                max: limits.max_texture_dimension_2d,
            });
        }
        let layers = 6 * count.max(1);
        if layers > limits.max_texture_array_layers {
            return Err(crate::GpuError::InvalidInput(format!(
                "{label}: {count} cube maps need {layers} texture layers; this adapter allows {}",
                limits.max_texture_array_layers
            )));
        }
        let color = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let depth = crate::depth_texture(ctx, size, size, 6, label);
        Ok(Self {
            size,
            count,
            format,
            face_views: (0..layers).map(|f| crate::layer_view(&color, f)).collect(),
            depth_face_views: (0..6).map(|f| crate::layer_view(&depth, f)).collect(),
            array_view: color.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::CubeArray),
                ..Default::default()
            }),
            color,
        })
    }

    /// Records copies of cubes `cubes` from `self` into the same cubes of `to` (same size
    /// and format).
    pub fn copy_cubes_to(&self, encoder: &mut wgpu::CommandEncoder, to: &CubeArray, cubes: &[u32]) {
        for &c in cubes {
            let at = |texture| wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: 6 * c,
                },
                aspect: wgpu::TextureAspect::All,
            };
            encoder.copy_texture_to_texture(
                at(&self.color),
                at(&to.color),
                wgpu::Extent3d {
                    width: self.size,
                    height: self.size,
                    depth_or_array_layers: 6,
                },
            );
        }
    }

    /// Records a copy of the six faces of `cube` (a [`CubeTarget`] of the same size and
    /// format) into cube `c` of the array.
    pub fn copy_from_cube(&self, encoder: &mut wgpu::CommandEncoder, cube: &CubeTarget, c: u32) {
        let at = |texture, z| wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z },
            aspect: wgpu::TextureAspect::All,
        };
        encoder.copy_texture_to_texture(
            at(&cube.color, 0),
            at(&self.color, 6 * c),
            wgpu::Extent3d {
                width: self.size,
                height: self.size,
                depth_or_array_layers: 6,
            },
        );
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
