//! The image-space refraction techniques: one [`Refraction`] type configured as each variant.
//!
//! Per frame (nothing is precomputed but the baseline's `d_N`):
//!
//! 1. "regenerate": per specular object an environment cube map from its centre (the paper's
//!    environment map; the scene without that object, `scene::foundation::render_environment`);
//! 2. "buffers": the specular objects' front- and back-facing surfaces from the eye into two
//!    `Rgba32Float` buffers (outward normal, view depth), the inputs of the searches of
//!    [`crate::search`];
//! 3. the opaque scene by the shared raster pass; the thickness proxy copies it (the engine's
//!    scene-colour buffer);
//! 4. "lookup": the specular objects drawn with `refract.wgsl`, which follows each pixel's
//!    refracted ray through the variant's second interface to the environment.

use crate::caustics::{CausticSettings, Caustics, RefractorBindings};
use crate::rectangles::{self, NearbyParamsGpu, Rectangles};
use crate::search::{Eye, EyeGpu};
use glam::{Mat4, Vec3};
use gpu::cube::CubeTarget;
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::Settings as _;
use scene::emission::jitter_declared;
use scene::technique::{
    Declared, ParamValue, check_map_budget, not_prepared, set_checked, setting_if,
};

use scene::{
    Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene, Technique, TechniqueError,
    TechniqueResult, View,
};

/// WGSL of the searches (`search.rs`'s twin); needs the gpu prelude before it and the
/// includer's `front_buffer`/`back_buffer` textures.
pub const SEARCH_WGSL: &str = include_str!("shaders/search.wgsl");
const REFRACT_WGSL: &str = include_str!("shaders/refract.wgsl");
const ENVIRONMENT_WGSL: &str = include_str!("shaders/environment.wgsl");
const NEARBY_WGSL: &str = concat!(
    include_str!("shaders/rect.wgsl"),
    "\n",
    include_str!("shaders/nearby.wgsl"),
    "\n",
    include_str!("shaders/photon.wgsl")
);

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

/// How a variant finds the second interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The refracted ray `T1` looks the environment up at once (one interface).
    OneInterface,
    /// Wyman 2005: `P2 = P1 + d T1`, `d` interpolated between the view-ray thickness and the
    /// precomputed thickness along the normal; back-facing `N2` (the method the paper improves).
    TwoInterfaceBaseline,
    /// Hu and Qin 2006, section 2.1: side by angle test (or back first), iterative `d_T`.
    HuQin,
    /// The engine approach (HDRP's sphere model): one bend, a thickness, the scene colour.
    ThicknessProxy,
}

impl Variant {
    fn wgsl_id(self) -> u32 {
        match self {
            Variant::OneInterface => 0,
            Variant::TwoInterfaceBaseline => 1,
            Variant::HuQin => 2,
            Variant::ThicknessProxy => 3,
        }
    }
    fn needs_buffers(self) -> bool {
        matches!(self, Variant::TwoInterfaceBaseline | Variant::HuQin)
    }
}

/// Parameters of a [`Refraction`] (settable by name through [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The second-interface method.
    pub variant: Variant,
    /// Face size of the environment cube maps (`resolution`).
    pub env_resolution: u32,
    /// `d_T` iteration: stop when a correction is at most this (metres, `tolerance`).
    pub tolerance: f32,
    /// `d_T` iteration: most corrections (`iterations`).
    pub max_iterations: u32,
    /// `d_T` iteration: the first `d_T` as a fraction of the refractor's bounding radius
    /// (`initial_step`).
    pub initial_step: f32,
    /// Section 4's acceleration: back side first, front side when `P2` leaves the silhouette
    /// (`back_first` 1), instead of the silhouette search and angle test (0).
    pub back_first: bool,
    /// Thickness proxy: the sphere's diameter (or the slab's thickness) as a fraction of the
    /// object's bounding diameter (`thickness`).
    pub thickness: f32,
    /// Thickness proxy: HDRP's box model (a slab: one bend, leaving along the view ray,
    /// `proxy` 1) instead of its sphere model (into and out of a tangent sphere, `proxy` 0).
    pub box_proxy: bool,
    /// Nearby geometry as rectangle impostors (section 2.2), or the environment map alone.
    pub nearby: Option<Nearby>,
    /// Caustics (section 3; needs `nearby`: photons land on the rectangles).
    pub caustics: Option<CausticSettings>,
    /// The engine's environment (`probe` 1): one reflection probe for every object, captured
    /// once in the first frame where an artist would place it (`scene::probe_centre`) without
    /// the specular objects, looked up box-projected against the scene's diffuse bounds
    /// (Lagarde and Zanuttini 2012, `gpu::prelude::box_project`), instead of the paper's map
    /// from each object's centre every frame. One map whatever the number of objects: a scene of many glass
    /// objects (`chess`) renders. Without `nearby` only.
    pub room_probe: bool,
}

