//! What the upload writes: the bind group layouts, the packed meshes, the per-object records and the albedo texture array.

use super::*;

pub(super) fn pipeline_layout(
    ctx: &Context,
    camera: &wgpu::BindGroupLayout,
    scene: &wgpu::BindGroupLayout,
    extra: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let mut layouts: Vec<Option<&wgpu::BindGroupLayout>> = vec![Some(camera), Some(scene)];
    layouts.extend(extra.iter().map(|l| Some(*l)));
    ctx.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene pipeline layout"),
            bind_group_layouts: &layouts,
            immediate_size: 0,
        })
}

pub(super) fn camera_bind_group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
    bind::layout(ctx, "camera", stages, &[bind::uniform()])
}

/// The first four bindings of `@group(1)`: objects, lights, albedo textures and their sampler,
/// all that `scene_vs` and `shadow_fs` read (the object's place, its alpha cut-out). The shadow
/// pass binds these alone ([`surfaces_only_layout`]); the scene group begins with them.
fn surface_bindings() -> [wgpu::BindingType; 4] {
    [
        bind::storage(true),      // objects
        bind::storage(true),      // lights
        bind::texture_2d_array(), // albedo textures
        bind::sampler(),          // albedo sampler
    ]
}

/// [`surface_bindings`] alone: what the shadow pass, which writes the shadow maps, may bind.
pub(super) fn surfaces_only_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
    bind::layout(ctx, "scene surfaces only", stages, &surface_bindings())
}

/// `@group(1)` of scene.wgsl.
pub(super) fn scene_bind_group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    use wgpu::TextureViewDimension::{CubeArray, D2Array};
    let stages = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
    let mut types = surface_bindings().to_vec();
    types.extend([
        bind::texture(CubeArray, false), // shadow cube maps
        bind::sampler_non_filtering(),   // shadow sampler
        bind::uniform(),                 // scene info
        bind::texture(D2Array, false),   // fitted shadow maps
    ]);
    bind::layout(ctx, "scene", stages, &types)
}

pub(super) fn pack_meshes(objects: &[Object]) -> (Vec<Vertex>, Vec<u32>, Vec<DrawRange>) {
    let (mut vertices, mut indices, mut draws) = (Vec::new(), Vec::new(), Vec::new());
    for o in objects {
        draws.push(DrawRange {
            first_index: indices.len() as u32,
            index_count: o.mesh.indices.len() as u32,
            base_vertex: vertices.len() as i32,
        });
        indices.extend_from_slice(&o.mesh.indices);
        vertices.extend(object_vertices(o, 0.0));
    }
    (vertices, indices, draws)
}

/// The object-space vertices of `o` at `time` (a deforming object's morph blended in), in the
/// shared vertex buffer's layout: the upload packs them at time 0, `set_time` rewrites a
/// deforming object's range.
pub(super) fn object_vertices(o: &Object, time: f32) -> Vec<Vertex> {
    o.positions_at(time)
        .iter()
        .zip(o.normals_at(time).iter())
        .zip(&o.mesh.uvs)
        .map(|((p, n), uv)| Vertex {
            position: p.to_array(),
            normal: n.to_array(),
            uv: uv.to_array(),
        })
        .collect()
}

pub(super) fn object_records(scene: &Scene, time: f32) -> Vec<ObjectGpu> {
    scene
        .objects
        .iter()
        .map(|o| {
            let normal = Mat4::from_mat3(o.normal_matrix_at(time));
            let (albedo, kind, ior, n, k) = match &o.material {
                Material::Diffuse {
                    albedo, texture, ..
                } => (
                    albedo.extend(texture.map_or(-1.0, |t| t as f32)),
                    0.0,
                    1.0,
                    Vec3::ZERO,
                    Vec3::ZERO,
                ),
                Material::Metal { n, k } => (Vec4::new(0.7, 0.7, 0.7, -1.0), 1.0, 1.0, *n, *k),
                Material::Glass { ior } => (
                    Vec4::new(0.7, 0.7, 0.7, -1.0),
                    2.0,
                    *ior,
                    Vec3::ZERO,
                    Vec3::ZERO,
                ),
            };
            ObjectGpu {
                model: o.world_at(time).to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
                albedo: albedo.to_array(),
                material: [
                    kind,
                    ior,
                    o.roles.bits() as f32,
                    o.material.cutout().map_or(0.0, |(_, c)| c),
                ],
                n: n.extend(0.0).to_array(),
                k: k.extend(0.0).to_array(),
                emission: o.emission.extend(0.0).to_array(),
            }
        })
        .collect()
}

