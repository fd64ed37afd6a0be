//! The driver of the many-object tracer: [`Tracer`], parameterised by an [`ObjectSearch`].
//!
//! Each frame ([`Tracer::render`]):
//!
//! 1. the environment impostor: the diffuse scene (no specular object) as a distance impostor
//!    (rgb radiance, alpha distance) from the centre of the pieces' bounds, asked of the scene
//!    as host (`gpu::DrawScene`), timed as "environment";
//! 2. the shared raster pass for the diffuse objects;
//! 3. the pieces drawn with `trace_fs` (`shaders/trace.wgsl`): from the rasterized first hit,
//!    the tree of reflected and refracted rays through the objects' maps, timed as "trace".
//!
//! [`Tracer::draw_over`] runs steps 1 and 3 over a renderer's own frame: the renderer is the
//! host, and the pieces are its objects uploaded alone (`crate::hosted`).
//!
//! The piece table and the board grid are made at each frame's time ([`Tracer::group`]): the
//! moving piece changes cells.

use super::grid::{ALL_CELLS, BoardGrid, EMPTY};
use super::pieces::{PIECES, PieceGpu, pieces_at};
use crate::kinds::Kinds;
use crate::{Frame, GpuScene, ObjectFilter, RasterTarget, Scene, TechniqueError, View};
use glam::Vec3;
use gpu::cube::CubeTarget;
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, GpuError, Target, Uniform, bind};

/// The board grid's nearest-piece search, the module `scene::grid_search` ([`GRID_SEARCH`]):
/// each candidate searched by `scene::pieces`' `piece_hit`, the grid's cells at the binding
/// [`GRID_DEFS`] place.
pub const GRID_SEARCH_WGSL: &str = include_str!("../shaders/grid_search.wgsl");
/// [`GRID_SEARCH_WGSL`] as a module.
pub static GRID_SEARCH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    GRID_SEARCH_WGSL,
    "scene/src/shaders/grid_search.wgsl",
    &[&PIECES],
);
/// Where the tracer binds the grid's cells: `@group(2) @binding(2)`.
pub const GRID_DEFS: [(&str, gpu::wgsl::Def); 2] = [
    ("GRID_GROUP", gpu::wgsl::Def::UInt(2)),
    ("GRID_CELLS_BINDING", gpu::wgsl::Def::UInt(2)),
];
/// The tracer's bindings and paths, the module `scene::trace` ([`TRACE`]), which its eye pass
/// ([`TRACE_FS_WGSL`]) and a technique's own passes over its bindings import.
pub const TRACE_WGSL: &str = include_str!("../shaders/trace.wgsl");
/// [`TRACE_WGSL`] as a module.
pub static TRACE: gpu::wgsl::Module = gpu::wgsl::Module::new(
    TRACE_WGSL,
    "scene/src/shaders/trace.wgsl",
    &[&GRID_SEARCH, &PIECES, &crate::SHADING],
);
/// The tracer's eye pass, `trace_fs`.
pub const TRACE_FS_WGSL: &str = include_str!("../shaders/trace_fs.wgsl");

/// The modules of the many-object drivers (the piece table and search, the grid, the tracer,
/// the section-5 impostors' shading), which a shader over a driver's bindings imports from.
pub const DRIVER_MODULES: [&gpu::wgsl::Module; 4] = [
    &PIECES,
    &GRID_SEARCH,
    &TRACE,
    &super::environment::ENVIRONMENT_PIECES,
];

/// Composes `source`, entry points over a driver's bindings (the tracer's eye pass, a
/// technique's own passes such as refractor-maps' photons, a proxy's entries), with the
/// drivers' modules and `imports` of its own, `search`'s module overriding the per-object
/// search.
pub fn driver_shader(
    ctx: &Context,
    label: &str,
    source: &str,
    imports: &[&gpu::wgsl::Module],
    search: &dyn ObjectSearch,
) -> wgpu::ShaderModule {
    let modules: Vec<&gpu::wgsl::Module> = DRIVER_MODULES
        .iter()
        .copied()
        .chain(imports.iter().copied())
        .collect();
    let overrides = [search.module()];
    let shader = gpu::wgsl::Shader::new(label, source)
        .importing(&modules)
        .with_defs(&GRID_DEFS)
        .overriding(&overrides);
    crate::shader_of(ctx, shader)
}

