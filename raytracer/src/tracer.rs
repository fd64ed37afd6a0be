//! The GPU side of the tracer: the BVH, the scene tables and the two passes of
//! `shaders/tracer.wgsl` (eye, photons), recorded into a frame, then the resolve
//! (`crate::resolve`) into the target.
//!
//! Inputs: the uploaded scene's CPU model (objects, materials, textures, lights, volumes,
//! medium) at the frame's time, and the view. Output: linear radiance in the target. Parameters:
//! the specular depth bound and the photon count ([`TracerSettings`]).

use crate::bvh::{FlatBvh, NodeGpu};
use crate::resolve::{Resolve, ResolveParamsGpu};
use crate::tables::{Tables, texture_data};
use bytemuck::{Pod, Zeroable};
use gpu::bind::{self, Uniform};
use gpu::{Context, Frame, Target, wgpu};
use scene::bvh::WorldTriangles;
use scene::emission::{Emitter, caustic_casters, emitters};
use scene::medium::MediumGpu;
use scene::technique::{TechniqueError, TechniqueResult};
use scene::{Camera, Medium, Scene, View};
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Most volumes the tracer marches (`MAX_VOLUMES` in WGSL: each ray sorts the spheres it
/// crosses in a fixed-size array).
pub const MAX_VOLUMES: usize = 64;

/// Photons per pixel when the photon count is left to the image: the reference's density
/// (`truth::reference::PHOTONS_PER_PIXEL`, 4 million over 256 x 256), at least
/// [`MIN_PHOTONS`]: the same constants, from `scene::emission`.
pub use scene::emission::{MIN_PHOTONS, PHOTONS_PER_PIXEL, photons_for_image};
/// Most photons one frame traces (indices are 32-bit on the GPU).
pub const MAX_PHOTONS: u64 = 1 << 30;

/// Fixed-point counts per unit of radiance in the photon accumulator (`FIXED_POINT_SCALE` in
/// `tracer.wgsl`: 2^32).
pub const FIXED_POINT_SCALE: f64 = 4_294_967_296.0;

const EYE_WORKGROUP: u32 = 8;
const PHOTON_WORKGROUP: u32 = 64;
/// Photon threads per dispatch row (the rest go to further rows: a dimension holds at most
/// 65535 workgroups).
const PHOTON_ROW_WORKGROUPS: u32 = 32768;

/// What a frame traces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracerSettings {
    /// Specular interactions followed along a path (the reference's `max_depth`).
    pub max_depth: u32,
    /// Caustic photons per frame: `None` traces none, `Some(0)` a [`FRAME_SHARE`]th of the
    /// reference's density for the image ([`photons_for_image`]). Frames of an unchanged view
    /// (camera, time, size) add up: each traces new photons with a seed of its own
    /// ([`frame_seed`]) and the image is the running mean of the frames' photon estimates, so
    /// [`FRAME_SHARE`] frames of one view reach the reference's density.
    pub photons: Option<u64>,
    /// Seed of the photons' random numbers (of the first frame of a view; frame `k` of the
    /// same view uses [`frame_seed`]).
    pub seed: u32,
}

impl Default for TracerSettings {
    fn default() -> Self {
        Self {
            max_depth: 8,
            photons: None,
            seed: 0x5eed,
        }
    }
}

/// The share of the reference's photons one frame traces by default: a frame costs a
/// sixteenth of the reference's light pass, and 16 frames of one view reach its density.
pub const FRAME_SHARE: u64 = 16;

/// The seed of frame `k` of one view: `seed` for the first, then a hash of both, so no two
/// frames of a view trace the same photons.
pub fn frame_seed(seed: u32, k: u32) -> u32 {
    match k {
        0 => seed,
        _ => seed ^ k.wrapping_mul(0x9e37_79b9).rotate_left(16) ^ 0x85eb_ca6b,
    }
}

/// Rays one frame cast, counted on the GPU the way the reference counts its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Closest-hit rays of the eye pass (primary, reflected, refracted).
    pub camera: u64,
    /// Shadow rays of the eye pass (direct light and in-scattering).
    pub shadow: u64,
    /// Photon path segments and visibility rays to the eye.
    pub photon: u64,
    /// Photons that landed visibly and were added to a pixel.
    pub photons_stored: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.photon
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ParamsGpu {
    eye: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    view_proj: [[f32; 4]; 4],
    size: [u32; 4],
    counts: [u32; 4],
    offsets: [u32; 4],
    photons: [u32; 4],
    background: [f32; 4],
    medium: MediumGpu,
}

