//! Multi-bounce rays with per-piece environment distance impostors (paper section 5): the
//! [`EnvironmentMaps`] technique, variants `full-update` and `separated`.
//!
//! The impostors, their rounds and the separation of the moving piece are `scene`'s
//! [`PieceImpostors`] (shared with `height-maps/separated`); here they search refractor
//! distance maps ([`DistanceSearch`]: the exit from inside, the moving piece from outside),
//! and each piece's first hit is its rasterized mesh.
//!
//! - `full-update` rebuilds every impostor, all rounds, every frame: the paper's first test
//!   (1.8 FPS on its scene).
//! - `separated` (section 5.2) builds the static pieces' impostors once, in `prepare`, without
//!   the moving piece; only the moving piece's impostor is rebuilt each frame, and a static
//!   piece finds the moving one by searching its refractor map from outside along each lookup
//!   ray (11.3 FPS in the paper, "approximately 6 times faster").

use crate::pieces::{Kinds, render_kind_maps};
use crate::technique::{DistanceSearch, MAP_FORMAT, Maps, check_kinds};
use gpu::Target;
use gpu::cube::CubeTarget;
use scene::multi_object::{ImpostorSettings, PieceImpostors, PieceSurface, piece_impostor_help};
use scene::technique::Declared;
use scene::{Frame, GpuScene, Param, Scene, Technique, TechniqueError, TechniqueResult, View};

pub use scene::multi_object::MAX_ENV_DEPTH;

/// Parameters of an [`EnvironmentMaps`] variant.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvSettings {
    /// Separated or full update, rounds, rebuild threshold, the search for the moving piece
    /// (their size and steps are `maps.env_resolution` and `maps.env_iterations`).
    pub impostors: ImpostorSettings,
    /// The maps and their searches (`env_resolution`: each piece's impostor).
    pub maps: Maps,
}

impl Default for EnvSettings {
    fn default() -> Self {
        let impostors = ImpostorSettings::separated();
        Self {
            maps: Maps::with_env_resolution(impostors.env_resolution),
            impostors,
        }
    }
}

impl EnvSettings {
    /// The impostors' settings, with the size and steps of `maps`.
    fn impostors(&self) -> ImpostorSettings {
        (self.impostors).with_maps(self.maps.env_resolution, self.maps.env_iterations)
    }
}

/// The impostors' parameters, then the maps' (each declared once by its own settings).
impl scene::Settings for EnvSettings {
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

/// A section-5 variant: per-piece environment impostors, fully updated or separated.
pub struct EnvironmentMaps {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: EnvSettings,
    state: Option<(PieceImpostors, DistanceSearch)>,
}

impl EnvironmentMaps {
    /// A variant named `id` (`refractor-maps/<variant>`).
    pub fn new(id: &str, description: &str, representative: bool, settings: EnvSettings) -> Self {
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

/// The section-5 variants.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = EnvSettings::default();
    vec![
        Box::new(EnvironmentMaps::new(
            "refractor-maps/full-update",
            "per-piece environment impostors holding multi-bounce radiance (section 5.1), every \
             impostor rebuilt every frame: the paper's baseline for a moving piece",
            true,
            EnvSettings {
                impostors: ImpostorSettings {
                    separated: false,
                    ..s.impostors
                },
                ..s.clone()
            },
        )),
        Box::new(EnvironmentMaps::new(
            "refractor-maps/separated",
            "static pieces' impostors built once without the moving piece, the moving piece's \
             rebuilt each frame and found by the search from outside (section 5.2)",
            true,
            s,
        )),
    ]
}

impl Technique for EnvironmentMaps {
    scene::named_variant!();
    scene::declared_params!(settings, state);
    fn supports(&self, scene: &Scene) -> bool {
        !scene.specular_objects().is_empty()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let kinds = Kinds::of(&scene.scene);
        check_kinds(&self.id, &kinds)?;
        let m = &self.settings.maps;
        let map_bytes = CubeTarget::bytes(m.resolution, MAP_FORMAT);
        let kind_count = kinds.representative.len();
        scene::technique::check_map_budget(&self.id, kind_count, map_bytes, "resolution")?;
        let settings = self.settings.impostors();
        let all_maps = kind_count as u64 * map_bytes;
        PieceImpostors::check(&scene.scene, &kinds, &settings, all_maps, &self.id)?;
        let maps = render_kind_maps(frame, scene, &kinds, m.resolution)?;
        let search = DistanceSearch::new(frame, maps, m);
        let impostors = PieceImpostors::new(
            frame,
            scene,
            kinds,
            &search,
            PieceSurface::Mesh,
            &settings,
            all_maps,
            &self.id,
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
