//! `height-maps/separated` and `height-maps/full-update`: the paper's own use of refractor
//! height maps (section 6: "in the algorithm described in 5.2, the refractor distance map can
//! be replaced by the refractor height map. Search can be executed from an outer point and the
//! calculation of multiple refractions is possible as well").
//!
//! The per-piece environment impostors, their rounds and the separation of the moving piece
//! are `scene`'s [`PieceImpostors`], the driver `refractor-maps/{full-update,separated}` runs on
//! distance maps; here every search is the height map's ([`HeightSearch`]: the exit from
//! inside, the moving piece from outside) and every piece is its billboard
//! ([`PieceSurface::Proxy`], `shaders/separated_billboard.wgsl`): the billboard turned to the
//! eye, or to the impostor's centre while the impostors are built, decides visibility, as in
//! `height-maps/single` and `double-refraction`, where `height-maps/in-chess` rasterizes each
//! piece's mesh for the first hit.

use crate::in_chess::HeightSearch;
use crate::map::render_height_maps;
use crate::technique::{BILLBOARD_BOX, BILLBOARD_BOX_VERTICES, MapSettings, unsupported};
use gpu::Target;
use scene::multi_object::{ImpostorSettings, PieceImpostors, PieceSurface, piece_impostor_help};
use scene::technique::Declared;
use scene::{
    Frame, GpuScene, Kinds, Param, Scene, Technique, TechniqueError, TechniqueResult, View,
};

const SEPARATED_BILLBOARD_WGSL: &str = include_str!("shaders/separated_billboard.wgsl");
/// The modules of its own the billboards' proxy imports (besides the drivers' and the search's).
static SEPARATED_BILLBOARD_IMPORTS: [&gpu::wgsl::Module; 1] = [&BILLBOARD_BOX];

/// Parameters of a [`HeightMapsSeparated`] variant.
#[derive(Clone, Debug, PartialEq)]
pub struct SeparatedSettings {
    /// Separated or full update, rounds, rebuild threshold, the search for the moving piece
    /// (their size and steps are `maps.env_resolution` and `maps.env_iterations`).
    pub impostors: ImpostorSettings,
    /// The height maps and their searches (`env_resolution`: each piece's impostor).
    pub maps: MapSettings,
}

impl Default for SeparatedSettings {
    /// The impostors of `refractor-maps/separated` (so the two compare map for map), the
    /// height maps of the other variants.
    fn default() -> Self {
        let impostors = ImpostorSettings::separated();
        Self {
            maps: MapSettings {
                env_resolution: impostors.env_resolution,
                env_iterations: impostors.env_iterations,
                ..MapSettings::default()
            },
            impostors,
        }
    }
}

impl SeparatedSettings {
    /// The impostors' settings, with the size and steps of `maps`.
    fn impostors(&self) -> ImpostorSettings {
        (self.impostors).with_maps(self.maps.env_resolution, self.maps.env_iterations)
    }
}

/// The impostors' parameters, then the maps' (each declared once by its own settings), the
/// maps' `env_resolution` naming each piece's impostor.
impl scene::Settings for SeparatedSettings {
    const DECLARED: &'static [Declared<Self>] = &[];
    fn params(&self) -> Vec<Param> {
        let mut params = self.impostors.params();
        params.extend(piece_impostor_help(self.maps.params()));
        params
    }
    fn set(&mut self, name: &str, value: f64) -> bool {
        self.impostors.set(name, value) || self.maps.set(name, value)
    }
}

/// A section-5 variant on refractor height maps: per-piece environment impostors, fully
/// updated or separated, the pieces drawn as billboards.
pub struct HeightMapsSeparated {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: SeparatedSettings,
    state: Option<(PieceImpostors, HeightSearch)>,
}

impl HeightMapsSeparated {
    /// A variant named `id` (`height-maps/<variant>`).
    pub fn new(
        id: &str,
        description: &str,
        representative: bool,
        settings: SeparatedSettings,
    ) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            representative,
            settings,
            state: None,
        }
    }

    /// Impostor rebuilds (one per impostor per round) since `prepare` (for tests).
    pub fn rebuilds(&self) -> u32 {
        self.state.as_ref().map_or(0, |(i, _)| i.rebuilds())
    }
}

/// The section-5 variants on height maps.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = SeparatedSettings::default();
    vec![
        Box::new(HeightMapsSeparated::new(
            "height-maps/separated",
            "the paper's section 5.2 with height maps (section 6): static pieces' impostors built \
             once, the moving piece's each frame and found from outside in its height map; every \
             piece a billboard that decides its own visibility",
            true,
            s.clone(),
        )),
        Box::new(HeightMapsSeparated::new(
            "height-maps/full-update",
            "as separated, every impostor rebuilt every frame (section 5.1)",
            false,
            SeparatedSettings {
                impostors: ImpostorSettings {
                    separated: false,
                    ..s.impostors
                },
                ..s
            },
        )),
    ]
}

impl Technique for HeightMapsSeparated {
    scene::named_variant!();
    scene::declared_params!(settings, state);
    fn supports(&self, scene: &Scene) -> bool {
        unsupported(&self.id, scene).is_none()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        if let Some(why) = unsupported(&self.id, &scene.scene) {
            return Err(TechniqueError::Unsupported(why));
        }
        let kinds = Kinds::of(&scene.scene);
        let m = &self.settings.maps;
        let map_bytes = (m.resolution as u64).pow(2) * 16;
        let kind_count = kinds.representative.len();
        scene::technique::check_map_budget(&self.id, kind_count, map_bytes, "resolution")?;
        let settings = self.settings.impostors();
        let all_maps = kind_count as u64 * map_bytes;
        PieceImpostors::check(&scene.scene, &kinds, &settings, all_maps, &self.id)?;
        let maps = render_height_maps(frame, scene, &kinds.representative, m.resolution)?;
        let search = HeightSearch::new(frame.gpu, &scene.scene, &kinds, &maps, m.steps);
        let billboards = PieceSurface::Proxy {
            source: SEPARATED_BILLBOARD_WGSL,
            imports: &SEPARATED_BILLBOARD_IMPORTS,
            vertex: "separated_billboard_vs",
            fragment: "separated_billboard_fs",
            vertices: BILLBOARD_BOX_VERTICES,
        };
        let impostors = PieceImpostors::new(
            frame, scene, kinds, &search, billboards, &settings, all_maps, &self.id,
        )?;
        self.state = Some((impostors, search));
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let settings = self.settings.impostors();
        let (impostors, _) = self
            .state
            .as_mut()
            .ok_or(TechniqueError::NotPrepared(self.id.clone()))?;
        impostors.render(frame, scene, view, target, &settings, &self.id);
        Ok(())
    }
}
