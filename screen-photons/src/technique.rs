//! The screen-photons technique: the passes of a frame and its variants.
//!
//! A frame (every pass recorded into the harness's encoder, in this order):
//!
//! 1. *LDI* ("ldi" span): two layered depth images from the eye by `scene::DepthPeeler`: the
//!    whole scene (photons and retraced rays march over it) and the specular objects alone
//!    (section 4's LDI "of the transmitting object"), each peeled only as deep as the view's
//!    depth complexity, counted first (section 2.2; `count_layers`).
//! 2. The shared raster pass draws the diffuse scene (direct light, shadow maps); the
//!    `shadows` variant instead draws it with screen-space shadow rays ("shadows" span:
//!    `shadow_mask.wgsl`, `shadowed.wgsl`).
//! 3. *Caustics* ("caustics" span, the caustic variants only), per light:
//!    - the transfer map: every object drawn from the light into a `photons` x `photons`
//!      grid fitted to the caustic casters; a pixel on a specular surface is one photon,
//!      refracted or reflected there (`transfer.wgsl`), gathered into a photon buffer;
//!    - `1 + bounces` rounds of a march over the scene's LDI ("march" span: the paper's
//!      lines, `lines.wgsl` and `reduce.wgsl`, or one invocation per photon, `dda.wgsl`: the
//!      DDA or the lines' test) and a resolve (`resolve.wgsl`): a photon
//!      that met a specular surface reflects or refracts and goes on (section 2.3), one that
//!      met a diffuse surface becomes a receiver point.
//! 4. *Splats* ("splat" span): a quad per receiver point adds its flux times a normalised
//!    cone kernel into an irradiance buffer (oriented: section 3.1's tangent-plane ray
//!    caster; sprites: screen-aligned), and the diffuse surfaces are drawn again adding
//!    `albedo / pi * E` (`apply.wgsl`).
//! 5. *Refraction* ("refraction" span): the specular surfaces, shaded by screen-space
//!    refraction tracing (section 4, `specular.wgsl`).
//! 6. *Shafts* ("shafts" span, a scene with a scattering medium only): `god-rays` draws the
//!    march's photon beams as bands into an in-scattering buffer and blurs it (section 3.2,
//!    `shafts.wgsl`); `froxel-fog` lights a froxel grid from shadow maps in which transparent
//!    surfaces cast no shadow (no photons; `froxel-fog-photons` adds a caustic map of where
//!    the photons end), blends it with the last frame's grid reprojected, integrates it and
//!    looks it up per pixel (`froxels.wgsl`).
//!    Then every variant multiplies its image by the medium's transmittance to each pixel's
//!    first surface and adds the in-scattering (`composite.wgsl`); photons lose the medium's
//!    transmittance along every march segment (`resolve.wgsl`).

use glam::{Mat4, Vec3};
use gpu::pass::{self, ADD_RGB_KEEP_ALPHA, CLEAR_BLACK, CLEAR_FAR};
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::emission::{PHOTON_FOOTPRINT_PARAM, PHOTON_JITTER_PARAM, footprint_param, jitter_param};
use scene::{
    CasterShadowMaps, DepthPeeler, Frame, GpuScene, ObjectFilter, Param, RasterTarget, SCENE_WGSL,
    Scene, Technique, TechniqueError, TechniqueResult, View,
};

/// The LDI functions (the twin of [`crate::march`]).
pub const LDI_WGSL: &str = include_str!("shaders/ldi.wgsl");
/// Photon and receiver structs shared by the photon passes.
pub const PHOTON_WGSL: &str = include_str!("shaders/photon.wgsl");
/// The splat kernel and weights (also run by the conformance test).
pub const SPLAT_WGSL: &str = include_str!("shaders/splat.wgsl");
const TRANSFER_WGSL: &str = include_str!("shaders/transfer.wgsl");
const GATHER_WGSL: &str = include_str!("shaders/gather.wgsl");
const LINES_WGSL: &str = include_str!("shaders/lines.wgsl");
const REDUCE_WGSL: &str = include_str!("shaders/reduce.wgsl");
const DDA_WGSL: &str = include_str!("shaders/dda.wgsl");
const RESOLVE_WGSL: &str = include_str!("shaders/resolve.wgsl");
const APPLY_WGSL: &str = include_str!("shaders/apply.wgsl");
const SPECULAR_WGSL: &str = include_str!("shaders/specular.wgsl");
const SHADOW_MASK_WGSL: &str = include_str!("shaders/shadow_mask.wgsl");
const SHADOWED_WGSL: &str = include_str!("shaders/shadowed.wgsl");
/// A photon beam on the image: the twin of [`crate::shafts`]'s `beam_band` and
/// `beam_fragment` (pure functions; run by the conformance test).
pub const BEAM_WGSL: &str = include_str!("shaders/beam.wgsl");
/// God-ray bands and their blur (after [`BEAM_WGSL`]).
const SHAFTS_WGSL: &str = include_str!("shaders/shafts.wgsl");
/// The froxel grid (the twin of [`crate::shafts`]'s slices and integration).
pub const FROXELS_WGSL: &str = include_str!("shaders/froxels.wgsl");
const COMPOSITE_WGSL: &str = include_str!("shaders/composite.wgsl");

/// The LDI bindings of the technique's passes (`@group(2)`), and the material kind ldi.wgsl
/// asks for, from the scene's materials (0 diffuse, 1 metal, 2 glass: `MATERIAL_*`).
pub const LDI_BINDINGS_WGSL: &str = r#"
@group(2) @binding(0) var<uniform> ldi: LdiParams;
@group(2) @binding(1) var ldi_layers: texture_2d_array<f32>;
@group(2) @binding(2) var ldi_surfaces: texture_2d_array<f32>;
@group(2) @binding(3) var refractor_layers: texture_2d_array<f32>;
@group(2) @binding(4) var refractor_surfaces: texture_2d_array<f32>;

fn ldi_kind(object: u32) -> u32 {
    return u32(objects[object].material.x);
}
"#;

/// Photon buffers, line rows and transfer maps: 32-bit float (the irradiance buffer adds
/// many photons per pixel).
const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// How photon rays find their first surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum March {
    /// The paper's: lines rasterized into rows, the tolerance test, the first hit per row.
    Lines,
    /// One compute invocation per photon marching pixel by pixel with a thickness per layer.
    Dda,
    /// The paper's single-shader alternative (section 2.1: "photon tracing can also be
    /// implemented as a single pixel shader being executed for each photon"): one compute
    /// invocation per photon walking the same samples with the lines' tolerance test and
    /// keeping the same sample, stopping there.
    Shader,
}

/// How receiver points spread their flux.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Splat {
    /// Section 3.1: ray casting the receiver's tangent plane per covered pixel.
    Oriented,
    /// Screen-aligned point sprites (the naive variant of the paper's figure 6).
    Sprite,
}

/// How the view rays through specular surfaces are traced (section 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refraction {
    /// The paper's monotone layers inside refractors and the tolerance test outside.
    Monotone,
    /// The DDA with thickness, over every layer.
    Dda,
}

/// How light shafts in a scattering medium are made (section 3.2 and the engine's way).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shafts {
    /// The paper's: photon beams drawn as lines (bands), blurred, blended.
    GodRays,
    /// The engine baseline: froxel volumetric fog lit by shadow maps in which transparent
    /// surfaces cast no shadow, sampled with temporal jitter and reprojected history
    /// (Wronski 2014, Hillaire 2015). No photon reaches it.
    Froxels,
    /// A hybrid of ours, not an engine's: the froxels lit by the scene's shadow maps and by a
    /// caustic map of where this technique's photons end.
    FroxelsWithPhotons,
}

impl Shafts {
    /// Whether the froxel grid draws the shafts.
    pub fn froxels(self) -> bool {
        matches!(self, Shafts::Froxels | Shafts::FroxelsWithPhotons)
    }

    /// Whether the shafts are drawn from the photons' beams (the march keeps them).
    pub fn from_photons(self) -> bool {
        matches!(self, Shafts::GodRays | Shafts::FroxelsWithPhotons)
    }
}

/// The parameters of a variant (all declared, all sweepable).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Side of the photon grid: `photons`^2 photons per light.
    pub photons: u32,
    /// LDI layers peeled (the paper: "usually sufficient to only consider up to eight").
    pub layers: u32,
    /// Count the view's depth complexity first and peel only that many layers (section 2.2:
    /// a count pass and a reduce-max; `scene::layer_count`). Where the adapter cannot draw
    /// the layers indirectly (no `INDIRECT_FIRST_INSTANCE`) every layer is peeled, which gives
    /// the same LDI.
    pub count_layers: bool,
    /// The paper's world-space tolerance of the line test (m).
    pub tolerance: f32,
    /// The DDA's thickness of every surface (m).
    pub thickness: f32,
    /// Splat radius in photon spacings at the casters (the grid's pixel at their distance).
    pub splat_radius: f32,
    /// Specular events a photon may have after the transfer map (section 2.3).
    pub bounces: u32,
    /// Rows of the line buffer: photons per batch of the line marcher.
    pub rows: u32,
    /// Standard deviation of the god rays' Gaussian blur, as a fraction of the image height.
    pub shaft_blur: f32,
    /// Side of a froxel tile in pixels.
    pub froxel_size: u32,
    /// Depth slices of the froxel grid.
    pub slices: u32,
    /// Side of the hybrid froxels' caustic map (texels).
    pub caustic_map: u32,
    /// Froxels: weight of this frame's jittered sample against the reprojected history
    /// (Hillaire's exponential moving average); 1 keeps no history and does not jitter.
    pub temporal_blend: f32,
    /// Each photon leaves from a random point of its transfer-map pixel instead of the pixel
    /// centre (stratified jittered emission, `jittered_emission` in scene.wgsl).
    pub jitter: bool,
    /// Oriented splats: each photon's cone stretched over the footprint of its lattice cell on
    /// the receiver (`footprint_matrix` in splat_weight.wgsl).
    pub footprint: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            photons: 256,
            layers: 8,
            count_layers: true,
            tolerance: 0.03,
            thickness: 0.1,
            splat_radius: 3.0,
            bounces: 2,
            rows: 4096,
            shaft_blur: 0.01,
            froxel_size: 8,
            slices: 64,
            caustic_map: 128,
            temporal_blend: 0.1,
            jitter: false,
            footprint: true,
        }
    }
}

