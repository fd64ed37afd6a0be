//! The distance-impostor techniques: one [`Impostor`] type configured as each variant.
//!
//! Per specular object the technique keeps an environment impostor: a cube map taken from the
//! object's centre by the shared raster pass (rgb = radiance, alpha = distance from the
//! centre; `scene::techniques::render_environment`). It is regenerated only when the object
//! has moved farther than `regen_threshold` from the map's reference point (0: every frame),
//! inside a "regenerate" timer span. In the split layout the distances are copied into a
//! one-channel `R16Float` cube beside the radiance (paper section 6). For double refraction
//! each glass object also gets a refractor map (outward normal + distance of its own surface
//! from its centre), made once in `prepare`: objects only translate, so it never changes.
//! With caustics, each frame also renders a caustic map per light and object, splats its
//! photons into a grid indexed by direction from the reference point (compute, atomics) and
//! adds the resulting caustic radiance to the diffuse surfaces (README.md, "Caustics").

use crate::hit::Method;
use glam::Vec3;
use gpu::cube::{CubeTarget, cube_face_view_proj};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Target};
use scene::technique::check_param;
use scene::{
    BACKGROUND_DISTANCE, Frame, GpuScene, Material, ObjectFilter, Param, RasterTarget, Scene,
    Technique, TechniqueResult, View,
};

/// WGSL of `Hit()` (needs the gpu prelude before it).
pub const HIT_WGSL: &str = include_str!("shaders/hit.wgsl");
const LOCALIZED_WGSL: &str = include_str!("shaders/localized.wgsl");
const SPLIT_WGSL: &str = include_str!("shaders/split.wgsl");
const CAUSTIC_WGSL: &str = include_str!("shaders/caustic.wgsl");
const SPLAT_WGSL: &str = include_str!("shaders/splat.wgsl");
/// Format of the caustic map's two targets (photon landing point, photon power).
const PHOTON_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

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

/// Parameters of an [`Impostor`] (all settable by name through [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub mode: Mode,
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
    /// Caustic maps from the lights, splatted onto the diffuse surfaces (section 5).
    pub caustics: bool,
    /// Caustic map size C (C x C photons per light and object).
    pub caustic_resolution: u32,
    /// Face size of the photon accumulation grid (indexed like the environment impostor).
    pub caustic_grid: u32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            mode: Mode::Localized,
            method: Method::FalsePosition,
            iterations: 4,
            resolution: 256,
            regen_threshold: 0.0,
            split: false,
            refractor_iterations: 2,
            caustics: false,
            caustic_resolution: 128,
            caustic_grid: 64,
        }
    }
}

/// A distance-impostor technique variant.
pub struct Impostor {
    id: String,
    description: String,
    pub settings: Settings,
    state: Option<State>,
}

struct State {
    caustic: Option<CausticPipelines>,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    split_pipeline: wgpu::RenderPipeline,
    split_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    maps: Vec<ObjectMaps>,
}

/// Pipelines and layouts of the caustic passes.
struct CausticPipelines {
    map_pipeline: wgpu::RenderPipeline,
    apply_pipeline: wgpu::RenderPipeline,
    splat_pipeline: wgpu::ComputePipeline,
    group3_layout: wgpu::BindGroupLayout,
    splat_layout: wgpu::BindGroupLayout,
}

/// One object's caustic resources: the caustic map's targets and the accumulation grid.
struct CausticMaps {
    landing: wgpu::Texture,
    power: wgpu::Texture,
    depth: wgpu::Texture,
    grid: wgpu::Buffer,
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
    refractor: Option<(CubeTarget, Vec3)>,
    caustics: Option<CausticMaps>,
    /// Reference point of `env` (the object's centre when the map was last rendered).
    reference: Option<Vec3>,
    /// How many times `env` was (re)generated (for tests of `regen_threshold`).
    regenerations: u32,
}

impl Impostor {
    pub fn new(id: &str, description: &str, settings: Settings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            settings,
            state: None,
        }
    }

    /// How many times the environment impostors have been (re)generated since `prepare`.
    pub fn regenerations(&self) -> u32 {
        self.state.as_ref().map_or(0, |s| {
            s.maps.iter().map(|m| m.regenerations).max().unwrap_or(0)
        })
    }

    fn uses_distance(&self) -> bool {
        self.settings.mode != Mode::Classic
    }
}

