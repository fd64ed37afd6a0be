//! Caustics (Hu and Qin 2006, section 3): the photon buffer from each light, caustic textures
//! accumulated and filtered on the GPU, caustic mapping onto the receivers.
//!
//! The twins of `shaders/caustic_compute.wgsl` are [`scatter`] and [`filter`]; the GPU side is
//! [`Accumulator`] (the two compute passes, usable alone) and [`Caustics`] (the light views,
//! their front/back buffers, the photon pass and the caustic mapping pass).

use crate::rectangles::Rectangles;
use crate::search::{Eye, EyeGpu};
use glam::{Vec2, Vec3};
use gpu::wgpu;
use gpu::{Context, Uniform, bind};
use scene::{Frame, GpuScene};

/// Fixed-point counts the power of all photon buffers of a frame together maps to (2^31): a
/// texel receiving every photon of the frame still fits a `u32`, and one photon of a 128^2
/// buffer is about 2^17 counts.
pub const FULL_SCALE: f32 = 2_147_483_648.0;

/// The paper's filter weight `sqrt(1 + 2k^2 - (i^2 + j^2))` of texel offset `(i, j)`.
pub fn filter_weight(i: i32, j: i32, k: i32) -> f32 {
    ((1 + 2 * k * k - (i * i + j * j)) as f32).sqrt()
}

/// Photon power per texel, fixed point (`unit` watts per count) as the GPU's atomics add it:
/// `photons` are (texture coordinates, layer, rgb power).
pub fn scatter(
    photons: &[(Vec2, u32, Vec3)],
    resolution: u32,
    layers: u32,
    unit: f32,
) -> Vec<[u32; 3]> {
    let res = resolution as usize;
    let mut counts = vec![[0u32; 3]; res * res * layers as usize];
    for &(uv, layer, power) in photons {
        let r = resolution as f32;
        let x = (uv.x * r).floor().min(r - 1.0) as usize;
        let y = (uv.y * r).floor().min(r - 1.0) as usize;
        let c = &mut counts[(layer as usize * res + y) * res + x];
        for (channel, p) in c.iter_mut().zip(power.to_array()) {
            *channel = channel.wrapping_add((p / unit).round() as u32);
        }
    }
    counts
}

/// The paper's filter on one layer of counts (`resolution`^2 texels of rgb), normalized by
/// the sum of its weights and scaled by `scale`: with `scale` 1 the filtered power of a layer
/// equals its photons' power but for what the window carries past the texture's border.
pub fn filter(counts: &[[f32; 3]], resolution: u32, k: u32, scale: f32) -> Vec<[f32; 3]> {
    let (res, k) = (resolution as i32, k as i32);
    let weights: f32 = (-k..=k)
        .flat_map(|j| (-k..=k).map(move |i| filter_weight(i, j, k)))
        .sum();
    let mut out = vec![[0.0; 3]; counts.len()];
    for y in 0..res {
        for x in 0..res {
            let mut sum = [0.0f32; 3];
            for j in -k..=k {
                for i in -k..=k {
                    let (sx, sy) = (x + i, y + j);
                    if sx < 0 || sy < 0 || sx >= res || sy >= res {
                        continue;
                    }
                    let w = filter_weight(i, j, k);
                    let c = counts[(sy * res + sx) as usize];
                    for ch in 0..3 {
                        sum[ch] += w * c[ch];
                    }
                }
            }
            out[(y * res + x) as usize] = sum.map(|s| scale * s / weights);
        }
    }
    out
}

/// Parameters of the caustics (settable through the technique's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CausticSettings {
    /// Side of the photon buffer: photons per light and refractor are its square
    /// (`photon_buffer`; the paper shows 64 and 128).
    pub photon_size: u32,
    /// Side of each caustic texture (`caustic_resolution`).
    pub resolution: u32,
    /// Filter half size k (`filter_k`; the paper's default 2).
    pub k: u32,
    /// Filter scale s (`filter_s`): 1 keeps the photons' power (the paper's 0.01 is for its
    /// unnormalized filter and arbitrary units).
    pub scale: f32,
    /// Each photon leaves from a random point of its photon-buffer pixel instead of the pixel
    /// centre (`photon_jitter`; stratified jittered emission, `jittered_emission` in
    /// scene.wgsl).
    pub jitter: bool,
}

