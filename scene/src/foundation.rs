//! The foundation's techniques: `raster` (the shared raster pass with special objects drawn
//! as plain diffuse) and `envmap/classic` (special objects reflect/refract a classic
//! environment cube map taken from the object's centre: the baseline every later technique
//! must beat). They live here, not in a technique crate, so technique crates (which depend on
//! `gpu` and `scene` only) can reuse the classic map. The ground truth as a technique,
//! `reference`, is the `truth` crate's (`truth::techniques()`).

use crate::technique::{check_param, not_prepared};
use crate::{
    Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene, Technique, TechniqueResult, View,
};
use gpu::cube::CubeTarget;
use gpu::wgpu;
use gpu::{Context, Target, bind};

/// The foundation's family: the baselines `raster` and `envmap/classic`, which live in
/// `scene` (their ids carry no family name).
pub const FAMILY: crate::Family = crate::Family {
    name: "foundation",
    techniques,
    image_checks,
};

/// The foundation's variants, fresh: `raster`, `envmap/classic`.
pub fn techniques() -> Vec<Box<dyn Technique>> {
    vec![
        Box::new(RasterTechnique),
        Box::new(ClassicEnvMap::default()),
    ]
}

/// The foundation's image checks (run by the tests crate against the reference).
pub fn image_checks() -> Vec<crate::ImageCheck> {
    vec![
        crate::ImageCheck::new(
            "raster",
            "cornell-sphere:material=diffuse",
            0.002,
            0.005,
            "nothing specular: the raster pass computes the reference's model and differs \
             only at shadow edges (shadow map vs shadow ray); measured FLIP 0.0006, RMSE \
             0.0026 (64 x 64, worst of t = 0, 1, 2)",
        ),
        crate::ImageCheck::new(
            "envmap/classic",
            "cornell-sphere:material=mirror",
            0.09,
            0.46,
            "a baseline: the direction-only lookup misplaces the room in the mirror, and \
             the reference's light-traced caustics from the mirror are in no GPU \
             technique; measured FLIP 0.071, RMSE 0.361 (worst of t = 0, 1, 2)",
        ),
    ]
}

fn main_target(target: &Target) -> RasterTarget<'_> {
    RasterTarget::of(target, true)
}

/// Writes linear RGBA pixels into the target's colour texture.
pub fn upload_image(ctx: &Context, target: &Target, pixels: &[[f32; 4]]) {
    ctx.queue.write_texture(
        target.color.as_image_copy(),
        bytemuck::cast_slice(pixels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(16 * target.width),
            rows_per_image: Some(target.height),
        },
        target.color.size(),
    );
}

/// The shared raster pass alone: every object diffuse, specular ones as plain grey.
#[derive(Default)]
pub struct RasterTechnique;

/// The point the raster pass turns surfaces toward (`geometric_facing_normal`): a pinhole's
/// eye; for an orthographic camera, whose rays are parallel, a point a million view heights
/// back along its view direction, from which every surface faces as it faces those rays (to
/// within a microradian). The diffuse model needs nothing else of the view.
pub fn viewpoint(camera: &crate::Camera) -> glam::Vec3 {
    match camera.orthographic {
        None => camera.eye,
        Some(half_height) => camera.eye - camera.basis().0 * (2e6 * half_height.max(1.0)),
    }
}

impl Technique for RasterTechnique {
    fn id(&self) -> String {
        "raster".into()
    }
    fn description(&self) -> String {
        "shared raster pass (diffuse model + shadow maps); specular objects as grey diffuse".into()
    }
    fn supports(&self, _scene: &Scene) -> bool {
        true
    }
    /// Diffuse shading needs of the view only which side of a surface it sees, and the
    /// rasterizer projects either kind ([`viewpoint`]).
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
        let view_proj = view.camera.view_proj(view.width, view.height);
        scene.raster(
            frame,
            &main_target(target),
            view_proj,
            viewpoint(&view.camera),
            &ObjectFilter::All,
            true,
        );
        Ok(())
    }
}

