//! The interior-mapping techniques (`interior-mapping/...`) and the polygon baseline.

use crate::textures::{self, FURNITURE_FRAMES, FURNITURE_LAYER, VARIANTS};
use glam::{Mat4, Vec3};
use gpu::cube::CubeTarget;
use gpu::pass::{self, Load};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Target, Uniform, Vertex, bind};
use scene::Settings as _;
use scene::technique::{Declared, check_param, not_prepared, set_checked, setting_if};
use scene::{
    Frame, GpuScene, Material, Object, ObjectFilter, Param, RasterTarget, Roles, Scene, Technique,
    TechniqueResult, View,
};

const TECHNIQUE_WGSL: &str = include_str!("shaders/technique.wgsl");
/// Face size of the reflection cube map of `interior-mapping/exterior` and `interior-mapping/reflection-only`.
pub const ENV_MAP_SIZE: u32 = 64;
/// Refractive index of the window glass (Fresnel weight of the reflection).
pub const GLASS_IOR: f32 = 1.5;
/// Animation rate of the furniture sprite (frames per second).
pub const FURNITURE_FPS: f32 = 2.0;

/// Which of the paper's versions a technique renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Ceilings, floors and walls with lighting, flat colours (figure 5.13 top left).
    Basic,
    /// Four textures: floor, ceiling, two wall orientations (figure 5.13 bottom left).
    Textured,
    /// Textured, with the window glass reflecting an environment cube map (5.2.3).
    Exterior,
    /// Textured plus an alpha-tested, animated furniture plane (5.2.4).
    Furniture,
    /// Per-room lights, texture atlas variation and displaced walls (5.4).
    Varied,
    /// Baseline of 5.3.2: only the ceilings textured, walls and floors flat colours, lit
    /// (figure 5.13 top right).
    CeilingOnly,
    /// Baseline of 5.3.2: all four surfaces read from one texture (a 2 x 2 atlas), the tile
    /// chosen per hit from the plane family.
    SingleTexture,
    /// Baseline of 5.3 and 5.3.2: no interior at all, the windows fully reflect the
    /// environment cube map (the traditional building material the paper's ~5x is measured
    /// against).
    ReflectionOnly,
    /// Engine baseline: cube-map interiors (Unreal's `InteriorCubemap`): one pre-rendered room
    /// cube map looked up toward the exit of the room box (`rooms::cubemap_room`).
    Cubemap,
    /// Cube-map interiors with the per-window variation engines use: one of
    /// [`textures::VARIANTS`] room cube maps and a mirroring of each horizontal axis per room.
    CubemapVaried,
}

impl Variant {
    /// Every variant, in the order of `interior_mapping::techniques()` (without pre-pass).
    pub const ALL: [Variant; 10] = [
        Variant::Basic,
        Variant::Textured,
        Variant::Exterior,
        Variant::Furniture,
        Variant::Varied,
        Variant::CeilingOnly,
        Variant::SingleTexture,
        Variant::ReflectionOnly,
        Variant::Cubemap,
        Variant::CubemapVaried,
    ];
    fn name(self) -> &'static str {
        match self {
            Variant::Basic => "basic",
            Variant::Textured => "textured",
            Variant::Exterior => "exterior",
            Variant::Furniture => "furniture",
            Variant::Varied => "varied",
            Variant::CeilingOnly => "ceiling-only",
            Variant::SingleTexture => "single-texture",
            Variant::ReflectionOnly => "reflection-only",
            Variant::Cubemap => "cubemap",
            Variant::CubemapVaried => "cubemap-varied",
        }
    }
    /// The variant number the shader branches on (`Settings.a.x` in technique.wgsl).
    fn code(self) -> f32 {
        self as u32 as f32
    }
    /// Whether the windows reflect the environment cube map (rendered every frame).
    fn uses_env_map(self) -> bool {
        matches!(self, Variant::Exterior | Variant::ReflectionOnly)
    }
    /// Whether the rooms come from room cube maps (the engine baseline).
    pub fn uses_room_cubes(self) -> bool {
        matches!(self, Variant::Cubemap | Variant::CubemapVaried)
    }
    /// Room cube maps in the atlas: [`textures::VARIANTS`] for the varied cube maps, else 1.
    pub fn room_cube_count(self) -> u32 {
        match self {
            Variant::CubemapVaried => VARIANTS,
            Variant::Cubemap => 1,
            _ => 0,
        }
    }
}

