//! What a variant prepares: the hulls' geometry and records, the room textures, the
//! bindings and pipelines.

use super::*;

/// The building hulls of a scene at one time: each building object's record (its
/// world-to-object transform, room grid, displacement), and for hulls with window holes a
/// box of their own to draw instead of their mesh.
pub(super) struct HullGeometry {
    pub(super) records: Vec<BuildingGpu>,
    pub(super) vertices: Vec<Vertex>,
    pub(super) indices: Vec<u32>,
    pub(super) hulls: Vec<(usize, Option<HullRange>)>,
    pub(super) hull_boxes: Vec<(Mat4, Vec3, Vec3)>,
}

/// The room textures: the thesis's surface textures (or one placeholder texel for cube-map
/// interiors), the single-texture atlas, the room faces, and the bytes they hold.
pub(super) struct RoomTextures {
    pub(super) texture_view: wgpu::TextureView,
    pub(super) atlas_view: wgpu::TextureView,
    pub(super) room_faces_view: wgpu::TextureView,
    pub(super) texture_bytes: u64,
}

impl InteriorMapping {
    /// The hulls' pipelines: the interior from outside, from inside a hull (writing the
    /// room surface's depth), and the depth pre-pass of the `-prepass` variants.
    pub(super) fn hull_pipelines(
        &self,
        ctx: &Context,
        scene: &GpuScene,
        layout: &wgpu::BindGroupLayout,
    ) -> (
        wgpu::RenderPipeline,
        wgpu::RenderPipeline,
        Option<wgpu::RenderPipeline>,
    ) {
        let module =
            scene::shader_importing(ctx, "interior mapping", TECHNIQUE_WGSL, &[&crate::ROOMS]);
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[layout]);
        let writes_depth = !self.prepass;
        let formats = self.formats;
        let shaded = |entry| {
            let fragment = Some(entry);
            hull_pipeline(
                ctx,
                &pipeline_layout,
                (&module, fragment),
                formats,
                writes_depth,
            )
        };
        let prepass = self
            .prepass
            .then(|| hull_pipeline(ctx, &pipeline_layout, (&module, None), formats, true));
        (shaded("interior_fs"), shaded("interior_inside_fs"), prepass)
    }

    /// The building hulls of `s` at `time` (see [`HullGeometry`]).
    pub(super) fn hull_geometry(&self, s: &Scene, time: f32) -> HullGeometry {
        let mut records =
            vec![<BuildingGpu as bytemuck::Zeroable>::zeroed(); s.objects.len().max(1)];
        let (mut vertices, mut indices, mut hulls) =
            (Vec::<Vertex>::new(), Vec::<u32>::new(), Vec::new());
        let mut hull_boxes = Vec::new();
        let mut number = 0.0;
        for (i, o) in s.objects.iter().enumerate() {
            let Some(b) = o.building.filter(|_| o.roles.contains(Roles::BUILDING)) else {
                continue;
            };
            let (lo, hi) = o.mesh.bounds();
            hull_boxes.push((o.world_at(time).inverse(), lo, hi));
            records[i] = BuildingGpu {
                world_to_object: o.world_at(time).inverse().to_cols_array_2d(),
                grid_origin: lo.extend(number).to_array(),
                room_size: (b.room_size * self.settings.room_scale)
                    .extend(1.0)
                    .to_array(),
                displacement: Vec3::new(
                    self.settings.displacement,
                    0.0,
                    self.settings.displacement,
                )
                .extend(if has_window_holes(o) || o.mesh.triangle_count() == 12 {
                    1.0
                } else {
                    0.0
                })
                .to_array(),
                hull_max: hi.extend(0.0).to_array(),
            };
            number += 1.0;
            if has_window_holes(o) {
                let mesh = scene::mesh::cuboid(lo, hi);
                let range = (
                    indices.len() as u32,
                    mesh.indices.len() as u32,
                    vertices.len() as i32,
                );
                indices.extend_from_slice(&mesh.indices);
                vertices.extend(mesh.positions.iter().zip(&mesh.normals).zip(&mesh.uvs).map(
                    |((p, n), uv)| Vertex {
                        position: p.to_array(),
                        normal: n.to_array(),
                        uv: uv.to_array(),
                    },
                ));
                hulls.push((i, Some(range)));
            } else {
                hulls.push((i, None));
            }
        }
        HullGeometry {
            records,
            vertices,
            indices,
            hulls,
            hull_boxes,
        }
    }

    /// The room textures at `texture_resolution` (see [`RoomTextures`]).
    pub(super) fn room_textures(&self, ctx: &Context) -> TechniqueResult<RoomTextures> {
        let size = self.settings.texture_resolution;
        ctx.check_size(size, size)?;
        // The thesis's surface textures (every tint and the furniture frames), or, for the
        // cube-map interiors, which never read them, one placeholder texel.
        let (side, layers, data) = if self.variant.uses_room_cubes() {
            (1, 1, vec![0; 4])
        } else {
            let layers = FURNITURE_LAYER + FURNITURE_FRAMES;
            (size, layers, textures::texture_layers(size))
        };
        // Placeholders are not counted.
        let mut texture_bytes = if self.variant.uses_room_cubes() {
            0
        } else {
            data.len() as u64
        };
        let texture = srgb_texture(ctx, "interior textures", side, layers, &data);
        debug_assert_eq!(VARIANTS * 4, FURNITURE_LAYER);
        let texture_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let atlas_view = single_texture_view(ctx, self.variant, size);
        let (room_faces_view, room_face_bytes) = room_faces_view(ctx, self.variant, size);
        texture_bytes += room_face_bytes;
        Ok(RoomTextures {
            texture_view,
            atlas_view,
            room_faces_view,
            texture_bytes,
        })
    }
}