/// Width and height of the layers of the albedo texture array that holds `textures`: the
/// widest texture's width and the tallest one's height (1 x 1 without textures).
pub fn albedo_array_extent(textures: &[crate::Texture]) -> (u32, u32) {
    let width = textures.iter().map(|t| t.width).max().unwrap_or(1);
    let height = textures.iter().map(|t| t.height).max().unwrap_or(1);
    (width, height)
}

/// Uploads all diffuse textures as layers of one `Rgba8UnormSrgb` array (the GPU decodes
/// sRGB then filters bilinearly, exactly what `Texture::sample` does). The array is as wide
/// as the widest texture and as tall as the tallest (never padded to a square: a 16384 x 2
/// texture costs 128 KiB, not 1 GiB); textures of other sizes are resampled to it (nearest),
/// which only imported glTF scenes with mixed sizes hit.
pub(super) fn upload_textures(
    ctx: &Context,
    scene: &Scene,
) -> Result<wgpu::TextureView, SceneError> {
    let (width, height) = albedo_array_extent(&scene.textures);
    ctx.check_size(width, height)?;
    let layers = scene.textures.len().max(1) as u32;
    let mut data = Vec::with_capacity(width as usize * height as usize * 4 * layers as usize);
    if scene.textures.is_empty() {
        data.extend_from_slice(&[255, 255, 255, 255]);
    }
    for t in &scene.textures {
        for j in 0..height as u64 {
            for i in 0..width as u64 {
                let x = i * t.width as u64 / width as u64;
                let y = j * t.height as u64 / height as u64;
                let o = 4 * (y * t.width as u64 + x) as usize;
                data.extend_from_slice(&t.rgba8[o..o + 4]);
            }
        }
    }
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("albedo textures"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &data,
    );
    Ok(texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    }))
}

/// The scene's vertex, index and object buffers (every mesh packed into one vertex and one
/// index buffer, object records at time 0) and each object's draw range.
pub(super) fn mesh_buffers(
    ctx: &Context,
    scene: &Scene,
) -> (wgpu::Buffer, wgpu::Buffer, wgpu::Buffer, Vec<DrawRange>) {
    let device = &ctx.device;
    let (vertices, indices, draws) = pack_meshes(&scene.objects);
    let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scene vertices"),
        contents: bytemuck::cast_slice(&vertices),
        // COPY_DST: `set_time` rewrites the vertices of deforming objects.
        usage: wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST,
    });
    let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scene indices"),
        contents: bytemuck::cast_slice(&indices),
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
    });
    let object_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scene objects"),
        contents: bytemuck::cast_slice(&object_records(scene, 0.0)),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    });
    (vertex_buffer, index_buffer, object_buffer, draws)
}

/// The lights' records (position, intensity, fitted shadow projection; one zero light when
/// there is none, as a storage buffer may not be empty) and the count of real lights.
pub(super) fn light_records(
    scene: &Scene,
    fitted: &[Option<FittedShadow>],
) -> (Vec<LightGpu>, u32) {
    let mut lights: Vec<LightGpu> = scene
        .lights
        .iter()
        .zip(fitted)
        .map(|(l, f)| light_record(l, f.as_ref()))
        .collect();
    let light_count = lights.len() as u32;
    if lights.is_empty() {
        lights.push(LightGpu {
            position: [0.0; 4],
            intensity: [0.0; 4],
            shadow_view_proj: Mat4::IDENTITY.to_cols_array_2d(),
            shadow_params: [1.0, 0.0, 0.0, 0.0],
            direction: [0.0; 4],
            cone: [0.0; 4],
        });
    }
    (lights, light_count)
}

/// One light's record as `scene.wgsl`'s `LightGpu` reads it. A directional light's position
/// is its fitted map's eye (the distances its shadow map holds are measured from there), and
/// it always has a fitted map ([`FittedShadow::for_direction`]).
fn light_record(l: &Light, f: Option<&FittedShadow>) -> LightGpu {
    let (kind, direction, cone) = l.shader_fields();
    let position = f.and_then(|f| f.eye).unwrap_or(l.position);
    LightGpu {
        position: position
            .extend(if f.is_some() { 1.0 } else { 0.0 })
            .to_array(),
        intensity: l.intensity.extend(0.0).to_array(),
        shadow_view_proj: f.map_or(Mat4::IDENTITY, |f| f.view_proj).to_cols_array_2d(),
        shadow_params: [
            f.map_or(1.0, |f| f.tan_half_fov),
            f.map_or(0.0, |f| f.half_width),
            0.0,
            0.0,
        ],
        direction: direction.extend(kind).to_array(),
        cone,
    }
}
