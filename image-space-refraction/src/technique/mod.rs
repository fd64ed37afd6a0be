//! The image-space refraction techniques: one [`Refraction`] type configured as each variant.
//!
//! Where things are: `settings.rs` (the parameters, declared once), `variants.rs` (the
//! variants), `passes.rs` (the passes below, each a method of the prepared state stating what
//! it reads and writes), `resources.rs` (pipelines, layouts, budgets, view-sized buffers); this
//! file, [`Refraction`] with its `prepare` and a `render` that orders the passes.
//!
//! Per frame (nothing is precomputed but the baseline's `d_N`):
//!
//! 1. "regenerate": per specular object an environment cube map from its centre (the paper's
//!    environment map; the scene without that object, `scene::foundation::render_environment`);
//! 2. (nearby geometry) "impostors": the rectangle impostors' textures (recursive ones draw
//!    the specular objects with one interface); with caustics, "caustics": per light and
//!    refractor the light's front/back buffers, the photon pass and the scatter into the
//!    caustic textures, then their filter;
//! 3. "buffers": the specular objects' front- and back-facing surfaces from the eye into two
//!    `Rgba32Float` buffers (outward normal, view depth), the inputs of the searches of
//!    [`crate::search`];
//! 4. the opaque scene by the shared raster pass, then (caustics) caustic mapping adds the
//!    caustic textures onto the receivers; the thickness proxy copies it (the engine's
//!    scene-colour buffer);
//! 5. "lookup": the specular objects drawn with `refract_fs` (`refract_passes.wgsl` over the
//!    module `image_space_refraction::refract`), which follows each pixel's
//!    refracted ray through the variant's second interface to the environment.

use crate::caustics::{CausticSettings, Caustics, RefractorBindings};
use crate::rectangles::{self, NearbyParamsGpu, Rectangles};
use crate::search::{Eye, EyeGpu};
use glam::{Mat4, Vec3};
use gpu::cube::CubeTarget;
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::emission::jitter_declared;
use scene::technique::{Declared, ParamValue, check_map_budget, not_prepared, setting_if};

use scene::{
    Frame, GpuScene, ObjectFilter, RasterTarget, Scene, Technique, TechniqueError, TechniqueResult,
    View,
};

mod hosted;
mod passes;
mod resources;
mod settings;
mod variants;

pub use resources::*;
pub use settings::*;
pub use variants::*;

/// The refractor's bindings and shading: the module `image_space_refraction::refract`
/// ([`REFRACT`]).
pub const REFRACT_WGSL: &str = include_str!("../shaders/refract.wgsl");
/// [`REFRACT_WGSL`] as a module.
pub static REFRACT: gpu::wgsl::Module = gpu::wgsl::Module::new(
    REFRACT_WGSL,
    "image-space-refraction/src/shaders/refract.wgsl",
    &[&crate::search::SEARCH],
);
/// The radiance leaving the refractor with nearby geometry (the nearest rectangle impostor's
/// texel, else the environment): the module `image_space_refraction::nearby_radiance`, which
/// overrides `image_space_refraction::refract`'s `outgoing_radiance`.
pub static NEARBY_RADIANCE: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("../shaders/nearby_radiance.wgsl"),
    "image-space-refraction/src/shaders/nearby_radiance.wgsl",
    &[&crate::nearby::NEARBY, &REFRACT],
);
/// The entry points of the refractor's passes (its vertex stage, the buffers, the eye's view).
const REFRACT_PASSES_WGSL: &str = include_str!("../shaders/refract_passes.wgsl");
/// The photon buffer's entry point (with nearby geometry).
const PHOTON_WGSL: &str = include_str!("../shaders/photon.wgsl");

/// Most specular objects of a scene the technique renders with a map per object (the room
/// probe, `Settings::room_probe`, serves any number). The paper's scenes have one
/// refractor and a reflector or two; each specular object here costs an environment map, a
/// rectangle texture for every nearby object and (with caustics) a photon buffer per light,
/// every frame: `chess`'s 33 pieces would draw over a thousand rectangle textures a frame.
pub const MAX_SPECULAR_OBJECTS: usize = 4;