impl scene::Settings for Settings {
    /// Which parameters a variant has follows its second-interface method, its nearby
    /// geometry and its caustics.
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "resolution",
            (4.0, 4096.0),
            "environment cube map face size (texels)",
            |s| Some(&mut s.env_resolution),
        ),
        Declared::new(
            "tolerance",
            (1e-6, 1.0),
            "d_T iteration stops when a correction is at most this (m of view depth)",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.tolerance),
        ),
        Declared::new(
            "iterations",
            (1.0, 64.0),
            "d_T iteration: most corrections",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.max_iterations),
        ),
        Declared::new(
            "initial_step",
            (1e-4, 2.0),
            "d_T iteration: first d_T as a fraction of the refractor's bounding radius",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.initial_step),
        ),
        Declared::new(
            "back_first",
            (0.0, 1.0),
            "1: section 4's acceleration (back side first); 0: silhouette search and angle \
             test",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.back_first),
        ),
        Declared::new(
            "thickness",
            (0.0, 4.0),
            "the proxy sphere's diameter (slab's thickness) as a fraction of the object's \
             bounding diameter",
            |s| setting_if(s.variant == Variant::ThicknessProxy, &mut s.thickness),
        ),
        Declared::new(
            "proxy",
            (0.0, 1.0),
            "0: HDRP's sphere model (in and out of a tangent sphere); 1: its box model (a \
             slab, leaving along the view ray)",
            |s| setting_if(s.variant == Variant::ThicknessProxy, &mut s.box_proxy),
        ),
        Declared::new(
            "probe",
            (0.0, 1.0),
            "1: one room probe for every object, captured once, box-projected (the engine's); \
             0: the paper's map from each object's centre every frame",
            |s| setting_if(s.nearby.is_none(), &mut s.room_probe),
        ),
        Declared::new(
            "photon_buffer",
            (8.0, 2048.0),
            "side of each light's photon buffer (photons per light: its square)",
            |s| Some(&mut s.caustics.as_mut()?.photon_size),
        ),
        Declared::new(
            "caustic_resolution",
            (8.0, 2048.0),
            "side of each rectangle's caustic texture (texels)",
            |s| Some(&mut s.caustics.as_mut()?.resolution),
        ),
        Declared::new(
            "filter_k",
            (0.0, 8.0),
            "the caustic filter's half size k (section 3.2; the paper's default 2)",
            |s| Some(&mut s.caustics.as_mut()?.k),
        ),
        jitter_declared(|s| Some(&mut s.caustics.as_mut()?.jitter)),
        Declared::new(
            "filter_s",
            (0.0, 100.0),
            "the caustic filter's scale s (1: the photons' power; the filter is normalized by \
             its weights)",
            |s| Some(&mut s.caustics.as_mut()?.scale),
        ),
        Declared::new(
            "impostor_resolution",
            (8.0, 4096.0),
            "side of each rectangle impostor's texture (texels)",
            |s| Some(&mut s.nearby.as_mut()?.resolution),
        ),
        Declared::new(
            "seeds",
            (1.0, 64.0),
            "points on the ray tried as the correction's start (figure 17)",
            |s| corrected(s).map(|n| &mut n.seeds as &mut dyn ParamValue),
        ),
        Declared::new(
            "corrections",
            (1.0, 64.0),
            "most depth corrections of a rectangle lookup (figure 16)",
            |s| corrected(s).map(|n| &mut n.iterations as &mut dyn ParamValue),
        ),
        Declared::new(
            "depth_tolerance",
            (1e-6, 1.0),
            "a correction stops within this depth difference (m)",
            |s| corrected(s).map(|n| &mut n.tolerance as &mut dyn ParamValue),
        ),
    ];
}

/// The rectangle impostors' settings where their lookup is depth-corrected.
fn corrected(s: &mut Settings) -> Option<&mut Nearby> {
    s.nearby.as_mut().filter(|n| n.corrected)
}

