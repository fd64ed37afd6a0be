//! The refractor-map tracer: one [`RefractorMaps`] type configured as each variant.
//!
//! `prepare` renders one refractor distance map per kind of piece (`pieces::Kinds`: outward
//! normal + distance of the piece's own surface from its centre, a cube of `resolution`
//! texels per face) and never again: pieces only translate. Each frame:
//!
//! 1. the environment impostor: the diffuse scene (no specular object) as a distance impostor
//!    (rgb radiance, alpha distance) from the centre of the pieces' bounds, timed as
//!    "environment";
//! 2. the piece table and the board grid at the frame's time (the moving piece changes cells);
//! 3. the shared raster pass for the diffuse objects;
//! 4. the pieces drawn with `trace_fs`: from the rasterized first hit, the tree of reflected
//!    and refracted rays through the refractor maps (trace.wgsl), timed as "trace";
//! 5. with caustics (section 7, [`crate::caustics`]): the moving piece's photon map and light
//!    map before the trace (timed as "caustics"), the light maps added to the chessboard after
//!    it ("caustics apply"); the static pieces' light map is made once, in `prepare`.

use crate::caustics::{CausticSettings, Caustics, PHOTONS_WGSL, caustic_receiver};
use crate::grid::{ALL_CELLS, BoardGrid, EMPTY};
use crate::pieces::{Kinds, MAX_KINDS, PieceGpu, pieces_at};
use glam::Vec3;
use gpu::cube::CubeTarget;
use gpu::distance_map::HIT_WGSL;
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::wgpu::util::DeviceExt;
use gpu::{Context, Target, Uniform, bind};
use scene::technique::check_param;
use scene::{
    Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene, Technique, TechniqueError,
    TechniqueResult, View,
};

/// The board grid's nearest-piece search (needs the prelude; the includer defines
/// `piece_hit` and `grid_cells`).
pub const GRID_SEARCH_WGSL: &str = include_str!("shaders/grid_search.wgsl");
const TRACE_WGSL: &str = include_str!("shaders/trace.wgsl");

/// Format of the refractor maps (normal + distance) and the environment impostor.
pub const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Deepest tree of rays the shader follows (its stack holds `MAX_DEPTH + 2` rays).
pub const MAX_DEPTH: u32 = 8;

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

/// Parameters of a [`RefractorMaps`] variant (settable by name through
/// [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Interfaces at which a path splits (1: the first surface only).
    pub depth: u32,
    /// How a ray leaving a piece finds the next one.
    pub search: Search,
    /// The maps and their searches.
    pub maps: Maps,
    /// Caustics on the chessboard (section 7), or none.
    pub caustics: Option<CausticSettings>,
}

/// What both techniques of the crate search: the refractor maps, the environment
/// impostor(s), and the steps of `Hit()` in them.
#[derive(Clone, Debug, PartialEq)]
pub struct Maps {
    /// Cube face size of each kind's refractor map.
    pub resolution: u32,
    /// Cube face size of the environment impostor(s).
    pub env_resolution: u32,
    /// Hit() refinement steps in the refractor maps (inside and from outside).
    pub iterations: u32,
    /// Hit() refinement steps in the environment impostor(s).
    pub env_iterations: u32,
    /// Distance from the ray within which a search from outside is accepted (metres).
    pub epsilon: f32,
}

impl Maps {
    /// The defaults with environment impostors of `env_resolution` texels.
    pub fn with_env_resolution(env_resolution: u32) -> Maps {
        Maps {
            resolution: 256,
            env_resolution,
            iterations: 4,
            env_iterations: 4,
            epsilon: 0.004,
        }
    }

    /// The declared parameters; `env_map` names the environment impostor(s) in the help.
    pub(crate) fn params(&self, env_map: &'static str) -> Vec<Param> {
        vec![
            Param::new(
                "resolution",
                self.resolution as f64,
                (4.0, 4096.0),
                true,
                "cube face size of each kind's refractor map (texels)",
            ),
            Param::new(
                "env_resolution",
                self.env_resolution as f64,
                (4.0, 4096.0),
                true,
                env_map,
            ),
            Param::new(
                "iterations",
                self.iterations as f64,
                (0.0, 64.0),
                true,
                "Hit() refinement steps in the refractor maps",
            ),
            Param::new(
                "env_iterations",
                self.env_iterations as f64,
                (0.0, 64.0),
                true,
                "Hit() refinement steps in the environment impostor(s)",
            ),
            Param::new(
                "epsilon",
                self.epsilon as f64,
                (1e-6, 1.0),
                false,
                "a search from outside is accepted within this distance of the ray (metres)",
            ),
        ]
    }

