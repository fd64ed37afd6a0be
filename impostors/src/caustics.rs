//! Caustics with distance impostors (paper section 5): caustic maps from the lights, photon
//! landing points by `Hit()`, and two ways of turning them into caustic radiance.
//!
//! - [`CausticPath::LightMap`], the paper's: each photon stores the light-map address of its
//!   landing point (chart and atlas uv, through the *receiver cube* that plays the paper's
//!   uvmap); one Gaussian quad per caustic-map texel is drawn into the light-map atlas with
//!   additive blending (the vertex shader reads the caustic map, the paper's vertex texture
//!   fetch); the diffuse surfaces then add `albedo / pi * E` from their light map.
//! - [`CausticPath::Grid`], a modern alternative: a compute pass adds the photons with atomics
//!   into a per-face grid indexed by the landing point's direction from the reference point;
//!   surfaces the reference point sees read it back.
//!
//! Both also put the caustics into reflections and refractions (paper figure 11): the
//! localized lookup adds the caustic radiance of the surface the impostor shows.
//! Shaders: `caustic.wgsl`, `lightmap.wgsl`, `splat.wgsl` here; `chart.wgsl` and the quad
//! splat (`splat_quads.wgsl`) come from `scene::lightmap`.

use glam::Vec3;
use gpu::bind::UniformGroups;
use gpu::cube::CubeTarget;
use gpu::pass::{self, ADD_RGB_KEEP_ALPHA, CLEAR_BLACK, CLEAR_FAR, Load, color_target};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, GpuError, Uniform, bind};
use scene::lightmap::{ChartAtlas, QuadSplatter};
use scene::{Frame, GpuScene, Light, ObjectFilter, RasterTarget};

/// WGSL of the receivers' light-map charts: the chart and atlas uv under a fragment of a
/// diffuse object; the module `impostors::lightmap` ([`LIGHTMAP`]).
pub const LIGHTMAP_WGSL: &str = include_str!("shaders/lightmap.wgsl");
/// [`LIGHTMAP_WGSL`] as a module.
pub static LIGHTMAP: gpu::wgsl::Module = gpu::wgsl::Module::new(
    LIGHTMAP_WGSL,
    "impostors/src/shaders/lightmap.wgsl",
    &[&scene::lightmap::CHART, &scene::lightmap::RECEIVER],
);
/// WGSL of the caustic maps (paper section 5): photon tracing from the light
/// (`trace_photon`), what the caustic passes of both paths share, and the caustics the
/// localized lookups see, which it overrides (`caustic_radiance_at`: the light map's, or the
/// grid's with the definition `CAUSTIC_GRID`); the module `impostors::caustic` ([`CAUSTIC`]).
pub const CAUSTIC_WGSL: &str = include_str!("shaders/caustic.wgsl");
/// [`CAUSTIC_WGSL`] as a module.
pub static CAUSTIC: gpu::wgsl::Module = gpu::wgsl::Module::new(
    CAUSTIC_WGSL,
    "impostors/src/shaders/caustic.wgsl",
    &[&crate::localized::LOCALIZED, &LIGHTMAP],
);
/// The caustic passes' entry points (the caustic map, the receiver cube, the apply).
const CAUSTIC_PASSES_WGSL: &str = include_str!("shaders/caustic_passes.wgsl");
const SPLAT_WGSL: &str = include_str!("shaders/splat.wgsl");

/// Format of the caustic map's two targets (photon address, photon power).
const PHOTON_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Light-map atlas: power per texel, summed by blending in 32-bit float (16-bit float would
/// stop adding photons once a texel holds ~2000 of them: an 11-bit significand).
const LIGHT_MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Receiver cube: chart, object, 1 / texel area, cosine.
const RECEIVER_INFO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const RECEIVER_ALBEDO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// How photons become caustic radiance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CausticPath {
    /// The paper's: Gaussian quads blended into light maps addressed by chart and uv.
    LightMap,
    /// Compute scatter with atomics into a grid indexed by direction from the reference point.
    Grid,
}