/// Parameters of the rectangle impostors of nearby geometry (section 2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearby {
    /// Figure 16's iterative depth correction from figure 17's seed (`corrected`), or the
    /// texel where the ray meets the rectangle (figure 13).
    pub corrected: bool,
    /// Seeds on the ray for the first point of the correction (`seeds`).
    pub seeds: u32,
    /// Most corrections (`corrections`).
    pub iterations: u32,
    /// Depth tolerance of a correction, metres (`depth_tolerance`).
    pub tolerance: f32,
    /// Side of each impostor texture (`impostor_resolution`).
    pub resolution: u32,
    /// Reflective and refractive nearby objects drawn into their textures with their own
    /// (one-interface) shading: recursive reflections and refractions (section 2.2.1).
    pub recursive: bool,
}

impl Default for Nearby {
    fn default() -> Self {
        Self {
            corrected: true,
            seeds: 8,
            iterations: 4,
            tolerance: 1e-3,
            resolution: 256,
            recursive: false,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            variant: Variant::HuQin,
            env_resolution: 256,
            tolerance: 1e-3,
            max_iterations: 8,
            initial_step: 0.1,
            back_first: false,
            thickness: 1.0,
            box_proxy: false,
            nearby: None,
            caustics: None,
            room_probe: false,
        }
    }
}

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
            state: None,
        }
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

/// The variants of this crate.
pub fn variants() -> Vec<Box<dyn Technique>> {
    configured()
        .into_iter()
        .map(|r| Box::new(r) as Box<dyn Technique>)
        .collect()
}

/// One variant by its name (`hu-qin`, `caustics`, ...), as its concrete type.
pub fn variant(name: &str) -> Option<Refraction> {
    let id = format!("image-space-refraction/{name}");
    configured().into_iter().find(|r| r.id == id)
}

fn configured() -> Vec<Refraction> {
    let with = |variant, back_first| Settings {
        variant,
        back_first,
        ..Settings::default()
    };
    let id = |v: &str| format!("image-space-refraction/{v}");
    let nearby = |corrected, recursive| Settings {
        nearby: Some(Nearby {
            corrected,
            recursive,
            ..Nearby::default()
        }),
        ..Settings::default()
    };
    vec![
        (Refraction::new(
            &id("one-interface"),
            "refraction at the visible surface only, the environment map looked up with T1",
            with(Variant::OneInterface, false),
        )),
        (Refraction::new(
            &id("two-interface-baseline"),
            "Wyman 2005: exit point from the view-ray and precomputed normal thickness, \
             back-facing normal (the method Hu and Qin improve)",
            with(Variant::TwoInterfaceBaseline, false),
        )),
        (Refraction::new(
            &id("hu-qin"),
            "Hu and Qin 2006: front/back buffers every frame, silhouette search and angle \
             test, iterative d_T, environment map",
            with(Variant::HuQin, false),
        )),
        (Refraction::new(
            &id("hu-qin-back-first"),
            "hu-qin with section 4's acceleration: back side first, front side when P2 \
             leaves the silhouette",
            with(Variant::HuQin, true),
        ))
        .exhaustive(),
        (Refraction::new(
            &id("nearby-uncorrected"),
            "hu-qin with nearby objects as rectangle impostors (section 2.2), the texel where \
             the ray meets the rectangle",
            nearby(false, false),
        )),
        (Refraction::new(
            &id("baseline-nearby"),
            "two-interface-baseline with the rectangle impostors and depth correction: the \
             paper's figure 11 (Wyman's exit point against Hu and Qin's, nearby geometry)",
            Settings {
                variant: Variant::TwoInterfaceBaseline,
                ..nearby(true, false)
            },
        ))
        .exhaustive(),
        (Refraction::new(
            &id("nearby-corrected"),
            "hu-qin with rectangle impostors and the iterative depth correction from the \
             paper's seed (figures 16-17)",
            nearby(true, false),
        )),
        (Refraction::new(
            &id("recursive"),
            "nearby-corrected with reflective and refractive nearby objects drawn into their \
             textures with their own shading (recursive reflections and refractions)",
            nearby(true, true),
        )),
        (Refraction::new(
            &id("caustics"),
            "nearby-corrected with caustics: photon buffers from the lights through the \
             refractor, caustic textures on the rectangles filtered on the GPU, caustic \
             mapping onto the receivers (section 3)",
            Settings {
                caustics: Some(CausticSettings::default()),
                ..nearby(true, false)
            },
        )),
        (Refraction::new(
            &id("thickness-proxy"),
            "engine baseline: screen-space refraction with a thickness proxy (HDRP's sphere \
             model: one bend, a sphere's chord, the scene colour buffer)",
            with(Variant::ThicknessProxy, false),
        )),
        (Refraction::new(
            &id("thickness-proxy-probe"),
            "engine baseline as shipped: thickness-proxy with the room's reflection probe (one \
             box-projected probe captured once, no per-object maps): any number of glass \
             objects",
            Settings {
                room_probe: true,
                ..with(Variant::ThicknessProxy, false)
            },
        )),
    ]
}