/// Every variant of this crate, with the ids the harness lists.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let mut v: Vec<Box<dyn Technique>> = Vec::new();
    let s = Settings::default();
    v.push(Box::new(Impostor::new(
        "impostors/classic",
        "classic environment map (direction-only lookup) on the impostor's own maps and regeneration",
        Settings { mode: Mode::Classic, iterations: 0, ..s.clone() },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/initial-guess",
        "distance impostor, perpendicular + planar guesses only (eqs. 2, 4), no iteration",
        Settings {
            iterations: 0,
            ..s.clone()
        },
    )));
    for n in 1..=8 {
        v.push(Box::new(Impostor::new(
            &format!("impostors/secant-{n}"),
            &format!("distance impostor, {n} secant iterations (eq. 6, previous approximation as partner)"),
            Settings { method: Method::Secant, iterations: n, ..s.clone() },
        )));
    }
    for n in 1..=8 {
        v.push(Box::new(Impostor::new(
            &format!("impostors/false-position-{n}"),
            &format!("distance impostor, {n} false-position iterations (the paper's Hit listing)"),
            Settings {
                method: Method::FalsePosition,
                iterations: n,
                ..s.clone()
            },
        )));
    }
    v.push(Box::new(Impostor::new(
        "impostors/false-position-4-split",
        "false position, 4 iterations, distances in a separate R16Float cube (paper section 6)",
        Settings {
            iterations: 4,
            split: true,
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/double-refraction",
        "glass: Hit() in a refractor map (normal + distance), refraction out, then Hit() in the \
         environment impostor (section 4); false position, 4 iterations",
        Settings {
            mode: Mode::DoubleRefraction,
            iterations: 4,
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/caustics",
        "double-refraction plus caustics: photons from the lights through the object, landing \
         points by Hit(), splatted by direction from the reference point (section 5)",
        Settings {
            mode: Mode::DoubleRefraction,
            iterations: 4,
            caustics: true,
            ..s
        },
    )));
    v
}

fn param(
    name: &'static str,
    default: f64,
    min: f64,
    max: f64,
    integer: bool,
    help: &'static str,
) -> Param {
    Param {
        name,
        default,
        min,
        max,
        integer,
        help,
    }
}

impl Technique for Impostor {
    fn id(&self) -> String {
        self.id.clone()
    }
    fn description(&self) -> String {
        self.description.clone()
    }
    fn params(&self) -> Vec<Param> {
        let s = &self.settings;
        let mut p = vec![
            param(
                "resolution",
                s.resolution as f64,
                4.0,
                4096.0,
                true,
                "cube map face size (texels)",
            ),
            param(
                "regen_threshold",
                s.regen_threshold as f64,
                0.0,
                1000.0,
                false,
                "metres the object may move from the map's reference point before the map is \
                 regenerated (0: every frame)",
            ),
        ];
        if self.uses_distance() {
            p.push(param(
                "iterations",
                s.iterations as f64,
                0.0,
                64.0,
                true,
                "Hit() refinement steps after the two initial guesses",
            ));
            p.push(param(
                "split",
                s.split as u32 as f64,
                0.0,
                1.0,
                true,
                "1: distances in a separate R16Float cube; 0: in the radiance map's alpha",
            ));
        }
        if s.caustics {
            p.push(param(
                "caustic_resolution",
                s.caustic_resolution as f64,
                4.0,
                2048.0,
                true,
                "caustic map size (photons per side, per light and object)",
            ));
            p.push(param(
                "caustic_grid",
                s.caustic_grid as f64,
                4.0,
                1024.0,
                true,
                "face size of the photon accumulation grid",
            ));
        }
        if s.mode == Mode::DoubleRefraction {
            p.push(param(
                "refractor_iterations",
                s.refractor_iterations as f64,
                0.0,
                64.0,
                true,
                "Hit() refinement steps inside the refractor map",
            ));
        }
        p
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id, &self.params(), name, value)?;
        let s = &mut self.settings;
        match name {
            "resolution" => s.resolution = value as u32,
            "regen_threshold" => s.regen_threshold = value as f32,
            "iterations" => s.iterations = value as u32,
            "split" => s.split = value != 0.0,
            "refractor_iterations" => s.refractor_iterations = value as u32,
            "caustic_resolution" => s.caustic_resolution = value as u32,
            "caustic_grid" => s.caustic_grid = value as u32,
            _ => unreachable!("check_param accepted an undeclared parameter"),
        }
        // Maps and pipelines depend on the settings: prepare() rebuilds them.
        self.state = None;
        Ok(())
    }
    fn supports(&self, scene: &Scene) -> bool {
        if self.settings.caustics && scene.lights.is_empty() {
            return false;
        }
        match self.settings.mode {
            Mode::DoubleRefraction => scene
                .objects
                .iter()
                .any(|o| matches!(o.material, Material::Glass { .. })),
            _ => scene.objects.iter().any(|o| o.material.is_specular()),
        }
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let layout = impostor_layout(ctx);
        let sampler = ctx.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("impostor sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let source = format!("{}\n{}\n{}", scene::SCENE_WGSL, HIT_WGSL, LOCALIZED_WGSL);
        let module = gpu::shader_with_prelude(ctx, &self.id, &source);
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        let pipeline = scene::scene_pipeline(
            ctx,
            &self.id,
            &pipeline_layout,
            &module,
            "localized_fs",
            gpu::HDR_FORMAT,
        );
        let split_layout = single_texture_layout(ctx);
        let split_pipeline = gpu::fullscreen::pipeline(
            ctx,
            "impostor split copy",
            SPLIT_WGSL,
            &[Some(&split_layout)],
            SPLIT_DISTANCE_FORMAT,
            None,
        );

        let mut maps = Vec::new();
        for (object, o) in scene.scene.objects.iter().enumerate() {
            if !o.material.is_specular() {
                continue;
            }
            let res = self.settings.resolution;
            let env = CubeTarget::new(ctx, res, IMPOSTOR_FORMAT, "distance impostor")?;
            let split = (self.settings.split && self.uses_distance())
                .then(|| split_distance(ctx, &env, &split_layout))
                .transpose()?;
            let refractor = if self.settings.mode == Mode::DoubleRefraction
                && matches!(o.material, Material::Glass { .. })
            {
                let cube = CubeTarget::new(ctx, res, IMPOSTOR_FORMAT, "refractor map")?;
                let center = o.center_at(scene.time());
                let refractor_pipeline = scene::scene_pipeline(
                    ctx,
                    "refractor map",
                    &scene.pipeline_layout_with(ctx, &[]),
                    &module,
                    "refractor_map_fs",
                    IMPOSTOR_FORMAT,
                );
                render_refractor_map(frame, scene, &refractor_pipeline, &cube, object, center);
                Some((cube, center))
            } else {
                None
            };
            let caustics = self.settings.caustics.then(|| {
                caustic_maps(
                    ctx,
                    self.settings.caustic_resolution,
                    self.settings.caustic_grid,
                )
            });
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
        let caustic = self
            .settings
            .caustics
            .then(|| caustic_pipelines(ctx, scene, &layout));
        self.state = Some(State {
            caustic,
            layout,
            pipeline,
            split_pipeline,
            split_layout,
            sampler,
            maps,
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
        if self.state.is_none() {
            self.prepare(frame, scene)?;
        }
        let settings = self.settings.clone();
        let state = self.state.as_mut().expect("prepared above");

        // Regenerate the environment impostors of objects that moved too far.
        let time = scene.time();
        let stale: Vec<usize> = (0..state.maps.len())
            .filter(|&i| {
                let m = &state.maps[i];
                let center = scene.scene.objects[m.object].center_at(time);
                match m.reference {
                    None => true,
                    Some(r) => {
                        settings.regen_threshold <= 0.0
                            || r.distance(center) > settings.regen_threshold
                    }
                }
            })
            .collect();
        if !stale.is_empty() {
            frame.timer.begin(frame.encoder, "regenerate");
            for &i in &stale {
                let m = &mut state.maps[i];
                scene::techniques::render_environment(frame, scene, &m.env, m.object);
                if let Some(split) = &m.split {
                    copy_distances(frame, &state.split_pipeline, split);
                }
                m.reference = Some(scene.scene.objects[m.object].center_at(time));
                m.regenerations += 1;
            }
            frame.timer.end(frame.encoder, "regenerate");
        }
        let _ = &state.split_layout;
        let groups = impostor_groups(frame.gpu, state, &settings);

        let ctx = frame.gpu;
        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget {
            color: &target.color_view,
            depth: &target.depth_view,
            format: gpu::HDR_FORMAT,
            clear: true,
        };
        let specular: Vec<usize> = state.maps.iter().map(|m| m.object).collect();
        // Caustics: photons from each light through each object, accumulated per object.
        let caustic_groups = match &state.caustic {
            Some(pipelines) => {
                frame.timer.begin(frame.encoder, "caustics");
                let g = render_caustics(frame, scene, state, pipelines, &groups, &settings);
                frame.timer.end(frame.encoder, "caustics");
                g
            }
            None => Vec::new(),
        };
        scene.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::Except(specular.clone()),
            false,
        );
        if let Some(pipelines) = &state.caustic {
            let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
            let mut pass = scene::begin_scene_pass(
                frame.encoder,
                &RasterTarget {
                    clear: false,
                    ..main
                },
                scene.scene.background,
                "caustics apply",
            );
            pass.set_pipeline(&pipelines.apply_pipeline);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            for (group, caustic_group) in groups.iter().zip(&caustic_groups) {
                pass.set_bind_group(2, group, &[]);
                pass.set_bind_group(3, caustic_group, &[]);
                scene.draw_objects(&mut pass, &ObjectFilter::Except(specular.clone()));
            }
        }

        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        // The specular objects' pass, timed on its own as "lookup" (pass timestamps).
        let mut pass = frame
            .encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&self.id),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: frame.timer.render_pass("lookup"),
                occlusion_query_set: None,
                multiview_mask: None,
            });
        pass.set_pipeline(&state.pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        for (m, group) in state.maps.iter().zip(&groups) {
            pass.set_bind_group(2, group, &[]);
            scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![m.object]));
        }
        Ok(())
    }
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
    _pad: [u32; 3],
}