/// Classic environment mapping: one cube map per specular object from its centre,
/// regenerated every frame (objects move), looked up by direction only.
pub struct ClassicEnvMap {
    pub resolution: u32,
    maps: Vec<EnvMap>,
    pipeline: Option<wgpu::RenderPipeline>,
}

/// One specular object's environment cube map and the bind group that samples it.
pub struct EnvMap {
    pub object: usize,
    pub cube: CubeTarget,
    pub bind_group: wgpu::BindGroup,
}

impl Default for ClassicEnvMap {
    fn default() -> Self {
        Self {
            resolution: 256,
            maps: Vec::new(),
            pipeline: None,
        }
    }
}

/// Layout of `@group(2)` in envmap.wgsl: a cube texture and a filtering sampler.
pub fn envmap_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::FRAGMENT;
    bind::layout(
        ctx,
        "environment map",
        stages,
        &[bind::texture_cube(), bind::sampler()],
    )
}

/// Renders the diffuse scene (without `object`) into the six faces of `cube` from `object`'s
/// centre at the scene's current time: the localized (radiance + distance) environment of
/// the object. Alpha holds the per-fragment distance from the centre.
pub fn render_environment(frame: &mut Frame, scene: &GpuScene, cube: &CubeTarget, object: usize) {
    let center = scene.scene.objects[object].center_at(scene.time());
    scene.raster_cube(
        frame,
        cube,
        center,
        &ObjectFilter::Except(vec![object]),
        false,
    );
}

impl Technique for ClassicEnvMap {
    fn id(&self) -> String {
        "envmap/classic".into()
    }
    fn description(&self) -> String {
        "classic environment map from each specular object's centre (direction-only lookup)".into()
    }
    fn params(&self) -> Vec<Param> {
        vec![Param {
            name: "resolution",
            default: self.resolution as f64,
            min: 4.0,
            max: 4096.0,
            integer: true,
            help: "cube map face size (texels)",
        }]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id(), &self.params(), name, value)?;
        self.resolution = value as u32;
        Ok(())
    }
    fn supports(&self, scene: &Scene) -> bool {
        scene.objects.iter().any(|o| o.material.is_specular())
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let layout = envmap_layout(ctx);
        self.maps.clear();
        let specular = scene.scene.specular_objects().len();
        let format = wgpu::TextureFormat::Rgba16Float;
        crate::technique::check_map_budget(
            &self.id(),
            specular,
            CubeTarget::bytes(self.resolution, format),
            "resolution",
        )?;
        for (object, o) in scene.scene.objects.iter().enumerate() {
            if !o.material.is_specular() {
                continue;
            }
            let cube = CubeTarget::new(ctx, self.resolution, format, "classic environment map")?;
            let bind_group = bind::group(
                ctx,
                "environment map",
                &layout,
                &[
                    bind::view(&cube.cube_view),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                ],
            );
            self.maps.push(EnvMap {
                object,
                cube,
                bind_group,
            });
        }
        let module = crate::shader(ctx, "envmap/classic", include_str!("shaders/envmap.wgsl"));
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        self.pipeline = Some(crate::scene_pipeline(
            ctx,
            "envmap/classic",
            &pipeline_layout,
            &module,
            "envmap_fs",
            gpu::HDR_FORMAT,
        ));
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        frame.span("regenerate", |frame| {
            for map in &self.maps {
                render_environment(frame, scene, &map.cube, map.object);
            }
        });

        let view_proj = view.camera.view_proj(view.width, view.height);
        let specular: Vec<usize> = self.maps.iter().map(|m| m.object).collect();
        scene.raster(
            frame,
            &main_target(target),
            view_proj,
            view.camera.eye,
            &ObjectFilter::Except(specular),
            false,
        );
        let camera = scene.camera_bind_group(frame.gpu, view_proj, view.camera.eye);
        let pipeline = self.pipeline.as_ref().ok_or_else(|| not_prepared(self))?;
        let mut pass = crate::begin_scene_pass(
            frame.encoder,
            &RasterTarget {
                clear: false,
                ..main_target(target)
            },
            scene.scene.background,
            "envmap/classic",
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        for map in &self.maps {
            pass.set_bind_group(2, &map.bind_group, &[]);
            scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![map.object]));
        }
        Ok(())
    }
}