/// The volumes the eye pass marches (valid, with some extinction), as `truth::media` keeps them.
pub fn marched_volumes(scene: &Scene) -> usize {
    scene
        .volumes
        .iter()
        .filter(|v| v.validate().is_ok() && v.density > 0.0)
        .count()
}

/// Whether geometry moves over time (the BVH is then rebuilt for every frame's time).
fn geometry_moves(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| !o.motion.is_static() || o.morph.as_ref().is_some_and(|m| m.is_animated()))
}

/// A scene's tracer: buffers, pipelines and the BVH of the last time traced.
pub struct GpuTracer {
    settings: TracerSettings,
    params: Uniform<ParamsGpu>,
    /// What the rays traverse: the flattened BVH, or the hardware's acceleration structures.
    structure: Structure,
    triangles: wgpu::Buffer,
    attributes: wgpu::Buffer,
    tables: wgpu::Buffer,
    /// The objects' alpha cut-outs, then every texture's texels (`tables::texture_data`).
    texture_data: wgpu::Buffer,
    radiance: wgpu::Buffer,
    photon_sum: wgpu::Buffer,
    stats: wgpu::Buffer,
    stats_readback: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
    /// The resolve into the harness's targets.
    resolve: Resolve,
    /// What the last frame traced, as its resolve reads it.
    last_frame: ResolveParamsGpu,
    eye_pipeline: wgpu::ComputePipeline,
    photon_pipeline: wgpu::ComputePipeline,
    /// Pixels the per-pixel buffers hold.
    pixels: u64,
    /// The view the photon sum holds frames of, and how many.
    accumulated: Option<(View, u32)>,
    bvh_time: f32,
    moves: bool,
    traversal: Traversal,
    /// Seconds the last BVH build took on the CPU.
    pub bvh_build_seconds: f64,
    pub triangle_count: usize,
}

/// How rays find their nearest triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Traversal {
    /// The scene's BVH flattened into storage buffers, traversed by `raytracer::bvh`
    /// (`shaders/bvh.wgsl`, the twin of [`crate::bvh::FlatBvh`]): runs on every adapter.
    Bvh,
    /// The hardware's acceleration structures (one BLAS of every world triangle, one TLAS
    /// instance) and wgpu's ray queries (`raytracer::ray_query`, `shaders/ray_query.wgsl`):
    /// needs
    /// `wgpu::Features::EXPERIMENTAL_RAY_QUERY`.
    RayQuery,
}

impl Traversal {
    fn binding_type(self) -> wgpu::BindingType {
        match self {
            Traversal::Bvh => bind::storage(true),
            Traversal::RayQuery => wgpu::BindingType::AccelerationStructure {
                vertex_return: false,
            },
        }
    }
}

/// The traversal's GPU structure.
enum Structure {
    Bvh {
        nodes: wgpu::Buffer,
    },
    RayQuery {
        /// Three world-space vertices per triangle, in the order of the triangle buffers.
        vertices: wgpu::Buffer,
        size: wgpu::BlasTriangleGeometrySizeDescriptor,
        blas: wgpu::Blas,
        tlas: wgpu::Tlas,
        /// The vertices changed since the last build (the next frame rebuilds, timed).
        stale: bool,
    },
}

/// The scene's triangles as the traversals see them: the module `raytracer::triangles`.
pub static TRIANGLES: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/triangles.wgsl"),
    "raytracer/src/shaders/triangles.wgsl",
    &[],
);
/// The BVH traversal (the twin of [`crate::bvh::FlatBvh`]): the module `raytracer::bvh`.
pub static BVH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/bvh.wgsl"),
    "raytracer/src/shaders/bvh.wgsl",
    &[&TRIANGLES],
);
/// The hardware's ray queries: the module `raytracer::ray_query`.
pub static RAY_QUERY: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/ray_query.wgsl"),
    "raytracer/src/shaders/ray_query.wgsl",
    &[&TRIANGLES],
);
/// `trace_closest` and `trace_any` by one traversal's `trace`: the module `raytracer::queries`
/// (the BVH's, or the ray queries' with the definition `RAY_QUERY`).
pub static QUERIES: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/queries.wgsl"),
    "raytracer/src/shaders/queries.wgsl",
    &[&BVH, &RAY_QUERY],
);
/// The tracer's passes (`eye_pass`, `photon_pass`).
pub const TRACER_WGSL: &str = include_str!("shaders/tracer.wgsl");
/// Where the tracer binds the traversal's structure (binding 1), the triangles (2 and 3) and the
/// cut-outs and texels (4).
pub const TRACE_FIRST_BINDING: (&str, gpu::wgsl::Def) =
    ("TRACE_FIRST_BINDING", gpu::wgsl::Def::UInt(1));