impl Default for CausticSettings {
    fn default() -> Self {
        Self {
            photon_size: 128,
            resolution: 256,
            k: 2,
            scale: 1.0,
            jitter: false,
        }
    }
}

/// The WGSL `CausticParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CausticParamsGpu {
    /// Side of each caustic texture.
    pub resolution: u32,
    /// Layers.
    pub layers: u32,
    /// Filter half size.
    pub k: u32,
    /// Side of the photon buffer.
    pub photon_size: u32,
    /// Watts per count.
    pub unit: f32,
    /// Filter scale.
    pub scale: f32,
    _pad: [f32; 2],
}

impl CausticParamsGpu {
    /// The parameters of `settings` over `layers` layers at `unit` watts per count.
    pub fn new(settings: &CausticSettings, layers: u32, unit: f32) -> Self {
        Self {
            resolution: settings.resolution,
            layers,
            k: settings.k,
            photon_size: settings.photon_size,
            unit,
            scale: settings.scale,
            _pad: [0.0; 2],
        }
    }
}

/// The two compute passes of section 3.2 and their buffers: photon buffers in, caustic
/// irradiance per texel out (`caustic`), nothing read back.
pub struct Accumulator {
    params: Uniform<CausticParamsGpu>,
    counts: wgpu::Buffer,
    /// Irradiance per texel, `[layer][row][column]` of `vec4f` (rgb, 0).
    pub caustic: wgpu::Buffer,
    areas: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    scatter: wgpu::ComputePipeline,
    filter: wgpu::ComputePipeline,
    settings: CausticSettings,
    layers: u32,
}

impl Accumulator {
    /// Buffers for `layers` caustic textures of `settings.resolution` texels.
    pub fn new(ctx: &Context, settings: CausticSettings, layers: u32) -> Self {
        let texels = u64::from(settings.resolution).pow(2) * u64::from(layers.max(1));
        let buffer = |label, size, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let counts = buffer("caustic counts", texels * 12, U::STORAGE | U::COPY_DST);
        let caustic = buffer("caustic irradiance", texels * 16, U::STORAGE | U::COPY_SRC);
        let areas = buffer(
            "caustic texel areas",
            u64::from(layers.max(1)) * 4,
            U::STORAGE | U::COPY_DST,
        );
        let layout = bind::layout(
            ctx,
            "caustic textures",
            wgpu::ShaderStages::COMPUTE,
            &[
                bind::uniform(),                 // cp
                bind::texture_2d_unfilterable(), // photon_hit
                bind::texture_2d_unfilterable(), // photon_power
                bind::storage(false),            // counts
                bind::storage(false),            // caustic
                bind::storage(true),             // texel_areas
            ],
        );
        let module = scene::shader(
            ctx,
            "caustic textures",
            include_str!("shaders/caustic_compute.wgsl"),
        );
        let pipeline = |entry: &str| gpu::compute::pipeline(ctx, entry, &[&layout], &module, entry);
        Self {
            params: Uniform::new(
                ctx,
                "caustic params",
                &CausticParamsGpu::new(&settings, layers, 1.0),
            ),
            counts,
            caustic,
            areas,
            scatter: pipeline("scatter"),
            filter: pipeline("filter_caustics"),
            layout,
            settings,
            layers,
        }
    }