/// `supports`: the scene has building objects with a room layout.
pub fn has_buildings(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| o.roles.contains(Roles::BUILDING) && o.building.is_some())
}

/// Whether the building's mesh is a facade with real window holes (the `city` scene's real
/// interiors): interior mapping then draws its closed bounding box instead.
pub fn has_window_holes(o: &Object) -> bool {
    o.name.contains("window holes")
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BuildingGpu {
    world_to_object: [[f32; 4]; 4],
    grid_origin: [f32; 4],
    room_size: [f32; 4],
    displacement: [f32; 4],
    hull_max: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SettingsGpu {
    a: [f32; 4],
    b: [f32; 4],
}

/// First index, index count and base vertex of a hull drawn from this technique's buffers.
type HullRange = (u32, u32, i32);

/// One interior-mapping variant, with or without a depth pre-pass.
pub struct InteriorMapping {
    /// What the rooms show (flat colours, textures, reflections, furniture...).
    pub variant: Variant,
    /// Depth-only pass over the hulls first, then shading with `LessEqual` (the `-prepass`
    /// ids): each pixel is shaded once.
    pub prepass: bool,
    /// The parameters.
    pub settings: Settings,
    state: Option<State>,
}

/// The parameters of an [`InteriorMapping`] variant, each declared once
/// ([`scene::Settings`]); which a variant has follows its `variant`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The variant (what decides which parameters it has).
    pub variant: Variant,
    /// Multiplies each building's room size (parameter `room_scale`).
    pub room_scale: f32,
    /// Interior texture size, texels per side (parameter `texture_resolution`).
    pub texture_resolution: u32,
    /// `varied`: probability that a room's light is on (parameter `light_probability`).
    pub light_probability: f32,
    /// Unshadowed room light, radiance = albedo x value (parameter `interior_light`; 0 matches
    /// the reference).
    pub interior_light: f32,
    /// `furniture`: depth of the furniture plane behind the facade, in rooms (parameter
    /// `furniture_depth`).
    pub furniture_depth: f32,
    /// `varied`: largest wall displacement, in rooms (parameter `displacement`).
    pub displacement: f32,
    /// Room surfaces of box hulls lit only through the windows (exact); false: the scene's
    /// shadow maps, as the polygon baseline.
    pub room_shadows: bool,
}

impl Settings {
    /// Whether rooms are cast (all but `reflection-only`, whose only parameter is the window
    /// grid's `room_scale`).
    fn casts_rooms(&self) -> bool {
        self.variant != Variant::ReflectionOnly
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "room_scale",
            (0.05, 20.0),
            "multiplies each building's room size",
            |s| Some(&mut s.room_scale),
        ),
        Declared::new(
            "texture_resolution",
            (16.0, 256.0),
            "room cube map face size (texels per side; one face spans a room face as one \
             interior texture does)",
            |s| {
                let cubes = s.casts_rooms() && s.variant.uses_room_cubes();
                setting_if(cubes, &mut s.texture_resolution)
            },
        ),
        Declared::new(
            "texture_resolution",
            (16.0, 256.0),
            "interior texture size (texels per side)",
            |s| {
                let textures = s.casts_rooms() && !s.variant.uses_room_cubes();
                setting_if(textures, &mut s.texture_resolution)
            },
        ),
        Declared::new(
            "room_shadows",
            (0.0, 1.0),
            "1: rooms of box hulls lit only through their windows (exact); 0: the scene's \
             shadow maps, like interior-mapping/polygons",
            |s| setting_if(s.casts_rooms(), &mut s.room_shadows),
        ),
        Declared::new(
            "interior_light",
            (0.0, 100.0),
            "unshadowed room light: radiance = albedo * value (0 matches the reference)",
            |s| setting_if(s.casts_rooms(), &mut s.interior_light),
        ),
        Declared::new(
            "light_probability",
            (0.0, 1.0),
            "probability that a room's light is on (c in 5.4.1)",
            |s| setting_if(s.variant == Variant::Varied, &mut s.light_probability),
        ),
        Declared::new(
            "displacement",
            (0.0, crate::rooms::MAX_DISPLACEMENT as f64),
            "largest wall displacement (rooms)",
            |s| setting_if(s.variant == Variant::Varied, &mut s.displacement),
        ),
        Declared::new(
            "furniture_depth",
            (0.0, 1.0),
            "furniture plane depth behind the facade (rooms)",
            |s| setting_if(s.variant == Variant::Furniture, &mut s.furniture_depth),
        ),
    ];
}

