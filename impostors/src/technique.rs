//! The distance-impostor techniques: one [`Impostor`] type configured as each variant.
//!
//! Per specular object the technique keeps an environment impostor: a cube map taken from the
//! object's centre by the shared raster pass (rgb = radiance, alpha = distance from the
//! centre; `scene::foundation::render_environment`). It is regenerated only when the object
//! has moved farther than `regen_threshold` from the map's reference point (0: every frame),
//! inside a "regenerate" timer span. In the split layout the distances are copied into a
//! one-channel `R16Float` cube beside the radiance (paper section 6). For double refraction
//! each glass object also gets a refractor map (outward normal + distance of its own surface
//! from its centre), made once in `prepare`: objects only translate, so it never changes.
//! With caustics, each frame also renders a caustic map per light and object, splats its
//! photons into a grid indexed by direction from the reference point (compute, atomics) and
//! adds the resulting caustic radiance to the diffuse surfaces (README.md, "Caustics").

use crate::caustics::{CausticPath, CausticSettings, Caustics, GeneratorMaps};
use crate::localized::{LOCALIZED, LOCALIZED_FS_WGSL};
use glam::Vec3;
use gpu::bind::UniformGroups;
use gpu::cube::CubeTarget;
use gpu::distance_map::Method;
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::{Context, Target, bind};
use scene::emission::{footprint_declared, jitter_declared};
use scene::technique::{Declared, setting_if};
use scene::{
    Frame, GpuScene, Material, ObjectFilter, RasterTarget, Scene, Technique, TechniqueResult, View,
};

mod hosted;

const SPLIT_WGSL: &str = include_str!("shaders/split.wgsl");

/// Format of the environment impostor (radiance + distance in alpha) and the refractor map.
pub const IMPOSTOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the separate distance cube of the split layout.
pub const SPLIT_DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// How a variant finds the radiance it reflects or refracts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Direction-only lookup (classic environment mapping) on the same maps.
    Classic,
    /// `Hit()` in the environment impostor; glass refracts at the visible surface only.
    Localized,
    /// Glass: `Hit()` in the refractor map, refraction out at the exit point, then `Hit()` in
    /// the environment impostor (paper section 4). Metals as `Localized`.
    DoubleRefraction,
}

impl Mode {
    fn wgsl_id(self) -> u32 {
        match self {
            Mode::Classic => 0,
            Mode::Localized => 1,
            Mode::DoubleRefraction => 2,
        }
    }
}

/// How a non-classic lookup turns a ray into the direction to look the environment map up in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// The paper's `Hit()` search in the distance impostor.
    Hit,
    /// Today's engine probes: the parallax-corrected (box-projected) cube map of Lagarde and
    /// Zanuttini 2012 against a proxy box, the bounds of the scene's diffuse objects (the
    /// room): `gpu::prelude::box_project`. No distances are read.
    BoxProjected,
}

/// Where the environment map of a box-projected variant is captured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Probe {
    /// At the object's centre, re-captured as the object moves (`regen_threshold`): the
    /// impostor's own map, so that only the lookup differs from `Hit()`.
    ObjectCentre,
    /// Where an artist puts the probe (`scene::probe_centre`: the centre of the specular
    /// objects' bounds, inside the room), captured once in the first frame and never again,
    /// as an engine bakes its reflection probes; the object is left out of its own map.
    RoomCentre,
}