    /// Sets parameter `name` if it is one of these (already checked against its range).
    pub(crate) fn set(&mut self, name: &str, value: f64) -> bool {
        match name {
            "resolution" => self.resolution = value as u32,
            "env_resolution" => self.env_resolution = value as u32,
            "iterations" => self.iterations = value as u32,
            "env_iterations" => self.env_iterations = value as u32,
            "epsilon" => self.epsilon = value as f32,
            _ => return false,
        }
        true
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            depth: 4,
            search: Search::Grid {
                max_cells: ALL_CELLS,
            },
            maps: Maps::with_env_resolution(256),
            caustics: None,
        }
    }
}

/// A refractor-map technique variant.
pub struct RefractorMaps {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: Settings,
    state: Option<State>,
}

struct State {
    kinds: Kinds,
    /// One refractor map per kind, in kind order.
    maps: Vec<CubeTarget>,
    env: CubeTarget,
    env_reference: Vec3,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The piece of each scene object, [`EMPTY`] for a diffuse one.
    piece_of_object: wgpu::Buffer,
    caustics: Option<Caustics>,
}

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
    iterations: u32,
    env_iterations: u32,
    epsilon: f32,
    _pad: u32,
}

impl RefractorMaps {
    /// A variant named `id` (`refractor-maps/<variant>`); [`variants`] lists the configured
    /// ones.
    pub fn new(id: &str, description: &str, representative: bool, settings: Settings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            representative,
            settings,
            state: None,
        }
    }

    /// The kinds of the prepared scene (for tests): each kind's representative object.
    pub fn kinds(&self) -> Option<&Kinds> {
        self.state.as_ref().map(|s| &s.kinds)
    }

    /// The caustic light maps of the prepared variant (static pieces, moving piece), for tests
    /// and images; `None` without caustics.
    pub fn light_maps(&self) -> Option<(&wgpu::Texture, &wgpu::Texture)> {
        self.state
            .as_ref()?
            .caustics
            .as_ref()
            .map(|c| c.light_maps())
    }
}

/// Every variant of this crate.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = Settings::default();
    let grid = Search::Grid {
        max_cells: ALL_CELLS,
    };
    let v = |id: &str, description: &str, representative: bool, settings: Settings| {
        Box::new(RefractorMaps::new(
            &format!("refractor-maps/{id}"),
            description,
            representative,
            settings,
        )) as Box<dyn Technique>
    };
    vec![
        v(
            "single-bounce",
            "refractor map of the piece's kind for the exit, then the environment impostor: no \
             other piece is seen (one interface split, section 3 on refractor maps)",
            true,
            Settings {
                depth: 1,
                search: Search::None,
                ..s.clone()
            },
        ),
        v(
            "multi-bounce-2",
            "rays traced through the pieces' refractor maps, next piece by the board grid and the \
             search from outside (sections 4.1-4.2), paths split at up to 2 interfaces",
            false,
            Settings {
                depth: 2,
                search: grid,
                ..s.clone()
            },
        ),
        v(
            "multi-bounce-4",
            "as multi-bounce-2, paths split at up to 4 interfaces",
            true,
            Settings {
                depth: 4,
                search: grid,
                ..s.clone()
            },
        ),
        v(
            "first-square",
            "multi-bounce-4 with the paper's shortcut: only the first non-empty grid cell along \
             a ray is searched, then the environment",
            false,
            Settings {
                depth: 4,
                search: Search::Grid { max_cells: 1 },
                ..s.clone()
            },
        ),
        v(
            "all-pieces",
            "multi-bounce-4 searching every piece from outside for each ray (the slow \
             exact-visibility variant the grid replaces)",
            false,
            Settings {
                depth: 4,
                search: Search::AllPieces,
                ..s.clone()
            },
        ),
        v(
            "caustics",
            "multi-bounce-4 with caustics on the chessboard (section 7): photons through each \
             piece's refractor map splatted into light maps, the static pieces' made once, the \
             moving piece's every frame",
            true,
            Settings {
                depth: 4,
                search: grid,
                caustics: Some(CausticSettings::default()),
                ..s
            },
        ),
    ]
}