impl Technique for Refraction {
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
        self.settings.params()
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id, &mut self.settings, name, value)?;
        // Maps, buffers and the probe follow the settings: prepare() makes them again.
        self.state = None;
        Ok(())
    }
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
        (1..=most).contains(&specular)
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        ctx.require(self.required_features())?;
        if self.settings.caustics.is_some() && self.settings.nearby.is_none() {
            return Err(TechniqueError::Unsupported(format!(
                "{}: caustics need the rectangle impostors of nearby geometry (the photons land \
                 on them); set Settings::nearby",
                self.id
            )));
        }
        let specular: Vec<usize> = (0..scene.scene.objects.len())
            .filter(|&i| scene.scene.objects[i].material.is_specular())
            .collect();
        let resolution = self.settings.env_resolution;
        let room_probe = self.settings.room_probe;
        if room_probe && self.settings.nearby.is_some() {
            return Err(TechniqueError::Unsupported(format!(
                "{}: the room probe replaces the environment maps of the variants without \
                 nearby geometry; set Settings::nearby to None",
                self.id
            )));
        }
        check_map_budget(
            &self.id,
            if room_probe { 1 } else { specular.len() },
            CubeTarget::bytes(resolution, ENV_FORMAT),
            "resolution",
        )?;
        let new_map = || -> TechniqueResult<std::rc::Rc<CubeTarget>> {
            Ok(std::rc::Rc::new(CubeTarget::new(
                ctx,
                resolution,
                ENV_FORMAT,
                "environment map",
            )?))
        };
        let probe = if room_probe { Some(new_map()?) } else { None };
        // Where the probe stands and what it is projected against, once.
        let room_probe = room_probe
            .then(|| scene::probe_centre(&scene.scene).zip(scene::probe_proxy_box(&scene.scene)))
            .flatten();
        let layout = group_layout(ctx);
        let nearby_layout = rectangles::group_layout(ctx);
        let made = match self.settings.nearby {
            Some(_) => pipelines(ctx, scene, &[&layout, &nearby_layout], NEARBY_WGSL),
            None => pipelines(ctx, scene, &[&layout], ENVIRONMENT_WGSL),
        };
        let impostor_pipeline = self
            .settings
            .nearby
            .filter(|n| n.recursive)
            .map(|_| pipelines(ctx, scene, &[&layout], ENVIRONMENT_WGSL).refract);
        let rectangles = match self.settings.nearby {
            Some(n) => {
                check_map_budget(
                    &self.id,
                    scene.scene.objects.len() * specular.len(),
                    u64::from(n.resolution).pow(2) * 20,
                    "impostor_resolution",
                )?;
                let params =
                    NearbyParamsGpu::new(0, n.corrected, n.seeds, n.iterations, n.tolerance);
                Some(ctx.allocating("rectangle impostors", || {
                    Rectangles::new(ctx, &scene.scene, &specular, n.resolution, params)
                })?)
            }
            None => None,
        };
        let mut maps = Vec::new();
        for &object in &specular {
            let params = self.params_gpu(scene, object, room_probe);
            let one_interface = ParamsGpu {
                variant: Variant::OneInterface.wgsl_id(),
                ..params
            };
            let recursive = self.settings.nearby.is_some_and(|n| n.recursive);
            maps.push(ObjectMap {
                object,
                full_cube: if recursive {
                    Some(CubeTarget::new(
                        ctx,
                        resolution,
                        ENV_FORMAT,
                        "whole environment",
                    )?)
                } else {
                    None
                },
                cube: match &probe {
                    Some(shared) => shared.clone(),
                    None => new_map()?,
                },
                params: Uniform::new(ctx, "refract params", &params),
                impostor_params: Uniform::new(ctx, "impostor params", &one_interface),
            });
        }
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
        state.eye.write(ctx, &EyeGpu::from(&eye));
        for (map, p) in state.maps.iter().zip(&params) {
            map.params.write(ctx, p);
            let one_interface = ParamsGpu {
                variant: Variant::OneInterface.wgsl_id(),
                ..*p
            };
            map.impostor_params.write(ctx, &one_interface);
        }
        if let Some(rects) = state.rectangles.as_mut() {
            rects.place(ctx, scene);
        }
        let probe_to_capture = state.probe_to_capture.take();
        let state = &*state;

        // The environment: everything but the object itself and its rectangles.
        let in_rectangles = state
            .rectangles
            .as_ref()
            .map(|r| r.objects())
            .unwrap_or_default();
        frame.span("regenerate", |frame| {
            if let Some((probe, centre)) = probe_to_capture {
                // The engine's baked probe: the scene without its specular objects, once.
                let specular = state.maps.iter().map(|m| m.object).collect();
                scene.raster_cube(
                    frame,
                    &probe,
                    centre,
                    &ObjectFilter::Except(specular),
                    false,
                );
            }
            // What `prepare` built decides, not the settings since.
            let per_object = match state.room_probe.is_some() {
                true => &[][..],
                false => &state.maps[..],
            };
            for map in per_object {
                let centre = scene.scene.objects[map.object].center_at(scene.time());
                let mut left_out = in_rectangles.clone();
                left_out.push(map.object);
                scene.raster_cube(
                    frame,
                    &map.cube,
                    centre,
                    &ObjectFilter::Except(left_out),
                    false,
                );
                if let Some(full) = &map.full_cube {
                    let own = ObjectFilter::Except(vec![map.object]);
                    scene.raster_cube(frame, full, centre, &own, false);
                }
            }
        });

        let screen = state.screen.as_ref().expect("ensure_screen made it");
        if let Some(rects) = &state.rectangles {
            frame.span("impostors", |frame| {
                let mut draw =
                    |frame: &mut Frame, object: usize, view_proj, eye, target: RasterTarget| {
                        let i = state.maps.iter().position(|m| m.object == object);
                        let (Some(i), Some(pipeline)) = (i, &state.impostor_pipeline) else {
                            return;
                        };
                        let camera = scene.camera_bind_group(frame.gpu, view_proj, eye);
                        let mut pass = scene::begin_scene_pass(
                            frame.encoder,
                            &target,
                            scene.scene.background,
                            "recursive impostor",
                        );
                        pass.set_pipeline(pipeline);
                        pass.set_bind_group(0, &camera, &[]);
                        pass.set_bind_group(1, scene.bind_group(), &[]);
                        pass.set_bind_group(2, &screen.impostor_groups[i], &[]);
                        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![object]));
                    };
                let recursive = state.impostor_pipeline.is_some();
                rects.render(frame, scene, if recursive { Some(&mut draw) } else { None });
            });
            if let Some(caustics) = &state.caustics {
                frame.span("caustics", |frame| {
                    let refractors: Vec<usize> = state.maps.iter().map(|m| m.object).collect();
                    caustics.record(
                        frame,
                        scene,
                        &refractors,
                        rects,
                        [&state.front_pipeline, &state.back_pipeline],
                    );
                });
            }
        }

        let specular: Vec<usize> = state.maps.iter().map(|m| m.object).collect();
        let view_proj = view.camera.view_proj(view.width, view.height);
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        if variant.needs_buffers() {
            frame.span("buffers", |frame| {
                for (pipeline, buffer) in [
                    (&state.front_pipeline, &screen.front),
                    (&state.back_pipeline, &screen.back),
                ] {
                    let mut pass = gpu::pass::begin(
                        frame.encoder,
                        "front/back buffer",
                        &[gpu::pass::color(buffer, gpu::pass::CLEAR_BLACK)],
                        Some(gpu::pass::depth(&screen.depth, gpu::pass::CLEAR_FAR)),
                        None,
                    );
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &camera, &[]);
                    pass.set_bind_group(1, scene.bind_group(), &[]);
                    scene.draw_objects(&mut pass, &ObjectFilter::Only(specular.clone()));
                }
            });
        }

        scene::multi_object::raster_diffuse(frame, scene, view, target, &specular);
        let main = RasterTarget::of(target, false);
        if let (Some(caustics), Some(rects)) = (&state.caustics, &state.rectangles) {
            caustics.map(frame, scene, &camera, rects, &main);
        }
        if variant == Variant::ThicknessProxy {
            frame.encoder.copy_texture_to_texture(
                target.color.as_image_copy(),
                screen.scene_color.as_image_copy(),
                screen.scene_color.size(),
            );
        }

        frame.span("lookup", |frame| {
            let mut pass = scene::begin_scene_pass(
                frame.encoder,
                &RasterTarget {
                    clear: false,
                    ..main
                },
                scene.scene.background,
                "image-space refraction",
            );
            pass.set_pipeline(&state.refract_pipeline);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            for (k, (map, group)) in state.maps.iter().zip(&screen.groups).enumerate() {
                pass.set_bind_group(2, group, &[]);
                if let Some(rects) = &state.rectangles {
                    pass.set_bind_group(3, &rects.refractors[k].group, &[]);
                }
                scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![map.object]));
            }
        });
        Ok(())
    }
}