/// Layout of `@group(2)` in localized.wgsl.
pub fn impostor_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    let cube = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::Cube,
            multisampled: false,
        },
        count: None,
    };
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("distance impostor"),
            entries: &[
                cube(0),
                cube(1),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                cube(4),
            ],
        })
}

fn single_texture_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("packed face"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        })
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
        .map(|face| {
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("packed face"),
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(face),
                }],
            })
        })
        .collect();
    Ok(SplitDistance {
        distances,
        copy_groups,
    })
}

fn copy_distances(frame: &mut Frame, pipeline: &wgpu::RenderPipeline, split: &SplitDistance) {
    for face in 0..6 {
        let mut pass = frame
            .encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("impostor split copy"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &split.distances.face_views[face],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
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
    for face in 0..6 {
        let view_proj = cube_face_view_proj(face, center, 1e-3, 2.0 * BACKGROUND_DISTANCE);
        let camera = scene.camera_bind_group(frame.gpu, view_proj, center);
        let target = RasterTarget {
            color: &cube.face_views[face],
            depth: &cube.depth_face_views[face],
            format: cube.format,
            clear: true,
        };
        let mut pass = scene::begin_scene_pass(frame.encoder, &target, Vec3::ZERO, "refractor map");
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![object]));
    }
}

/// The `@group(2)` bind group of each object's maps for this frame.
fn impostor_groups(ctx: &Context, state: &State, settings: &Settings) -> Vec<wgpu::BindGroup> {
    state
        .maps
        .iter()
        .map(|m| {
            let reference = m.reference.expect("regenerated before use");
            let distance_view = m.split.as_ref().map_or(&m.env.cube_view, |s| &s.distances.cube_view);
            let (refractor_view, refractor_center) = m
                .refractor
                .as_ref()
                .map_or((&m.env.cube_view, reference), |(c, center)| {
                    (&c.cube_view, *center)
                });
            let uniform = ParamsGpu {
                reference: reference.extend(0.0).to_array(),
                refractor_center: refractor_center.extend(0.0).to_array(),
                mode: settings.mode.wgsl_id(),
                method: settings.method.wgsl_id(),
                iterations: settings.iterations,
                distance_channel: if m.split.is_some() { 0 } else { 3 },
                refractor_iterations: settings.refractor_iterations,
                _pad: [0; 3],
            };
            let buffer = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("impostor params"),
                    contents: bytemuck::bytes_of(&uniform),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("impostor"),
                layout: &state.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&m.env.cube_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(distance_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&state.sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::TextureView(refractor_view),
                    },
                ],
            })
        })
        .collect()
}

