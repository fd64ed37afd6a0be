//! What a variant prepares (pipelines, layouts, budgets, Wyman's per-vertex thickness) and
//! the resources that follow the view's size.

use super::*;

impl State {
    /// (Re)makes the buffers and bind groups when the view's size changes.
    pub(super) fn ensure_screen(&mut self, ctx: &Context, width: u32, height: u32) {
        if self
            .screen
            .as_ref()
            .is_some_and(|s| s.width == width && s.height == height)
        {
            return;
        }
        let size = (width, height, 1);
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let none = wgpu::TextureUsages::empty();
        let front = gpu::render_texture(ctx, "front buffer", size, BUFFER_FORMAT, none);
        let back = gpu::render_texture(ctx, "back buffer", size, BUFFER_FORMAT, none);
        let depth = gpu::depth_texture(ctx, width, height, 1, "front/back depth");
        let scene_color = gpu::render_texture(
            ctx,
            "scene colour",
            size,
            gpu::HDR_FORMAT,
            wgpu::TextureUsages::COPY_DST,
        );
        let (front, back, depth, scene_color_view) =
            (view(&front), view(&back), view(&depth), view(&scene_color));
        let group = |cube: &CubeTarget, params: &Uniform<ParamsGpu>| {
            bind::group(
                ctx,
                "image-space refraction",
                &self.layout,
                &[
                    bind::view(&cube.cube_view),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                    params.binding(),
                    self.eye.binding(),
                    bind::view(&front),
                    bind::view(&back),
                    bind::view(&scene_color_view),
                    self.normal_thickness.as_entire_binding(),
                ],
            )
        };
        let groups = self
            .maps
            .iter()
            .map(|m| group(&m.cube, &m.params))
            .collect();
        let impostor_groups = self
            .maps
            .iter()
            .map(|m| group(m.full_cube.as_ref().unwrap_or(&m.cube), &m.impostor_params))
            .collect();
        self.screen = Some(Screen {
            width,
            height,
            front,
            back,
            depth,
            scene_color,
            groups,
            impostor_groups,
        });
    }
}

/// The caustic textures against the map budget and the adapter's largest storage binding
/// (each of the two caustic buffers is bound whole).
pub(super) fn check_caustic_budget(
    ctx: &Context,
    id: &str,
    settings: &CausticSettings,
    rects: &Rectangles,
) -> TechniqueResult<()> {
    let layers: usize = rects.refractors.iter().map(|r| r.members.len()).sum();
    let texels = u64::from(settings.resolution).pow(2);
    // Counts (3 x u32) and irradiance (vec4f) per texel.
    check_map_budget(id, layers, texels * 28, "caustic_resolution")?;
    let largest = texels * 16 * layers.max(1) as u64;
    let limit = u64::from(ctx.device.limits().max_storage_buffer_binding_size);
    if largest > limit {
        return Err(TechniqueError::OverBudget(format!(
            "{id}: {layers} caustic textures of {r} x {r} texels need a {largest}-byte storage \
             buffer, past this adapter's largest binding ({limit} bytes): lower \
             caustic_resolution",
            r = settings.resolution
        )));
    }
    Ok(())
}

/// `@group(2)` of refract.wgsl.
pub(super) fn group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "image-space refraction",
        wgpu::ShaderStages::VERTEX_FRAGMENT,
        &[
            bind::texture_cube(),            // env_map
            bind::sampler(),                 // env_sampler
            bind::uniform(),                 // params
            bind::uniform(),                 // eye_params
            bind::texture_2d_unfilterable(), // front_buffer
            bind::texture_2d_unfilterable(), // back_buffer
            bind::texture_2d_unfilterable(), // scene_color
            bind::storage(true),             // normal_thickness
        ],
    )
}