    /// Starts a frame: counts cleared, `unit` watts per count, the texel areas of each layer.
    pub fn begin(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        unit: f32,
        areas: &[f32],
    ) {
        encoder.clear_buffer(&self.counts, 0, None);
        self.params.write(
            ctx,
            &CausticParamsGpu::new(&self.settings, self.layers, unit),
        );
        if !areas.is_empty() {
            ctx.queue
                .write_buffer(&self.areas, 0, bytemuck::cast_slice(areas));
        }
    }

    /// Adds one photon buffer (hit and power textures, `settings.photon_size` square).
    pub fn scatter(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        hit: &wgpu::TextureView,
        power: &wgpu::TextureView,
    ) {
        let n = self.settings.photon_size.div_ceil(8);
        self.dispatch(ctx, encoder, &self.scatter, [hit, power], (n, n, 1));
    }

    /// Filters the counts into `caustic` (any photon views: the filter reads none).
    pub fn filter(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        hit: &wgpu::TextureView,
        power: &wgpu::TextureView,
    ) {
        let n = self.settings.resolution.div_ceil(8);
        let workgroups = (n, n, self.layers.max(1));
        self.dispatch(ctx, encoder, &self.filter, [hit, power], workgroups);
    }

    /// One compute pass of `pipeline` over the accumulator's bindings.
    fn dispatch(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        [hit, power]: [&wgpu::TextureView; 2],
        (x, y, z): (u32, u32, u32),
    ) {
        let group = self.group(ctx, hit, power);
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(x, y, z);
    }

    fn group(
        &self,
        ctx: &Context,
        hit: &wgpu::TextureView,
        power: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind::group(
            ctx,
            "caustic textures",
            &self.layout,
            &[
                self.params.binding(),
                bind::view(hit),
                bind::view(power),
                self.counts.as_entire_binding(),
                self.caustic.as_entire_binding(),
                self.areas.as_entire_binding(),
            ],
        )
    }
}

/// One light's view of one refractor.
struct LightView {
    light: usize,
    /// Index of the refractor in the technique's list of specular objects.
    refractor: usize,
    eye: Uniform<EyeGpu>,
    /// `@group(2)` of refract.wgsl with the light's eye and buffers.
    group: wgpu::BindGroup,
}

/// The light's camera looking at a refractor of centre `centre` and bounding radius `radius`,
/// with its pixel size at unit distance for `size` pixels; `None` when the light is inside the
/// bounding sphere.
pub fn light_camera(
    light: Vec3,
    centre: Vec3,
    radius: f32,
    size: u32,
) -> Option<(scene::Camera, f32)> {
    let distance = light.distance(centre);
    let reach = 1.05 * radius;
    if !(distance > reach) {
        return None;
    }
    let half = (reach / distance).asin();
    let dir = (centre - light) / distance;
    let up = if dir.y.abs() < 0.99 { Vec3::Y } else { Vec3::X };
    let camera = scene::Camera {
        eye: light,
        target: centre,
        up,
        fov_y_deg: (2.0 * half).to_degrees(),
        orthographic: None,
    };
    Some((camera, 2.0 * half.tan() / size as f32))
}

/// The GPU passes of section 3 for every light and refractor.
pub struct Caustics {
    /// The parameters.
    pub settings: CausticSettings,
    /// The caustic textures.
    pub accumulator: Accumulator,
    light_front: wgpu::TextureView,
    light_back: wgpu::TextureView,
    light_depth: wgpu::TextureView,
    photon_hit: wgpu::TextureView,
    photon_power: wgpu::TextureView,
    photon_textures: [wgpu::Texture; 2],
    photon_pipeline: wgpu::RenderPipeline,
    views: Vec<LightView>,
    map_pipeline: wgpu::RenderPipeline,
    map_groups: Vec<wgpu::BindGroup>,
    _map_params: Uniform<[u32; 4]>,
    _rect_of_object: Vec<wgpu::Buffer>,
}

