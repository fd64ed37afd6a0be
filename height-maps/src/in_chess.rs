//! `height-maps/in-chess`: section 6's closing remark ("the refractor distance map can be
//! replaced by the refractor height map"), the many-object tracer of sections 4-5 with
//! refractor height maps in place of refractor distance maps.
//!
//! The tracer is `scene::multi_object::Tracer` (the board grid, the depth-first tree of
//! reflected and refracted rays, the environment impostor), the same code `refractor-maps`
//! drives with its distance maps; here it calls [`HeightSearch`], whose WGSL
//! (`shaders/height_object_search.wgsl`) answers the tracer's three questions with the
//! height-map search of [`crate::search`]. Neither crate depends on the other.

use crate::map::{map_bounds, render_height_maps};
use crate::search::{SEARCH, Steps};
use crate::technique::{MapSettings, unsupported};
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::multi_object::grid::ALL_CELLS;
use scene::multi_object::{
    ObjectSearch, Search, Tracer, TracerSettings, depth_declared, max_cells_declared, storage,
};
use scene::technique::{Declared, declared_params, declared_set};
use scene::{
    Frame, GpuScene, Kinds, Param, Scene, Technique, TechniqueError, TechniqueResult, View,
};

/// The height-map search of the many-object drivers: the module `height_maps::object_search`,
/// which overrides `scene::pieces`' per-object search.
pub const HEIGHT_OBJECT_SEARCH_WGSL: &str = include_str!("shaders/height_object_search.wgsl");
/// [`HEIGHT_OBJECT_SEARCH_WGSL`] as a module.
pub static OBJECT_SEARCH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    HEIGHT_OBJECT_SEARCH_WGSL,
    "height-maps/src/shaders/height_object_search.wgsl",
    &[&scene::multi_object::PIECES, &SEARCH],
);

/// The per-object search of the many-object tracer with refractor height maps: each piece's
/// map on a billboard facing the ray's origin.
pub struct HeightSearch {
    maps_view: wgpu::TextureView,
    params: Uniform<[u32; 4]>,
    bounds: wgpu::Buffer,
}

impl HeightSearch {
    /// The search in `maps` (a layer per kind of `kinds`) with `steps`.
    pub fn new(
        ctx: &Context,
        scene: &Scene,
        kinds: &Kinds,
        maps: &wgpu::Texture,
        steps: Steps,
    ) -> Self {
        let bounds: Vec<[f32; 4]> = kinds
            .representative
            .iter()
            .map(|&rep| {
                let b = map_bounds(&scene.objects[rep]);
                [b.half_width, b.v_min, b.v_max, b.height]
            })
            .collect();
        Self {
            maps_view: maps.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            params: Uniform::new(ctx, "height search", &[steps.linear, steps.binary, 0, 0]),
            bounds: storage(ctx, "height-map bounds", &bounds),
        }
    }
}

impl ObjectSearch for HeightSearch {
    fn module(&self) -> &'static gpu::wgsl::Module {
        &OBJECT_SEARCH
    }
    fn binding_types(&self) -> Vec<wgpu::BindingType> {
        vec![
            bind::uniform(),
            bind::texture(wgpu::TextureViewDimension::D2Array, false),
            bind::storage(true),
        ]
    }
    fn resources(&self) -> Vec<wgpu::BindingResource<'_>> {
        vec![
            self.params.binding(),
            bind::view(&self.maps_view),
            self.bounds.as_entire_binding(),
        ]
    }
}

/// Parameters of `height-maps/in-chess`.
#[derive(Clone, Debug, PartialEq)]
pub struct InChessSettings {
    /// Interfaces at which a path splits.
    pub depth: u32,
    /// The search for the next piece: the board grid, `max_cells` occupied cells at most.
    pub search: Search,
    /// The maps and their searches.
    pub maps: MapSettings,
}