/// The uniform block `CausticParams` of caustic.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CausticGpu {
    light: [f32; 4],
    intensity: [f32; 4],
    axis: [f32; 4],
    grid: u32,
    scale: f32,
    size: u32,
    _pad: u32,
}

/// The uniform block `SplatParams` of splat.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SplatGpu {
    reference: [f32; 4],
    grid: u32,
    scale: f32,
    size: u32,
    _pad: u32,
}

fn caustic_maps(ctx: &Context, size: u32, grid: u32) -> CausticMaps {
    let target = |label| {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PHOTON_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    CausticMaps {
        landing: target("caustic map: landing points"),
        power: target("caustic map: photon power"),
        depth: gpu::depth_texture(ctx, size, size, 1, "caustic map depth"),
        grid: ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("caustic grid"),
            size: 6 * 3 * 4 * (grid as u64) * (grid as u64),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
    }
}

fn caustic_pipelines(
    ctx: &Context,
    scene: &GpuScene,
    impostor_layout: &wgpu::BindGroupLayout,
) -> CausticPipelines {
    let device = &ctx.device;
    let frag = wgpu::ShaderStages::FRAGMENT;
    let uniform = |binding, visibility| wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let storage = |binding, visibility, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let group3_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("caustics"),
        entries: &[uniform(0, frag), storage(1, frag, true)],
    });
    let source = format!(
        "{}\n{}\n{}\n{}",
        scene::SCENE_WGSL,
        HIT_WGSL,
        LOCALIZED_WGSL,
        CAUSTIC_WGSL
    );
    let module = gpu::shader_with_prelude(ctx, "impostors/caustics", &source);
    let layout = scene.pipeline_layout_with(ctx, &[impostor_layout, &group3_layout]);
    let pipeline = |label: &str,
                    entry: &str,
                    targets: &[Option<wgpu::ColorTargetState>],
                    depth_write: bool,
                    compare| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("scene_vs"),
                compilation_options: Default::default(),
                buffers: &[Some(gpu::Vertex::layout())],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets,
            }),
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: gpu::DEPTH_FORMAT,
                depth_write_enabled: Some(depth_write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        })
    };
    let photon_target = Some(wgpu::ColorTargetState {
        format: PHOTON_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    });
    let map_pipeline = pipeline(
        "caustic map",
        "caustic_map_fs",
        &[photon_target.clone(), photon_target],
        true,
        wgpu::CompareFunction::Less,
    );
    // Adds the caustic radiance to what the raster pass drew; alpha (distance) is kept.
    let add = wgpu::BlendState {
        color: wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        },
        alpha: wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        },
    };
    let apply_pipeline = pipeline(
        "caustics apply",
        "caustic_apply_fs",
        &[Some(wgpu::ColorTargetState {
            format: gpu::HDR_FORMAT,
            blend: Some(add),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        false,
        wgpu::CompareFunction::LessEqual,
    );

    let comp = wgpu::ShaderStages::COMPUTE;
    let photon_texture = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: comp,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let splat_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("caustic splat"),
        entries: &[
            photon_texture(0),
            photon_texture(1),
            storage(2, comp, false),
            uniform(3, comp),
        ],
    });
    let splat_module = gpu::shader_with_prelude(ctx, "caustic splat", SPLAT_WGSL);
    let splat_pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("caustic splat"),
        layout: Some(
            &device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("caustic splat"),
                bind_group_layouts: &[Some(&splat_layout)],
                immediate_size: 0,
            }),
        ),
        module: &splat_module,
        entry_point: Some("splat_main"),
        compilation_options: Default::default(),
        cache: None,
    });
    CausticPipelines {
        map_pipeline,
        apply_pipeline,
        splat_pipeline,
        group3_layout,
        splat_layout,
    }
}