/// Format of the environment cube maps.
pub const ENV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the front and back buffers (outward normal, view depth).
pub const BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The WGSL `RefractParams` (refract.wgsl).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ParamsGpu {
    variant: u32,
    strategy: u32,
    max_iterations: u32,
    proxy: u32,
    tolerance: f32,
    initial_step: f32,
    thickness: f32,
    photon_jitter: u32,
    /// The room probe's centre (w: 1 when the lookup is box-projected) and its proxy box.
    probe: [f32; 4],
    box_min: [f32; 4],
    box_max: [f32; 4],
}

/// An image-space refraction variant.
pub struct Refraction {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: Settings,
    /// The formats of the targets the refractors are drawn into (the harness's, or a
    /// renderer's own through [`crate::RefractorPass`]).
    formats: gpu::TargetFormats,
    state: Option<State>,
}

struct State {
    layout: wgpu::BindGroupLayout,
    front_pipeline: wgpu::RenderPipeline,
    back_pipeline: wgpu::RenderPipeline,
    refract_pipeline: wgpu::RenderPipeline,
    /// Recursive variant: the one-interface, environment-only pipeline that draws a specular
    /// nearby object into its rectangle's texture.
    impostor_pipeline: Option<wgpu::RenderPipeline>,
    maps: Vec<ObjectMap>,
    rectangles: Option<Rectangles>,
    caustics: Option<Caustics>,
    normal_thickness: wgpu::Buffer,
    eye: Uniform<EyeGpu>,
    screen: Option<Screen>,
    /// The room probe, with where it is captured, until its one capture (first frame).
    probe_to_capture: Option<(std::rc::Rc<CubeTarget>, Vec3)>,
    /// The room probe's centre and proxy box (`Settings::room_probe` at `prepare`).
    room_probe: Option<RoomProbe>,
}

/// One specular object's environment map and parameters.
struct ObjectMap {
    object: usize,
    /// Its environment map: its own, or the room probe every object shares.
    cube: std::rc::Rc<CubeTarget>,
    params: Uniform<ParamsGpu>,
    /// The same with the one-interface variant: how the object is drawn into the rectangle
    /// textures of the recursive variant.
    impostor_params: Uniform<ParamsGpu>,
    /// Recursive variant: the whole environment (nearby objects included) from the object's
    /// centre, which its one-interface shading in the rectangle textures looks up.
    full_cube: Option<CubeTarget>,
}

/// The resources that follow the view's size.
struct Screen {
    width: u32,
    height: u32,
    front: wgpu::TextureView,
    back: wgpu::TextureView,
    depth: wgpu::TextureView,
    scene_color: wgpu::Texture,
    groups: Vec<wgpu::BindGroup>,
    impostor_groups: Vec<wgpu::BindGroup>,
}