/// The first `@group(2)` binding of an [`ObjectSearch`]'s own resources (the tracer's take
/// 0..6).
pub const SEARCH_FIRST_BINDING: u32 = 6;

/// The binding types of both drivers' own `@group(2)` resources, before the search's (from
/// [`SEARCH_FIRST_BINDING`]): their parameters, the piece table, a per-piece buffer of their
/// own (the tracer's grid cells, the impostors' centres), the piece of each object, a sampler
/// and their environment map(s) (`env_map`).
pub(super) fn driver_entries(env_map: wgpu::BindingType) -> Vec<wgpu::BindingType> {
    vec![
        bind::uniform(),
        bind::storage(true),
        bind::storage(true),
        bind::storage(true),
        bind::sampler(),
        env_map,
    ]
}

/// Format of the environment impostor.
const ENV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The search in one object's map that the many-object drivers call: a WGSL module that
/// overrides `scene::pieces`' `piece_hit`, `piece_hit_normal` and `chord` (pieces.wgsl says
/// what each answers), with its own resources after the driver's. Implemented with refractor
/// distance maps (`refractor-maps`) and refractor height maps (`height-maps`).
pub trait ObjectSearch {
    /// The module holding its overrides; its `i`-th resource of
    /// [`ObjectSearch::binding_types`] at `@group(2) @binding(SEARCH_FIRST_BINDING + i)`
    /// (`SEARCH_FIRST_BINDING` is a constant of `scene::pieces`, equal to the Rust one). The
    /// module's own imports name what else it needs (its search routines' module).
    fn module(&self) -> &'static gpu::wgsl::Module;
    /// The binding types of its resources, in order (visible to the fragment stage, and to
    /// the vertex stage in [`super::PieceImpostors`], whose proxies may read them).
    fn binding_types(&self) -> Vec<wgpu::BindingType>;
    /// Its resources, in the order of [`ObjectSearch::binding_types`].
    fn resources(&self) -> Vec<wgpu::BindingResource<'_>>;
}

/// The largest `max_cells` a parameter names: more cells than any board has, so it reads as
/// every cell ([`super::grid::ALL_CELLS`]).
pub const MAX_CELLS_PARAM_MAX: u32 = 1 << 20;

/// The parameter `max_cells` of a grid search, declared once for every family whose settings
/// hold a [`Search`] (`setting` finds it; settings whose search is not the grid's lack it).
pub const fn max_cells_declared<S>(
    setting: fn(&mut S) -> Option<&mut dyn crate::technique::ParamValue>,
) -> crate::technique::Declared<S> {
    crate::technique::Declared::new(
        "max_cells",
        (1.0, MAX_CELLS_PARAM_MAX as f64),
        "occupied grid cells a ray examines at most (1: the paper's first non-empty square; \
         large: every cell along the ray)",
        setting,
    )
}

/// The tracer's parameter `depth`, declared once for every family that runs it (`setting`
/// finds the interfaces a path meets).
pub const fn depth_declared<S>(
    setting: fn(&mut S) -> Option<&mut dyn crate::technique::ParamValue>,
) -> crate::technique::Declared<S> {
    crate::technique::Declared::new(
        "depth",
        (1.0, MAX_DEPTH as f64),
        "interfaces at which a path splits into reflection and refraction",
        setting,
    )
}

/// A grid search as the parameter `max_cells` (every cell reads as [`MAX_CELLS_PARAM_MAX`]).
impl crate::technique::ParamValue for Search {
    fn read(&self) -> f64 {
        match self {
            Search::Grid { max_cells } => (*max_cells).min(MAX_CELLS_PARAM_MAX) as f64,
            _ => 0.0,
        }
    }
    fn write(&mut self, value: f64) {
        *self = Search::Grid {
            max_cells: value as u32,
        };
    }
    fn integer(&self) -> bool {
        true
    }
}