/// What [`Caustics::new`] needs of the technique: its `@group(2)` layout and, per refractor,
/// the environment map, parameters and `d_N` it binds there.
pub struct RefractorBindings<'a> {
    /// refract.wgsl's `@group(2)` layout.
    pub layout: &'a wgpu::BindGroupLayout,
    /// Per refractor: (environment cube view, params uniform binding).
    pub refractors: Vec<(&'a wgpu::TextureView, wgpu::BindingResource<'a>)>,
    /// `d_N` storage.
    pub normal_thickness: &'a wgpu::Buffer,
    /// The photon pipeline (refractor_vs + photon_fs with groups 2 and 3).
    pub photon_pipeline: wgpu::RenderPipeline,
}

impl Caustics {
    /// The passes for every (light, refractor) pair of `scene`.
    pub fn new(
        ctx: &Context,
        scene: &GpuScene,
        settings: CausticSettings,
        rectangles: &Rectangles,
        bindings: RefractorBindings,
    ) -> Self {
        let n = settings.photon_size;
        let size = (n, n, 1);
        let view = |t: wgpu::Texture| t.create_view(&Default::default());
        let f32x4 = wgpu::TextureFormat::Rgba32Float;
        let none = wgpu::TextureUsages::empty();
        let light_front = view(gpu::render_texture(
            ctx,
            "light front buffer",
            size,
            f32x4,
            none,
        ));
        let light_back = view(gpu::render_texture(
            ctx,
            "light back buffer",
            size,
            f32x4,
            none,
        ));
        let light_depth = view(gpu::depth_texture(ctx, n, n, 1, "light depth"));
        let copy = wgpu::TextureUsages::COPY_SRC;
        let photon_textures = [
            gpu::render_texture(ctx, "photon hits", size, f32x4, copy),
            gpu::render_texture(ctx, "photon power", size, f32x4, copy),
        ];
        let photon_hit = photon_textures[0].create_view(&Default::default());
        let photon_power = photon_textures[1].create_view(&Default::default());
        let layers = rectangles
            .refractors
            .iter()
            .map(|r| r.members.len() as u32)
            .sum::<u32>();
        let accumulator = Accumulator::new(ctx, settings, layers);
        let views = light_views(ctx, scene, &bindings, [&light_front, &light_back]);
        let (map_pipeline, map_groups, map_params, rect_of_object) =
            caustic_mapping(ctx, scene, &settings, rectangles, &accumulator);
        Self {
            settings,
            accumulator,
            light_front,
            light_back,
            light_depth,
            photon_hit,
            photon_power,
            photon_textures,
            photon_pipeline: bindings.photon_pipeline,
            views,
            map_pipeline,
            map_groups,
            _map_params: map_params,
            _rect_of_object: rect_of_object,
        }
    }