impl Refraction {
    /// A variant named `id` with its description and settings ([`crate::techniques`] lists
    /// the configured ones).
    pub fn new(id: &str, description: &str, settings: Settings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            representative: true,
            settings,
            formats: gpu::TargetFormats::HDR,
            state: None,
        }
    }

    /// The variant drawing its refractors into targets of `formats` (a renderer's own).
    pub fn for_targets(mut self, formats: gpu::TargetFormats) -> Self {
        self.formats = formats;
        self.state = None;
        self
    }

    /// Leaves the variant out of the default `harness compare` (`--all-variants` runs it).
    pub fn exhaustive(mut self) -> Self {
        self.representative = false;
        self
    }

    /// The caustic passes, once prepared (caustic variants; for tests).
    pub fn caustics(&self) -> Option<&Caustics> {
        self.state.as_ref()?.caustics.as_ref()
    }

    /// The rectangle impostors, once prepared (nearby variants; for tests).
    pub fn rectangles(&self) -> Option<&Rectangles> {
        self.state.as_ref()?.rectangles.as_ref()
    }

    /// `probe`: the room probe's centre and proxy box, made at `prepare` (room probe only).
    fn params_gpu(&self, scene: &GpuScene, object: usize, probe: Option<RoomProbe>) -> ParamsGpu {
        let o = &scene.scene.objects[object];
        let time = scene.time();
        let radius = o.bounding_radius_at(time);
        let s = &self.settings;
        ParamsGpu {
            variant: s.variant.wgsl_id(),
            strategy: u32::from(s.back_first),
            max_iterations: s.max_iterations,
            proxy: u32::from(s.box_proxy),
            tolerance: s.tolerance,
            initial_step: s.initial_step * radius,
            thickness: s.thickness * 2.0 * radius,
            photon_jitter: s.caustics.as_ref().is_some_and(|c| c.jitter) as u32,
            probe: [0.0; 4],
            box_min: [0.0; 4],
            box_max: [0.0; 4],
        }
        .with_probe(probe)
    }
}

/// Where the room probe is captured and the proxy box it is projected against.
type RoomProbe = (Vec3, (Vec3, Vec3));

impl Refraction {
    /// Settings that cannot go together: caustics without the rectangles they land on, the
    /// room probe with nearby geometry.
    fn check_settings(&self) -> TechniqueResult<()> {
        if self.settings.caustics.is_some() && self.settings.nearby.is_none() {
            return Err(TechniqueError::Unsupported(format!(
                "{}: caustics need the rectangle impostors of nearby geometry (the photons land \
                 on them); set Settings::nearby",
                self.id
            )));
        }
        if self.settings.room_probe && self.settings.nearby.is_some() {
            return Err(TechniqueError::Unsupported(format!(
                "{}: the room probe replaces the environment maps of the variants without \
                 nearby geometry; set Settings::nearby to None",
                self.id
            )));
        }
        Ok(())
    }

    /// Caustic mapping renders its photon buffers from each light's position (section 5).
    fn caustic_lights(&self, scene: &Scene) -> TechniqueResult<()> {
        if self.settings.caustics.is_none() {
            return Ok(());
        }
        scene::point_lights_only(
            &self.id,
            "its photon buffers are the refractors seen from each light's position",
            scene,
        )
    }

    /// Each specular object's maps (its environment cube, or the shared room probe; the whole
    /// environment for recursive impostors) and its parameter uniforms.
    fn object_maps(
        &self,
        ctx: &Context,
        scene: &GpuScene,
        specular: &[usize],
        probe: Option<&std::rc::Rc<CubeTarget>>,
        room_probe: Option<RoomProbe>,
    ) -> TechniqueResult<Vec<ObjectMap>> {
        let resolution = self.settings.env_resolution;
        let recursive = self.settings.nearby.is_some_and(|n| n.recursive);
        let mut maps = Vec::new();
        for &object in specular {
            let params = self.params_gpu(scene, object, room_probe);
            let one_interface = ParamsGpu {
                variant: Variant::OneInterface.wgsl_id(),
                ..params
            };
            let full_cube = match recursive {
                true => Some(CubeTarget::new(
                    ctx,
                    resolution,
                    ENV_FORMAT,
                    "whole environment",
                )?),
                false => None,
            };
            let cube = match probe {
                Some(shared) => shared.clone(),
                None => std::rc::Rc::new(environment_map(ctx, resolution)?),
            };
            maps.push(ObjectMap {
                object,
                full_cube,
                cube,
                params: Uniform::new(ctx, "refract params", &params),
                impostor_params: Uniform::new(ctx, "impostor params", &one_interface),
            });
        }
        Ok(maps)
    }