struct State {
    pipeline: wgpu::RenderPipeline,
    /// The same shading writing the room surface's depth (eye inside a hull).
    pipeline_inside: wgpu::RenderPipeline,
    /// (world-to-object, bounds min, bounds max) of every hull.
    hull_boxes: Vec<(Mat4, Vec3, Vec3)>,
    prepass: Option<wgpu::RenderPipeline>,
    bind_group: wgpu::BindGroup,
    settings: Uniform<SettingsGpu>,
    hull_vertices: wgpu::Buffer,
    hull_indices: wgpu::Buffer,
    /// (object, Some(first index, count, base vertex) for an own bounding box, None: its mesh)
    hulls: Vec<(usize, Option<HullRange>)>,
    building_objects: Vec<usize>,
    env: Option<CubeTarget>,
    /// Bytes of interior texture data uploaded in `prepare` (surface layers or room faces).
    texture_bytes: u64,
}

impl InteriorMapping {
    /// The technique of `variant` (with a depth pre-pass if `prepass`) with the default
    /// parameters.
    pub fn new(variant: Variant, prepass: bool) -> Self {
        let varied = variant == Variant::Varied;
        let settings = Settings {
            variant,
            room_scale: 1.0,
            texture_resolution: 64,
            light_probability: 0.5,
            interior_light: if varied { 0.3 } else { 0.0 },
            furniture_depth: 0.4,
            displacement: if varied { 0.3 } else { 0.0 },
            room_shadows: true,
        };
        Self {
            variant,
            prepass,
            settings,
            state: None,
        }
    }
}