impl Technique for RefractorMaps {
    fn id(&self) -> String {
        self.id.clone()
    }
    fn description(&self) -> String {
        self.description.clone()
    }
    fn representative(&self) -> bool {
        self.representative
    }
    fn params(&self) -> Vec<Param> {
        let s = &self.settings;
        let mut p = vec![Param::new(
            "depth",
            s.depth as f64,
            (1.0, MAX_DEPTH as f64),
            true,
            "interfaces at which a path splits into reflection and refraction",
        )];
        p.extend(
            s.maps
                .params("cube face size of the diffuse environment impostor (texels)"),
        );
        if let Some(c) = &s.caustics {
            p.extend(c.params());
        }
        if let Search::Grid { max_cells } = s.search {
            p.push(Param::new(
                "max_cells",
                max_cells.min(1 << 20) as f64,
                (1.0, (1 << 20) as f64),
                true,
                "occupied grid cells a ray examines at most (1: the paper's first non-empty \
                 square; large: every cell along the ray)",
            ));
        }
        p
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id, &self.params(), name, value)?;
        let s = &mut self.settings;
        match name {
            "depth" => s.depth = value as u32,
            name if s.maps.set(name, value) => {}
            name if s.caustics.as_mut().is_some_and(|c| c.set(name, value)) => {}
            "max_cells" => {
                s.search = Search::Grid {
                    max_cells: value as u32,
                }
            }
            _ => unreachable!("check_param accepted an undeclared parameter"),
        }
        self.state = None;
        Ok(())
    }
    fn required_features(&self) -> wgpu::Features {
        match self.settings.caustics {
            // Photons are added into 32-bit float light maps by blending.
            Some(_) => wgpu::Features::FLOAT32_BLENDABLE,
            None => wgpu::Features::empty(),
        }
    }
    fn supports(&self, scene: &Scene) -> bool {
        let specular = scene.specular_objects();
        if specular.is_empty() {
            return false;
        }
        // Caustics need a flat receiver under the pieces (the chessboard).
        self.settings.caustics.is_none() || {
            let kinds = Kinds::of(scene);
            caustic_receiver(scene, environment_reference(scene, &kinds)).is_some()
        }
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let kinds = Kinds::of(&scene.scene);
        if kinds.representative.len() > MAX_KINDS {
            return Err(TechniqueError::Unsupported(format!(
                "{} keeps one refractor map per kind of specular object (same mesh and scale), \
                 each a texture binding, and has {MAX_KINDS} map slots; this scene has {} kinds",
                self.id,
                kinds.representative.len()
            )));
        }
        let res = self.settings.maps.resolution;
        scene::technique::check_map_budget(
            &self.id,
            kinds.representative.len() + 1,
            CubeTarget::bytes(res.max(self.settings.maps.env_resolution), MAP_FORMAT),
            "resolution",
        )?;
        if let Some(c) = &self.settings.caustics {
            let bytes = Caustics::bytes(c, kinds.pieces.len(), scene.scene.lights.len());
            scene::technique::check_map_budget(&self.id, 1, bytes, "photons")?;
        }
        let mut source = format!(
            "{}\n{}\n{}\n{}\n{}",
            scene::SCENE_WGSL,
            HIT_WGSL,
            GRID_SEARCH_WGSL,
            crate::pieces::PIECES_WGSL,
            trace_source(kinds.representative.len())
        );
        if self.settings.caustics.is_some() {
            use scene::lightmap::{CHART_WGSL, RECEIVER_WGSL};
            source = format!("{source}\n{CHART_WGSL}\n{RECEIVER_WGSL}\n{PHOTONS_WGSL}");
        }
        let module = gpu::shader_with_prelude(ctx, &self.id, &source);
        let layout = tracer_layout(ctx, kinds.representative.len());
        let pipeline = scene::scene_pipeline(
            ctx,
            &self.id,
            &scene.pipeline_layout_with(ctx, &[&layout]),
            &module,
            "trace_fs",
            gpu::HDR_FORMAT,
        );
        let maps = crate::pieces::render_kind_maps(frame, scene, &kinds, res)?;
        let mut piece_of_object = vec![EMPTY; scene.scene.objects.len()];
        for (piece, &(object, _)) in kinds.pieces.iter().enumerate() {
            piece_of_object[object] = piece as u32;
        }
        let env = CubeTarget::new(
            ctx,
            self.settings.maps.env_resolution,
            MAP_FORMAT,
            "environment impostor",
        )?;
        let env_reference = environment_reference(&scene.scene, &kinds);
        let caustics = match &self.settings.caustics {
            None => None,
            Some(c) => {
                let receiver = caustic_receiver(&scene.scene, env_reference).ok_or_else(|| {
                    TechniqueError::Unsupported(format!(
                        "{}: no flat diffuse surface under the pieces to receive caustics",
                        self.id
                    ))
                })?;
                Some(Caustics::new(
                    ctx, scene, &kinds, &module, &layout, c, receiver,
                )?)
            }
        };
        let state = State {
            env_reference,
            kinds,
            maps,
            env,
            layout,
            pipeline,
            piece_of_object: storage(ctx, "piece of object", &piece_of_object),
            caustics,
        };
        if let Some(caustics) = &state.caustics {
            // The static pieces' light map, once (they stand where they stand at any time).
            let group = frame_group(
                ctx,
                &state,
                &self.settings,
                &scene.scene,
                scene.time(),
                &self.id,
            )?;
            caustics.build_static(frame, scene, &state.kinds, &group);
        }
        self.state = Some(state);
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let settings = self.settings.clone();
        let id = self.id.clone();
        let state = self
            .state
            .as_ref()
            .ok_or(TechniqueError::NotPrepared(id.clone()))?;
        let ctx = frame.gpu;
        let time = scene.time();

        frame.timer.begin(frame.encoder, "environment");
        scene.raster_cube(
            frame,
            &state.env,
            state.env_reference,
            &ObjectFilter::All,
            false,
        );
        frame.timer.end(frame.encoder, "environment");

        let group = frame_group(ctx, state, &settings, &scene.scene, time, &id)?;
        if let Some(caustics) = &state.caustics {
            frame.timer.begin(frame.encoder, "caustics");
            caustics.update(frame, scene, &state.kinds, &group);
            frame.timer.end(frame.encoder, "caustics");
        }

        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget {
            color: &target.color_view,
            depth: &target.depth_view,
            format: gpu::HDR_FORMAT,
            clear: true,
        };
        let specular: Vec<usize> = state.kinds.pieces.iter().map(|&(o, _)| o).collect();
        scene.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::Except(specular.clone()),
            false,
        );
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        let mut pass = gpu::pass::begin(
            frame.encoder,
            &id,
            &[pass::color(&target.color_view, Load::Keep)],
            Some(pass::depth(&target.depth_view, Load::Keep)),
            frame.timer.render_pass("trace"),
        );
        pass.set_pipeline(&state.pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(specular));
        drop(pass);
        if let Some(caustics) = &state.caustics {
            caustics.apply(frame, scene, &camera, target);
        }
        Ok(())
    }
}