    /// The rectangle impostors of nearby geometry, for every specular object (variants
    /// with `nearby` only), within the map budget.
    fn rectangles_of(
        &self,
        ctx: &Context,
        scene: &GpuScene,
        specular: &[usize],
    ) -> TechniqueResult<Option<Rectangles>> {
        let Some(n) = self.settings.nearby else {
            return Ok(None);
        };
        check_map_budget(
            &self.id,
            scene.scene.objects.len() * specular.len(),
            u64::from(n.resolution).pow(2) * 20,
            "impostor_resolution",
        )?;
        let params = NearbyParamsGpu::new(0, n.corrected, n.seeds, n.iterations, n.tolerance);
        Ok(Some(ctx.allocating("rectangle impostors", || {
            Rectangles::new(ctx, &scene.scene, specular, n.resolution, params)
        })?))
    }
}

/// An object's environment cube map (or the room probe).
fn environment_map(ctx: &Context, resolution: u32) -> Result<CubeTarget, gpu::GpuError> {
    CubeTarget::new(ctx, resolution, ENV_FORMAT, "environment map")
}

impl ParamsGpu {
    /// The room probe's lookup: from where it was captured (`scene::probe_centre`),
    /// box-projected against its proxy box.
    fn with_probe(mut self, probe: Option<RoomProbe>) -> Self {
        if let Some((centre, (lo, hi))) = probe {
            self.probe = centre.extend(1.0).to_array();
            self.box_min = lo.extend(0.0).to_array();
            self.box_max = hi.extend(0.0).to_array();
        }
        self
    }
}