impl Technique for InteriorMapping {
    fn id(&self) -> String {
        format!(
            "interior-mapping/{}{}",
            self.variant.name(),
            if self.prepass { "-prepass" } else { "" }
        )
    }
    /// The depth pre-pass only changes the cost: the default compare shows it once
    /// (`textured-prepass`); the other `-prepass` variants run with `compare --all-variants`.
    fn representative(&self) -> bool {
        !self.prepass || self.variant == Variant::Textured
    }
    fn description(&self) -> String {
        let what = match self.variant {
            Variant::Basic => "rooms by per-pixel ray cast against plane families, lit, untextured",
            Variant::Textured => {
                "rooms by per-pixel ray cast, four textures (floor, ceiling, two walls)"
            }
            Variant::Exterior => {
                "textured rooms through windows blended with a reflection cube map"
            }
            Variant::Furniture => "textured rooms plus an alpha-tested animated furniture plane",
            Variant::Varied => "per-room lights by probability, atlas variation, displaced walls",
            Variant::CeilingOnly => {
                "baseline: only ceilings textured, walls and floors flat colours, lit"
            }
            Variant::SingleTexture => {
                "baseline: all surfaces from one 2x2 atlas texture, tile chosen per hit"
            }
            Variant::ReflectionOnly => {
                "baseline: no interior, windows fully reflect a cube map (traditional material)"
            }
            Variant::Cubemap => {
                "engine baseline: cube-map interiors, one room cube map looked up at the exit of \
                 the room box (Unreal's InteriorCubemap)"
            }
            Variant::CubemapVaried => {
                "engine baseline: cube-map interiors, a random room cube map of four and a \
                 random mirroring per room"
            }
        };
        format!(
            "interior mapping: {what}{}",
            if self.prepass {
                " (depth pre-pass)"
            } else {
                ""
            }
        )
    }
    fn params(&self) -> Vec<Param> {
        self.settings.params()
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id(), &mut self.settings, name, value)
    }
    fn supports(&self, scene: &Scene) -> bool {
        has_buildings(scene)
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let s = &scene.scene;
        let time = scene.time();
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
        if hulls.is_empty() {
            return Err(scene::TechniqueError::Unsupported(format!(
                "{} needs building objects with a room layout; scene {} has none",
                self.id(),
                s.name
            )));
        }
        vertices.push(Vertex::default());
        indices.extend([0, 0, 0]);
        let device = &ctx.device;
        let buffer = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let buildings = buffer(
            "interior buildings",
            bytemuck::cast_slice(&records),
            wgpu::BufferUsages::STORAGE,
        );
        let settings = Uniform::new(
            ctx,
            "interior settings",
            &SettingsGpu {
                a: [0.0; 4],
                b: [0.0; 4],
            },
        );
        let hull_vertices = buffer(
            "interior hulls",
            bytemuck::cast_slice(&vertices),
            wgpu::BufferUsages::VERTEX,
        );
        let hull_indices = buffer(
            "interior hull indices",
            bytemuck::cast_slice(&indices),
            wgpu::BufferUsages::INDEX,
        );

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
        let env_size = if self.variant.uses_env_map() {
            ENV_MAP_SIZE
        } else {
            1
        };
        let env = CubeTarget::new(
            ctx,
            env_size,
            wgpu::TextureFormat::Rgba16Float,
            "interior reflection map",
        )?;
        let layout = bind::layout(
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
        );
        // Room textures tile (repeat); the reflection map is a cube map, whose sampling
        // ignores the address modes.
        let samplers = &ctx.samplers;
        let bind_group = bind::group(
            ctx,
            "interior mapping",
            &layout,
            &[
                buildings.as_entire_binding(),
                settings.binding(),
                bind::view(&texture_view),
                bind::sampler_resource(&samplers.linear_repeat),
                bind::view(&env.cube_view),
                bind::sampler_resource(&samplers.linear_clamp),
                bind::view(&atlas_view),
                bind::view(&room_faces_view),
            ],
        );
        let source = format!(
            "{}\n{}\n{}",
            scene::SCENE_WGSL,
            crate::INTERIOR_WGSL,
            TECHNIQUE_WGSL
        );
        let module = gpu::shader_with_prelude(ctx, "interior mapping", &source);
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        let pipeline = hull_pipeline(
            ctx,
            &pipeline_layout,
            &module,
            Some("interior_fs"),
            !self.prepass,
        );
        let pipeline_inside = hull_pipeline(
            ctx,
            &pipeline_layout,
            &module,
            Some("interior_inside_fs"),
            !self.prepass,
        );
        let prepass = self
            .prepass
            .then(|| hull_pipeline(ctx, &pipeline_layout, &module, None, true));
        self.state = Some(State {
            pipeline,
            pipeline_inside,
            hull_boxes,
            prepass,
            bind_group,
            settings,
            hull_vertices,
            hull_indices,
            hulls,
            building_objects: s.objects_with(Roles::BUILDING),
            env: self.variant.uses_env_map().then_some(env),
            texture_bytes,
        });
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let state = self.state.as_ref().ok_or_else(|| not_prepared(self))?;
        let eye = view.camera.eye;
        if let Some(env) = &state.env {
            // The reflection map: the scene around the eye (buildings' hulls included as drawn by
            // the shared pass), regenerated every frame.
            frame.span("regenerate", |frame| {
                scene.raster_cube(frame, env, eye, &ObjectFilter::All, true);
            });
        }
        let frame_index = ((view.time * FURNITURE_FPS).floor().max(0.0) as u32) % FURNITURE_FRAMES;
        let settings = SettingsGpu {
            a: [
                self.variant.code(),
                self.settings.light_probability,
                self.settings.interior_light,
                frame_index as f32,
            ],
            b: [
                self.settings.furniture_depth,
                GLASS_IOR,
                if self.settings.room_shadows { 1.0 } else { 0.0 },
                0.0,
            ],
        };
        state.settings.write(frame.gpu, &settings);

        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget::of(target, true);
        scene.raster(
            frame,
            &main,
            view_proj,
            eye,
            &ObjectFilter::Except(state.building_objects.clone()),
            true,
        );
        let camera = scene.camera_bind_group(frame.gpu, view_proj, eye);
        // The hulls' own passes (pre-pass and interior mapping), timed apart from the shared
        // raster pass as span "interior" (encoder timestamps around the passes).
        frame.span("interior", |frame| {
            if let Some(prepass) = &state.prepass {
                let mut pass = pass::begin(
                    frame.encoder,
                    "interior depth pre-pass",
                    &[],
                    Some(pass::depth(&target.depth_view, Load::Keep)),
                    None,
                );
                pass.set_pipeline(prepass);
                pass.set_bind_group(0, &camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &state.bind_group, &[]);
                draw_hulls(&mut pass, state, scene);
            }
            let mut pass = scene::begin_scene_pass(
                frame.encoder,
                &RasterTarget {
                    clear: false,
                    ..main
                },
                scene.scene.background,
                "interior mapping",
            );
            let inside = state.hull_boxes.iter().any(|(to_object, lo, hi)| {
                let e = to_object.transform_point3(eye);
                e.cmpgt(*lo).all() && e.cmplt(*hi).all()
            });
            pass.set_pipeline(if inside {
                &state.pipeline_inside
            } else {
                &state.pipeline
            });
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            pass.set_bind_group(2, &state.bind_group, &[]);
            draw_hulls(&mut pass, state, scene);
            drop(pass);
        });
        Ok(())
    }
}