impl Search {
    /// The grid search as a [`max_cells_declared`] setting; `None` for the other searches.
    pub fn grid_setting(&mut self) -> Option<&mut dyn crate::technique::ParamValue> {
        match self {
            Search::Grid { .. } => Some(self),
            _ => None,
        }
    }
}

/// How a ray that leaves a piece finds the next one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Search {
    /// It does not: every ray leaving a piece takes the diffuse environment (one piece per
    /// path, the double refraction of section 3 with one shared environment impostor).
    None,
    /// Through the board grid, cell by cell along the ray (section 4.2); `max_cells` occupied
    /// cells at most (1: the paper's first non-empty square).
    Grid {
        /// Occupied cells examined at most per ray.
        max_cells: u32,
    },
    /// Over every piece, nearest hit kept: the paper's N - 1 searches, the slow
    /// exact-visibility variant.
    AllPieces,
}

impl Search {
    fn wgsl_id(self) -> u32 {
        match self {
            Search::None => 0,
            Search::Grid { .. } => 1,
            Search::AllPieces => 2,
        }
    }
}

/// The tracer's own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracerSettings {
    /// Interfaces at which a path splits (1: the first surface only).
    pub depth: u32,
    /// How a ray leaving a piece finds the next one.
    pub search: Search,
    /// Cube face size of the environment impostor.
    pub env_resolution: u32,
    /// Hit() refinement steps in the environment impostor.
    pub env_iterations: u32,
}

/// Deepest tree of rays the shader follows (its stack holds `MAX_DEPTH + 2` rays).
pub const MAX_DEPTH: u32 = 8;

/// The uniform block `TracerParams` of trace.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TracerGpu {
    env_reference: [f32; 4],
    grid_min_cell: [f32; 4],
    grid_count: [i32; 4],
    depth: u32,
    search: u32,
    max_cells: u32,
    piece_count: u32,
    env_iterations: u32,
    _pad: [u32; 3],
}

/// The many-object tracer of one scene, prepared for one [`ObjectSearch`].
pub struct Tracer {
    kinds: Kinds,
    env: EnvironmentImpostor,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The piece of each scene object, [`EMPTY`] for a diffuse one.
    piece_of_object: wgpu::Buffer,
}

impl Tracer {
    /// The tracer of `scene`'s specular objects (`kinds`) searched with `search`, drawing them
    /// into targets of `formats` (the harness's, or a renderer's own); a technique's own passes
    /// over the tracer's bindings compose their shaders with [`driver_shader`].
    pub fn new(
        ctx: &Context,
        scene: &GpuScene,
        kinds: Kinds,
        search: &dyn ObjectSearch,
        (settings, formats): (&TracerSettings, gpu::TargetFormats),
        label: &str,
    ) -> Result<Self, GpuError> {
        let module = driver_shader(ctx, label, TRACE_FS_WGSL, &[], search);
        let mut entries = driver_entries(bind::texture_cube());
        entries.extend(search.binding_types());
        let layout = bind::layout(ctx, label, wgpu::ShaderStages::FRAGMENT, &entries);
        let pipeline = crate::scene_pipeline_for(
            ctx,
            label,
            &scene.pipeline_layout_with(ctx, &[&layout]),
            &module,
            "trace_fs",
            formats,
        );
        let mut piece_of_object = vec![EMPTY; scene.scene.objects.len()];
        for (piece, &(object, _)) in kinds.pieces.iter().enumerate() {
            piece_of_object[object] = piece as u32;
        }
        let env = EnvironmentImpostor::new(ctx, &scene.scene, &kinds, settings.env_resolution)?;
        Ok(Self {
            kinds,
            env,
            layout,
            pipeline,
            piece_of_object: storage(ctx, "piece of object", &piece_of_object),
        })
    }

