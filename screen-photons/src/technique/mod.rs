//! The screen-photons technique: the passes of a frame and its variants.
//!
//! Where things are: `settings.rs` (the variants and the settings each parameter sets),
//! `resources.rs` (what follows the view's size: LDIs, photon buffers, transfer maps, the
//! medium's targets, and the check that they fit), `passes.rs` (the pipelines, and
//! [`Passes::frame`], a short function that orders the passes below, each a method stating
//! what it reads and writes), `medium.rs` (the passes of a scene with a scattering medium),
//! `gpu_types.rs` (the uniform blocks and pipeline helpers), `shaders.rs` (the WGSL sources),
//! `light.rs` (the light's view of the casters); this file, [`ScreenPhotons`] and its
//! `Technique` impl.
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
use scene::emission::{footprint_declared, jitter_declared};
use scene::technique::Declared;
use scene::{
    CasterShadowMaps, DepthPeeler, Frame, GpuScene, ObjectFilter, RasterTarget, Scene, Technique,
    TechniqueError, TechniqueResult, View,
};

mod gpu_types;
mod light;
mod medium;
mod passes;
mod resources;
mod settings;
mod shaders;

pub use gpu_types::*;
pub use light::*;
use medium::*;
use passes::*;
pub use resources::*;
pub use settings::*;
pub use shaders::*;

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

    /// The transfer map is one perspective view from each light's position (section 3), and
    /// the shadowed and fog passes light with point lights.
    fn point_lights(&self, scene: &Scene) -> TechniqueResult<()> {
        scene::point_lights_only(
            &self.id(),
            "its transfer map is the scene seen from each light's position",
            scene,
        )
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

    // Sizes and batch counts follow the settings: a set parameter drops them.
    scene::declared_params!(settings, sized);

    fn required_features(&self) -> wgpu::Features {
        wgpu::Features::FLOAT32_BLENDABLE
    }

    /// A scene with a specular object, every light outside the caustic casters' bounding
    /// sphere (at time 0; [`light_outside_casters`]).
    fn supports(&self, scene: &Scene) -> bool {
        (self.variant.shafts.is_none() || scene.medium.is_some())
            && !scene.specular_objects().is_empty()
            && self.point_lights(scene).is_ok()
            && scene
                .lights
                .iter()
                .all(|l| light_outside_casters(scene, l, 0.0).is_ok())
    }

    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        self.point_lights(&scene.scene)?;
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