    /// Records the photon buffers and caustic textures of this frame: per light and
    /// refractor, the light's front/back buffers, the photon pass and the scatter; then the
    /// filter. `refractors` are the specular objects' indices; `buffer_pipelines` the
    /// technique's front and back buffer pipelines.
    pub fn record(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        refractors: &[usize],
        rectangles: &Rectangles,
        buffer_pipelines: [&wgpu::RenderPipeline; 2],
    ) {
        let ctx = frame.gpu;
        let time = scene.time();
        let n = self.settings.photon_size;
        // Fixed point: the power of all photon buffers together maps to FULL_SCALE counts.
        let mut total = 0.0f32;
        let mut cameras = Vec::new();
        for v in &self.views {
            let o = &scene.scene.objects[refractors[v.refractor]];
            let light = &scene.scene.lights[v.light];
            let camera = light_camera(
                light.position,
                o.center_at(time),
                o.bounding_radius_at(time),
                n,
            );
            if let Some((_, pixel)) = camera {
                let power = light.intensity.max_element() * (pixel * n as f32).powi(2);
                total += power;
            }
            cameras.push(camera);
        }
        let unit = total.max(1e-20) / FULL_SCALE;
        let areas: Vec<f32> = rectangles
            .refractors
            .iter()
            .flat_map(|t| t.placed.iter())
            .map(|r| 4.0 * r.half_u * r.half_v / (self.settings.resolution as f32).powi(2))
            .collect();
        self.accumulator.begin(ctx, frame.encoder, unit, &areas);
        for (v, camera) in self.views.iter().zip(cameras) {
            let Some((camera, pixel)) = camera else {
                continue;
            };
            let eye = Eye::of_camera(&camera, n, n);
            v.eye
                .write(ctx, &EyeGpu::from(&eye).for_light(pixel, v.light as u32));
            let light_camera = scene.camera_bind_group(ctx, camera.view_proj(n, n), camera.eye);
            for (pipeline, buffer) in buffer_pipelines
                .iter()
                .zip([&self.light_front, &self.light_back])
            {
                let mut pass = gpu::pass::begin(
                    frame.encoder,
                    "light front/back buffer",
                    &[gpu::pass::color(buffer, gpu::pass::CLEAR_BLACK)],
                    Some(gpu::pass::depth(&self.light_depth, gpu::pass::CLEAR_FAR)),
                    None,
                );
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &light_camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                scene.draw_objects(&mut pass, &scene::ObjectFilter::Only(refractors.to_vec()));
            }
            {
                let mut pass = gpu::pass::begin(
                    frame.encoder,
                    "photon buffer",
                    &[
                        gpu::pass::color(&self.photon_hit, gpu::pass::CLEAR_BLACK),
                        gpu::pass::color(&self.photon_power, gpu::pass::CLEAR_BLACK),
                    ],
                    Some(gpu::pass::depth(&self.light_depth, gpu::pass::CLEAR_FAR)),
                    None,
                );
                pass.set_pipeline(&self.photon_pipeline);
                pass.set_bind_group(0, &light_camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &v.group, &[]);
                pass.set_bind_group(3, &rectangles.refractors[v.refractor].group, &[]);
                let object = refractors[v.refractor];
                scene.draw_objects(&mut pass, &scene::ObjectFilter::Only(vec![object]));
            }
            self.accumulator
                .scatter(ctx, frame.encoder, &self.photon_hit, &self.photon_power);
        }
        self.accumulator
            .filter(ctx, frame.encoder, &self.photon_hit, &self.photon_power);
    }