/// The tracer's `@group(2)` with the pieces and the board grid at `time`.
fn frame_group(
    ctx: &Context,
    state: &State,
    settings: &Settings,
    scene: &Scene,
    time: f32,
    id: &str,
) -> TechniqueResult<wgpu::BindGroup> {
    let (pieces, footprints) = pieces_at(scene, &state.kinds, time);
    let grid = BoardGrid::build(&footprints)
        .map_err(|e| TechniqueError::Unsupported(format!("{id}: {e}")))?;
    Ok(tracer_group(ctx, state, settings, &pieces, &grid))
}

/// The environment impostor's reference point: the centre of the pieces' bounds at time 0
/// (above the board, among the pieces: where the paper's per-piece maps are taken from).
fn environment_reference(scene: &Scene, kinds: &Kinds) -> Vec3 {
    let objects: Vec<_> = kinds
        .pieces
        .iter()
        .map(|&(o, _)| scene.objects[o].clone())
        .collect();
    let (lo, hi) = scene::world_bounds(&objects);
    (lo + hi) * 0.5
}

/// A read-only storage buffer holding `data` (padded: a storage binding may not be empty).
pub(crate) fn storage<T: bytemuck::Pod>(ctx: &Context, label: &str, data: &[T]) -> wgpu::Buffer {
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

/// trace.wgsl for a scene with `kinds` kinds: one refractor-map binding per kind and a
/// `switch` arm per kind in the functions that read them (WGSL has no arrays of cube
/// textures without an extra feature; a shader with exactly the scene's kinds also keeps the
/// software rasterizer from compiling eight inlined searches for a one-sphere scene).
pub fn trace_source(kinds: usize) -> String {
    let arms = |call: &str| -> String {
        (0..kinds)
            .map(|k| {
                let case = if k + 1 == kinds {
                    "default".to_string()
                } else {
                    format!("case {k}u")
                };
                format!(
                    "        {case}: {{ return {}; }}\n",
                    call.replace("MAP", &format!("kind_map{k}"))
                )
            })
            .collect()
    };
    let bindings: String = (0..kinds)
        .map(|k| {
            format!(
                "@group(2) @binding({}) var kind_map{k}: texture_cube<f32>;\n",
                6 + k
            )
        })
        .collect();
    TRACE_WGSL
        .replace(
            "// {KIND_MAP_BINDINGS}: one `kind_mapK: texture_cube<f32>` per kind at binding 6 + K.",
            &bindings,
        )
        .replace(
            "// {SAMPLE_ARMS}\n",
            &arms("textureSampleLevel(MAP, map_sampler, dir, 0.0)"),
        )
        .replace(
            "// {INSIDE_ARMS}\n",
            &arms("hit(x, R, MAP, map_sampler, 3u, HIT_FALSE_POSITION, tracer.iterations)"),
        )
        .replace(
            "// {OUTSIDE_ARMS}\n",
            &arms(
                "hit_from_outside(y, R, MAP, map_sampler, 3u, bmin, bmax, HIT_FALSE_POSITION, \
                 tracer.iterations, tracer.epsilon)",
            ),
        )
}

/// Layout of `@group(2)` in trace.wgsl with `kinds` refractor maps.
fn tracer_layout(ctx: &Context, kinds: usize) -> wgpu::BindGroupLayout {
    let mut entries = vec![
        bind::uniform(),
        bind::storage(true),
        bind::storage(true),
        bind::storage(true),
        bind::sampler(),
        bind::texture_cube(),
    ];
    entries.extend(std::iter::repeat_n(bind::texture_cube(), kinds));
    bind::layout(
        ctx,
        "refractor maps",
        wgpu::ShaderStages::FRAGMENT,
        &entries,
    )
}

/// This frame's `@group(2)`: parameters, pieces, grid cells, the environment impostor and the
/// kinds' refractor maps.
fn tracer_group(
    ctx: &Context,
    state: &State,
    settings: &Settings,
    pieces: &[PieceGpu],
    grid: &BoardGrid,
) -> wgpu::BindGroup {
    let uniform = TracerGpu {
        env_reference: state.env_reference.extend(0.0).to_array(),
        grid_min_cell: [grid.min.x, grid.min.y, grid.cell, 0.0],
        grid_count: [grid.count.x, grid.count.y, 0, 0],
        depth: settings.depth,
        search: settings.search.wgsl_id(),
        max_cells: match settings.search {
            Search::Grid { max_cells } => max_cells,
            _ => ALL_CELLS,
        },
        piece_count: pieces.len() as u32,
        iterations: settings.maps.iterations,
        env_iterations: settings.maps.env_iterations,
        epsilon: settings.maps.epsilon,
        _pad: 0,
    };
    let params = Uniform::new(ctx, "tracer params", &uniform);
    let piece_buffer = storage(ctx, "pieces", pieces);
    let cells = storage(ctx, "grid cells", &grid.cells);
    let mut resources = vec![
        params.binding(),
        piece_buffer.as_entire_binding(),
        cells.as_entire_binding(),
        state.piece_of_object.as_entire_binding(),
        bind::sampler_resource(&ctx.samplers.linear_clamp),
        bind::view(&state.env.cube_view),
    ];
    resources.extend(state.maps.iter().map(|m| bind::view(&m.cube_view)));
    bind::group(ctx, "refractor maps", &state.layout, &resources)
}