/// Renders each object's caustic maps (one per light), splats the photons into its grid and
/// returns the `@group(3)` bind group of each object for the apply pass.
fn render_caustics(
    frame: &mut Frame,
    scene: &GpuScene,
    state: &State,
    p: &CausticPipelines,
    groups: &[wgpu::BindGroup],
    settings: &Settings,
) -> Vec<wgpu::BindGroup> {
    let ctx = frame.gpu;
    let time = scene.time();
    let size = settings.caustic_resolution;
    let mut apply_groups = Vec::new();
    for (m, group) in state.maps.iter().zip(groups) {
        let maps = m
            .caustics
            .as_ref()
            .expect("caustic maps are made in prepare");
        let o = &scene.scene.objects[m.object];
        let center = o.center_at(time);
        let radius = o.bounding_radius_at(time) * 1.05;
        // The cones from each light that hold the object; their total flux bounds any texel's
        // sum, which sets the fixed-point scale.
        let cones: Vec<_> = scene
            .scene
            .lights
            .iter()
            .filter_map(|light| {
                let to = center - light.position;
                let dist = to.length();
                (dist > radius).then(|| {
                    let half = (radius / dist).asin();
                    (light, to / dist, dist, half)
                })
            })
            .collect();
        let total: f32 = cones
            .iter()
            .map(|(l, _, _, half)| {
                l.intensity.max_element() * 2.0 * std::f32::consts::PI * (1.0 - half.cos())
            })
            .sum();
        let scale = if total > 0.0 { 1.5e9 / total } else { 1.0 };
        frame.encoder.clear_buffer(&maps.grid, 0, None);
        let reference = m.reference.expect("regenerated before use");
        let mut apply_group = None;
        for (light, axis, dist, half) in cones.iter().copied() {
            let up = if axis.y.abs() > 0.9 { Vec3::X } else { Vec3::Y };
            let view = glam::camera::rh::view::look_at_mat4(light.position, center, up);
            let proj = glam::camera::rh::proj::directx::perspective(
                2.0 * half,
                1.0,
                ((dist - radius) * 0.5).max(1e-3),
                dist + 2.0 * radius,
            );
            let camera = scene.camera_bind_group(ctx, proj * view, light.position);
            let pixel_area = (2.0 * half.tan() / size as f32).powi(2);
            let uniform = CausticGpu {
                light: light.position.extend(1.0).to_array(),
                intensity: light.intensity.extend(0.0).to_array(),
                axis: axis.extend(pixel_area).to_array(),
                grid: settings.caustic_grid,
                scale,
                size,
                _pad: 0,
            };
            let buffer = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("caustic params"),
                    contents: bytemuck::bytes_of(&uniform),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            let group3 = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("caustics"),
                layout: &p.group3_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: maps.grid.as_entire_binding(),
                    },
                ],
            });
            let landing_view = maps.landing.create_view(&Default::default());
            let power_view = maps.power.create_view(&Default::default());
            let depth_view = maps.depth.create_view(&Default::default());
            {
                let clear = |view| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let mut pass = frame
                    .encoder
                    .begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("caustic map"),
                        color_attachments: &[clear(&landing_view), clear(&power_view)],
                        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                            view: &depth_view,
                            depth_ops: Some(wgpu::Operations {
                                load: wgpu::LoadOp::Clear(1.0),
                                store: wgpu::StoreOp::Store,
                            }),
                            stencil_ops: None,
                        }),
                        timestamp_writes: None,
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                pass.set_pipeline(&p.map_pipeline);
                pass.set_bind_group(0, &camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, group, &[]);
                pass.set_bind_group(3, &group3, &[]);
                scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![m.object]));
            }
            let splat_uniform = SplatGpu {
                reference: reference.extend(0.0).to_array(),
                grid: settings.caustic_grid,
                scale,
                size,
                _pad: 0,
            };
            let splat_buffer = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("splat params"),
                    contents: bytemuck::bytes_of(&splat_uniform),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            let splat_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("caustic splat"),
                layout: &p.splat_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&landing_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&power_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: maps.grid.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: splat_buffer.as_entire_binding(),
                    },
                ],
            });
            {
                let mut pass = frame
                    .encoder
                    .begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("caustic splat"),
                        timestamp_writes: None,
                    });
                pass.set_pipeline(&p.splat_pipeline);
                pass.set_bind_group(0, &splat_group, &[]);
                pass.dispatch_workgroups(size.div_ceil(8), size.div_ceil(8), 1);
            }
            apply_group.get_or_insert(group3);
        }
        // No light outside the object: an empty grid (cleared above) adds nothing.
        let apply_group = apply_group.unwrap_or_else(|| {
            let uniform = CausticGpu {
                light: [0.0; 4],
                intensity: [0.0; 4],
                axis: [0.0, 0.0, 1.0, 0.0],
                grid: settings.caustic_grid,
                scale: 1.0,
                size,
                _pad: 0,
            };
            let buffer = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("caustic params"),
                    contents: bytemuck::bytes_of(&uniform),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("caustics"),
                layout: &p.group3_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: maps.grid.as_entire_binding(),
                    },
                ],
            })
        });
        apply_groups.push(apply_group);
    }
    apply_groups
}