    /// Reads back the caustic irradiance of the last frame, `[layer][row][column]` (rgb, 0):
    /// for tests; the technique itself reads nothing back.
    pub fn read_caustic(&self, ctx: &Context) -> Result<Vec<[f32; 4]>, gpu::GpuError> {
        let bytes = gpu::read_buffer(ctx, &self.accumulator.caustic)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Reads back the last photon buffer written in the last frame (the last light and
    /// refractor): per photon (u, v, layer + 1, 0) and (rgb power, 0). For tests.
    pub fn read_photons(&self, ctx: &Context) -> Result<[Vec<[f32; 4]>; 2], gpu::GpuError> {
        Ok([
            gpu::read_texture_f32x4(ctx, &self.photon_textures[0], 0)?,
            gpu::read_texture_f32x4(ctx, &self.photon_textures[1], 0)?,
        ])
    }

    /// Adds the caustics to the receivers drawn in `target` (caustic mapping), seen by
    /// `camera` (the eye's `@group(0)`).
    pub fn map(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        rectangles: &Rectangles,
        target: &scene::RasterTarget,
    ) {
        let mut pass = scene::begin_scene_pass(
            frame.encoder,
            &scene::RasterTarget {
                clear: false,
                ..*target
            },
            scene.scene.background,
            "caustic mapping",
        );
        pass.set_pipeline(&self.map_pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        for (table, group) in rectangles.refractors.iter().zip(&self.map_groups) {
            pass.set_bind_group(2, group, &[]);
            let members = table.members.iter().map(|m| m.object).collect();
            scene.draw_objects(&mut pass, &scene::ObjectFilter::Only(members));
        }
    }
}

/// One bind group of the photon pass per light and refractor: the refractor's environment
/// map and parameters, the light's eye, and the light's front and back buffers.
fn light_views(
    ctx: &Context,
    scene: &GpuScene,
    bindings: &RefractorBindings,
    [light_front, light_back]: [&wgpu::TextureView; 2],
) -> Vec<LightView> {
    let mut views = Vec::new();
    for light in 0..scene.scene.lights.len() {
        for (refractor, (env, params)) in bindings.refractors.iter().enumerate() {
            let eye = Uniform::new(ctx, "light eye", &bytemuck::Zeroable::zeroed());
            let group = bind::group(
                ctx,
                "photon pass",
                bindings.layout,
                &[
                    bind::view(env),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                    params.clone(),
                    eye.binding(),
                    bind::view(light_front),
                    bind::view(light_back),
                    bind::view(light_front),
                    bindings.normal_thickness.as_entire_binding(),
                ],
            );
            views.push(LightView {
                light,
                refractor,
                eye,
                group,
            });
        }
    }
    views
}

/// Caustic mapping: the pass that adds each rectangle's caustic texture onto
/// the receivers seen from the eye, with its bind group per refractor, its parameters and
/// each refractor's rectangle-of-object table.
fn caustic_mapping(
    ctx: &Context,
    scene: &GpuScene,
    settings: &CausticSettings,
    rectangles: &Rectangles,
    accumulator: &Accumulator,
) -> (
    wgpu::RenderPipeline,
    Vec<wgpu::BindGroup>,
    Uniform<[u32; 4]>,
    Vec<wgpu::Buffer>,
) {
    // Caustic mapping.
    let map_layout = bind::layout(
        ctx,
        "caustic mapping",
        wgpu::ShaderStages::FRAGMENT,
        &[
            bind::storage(true),                                      // rects
            bind::storage(true),                                      // caustic
            bind::depth_texture(wgpu::TextureViewDimension::D2Array), // impostor_depth
            bind::uniform(),                                          // map
            bind::storage(true),                                      // rect_of_object
        ],
    );
    // The visibility test's slack: 2% of a rectangle's depth range (a few texels of depth
    // on a slanted receiver).
    let bias = 0.02f32;
    let map_params = Uniform::new(
        ctx,
        "caustic map params",
        &[settings.resolution, 0, f32::to_bits(bias), 0],
    );
    let depth_array = rectangles.depth.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let mut rect_of_object = Vec::new();
    let mut map_groups = Vec::new();
    for table in &rectangles.refractors {
        let mut of_object = vec![-1i32; scene.scene.objects.len().max(1)];
        for (i, m) in table.members.iter().enumerate() {
            of_object[m.object] = i as i32;
        }
        use wgpu::util::DeviceExt;
        let buffer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("rect of object"),
                contents: bytemuck::cast_slice(&of_object),
                usage: wgpu::BufferUsages::STORAGE,
            });
        map_groups.push(bind::group(
            ctx,
            "caustic mapping",
            &map_layout,
            &[
                table.rects.as_entire_binding(),
                accumulator.caustic.as_entire_binding(),
                bind::view(&depth_array),
                map_params.binding(),
                buffer.as_entire_binding(),
            ],
        ));
        rect_of_object.push(buffer);
    }
    let module = scene::shader_importing(
        ctx,
        "caustic mapping",
        include_str!("shaders/caustic.wgsl"),
        &[&crate::nearby::RECT],
    );
    let map_pipeline = scene::scene_pipeline_with(
        ctx,
        "caustic mapping",
        &scene.pipeline_layout_with(ctx, &[&map_layout]),
        &module,
        "caustic_fs",
        &[gpu::pass::color_target(
            gpu::HDR_FORMAT,
            Some(gpu::pass::ADD_RGB_KEEP_ALPHA),
        )],
        (false, wgpu::CompareFunction::LessEqual),
    );
    (map_pipeline, map_groups, map_params, rect_of_object)
}