/// Parameters of an [`Impostor`] (all settable by name through [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// How the radiance a ray leaves with is found (direction only, `Hit()`, double refraction).
    pub mode: Mode,
    /// How `Localized` and `DoubleRefraction` look the map up: `Hit()` or box projection.
    pub lookup: Lookup,
    /// Where the map is captured (`RoomCentre` only with `Lookup::BoxProjected`).
    pub probe: Probe,
    /// The `Hit()` search: secant or false position.
    pub method: Method,
    /// Refinement steps after the two initial guesses (`iterations` parameter).
    pub iterations: u32,
    /// Cube face size of the environment impostor and the refractor map.
    pub resolution: u32,
    /// Metres the object may move from the map's reference point before regeneration.
    pub regen_threshold: f32,
    /// Distances in a separate `R16Float` cube (true) or in the radiance map's alpha.
    pub split: bool,
    /// Refinement steps of `Hit()` inside the refractor map (double refraction).
    pub refractor_iterations: u32,
    /// Caustic maps from the lights, turned into caustic radiance on the diffuse surfaces
    /// (section 5), or none.
    pub caustics: Option<CausticSettings>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            mode: Mode::Localized,
            lookup: Lookup::Hit,
            probe: Probe::ObjectCentre,
            method: Method::FalsePosition,
            iterations: 4,
            resolution: 256,
            regen_threshold: 0.0,
            split: false,
            refractor_iterations: 2,
            caustics: None,
        }
    }
}

/// A distance-impostor technique variant.
pub struct Impostor {
    id: String,
    description: String,
    /// The variant's parameters; [`Technique::set_param`] changes them by name.
    pub settings: Settings,
    /// The formats of the targets the specular objects are drawn into (the harness's, or a
    /// renderer's own through [`crate::ImpostorPass`]).
    formats: gpu::TargetFormats,
    state: Option<State>,
}

struct State {
    caustic: Option<Caustics>,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    split_pipeline: wgpu::RenderPipeline,
    split_layout: wgpu::BindGroupLayout,
    maps: Vec<ObjectMaps>,
    /// The proxy box of the box-projected lookup: bounds of the scene's diffuse objects (none
    /// in a scene without any: the lookup is then the direction).
    proxy: Option<(Vec3, Vec3)>,
    /// Each object's `@group(2)` with its parameters, made once and rewritten every frame.
    groups: UniformGroups<ParamsGpu>,
}

/// The distance cube of the split layout.
struct SplitDistance {
    /// Distance-only cube map (its depth cube is unused: the copy pass draws no geometry).
    distances: CubeTarget,
    /// Bind groups of the copy pass, one per face of the packed map.
    copy_groups: Vec<wgpu::BindGroup>,
}

/// One specular object's maps.
struct ObjectMaps {
    object: usize,
    env: CubeTarget,
    split: Option<SplitDistance>,
    /// The object's own surface (outward normal + distance) seen from its centre, rendered
    /// once in prepare. `Motion` only translates objects, so the map stays valid as the object
    /// moves: it is searched from the object's *current* centre (see `impostor_groups`).
    refractor: Option<CubeTarget>,
    caustics: Option<GeneratorMaps>,
    /// Reference point of `env` (the object's centre when the map was last rendered).
    reference: Option<Vec3>,
    /// How many times `env` was (re)generated (for tests of `regen_threshold`).
    regenerations: u32,
}

impl Impostor {
    /// A variant named `id` (`impostors/<variant>`) with its one-line `description` and
    /// `settings`; [`crate::techniques`] lists the configured ones.
    pub fn new(id: &str, description: &str, settings: Settings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            settings,
            formats: gpu::TargetFormats::HDR,
            state: None,
        }
    }

    /// The variant drawing its objects into targets of `formats` (a renderer's own).
    pub fn for_targets(mut self, formats: gpu::TargetFormats) -> Self {
        self.formats = formats;
        self.state = None;
        self
    }

    /// How many times the environment impostors have been (re)generated since `prepare`.
    pub fn regenerations(&self) -> u32 {
        self.state.as_ref().map_or(0, |s| {
            s.maps.iter().map(|m| m.regenerations).max().unwrap_or(0)
        })
    }

    /// The caustic passes and each generator's caustic maps, once prepared (for tests).
    pub fn caustics(&self) -> Option<(&Caustics, Vec<&GeneratorMaps>)> {
        let state = self.state.as_ref()?;
        let c = state.caustic.as_ref()?;
        Some((
            c,
            state
                .maps
                .iter()
                .filter_map(|m| m.caustics.as_ref())
                .collect(),
        ))
    }

    /// The map is captured once where the probe stands (no regeneration parameter).
    fn room_probe(&self) -> bool {
        self.settings.room_probe()
    }

    fn uses_distance(&self) -> bool {
        self.settings.uses_distance()
    }

    /// Caustic maps are rendered from each light's position (section 5 of the paper).
    fn caustic_lights(&self, scene: &Scene) -> TechniqueResult<()> {
        scene::point_lights_only(
            &self.id,
            "its caustic maps are the casters seen from each light's position",
            scene,
        )
    }
}