/// The bindings of the interior pass (`@group(2)`).
pub(super) fn bind_group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "interior mapping",
        wgpu::ShaderStages::FRAGMENT,
        &[
            bind::storage(true),      // buildings
            bind::uniform(),          // settings
            bind::texture_2d_array(), // room_textures
            bind::sampler(),          // room_sampler
            bind::texture_cube(),     // env_map
            bind::sampler(),          // env_sampler
            bind::texture_2d(),       // single_texture
            bind::texture_2d_array(), // room_faces
        ],
    )
}

pub(super) fn draw_hulls(pass: &mut wgpu::RenderPass<'_>, state: &State, scene: &GpuScene) {
    let own: Vec<usize> = state
        .hulls
        .iter()
        .filter(|h| h.1.is_none())
        .map(|h| h.0)
        .collect();
    if !own.is_empty() {
        scene.draw_objects(pass, &ObjectFilter::Only(own));
    }
    pass.set_vertex_buffer(0, state.hull_vertices.slice(..));
    pass.set_index_buffer(state.hull_indices.slice(..), wgpu::IndexFormat::Uint32);
    for &(object, range) in &state.hulls {
        if let Some((first, count, base)) = range {
            let instance = object as u32;
            pass.draw_indexed(first..first + count, base, instance..instance + 1);
        }
    }
}

/// A hulls' pipeline into targets of `formats`: shading with `fragment_entry` of `module`, or
/// the depth pre-pass (`None`).
pub(super) fn hull_pipeline(
    ctx: &Context,
    layout: &wgpu::PipelineLayout,
    (module, fragment_entry): (&wgpu::ShaderModule, Option<&str>),
    formats: gpu::TargetFormats,
    write_depth: bool,
) -> wgpu::RenderPipeline {
    let shade = fragment_entry.is_some();
    let targets = [formats.color_target()];
    let vertex = scene::scene_vertex_module(ctx);
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(if shade {
                "interior mapping"
            } else {
                "interior depth pre-pass"
            }),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: &vertex,
                entry_point: Some("scene_vs"),
                compilation_options: Default::default(),
                buffers: &[Some(Vertex::layout())],
            },
            fragment: fragment_entry.map(|entry| wgpu::FragmentState {
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(pass::depth_state_for(
                formats.depth,
                write_depth,
                if write_depth {
                    wgpu::CompareFunction::Less
                } else {
                    wgpu::CompareFunction::LessEqual
                },
            )),
            multisample: Default::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// The one texture of `interior-mapping/single-texture` (the 2 x 2 atlas of `textures::single_atlas`);
/// a 1 x 1 placeholder for the other variants, which bind but never read it.
pub(super) fn single_texture_view(ctx: &Context, variant: Variant, size: u32) -> wgpu::TextureView {
    let (side, data) = if variant == Variant::SingleTexture {
        (2 * size, textures::single_atlas(size))
    } else {
        (1, vec![0; 4])
    };
    srgb_texture(ctx, "interior single texture", side, 1, &data).create_view(&Default::default())
}

/// The room cube maps of the cube-map interiors (`textures::room_cube_layers`) as a 2D array
/// of six faces per room, addressed in the shader with the prelude's `cube_dir_to_face_uv`
/// (a 2D array rather than a cube array, which some adapters lack); one placeholder texel for
/// the other variants, which bind but never read it. Also returns the bytes uploaded for
/// the cube-map variants (0 for the placeholder).
pub(super) fn room_faces_view(
    ctx: &Context,
    variant: Variant,
    size: u32,
) -> (wgpu::TextureView, u64) {
    let cubes = variant.room_cube_count();
    let (side, layers, data) = if cubes > 0 {
        (size, 6 * cubes, textures::room_cube_layers(size, cubes))
    } else {
        (1, 1, vec![0; 4])
    };
    let bytes = if cubes > 0 { data.len() as u64 } else { 0 };
    let view = srgb_texture(ctx, "interior room faces", side, layers, &data).create_view(
        &wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        },
    );
    (view, bytes)
}

/// Bytes of interior texture data a variant uploads at `size` texels per side (RGBA8): the
/// thesis's surface texture array (four surfaces in [`VARIANTS`] tints and the furniture
/// frames: what every thesis variant binds, whichever layers it reads), or the room faces of
/// the cube-map interiors (six per room cube map). [`InteriorMapping::texture_bytes`] reports
/// what `prepare` actually uploaded.
pub fn interior_texture_bytes(variant: Variant, size: u32) -> u64 {
    let texels = u64::from(size) * u64::from(size) * 4;
    if variant.uses_room_cubes() {
        texels * 6 * u64::from(variant.room_cube_count())
    } else {
        texels * u64::from(FURNITURE_LAYER + FURNITURE_FRAMES)
    }
}

/// A sampled sRGB RGBA8 texture of `layers` square `side` x `side` layers, filled with `data`
/// (layer after layer).
pub(super) fn srgb_texture(
    ctx: &Context,
    label: &str,
    side: u32,
    layers: u32,
    data: &[u8],
) -> wgpu::Texture {
    ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: side,
                height: side,
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
        data,
    )
}