impl State {
    /// (Re)makes the buffers and bind groups when the view's size changes.
    fn ensure_screen(&mut self, ctx: &Context, width: u32, height: u32) {
        if self
            .screen
            .as_ref()
            .is_some_and(|s| s.width == width && s.height == height)
        {
            return;
        }
        let size = (width, height, 1);
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let none = wgpu::TextureUsages::empty();
        let front = gpu::render_texture(ctx, "front buffer", size, BUFFER_FORMAT, none);
        let back = gpu::render_texture(ctx, "back buffer", size, BUFFER_FORMAT, none);
        let depth = gpu::depth_texture(ctx, width, height, 1, "front/back depth");
        let scene_color = gpu::render_texture(
            ctx,
            "scene colour",
            size,
            gpu::HDR_FORMAT,
            wgpu::TextureUsages::COPY_DST,
        );
        let (front, back, depth, scene_color_view) =
            (view(&front), view(&back), view(&depth), view(&scene_color));
        let group = |cube: &CubeTarget, params: &Uniform<ParamsGpu>| {
            bind::group(
                ctx,
                "image-space refraction",
                &self.layout,
                &[
                    bind::view(&cube.cube_view),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                    params.binding(),
                    self.eye.binding(),
                    bind::view(&front),
                    bind::view(&back),
                    bind::view(&scene_color_view),
                    self.normal_thickness.as_entire_binding(),
                ],
            )
        };
        let groups = self
            .maps
            .iter()
            .map(|m| group(&m.cube, &m.params))
            .collect();
        let impostor_groups = self
            .maps
            .iter()
            .map(|m| group(m.full_cube.as_ref().unwrap_or(&m.cube), &m.impostor_params))
            .collect();
        self.screen = Some(Screen {
            width,
            height,
            front,
            back,
            depth,
            scene_color,
            groups,
            impostor_groups,
        });
    }
}