impl Settings {
    /// The engine's room probe: one box-projected map for every object, never regenerated.
    fn room_probe(&self) -> bool {
        self.lookup == Lookup::BoxProjected && self.probe == Probe::RoomCentre
    }

    /// Whether lookups search a distance map by Hit().
    fn uses_distance(&self) -> bool {
        self.mode != Mode::Classic && self.lookup == Lookup::Hit
    }

    /// The caustics' settings on `path` only.
    fn caustics_on(&mut self, path: CausticPath) -> Option<&mut CausticSettings> {
        self.caustics.as_mut().filter(|c| c.path == path)
    }
}

impl scene::Settings for Settings {
    /// Which parameters a variant has follows its lookup, its mode and its caustics.
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "resolution",
            (4.0, 4096.0),
            "cube map face size (texels)",
            |s| Some(&mut s.resolution),
        ),
        Declared::new(
            "regen_threshold",
            (0.0, 1000.0),
            "metres the object may move from the map's reference point before the map is \
             regenerated (0: every frame)",
            |s| setting_if(!s.room_probe(), &mut s.regen_threshold),
        ),
        Declared::new(
            "iterations",
            (0.0, 64.0),
            "Hit() refinement steps after the two initial guesses",
            |s| setting_if(s.uses_distance(), &mut s.iterations),
        ),
        Declared::new(
            "split",
            (0.0, 1.0),
            "1: distances in a separate R16Float cube; 0: in the radiance map's alpha",
            |s| setting_if(s.uses_distance(), &mut s.split),
        ),
        Declared::new(
            "caustic_resolution",
            (4.0, 2048.0),
            "caustic map size (photons per side, per light and object)",
            |s| Some(&mut s.caustics.as_mut()?.resolution),
        ),
        Declared::new(
            "caustics_in_lookup",
            (0.0, 1.0),
            "1: reflections and refractions show the caustics (paper fig. 11; the reference \
             has none there)",
            |s| Some(&mut s.caustics.as_mut()?.in_lookup),
        ),
        jitter_declared(|s| Some(&mut s.caustics.as_mut()?.jitter)),
        Declared::new(
            "caustic_grid",
            (4.0, 1024.0),
            "face size of the photon accumulation grid",
            |s| Some(&mut s.caustics_on(CausticPath::Grid)?.grid),
        ),
        Declared::new(
            "lightmap_resolution",
            (16.0, 8192.0),
            "side of the receivers' light-map atlas (texels)",
            |s| Some(&mut s.caustics_on(CausticPath::LightMap)?.lightmap_resolution),
        ),
        Declared::new(
            "splat_radius",
            (1.0, 64.0),
            "radius of a photon's Gaussian quad in light-map texels (sigma = R / 2)",
            |s| Some(&mut s.caustics_on(CausticPath::LightMap)?.splat_radius),
        ),
        footprint_declared(|s| Some(&mut s.caustics_on(CausticPath::LightMap)?.footprint)),
        Declared::new(
            "refractor_iterations",
            (0.0, 64.0),
            "Hit() refinement steps inside the refractor map",
            |s| {
                let double = s.mode == Mode::DoubleRefraction;
                setting_if(double, &mut s.refractor_iterations)
            },
        ),
    ];
}