impl Traversal {
    /// The tracer's shader for this traversal.
    fn shader(self, ctx: &Context) -> wgpu::ShaderModule {
        let ray_query = ("RAY_QUERY", gpu::wgsl::Def::Bool(true));
        let defs: &[_] = match self {
            Traversal::Bvh => &[TRACE_FIRST_BINDING],
            Traversal::RayQuery => &[TRACE_FIRST_BINDING, ray_query],
        };
        let imports = [&QUERIES];
        let shader = gpu::wgsl::Shader::new("ray tracer", TRACER_WGSL)
            .importing(&imports)
            .with_defs(defs);
        scene::shader_of(ctx, shader)
    }
}

impl GpuTracer {
    /// Builds the tracer of `scene` (the BVH at `time`).
    pub fn new(
        ctx: &Context,
        scene: &Scene,
        time: f32,
        settings: TracerSettings,
        traversal: Traversal,
    ) -> TechniqueResult<Self> {
        let usable = marched_volumes(scene);
        if usable > MAX_VOLUMES {
            return Err(TechniqueError::Unsupported(format!(
                "the ray tracer marches at most {MAX_VOLUMES} volumes; this scene has {usable}"
            )));
        }
        let device = &ctx.device;
        let storage = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | usage,
            })
        };
        let empty = wgpu::BufferUsages::empty();
        let dst = wgpu::BufferUsages::COPY_DST;
        let layout = tracer_layout(ctx, traversal);
        let module = traversal.shader(ctx);
        let pipeline = |entry: &str| gpu::compute::pipeline(ctx, entry, &[&layout], &module, entry);
        let (eye_pipeline, photon_pipeline) = (pipeline("eye_pass"), pipeline("photon_pass"));
        let emitters = Self::emitters_of(scene, time, 1);
        let tables = Tables::new(scene, time, &emitters);
        let stats = storage(
            "ray tracer stats",
            &[0u8; 16],
            wgpu::BufferUsages::COPY_SRC | dst,
        );
        let stats_readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ray tracer stats read-back"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | dst,
            mapped_at_creation: false,
        });
        let placeholder = |label: &str| storage(label, &[0u8; 16], dst);
        let mut tracer = Self {
            settings,
            params: Uniform::new(ctx, "ray tracer params", &ParamsGpu::zeroed()),
            structure: Structure::Bvh {
                nodes: placeholder("bvh nodes"),
            },
            triangles: placeholder("bvh triangles"),
            attributes: placeholder("bvh attributes"),
            tables: storage("ray tracer tables", bytemuck::cast_slice(&tables.data), dst),
            texture_data: storage(
                "ray tracer texture data",
                bytemuck::cast_slice(&texture_data(scene)),
                empty,
            ),
            radiance: placeholder("eye radiance"),
            photon_sum: placeholder("photon sum"),
            stats,
            stats_readback,
            group: placeholder_group(ctx),
            resolve: Resolve::new(ctx, gpu::TargetFormats::HDR, false),
            last_frame: ResolveParamsGpu::zeroed(),
            layout,
            eye_pipeline,
            photon_pipeline,
            pixels: 0,
            accumulated: None,
            bvh_time: f32::NAN,
            moves: geometry_moves(scene),
            traversal,
            bvh_build_seconds: 0.0,
            triangle_count: 0,
        };
        tracer.build_geometry(ctx, scene, time)?;
        Ok(tracer)
    }

    pub fn settings(&self) -> TracerSettings {
        self.settings
    }

    pub fn set_settings(&mut self, settings: TracerSettings) {
        self.settings = settings;
        self.accumulated = None;
    }

    /// The emission cones and discs for `photons` photons (each gets at least one photon).
    fn emitters_of(scene: &Scene, time: f32, photons: u64) -> Vec<Emitter> {
        emitters(scene, time, &caustic_casters(scene), photons.max(1))
    }

    /// The scene's triangles at `time` for the traversal: the BVH built on the CPU (timed
    /// apart, `bvh_build_seconds`), or the vertices of the hardware's BLAS (built on the GPU in
    /// the next frame).
    fn build_geometry(&mut self, ctx: &Context, scene: &Scene, time: f32) -> TechniqueResult<()> {
        match self.traversal {
            Traversal::Bvh => self.build_bvh(ctx, scene, time),
            Traversal::RayQuery => self.build_ray_query_geometry(ctx, scene, time),
        }
    }

    /// Uploads every world triangle in scene order and (re)creates the BLAS and TLAS over them.
    fn build_ray_query_geometry(
        &mut self,
        ctx: &Context,
        scene: &Scene,
        time: f32,
    ) -> TechniqueResult<()> {
        let world = WorldTriangles::of(scene, time);
        if world.triangles.is_empty() {
            return Err(TechniqueError::Unsupported(
                "hardware ray queries need at least one triangle in the scene".into(),
            ));
        }
        let flat = FlatBvh::in_scene_order(world);
        self.triangle_count = flat.triangles.len();
        let vertices: Vec<[f32; 3]> = flat
            .triangles
            .iter()
            .flat_map(|t| {
                let v0 = t.v0;
                [v0.into(), (v0 - t.e1).into(), (v0 + t.e2).into()]
            })
            .collect();
        let device = &ctx.device;
        let vertex_bytes: &[u8] = bytemuck::cast_slice(&vertices);
        if let Structure::RayQuery {
            vertices: buffer,
            stale,
            ..
        } = &mut self.structure
            && buffer.size() == vertex_bytes.len() as u64
        {
            // Same triangle count: new positions, the same structures rebuilt next frame.
            ctx.queue.write_buffer(buffer, 0, vertex_bytes);
            ctx.queue.write_buffer(
                &self.triangles,
                0,
                bytemuck::cast_slice(&flat.triangle_gpu()),
            );
            ctx.queue.write_buffer(
                &self.attributes,
                0,
                bytemuck::cast_slice(&flat.attributes_gpu()),
            );
            *stale = true;
            self.bvh_time = time;
            return Ok(());
        }
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: usage | wgpu::BufferUsages::COPY_DST,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        self.triangles = init(
            "ray query triangles",
            bytemuck::cast_slice(&flat.triangle_gpu()),
            storage,
        );
        self.attributes = init(
            "ray query attributes",
            bytemuck::cast_slice(&flat.attributes_gpu()),
            storage,
        );
        let vertices = init(
            "ray query vertices",
            vertex_bytes,
            wgpu::BufferUsages::BLAS_INPUT,
        );
        let size = wgpu::BlasTriangleGeometrySizeDescriptor {
            vertex_format: wgpu::VertexFormat::Float32x3,
            vertex_count: (3 * flat.triangles.len()) as u32,
            index_format: None,
            index_count: None,
            flags: geometry_flags(scene),
        };
        let blas = device.create_blas(
            &wgpu::CreateBlasDescriptor {
                label: Some("scene blas"),
                flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                update_mode: wgpu::AccelerationStructureUpdateMode::Build,
            },
            wgpu::BlasGeometrySizeDescriptors::Triangles {
                descriptors: vec![size.clone()],
            },
        );
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("scene tlas"),
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
            max_instances: 1,
        });
        const IDENTITY: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        tlas[0] = Some(wgpu::TlasInstance::new(&blas, IDENTITY, 0, 0xff));
        self.structure = Structure::RayQuery {
            vertices,
            size,
            blas,
            tlas,
            stale: true,
        };
        self.bvh_time = time;
        self.pixels = 0; // the bind group names the new structures
        Ok(())
    }

    /// Records the build of the hardware's structures when their vertices changed.
    fn build_acceleration_structures(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Structure::RayQuery {
            vertices,
            size,
            blas,
            tlas,
            stale,
        } = &mut self.structure
            && *stale
        {
            encoder.build_acceleration_structures(
                std::iter::once(&wgpu::BlasBuildEntry {
                    blas,
                    geometry: wgpu::BlasGeometries::TriangleGeometries(vec![
                        wgpu::BlasTriangleGeometry {
                            size,
                            vertex_buffer: vertices,
                            first_vertex: 0,
                            vertex_stride: 12,
                            index_buffer: None,
                            first_index: None,
                            transform_buffer: None,
                            transform_buffer_offset: None,
                        },
                    ]),
                }),
                std::iter::once(&*tlas),
            );
            *stale = false;
        }
    }

    /// Builds and uploads the BVH of `scene` at `time` (on the CPU, timed apart).
    fn build_bvh(&mut self, ctx: &Context, scene: &Scene, time: f32) -> TechniqueResult<()> {
        let start = Instant::now();
        let bvh = FlatBvh::from_triangles(WorldTriangles::of(scene, time)).map_err(|e| {
            TechniqueError::Unsupported(format!(
                "the scene's BVH is {} levels deep, more than the GPU traversal's stack of {}",
                e.depth,
                crate::bvh::STACK_SIZE
            ))
        })?;
        self.bvh_build_seconds = start.elapsed().as_secs_f64();
        self.triangle_count = bvh.triangles.len();
        let device = &ctx.device;
        let init = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        if bvh.nodes.is_empty() {
            // An inner root whose two children bound nothing: every ray misses.
            let empty = NodeGpu {
                min: [f32::MAX; 3],
                max: [f32::MIN; 3],
                ..Default::default()
            };
            let root = NodeGpu {
                first: 1,
                ..Default::default()
            };
            self.structure = Structure::Bvh {
                nodes: init("bvh nodes", bytemuck::cast_slice(&[root, empty, empty])),
            };
            self.triangles = init("bvh triangles", &[0u8; 64]);
            self.attributes = init("bvh attributes", &[0u8; 96]);
        } else {
            let triangles = bvh.triangle_gpu();
            let attributes = bvh.attributes_gpu();
            let contents: [&[u8]; 3] = [
                bytemuck::cast_slice(&bvh.nodes),
                bytemuck::cast_slice(&triangles),
                bytemuck::cast_slice(&attributes),
            ];
            if let Structure::Bvh { nodes } = &self.structure {
                let buffers = [nodes, &self.triangles, &self.attributes];
                if buffers
                    .iter()
                    .zip(&contents)
                    .all(|(b, c)| b.size() == c.len() as u64)
                {
                    // A rigidly moving object keeps the tree's shape: rewrite in place.
                    for (b, c) in buffers.iter().zip(&contents) {
                        ctx.queue.write_buffer(b, 0, c);
                    }
                    self.bvh_time = time;
                    return Ok(());
                }
            }
            self.structure = Structure::Bvh {
                nodes: init("bvh nodes", contents[0]),
            };
            self.triangles = init("bvh triangles", contents[1]);
            self.attributes = init("bvh attributes", contents[2]);
        }
        self.bvh_time = time;
        self.pixels = 0; // the bind group names the new buffers
        Ok(())
    }

    /// (Re)allocates the per-pixel buffers for `pixels` and rebuilds the bind group.
    fn ensure_pixels(&mut self, ctx: &Context, pixels: u64) {
        if self.pixels == pixels {
            return;
        }
        self.accumulated = None;
        let device = &ctx.device;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        self.radiance = buffer("eye radiance", pixels * 16, wgpu::BufferUsages::empty());
        self.photon_sum = buffer("photon sum", pixels * 24, wgpu::BufferUsages::COPY_DST);
        self.group = bind::group(
            ctx,
            "ray tracer",
            &self.layout,
            &[
                self.params.binding(),
                match &self.structure {
                    Structure::Bvh { nodes } => nodes.as_entire_binding(),
                    Structure::RayQuery { tlas, .. } => {
                        wgpu::BindingResource::AccelerationStructure(tlas)
                    }
                },
                self.triangles.as_entire_binding(),
                self.attributes.as_entire_binding(),
                self.texture_data.as_entire_binding(),
                self.tables.as_entire_binding(),
                self.radiance.as_entire_binding(),
                self.photon_sum.as_entire_binding(),
                self.stats.as_entire_binding(),
            ],
        );
        self.resolve.bind(ctx, &self.radiance, &self.photon_sum);
        self.pixels = pixels;
    }

    /// Photons one frame traces for a `width` x `height` image.
    pub fn photons(&self, width: u32, height: u32) -> u64 {
        match self.settings.photons {
            None => 0,
            Some(0) => photons_for_image(width, height).div_ceil(FRAME_SHARE),
            Some(n) => n.min(MAX_PHOTONS),
        }
    }

    /// Which frame of `view` this is (0: the first, whose photon sum starts empty), noted.
    fn next_frame_of(&mut self, view: &View) -> u32 {
        let k = match self.accumulated {
            Some((v, n)) if v == *view => n,
            _ => 0,
        };
        self.accumulated = Some((*view, k + 1));
        k
    }

    /// Records one frame of `view` into `target`.
    pub fn record(
        &mut self,
        frame: &mut Frame,
        scene: &Scene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        self.trace(frame, scene, view, (target.width, target.height))?;
        let params = self.last_frame;
        frame.span("resolve", |frame| {
            let color = &target.color_view;
            self.resolve
                .draw(frame.gpu, frame.encoder, &params, color, None);
        });
        Ok(())
    }

    /// Records the eye pass and the light pass of one `width` x `height` frame of `view` (the
    /// photon sum adds up the frames of an unchanged view); its resolve is the caller's.
    pub(crate) fn trace(
        &mut self,
        frame: &mut Frame,
        scene: &Scene,
        view: &View,
        (width, height): (u32, u32),
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if self.moves && self.bvh_time != view.time {
            self.build_geometry(ctx, scene, view.time)?;
        }
        check_pixel_buffers(ctx, width, height)?;
        self.ensure_pixels(ctx, width as u64 * height as u64);
        let photons = self.photons(width, height);
        let k = self.next_frame_of(view);
        let emitters = if photons > 0 {
            Self::emitters_of(scene, view.time, photons)
        } else {
            Vec::new()
        };
        let traced: u64 = emitters.iter().map(|e| e.photons).sum();
        let tables = Tables::new(scene, view.time, &emitters);
        let size = (tables.data.len() * 16) as u64;
        if size > self.tables.size() {
            return Err(TechniqueError::Unsupported(
                "the scene's tables grew after prepare()".into(),
            ));
        }
        ctx.queue
            .write_buffer(&self.tables, 0, bytemuck::cast_slice(&tables.data));
        let row_threads = PHOTON_ROW_WORKGROUPS * PHOTON_WORKGROUP;
        self.params.write(
            ctx,
            &params_of(
                &view.camera,
                width,
                height,
                self.settings,
                &tables,
                [traced as u32, frame_seed(self.settings.seed, k)],
                row_threads,
                scene,
            ),
        );
        // The photon sum holds k + 1 frames' estimates: their mean is the image's.
        let projection = view.camera.projection(width as f32 / height as f32);
        self.last_frame = ResolveParamsGpu::new((width, height), traced > 0, k + 1, &projection);
        if matches!(self.structure, Structure::RayQuery { stale: true, .. }) {
            frame.span("build", |frame| {
                self.build_acceleration_structures(frame.encoder);
            });
        }
        frame.encoder.clear_buffer(&self.stats, 0, None);
        if k == 0 {
            frame.encoder.clear_buffer(&self.photon_sum, 0, None);
        }

        frame.span("eye", |frame| {
            let mut pass = frame.encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.eye_pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(
                width.div_ceil(EYE_WORKGROUP),
                height.div_ceil(EYE_WORKGROUP),
                1,
            );
        });
        if traced > 0 {
            frame.span("photons", |frame| {
                let groups = (traced as u32).div_ceil(PHOTON_WORKGROUP);
                let (x, y) = (
                    groups.min(PHOTON_ROW_WORKGROUPS),
                    groups.div_ceil(PHOTON_ROW_WORKGROUPS),
                );
                let mut pass = frame.encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.photon_pipeline);
                pass.set_bind_group(0, &self.group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            });
        }
        let encoder = &mut *frame.encoder;
        encoder.copy_buffer_to_buffer(&self.stats, 0, &self.stats_readback, 0, 16);
        Ok(())
    }

    /// The buffers the last frame traced into (eye radiance with each pixel's first-hit depth,
    /// and the photon sum) and how its resolve reads them.
    pub(crate) fn last_frame(&self) -> (&wgpu::Buffer, &wgpu::Buffer, ResolveParamsGpu) {
        (&self.radiance, &self.photon_sum, self.last_frame)
    }

    /// Draws the last frame's eye pass alone (its Whitted image, no photons) into `target`:
    /// record it after that frame's submission (it rewrites the resolve's parameters, which
    /// the next frame sets again).
    pub fn resolve_eye_only(&self, frame: &mut Frame, target: &Target) {
        let params = ResolveParamsGpu {
            size: [target.width, target.height, 0, 1],
            ..self.last_frame
        };
        let color = &target.color_view;
        self.resolve
            .draw(frame.gpu, frame.encoder, &params, color, None);
    }

    /// The rays the last recorded frame cast (after its submission finished).
    pub fn ray_counts(&self, ctx: &Context) -> Result<RayCounts, gpu::GpuError> {
        let slice = self.stats_readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        ctx.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu::GpuError::ReadBack(e.to_string()))?;
        let counts: [u32; 4] = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| gpu::GpuError::ReadBack(e.to_string()))?;
            *bytemuck::from_bytes(&data[..16])
        };
        self.stats_readback.unmap();
        Ok(RayCounts {
            camera: counts[0] as u64,
            shadow: counts[1] as u64,
            photon: counts[2] as u64,
            photons_stored: counts[3] as u64,
        })
    }
}