/// The buffer pipelines (front, back) and the refractor's pipeline; with `nearby` (its
/// `@group(3)` last in `layouts`) the rays leaving the refractor meet the rectangle impostors
/// first (`image_space_refraction::nearby_radiance` overriding `outgoing_radiance`), and the
/// photon pass is made.
pub(super) fn pipelines(
    ctx: &Context,
    scene: &GpuScene,
    layouts: &[&wgpu::BindGroupLayout],
    nearby: bool,
    formats: gpu::TargetFormats,
) -> Pipelines {
    let overrides: &[&gpu::wgsl::Module] = match nearby {
        true => &[&NEARBY_RADIANCE],
        false => &[],
    };
    let imports = [&REFRACT, &crate::search::SEARCH, &crate::nearby::NEARBY];
    let shader = |label, source| {
        let shader = gpu::wgsl::Shader::new(label, source)
            .importing(&imports)
            .with_defs(&crate::nearby::NEARBY_DEFS)
            .overriding(overrides);
        scene::shader_of(ctx, shader)
    };
    let module = shader("image-space refraction", REFRACT_PASSES_WGSL);
    let buffers_layout = scene.pipeline_layout_with(ctx, &[]);
    let buffer_pipeline = |entry: &str| {
        scene::scene_pipeline_with(
            ctx,
            entry,
            &buffers_layout,
            &module,
            entry,
            &[gpu::pass::color_target(BUFFER_FORMAT, None)],
            (true, wgpu::CompareFunction::Less),
        )
    };
    let refract_layout = scene.pipeline_layout_with(ctx, layouts);
    let refractor_pipeline = |fragment: (&wgpu::ShaderModule, &str), targets: &[_], depth| {
        let depth = gpu::pass::depth_state_for(depth, true, wgpu::CompareFunction::Less);
        scene::scene_pipeline_with_depth(
            ctx,
            fragment.1,
            &refract_layout,
            ((&module, "refractor_vs"), fragment),
            targets,
            depth,
        )
    };
    let refract = refractor_pipeline(
        (&module, "refract_fs"),
        &[formats.color_target()],
        formats.depth,
    );
    let photon = nearby.then(|| {
        let photons = shader("image-space refraction photons", PHOTON_WGSL);
        refractor_pipeline(
            (&photons, "photon_fs"),
            &[
                gpu::pass::color_target(BUFFER_FORMAT, None),
                gpu::pass::color_target(BUFFER_FORMAT, None),
            ],
            gpu::DEPTH_FORMAT,
        )
    });
    Pipelines {
        front: buffer_pipeline("front_buffer_fs"),
        back: buffer_pipeline("back_buffer_fs"),
        refract,
        photon,
    }
}

/// The pipelines of one shader module.
pub(super) struct Pipelines {
    pub(super) front: wgpu::RenderPipeline,
    pub(super) back: wgpu::RenderPipeline,
    pub(super) refract: wgpu::RenderPipeline,
    /// The photon pass (with nearby geometry only: photons land on the rectangles).
    pub(super) photon: Option<wgpu::RenderPipeline>,
}

/// Wyman's `d_N`: per vertex of each specular object, the distance along the inward normal
/// to the object's other side at time 0 (0 without a hit), at the vertex's place in the
/// scene's vertex buffer; 0 for other objects. The precomputation the paper does away with:
/// it is stale once the object deforms.
pub fn normal_thickness(scene: &GpuScene, objects: &[usize]) -> Vec<f32> {
    let total: usize = scene
        .scene
        .objects
        .iter()
        .map(|o| o.mesh.positions.len())
        .sum();
    let mut thickness = vec![0.0; total.max(1)];
    if objects.is_empty() {
        return thickness;
    }
    let bvh = scene::bvh::SceneBvh::build(&scene.scene, 0.0);
    for &object in objects {
        let o = &scene.scene.objects[object];
        let world = o.world_at(0.0);
        let normals = o.normal_matrix_at(0.0);
        let offset = 1e-4 * o.bounding_radius_at(0.0).max(1e-3);
        let base = scene.draws[object].base_vertex as usize;
        // As the BVH places the object at time 0 (a morph's weight there included).
        let (positions, object_normals) = (o.positions_at(0.0), o.normals_at(0.0));
        for (i, (p, n)) in positions.iter().zip(object_normals.iter()).enumerate() {
            let inward = -(normals * *n).normalize_or_zero();
            if inward == Vec3::ZERO {
                continue;
            }
            let origin = world.transform_point3(*p) + inward * offset;
            if let Some(hit) = bvh.closest_hit_where(origin, inward, f32::MAX, |h| h == object) {
                thickness[base + i] = hit.t + offset;
            }
        }
    }
    thickness
}

pub(super) fn storage_buffer(ctx: &Context, label: &str, data: &[f32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// An eye for the uniform's first contents (overwritten before every frame).
pub(super) fn placeholder_eye() -> Eye {
    Eye {
        view_proj: Mat4::IDENTITY,
        position: Vec3::ZERO,
        forward: Vec3::NEG_Z,
        width: 1,
        height: 1,
    }
}
