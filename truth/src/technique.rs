//! The ground truth as a technique (`reference`): renders on the CPU with
//! [`crate::reference::render`] and uploads the image, so the harness can list, time and
//! render it like any other technique.

use crate::reference::{self, ReferenceOptions};
use gpu::Target;
use scene::Settings as _;
use scene::foundation::upload_image;
use scene::technique::{Declared, set_checked};
use scene::{Frame, GpuScene, Param, Scene, Technique, TechniqueResult, Timing, View};

/// The reference's parameters, declared once.
impl scene::Settings for ReferenceOptions {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new("max_depth", (0.0, 64.0), "specular bounces followed", |s| {
            Some(&mut s.max_depth)
        }),
        Declared::new(
            "photons",
            (0.0, 1e9),
            "caustic photons per frame (0: no caustics)",
            |s| Some(&mut s.photons),
        ),
    ];
}

/// The ground truth as a technique: renders on the CPU and uploads the image.
pub struct ReferenceTechnique {
    pub options: ReferenceOptions,
}

impl Default for ReferenceTechnique {
    fn default() -> Self {
        Self {
            options: ReferenceOptions::default(),
        }
    }
}

impl Technique for ReferenceTechnique {
    fn id(&self) -> String {
        "reference".into()
    }
    fn description(&self) -> String {
        "CPU ground truth: Whitted specular chains split by Fresnel + light-traced caustics".into()
    }
    fn params(&self) -> Vec<Param> {
        self.options.params()
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id(), &mut self.options, name, value)
    }
    fn supports(&self, _scene: &Scene) -> bool {
        true
    }
    fn timing(&self) -> Timing {
        Timing::Cpu
    }
    fn orthographic_camera(&self) -> bool {
        true
    }
    fn prepare(&mut self, _frame: &mut Frame, _scene: &GpuScene) -> TechniqueResult<()> {
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let image = reference::render(
            &scene.scene,
            &view.camera,
            view.time,
            view.width,
            view.height,
            &self.options,
        )
        .image;
        upload_image(frame.gpu, target, &image.pixels);
        Ok(())
    }
}