/// The per-pixel buffers a `width` x `height` frame binds (the photon sum, 24 bytes a pixel, is
/// the larger) must fit the device's storage binding limit: a sentence instead of a validation
/// panic on a renderer's device with default limits (128 MiB: about 2560 x 2160).
fn check_pixel_buffers(ctx: &Context, width: u32, height: u32) -> TechniqueResult<()> {
    let bytes = width as u64 * height as u64 * 24;
    let limits = ctx.device.limits();
    let limit = (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size);
    if bytes <= limit {
        return Ok(());
    }
    Err(TechniqueError::Unsupported(format!(
        "the ray tracer's photon sum for {width}x{height} is {} MiB, over this device's \
         storage binding limit of {} MiB: request a device with a higher \
         max_storage_buffer_binding_size (the adapter's own limit), or trace a smaller view",
        bytes >> 20,
        limit >> 20
    )))
}

fn placeholder_group(ctx: &Context) -> wgpu::BindGroup {
    let layout = bind::layout(ctx, "placeholder", wgpu::ShaderStages::COMPUTE, &[]);
    bind::group(ctx, "placeholder", &layout, &[])
}

#[allow(clippy::too_many_arguments)]
fn params_of(
    camera: &Camera,
    width: u32,
    height: u32,
    settings: TracerSettings,
    tables: &Tables,
    [photons, seed]: [u32; 2],
    row_threads: u32,
    scene: &Scene,
) -> ParamsGpu {
    let (forward, right, up) = camera.basis();
    // The view's half height: on the image plane at unit distance, or in the world.
    let (pinhole, half) = match camera.orthographic {
        Some(h) => (0.0, h),
        None => (1.0, (camera.fov_y_deg.to_radians() * 0.5).tan()),
    };
    let aspect = width as f32 / height as f32;
    ParamsGpu {
        eye: camera.eye.extend(pinhole).to_array(),
        forward: forward.extend(half).to_array(),
        right: right.extend(aspect).to_array(),
        up: up.extend(camera.film(width, height).pixel_area).to_array(),
        view_proj: camera.view_proj(width, height).to_cols_array_2d(),
        size: [width, height, settings.max_depth, 0],
        counts: tables.counts,
        offsets: tables.offsets,
        photons: [photons, seed, tables.texture_table, tables.srgb_table],
        background: scene.background.extend(row_threads as f32).to_array(),
        medium: Medium::gpu(scene.medium.as_ref()),
    }
}

/// The BLAS geometry's flags: opaque unless an object is cut out, when the shader must see each
/// candidate hit (`raytracer::ray_query::trace`).
fn geometry_flags(scene: &Scene) -> wgpu::AccelerationStructureGeometryFlags {
    if scene.objects.iter().any(|o| o.material.cutout().is_some()) {
        wgpu::AccelerationStructureGeometryFlags::empty()
    } else {
        wgpu::AccelerationStructureGeometryFlags::OPAQUE
    }
}

/// The tracer's bindings: its parameters, the BVH (or the scene's acceleration structure),
/// the cut-outs and texels, the scene's tables, and the radiance, photon and statistics
/// accumulators.
fn tracer_layout(ctx: &Context, traversal: Traversal) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "ray tracer",
        wgpu::ShaderStages::COMPUTE,
        &[
            bind::uniform(),          // params
            traversal.binding_type(), // bvh_nodes or scene_tlas
            bind::storage(true),      // bvh_triangles
            bind::storage(true),      // bvh_attributes
            bind::storage(true),      // texture_data
            bind::storage(true),      // tables
            bind::storage(false),     // radiance
            bind::storage(false),     // photon_sum
            bind::storage(false),     // stats
        ],
    )
}
