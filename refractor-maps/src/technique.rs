//! The refractor-map tracer: one [`RefractorMaps`] type configured as each variant.
//!
//! `prepare` renders one refractor distance map per kind of piece (`pieces::Kinds`: outward
//! normal + distance of the piece's own surface from its centre, a cube of `resolution`
//! texels per face) and never again: pieces only translate. The frame is `scene`'s
//! many-object tracer (`scene::multi_object::Tracer`: the environment impostor, the raster
//! pass, the pieces drawn with `trace.wgsl`) searching these maps through [`DistanceSearch`];
//! with caustics (section 7, [`crate::caustics`]) the moving piece's photon map and light map
//! come before the trace (timed as "caustics") and the light maps are added to the chessboard
//! after it ("caustics apply"); the static pieces' light map is made once, in `prepare`.

use crate::caustics::{CausticSettings, Caustics, PHOTONS_WGSL, caustic_receiver};
use crate::pieces::{Kinds, MAX_KINDS};
use gpu::cube::CubeTarget;
use gpu::wgpu;
use gpu::{Target, Uniform};
use scene::multi_object::grid::ALL_CELLS;
use scene::multi_object::{ObjectSearch, Tracer, TracerSettings, driver_shader, pieces_centre};
use scene::multi_object::{depth_declared, max_cells_declared};
use scene::technique::{Declared, declared_params, declared_set};
use scene::{Frame, GpuScene, Param, Scene, Technique, TechniqueError, TechniqueResult, View};

pub use scene::multi_object::{MAX_DEPTH, Search};

/// The refractor-map search of the many-object drivers: the module
/// `refractor_maps::distance_search`, which overrides `scene::pieces`' per-object search.
pub const DISTANCE_SEARCH_WGSL: &str = include_str!("shaders/distance_search.wgsl");
/// [`DISTANCE_SEARCH_WGSL`] as a module.
pub static DISTANCE_SEARCH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    DISTANCE_SEARCH_WGSL,
    "refractor-maps/src/shaders/distance_search.wgsl",
    &[&scene::multi_object::PIECES],
);

pub use crate::pieces::MAP_FORMAT;
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
}

/// The maps' parameters, each declared once (`env_resolution` is the tracer's one impostor of
/// the diffuse scene; the section-5 variants name each piece's impostor in its help,
/// `scene::multi_object::PIECE_IMPOSTOR_HELP`).
impl scene::Settings for Maps {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "resolution",
            (4.0, 4096.0),
            "cube face size of each kind's refractor map (texels)",
            |s| Some(&mut s.resolution),
        ),
        Declared::new(
            "env_resolution",
            (4.0, 4096.0),
            "cube face size of the diffuse environment impostor (texels)",
            |s| Some(&mut s.env_resolution),
        ),
        Declared::new(
            "iterations",
            (0.0, 64.0),
            "Hit() refinement steps in the refractor maps",
            |s| Some(&mut s.iterations),
        ),
        Declared::new(
            "env_iterations",
            (0.0, 64.0),
            "Hit() refinement steps in the environment impostor(s)",
            |s| Some(&mut s.env_iterations),
        ),
        Declared::new(
            "epsilon",
            (1e-6, 1.0),
            "a search from outside is accepted within this distance of the ray (metres)",
            |s| Some(&mut s.epsilon),
        ),
    ];
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
    /// The formats of the targets the pieces are drawn into (the harness's, or a renderer's
    /// own: [`RefractorMaps::for_targets`]).
    formats: gpu::TargetFormats,
    state: Option<State>,
}

struct State {
    tracer: Tracer,
    search: DistanceSearch,
    caustics: Option<Caustics>,
}

/// The per-object search of the many-object tracer with refractor distance maps: `Hit()` in
/// the kind's map from inside, the search from outside (section 4.1) from outside
/// (`shaders/distance_search.wgsl`).
pub struct DistanceSearch {
    /// The kinds' refractor maps, kind k as cube k of one cube-map array: the search reads
    /// every kind through one binding and one call (`hit_layered`), whatever their number.
    maps: wgpu::TextureView,
    params: Uniform<DistanceGpu>,
    sampler: wgpu::Sampler,
}

/// The uniform block `DistanceSearch` of distance_search.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DistanceGpu {
    iterations: u32,
    epsilon: f32,
    _pad: [u32; 2],
}