    /// The specular objects and their kinds.
    pub fn kinds(&self) -> &Kinds {
        &self.kinds
    }

    /// Takes the environment impostor from the centre of the pieces where `scene` now puts
    /// them (a renderer's pieces move; the harness's impostor stays where the pieces stood at
    /// time 0). Call before [`Tracer::group`], which hands the shaders the reference point.
    pub fn follow_pieces(&mut self, scene: &Scene) {
        self.env.follow(scene, &self.kinds);
    }

    /// The scene objects of the pieces.
    fn piece_objects(&self) -> Vec<usize> {
        self.kinds.pieces.iter().map(|&(o, _)| o).collect()
    }

    /// The tracer's `@group(2)` layout (its bindings, then the search's).
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// The `@group(2)` at `time`: parameters, the piece table, the board grid, the environment
    /// impostor and the search's resources. Fails when the pieces cannot be put in a grid.
    pub fn group(
        &self,
        ctx: &Context,
        scene: &Scene,
        search: &dyn ObjectSearch,
        settings: &TracerSettings,
        time: f32,
    ) -> Result<wgpu::BindGroup, TechniqueError> {
        let (pieces, footprints) = pieces_at(scene, &self.kinds, time);
        let grid = BoardGrid::build(&footprints)
            .map_err(|e| TechniqueError::Unsupported(e.to_string()))?;
        Ok(self.group_with(ctx, search, settings, &pieces, &grid))
    }

    fn group_with(
        &self,
        ctx: &Context,
        search: &dyn ObjectSearch,
        settings: &TracerSettings,
        pieces: &[PieceGpu],
        grid: &BoardGrid,
    ) -> wgpu::BindGroup {
        let uniform = TracerGpu {
            env_reference: self.env.reference.extend(0.0).to_array(),
            grid_min_cell: [grid.min.x, grid.min.y, grid.cell, 0.0],
            grid_count: [grid.count.x, grid.count.y, 0, 0],
            depth: settings.depth,
            search: settings.search.wgsl_id(),
            max_cells: match settings.search {
                Search::Grid { max_cells } => max_cells,
                _ => ALL_CELLS,
            },
            piece_count: pieces.len() as u32,
            env_iterations: settings.env_iterations,
            _pad: [0; 3],
        };
        let params = Uniform::new(ctx, "tracer params", &uniform);
        let piece_buffer = storage(ctx, "pieces", pieces);
        let cells = storage(ctx, "grid cells", &grid.cells);
        let mut resources = vec![
            params.binding(),
            piece_buffer.as_entire_binding(),
            cells.as_entire_binding(),
            self.piece_of_object.as_entire_binding(),
            bind::sampler_resource(&ctx.samplers.linear_clamp),
            bind::view(self.env.view()),
        ];
        resources.extend(search.resources());
        bind::group(ctx, "many-object tracer", &self.layout, &resources)
    }

    /// Records a frame: the environment impostor, the diffuse objects, then the traced
    /// specular objects with `group` (this frame's [`Tracer::group`]). `label` names the trace
    /// pass.
    pub fn render(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
        group: &wgpu::BindGroup,
        label: &str,
    ) {
        let specular = self.piece_objects();
        self.env.capture(frame, scene, &specular);
        let view_proj = raster_diffuse(frame, scene, view, target, &specular);
        let camera = scene.camera_bind_group(frame.gpu, view_proj, view.camera.eye);
        let targets = (&target.color_view, &target.depth_view);
        self.trace(frame, scene, &camera, targets, group, label);
    }