impl Technique for Impostor {
    fn id(&self) -> String {
        self.id.clone()
    }
    /// The default compare shows the classic map, the guess, secant 4, false position 1, 4
    /// and 8, double refraction and both caustic paths; the other iteration counts and the
    /// split layout are for `harness sweep` (or `compare --all-variants`).
    fn representative(&self) -> bool {
        let exhaustive = [
            "secant-1",
            "secant-2",
            "secant-3",
            "secant-5",
            "secant-6",
            "secant-7",
            "secant-8",
            "false-position-2",
            "false-position-3",
            "false-position-5",
            "false-position-6",
            "false-position-7",
            "false-position-4-split",
        ];
        !exhaustive
            .iter()
            .any(|v| self.id == format!("impostors/{v}"))
    }
    fn description(&self) -> String {
        self.description.clone()
    }
    // Maps and pipelines depend on the settings: a set parameter drops them.
    scene::declared_params!(settings, state);
    fn supports(&self, scene: &Scene) -> bool {
        if self.settings.caustics.is_some()
            && (scene.lights.is_empty() || self.caustic_lights(scene).is_err())
        {
            return false;
        }
        match self.settings.mode {
            // Caustic variants also cast caustics from metals (double refraction is only
            // what their glass does).
            Mode::DoubleRefraction if self.settings.caustics.is_none() => scene
                .objects
                .iter()
                .any(|o| matches!(o.material, Material::Glass { .. })),
            _ => scene.objects.iter().any(|o| o.material.is_specular()),
        }
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let layout = impostor_layout(ctx);
        // The plain localized pass (and the refractor map) from a shader without caustics;
        // caustic variants draw with their own shader, whose lookups add the caustics.
        let module = scene::shader_importing(ctx, &self.id, LOCALIZED_FS_WGSL, &[&LOCALIZED]);
        let caustic = match &self.settings.caustics {
            Some(c) => {
                self.caustic_lights(&scene.scene)?;
                Some(Caustics::new(ctx, scene, &layout, c)?)
            }
            None => None,
        };
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        let pipeline = scene::scene_pipeline_for(
            ctx,
            &self.id,
            &pipeline_layout,
            &module,
            "localized_fs",
            self.formats,
        );
        let split_layout = single_texture_layout(ctx);
        let split_pipeline = gpu::fullscreen::pipeline(
            ctx,
            "impostor split copy",
            gpu::wgsl::Shader::new("impostor split copy", SPLIT_WGSL),
            &[Some(&split_layout)],
            SPLIT_DISTANCE_FORMAT,
            None,
        );

        // Every specular object keeps its own maps: refuse, naming the limit, a scene whose
        // maps exceed the shared per-object budget (200 glass spheres took 5.9 GB and 219 s
        // for one caustics frame before this check).
        let res = self.settings.resolution;
        let double_refraction = self.settings.mode == Mode::DoubleRefraction;
        let split = self.settings.split && self.uses_distance();
        let per_object = CubeTarget::bytes(res, IMPOSTOR_FORMAT)
            + if split {
                CubeTarget::bytes(res, SPLIT_DISTANCE_FORMAT)
            } else {
                0
            }
            + if double_refraction {
                CubeTarget::bytes(res, IMPOSTOR_FORMAT)
            } else {
                0
            }
            + caustic.as_ref().map_or(0, |c| c.generator_bytes(res));
        let specular = scene.scene.specular_objects().len();
        scene::technique::check_map_budget(&self.id, specular, per_object, "resolution")?;
        let refractor_pipeline = double_refraction.then(|| {
            scene::scene_pipeline(
                ctx,
                "refractor map",
                &scene.pipeline_layout_with(ctx, &[]),
                &module,
                "refractor_map_fs",
                IMPOSTOR_FORMAT,
            )
        });
        let made = MapPipelines {
            split: split.then_some(&split_layout),
            refractor: refractor_pipeline.as_ref(),
            caustic: caustic.as_ref(),
        };
        let maps = object_maps(frame, scene, res, &made)?;
        let proxy = scene::probe_proxy_box(&scene.scene);
        self.state = Some(State {
            caustic,
            layout,
            pipeline,
            split_pipeline,
            split_layout,
            maps,
            proxy,
            groups: UniformGroups::new("impostor params"),
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
        let settings = self.settings.clone();
        let id = self.id.clone();
        let room_probe = self.room_probe();
        let state = self
            .state
            .as_mut()
            .ok_or(scene::TechniqueError::NotPrepared(id))?;

        regenerate_stale(frame, scene, scene, state, &settings, room_probe);
        let _ = &state.split_layout;
        let groups = impostor_groups(frame.gpu, scene, state, &settings);

        let ctx = frame.gpu;
        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget::of(target, true);
        let specular: Vec<usize> = state.maps.iter().map(|m| m.object).collect();
        // Caustics: photons from each light through each object.
        let caustic_groups = match &state.caustic {
            Some(caustic) => {
                let generators: Vec<_> = state
                    .maps
                    .iter()
                    .zip(&groups)
                    .map(|(m, group)| {
                        let maps = m
                            .caustics
                            .as_ref()
                            .expect("caustic maps are made in prepare");
                        (
                            m.object,
                            m.reference.expect("regenerated above"),
                            maps,
                            group,
                        )
                    })
                    .collect();
                frame.span("caustics", |frame| {
                    caustic.render(frame, scene, &generators)
                })
            }
            None => Vec::new(),
        };
        let receivers = ObjectFilter::Except(specular.clone());
        scene.raster(frame, &main, view_proj, view.camera.eye, &receivers, false);
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        if let Some(caustic) = &state.caustic {
            caustic.apply(
                frame,
                scene,
                &main,
                &camera,
                &groups,
                &caustic_groups,
                &receivers,
            );
        }

        let targets = (&target.color_view, &target.depth_view);
        let lookup_groups = (&groups[..], &caustic_groups[..]);
        lookup(
            frame,
            scene,
            targets,
            state,
            &camera,
            lookup_groups,
            &self.id,
        );
        Ok(())
    }
}

/// Regenerates the environment impostors of objects that moved farther than
/// `regen_threshold` from where their maps were made ("regenerate" span; a room probe is
/// captured once). Reads: the scene. Writes: those objects' cube maps, split distances and
/// caustic receivers.
fn regenerate_stale(
    frame: &mut Frame,
    scene: &GpuScene,
    host: &dyn gpu::DrawScene,
    state: &mut State,
    settings: &Settings,
    room_probe: bool,
) {
    // Regenerate the environment impostors of objects that moved too far (a room probe is
    // captured once).
    let time = scene.time();
    let stale: Vec<usize> = (0..state.maps.len())
        .filter(|&i| {
            let m = &state.maps[i];
            let center = scene.scene.objects[m.object].center_at(time);
            match m.reference {
                None => true,
                Some(_) if room_probe => false,
                Some(r) => {
                    settings.regen_threshold <= 0.0 || r.distance(center) > settings.regen_threshold
                }
            }
        })
        .collect();
    if !stale.is_empty() {
        frame.span("regenerate", |frame| {
            for &i in &stale {
                let m = &mut state.maps[i];
                let reference = match (state.proxy, scene::probe_centre(&scene.scene)) {
                    (Some(_), Some(probe)) if room_probe => probe,
                    _ => scene.scene.objects[m.object].center_at(time),
                };
                // Without the object itself (`render_environment` from another point: an
                // engine's probe would not hold the moving object either).
                let others = gpu::Objects::AllBut(&[m.object]);
                let depth_range = (0.01, 2.0 * scene::BACKGROUND_DISTANCE);
                gpu::host::draw_scene_cube(frame, host, &m.env, reference, depth_range, others);
                if let Some(split) = &m.split {
                    copy_distances(frame, &state.split_pipeline, split);
                }
                if let (Some(c), Some(maps)) = (&state.caustic, &m.caustics) {
                    c.render_receivers(frame, scene, i, maps, m.object, reference);
                }
                m.reference = Some(reference);
                m.regenerations += 1;
            }
        });
    }
}

/// The specular objects' pass, timed on its own as "lookup" (pass timestamps). Reads: each
/// object's impostor bindings (and caustic bindings). Writes: the specular surfaces' colour and
/// depth into the target.
fn lookup(
    frame: &mut Frame,
    scene: &GpuScene,
    (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
    state: &State,
    camera: &wgpu::BindGroup,
    (groups, caustic_groups): (&[wgpu::BindGroup], &[wgpu::BindGroup]),
    label: &str,
) {
    // The specular objects' pass, timed on its own as "lookup" (pass timestamps).
    let pipeline = match &state.caustic {
        Some(c) => &c.localized_pipeline,
        None => &state.pipeline,
    };
    let mut pass = scene.pass_over(frame, label, (color, depth), "lookup", (pipeline, camera));
    for (i, (m, group)) in state.maps.iter().zip(groups).enumerate() {
        pass.set_bind_group(2, group, &[]);
        if let Some(g3) = caustic_groups.get(i) {
            pass.set_bind_group(3, g3, &[]);
        }
        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![m.object]));
    }
}

/// What each object's maps are made with: the split copy's layout (split variants), the
/// refractor-map pipeline (double refraction), the caustics (caustic variants).
struct MapPipelines<'a> {
    split: Option<&'a wgpu::BindGroupLayout>,
    refractor: Option<&'a wgpu::RenderPipeline>,
    caustic: Option<&'a Caustics>,
}