impl DistanceSearch {
    /// The search in `maps` (one per kind, rendered in this frame) with `settings`' iterations
    /// and epsilon; the frame copies the maps into the search's cube-map array.
    pub fn new(frame: &mut Frame, maps: Vec<CubeTarget>, settings: &Maps) -> Self {
        let ctx = frame.gpu;
        let params = DistanceGpu {
            iterations: settings.iterations,
            epsilon: settings.epsilon,
            _pad: [0; 2],
        };
        Self {
            maps: cube_array_of(frame, &maps).create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::CubeArray),
                ..Default::default()
            }),
            params: Uniform::new(ctx, "distance search", &params),
            sampler: ctx.samplers.linear_clamp.clone(),
        }
    }
}

/// The maps of `cubes` copied into one cube-map array, cube k = `cubes[k]` (the copies are
/// recorded after the frame's passes that render the maps).
fn cube_array_of(frame: &mut Frame, cubes: &[CubeTarget]) -> wgpu::Texture {
    let ctx = frame.gpu;
    let (size, format) = (cubes[0].size, cubes[0].format);
    let array = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("refractor maps"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 6 * cubes.len() as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (k, cube) in cubes.iter().enumerate() {
        frame.encoder.copy_texture_to_texture(
            cube.color.as_image_copy(),
            wgpu::TexelCopyTextureInfo {
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: 6 * k as u32,
                },
                ..array.as_image_copy()
            },
            cube.color.size(),
        );
    }
    array
}

impl ObjectSearch for DistanceSearch {
    fn module(&self) -> &'static gpu::wgsl::Module {
        &DISTANCE_SEARCH
    }
    fn binding_types(&self) -> Vec<wgpu::BindingType> {
        vec![
            gpu::bind::uniform(),
            gpu::bind::sampler(),
            gpu::bind::texture(wgpu::TextureViewDimension::CubeArray, true),
        ]
    }
    fn resources(&self) -> Vec<wgpu::BindingResource<'_>> {
        vec![
            self.params.binding(),
            gpu::bind::sampler_resource(&self.sampler),
            gpu::bind::view(&self.maps),
        ]
    }
}

/// The variant's parameters: its own (`depth`, and `max_cells` with the grid search), then
/// the maps' and, with caustics, the caustics' (each declared once by its own settings).
impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        depth_declared(|s| Some(&mut s.depth)),
        max_cells_declared(|s| s.search.grid_setting()),
    ];
    fn params(&self) -> Vec<Param> {
        let mut params = declared_params(self);
        params.extend(self.maps.params());
        if let Some(caustics) = &self.caustics {
            params.extend(caustics.params());
        }
        params
    }
    fn set(&mut self, name: &str, value: f64) -> bool {
        declared_set(self, name, value)
            || self.maps.set(name, value)
            || self.caustics.as_mut().is_some_and(|c| c.set(name, value))
    }
}

