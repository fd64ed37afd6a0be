//! The tracer as a [`Technique`]: `raytracer/whitted` (the eye pass alone) and
//! `raytracer/caustics` (the eye pass and the light pass: the reference's whole image).

use crate::tracer::{GpuTracer, MAX_PHOTONS, MAX_VOLUMES, TracerSettings, Traversal};
use gpu::Target;
use scene::Settings as _;
use scene::technique::{
    Declared, Param, ParamValue, TechniqueResult, not_prepared, set_checked, setting_if,
};
use scene::{Frame, GpuScene, Scene, Technique, View};

/// The two variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Whitted chains with shadow rays and the media, no caustic photons.
    Whitted,
    /// The same plus light-traced caustic photons: the exact counterpart of the reference.
    Caustics,
    /// `Caustics` with the hardware's ray queries in place of the BVH traversal.
    RayQuery,
}

/// A variant with its settings; the scene's tracer after `prepare`.
pub struct RayTracer {
    variant: Variant,
    settings: Settings,
    tracer: Option<GpuTracer>,
}

/// The parameters of a variant: the tracer's, and the frames an error frame accumulates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub tracer: TracerSettings,
    /// Frames an error frame accumulates ([`Technique::frames_to_converge`]).
    pub converge: u32,
}

impl scene::Settings for Settings {
    /// `photons` and `converge` where the variant traces photons (`photons` is `Some`).
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "max_depth",
            (0.0, 16.0),
            "specular interactions followed along a path (the reference's max_depth)",
            |s| Some(&mut s.tracer.max_depth),
        ),
        Declared::new(
            "photons",
            (0.0, MAX_PHOTONS as f64),
            "caustic photons per frame; 0: a sixteenth of the reference's density (61 per \
             pixel, at least 100 000), so 16 frames of one view reach it",
            |s| s.tracer.photons.as_mut().map(|p| p as &mut dyn ParamValue),
        ),
        Declared::new(
            "converge",
            (1.0, 1024.0),
            "frames of one view an error frame accumulates (each with new photons, the \
             image their running mean): 16 reach the reference's density with photons=0",
            |s| setting_if(s.tracer.photons.is_some(), &mut s.converge),
        ),
    ];
}

/// The default of `converge`: an error frame holds 4 frames' photons, a quarter of the
/// reference's density (16 frames reach it; the default compare on a 2-core software adapter
/// cannot afford that at every error time of every scene).
pub const DEFAULT_CONVERGE: u32 = 4;

impl RayTracer {
    pub fn new(variant: Variant) -> Self {
        let photons = match variant {
            Variant::Whitted => None,
            Variant::Caustics | Variant::RayQuery => Some(0),
        };
        let tracer = TracerSettings {
            photons,
            ..TracerSettings::default()
        };
        let converge = match variant {
            Variant::Whitted => 1,
            Variant::Caustics | Variant::RayQuery => DEFAULT_CONVERGE,
        };
        Self {
            variant,
            settings: Settings { tracer, converge },
            tracer: None,
        }
    }

    /// The prepared tracer (BVH build time, triangle count, ray counts of the last frame).
    pub fn tracer(&self) -> Option<&GpuTracer> {
        self.tracer.as_ref()
    }
}

impl Technique for RayTracer {
    fn id(&self) -> String {
        match self.variant {
            Variant::Whitted => "raytracer/whitted".into(),
            Variant::Caustics => "raytracer/caustics".into(),
            Variant::RayQuery => "raytracer/ray-query".into(),
        }
    }

    fn description(&self) -> String {
        match self.variant {
            Variant::Whitted => "exact GPU ray tracing of the reference's eye pass (Whitted \
                                 chains, shadow rays, media) over the scene's BVH, no caustics"
                .into(),
            Variant::Caustics => "exact GPU ray tracing of the whole reference: the eye pass \
                                  plus light-traced caustic photons (the yardstick of \
                                  speedup_vs_raytracer)"
                .into(),
            Variant::RayQuery => "raytracer/caustics with the hardware's ray queries (wgpu's \
                                  experimental ray_query) in place of the BVH traversal"
                .into(),
        }
    }

    fn params(&self) -> Vec<Param> {
        self.settings.params()
    }
    fn orthographic_camera(&self) -> bool {
        true
    }

    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id(), &mut self.settings, name, value)?;
        if let Some(t) = &mut self.tracer {
            t.set_settings(self.settings.tracer);
        }
        Ok(())
    }

    fn required_features(&self) -> gpu::wgpu::Features {
        match self.variant {
            Variant::RayQuery => gpu::wgpu::Features::EXPERIMENTAL_RAY_QUERY,
            _ => gpu::wgpu::Features::empty(),
        }
    }

    fn frames_to_converge(&self) -> u32 {
        self.settings.converge
    }

    /// The ray-query variant is the same image as `caustics`, traversed by the hardware: what
    /// it measures is a GPU's ray-tracing units, which a software adapter only emulates (it
    /// took 14 times `caustics`' frame on lavapipe 25). `--all-variants` or naming it runs it.
    fn representative(&self) -> bool {
        self.variant != Variant::RayQuery
    }

    /// `caustics` contains `whitted`: its eye pass is whitted's whole frame (the same rays by
    /// the same traversal), timed by the "eye" and "resolve" spans; with another `max_depth`
    /// than whitted's default it is another eye pass, and contains nothing.
    fn contains(&self) -> Vec<scene::Contained> {
        let whitted = RayTracer::new(Variant::Whitted);
        if self.variant != Variant::Caustics
            || self.settings.tracer.max_depth != whitted.settings.tracer.max_depth
        {
            return Vec::new();
        }
        vec![scene::Contained {
            id: whitted.id(),
            spans: vec!["eye", "resolve"],
        }]
    }

    fn render_contained(
        &mut self,
        frame: &mut Frame,
        id: &str,
        target: &Target,
    ) -> TechniqueResult<()> {
        let contained = self.contains().iter().any(|c| c.id == id);
        match (&self.tracer, contained) {
            (Some(tracer), true) => {
                tracer.resolve_eye_only(frame, target);
                Ok(())
            }
            (None, _) => Err(not_prepared(self)),
            (Some(_), false) => Err(scene::TechniqueError::Unsupported(format!(
                "{} contains no variant {id}",
                self.id()
            ))),
        }
    }

    /// Every scene the marcher can hold: at most [`MAX_VOLUMES`] volumes.
    fn supports(&self, scene: &Scene) -> bool {
        crate::tracer::marched_volumes(scene) <= MAX_VOLUMES
    }

    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        frame.gpu.require(self.required_features())?;
        self.tracer = Some(GpuTracer::new(
            frame.gpu,
            &scene.scene,
            scene.time(),
            self.settings.tracer,
            match self.variant {
                Variant::RayQuery => Traversal::RayQuery,
                _ => Traversal::Bvh,
            },
        )?);
        Ok(())
    }

    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let Some(tracer) = self.tracer.as_mut() else {
            return Err(not_prepared(self));
        };
        tracer.record(frame, &scene.scene, view, target)
    }
}

/// Every variant, fresh.
pub fn variants() -> Vec<Box<dyn Technique>> {
    vec![
        Box::new(RayTracer::new(Variant::Whitted)),
        Box::new(RayTracer::new(Variant::Caustics)),
        Box::new(RayTracer::new(Variant::RayQuery)),
    ]
}