/// Each specular object's maps at `res` texels: its distance impostor, and as the variant
/// needs the split distances, the refractor map (drawn now, once) and the caustic
/// generator maps.
fn object_maps(
    frame: &mut Frame,
    scene: &GpuScene,
    res: u32,
    made: &MapPipelines,
) -> TechniqueResult<Vec<ObjectMaps>> {
    let ctx = frame.gpu;
    let mut maps = Vec::new();
    for (object, o) in scene.scene.objects.iter().enumerate() {
        if !o.material.is_specular() {
            continue;
        }
        let env = CubeTarget::new(ctx, res, IMPOSTOR_FORMAT, "distance impostor")?;
        let split = (made.split)
            .map(|layout| split_distance(ctx, &env, layout))
            .transpose()?;
        let refractor = match (made.refractor, &o.material) {
            (Some(pipeline), Material::Glass { .. }) => {
                let cube = CubeTarget::new(ctx, res, IMPOSTOR_FORMAT, "refractor map")?;
                let center = o.center_at(scene.time());
                render_refractor_map(frame, scene, pipeline, &cube, object, center);
                Some(cube)
            }
            _ => None,
        };
        let caustics = match made.caustic {
            Some(c) => Some(c.generator_maps(ctx, res)?),
            None => None,
        };
        maps.push(ObjectMaps {
            object,
            env,
            split,
            refractor,
            caustics,
            reference: None,
            regenerations: 0,
        });
    }
    Ok(maps)
}