/// Fails when `kinds` has more kinds than the [`DistanceSearch`]'s array of maps holds
/// ([`MAX_KINDS`]).
pub(crate) fn check_kinds(id: &str, kinds: &Kinds) -> TechniqueResult<()> {
    if kinds.representative.len() <= MAX_KINDS {
        return Ok(());
    }
    Err(TechniqueError::Unsupported(format!(
        "{id} keeps one refractor map per kind of specular object (same mesh and scale), as the \
         cubes of one array texture of at most {MAX_KINDS}; this scene has {} kinds",
        kinds.representative.len()
    )))
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
            formats: gpu::TargetFormats::HDR,
            state: None,
        }
    }

    /// The variant drawing its pieces into targets of `formats` (a renderer's own).
    pub fn for_targets(mut self, formats: gpu::TargetFormats) -> Self {
        self.formats = formats;
        self.state = None;
        self
    }

    /// The kinds of the prepared scene (for tests): each kind's representative object.
    pub fn kinds(&self) -> Option<&Kinds> {
        self.state.as_ref().map(|s| s.tracer.kinds())
    }

    /// Section 7's photons leave each light's position through the refractor maps.
    fn caustic_lights(&self, scene: &Scene) -> TechniqueResult<()> {
        scene::point_lights_only(
            &self.id,
            "its photon maps are rendered from each light's position",
            scene,
        )
    }

    fn tracer_settings(&self) -> TracerSettings {
        TracerSettings {
            depth: self.settings.depth,
            search: self.settings.search,
            env_resolution: self.settings.maps.env_resolution,
            env_iterations: self.settings.maps.env_iterations,
        }
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
    scene::named_variant!();
    scene::declared_params!(settings, state);
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
        // Caustics need a flat receiver under the pieces (the chessboard) and point lights.
        self.settings.caustics.is_none() || {
            let kinds = Kinds::of(scene);
            caustic_receiver(scene, pieces_centre(scene, &kinds)).is_some()
                && self.caustic_lights(scene).is_ok()
        }
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let kinds = Kinds::of(&scene.scene);
        check_kinds(&self.id, &kinds)?;
        if self.settings.caustics.is_some() {
            self.caustic_lights(&scene.scene)?;
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
        let maps = crate::pieces::render_kind_maps(frame, scene, &kinds, res)?;
        let search = DistanceSearch::new(frame, maps, &self.settings.maps);
        let tracer_settings = self.tracer_settings();
        let reference = pieces_centre(&scene.scene, &kinds);
        let settings = (&tracer_settings, self.formats);
        let tracer = Tracer::new(ctx, scene, kinds, &search, settings, &self.id)?;
        let caustics = match &self.settings.caustics {
            None => None,
            Some(c) => {
                let receiver = caustic_receiver(&scene.scene, reference).ok_or_else(|| {
                    TechniqueError::Unsupported(format!(
                        "{}: no flat diffuse surface under the pieces to receive caustics",
                        self.id
                    ))
                })?;
                let photons = driver_shader(ctx, "photon map", PHOTONS_WGSL, &[], &search);
                let caustics = Caustics::new(
                    ctx,
                    scene,
                    tracer.kinds(),
                    &photons,
                    tracer.layout(),
                    c,
                    receiver,
                );
                Some(caustics.map_err(|e| prefixed(&self.id, e))?)
            }
        };
        if let Some(caustics) = &caustics {
            // The static pieces' light map, once (they stand where they stand at any time).
            let group = tracer
                .group(ctx, &scene.scene, &search, &tracer_settings, scene.time())
                .map_err(|e| prefixed(&self.id, e))?;
            caustics.build_static(frame, scene, tracer.kinds(), &group);
        }
        self.state = Some(State {
            tracer,
            search,
            caustics,
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
        let settings = self.tracer_settings();
        let state = self
            .state
            .as_ref()
            .ok_or_else(|| TechniqueError::NotPrepared(self.id.clone()))?;
        let ctx = frame.gpu;
        let group = state
            .tracer
            .group(ctx, &scene.scene, &state.search, &settings, scene.time())
            .map_err(|e| prefixed(&self.id, e))?;
        if let Some(caustics) = &state.caustics {
            frame.span("caustics", |frame| {
                caustics.update(frame, scene, state.tracer.kinds(), &group);
            });
        }
        state
            .tracer
            .render(frame, scene, view, target, &group, &self.id);
        if let Some(caustics) = &state.caustics {
            let view_proj = view.camera.view_proj(view.width, view.height);
            let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
            caustics.apply(frame, scene, &camera, target);
        }
        Ok(())
    }
}

impl scene::hosted::DrawOver for RefractorMaps {
    /// The pieces of `pieces` (a renderer's objects, uploaded alone) drawn over `color` and
    /// `depth` (targets of the formats of [`RefractorMaps::for_targets`], holding the
    /// renderer's frame): the environment impostor asked of `host` from the centre of the
    /// pieces where they now stand, the board grid of where they stand, then the traced
    /// pieces, depth-tested against what is there. Caustics refuse: their receiver is a
    /// chessboard of the technique's own scene.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        (pieces, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        if self.settings.caustics.is_some() {
            return Err(TechniqueError::Unsupported(format!(
                "{}: caustics land on the technique's chessboard; the pass draws the pieces only",
                self.id
            )));
        }
        let settings = self.tracer_settings();
        let state = self
            .state
            .as_mut()
            .ok_or_else(|| TechniqueError::NotPrepared(self.id.clone()))?;
        state.tracer.follow_pieces(&pieces.scene);
        let group = state
            .tracer
            .group(frame.gpu, &pieces.scene, &state.search, &settings, 0.0)
            .map_err(|e| prefixed(&self.id, e))?;
        let hosted = (pieces, host);
        let targets = (color, depth);
        state
            .tracer
            .draw_over(frame, hosted, view, targets, &group, &self.id);
        Ok(())
    }
}

/// `e` with the variant's id in front.
fn prefixed(id: &str, e: TechniqueError) -> TechniqueError {
    match e {
        TechniqueError::Unsupported(m) => TechniqueError::Unsupported(format!("{id}: {m}")),
        other => other,
    }
}