impl Settings {
    fn params(&self) -> Vec<Param> {
        vec![
            Param::new(
                "photons",
                self.photons as f64,
                (8.0, 1024.0),
                true,
                "side of the photon grid (photons x photons per light; the paper: 128 x 64 to \
                 1024 x 1024)",
            ),
            Param::new(
                "layers",
                self.layers as f64,
                (1.0, 16.0),
                true,
                "LDI layers peeled from the eye (depth complexity cap)",
            ),
            Param::new(
                "count_layers",
                self.count_layers as u32 as f64,
                (0.0, 1.0),
                true,
                "1: count the depth complexity and peel only that many layers (section 2.2); \
                 0: peel every layer",
            ),
            Param::new(
                "tolerance",
                self.tolerance as f64,
                (1e-4, 1.0),
                false,
                "world-space tolerance of the line test (m)",
            ),
            Param::new(
                "thickness",
                self.thickness as f64,
                (1e-4, 2.0),
                false,
                "thickness of every LDI surface for the DDA test (m)",
            ),
            Param::new(
                "splat_radius",
                self.splat_radius as f64,
                (0.25, 32.0),
                false,
                "splat radius in photon spacings at the casters",
            ),
            Param::new(
                "bounces",
                self.bounces as f64,
                (0.0, 6.0),
                true,
                "specular events a photon may have after the transfer map",
            ),
            Param::new(
                "rows",
                self.rows as f64,
                (64.0, 8192.0),
                true,
                "rows of the line buffer (photons per line batch)",
            ),
            Param::new(
                "shaft_blur",
                self.shaft_blur as f64,
                (0.0, 0.1),
                false,
                "god rays: standard deviation of the blur, a fraction of the image height",
            ),
            Param::new(
                "froxel_size",
                self.froxel_size as f64,
                (1.0, 64.0),
                true,
                "froxel fog: side of a froxel tile (pixels)",
            ),
            Param::new(
                "slices",
                self.slices as f64,
                (1.0, 256.0),
                true,
                "froxel fog: exponential depth slices",
            ),
            Param::new(
                "caustic_map",
                self.caustic_map as f64,
                (8.0, 2048.0),
                true,
                "froxel-fog-photons: side of the caustic map (texels)",
            ),
            Param::new(
                "temporal_blend",
                self.temporal_blend as f64,
                (0.01, 1.0),
                false,
                "froxel fog: weight of the frame's jittered sample against the reprojected \
                 history (1: no history, no jitter)",
            ),
            footprint_param(self.footprint),
            jitter_param(self.jitter),
        ]
    }

    fn set(&mut self, name: &str, value: f64) {
        match name {
            "photons" => self.photons = value as u32,
            "layers" => self.layers = value as u32,
            "count_layers" => self.count_layers = value != 0.0,
            "tolerance" => self.tolerance = value as f32,
            "thickness" => self.thickness = value as f32,
            "splat_radius" => self.splat_radius = value as f32,
            "bounces" => self.bounces = value as u32,
            "rows" => self.rows = value as u32,
            "shaft_blur" => self.shaft_blur = value as f32,
            "froxel_size" => self.froxel_size = value as u32,
            "slices" => self.slices = value as u32,
            "caustic_map" => self.caustic_map = value as u32,
            "temporal_blend" => self.temporal_blend = value as f32,
            PHOTON_JITTER_PARAM => self.jitter = value != 0.0,
            PHOTON_FOOTPRINT_PARAM => self.footprint = value != 0.0,
            _ => unreachable!("checked against params()"),
        }
    }
}

/// A variant: caustics (marcher and splats) or none, the refraction tracing, and the
/// shadows (the shared pass's shadow maps, or screen-space shadow rays).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variant {
    pub name: &'static str,
    pub caustics: Option<(March, Splat)>,
    pub refraction: Refraction,
    pub screen_space_shadows: bool,
    /// Light shafts (only in a scene with a scattering medium).
    pub shafts: Option<Shafts>,
}

/// The variants: `lines`, `dda`, `sprites`, `shader` (caustics; the specular surfaces traced by
/// the DDA), `refraction` and `refraction-dda` (refraction tracing alone), `shadows` (screen-space
/// shadow rays instead of shadow maps, no caustics), `god-rays` and `froxel-fog` (the `dda`
/// caustics plus light shafts, the paper's and the engines'), `froxel-fog-photons` (the
/// froxels fed the photons too: a hybrid of ours, not representative).
pub fn variants() -> Vec<Variant> {
    use March::*;
    // The caustic variants trace the specular surfaces with the DDA: the paper's tolerance
    // test misses grazing surfaces (README, "Failure cases"), and its misses would bury the
    // caustics' error under the surface's; `refraction` measures the paper's tracing alone.
    let caustics = |name, march, splat| Variant {
        name,
        caustics: Some((march, splat)),
        refraction: Refraction::Dda,
        screen_space_shadows: false,
        shafts: None,
    };
    let shafts = |name, shafts| Variant {
        shafts: Some(shafts),
        ..caustics(name, Dda, Splat::Oriented)
    };
    vec![
        caustics("lines", Lines, Splat::Oriented),
        caustics("dda", Dda, Splat::Oriented),
        caustics("sprites", Lines, Splat::Sprite),
        caustics("shader", Shader, Splat::Oriented),
        Variant {
            name: "refraction",
            caustics: None,
            refraction: Refraction::Monotone,
            screen_space_shadows: false,
            shafts: None,
        },
        Variant {
            name: "refraction-dda",
            caustics: None,
            refraction: Refraction::Dda,
            screen_space_shadows: false,
            shafts: None,
        },
        Variant {
            name: "shadows",
            caustics: None,
            refraction: Refraction::Dda,
            screen_space_shadows: true,
            shafts: None,
        },
        shafts("god-rays", Shafts::GodRays),
        shafts("froxel-fog", Shafts::Froxels),
        shafts("froxel-fog-photons", Shafts::FroxelsWithPhotons),
    ]
}

/// One variant of screen-space photon tracing.
pub struct ScreenPhotons {
    variant: Variant,
    settings: Settings,
    passes: Option<Passes>,
    sized: Option<Sized>,
}