/// The uniform block `ImpostorParams` of localized.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ParamsGpu {
    reference: [f32; 4],
    refractor_center: [f32; 4],
    mode: u32,
    method: u32,
    iterations: u32,
    distance_channel: u32,
    refractor_iterations: u32,
    lookup: u32,
    _pad: [u32; 2],
    proxy_min: [f32; 4],
    proxy_max: [f32; 4],
}

/// Layout of `@group(2)` in localized.wgsl.
pub fn impostor_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "distance impostor",
        wgpu::ShaderStages::FRAGMENT,
        &[
            bind::texture_cube(), // radiance (+ distance in alpha when packed)
            bind::texture_cube(), // distances (split) or the radiance map again
            bind::sampler(),
            bind::uniform(),      // ImpostorParams
            bind::texture_cube(), // refractor map (normal + distance)
        ],
    )
}

fn single_texture_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    let unfilterable = bind::texture_2d_unfilterable();
    bind::layout(
        ctx,
        "packed face",
        wgpu::ShaderStages::FRAGMENT,
        &[unfilterable],
    )
}

fn split_distance(
    ctx: &Context,
    env: &CubeTarget,
    layout: &wgpu::BindGroupLayout,
) -> Result<SplitDistance, gpu::GpuError> {
    let distances = CubeTarget::new(ctx, env.size, SPLIT_DISTANCE_FORMAT, "impostor distances")?;
    let copy_groups = env
        .face_views
        .iter()
        .map(|face| bind::group(ctx, "packed face", layout, &[bind::view(face)]))
        .collect();
    Ok(SplitDistance {
        distances,
        copy_groups,
    })
}