/// The caustic textures against the map budget and the adapter's largest storage binding
/// (each of the two caustic buffers is bound whole).
fn check_caustic_budget(
    ctx: &Context,
    id: &str,
    settings: &CausticSettings,
    rects: &Rectangles,
) -> TechniqueResult<()> {
    let layers: usize = rects.refractors.iter().map(|r| r.members.len()).sum();
    let texels = u64::from(settings.resolution).pow(2);
    // Counts (3 x u32) and irradiance (vec4f) per texel.
    check_map_budget(id, layers, texels * 28, "caustic_resolution")?;
    let largest = texels * 16 * layers.max(1) as u64;
    let limit = u64::from(ctx.device.limits().max_storage_buffer_binding_size);
    if largest > limit {
        return Err(TechniqueError::OverBudget(format!(
            "{id}: {layers} caustic textures of {r} x {r} texels need a {largest}-byte storage \
             buffer, past this adapter's largest binding ({limit} bytes): lower \
             caustic_resolution",
            r = settings.resolution
        )));
    }
    Ok(())
}

/// `@group(2)` of refract.wgsl.
fn group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "image-space refraction",
        wgpu::ShaderStages::VERTEX_FRAGMENT,
        &[
            bind::texture_cube(),            // env_map
            bind::sampler(),                 // env_sampler
            bind::uniform(),                 // params
            bind::uniform(),                 // eye_params
            bind::texture_2d_unfilterable(), // front_buffer
            bind::texture_2d_unfilterable(), // back_buffer
            bind::texture_2d_unfilterable(), // scene_color
            bind::storage(true),             // normal_thickness
        ],
    )
}

