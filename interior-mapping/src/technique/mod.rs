//! The interior-mapping techniques (`interior-mapping/...`) and the polygon baseline.
//!
//! Where things are: `settings.rs` (the versions and the parameters), `resources.rs` (what
//! `prepare` builds), `polygons.rs` (the polygon baseline); this file, [`InteriorMapping`]
//! and its `Technique` impl.

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

mod polygons;
mod resources;
mod settings;

pub use polygons::*;
pub use resources::*;
pub use settings::*;

const TECHNIQUE_WGSL: &str = include_str!("../shaders/technique.wgsl");
/// Face size of the reflection cube map of `interior-mapping/exterior` and `interior-mapping/reflection-only`.
pub const ENV_MAP_SIZE: u32 = 64;
/// Refractive index of the window glass (Fresnel weight of the reflection).
pub const GLASS_IOR: f32 = 1.5;
/// Animation rate of the furniture sprite (frames per second).
pub const FURNITURE_FPS: f32 = 2.0;

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
    /// The formats of the targets the hulls are drawn into (the harness's, or a renderer's
    /// own: [`InteriorMapping::for_targets`]).
    formats: gpu::TargetFormats,
    state: Option<State>,
}

struct State {
    pipeline: wgpu::RenderPipeline,
    /// The same shading writing the room surface's depth (eye inside a hull).
    pipeline_inside: wgpu::RenderPipeline,
    /// (world-to-object, bounds min, bounds max) of every hull.
    hull_boxes: Vec<(Mat4, Vec3, Vec3)>,
    prepass: Option<wgpu::RenderPipeline>,
    /// Every object's record (`BuildingGpu`), rewritten when a renderer's building moves.
    buildings: wgpu::Buffer,
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
            formats: gpu::TargetFormats::HDR,
            state: None,
        }
    }

    /// The variant drawing its hulls into targets of `formats` (a renderer's own).
    pub fn for_targets(mut self, formats: gpu::TargetFormats) -> Self {
        self.formats = formats;
        self.state = None;
        self
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
        let HullGeometry {
            records,
            mut vertices,
            mut indices,
            hulls,
            hull_boxes,
        } = self.hull_geometry(s, time);
        if hulls.is_empty() {
            return Err(scene::TechniqueError::Unsupported(format!(
                "{} needs building objects with a room layout; scene {} has none",
                self.id(),
                s.name
            )));
        }
        // A degenerate triangle keeps the buffers non-empty when every hull draws its mesh.
        vertices.push(Vertex::default());
        indices.extend([0, 0, 0]);
        let buffer = |label: &str, contents: &[u8], usage| {
            let descriptor = wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            };
            ctx.device.create_buffer_init(&descriptor)
        };
        let buildings = buffer(
            "interior buildings",
            bytemuck::cast_slice(&records),
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        );
        let zero = SettingsGpu {
            a: [0.0; 4],
            b: [0.0; 4],
        };
        let settings = Uniform::new(ctx, "interior settings", &zero);
        let (vertex, index) = (wgpu::BufferUsages::VERTEX, wgpu::BufferUsages::INDEX);
        let hull_vertices = buffer("interior hulls", bytemuck::cast_slice(&vertices), vertex);
        let hull_indices = buffer(
            "interior hull indices",
            bytemuck::cast_slice(&indices),
            index,
        );

        let RoomTextures {
            texture_view,
            atlas_view,
            room_faces_view,
            texture_bytes,
        } = self.room_textures(ctx)?;
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
        let layout = bind_group_layout(ctx);
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
        let (pipeline, pipeline_inside, prepass) = self.hull_pipelines(ctx, scene, &layout);
        self.state = Some(State {
            pipeline,
            pipeline_inside,
            hull_boxes,
            prepass,
            buildings,
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
        self.write_settings(frame, state, view.time);

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
        let targets = (&target.color_view, &target.depth_view);
        self.draw_interiors(frame, scene, state, (&camera, eye), targets);
        Ok(())
    }
}