    /// Records the pieces over a renderer's frame (`color` and `depth`, of the formats the
    /// tracer was made for): the environment impostor asked of `host` (everything but the
    /// pieces), then the traced pieces of `pieces` (the renderer's objects, uploaded alone),
    /// depth-tested against what is there, as `view` sees them.
    #[allow(clippy::too_many_arguments)]
    pub fn draw_over(
        &self,
        frame: &mut Frame,
        (pieces, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
        group: &wgpu::BindGroup,
        label: &str,
    ) {
        self.env.capture(frame, host, &self.piece_objects());
        let camera = pieces.camera_bind_group(frame.gpu, view.view_proj(), view.eye());
        self.trace(frame, pieces, &camera, (color, depth), group, label);
    }

    /// The pieces drawn with `trace_fs` into `color` and `depth` (loaded), timed as "trace".
    fn trace(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
        group: &wgpu::BindGroup,
        label: &str,
    ) {
        let drawn = (&self.pipeline, camera);
        let mut pass = scene.pass_over(frame, label, (color, depth), "trace", drawn);
        pass.set_bind_group(2, group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(self.piece_objects()));
    }
}

/// The diffuse scene (no specular object) as one distance impostor (rgb radiance, alpha
/// distance) from the centre of the specular objects' bounds: what a ray that finds no
/// specular object sees (`environment()` in trace.wgsl and height-maps' billboards).
pub struct EnvironmentImpostor {
    cube: CubeTarget,
    /// The reference point (world).
    pub reference: Vec3,
}

impl EnvironmentImpostor {
    /// An impostor of `resolution` texels per face for the specular objects `kinds`.
    pub fn new(
        ctx: &Context,
        scene: &Scene,
        kinds: &Kinds,
        resolution: u32,
    ) -> Result<Self, GpuError> {
        Ok(Self {
            cube: CubeTarget::new(ctx, resolution, ENV_FORMAT, "environment impostor")?,
            reference: pieces_centre(scene, kinds),
        })
    }

    /// Asks `host` for everything but the `pieces` (its own object indices) around the
    /// reference point, timed as "environment". With the harness's scene as the host, this is
    /// the shared raster pass's cube (`scene/tests/host.rs` holds the two equal bit for bit).
    pub fn capture(&self, frame: &mut Frame, host: &dyn gpu::DrawScene, pieces: &[usize]) {
        frame.span("environment", |frame| {
            let depth_range = (0.01, 2.0 * crate::BACKGROUND_DISTANCE);
            let others = gpu::Objects::AllBut(pieces);
            gpu::host::draw_scene_cube(
                frame,
                host,
                &self.cube,
                self.reference,
                depth_range,
                others,
            );
        });
    }

    /// Takes it from the centre of `kinds`' pieces where `scene` now puts them.
    pub fn follow(&mut self, scene: &Scene, kinds: &Kinds) {
        self.reference = pieces_centre(scene, kinds);
    }

    /// Its cube view.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.cube.cube_view
    }
}

/// The shared raster pass into `target` (cleared) of every object but `specular`; returns the
/// view's view-projection matrix.
pub fn raster_diffuse(
    frame: &mut Frame,
    scene: &GpuScene,
    view: &View,
    target: &Target,
    specular: &[usize],
) -> glam::Mat4 {
    let view_proj = view.camera.view_proj(view.width, view.height);
    let main = RasterTarget::of(target, true);
    scene.raster(
        frame,
        &main,
        view_proj,
        view.camera.eye,
        &ObjectFilter::Except(specular.to_vec()),
        false,
    );
    view_proj
}

/// The centre of the specular objects' bounds at time 0: the environment impostor's reference
/// point (above the board, among the pieces: where the paper's per-piece maps are taken from).
pub fn pieces_centre(scene: &Scene, kinds: &Kinds) -> Vec3 {
    let objects: Vec<_> = kinds
        .pieces
        .iter()
        .map(|&(o, _)| scene.objects[o].clone())
        .collect();
    let (lo, hi) = crate::world_bounds(&objects);
    (lo + hi) * 0.5
}

/// A read-only storage buffer holding `data` (padded: a storage binding may not be empty).
pub fn storage<T: bytemuck::Pod>(ctx: &Context, label: &str, data: &[T]) -> wgpu::Buffer {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    let mut contents = bytes.to_vec();
    contents.resize(bytes.len().max(16), 0);
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
}