/// Caustic parameters (the `caustic_*`, `lightmap_resolution`, `splat_radius` variant
/// parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct CausticSettings {
    /// How photons become caustic radiance (light maps or the direction grid).
    pub path: CausticPath,
    /// Caustic map size C: C x C photons per light and object.
    pub resolution: u32,
    /// Grid path: face size of the accumulation grid.
    pub grid: u32,
    /// Light-map path: atlas side in texels.
    pub lightmap_resolution: u32,
    /// Light-map path: radius of a photon's Gaussian quad in light-map texels (sigma = R / 2).
    pub splat_radius: f32,
    /// Reflections and refractions add the caustics they see (paper figure 11). Off by
    /// default: the reference has no caustics seen through specular chains, so turning it
    /// on adds error there (README.md, "Caustics").
    pub in_lookup: bool,
    /// Each photon leaves from a random point of its caustic-map pixel instead of the pixel
    /// centre (stratified jittered emission, `jittered_emission` in scene.wgsl): a regular
    /// lattice of photons shows as moire rings where the caustic spreads; jittered, as noise.
    pub jitter: bool,
    /// Light-map path: each photon's Gaussian widened to its lattice cell's footprint on the
    /// atlas (`scene::lightmap::Footprint`).
    pub footprint: bool,
}

impl CausticSettings {
    /// The default settings of `path` (128 x 128 photons, 64-texel grid faces, a 1024-texel
    /// atlas, splat radius 3 texels, caustics not seen in lookups).
    pub fn new(path: CausticPath) -> Self {
        Self {
            path,
            resolution: 128,
            grid: 64,
            lightmap_resolution: 1024,
            splat_radius: 3.0,
            in_lookup: false,
            jitter: false,
            footprint: true,
        }
    }
}