impl InteriorMapping {
    /// Bytes of interior texture data uploaded by the last `prepare` (None before it): the
    /// memory figure reported beside error and time.
    pub fn texture_bytes(&self) -> Option<u64> {
        self.state.as_ref().map(|s| s.texture_bytes)
    }
}

fn draw_hulls(pass: &mut wgpu::RenderPass<'_>, state: &State, scene: &GpuScene) {
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

fn hull_pipeline(
    ctx: &Context,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment_entry: Option<&str>,
    write_depth: bool,
) -> wgpu::RenderPipeline {
    let shade = fragment_entry.is_some();
    let targets = [pass::color_target(gpu::HDR_FORMAT, None)];
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(if shade {
                "interior mapping"
            } else {
                "interior depth pre-pass"
            }),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
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
            depth_stencil: Some(pass::depth_state(
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
fn single_texture_view(ctx: &Context, variant: Variant, size: u32) -> wgpu::TextureView {
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
fn room_faces_view(ctx: &Context, variant: Variant, size: u32) -> (wgpu::TextureView, u64) {
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
fn srgb_texture(ctx: &Context, label: &str, side: u32, layers: u32, data: &[u8]) -> wgpu::Texture {
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

/// The baseline: the same rooms as real geometry (a facade with window holes and planes
/// spanning each box hull, as the paper's polygonised building), drawn by the shared raster
/// pass. Box hulls that already have real interiors in the scene are kept as they are;
/// curved hulls (cylinder, sphere) stay solid.
pub struct PolygonInteriors {
    /// Multiplies each building's room size (parameter `room_scale`).
    pub room_scale: f32,
    /// Interior texture size, texels per side (parameter `texture_resolution`).
    pub texture_resolution: u32,
    state: Option<GpuScene>,
}

impl Default for PolygonInteriors {
    fn default() -> Self {
        Self {
            room_scale: 1.0,
            texture_resolution: 64,
            state: None,
        }
    }
}

/// The scene with real room geometry in every box building (what `interior-mapping/polygons` draws).
pub fn polygon_scene(scene: &Scene, room_scale: f32, texture_resolution: u32) -> Scene {
    let mut out = scene.clone();
    let base = out.textures.len();
    out.textures
        .extend(textures::scene_textures(texture_resolution));
    let mut added = Vec::new();
    for o in &mut out.objects {
        let Some(b) = o.building else { continue };
        if !o.name.contains("(box)") || has_window_holes(o) {
            continue;
        }
        let (lo, hi) = o.mesh.bounds();
        let room = b.room_size * room_scale;
        o.mesh = crate::geometry::facade_with_windows(lo, hi, room);
        o.name = o.name.replace("(box)", "(box, window holes)");
        for (family, name, texture) in [
            (1u32, "floors", 0usize),
            (4, "ceilings", 1),
            (0, "walls x", 2),
            (2, "walls z", 3),
        ] {
            let material = Material::Diffuse {
                albedo: Vec3::ONE,
                texture: Some(base + texture),
            };
            let mut planes = Object::new(
                &format!("{} {name}", o.name),
                crate::geometry::room_planes(lo, hi, room, family),
                material,
                o.transform,
            )
            .with_roles(Roles::BUILDING);
            planes.motion = o.motion.clone();
            added.push(planes);
        }
    }
    out.objects.extend(added);
    out
}

impl Technique for PolygonInteriors {
    fn id(&self) -> String {
        "interior-mapping/polygons".into()
    }
    fn description(&self) -> String {
        "baseline: the same rooms as real geometry (facade with window holes, room planes) through the shared raster pass".into()
    }
    fn params(&self) -> Vec<Param> {
        vec![
            Param {
                name: "room_scale",
                default: self.room_scale as f64,
                min: 0.05,
                max: 20.0,
                integer: false,
                help: "multiplies each building's room size",
            },
            Param {
                name: "texture_resolution",
                default: self.texture_resolution as f64,
                min: 16.0,
                max: 256.0,
                integer: true,
                help: "interior texture size (texels per side)",
            },
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id(), &self.params(), name, value)?;
        match name {
            "room_scale" => self.room_scale = value as f32,
            _ => self.texture_resolution = value as u32,
        }
        Ok(())
    }
    fn supports(&self, scene: &Scene) -> bool {
        has_buildings(scene)
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let modified = polygon_scene(&scene.scene, self.room_scale, self.texture_resolution);
        self.state = Some(GpuScene::new(frame.gpu, &modified)?);
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        _scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let Some(state) = self.state.as_mut() else {
            return Err(not_prepared(self));
        };
        state.set_time(frame, view.time);
        let view_proj: Mat4 = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget::of(target, true);
        state.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::All,
            true,
        );
        Ok(())
    }
}

/// Every variant: the eight interior-mapping versions (five of the paper's, three baselines
/// of 5.3.2) with and without a depth pre-pass, and the polygon baseline.
pub fn all() -> Vec<Box<dyn Technique>> {
    let mut out: Vec<Box<dyn Technique>> = Vec::new();
    for v in Variant::ALL {
        out.push(Box::new(InteriorMapping::new(v, false)));
        out.push(Box::new(InteriorMapping::new(v, true)));
    }
    out.push(Box::new(PolygonInteriors::default()));
    out
}