impl ScreenPhotons {
    pub fn new(variant: Variant) -> Self {
        Self {
            variant,
            settings: Settings::default(),
            passes: None,
            sized: None,
        }
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    fn last_frame(&self) -> TechniqueResult<&Sized> {
        self.sized
            .as_ref()
            .ok_or_else(|| scene::technique::not_prepared(self))
    }

    /// Diagnostics of the last frame rendered: the hit buffer of the last march, one
    /// `[t, layer, x, y]` per photon of the transfer map (`t = 0`: no hit). With `bounces = 0`
    /// these are the first hits of the photons leaving the transfer map.
    pub fn last_hits(&self, ctx: &Context) -> TechniqueResult<Vec<[f32; 4]>> {
        let bytes = gpu::read_buffer(ctx, &self.last_frame()?.photons.hits)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Diagnostics of the last frame rendered (`shadows`): the screen-space visibility of the
    /// first four lights per pixel, row 0 at the top (1 where the pixel's layer 0 is not a
    /// diffuse surface).
    pub fn last_shadow_mask(&self, ctx: &Context) -> TechniqueResult<Vec<[f32; 4]>> {
        let Some(mask) = &self.last_frame()?.shadow_mask else {
            return Err(TechniqueError::Unsupported(format!(
                "{} has no screen-space shadow mask (only screen-photons/shadows)",
                self.id()
            )));
        };
        let bytes = gpu::read_buffer(ctx, mask)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Diagnostics of the last frame rendered: layer `layer` of the scene's LDI, `[nx, ny, nz,
    /// distance]` per pixel (see `scene::DepthPeeler::read_layer`).
    pub fn last_ldi_layer(&self, ctx: &Context, layer: u32) -> TechniqueResult<Vec<[f32; 4]>> {
        Ok(self.last_frame()?.scene_ldi.read_layer(ctx, layer)?)
    }

    /// Diagnostics of the last frame rendered: layer `layer` of the scene's LDI, `[object, u,
    /// v, 1]` per pixel (see `scene::DepthPeeler::read_surface`).
    pub fn last_ldi_surface(&self, ctx: &Context, layer: u32) -> TechniqueResult<Vec<[f32; 4]>> {
        Ok(self.last_frame()?.scene_ldi.read_surface(ctx, layer)?)
    }

    /// Diagnostics of the last frame rendered: the LDI uniform its marches read (the eye, the
    /// sizes, the tests, the scene's box).
    pub fn last_ldi_params(&self) -> TechniqueResult<LdiParamsGpu> {
        self.last_frame()?
            .ldi_params
            .get()
            .ok_or_else(|| scene::technique::not_prepared(self))
    }

    /// Diagnostics of the last frame rendered: the photon buffer, `[origin + travelling,
    /// direction + inside, power + specular events]` per photon (photon.wgsl's `Photon`). With
    /// `bounces = 0` the origins, directions and powers are the transfer map's.
    pub fn last_photons(&self, ctx: &Context) -> TechniqueResult<Vec<[[f32; 4]; 3]>> {
        let bytes = gpu::read_buffer(ctx, &self.last_frame()?.photons.photons)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

impl Technique for ScreenPhotons {
    fn id(&self) -> String {
        format!("screen-photons/{}", self.variant.name)
    }

    /// `shader` makes the same image as `lines` (the conformance test holds them to the same
    /// hits): it is there for the speed comparison of the two, not for the default table.
    fn representative(&self) -> bool {
        !matches!(self.variant.caustics, Some((March::Shader, _)))
            && self.variant.shafts != Some(Shafts::FroxelsWithPhotons)
    }

    fn description(&self) -> String {
        let refraction = match self.variant.refraction {
            Refraction::Monotone => "refraction traced through monotone LDI layers",
            Refraction::Dda => "refraction traced by the DDA over every LDI layer",
        };
        if self.variant.screen_space_shadows {
            return format!(
                "screen-space shadow rays over the eye's LDI (the paper's figures 11-12) instead \
                 of shadow maps; {refraction}"
            );
        }
        match self.variant.shafts {
            Some(Shafts::GodRays) => {
                return format!(
                    "light shafts as the paper draws them: the DDA's photon beams drawn as lines \
                     with exponential attenuation, blurred and blended (section 3.2); caustics \
                     as `dda`; {refraction}"
                );
            }
            Some(Shafts::Froxels) => {
                return format!(
                    "engine baseline: froxel volumetric fog lit by shadow maps in which \
                     transparent surfaces cast no shadow, jittered and reprojected frame to \
                     frame, integrated front to back (Wronski 2014, Hillaire 2015), no photons \
                     in the fog; caustics on surfaces as `dda`; {refraction}"
                );
            }
            Some(Shafts::FroxelsWithPhotons) => {
                return format!(
                    "hybrid (ours): the froxel fog lit by the scene's shadow maps and a caustic \
                     map of where the DDA's photons end; caustics as `dda`; {refraction}"
                );
            }
            None => {}
        }
        match self.variant.caustics {
            Some((march, splat)) => format!(
                "screen-space photon tracing: photons marched over the eye's LDI by {}, {} \
                 splats; {refraction}",
                match march {
                    March::Lines => "rasterized lines (the paper)",
                    March::Dda => "a compute DDA (engine-style marcher)",
                    March::Shader => {
                        "one compute invocation per photon with the lines' tolerance test (the \
                         paper's single-shader alternative)"
                    }
                },
                match splat {
                    Splat::Oriented => "oriented",
                    Splat::Sprite => "screen-aligned sprite",
                }
            ),
            None => format!("screen-space {refraction}; no caustics"),
        }
    }

    fn params(&self) -> Vec<Param> {
        self.settings.params()
    }

    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        scene::technique::check_param(&self.id(), &self.params(), name, value)?;
        self.settings.set(name, value);
        // Sizes and batch counts follow the settings: rebuilt at the next frame.
        self.sized = None;
        Ok(())
    }

    fn required_features(&self) -> wgpu::Features {
        wgpu::Features::FLOAT32_BLENDABLE
    }

    /// A scene with a specular object, every light outside the caustic casters' bounding
    /// sphere (at time 0; [`light_outside_casters`]).
    fn supports(&self, scene: &Scene) -> bool {
        (self.variant.shafts.is_none() || scene.medium.is_some())
            && !scene.specular_objects().is_empty()
            && scene
                .lights
                .iter()
                .all(|l| light_outside_casters(scene, l, 0.0).is_ok())
    }

    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        if !self.supports(&scene.scene) {
            let needs = if self.variant.shafts.is_some() {
                "a scattering medium (murky-pool) and a specular object"
            } else {
                "a specular object (a refractor or a mirror)"
            };
            return Err(TechniqueError::Unsupported(format!(
                "{} needs {needs} in the scene",
                self.id()
            )));
        }
        let ctx = frame.gpu;
        ctx.require(wgpu::Features::FLOAT32_BLENDABLE)?;
        self.passes = Some(ctx.validated(|| Passes::new(ctx, scene, &self.variant))?);
        self.sized = None;
        Ok(())
    }

    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let Some(passes) = &self.passes else {
            return Err(scene::technique::not_prepared(self));
        };
        let ctx = frame.gpu;
        let key = (view.width, view.height);
        if self.sized.as_ref().is_none_or(|s| s.key != key) {
            self.sized = Some(Sized::new(ctx, scene, &self.settings, key, &self.variant)?);
        }
        let sized = self.sized.as_ref().expect("made above");
        passes.frame(
            frame,
            scene,
            view,
            target,
            sized,
            &self.settings,
            &self.variant,
        )
    }
}

/// Size-dependent resources: the LDIs, the irradiance buffer, the photon buffers.
struct Sized {
    key: (u32, u32),
    scene_ldi: DepthPeeler,
    refractor_ldi: DepthPeeler,
    irradiance: wgpu::TextureView,
    photons: PhotonBuffers,
    /// The line buffer: `max_steps` wide, `rows` high.
    line_rows: wgpu::TextureView,
    line_width: u32,
    line_rows_count: u32,
    /// Transfer map targets: origin, direction (transfer.wgsl says what they hold), depth.
    transfer: [wgpu::TextureView; 3],
    /// Screen-space visibility of the first four lights per pixel (the `shadows` variant
    /// only).
    shadow_mask: Option<wgpu::Buffer>,
    /// The LDI uniform of the last frame (diagnostics).
    ldi_params: std::cell::Cell<Option<LdiParamsGpu>>,
    /// The medium's resources (a scene with a scattering medium only).
    media: Option<MediaTargets>,
    /// The resolve's beam binding when no beams are kept (one unused beam).
    no_beams: wgpu::Buffer,
}

/// What a frame in a scattering medium uses: the in-scattering buffer every variant blends
/// (cleared to nothing for the variants without shafts), and the shafts' own.
struct MediaTargets {
    /// In-scattered radiance per pixel (god rays: the bands, then blurred; froxels: the
    /// lookup).
    inscatter: wgpu::TextureView,
    /// The blur's intermediate (god rays).
    blurred: wgpu::TextureView,
    /// `photons * rounds` beams (god rays, the hybrid froxels), or one unused beam.
    beams: wgpu::Buffer,
    /// Froxels: the in-scattering grid of even frames, its integral, the grid of odd frames
    /// (each frame's history is the other's grid), and the hybrid's caustic map (flux,
    /// direction); 1-texel stand-ins for the other variants.
    froxels: [wgpu::TextureView; 3],
    froxel_grid: [u32; 3],
    caustic_maps: [wgpu::TextureView; 2],
    /// Froxels: frames drawn so far (the jitter sequence and the grids' parity) and the last
    /// frame's view, which its grid is reprojected from (`None` before the first frame).
    froxel_history: std::cell::Cell<(u32, Option<FroxelView>)>,
}

/// The view a froxel grid was drawn from: what reprojecting it needs.
#[derive(Clone, Copy, Debug)]
struct FroxelView {
    view_proj: Mat4,
    eye: glam::Vec3,
    /// The slices' near and far distances.
    near: f32,
    far: f32,
}

/// A froxel frame's temporal terms: where in its froxel each sample is taken, how much of it
/// enters the running mean, and the view the history was drawn from.
#[derive(Clone, Copy, Debug)]
struct FroxelTemporal {
    /// Position of the sample in its froxel: across, down, in depth (0.5: the centre).
    jitter: glam::Vec3,
    /// Weight of this frame's sample (1: the history is not read).
    blend: f32,
    previous: Option<FroxelView>,
}

impl FroxelTemporal {
    /// The centre, no history (a pass that does not light the grid).
    const NONE: Self = Self {
        jitter: glam::Vec3::splat(0.5),
        blend: 1.0,
        previous: None,
    };

    /// Frame `index`'s terms (frames counted from the first of this grid): with a history
    /// (`blend` < 1), the sample moves through its froxel along the Halton (3, 5, 2)
    /// sequence, Wronski's and Hillaire's jitter, and the grid is the running mean of what
    /// each froxel saw, which tends to its average over the froxel: the plain mean of the
    /// frames so far while they are fewer than `1 / blend`, an exponential moving average of
    /// weight `blend` after (a young history is not weighted as a full one); without, the
    /// centre every frame.
    fn of_frame(index: u32, previous: Option<FroxelView>, blend: f32) -> Self {
        if blend >= 1.0 {
            return Self::NONE;
        }
        // Index 0 of the sequence is 0: start at 1 so that no frame samples a corner.
        let i = index + 1;
        Self {
            jitter: glam::Vec3::new(halton(i, 3), halton(i, 5), halton(i, 2)),
            blend: blend.max(1.0 / i as f32),
            previous,
        }
    }
}

/// Element `index` of the Halton sequence of `base` (the radical inverse), in [0, 1).
fn halton(mut index: u32, base: u32) -> f32 {
    let (mut result, mut fraction) = (0.0, 1.0 / base as f32);
    while index > 0 {
        result += (index % base) as f32 * fraction;
        index /= base;
        fraction /= base as f32;
    }
    result
}

struct PhotonBuffers {
    count: u32,
    photons: wgpu::Buffer,
    hits: wgpu::Buffer,
    receivers: wgpu::Buffer,
}

/// GPU memory one frame's resources may take together (the LDIs dominate: 36 bytes per pixel
/// and layer, twice).
pub const FRAME_BUDGET_BYTES: u64 = scene::technique::MAP_BUDGET_BYTES;

/// At most this many line batches per march: `rows` is raised to fit (each batch is a render
/// pass and a compute pass).
pub const MAX_LINE_BATCHES: u32 = 256;

impl Sized {
    /// The bytes of a frame's resources at `width` x `height` (`medium`: the scene has a
    /// scattering medium).
    pub fn bytes(
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
        medium: bool,
    ) -> u64 {
        let pixels = width as u64 * height as u64;
        let photons = settings.photons as u64 * settings.photons as u64;
        let ldis = 2 * pixels * settings.layers as u64 * (2 * 16 + 4);
        let per_photon = 48 + 16 + 48 + 2 * 16 + 4;
        let rows = Self::line_rows(settings) as u64 * width.max(height) as u64 * 16;
        let shadows = variant.screen_space_shadows as u64;
        let mut bytes = ldis + pixels * 16 * (1 + shadows) + photons * per_photon + rows;
        if medium {
            bytes += 2 * pixels * 16;
            if variant.shafts.is_some_and(Shafts::from_photons) {
                bytes += photons * (settings.bounces as u64 + 1) * 48;
            }
            if variant.shafts.is_some_and(Shafts::froxels) {
                let [x, y, z] = froxel_grid(settings, (width, height));
                bytes += 3 * (x * y * z) as u64 * 16;
            }
            if variant.shafts == Some(Shafts::FroxelsWithPhotons) {
                bytes += 2 * (settings.caustic_map as u64).pow(2) * 16;
            }
        }
        bytes
    }

    /// Rows of the line buffer: `rows`, raised so that a march takes at most
    /// [`MAX_LINE_BATCHES`] batches, and no more than the photons.
    fn line_rows(settings: &Settings) -> u32 {
        let count = settings.photons * settings.photons;
        settings
            .rows
            .max(count.div_ceil(MAX_LINE_BATCHES))
            .min(count)
    }

    fn new(
        ctx: &Context,
        scene: &GpuScene,
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
    ) -> TechniqueResult<Self> {
        let shadows = variant.screen_space_shadows;
        let medium = scene.scene.medium.is_some();
        let bytes = Self::bytes(settings, (width, height), variant, medium);
        if bytes > FRAME_BUDGET_BYTES {
            return Err(TechniqueError::OverBudget(format!(
                "screen-photons at {width}x{height} with {} layers and {}^2 photons needs {:.2} GB \
                 of GPU memory, over its {} MB budget: lower the size, `layers` or `photons`",
                settings.layers,
                settings.photons,
                bytes as f64 / 1e9,
                FRAME_BUDGET_BYTES >> 20
            )));
        }
        let max_binding = ctx.device.limits().max_storage_buffer_binding_size as u64;
        let mask_bytes = width as u64 * height as u64 * 16;
        if shadows && mask_bytes > max_binding {
            return Err(TechniqueError::Unsupported(format!(
                "the shadow mask of {width}x{height} pixels ({} MB) is larger than the adapter's \
                 largest storage binding ({} MB): lower the size",
                mask_bytes >> 20,
                max_binding >> 20
            )));
        }
        let mut scene_ldi = DepthPeeler::new(ctx, scene, width, height, settings.layers)?;
        let mut refractor_ldi = DepthPeeler::new(ctx, scene, width, height, settings.layers)?;
        // Without indirect first instances the peelers peel every layer: the same LDI. Any
        // other failure to make the counters is an error.
        if settings.count_layers && scene::layer_count::LayerCounter::available(ctx) {
            scene_ldi.count_layers(ctx, scene)?;
            refractor_ldi.count_layers(ctx, scene)?;
        }
        let grid = settings.photons;
        ctx.check_size(grid, grid)?;
        let count = grid * grid;
        let storage = |label: &str, bytes: u64| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let photons = ctx.allocating("screen-photons buffers", || PhotonBuffers {
            count,
            photons: storage("photons", count as u64 * 48),
            hits: storage("photon hits", count as u64 * 16),
            receivers: storage("receivers", count as u64 * 48),
        })?;
        let line_width = width.max(height);
        let line_rows_count = Self::line_rows(settings);
        ctx.check_size(line_width, line_rows_count)?;
        let texture = |label: &str, w: u32, h: u32, format| {
            gpu::render_texture(ctx, label, (w, h, 1), format, wgpu::TextureUsages::empty())
                .create_view(&Default::default())
        };
        let beam_bytes = count as u64 * (settings.bounces as u64 + 1) * 48;
        if medium && variant.shafts.is_some_and(Shafts::from_photons) && beam_bytes > max_binding {
            return Err(TechniqueError::OverBudget(format!(
                "the photon beams of {}^2 photons and {} bounces ({} MB) are larger than the \
                 adapter's largest storage binding ({} MB): lower `photons` or `bounces`",
                settings.photons,
                settings.bounces,
                beam_bytes >> 20,
                max_binding >> 20
            )));
        }
        let media = if medium {
            Some(ctx.allocating("screen-photons medium targets", || {
                MediaTargets::new(ctx, settings, (width, height), variant, count)
            })?)
        } else {
            None
        };
        Ok(Self {
            media,
            no_beams: storage("no beams", 48),
            key: (width, height),
            scene_ldi,
            refractor_ldi,
            irradiance: texture("caustic irradiance", width, height, MAP_FORMAT),
            photons,
            line_rows: texture("line rows", line_width, line_rows_count, MAP_FORMAT),
            line_width,
            line_rows_count,
            ldi_params: std::cell::Cell::new(None),
            shadow_mask: shadows.then(|| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("shadow mask"),
                    size: mask_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            }),
            transfer: [
                texture("transfer origin", grid, grid, MAP_FORMAT),
                texture("transfer direction", grid, grid, MAP_FORMAT),
                gpu::depth_texture(ctx, grid, grid, 1, "transfer depth")
                    .create_view(&Default::default()),
            ],
        })
    }
}

/// The froxel grid at `width` x `height`: tiles across, tiles down, slices.
fn froxel_grid(settings: &Settings, (width, height): (u32, u32)) -> [u32; 3] {
    let size = settings.froxel_size.max(1);
    [
        width.div_ceil(size),
        height.div_ceil(size),
        settings.slices.max(1),
    ]
}

impl MediaTargets {
    fn new(
        ctx: &Context,
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
        photons: u32,
    ) -> Self {
        let texture = |label: &str, (w, h): (u32, u32)| {
            gpu::render_texture(
                ctx,
                label,
                (w, h, 1),
                MAP_FORMAT,
                wgpu::TextureUsages::empty(),
            )
            .create_view(&Default::default())
        };
        let beams = if variant.shafts.is_some_and(Shafts::from_photons) {
            photons as u64 * (settings.bounces as u64 + 1)
        } else {
            1
        };
        let froxels = variant.shafts.is_some_and(Shafts::froxels);
        let grid = if froxels {
            froxel_grid(settings, (width, height))
        } else {
            [1, 1, 1]
        };
        let volume = |label: &str| {
            ctx.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: grid[0],
                        height: grid[1],
                        depth_or_array_layers: grid[2],
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D3,
                    format: MAP_FORMAT,
                    usage: wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let map = if variant.shafts == Some(Shafts::FroxelsWithPhotons) {
            settings.caustic_map
        } else {
            1
        };
        Self {
            inscatter: texture("in-scattering", (width, height)),
            blurred: texture("in-scattering blur", (width, height)),
            beams: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("photon beams"),
                size: beams * 48,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            froxels: [
                volume("froxel scattering (even frames)"),
                volume("froxel integral"),
                volume("froxel scattering (odd frames)"),
            ],
            froxel_grid: grid,
            froxel_history: Default::default(),
            caustic_maps: [
                texture("caustic map flux", (map, map)),
                texture("caustic map direction", (map, map)),
            ],
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Uniform blocks (each mirrors the WGSL struct of the same name).
// ---------------------------------------------------------------------------------------------

/// `LdiParams` of ldi.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LdiParamsGpu {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// Width, height, layers, the longest line in samples.
    pub size: [u32; 4],
    /// Tolerance, thickness, t_skip, unused.
    pub tests: [f32; 4],
    pub bounds_min: [f32; 4],
    pub bounds_max: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TransferParamsGpu {
    light: [f32; 4],
    intensity: [f32; 4],
    axis: [f32; 4],
    jitter: u32,
    _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BatchGpu {
    first: u32,
    rows: u32,
    width: u32,
    _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ModeGpu {
    value: u32,
    _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ResolveParamsGpu {
    max_bounces: u32,
    round: u32,
    keep_beams: u32,
    _pad: u32,
}

/// `ShaftView` of shafts.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ShaftViewGpu {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    forward: [f32; 4],
    size: [u32; 4],
}

/// `FroxelParams` of froxels.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FroxelParamsGpu {
    light_view_proj: [[f32; 4]; 4],
    light: [f32; 4],
    axis: [f32; 4],
    grid: [u32; 4],
    slices: [f32; 4],
    prev_view_proj: [[f32; 4]; 4],
    prev_eye: [f32; 4],
    prev_slices: [f32; 4],
    temporal: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SplatParamsGpu {
    inv_view_proj: [[f32; 4]; 4],
    forward: [f32; 4],
    size: [f32; 4],
    mode: u32,
    lattice: u32,
    _pad: [u32; 2],
}

/// The shader of one pass: the prelude, scene.wgsl, the LDI bindings and functions, the
/// photon structs, then the pass's own file.
pub fn pass_source(own: &str) -> String {
    format!("{SCENE_WGSL}\n{LDI_BINDINGS_WGSL}\n{LDI_WGSL}\n{PHOTON_WGSL}\n{own}")
}

fn compute_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    let module = gpu::shader_with_prelude(ctx, label, &pass_source(own));
    gpu::compute::pipeline_with_layout(ctx, label, layout, &module, entry)
}

/// A pipeline whose vertex stage makes its own geometry (no vertex buffers, no depth).
fn bufferless_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    (vs, fs): (&str, &str),
    topology: wgpu::PrimitiveTopology,
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    render_pipeline(
        ctx,
        label,
        layout,
        own,
        (vs, fs),
        topology,
        &[pass::color_target(MAP_FORMAT, blend)],
    )
}

/// [`bufferless_pipeline`] with the caller's targets.
fn render_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    own: &str,
    (vs, fs): (&str, &str),
    topology: wgpu::PrimitiveTopology,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let module = gpu::shader_with_prelude(ctx, label, &pass_source(own));
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets,
            }),
            primitive: wgpu::PrimitiveState {
                topology,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// Additive blending of every channel (irradiance accumulation).
const ADD: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The constants beam.wgsl expects from its includer.
pub fn beam_constants() -> String {
    format!(
        "const CAMERA_NEAR: f32 = {:?};\nconst EYE_CLEARANCE: f32 = {:?};",
        scene::Camera::NEAR,
        scene::medium::EYE_CLEARANCE
    )
}

/// The target times the source, alpha kept: the image times the medium's transmittance.
const MULTIPLY_RGB_KEEP_ALPHA: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::Src,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The passes of a scene with a scattering medium: god rays, froxels, the composite.
struct MediumPasses {
    shafts_layout: wgpu::BindGroupLayout,
    composite_layout: wgpu::BindGroupLayout,
    froxel_layout: wgpu::BindGroupLayout,
    bands: wgpu::RenderPipeline,
    blur: wgpu::RenderPipeline,
    attenuate: wgpu::RenderPipeline,
    add_inscatter: wgpu::RenderPipeline,
    caustic_map: wgpu::RenderPipeline,
    froxel_scatter: wgpu::ComputePipeline,
    froxel_integrate: wgpu::ComputePipeline,
    froxel_lookup: wgpu::RenderPipeline,
    /// The engine froxels' light visibility: shadow maps in which transparent surfaces (glass,
    /// water) cast no shadow, as engines draw them (`froxel-fog` only).
    engine_shadows: Option<CasterShadowMaps>,
}

impl MediumPasses {
    fn new(
        ctx: &Context,
        scene: &GpuScene,
        ldi_layout: &wgpu::BindGroupLayout,
        variant: &Variant,
    ) -> Self {
        use wgpu::ShaderStages as S;
        let map = bind::texture_2d_unfilterable();
        let shafts_layout = bind::layout(
            ctx,
            "shafts",
            S::VERTEX_FRAGMENT,
            &[bind::storage(true), bind::uniform(), map],
        );
        let composite_layout = bind::layout(ctx, "medium composite", S::FRAGMENT, &[map]);
        let all = S::VERTEX_FRAGMENT | S::COMPUTE;
        let froxel_layout = bind::layout_with_stages(
            ctx,
            "froxels",
            &[
                (all, bind::uniform()),
                (all, bind::storage(true)),
                (all, map),
                (all, map),
                (all, bind::texture(wgpu::TextureViewDimension::D3, false)),
                (
                    S::COMPUTE | S::FRAGMENT,
                    wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: MAP_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D3,
                    },
                ),
                (all, bind::texture(wgpu::TextureViewDimension::D3, false)),
                (
                    all,
                    bind::texture(wgpu::TextureViewDimension::CubeArray, false),
                ),
                (
                    all,
                    bind::texture(wgpu::TextureViewDimension::D2Array, false),
                ),
            ],
        );
        let transparent: Vec<usize> = (scene.scene.objects.iter().enumerate())
            .filter(|(_, o)| matches!(o.material, scene::Material::Glass { .. }))
            .map(|(i, _)| i)
            .collect();
        let engine_shadows = (variant.shafts == Some(Shafts::Froxels))
            .then(|| CasterShadowMaps::new(ctx, scene, ObjectFilter::Except(transparent)));
        let with =
            |own: &wgpu::BindGroupLayout| scene.pipeline_layout_with(ctx, &[ldi_layout, own]);
        let fullscreen = gpu::fullscreen::FULLSCREEN_VS_WGSL;
        let shafts = format!(
            "{fullscreen}\n{}\n{BEAM_WGSL}\n{SHAFTS_WGSL}",
            beam_constants()
        );
        let composite = format!("{fullscreen}\n{COMPOSITE_WGSL}");
        let froxels = format!("{fullscreen}\n{FROXELS_WGSL}");
        let hdr = |blend| [pass::color_target(gpu::HDR_FORMAT, Some(blend))];
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        Self {
            bands: bufferless_pipeline(
                ctx,
                "god-ray bands",
                &with(&shafts_layout),
                &shafts,
                ("band_vs", "band_fs"),
                triangles,
                Some(ADD),
            ),
            blur: bufferless_pipeline(
                ctx,
                "god-ray blur",
                &with(&shafts_layout),
                &shafts,
                ("fullscreen_vs", "blur_fs"),
                triangles,
                None,
            ),
            attenuate: render_pipeline(
                ctx,
                "medium transmittance",
                &with(&composite_layout),
                &composite,
                ("fullscreen_vs", "attenuate_fs"),
                triangles,
                &hdr(MULTIPLY_RGB_KEEP_ALPHA),
            ),
            add_inscatter: render_pipeline(
                ctx,
                "medium in-scattering",
                &with(&composite_layout),
                &composite,
                ("fullscreen_vs", "inscatter_fs"),
                triangles,
                &hdr(ADD_RGB_KEEP_ALPHA),
            ),
            caustic_map: render_pipeline(
                ctx,
                "froxel caustic map",
                &with(&froxel_layout),
                &froxels,
                ("caustic_map_vs", "caustic_map_fs"),
                wgpu::PrimitiveTopology::PointList,
                &[
                    pass::color_target(MAP_FORMAT, Some(ADD)),
                    pass::color_target(MAP_FORMAT, Some(ADD)),
                ],
            ),
            froxel_scatter: compute_pipeline(
                ctx,
                "froxel scattering",
                &with(&froxel_layout),
                &froxels,
                "froxel_scatter_main",
            ),
            froxel_integrate: compute_pipeline(
                ctx,
                "froxel integration",
                &with(&froxel_layout),
                &froxels,
                "froxel_integrate_main",
            ),
            froxel_lookup: bufferless_pipeline(
                ctx,
                "froxel lookup",
                &with(&froxel_layout),
                &froxels,
                ("fullscreen_vs", "froxel_lookup_fs"),
                triangles,
                None,
            ),
            shafts_layout,
            composite_layout,
            froxel_layout,
            engine_shadows,
        }
    }
}

impl MediumPasses {
    fn shaft_view(&self, view: &View, settings: &Settings) -> ShaftViewGpu {
        let s = crate::shafts::ShaftView::new(&view.camera, view.width, view.height);
        ShaftViewGpu {
            view_proj: s.view_proj.to_cols_array_2d(),
            eye: s.eye.extend(s.pixel_area).to_array(),
            forward: s
                .forward
                .extend(settings.shaft_blur * view.height as f32)
                .to_array(),
            size: [view.width, view.height, 0, 0],
        }
    }

    /// God rays: every beam of the march's rounds drawn as a band into the in-scattering
    /// buffer (section 3.2).
    fn draw_bands(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        view: &View,
        settings: &Settings,
    ) {
        let ctx = frame.gpu;
        let beams = (targets.beams.size() / 48) as u32;
        let mut params = self.shaft_view(view, settings);
        params.size[2] = beams;
        let params = Uniform::new(ctx, "shaft view", &params);
        let group = bind::group(
            ctx,
            "god-ray bands",
            &self.shafts_layout,
            &[
                targets.beams.as_entire_binding(),
                params.binding(),
                bind::view(&targets.blurred),
            ],
        );
        let mut pass = pass::begin(
            frame.encoder,
            "god-ray bands",
            &[pass::color(&targets.inscatter, pass::Load::Keep)],
            None,
            None,
        );
        pass.set_pipeline(&self.bands);
        groups.set(&mut pass, &group);
        pass.draw(0..6, 0..beams);
    }

    /// God rays: the separable Gaussian blur of the in-scattering buffer (a constant
    /// screen-space support, as the paper's).
    fn blur(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        view: &View,
        settings: &Settings,
    ) {
        if settings.shaft_blur <= 0.0 {
            return;
        }
        let ctx = frame.gpu;
        for (direction, from, to) in [
            (0, &targets.inscatter, &targets.blurred),
            (1, &targets.blurred, &targets.inscatter),
        ] {
            let mut params = self.shaft_view(view, settings);
            params.size[3] = direction;
            let params = Uniform::new(ctx, "shaft blur", &params);
            let group = bind::group(
                ctx,
                "god-ray blur",
                &self.shafts_layout,
                &[
                    targets.beams.as_entire_binding(),
                    params.binding(),
                    bind::view(from),
                ],
            );
            let mut pass = pass::begin(
                frame.encoder,
                "god-ray blur",
                &[pass::color(to, CLEAR_BLACK)],
                None,
                None,
            );
            pass.set_pipeline(&self.blur);
            groups.set(&mut pass, &group);
            gpu::fullscreen::draw(&mut pass);
        }
    }

    /// The froxels' uniform: the hybrid's caustic map's light view (the first light's view of
    /// the casters, as its transfer map), the grid and its slices, and the temporal terms:
    /// this frame's jitter, the history's weight and the last frame's view (`previous`).
    fn froxel_params(
        &self,
        targets: &MediaTargets,
        scene: &GpuScene,
        view: &View,
        settings: &Settings,
        temporal: FroxelTemporal,
    ) -> TechniqueResult<FroxelParamsGpu> {
        let medium = scene
            .scene
            .medium
            .as_ref()
            .expect("a medium: checked by the caller");
        let slices = crate::shafts::Slices::of_medium(medium, view.camera.eye, settings.slices);
        let photons = self.engine_shadows.is_none();
        let (light_view_proj, light, axis) = match scene.scene.lights.first() {
            Some(light) if photons => {
                let (centre, radius) = light_outside_casters(&scene.scene, light, scene.time())?;
                let lv = scene::lightmap::LightView::of_sphere(
                    light.position,
                    centre,
                    radius,
                    settings.caustic_map,
                );
                (
                    lv.view_proj,
                    light.position.extend(lv.pixel_area),
                    lv.axis.extend(1.0),
                )
            }
            _ => (Mat4::IDENTITY, glam::Vec4::ZERO, glam::Vec4::ZERO),
        };
        let [x, y, z] = targets.froxel_grid;
        let previous = temporal.previous;
        Ok(FroxelParamsGpu {
            light_view_proj: light_view_proj.to_cols_array_2d(),
            light: light.to_array(),
            axis: axis.to_array(),
            grid: [x, y, z, settings.froxel_size],
            slices: [
                slices.near,
                slices.far,
                view.width as f32,
                view.height as f32,
            ],
            prev_view_proj: previous
                .map_or(Mat4::IDENTITY, |p| p.view_proj)
                .to_cols_array_2d(),
            prev_eye: previous
                .map_or(glam::Vec4::ZERO, |p| p.eye.extend(1.0))
                .to_array(),
            prev_slices: previous.map_or([0.0; 4], |p| [p.near, p.far, 0.0, 0.0]),
            temporal: [
                temporal.jitter.x,
                temporal.jitter.y,
                temporal.jitter.z,
                temporal.blend,
            ],
        })
    }

    /// The froxels' bind group: `(read, write, history)` index [`MediaTargets::froxels`].
    fn froxel_group(
        &self,
        ctx: &Context,
        params: &Uniform<FroxelParamsGpu>,
        targets: &MediaTargets,
        scene: &GpuScene,
        maps: [&wgpu::TextureView; 2],
        (read, write, history): (usize, usize, usize),
    ) -> wgpu::BindGroup {
        // The engine's maps (transparent surfaces cast no shadow), else the scene's own.
        let (cubes, fitted) = match &self.engine_shadows {
            Some(maps) => (maps.cube_view(), maps.fitted_view()),
            None => scene.shadow_views(),
        };
        bind::group(
            ctx,
            "froxels",
            &self.froxel_layout,
            &[
                params.binding(),
                targets.beams.as_entire_binding(),
                bind::view(maps[0]),
                bind::view(maps[1]),
                bind::view(&targets.froxels[read]),
                bind::view(&targets.froxels[write]),
                bind::view(&targets.froxels[history]),
                bind::view(cubes),
                bind::view(fitted),
            ],
        )
    }

    /// Froxels: the caustic map of the first light, one point per photon's last beam.
    fn draw_caustic_map(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        scene: &GpuScene,
        settings: &Settings,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        // The view's size does not enter the caustic map.
        let view = View {
            camera: scene.scene.camera,
            time: scene.time(),
            width: 1,
            height: 1,
        };
        let params = Uniform::new(
            ctx,
            "froxel params",
            &self.froxel_params(targets, scene, &view, settings, FroxelTemporal::NONE)?,
        );
        let group = self.froxel_group(
            ctx,
            &params,
            targets,
            scene,
            [&targets.inscatter, &targets.blurred],
            (1, 0, 2),
        );
        let mut pass = pass::begin(
            frame.encoder,
            "froxel caustic map",
            &[
                pass::color(&targets.caustic_maps[0], pass::Load::Keep),
                pass::color(&targets.caustic_maps[1], pass::Load::Keep),
            ],
            None,
            None,
        );
        pass.set_pipeline(&self.caustic_map);
        groups.set(&mut pass, &group);
        pass.draw(0..(targets.beams.size() / 48) as u32, 0..1);
        Ok(())
    }

    /// Froxels: light the grid (the engine's visibility drawn first), blend it with the last
    /// frame's grid reprojected, integrate it front to back, look it up per pixel into the
    /// in-scattering buffer.
    fn froxels(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        scene: &GpuScene,
        view: &View,
        settings: &Settings,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if let Some(maps) = &self.engine_shadows {
            maps.render(frame, scene);
        }
        let (index, previous) = targets.froxel_history.get();
        let temporal = FroxelTemporal::of_frame(index, previous, settings.temporal_blend);
        let params = self.froxel_params(targets, scene, view, settings, temporal)?;
        targets.froxel_history.set((
            index + 1,
            Some(FroxelView {
                view_proj: view.camera.view_proj(view.width, view.height),
                eye: view.camera.eye,
                // This frame's slices, as the uniform holds them (near, far).
                near: params.slices[0],
                far: params.slices[1],
            }),
        ));
        let params = Uniform::new(ctx, "froxel params", &params);
        let maps = [&targets.caustic_maps[0], &targets.caustic_maps[1]];
        // This frame's grid and the last frame's (its history) alternate between 0 and 2.
        let (grid, history) = if index % 2 == 0 { (0, 2) } else { (2, 0) };
        let [x, y, z] = targets.froxel_grid;
        for (pipeline, bindings, workgroups) in [
            (
                &self.froxel_scatter,
                (1, grid, history),
                [x.div_ceil(4), y.div_ceil(4), z.div_ceil(4)],
            ),
            (
                &self.froxel_integrate,
                (grid, 1, history),
                [x.div_ceil(8), y.div_ceil(8), 1],
            ),
        ] {
            let group = self.froxel_group(ctx, &params, targets, scene, maps, bindings);
            let mut pass = frame
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, groups.camera, &[]);
            pass.set_bind_group(1, groups.scene, &[]);
            pass.set_bind_group(2, groups.ldi, &[]);
            pass.set_bind_group(3, &group, &[]);
            pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
        }
        let group = self.froxel_group(ctx, &params, targets, scene, maps, (1, grid, history));
        let mut pass = pass::begin(
            frame.encoder,
            "froxel lookup",
            &[pass::color(&targets.inscatter, CLEAR_BLACK)],
            None,
            None,
        );
        pass.set_pipeline(&self.froxel_lookup);
        groups.set(&mut pass, &group);
        gpu::fullscreen::draw(&mut pass);
        Ok(())
    }

    /// Every variant in a medium: the image times the transmittance to its first surface,
    /// plus the in-scattering buffer.
    fn composite(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        target: &Target,
    ) {
        let ctx = frame.gpu;
        let group = bind::group(
            ctx,
            "medium composite",
            &self.composite_layout,
            &[bind::view(&targets.inscatter)],
        );
        for pipeline in [&self.attenuate, &self.add_inscatter] {
            let mut pass = pass::begin(
                frame.encoder,
                "medium composite",
                &[pass::color(&target.color_view, pass::Load::Keep)],
                None,
                None,
            );
            pass.set_pipeline(pipeline);
            groups.set(&mut pass, &group);
            gpu::fullscreen::draw(&mut pass);
        }
    }
}

/// The pipelines and bind-group layouts (per scene: they use its layouts).
struct Passes {
    /// A scene with a scattering medium only.
    medium: Option<MediumPasses>,
    ldi_layout: wgpu::BindGroupLayout,
    transfer_layout: wgpu::BindGroupLayout,
    gather_layout: wgpu::BindGroupLayout,
    lines_layout: wgpu::BindGroupLayout,
    reduce_layout: wgpu::BindGroupLayout,
    dda_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
    splat_layout: wgpu::BindGroupLayout,
    apply_layout: wgpu::BindGroupLayout,
    specular_layout: wgpu::BindGroupLayout,
    shadow_mask_layout: wgpu::BindGroupLayout,
    shadowed_layout: wgpu::BindGroupLayout,
    // The pipelines of the variant's passes only ([`Passes::new`]; [`made`] takes one out).
    transfer: Option<wgpu::RenderPipeline>,
    shadow_mask: Option<wgpu::ComputePipeline>,
    shadowed: Option<wgpu::RenderPipeline>,
    gather: Option<wgpu::ComputePipeline>,
    lines: Option<wgpu::RenderPipeline>,
    reduce: Option<wgpu::ComputePipeline>,
    /// The per-photon march: the DDA or the tolerance test in one invocation per photon.
    per_photon: Option<wgpu::ComputePipeline>,
    resolve: Option<wgpu::ComputePipeline>,
    splat: Option<wgpu::RenderPipeline>,
    apply: Option<wgpu::RenderPipeline>,
    specular: wgpu::RenderPipeline,
}

/// A pipeline of the variant's passes: [`Passes::new`] made it (a variant asking for one it
/// did not make is a bug in this file, not an input error).
fn made<T>(pipeline: &Option<T>) -> &T {
    pipeline
        .as_ref()
        .expect("Passes::new makes every pipeline the variant's passes use")
}

impl Passes {
    /// The layouts, and the pipelines of `variant`'s passes: the caustic passes (and the
    /// marcher it uses) for a caustic variant, the shadow mask for screen-space shadows, the
    /// refraction pass for all; in a scene with a scattering medium, the medium's passes for
    /// every variant (each variant's image is attenuated by it). On lavapipe a pipeline costs
    /// ~30 ms of compilation, so a variant that made them all spent most of its prepare on
    /// passes it never runs.
    fn new(ctx: &Context, scene: &GpuScene, variant: &Variant) -> Self {
        use wgpu::ShaderStages as S;
        let caustics = variant.caustics.is_some();
        let marches = |m: March| matches!(variant.caustics, Some((march, _)) if march == m);
        let shadows = variant.screen_space_shadows;
        let all = S::VERTEX_FRAGMENT | S::COMPUTE;
        let layers = bind::texture(wgpu::TextureViewDimension::D2Array, false);
        let ldi_layout = bind::layout(
            ctx,
            "ldi",
            all,
            &[bind::uniform(), layers, layers, layers, layers],
        );
        let map = bind::texture_2d_unfilterable();
        let transfer_layout = bind::layout(ctx, "transfer", S::FRAGMENT, &[bind::uniform()]);
        let gather_layout = bind::layout(
            ctx,
            "gather",
            S::COMPUTE,
            &[
                map,
                map,
                bind::storage(false),
                bind::storage(false),
                bind::uniform(),
            ],
        );
        let lines_layout = bind::layout(
            ctx,
            "lines",
            S::VERTEX_FRAGMENT,
            &[bind::storage(true), bind::uniform()],
        );
        let reduce_layout = bind::layout(
            ctx,
            "reduce",
            S::COMPUTE,
            &[map, bind::storage(false), bind::uniform()],
        );
        let dda_layout = bind::layout(
            ctx,
            "dda",
            S::COMPUTE,
            &[bind::storage(true), bind::storage(false)],
        );
        let resolve_layout = bind::layout(
            ctx,
            "resolve",
            S::COMPUTE,
            &[
                bind::storage(false),
                bind::storage(true),
                bind::storage(false),
                bind::uniform(),
                bind::storage(false),
            ],
        );
        let splat_layout = bind::layout(
            ctx,
            "splat",
            S::VERTEX_FRAGMENT,
            &[bind::storage(true), bind::uniform()],
        );
        let apply_layout = bind::layout(ctx, "apply", S::FRAGMENT, &[map]);
        let specular_layout = bind::layout(ctx, "specular", S::FRAGMENT, &[bind::uniform()]);
        let shadow_mask_layout =
            bind::layout(ctx, "shadow mask", S::COMPUTE, &[bind::storage(false)]);
        let shadowed_layout = bind::layout(ctx, "shadowed", S::FRAGMENT, &[bind::storage(true)]);

        let with =
            |own: &wgpu::BindGroupLayout| scene.pipeline_layout_with(ctx, &[&ldi_layout, own]);
        let transfer = caustics.then(|| {
            let transfer_module = gpu::shader_with_prelude(
                ctx,
                "transfer map",
                &format!("{SCENE_WGSL}\n{TRANSFER_WGSL}"),
            );
            scene::scene_pipeline_with(
                ctx,
                "transfer map",
                &scene.pipeline_layout_with(ctx, &[&transfer_layout]),
                &transfer_module,
                "transfer_fs",
                &[
                    pass::color_target(MAP_FORMAT, None),
                    pass::color_target(MAP_FORMAT, None),
                ],
                (true, wgpu::CompareFunction::Less),
            )
        });
        let hdr_module =
            |label: &str, own: &str| gpu::shader_with_prelude(ctx, label, &pass_source(own));
        let apply = caustics.then(|| {
            scene::scene_pipeline_with(
                ctx,
                "caustic apply",
                &with(&apply_layout),
                &hdr_module("caustic apply", APPLY_WGSL),
                "apply_fs",
                &[pass::color_target(
                    gpu::HDR_FORMAT,
                    Some(ADD_RGB_KEEP_ALPHA),
                )],
                (false, wgpu::CompareFunction::Equal),
            )
        });
        let specular = scene::scene_pipeline_with(
            ctx,
            "screen-space refraction",
            &with(&specular_layout),
            &hdr_module("screen-space refraction", SPECULAR_WGSL),
            "specular_fs",
            &[pass::color_target(gpu::HDR_FORMAT, None)],
            (true, wgpu::CompareFunction::Less),
        );
        let shadowed = shadows.then(|| {
            scene::scene_pipeline_with(
                ctx,
                "screen-space shadowed",
                &with(&shadowed_layout),
                &hdr_module("screen-space shadowed", SHADOWED_WGSL),
                "shadowed_fs",
                &[pass::color_target(gpu::HDR_FORMAT, None)],
                (true, wgpu::CompareFunction::Less),
            )
        });
        Self {
            medium: scene
                .scene
                .medium
                .is_some()
                .then(|| MediumPasses::new(ctx, scene, &ldi_layout, variant)),
            shadow_mask: shadows.then(|| {
                compute_pipeline(
                    ctx,
                    "shadow mask",
                    &with(&shadow_mask_layout),
                    SHADOW_MASK_WGSL,
                    "shadow_main",
                )
            }),
            shadowed,
            shadow_mask_layout,
            shadowed_layout,
            gather: caustics.then(|| {
                compute_pipeline(
                    ctx,
                    "gather photons",
                    &with(&gather_layout),
                    GATHER_WGSL,
                    "gather_main",
                )
            }),
            lines: marches(March::Lines).then(|| {
                bufferless_pipeline(
                    ctx,
                    "photon lines",
                    &with(&lines_layout),
                    LINES_WGSL,
                    ("line_vs", "line_fs"),
                    wgpu::PrimitiveTopology::LineList,
                    None,
                )
            }),
            reduce: marches(March::Lines).then(|| {
                compute_pipeline(
                    ctx,
                    "reduce rows",
                    &with(&reduce_layout),
                    REDUCE_WGSL,
                    "reduce_main",
                )
            }),
            per_photon: match variant.caustics {
                Some((March::Dda, _)) => Some(("dda march", "dda_main")),
                Some((March::Shader, _)) => Some(("tolerance march", "tolerance_main")),
                _ => None,
            }
            .map(|(label, entry)| {
                compute_pipeline(ctx, label, &with(&dda_layout), DDA_WGSL, entry)
            }),
            resolve: caustics.then(|| {
                compute_pipeline(
                    ctx,
                    "resolve photons",
                    &with(&resolve_layout),
                    RESOLVE_WGSL,
                    "resolve_main",
                )
            }),
            splat: caustics.then(|| {
                bufferless_pipeline(
                    ctx,
                    "splats",
                    &with(&splat_layout),
                    &format!(
                        "{}\n{}\n{SPLAT_WGSL}",
                        scene::lightmap::FOOTPRINT_WGSL,
                        crate::splat::WEIGHT_WGSL
                    ),
                    ("splat_vs", "splat_fs"),
                    wgpu::PrimitiveTopology::TriangleList,
                    Some(ADD),
                )
            }),
            transfer,
            apply,
            specular,
            ldi_layout,
            transfer_layout,
            gather_layout,
            lines_layout,
            reduce_layout,
            dda_layout,
            resolve_layout,
            splat_layout,
            apply_layout,
            specular_layout,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn frame(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
        sized: &Sized,
        settings: &Settings,
        variant: &Variant,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let (width, height) = (view.width, view.height);
        let camera = view.camera;
        let view_proj = camera.view_proj(width, height);
        let eye = camera.eye;
        let specular = scene.scene.specular_objects();
        frame.span("ldi", |frame| -> TechniqueResult<()> {
            sized
                .scene_ldi
                .peel(frame, scene, &ObjectFilter::All, view_proj, eye)?;
            sized.refractor_ldi.peel(
                frame,
                scene,
                &ObjectFilter::Only(specular.clone()),
                view_proj,
                eye,
            )?;
            Ok(())
        })?;

        // The scene's box at this time, grown a little (rays start on its surfaces).
        let (lo, hi) = scene_box(&scene.scene, scene.time());
        let margin = Vec3::splat((hi - lo).length() * 1e-3 + 1e-3);
        let ldi_params = LdiParamsGpu {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            size: [width, height, settings.layers, sized.line_width],
            tests: [
                settings.tolerance,
                settings.thickness,
                settings.tolerance,
                0.0,
            ],
            bounds_min: (lo - margin).extend(0.0).to_array(),
            bounds_max: (hi + margin).extend(0.0).to_array(),
        };
        sized.ldi_params.set(Some(ldi_params));
        let ldi_params = Uniform::new(ctx, "ldi params", &ldi_params);
        let ldi_group = bind::group(
            ctx,
            "ldi",
            &self.ldi_layout,
            &[
                ldi_params.binding(),
                bind::view(sized.scene_ldi.layers_view()),
                bind::view(sized.scene_ldi.surfaces_view()),
                bind::view(sized.refractor_ldi.layers_view()),
                bind::view(sized.refractor_ldi.surfaces_view()),
            ],
        );
        let camera_group = scene.camera_bind_group(ctx, view_proj, eye);
        let groups = Groups {
            camera: &camera_group,
            scene: scene.bind_group(),
            ldi: &ldi_group,
        };

        if let (true, Some(mask)) = (variant.screen_space_shadows, &sized.shadow_mask) {
            self.screen_space_shadowed(frame, scene, &groups, mask, sized.key, target, &specular);
        } else {
            scene.raster(
                frame,
                &RasterTarget::of(target, true),
                view_proj,
                eye,
                &ObjectFilter::All,
                false,
            );
        }

        let media = sized.media.as_ref().zip(self.medium.as_ref());
        if let Some((targets, _)) = media {
            pass::begin(
                frame.encoder,
                "clear in-scattering",
                &[pass::color(&targets.inscatter, CLEAR_BLACK)],
                None,
                None,
            );
            pass::begin(
                frame.encoder,
                "clear caustic map",
                &[
                    pass::color(&targets.caustic_maps[0], CLEAR_BLACK),
                    pass::color(&targets.caustic_maps[1], CLEAR_BLACK),
                ],
                None,
                None,
            );
        }
        let keep_beams = media.is_some() && variant.shafts.is_some_and(Shafts::from_photons);
        if let Some((march, splat)) = variant.caustics {
            pass::begin(
                frame.encoder,
                "clear irradiance",
                &[pass::color(&sized.irradiance, CLEAR_BLACK)],
                None,
                None,
            );
            for (light_index, light) in scene.scene.lights.iter().enumerate() {
                let spacing = frame.span("caustics", |frame| -> TechniqueResult<f32> {
                    let (spacing, flux) = self.transfer(frame, scene, sized, settings, light)?;
                    let flux = Uniform::new(ctx, "unit flux", &flux.extend(0.0).to_array());
                    self.dispatch(
                        frame,
                        &groups,
                        made(&self.gather),
                        &bind::group(
                            ctx,
                            "gather",
                            &self.gather_layout,
                            &[
                                bind::view(&sized.transfer[0]),
                                bind::view(&sized.transfer[1]),
                                sized.photons.photons.as_entire_binding(),
                                sized.photons.receivers.as_entire_binding(),
                                flux.binding(),
                            ],
                        ),
                        sized.photons.count.div_ceil(64),
                    );
                    for round in 0..=settings.bounces {
                        // The march alone (the paper: "intersection testing consumed over 80% of
                        // the time").
                        frame.span("march", |frame| match march {
                            March::Lines => self.march_lines(frame, &groups, sized),
                            March::Dda | March::Shader => self.dispatch(
                                frame,
                                &groups,
                                made(&self.per_photon),
                                &bind::group(
                                    ctx,
                                    "dda",
                                    &self.dda_layout,
                                    &[
                                        sized.photons.photons.as_entire_binding(),
                                        sized.photons.hits.as_entire_binding(),
                                    ],
                                ),
                                sized.photons.count.div_ceil(64),
                            ),
                        });
                        let beams = media.map(|(targets, _)| &targets.beams);
                        let keep = beams.filter(|_| keep_beams);
                        self.resolve(frame, &groups, sized, settings, round, keep);
                    }
                    Ok(spacing)
                })?;
                if let (Some((targets, passes)), true) = (media, keep_beams) {
                    frame.span("shafts", |frame| -> TechniqueResult<()> {
                        match variant.shafts {
                            Some(Shafts::GodRays) => {
                                passes.draw_bands(frame, &groups, targets, view, settings)
                            }
                            Some(Shafts::FroxelsWithPhotons) if light_index == 0 => {
                                passes.draw_caustic_map(frame, &groups, targets, scene, settings)?
                            }
                            _ => {}
                        }
                        Ok(())
                    })?;
                }
                frame.span("splat", |frame| {
                    self.splat(
                        frame,
                        &groups,
                        sized,
                        view,
                        splat,
                        spacing * settings.splat_radius,
                        settings,
                    );
                });
            }
            let apply_group = bind::group(
                ctx,
                "apply",
                &self.apply_layout,
                &[bind::view(&sized.irradiance)],
            );
            let mut pass = pass::begin(
                frame.encoder,
                "caustic apply",
                &[pass::color(&target.color_view, pass::Load::Keep)],
                Some(pass::depth(&target.depth_view, pass::Load::Keep)),
                None,
            );
            pass.set_pipeline(made(&self.apply));
            groups.set(&mut pass, &apply_group);
            scene.draw_objects(&mut pass, &ObjectFilter::Except(specular.clone()));
        }

        frame.span("refraction", |frame| {
            let mode = Uniform::new(
                ctx,
                "specular mode",
                &ModeGpu {
                    value: (variant.refraction == Refraction::Dda) as u32,
                    _pad: [0; 3],
                },
            );
            let specular_group =
                bind::group(ctx, "specular", &self.specular_layout, &[mode.binding()]);
            {
                let mut pass = pass::begin(
                    frame.encoder,
                    "screen-space refraction",
                    &[pass::color(&target.color_view, pass::Load::Keep)],
                    Some(pass::depth(&target.depth_view, pass::Load::Keep)),
                    None,
                );
                pass.set_pipeline(&self.specular);
                groups.set(&mut pass, &specular_group);
                scene.draw_objects(&mut pass, &ObjectFilter::Only(specular));
            }
        });
        if let Some((targets, passes)) = media {
            frame.span("shafts", |frame| -> TechniqueResult<()> {
                match variant.shafts {
                    Some(Shafts::GodRays) => passes.blur(frame, &groups, targets, view, settings),
                    Some(Shafts::Froxels | Shafts::FroxelsWithPhotons) => {
                        passes.froxels(frame, &groups, targets, scene, view, settings)?
                    }
                    None => {}
                }
                Ok(())
            })?;
            frame.span("medium", |frame| {
                passes.composite(frame, &groups, targets, target);
            });
        }
        Ok(())
    }

    /// The diffuse surfaces with screen-space shadow rays: the visibility mask (a compute
    /// pass over layer 0 of the LDI), then the surfaces drawn with it.
    #[allow(clippy::too_many_arguments)]
    fn screen_space_shadowed(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        groups: &Groups,
        mask: &wgpu::Buffer,
        (width, height): (u32, u32),
        target: &Target,
        specular: &[usize],
    ) {
        let ctx = frame.gpu;
        frame.span("shadows", |frame| {
            let mask_group = bind::group(
                ctx,
                "shadow mask",
                &self.shadow_mask_layout,
                &[mask.as_entire_binding()],
            );
            {
                let mut pass = frame
                    .encoder
                    .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
                pass.set_pipeline(made(&self.shadow_mask));
                pass.set_bind_group(0, groups.camera, &[]);
                pass.set_bind_group(1, groups.scene, &[]);
                pass.set_bind_group(2, groups.ldi, &[]);
                pass.set_bind_group(3, &mask_group, &[]);
                pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
            }
        });
        let group = bind::group(
            ctx,
            "shadowed",
            &self.shadowed_layout,
            &[mask.as_entire_binding()],
        );
        let background = scene.scene.background;
        let mut pass = pass::begin(
            frame.encoder,
            "screen-space shadowed",
            &[pass::color(
                &target.color_view,
                pass::Load::Clear(wgpu::Color {
                    r: background.x as f64,
                    g: background.y as f64,
                    b: background.z as f64,
                    a: scene::BACKGROUND_DISTANCE as f64,
                }),
            )],
            Some(pass::depth(&target.depth_view, CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(made(&self.shadowed));
        groups.set(&mut pass, &group);
        scene.draw_objects(&mut pass, &ObjectFilter::Except(specular.to_vec()));
    }

    /// The transfer map of `light`: returns the photon spacing at the casters' centre (m)
    /// and the flux of a unit weight (the light's intensity times a pixel's solid angle).
    fn transfer(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        sized: &Sized,
        settings: &Settings,
        light: &scene::PointLight,
    ) -> TechniqueResult<(f32, Vec3)> {
        let ctx = frame.gpu;
        let (centre, radius) = light_outside_casters(&scene.scene, light, scene.time())?;
        let grid = settings.photons;
        let (view_proj, params, spacing) = light_view(light, centre, radius, grid, settings.jitter);
        let uniform = Uniform::new(ctx, "transfer params", &params);
        let group = bind::group(ctx, "transfer", &self.transfer_layout, &[uniform.binding()]);
        let camera = scene.camera_bind_group(ctx, view_proj, light.position);
        let mut pass = pass::begin(
            frame.encoder,
            "transfer map",
            &[
                pass::color(&sized.transfer[0], CLEAR_BLACK),
                pass::color(&sized.transfer[1], CLEAR_BLACK),
            ],
            Some(pass::depth(&sized.transfer[2], CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(made(&self.transfer));
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::All);
        let flux = Vec3::from_slice(&params.intensity[..3]) * params.axis[3];
        Ok((spacing, flux))
    }

    fn dispatch(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        pipeline: &wgpu::ComputePipeline,
        own: &wgpu::BindGroup,
        workgroups: u32,
    ) {
        let mut pass = frame
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, groups.camera, &[]);
        pass.set_bind_group(1, groups.scene, &[]);
        pass.set_bind_group(2, groups.ldi, &[]);
        pass.set_bind_group(3, own, &[]);
        pass.dispatch_workgroups(workgroups.max(1), 1, 1);
    }

    /// The paper's line marcher: batches of `rows` photons, each drawn as lines into the row
    /// buffer and reduced to the first hit per row.
    fn march_lines(&self, frame: &mut Frame, groups: &Groups, sized: &Sized) {
        let ctx = frame.gpu;
        let rows = sized.line_rows_count;
        for first in (0..sized.photons.count).step_by(rows as usize) {
            let batch = Uniform::new(
                ctx,
                "line batch",
                &BatchGpu {
                    first,
                    rows,
                    width: sized.line_width,
                    _pad: 0,
                },
            );
            let lines_group = bind::group(
                ctx,
                "lines",
                &self.lines_layout,
                &[sized.photons.photons.as_entire_binding(), batch.binding()],
            );
            {
                let mut pass = pass::begin(
                    frame.encoder,
                    "photon lines",
                    &[pass::color(&sized.line_rows, CLEAR_BLACK)],
                    None,
                    None,
                );
                pass.set_pipeline(made(&self.lines));
                groups.set(&mut pass, &lines_group);
                pass.draw(0..2, 0..rows);
            }
            let reduce_group = bind::group(
                ctx,
                "reduce",
                &self.reduce_layout,
                &[
                    bind::view(&sized.line_rows),
                    sized.photons.hits.as_entire_binding(),
                    batch.binding(),
                ],
            );
            self.dispatch(
                frame,
                groups,
                made(&self.reduce),
                &reduce_group,
                rows.div_ceil(64),
            );
        }
    }

    /// Resolves round `round`'s hits; `beams`: keep each photon ray as a beam there.
    fn resolve(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        sized: &Sized,
        settings: &Settings,
        round: u32,
        beams: Option<&wgpu::Buffer>,
    ) {
        let ctx = frame.gpu;
        let params = Uniform::new(
            ctx,
            "resolve params",
            &ResolveParamsGpu {
                max_bounces: settings.bounces,
                round,
                keep_beams: beams.is_some() as u32,
                _pad: 0,
            },
        );
        let beams = beams.unwrap_or(&sized.no_beams);
        let group = bind::group(
            ctx,
            "resolve",
            &self.resolve_layout,
            &[
                sized.photons.photons.as_entire_binding(),
                sized.photons.hits.as_entire_binding(),
                sized.photons.receivers.as_entire_binding(),
                params.binding(),
                beams.as_entire_binding(),
            ],
        );
        self.dispatch(
            frame,
            groups,
            made(&self.resolve),
            &group,
            sized.photons.count.div_ceil(64),
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn splat(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        sized: &Sized,
        view: &View,
        splat: Splat,
        radius: f32,
        settings: &Settings,
    ) {
        let ctx = frame.gpu;
        let camera = view.camera;
        let (forward, _, _) = camera.basis();
        let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let focal = view.height as f32 / (2.0 * tan_half);
        // A sphere's projection off the view axis is wider than on it by up to the secant of
        // the angle to the view's corner (splat_vs sizes its quads with it).
        let aspect = view.width as f32 / view.height as f32;
        let corner_secant = (1.0 + tan_half * tan_half * (1.0 + aspect * aspect)).sqrt();
        let params = Uniform::new(
            ctx,
            "splat params",
            &SplatParamsGpu {
                inv_view_proj: camera
                    .view_proj(view.width, view.height)
                    .inverse()
                    .to_cols_array_2d(),
                forward: forward.extend(focal * corner_secant).to_array(),
                size: [
                    view.width as f32,
                    view.height as f32,
                    radius,
                    settings.tolerance.max(radius * 0.25),
                ],
                mode: (splat == Splat::Sprite) as u32,
                // Receiver i is the photon of transfer-map pixel i: one lattice per light.
                lattice: if settings.footprint {
                    settings.photons
                } else {
                    0
                },
                _pad: [0; 2],
            },
        );
        let group = bind::group(
            ctx,
            "splat",
            &self.splat_layout,
            &[
                sized.photons.receivers.as_entire_binding(),
                params.binding(),
            ],
        );
        let mut pass = pass::begin(
            frame.encoder,
            "splats",
            &[pass::color(&sized.irradiance, pass::Load::Keep)],
            None,
            None,
        );
        pass.set_pipeline(made(&self.splat));
        groups.set(&mut pass, &group);
        pass.draw(0..6, 0..sized.photons.count);
    }
}

/// The bind groups every pass of a frame shares.
struct Groups<'a> {
    camera: &'a wgpu::BindGroup,
    scene: &'a wgpu::BindGroup,
    ldi: &'a wgpu::BindGroup,
}

impl Groups<'_> {
    fn set(&self, pass: &mut wgpu::RenderPass<'_>, own: &wgpu::BindGroup) {
        pass.set_bind_group(0, self.camera, &[]);
        pass.set_bind_group(1, self.scene, &[]);
        pass.set_bind_group(2, self.ldi, &[]);
        pass.set_bind_group(3, own, &[]);
    }
}

/// A box holding every object's bounding sphere at `time`.
fn scene_box(scene: &Scene, time: f32) -> (Vec3, Vec3) {
    scene.objects.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), o| {
            let (c, r) = (o.center_at(time), Vec3::splat(o.bounding_radius_at(time)));
            (lo.min(c - r), hi.max(c + r))
        },
    )
}

/// The bounding sphere of the caustic casters (specular objects and those with the
/// `CAUSTIC_CASTER` role) at `time`.
pub fn casters_sphere(scene: &Scene, time: f32) -> (Vec3, f32) {
    let casters: Vec<_> = scene
        .objects
        .iter()
        .filter(|o| o.material.is_specular() || o.roles.contains(scene::Roles::CAUSTIC_CASTER))
        .collect();
    let (lo, hi) = casters.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), o| {
            let (c, r) = (o.center_at(time), o.bounding_radius_at(time));
            (lo.min(c - Vec3::splat(r)), hi.max(c + Vec3::splat(r)))
        },
    );
    let centre = (lo + hi) * 0.5;
    let radius = casters
        .iter()
        .map(|o| (o.center_at(time) - centre).length() + o.bounding_radius_at(time))
        .fold(0.0, f32::max);
    (centre, radius)
}

/// The casters' bounding sphere at `time` when `light` lies outside it (a transfer map is one
/// view from the light, which cannot hold casters around it: the reference emits over the
/// whole sphere there), else why not.
pub fn light_outside_casters(
    scene: &Scene,
    light: &scene::PointLight,
    time: f32,
) -> TechniqueResult<(Vec3, f32)> {
    let (centre, radius) = casters_sphere(scene, time);
    if centre.is_finite() && light.position.distance(centre) > radius * 1.05 {
        return Ok((centre, radius));
    }
    Err(TechniqueError::Unsupported(format!(
        "light \"{}\" lies inside the bounding sphere of the caustic casters (centre {centre}, \
         radius {radius:.3} m): a transfer map is one view from the light and cannot hold casters \
         around it",
        light.name
    )))
}

/// The light's view of the casters' sphere (`scene::lightmap::LightView`): its matrix, the
/// transfer uniform, and the photon spacing at the sphere's centre.
fn light_view(
    light: &scene::PointLight,
    centre: Vec3,
    radius: f32,
    grid: u32,
    jitter: bool,
) -> (Mat4, TransferParamsGpu, f32) {
    let view = scene::lightmap::LightView::of_sphere(light.position, centre, radius, grid);
    let params = TransferParamsGpu {
        light: light.position.extend(1.0).to_array(),
        intensity: light.intensity.extend(0.0).to_array(),
        axis: view.axis.extend(view.pixel_area).to_array(),
        jitter: jitter as u32,
        _pad: [0; 3],
    };
    (view.view_proj, params, view.spacing())
}