/// A shader of the caustic variants: `source`'s entry points with `impostors::caustic`
/// overriding the localized lookups' caustics for `path`.
pub fn caustic_shader(
    ctx: &Context,
    label: &str,
    source: &str,
    path: CausticPath,
) -> wgpu::ShaderModule {
    let grid = [("CAUSTIC_GRID", gpu::wgsl::Def::Bool(true))];
    let defs: &[_] = match path {
        CausticPath::LightMap => &[],
        CausticPath::Grid => &grid,
    };
    let modules = [&CAUSTIC];
    let shader = gpu::wgsl::Shader::new(label, source)
        .importing(&modules)
        .with_defs(defs)
        .overriding(&modules);
    scene::shader_of(ctx, shader)
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
    in_lookup: u32,
    lightmap: f32,
    jitter: u32,
    _pad: [u32; 2],
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

/// Pipelines, layouts and the shared light-map resources of one caustic variant.
pub struct Caustics {
    settings: CausticSettings,
    /// `@group(3)` of the caustic passes and of the localized pass.
    group3_layout: wgpu::BindGroupLayout,
    /// `@group(3)` of the receiver pass (charts and the uniform only).
    receiver_layout: wgpu::BindGroupLayout,
    /// Placeholder `@group(2)` of the receiver pass.
    empty_group: wgpu::BindGroup,
    map_pipeline: wgpu::RenderPipeline,
    apply_pipeline: wgpu::RenderPipeline,
    receiver_pipeline: wgpu::RenderPipeline,
    /// The localized pass with caustics in its lookups.
    pub localized_pipeline: wgpu::RenderPipeline,
    splat: Splatter,
    atlas: ChartAtlas,
    charts: wgpu::Buffer,
    chart_of: wgpu::Buffer,
    light_map: wgpu::Texture,
    light_map_view: wgpu::TextureView,
    /// The bind groups of each frame's passes, made once (see `gpu::bind::UniformGroups`):
    /// per generator, its receiver pass; per (generator, light), its caustic map's
    /// `@group(3)`; per generator, the `@group(3)` of a generator no light reaches, and its
    /// compute splat.
    receiver_groups: UniformGroups<CausticGpu>,
    caustic_groups: UniformGroups<CausticGpu>,
    unlit_groups: UniformGroups<CausticGpu>,
    splat_groups: UniformGroups<SplatGpu>,
}

enum Splatter {
    Compute {
        pipeline: wgpu::ComputePipeline,
        layout: wgpu::BindGroupLayout,
    },
    Quads(QuadSplatter),
}

/// One caustic generator's resources.
pub struct GeneratorMaps {
    address: wgpu::Texture,
    power: wgpu::Texture,
    /// Views of the caustic map's targets and of the receiver cubes as arrays, made once.
    views: GeneratorViews,
    /// Grid path accumulation (4 bytes on the light-map path).
    grid: wgpu::Buffer,
    receiver_info: CubeTarget,
    receiver_albedo: CubeTarget,
}

struct GeneratorViews {
    address: wgpu::TextureView,
    power: wgpu::TextureView,
    depth: wgpu::TextureView,
    receiver_info: wgpu::TextureView,
    receiver_albedo: wgpu::TextureView,
}

impl GeneratorMaps {
    /// The caustic map's address target (grid: landing point; light map: uv, chart; w = 1
    /// for a photon) and power target, as last rendered (for the last light).
    pub fn caustic_map(&self) -> (&wgpu::Texture, &wgpu::Texture) {
        (&self.address, &self.power)
    }
}

impl Caustics {
    /// Pipelines for `settings.path`; `impostor_layout` is the localized pass's `@group(2)`.
    pub fn new(
        ctx: &Context,
        scene: &GpuScene,
        impostor_layout: &wgpu::BindGroupLayout,
        settings: &CausticSettings,
    ) -> Result<Self, GpuError> {
        if settings.path == CausticPath::LightMap {
            // Additive blending into 32-bit float texels.
            ctx.require(wgpu::Features::FLOAT32_BLENDABLE)?;
        }
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layers = bind::texture(wgpu::TextureViewDimension::D2Array, false);
        let group3_layout = bind::layout(
            ctx,
            "caustics",
            frag,
            &[
                bind::uniform(),     // CausticParams
                bind::storage(true), // grid
                bind::storage(true), // charts
                bind::storage(true), // chart of each object
                layers,              // receiver info
                layers,              // receiver albedo
                bind::texture_2d(),  // light map
                bind::sampler(),     // light-map sampler
            ],
        );
        // The receivers' pass binds the same @group(3) declarations (lightmap.wgsl's charts at
        // 2 and 3); it reads no grid, but keeps binding 1 so the numbers stay those of the WGSL.
        let receiver_layout = bind::layout(
            ctx,
            "caustic receivers",
            frag,
            &[
                bind::uniform(),
                bind::storage(true),
                bind::storage(true),
                bind::storage(true),
            ],
        );
        let empty_layout = bind::layout(ctx, "empty", frag, &[]);
        let empty_group = bind::group(ctx, "empty", &empty_layout, &[]);

        let layouts = [
            impostor_layout,
            &group3_layout,
            &empty_layout,
            &receiver_layout,
        ];
        let [
            map_pipeline,
            apply_pipeline,
            localized_pipeline,
            receiver_pipeline,
        ] = caustic_pipelines(ctx, scene, layouts, settings.path);
        let splat = match settings.path {
            CausticPath::Grid => splat_compute(ctx),
            CausticPath::LightMap => Splatter::Quads(QuadSplatter::new(ctx, LIGHT_MAP_FORMAT)),
        };

        let (atlas, charts, chart_of, light_map) = light_map_resources(ctx, scene, settings);
        let light_map_view = light_map.create_view(&Default::default());
        Ok(Self {
            settings: settings.clone(),
            group3_layout,
            receiver_layout,
            empty_group,
            map_pipeline,
            apply_pipeline,
            receiver_pipeline,
            localized_pipeline,
            splat,
            atlas,
            charts,
            chart_of,
            light_map,
            light_map_view,
            receiver_groups: UniformGroups::new("receiver params"),
            caustic_groups: UniformGroups::new("caustic params"),
            unlit_groups: UniformGroups::new("caustic params"),
            splat_groups: UniformGroups::new("splat params"),
        })
    }

    /// The light-map atlas (for tests and images).
    pub fn light_map(&self) -> &wgpu::Texture {
        &self.light_map
    }

    /// The chart atlas of the receivers.
    pub fn atlas(&self) -> &ChartAtlas {
        &self.atlas
    }

    /// GPU memory of one object's [`GeneratorMaps`] whose impostor has face size `env_size`
    /// (two photon targets, their depth, the grid, the receiver cube maps), for the per-object
    /// map budget.
    pub fn generator_bytes(&self, env_size: u32) -> u64 {
        let size = self.settings.resolution as u64;
        let texel = PHOTON_FORMAT.block_copy_size(None).unwrap_or(16) as u64;
        let grid = match self.settings.path {
            CausticPath::Grid => 6 * 3 * 4 * (self.settings.grid as u64).pow(2),
            CausticPath::LightMap => 4,
        };
        size * size * (2 * texel + 4)
            + grid
            + CubeTarget::bytes(env_size, RECEIVER_INFO_FORMAT)
            + CubeTarget::bytes(env_size, RECEIVER_ALBEDO_FORMAT)
    }

    /// Resources of one caustic generator whose impostor has face size `env_size`.
    pub fn generator_maps(&self, ctx: &Context, env_size: u32) -> Result<GeneratorMaps, GpuError> {
        let size = self.settings.resolution;
        let photon_target = |label| {
            gpu::render_texture(
                ctx,
                label,
                (size, size, 1),
                PHOTON_FORMAT,
                wgpu::TextureUsages::COPY_SRC,
            )
        };
        let grid_bytes = match self.settings.path {
            CausticPath::Grid => 6 * 3 * 4 * (self.settings.grid as u64).pow(2),
            CausticPath::LightMap => 4,
        };
        let address = photon_target("caustic map: photon address");
        let power = photon_target("caustic map: photon power");
        let depth = gpu::depth_texture(ctx, size, size, 1, "caustic map depth");
        let receiver_info =
            CubeTarget::new(ctx, env_size, RECEIVER_INFO_FORMAT, "caustic receivers")?;
        let receiver_albedo =
            CubeTarget::new(ctx, env_size, RECEIVER_ALBEDO_FORMAT, "receiver albedo")?;
        let array_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let views = GeneratorViews {
            address: address.create_view(&Default::default()),
            power: power.create_view(&Default::default()),
            depth: depth.create_view(&Default::default()),
            receiver_info: array_view(&receiver_info.color),
            receiver_albedo: array_view(&receiver_albedo.color),
        };
        Ok(GeneratorMaps {
            address,
            power,
            views,
            grid: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("caustic grid"),
                size: grid_bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            receiver_info,
            receiver_albedo,
        })
    }

    fn params(&self, light: Option<(&Light, Vec3, f32)>, scale: f32) -> CausticGpu {
        let (light_pos, intensity, axis) = match light {
            Some((l, axis, pixel_area)) => (
                l.position.extend(1.0),
                l.intensity.extend(0.0),
                axis.extend(pixel_area),
            ),
            None => (glam::Vec4::ZERO, glam::Vec4::ZERO, glam::Vec4::Z),
        };
        CausticGpu {
            light: light_pos.to_array(),
            intensity: intensity.to_array(),
            axis: axis.to_array(),
            grid: self.settings.grid,
            scale,
            size: self.settings.resolution,
            in_lookup: self.settings.in_lookup as u32,
            lightmap: self.light_map.width() as f32,
            jitter: self.settings.jitter as u32,
            _pad: [0; 2],
        }
    }

    /// Renders what the reference point sees of the receivers (chart, object, texel area,
    /// cosine, albedo): the paper's *uvmap*. Made with the environment impostor.
    /// `slot` is the generator's (its index among the generators).
    pub fn render_receivers(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        slot: usize,
        maps: &GeneratorMaps,
        object: usize,
        reference: Vec3,
    ) {
        let ctx = frame.gpu;
        let params = self.params(None, 1.0);
        let group = self.receiver_groups.get(ctx, slot, &params, |uniform| {
            bind::group(
                ctx,
                "caustic receivers",
                &self.receiver_layout,
                &[
                    uniform.binding(),
                    maps.grid.as_entire_binding(),
                    self.charts.as_entire_binding(),
                    self.chart_of.as_entire_binding(),
                ],
            )
        });
        scene.render_cube(
            frame,
            &maps.receiver_info,
            reference,
            0.01,
            |frame, face| {
                let no_receiver = Load::Clear(wgpu::Color {
                    r: -1.0,
                    g: 0.0,
                    b: 0.0,
                    a: 0.0,
                });
                let mut pass = gpu::pass::begin(
                    frame.encoder,
                    "caustic receivers",
                    &[
                        pass::color(face.target.color, no_receiver),
                        pass::color(&maps.receiver_albedo.face_views[face.index], CLEAR_BLACK),
                    ],
                    Some(pass::depth(face.target.depth, CLEAR_FAR)),
                    None,
                );
                pass.set_pipeline(&self.receiver_pipeline);
                pass.set_bind_group(0, &face.camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &self.empty_group, &[]);
                pass.set_bind_group(3, &group, &[]);
                scene.draw_objects(&mut pass, &ObjectFilter::Except(vec![object]));
            },
        );
    }

    fn group3(
        &self,
        ctx: &Context,
        maps: &GeneratorMaps,
        uniform: &Uniform<CausticGpu>,
    ) -> wgpu::BindGroup {
        let (info, albedo) = (&maps.views.receiver_info, &maps.views.receiver_albedo);
        bind::group(
            ctx,
            "caustics",
            &self.group3_layout,
            &[
                uniform.binding(),
                maps.grid.as_entire_binding(),
                self.charts.as_entire_binding(),
                self.chart_of.as_entire_binding(),
                bind::view(info),
                bind::view(albedo),
                bind::view(&self.light_map_view),
                bind::sampler_resource(&ctx.samplers.linear_clamp),
            ],
        )
    }

    /// Renders the caustic maps of every generator from every light and splats the photons
    /// (into the light map or the generators' grids). Returns each generator's `@group(3)`
    /// for the apply and lookup passes.
    pub fn render(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        generators: &[(usize, Vec3, &GeneratorMaps, &wgpu::BindGroup)],
    ) -> Vec<wgpu::BindGroup> {
        let ctx = frame.gpu;
        let time = scene.time();
        let size = self.settings.resolution;
        if self.settings.path == CausticPath::LightMap {
            clear_texture_pass(frame.encoder, &self.light_map_view);
        }
        let mut groups = Vec::new();
        let lights = scene.scene.lights.len();
        for (g, &(object, reference, maps, impostor_group)) in generators.iter().enumerate() {
            let o = &scene.scene.objects[object];
            let center = o.center_at(time);
            let radius = o.bounding_radius_at(time) * 1.05;
            // The cones from each light that hold the object; their total flux bounds any grid
            // texel's sum, which sets the grid's fixed-point scale.
            let cones: Vec<_> = scene
                .scene
                .lights
                .iter()
                .enumerate()
                .filter_map(|(l, light)| {
                    let to = center - light.position;
                    let dist = to.length();
                    (dist > radius).then(|| (l, light, to / dist, dist, (radius / dist).asin()))
                })
                .collect();
            let total: f32 = cones
                .iter()
                .map(|(_, l, _, _, half)| {
                    l.intensity.max_element() * 2.0 * std::f32::consts::PI * (1.0 - half.cos())
                })
                .sum();
            let scale = if total > 0.0 { 1.5e9 / total } else { 1.0 };
            if self.settings.path == CausticPath::Grid {
                frame.encoder.clear_buffer(&maps.grid, 0, None);
            }
            let mut lookup_group = None;
            for (l, light, axis, dist, half) in cones.iter().copied() {
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
                let params = self.params(Some((light, axis, pixel_area)), scale);
                let group3 = self
                    .caustic_groups
                    .get(ctx, g * lights + l, &params, |u| self.group3(ctx, maps, u));
                self.caustic_map_pass(frame, scene, maps, object, &camera, impostor_group, &group3);
                self.splat(frame, g, maps, reference, scale);
                lookup_group.get_or_insert(group3);
            }
            // No light outside the object: nothing splatted, the group still binds the maps.
            groups.push(lookup_group.unwrap_or_else(|| {
                let params = self.params(None, 1.0);
                self.unlit_groups
                    .get(ctx, g, &params, |u| self.group3(ctx, maps, u))
            }));
        }
        groups
    }

    #[allow(clippy::too_many_arguments)]
    fn caustic_map_pass(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        maps: &GeneratorMaps,
        object: usize,
        camera: &wgpu::BindGroup,
        impostor_group: &wgpu::BindGroup,
        group3: &wgpu::BindGroup,
    ) {
        let views = &maps.views;
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "caustic map",
            &[
                pass::color(&views.address, CLEAR_BLACK),
                pass::color(&views.power, CLEAR_BLACK),
            ],
            Some(pass::depth(&views.depth, CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(&self.map_pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, impostor_group, &[]);
        pass.set_bind_group(3, group3, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![object]));
    }

    /// Adds one caustic map's photons: Gaussian quads into the light map, or atomics into
    /// the grid. `slot` is the generator's.
    fn splat(
        &self,
        frame: &mut Frame,
        slot: usize,
        maps: &GeneratorMaps,
        reference: Vec3,
        scale: f32,
    ) {
        let ctx = frame.gpu;
        let size = self.settings.resolution;
        let (address, power) = (&maps.views.address, &maps.views.power);
        match &self.splat {
            Splatter::Compute { pipeline, layout } => {
                let params = SplatGpu {
                    reference: reference.extend(0.0).to_array(),
                    grid: self.settings.grid,
                    scale,
                    size,
                    _pad: 0,
                };
                let group = self.splat_groups.get(ctx, slot, &params, |uniform| {
                    bind::group(
                        ctx,
                        "caustic splat",
                        layout,
                        &[
                            bind::view(address),
                            bind::view(power),
                            maps.grid.as_entire_binding(),
                            uniform.binding(),
                        ],
                    )
                });
                let mut pass = frame
                    .encoder
                    .begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("caustic splat"),
                        timestamp_writes: None,
                    });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(size.div_ceil(8), size.div_ceil(8), 1);
            }
            Splatter::Quads(splatter) => splatter.splat(
                frame,
                slot,
                &self.light_map_view,
                self.light_map.width(),
                address,
                power,
                &self.charts,
                size,
                // One lattice per caustic map.
                if self.settings.footprint { size } else { 0 },
                self.settings.splat_radius,
            ),
        }
    }

    /// Adds the caustic radiance to the diffuse surfaces already drawn into `target` (depth
    /// `LessEqual`, additive, alpha kept). `groups` are [`Caustics::render`]'s.
    #[allow(clippy::too_many_arguments)]
    pub fn apply(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        target: &RasterTarget,
        camera: &wgpu::BindGroup,
        impostor_groups: &[wgpu::BindGroup],
        groups: &[wgpu::BindGroup],
        receivers: &ObjectFilter,
    ) {
        let mut pass = scene::begin_scene_pass(
            frame.encoder,
            &RasterTarget {
                clear: false,
                ..*target
            },
            scene.scene.background,
            "caustics apply",
        );
        pass.set_pipeline(&self.apply_pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        match self.settings.path {
            // One light map for every generator: one draw.
            CausticPath::LightMap => {
                if let (Some(g2), Some(g3)) = (impostor_groups.first(), groups.first()) {
                    pass.set_bind_group(2, g2, &[]);
                    pass.set_bind_group(3, g3, &[]);
                    scene.draw_objects(&mut pass, receivers);
                }
            }
            // One grid per generator, each seen from its own reference point.
            CausticPath::Grid => {
                for (g2, g3) in impostor_groups.iter().zip(groups) {
                    pass.set_bind_group(2, g2, &[]);
                    pass.set_bind_group(3, g3, &[]);
                    scene.draw_objects(&mut pass, receivers);
                }
            }
        }
    }
}

fn clear_texture_pass(encoder: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
    gpu::pass::begin(
        encoder,
        "clear light map",
        &[pass::color(view, CLEAR_BLACK)],
        None,
        None,
    );
}

fn splat_compute(ctx: &Context) -> Splatter {
    let photons = bind::texture_2d_unfilterable();
    let layout = bind::layout(
        ctx,
        "caustic splat",
        wgpu::ShaderStages::COMPUTE,
        &[photons, photons, bind::storage(false), bind::uniform()],
    );
    let module = scene::shader(ctx, "caustic splat", SPLAT_WGSL);
    let pipeline = gpu::compute::pipeline(ctx, "caustic splat", &[&layout], &module, "splat_main");
    Splatter::Compute { pipeline, layout }
}

/// The caustic passes' pipelines (their shaders with the caustics of `path`): the caustic map
/// (photon landing points and power), the apply onto the receivers, the localized lookup
/// with caustics, and the receivers' pass. `layouts`: the impostor's `@group(2)`, the
/// caustics' `@group(3)`, and the receiver pass's empty `@group(2)` and `@group(3)`.
fn caustic_pipelines(
    ctx: &Context,
    scene: &GpuScene,
    [
        impostor_layout,
        group3_layout,
        empty_layout,
        receiver_layout,
    ]: [&wgpu::BindGroupLayout; 4],
    path: CausticPath,
) -> [wgpu::RenderPipeline; 4] {
    let module = caustic_shader(ctx, "impostors caustics", CAUSTIC_PASSES_WGSL, path);
    let localized = caustic_shader(
        ctx,
        "localized lookup with caustics",
        crate::localized::LOCALIZED_FS_WGSL,
        path,
    );
    let layout = scene.pipeline_layout_with(ctx, &[impostor_layout, group3_layout]);
    let (map_entry, apply_entry) = match path {
        CausticPath::LightMap => ("caustic_uv_fs", "lightmap_apply_fs"),
        CausticPath::Grid => ("caustic_map_fs", "caustic_apply_fs"),
    };
    let less = (true, wgpu::CompareFunction::Less);
    let map_pipeline = scene::scene_pipeline_with(
        ctx,
        "caustic map",
        &layout,
        &module,
        map_entry,
        &[
            color_target(PHOTON_FORMAT, None),
            color_target(PHOTON_FORMAT, None),
        ],
        less,
    );
    let apply_pipeline = scene::scene_pipeline_with(
        ctx,
        "caustics apply",
        &layout,
        &module,
        apply_entry,
        &[color_target(gpu::HDR_FORMAT, Some(ADD_RGB_KEEP_ALPHA))],
        (false, wgpu::CompareFunction::LessEqual),
    );
    let localized_pipeline = scene::scene_pipeline_with(
        ctx,
        "localized lookup with caustics",
        &layout,
        &localized,
        "localized_fs",
        &[color_target(gpu::HDR_FORMAT, None)],
        less,
    );
    let receiver_pipeline = scene::scene_pipeline_with(
        ctx,
        "caustic receivers",
        &scene.pipeline_layout_with(ctx, &[empty_layout, receiver_layout]),
        &module,
        "receiver_fs",
        &[
            color_target(RECEIVER_INFO_FORMAT, None),
            color_target(RECEIVER_ALBEDO_FORMAT, None),
        ],
        less,
    );
    [
        map_pipeline,
        apply_pipeline,
        localized_pipeline,
        receiver_pipeline,
    ]
}

/// The light-map path's atlas of receiver charts with its chart tables, and the light map
/// (a 1 x 1 stand-in on the grid path, which never writes it).
fn light_map_resources(
    ctx: &Context,
    scene: &GpuScene,
    settings: &CausticSettings,
) -> (ChartAtlas, wgpu::Buffer, wgpu::Buffer, wgpu::Texture) {
    let atlas = ChartAtlas::new(&scene.scene, settings.lightmap_resolution);
    let charts = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light-map charts"),
            contents: bytemuck::cast_slice(&atlas.gpu_charts()),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let chart_of = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light-map chart table"),
            contents: bytemuck::cast_slice(&atlas.chart_of),
            usage: wgpu::BufferUsages::STORAGE,
        });
    // The grid path never writes the light map: a 1 x 1 stand-in.
    let side = match settings.path {
        CausticPath::LightMap => settings.lightmap_resolution,
        CausticPath::Grid => 1,
    };
    let light_map = gpu::render_texture(
        ctx,
        "caustic light map",
        (side, side, 1),
        LIGHT_MAP_FORMAT,
        wgpu::TextureUsages::COPY_SRC,
    );
    (atlas, charts, chart_of, light_map)
}