impl scene::hosted::DrawOver for InteriorMapping {
    /// The buildings of `buildings` (a renderer's objects, uploaded alone with the lights that
    /// shade their rooms) drawn over `color` and `depth` (targets of the formats of
    /// [`InteriorMapping::for_targets`], holding the renderer's frame): with a reflection map,
    /// the renderer's world around the eye asked of `host`; then the hulls, depth-tested
    /// against what is there, each building's rooms where it now stands. The furniture sprite
    /// shows its first frame.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        (buildings, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        // A renderer's buildings move (`set_position_of`): their records and boxes follow.
        let placed = self.hull_geometry(&buildings.scene, 0.0);
        let Some(state) = self.state.as_mut() else {
            return Err(not_prepared(self));
        };
        let records = bytemuck::cast_slice(&placed.records);
        frame.gpu.queue.write_buffer(&state.buildings, 0, records);
        state.hull_boxes = placed.hull_boxes;
        let state = self.state.as_ref().expect("prepared");
        let eye = view.eye();
        if let Some(env) = &state.env {
            frame.span("regenerate", |frame| {
                let depth_range = (0.01, 2.0 * scene::BACKGROUND_DISTANCE);
                let all = gpu::Objects::All;
                gpu::host::draw_scene_cube(frame, host, env, eye, depth_range, all);
            });
        }
        self.write_settings(frame, state, 0.0);
        let camera = buildings.camera_bind_group(frame.gpu, view.view_proj(), eye);
        self.draw_interiors(frame, buildings, state, (&camera, eye), (color, depth));
        Ok(())
    }
}

impl InteriorMapping {
    /// The variant's settings at `time` (the furniture sprite's frame) into its uniform.
    fn write_settings(&self, frame: &mut Frame, state: &State, time: f32) {
        let frame_index = ((time * FURNITURE_FPS).floor().max(0.0) as u32) % FURNITURE_FRAMES;
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
    }

    /// The hulls' own passes (pre-pass and interior mapping) into `color` and `depth`
    /// (loaded), seen from `eye` through `camera`, timed apart from the shared raster pass as
    /// span "interior" (encoder timestamps around the passes).
    fn draw_interiors(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        state: &State,
        (camera, eye): (&wgpu::BindGroup, Vec3),
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
    ) {
        frame.span("interior", |frame| {
            if let Some(prepass) = &state.prepass {
                let mut pass = pass::begin(
                    frame.encoder,
                    "interior depth pre-pass",
                    &[],
                    Some(pass::depth(depth, Load::Keep)),
                    None,
                );
                pass.set_pipeline(prepass);
                pass.set_bind_group(0, camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &state.bind_group, &[]);
                draw_hulls(&mut pass, state, scene);
            }
            let target = RasterTarget {
                color,
                depth,
                format: self.formats.color,
                clear: false,
            };
            let mut pass = scene::begin_scene_pass(
                frame.encoder,
                &target,
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
            pass.set_bind_group(0, camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            pass.set_bind_group(2, &state.bind_group, &[]);
            draw_hulls(&mut pass, state, scene);
            drop(pass);
        });
    }
}

impl InteriorMapping {
    /// Bytes of interior texture data uploaded by the last `prepare` (None before it): the
    /// memory figure reported beside error and time.
    pub fn texture_bytes(&self) -> Option<u64> {
        self.state.as_ref().map(|s| s.texture_bytes)
    }
}

/// Every variant: the ten interior-mapping versions of [`Variant::ALL`] (the paper's, the
/// baselines of 5.3.2 and the engine's cube-map interiors) with and without a depth pre-pass, and the polygon baseline.
pub fn all() -> Vec<Box<dyn Technique>> {
    let mut out: Vec<Box<dyn Technique>> = Vec::new();
    for v in Variant::ALL {
        out.push(Box::new(InteriorMapping::new(v, false)));
        out.push(Box::new(InteriorMapping::new(v, true)));
    }
    out.push(Box::new(PolygonInteriors::default()));
    out
}