/// Split distances start as opaque black (distance 0 where the copy draws nothing).
const CLEAR_OPAQUE_BLACK: Load<wgpu::Color> = Load::Clear(wgpu::Color::BLACK);

fn copy_distances(frame: &mut Frame, pipeline: &wgpu::RenderPipeline, split: &SplitDistance) {
    for face in 0..6 {
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "impostor split copy",
            &[pass::color(
                &split.distances.face_views[face],
                CLEAR_OPAQUE_BLACK,
            )],
            None,
            None,
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &split.copy_groups[face], &[]);
        gpu::fullscreen::draw(&mut pass);
    }
}

/// Renders `object`'s own surface from `center` into `cube`: outward normal and distance.
fn render_refractor_map(
    frame: &mut Frame,
    scene: &GpuScene,
    pipeline: &wgpu::RenderPipeline,
    cube: &CubeTarget,
    object: usize,
    center: Vec3,
) {
    let only = ObjectFilter::Only(vec![object]);
    scene.draw_cube(
        frame,
        cube,
        center,
        1e-3,
        pipeline,
        &[],
        &only,
        "refractor map",
    );
}

/// The `@group(2)` bind group of each object's maps for this frame. The refractor map is
/// searched from the object's centre *now*: double refraction and the caustic photons follow
/// a moving refractor in every frame, not where it stood when prepare rendered the map.
fn impostor_groups(
    ctx: &Context,
    scene: &GpuScene,
    state: &State,
    settings: &Settings,
) -> Vec<wgpu::BindGroup> {
    let time = scene.time();
    let proxy = state.proxy.unwrap_or((Vec3::ZERO, Vec3::ZERO));
    state
        .maps
        .iter()
        .enumerate()
        .map(|(slot, m)| {
            let reference = m.reference.expect("regenerated before use");
            let distance_view = m
                .split
                .as_ref()
                .map_or(&m.env.cube_view, |s| &s.distances.cube_view);
            let refractor_view = m
                .refractor
                .as_ref()
                .map_or(&m.env.cube_view, |c| &c.cube_view);
            let refractor_center = scene.scene.objects[m.object].center_at(time);
            let uniform = ParamsGpu {
                reference: reference.extend(0.0).to_array(),
                refractor_center: refractor_center.extend(0.0).to_array(),
                mode: settings.mode.wgsl_id(),
                method: settings.method.wgsl_id(),
                iterations: settings.iterations,
                distance_channel: if m.split.is_some() { 0 } else { 3 },
                refractor_iterations: settings.refractor_iterations,
                lookup: match (settings.lookup, state.proxy) {
                    (Lookup::Hit, _) => 0,
                    (Lookup::BoxProjected, Some(_)) => 1,
                    (Lookup::BoxProjected, None) => 2,
                },
                _pad: [0; 2],
                proxy_min: proxy.0.extend(0.0).to_array(),
                proxy_max: proxy.1.extend(0.0).to_array(),
            };
            state.groups.get(ctx, slot, &uniform, |params| {
                bind::group(
                    ctx,
                    "impostor",
                    &state.layout,
                    &[
                        bind::view(&m.env.cube_view),
                        bind::view(distance_view),
                        bind::sampler_resource(&ctx.samplers.linear_clamp),
                        params.binding(),
                        bind::view(refractor_view),
                    ],
                )
            })
        })
        .collect()
}