/// The buffer pipelines (front, back) and the refractor's pipeline, from one module whose
/// `outgoing_radiance` is `radiance_wgsl`.
fn pipelines(
    ctx: &Context,
    scene: &GpuScene,
    layouts: &[&wgpu::BindGroupLayout],
    radiance_wgsl: &str,
) -> Pipelines {
    let source = format!(
        "{}\n{SEARCH_WGSL}\n{REFRACT_WGSL}\n{radiance_wgsl}",
        scene::SCENE_WGSL
    );
    let module = gpu::shader_with_prelude(ctx, "image-space refraction", &source);
    let buffers_layout = scene.pipeline_layout_with(ctx, &[]);
    let buffer_pipeline = |entry: &str| {
        scene::scene_pipeline_with(
            ctx,
            entry,
            &buffers_layout,
            &module,
            entry,
            &[gpu::pass::color_target(BUFFER_FORMAT, None)],
            (true, wgpu::CompareFunction::Less),
        )
    };
    let refract_layout = scene.pipeline_layout_with(ctx, layouts);
    let refractor_pipeline = |fragment: &str, targets: &[Option<wgpu::ColorTargetState>]| {
        scene::scene_pipeline_entries(
            ctx,
            fragment,
            &refract_layout,
            &module,
            ("refractor_vs", fragment),
            targets,
            (true, wgpu::CompareFunction::Less),
        )
    };
    let refract = refractor_pipeline(
        "refract_fs",
        &[gpu::pass::color_target(gpu::HDR_FORMAT, None)],
    );
    // Only the nearby module (`layouts` with @group(3)) has photon_fs.
    let photon = (layouts.len() > 1).then(|| {
        refractor_pipeline(
            "photon_fs",
            &[
                gpu::pass::color_target(BUFFER_FORMAT, None),
                gpu::pass::color_target(BUFFER_FORMAT, None),
            ],
        )
    });
    Pipelines {
        front: buffer_pipeline("front_buffer_fs"),
        back: buffer_pipeline("back_buffer_fs"),
        refract,
        photon,
    }
}

/// The pipelines of one shader module.
struct Pipelines {
    front: wgpu::RenderPipeline,
    back: wgpu::RenderPipeline,
    refract: wgpu::RenderPipeline,
    /// The photon pass (with nearby geometry only: photons land on the rectangles).
    photon: Option<wgpu::RenderPipeline>,
}

/// Wyman's `d_N`: per vertex of each specular object, the distance along the inward normal
/// to the object's other side at time 0 (0 without a hit), at the vertex's place in the
/// scene's vertex buffer; 0 for other objects. The precomputation the paper does away with:
/// it is stale once the object deforms.
pub fn normal_thickness(scene: &GpuScene, objects: &[usize]) -> Vec<f32> {
    let total: usize = scene
        .scene
        .objects
        .iter()
        .map(|o| o.mesh.positions.len())
        .sum();
    let mut thickness = vec![0.0; total.max(1)];
    if objects.is_empty() {
        return thickness;
    }
    let bvh = scene::bvh::SceneBvh::build(&scene.scene, 0.0);
    for &object in objects {
        let o = &scene.scene.objects[object];
        let world = o.world_at(0.0);
        let normals = o.normal_matrix_at(0.0);
        let offset = 1e-4 * o.bounding_radius_at(0.0).max(1e-3);
        let base = scene.draws[object].base_vertex as usize;
        // As the BVH places the object at time 0 (a morph's weight there included).
        let (positions, object_normals) = (o.positions_at(0.0), o.normals_at(0.0));
        for (i, (p, n)) in positions.iter().zip(object_normals.iter()).enumerate() {
            let inward = -(normals * *n).normalize_or_zero();
            if inward == Vec3::ZERO {
                continue;
            }
            let origin = world.transform_point3(*p) + inward * offset;
            if let Some(hit) = bvh.closest_hit_where(origin, inward, f32::MAX, |h| h == object) {
                thickness[base + i] = hit.t + offset;
            }
        }
    }
    thickness
}

fn storage_buffer(ctx: &Context, label: &str, data: &[f32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// An eye for the uniform's first contents (overwritten before every frame).
fn placeholder_eye() -> Eye {
    Eye {
        view_proj: Mat4::IDENTITY,
        position: Vec3::ZERO,
        forward: Vec3::NEG_Z,
        width: 1,
        height: 1,
    }
}