impl Technique for Refraction {
    scene::named_variant!();
    // Maps, buffers and the probe follow the settings: a set parameter drops them.
    scene::declared_params!(settings, state);
    fn required_features(&self) -> wgpu::Features {
        match self.settings.caustics {
            // Caustic mapping adds the caustics onto the 32-bit float target by blending.
            Some(_) => wgpu::Features::FLOAT32_BLENDABLE,
            None => wgpu::Features::empty(),
        }
    }
    fn supports(&self, scene: &Scene) -> bool {
        let specular = scene
            .objects
            .iter()
            .filter(|o| o.material.is_specular())
            .count();
        // One probe serves any number of objects; per-object maps are budgeted.
        let most = match self.settings.room_probe {
            true => usize::MAX,
            false => MAX_SPECULAR_OBJECTS,
        };
        (1..=most).contains(&specular) && self.caustic_lights(scene).is_ok()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        ctx.require(self.required_features())?;
        self.check_settings()?;
        self.caustic_lights(&scene.scene)?;
        let specular = scene.scene.specular_objects();
        let resolution = self.settings.env_resolution;
        let room_probe = self.settings.room_probe;
        check_map_budget(
            &self.id,
            if room_probe { 1 } else { specular.len() },
            CubeTarget::bytes(resolution, ENV_FORMAT),
            "resolution",
        )?;
        let probe = match room_probe {
            true => Some(std::rc::Rc::new(environment_map(ctx, resolution)?)),
            false => None,
        };
        // Where the probe stands and what it is projected against, once.
        let room_probe = room_probe
            .then(|| scene::probe_centre(&scene.scene).zip(scene::probe_proxy_box(&scene.scene)))
            .flatten();
        let layout = group_layout(ctx);
        let nearby_layout = rectangles::group_layout(ctx);
        let made = match self.settings.nearby {
            Some(_) => pipelines(ctx, scene, &[&layout, &nearby_layout], true, self.formats),
            None => pipelines(ctx, scene, &[&layout], false, self.formats),
        };
        let impostor_pipeline = self
            .settings
            .nearby
            .filter(|n| n.recursive)
            .map(|_| pipelines(ctx, scene, &[&layout], false, gpu::TargetFormats::HDR).refract);
        let rectangles = self.rectangles_of(ctx, scene, &specular)?;
        let maps = self.object_maps(ctx, scene, &specular, probe.as_ref(), room_probe)?;
        // Every variant's vertex stage reads it; only Wyman's baseline fills it.
        let wyman = self.settings.variant == Variant::TwoInterfaceBaseline;
        let thickness = normal_thickness(scene, if wyman { &specular } else { &[] });
        let normal_thickness = storage_buffer(ctx, "d_N per vertex", &thickness);
        let eye = Uniform::new(ctx, "eye", &EyeGpu::from(&placeholder_eye()));
        let caustics = match (self.settings.caustics, &rectangles, made.photon) {
            (Some(settings), Some(rects), Some(photon_pipeline)) => {
                check_caustic_budget(ctx, &self.id, &settings, rects)?;
                let bindings = RefractorBindings {
                    layout: &layout,
                    refractors: maps
                        .iter()
                        .map(|m| (&m.cube.cube_view, m.params.binding()))
                        .collect(),
                    normal_thickness: &normal_thickness,
                    photon_pipeline,
                };
                Some(ctx.allocating("caustics", || {
                    Caustics::new(ctx, scene, settings, rects, bindings)
                })?)
            }
            _ => None,
        };
        self.state = Some(State {
            layout,
            front_pipeline: made.front,
            back_pipeline: made.back,
            refract_pipeline: made.refract,
            impostor_pipeline,
            maps,
            rectangles,
            caustics,
            normal_thickness,
            eye,
            screen: None,
            probe_to_capture: probe.map(|cube| {
                let centre = room_probe.map_or(Vec3::ZERO, |(centre, _)| centre);
                (cube, centre)
            }),
            room_probe,
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
        let params: Vec<ParamsGpu> = match &self.state {
            Some(state) => state
                .maps
                .iter()
                .map(|m| self.params_gpu(scene, m.object, state.room_probe))
                .collect(),
            None => return Err(not_prepared(self)),
        };
        let variant = self.settings.variant;
        let Some(state) = self.state.as_mut() else {
            return Err(TechniqueError::NotPrepared(self.id.clone()));
        };
        let ctx = frame.gpu;
        if variant == Variant::ThicknessProxy
            && !target.color.usage().contains(wgpu::TextureUsages::COPY_SRC)
        {
            return Err(TechniqueError::Unsupported(
                "the thickness proxy copies the target's colour (the scene colour buffer): \
                 its texture needs the COPY_SRC usage"
                    .into(),
            ));
        }
        state.ensure_screen(ctx, view.width, view.height);
        let eye = Eye::of_camera(&view.camera, view.width, view.height);
        state.write_frame_params(ctx, &eye, &params);
        if let Some(rects) = state.rectangles.as_mut() {
            rects.place(ctx, scene);
        }
        let probe_to_capture = state.probe_to_capture.take();
        let state = &*state;
        frame.span("regenerate", |frame| {
            state.regenerate(frame, scene, scene, probe_to_capture)
        });
        if let Some(rects) = &state.rectangles {
            frame.span("impostors", |frame| state.impostors(frame, scene, rects));
            if let Some(caustics) = &state.caustics {
                frame.span("caustics", |frame| {
                    let pipelines = [&state.front_pipeline, &state.back_pipeline];
                    caustics.record(frame, scene, &state.specular(), rects, pipelines);
                });
            }
        }
        let view_proj = view.camera.view_proj(view.width, view.height);
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        if variant.needs_buffers() {
            frame.span("buffers", |frame| state.front_back(frame, scene, &camera));
        }
        scene::multi_object::raster_diffuse(frame, scene, view, target, &state.specular());
        let main = RasterTarget::of(target, false);
        if let (Some(caustics), Some(rects)) = (&state.caustics, &state.rectangles) {
            caustics.map(frame, scene, &camera, rects, &main);
        }
        if variant == Variant::ThicknessProxy {
            let scene_color = &state
                .screen
                .as_ref()
                .expect("ensure_screen made it")
                .scene_color;
            frame.encoder.copy_texture_to_texture(
                target.color.as_image_copy(),
                scene_color.as_image_copy(),
                scene_color.size(),
            );
        }
        frame.span("lookup", |frame| state.lookup(frame, scene, &camera, &main));
        Ok(())
    }
}
