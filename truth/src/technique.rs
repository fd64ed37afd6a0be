//! The ground truth as a technique (`reference`): renders on the CPU with
//! [`crate::reference::render`] and uploads the image, so the harness can list, time and
//! render it like any other technique.

use crate::reference::{self, ReferenceOptions};
use gpu::Target;
use scene::foundation::upload_image;
use scene::technique::check_param;
use scene::{Frame, GpuScene, Param, Scene, Technique, TechniqueResult, Timing, View};

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
        vec![
            Param {
                name: "max_depth",
                default: 8.0,
                min: 0.0,
                max: 64.0,
                integer: true,
                help: "specular bounces followed",
            },
            Param {
                name: "photons",
                default: ReferenceOptions::default().photons as f64,
                min: 0.0,
                max: 1e9,
                integer: true,
                help: "caustic photons per frame (0: no caustics)",
            },
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id(), &self.params(), name, value)?;
        match name {
            "max_depth" => self.options.max_depth = value as u32,
            _ => self.options.photons = value as u64,
        }
        Ok(())
    }
    fn supports(&self, _scene: &Scene) -> bool {
        true
    }
    fn timing(&self) -> Timing {
        Timing::Cpu
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