impl Default for InChessSettings {
    fn default() -> Self {
        Self {
            depth: 4,
            search: Search::Grid {
                max_cells: ALL_CELLS,
            },
            maps: MapSettings::default(),
        }
    }
}

/// The variant's parameters: its own (`depth`, `max_cells`), then the maps'.
impl scene::Settings for InChessSettings {
    const DECLARED: &'static [Declared<Self>] = &[
        depth_declared(|s| Some(&mut s.depth)),
        max_cells_declared(|s| s.search.grid_setting()),
    ];
    fn params(&self) -> Vec<Param> {
        let mut params = declared_params(self);
        params.extend(self.maps.params());
        params
    }
    fn set(&mut self, name: &str, value: f64) -> bool {
        declared_set(self, name, value) || self.maps.set(name, value)
    }
}

/// `height-maps/in-chess`.
pub struct HeightMapsInChess {
    /// The variant's parameters.
    pub settings: InChessSettings,
    state: Option<(Tracer, HeightSearch)>,
}

impl HeightMapsInChess {
    /// The variant with default settings.
    pub fn new() -> Self {
        Self {
            settings: InChessSettings::default(),
            state: None,
        }
    }

    fn tracer_settings(&self) -> TracerSettings {
        TracerSettings {
            depth: self.settings.depth,
            search: self.settings.search,
            env_resolution: self.settings.maps.env_resolution,
            env_iterations: self.settings.maps.env_iterations,
        }
    }
}

impl Default for HeightMapsInChess {
    fn default() -> Self {
        Self::new()
    }
}

impl Technique for HeightMapsInChess {
    fn id(&self) -> String {
        "height-maps/in-chess".into()
    }
    fn description(&self) -> String {
        "scene's many-object tracer, the one refractor-maps runs on distance maps (board grid, \
         rays between pieces, paths split at up to 4 interfaces), with refractor height maps in \
         place of distance maps (section 6's closing remark)"
            .into()
    }
    fn representative(&self) -> bool {
        true
    }
    scene::declared_params!(settings, state);
    fn supports(&self, scene: &Scene) -> bool {
        unsupported(&self.id(), scene).is_none()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let id = self.id();
        if let Some(why) = unsupported(&id, &scene.scene) {
            return Err(TechniqueError::Unsupported(why));
        }
        let kinds = Kinds::of(&scene.scene);
        let s = &self.settings.maps;
        scene::technique::check_map_budget(
            &id,
            kinds.representative.len(),
            (s.resolution as u64).pow(2) * 16,
            "resolution",
        )?;
        let maps = render_height_maps(frame, scene, &kinds.representative, s.resolution)?;
        let search = HeightSearch::new(ctx, &scene.scene, &kinds, &maps, s.steps);
        let settings = self.tracer_settings();
        let formats = gpu::TargetFormats::HDR;
        let tracer = Tracer::new(ctx, scene, kinds, &search, (&settings, formats), &id)?;
        // The board grid at the scene's time: a scene whose pieces cannot be put in a grid is
        // refused here, not at the first frame.
        tracer
            .group(ctx, &scene.scene, &search, &settings, scene.time())
            .map_err(|e| with_id(&id, e))?;
        self.state = Some((tracer, search));
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let id = self.id();
        let settings = self.tracer_settings();
        let (tracer, search) = self
            .state
            .as_ref()
            .ok_or_else(|| TechniqueError::NotPrepared(id.clone()))?;
        let group = tracer
            .group(frame.gpu, &scene.scene, search, &settings, scene.time())
            .map_err(|e| with_id(&id, e))?;
        tracer.render(frame, scene, view, target, &group, &id);
        Ok(())
    }
}

/// `e` with the variant's id in front.
fn with_id(id: &str, e: TechniqueError) -> TechniqueError {
    match e {
        TechniqueError::Unsupported(m) => TechniqueError::Unsupported(format!("{id}: {m}")),
        other => other,
    }
}
