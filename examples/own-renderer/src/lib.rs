//! A renderer of its own, as a user's engine has one: its own vertex layout (position, normal,
//! colour), its own WGSL and pipelines, its own camera (glam's right-handed `look_at_mat4`
//! and wgpu-depth `perspective`), its own targets in its own formats (`Rgba8UnormSrgb` colour,
//! `Depth24Plus` depth) and its own device. Into that frame it adds six technique crates'
//! passes:
//!
//! - a glass ball through its distance impostor (`impostors::ImpostorPass`, double
//!   refraction: reflection and refraction through both of its surfaces);
//! - a second glass ball refracted through both interfaces in image space
//!   (`image_space_refraction::RefractorPass`, Hu and Qin's search);
//! - two glass pawns whose rays go from one to the other through their refractor distance
//!   maps (`refractor_maps::RefractorMapsPass`, paths split at up to four interfaces);
//! - a glass pawn stood on a billboard and searched in its refractor height map
//!   (`height_maps::HeightMapPass`, double refraction);
//! - a building whose windows show rooms cast per pixel (`interior_mapping::InteriorPass`,
//!   the thesis's varied rooms, lit by a point light of the renderer's);
//! - a ball of smoke blended over the colour and clipped by the depth buffer
//!   (`volumes::SoftVolumePass`).
//!
//! The glass needs the world seen from the balls and the pawns: the renderer implements
//! `gpu::DrawScene` (draw everything but these objects, with this view, into these targets)
//! with a second pipeline that writes the distance from the view's eye in alpha. Nothing here
//! is a `scene` type, and no GPU timer is kept.
//!
//! `cargo run -p own-renderer` writes `target/examples/own-renderer.png`; its tests (run by
//! `cargo xtask test`) check the image and write the same file.

mod world;

pub use world::{Ball, House, Pawn, World};

use glam::Vec3;
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{DrawScene, EyeView, Frame, SceneView, TargetFormats};
use height_maps::{HeightMapPass, HeightPiece, Refraction};
use image_space_refraction::{Exit, Refractor, RefractorPass};
use impostors::{ImpostorLookup, ImpostorPass, SpecularObject, Surface};
use interior_mapping::{Building, InteriorPass, PointLight, Variant};
use refractor_maps::{Bounces, Piece, RefractorMapsPass};
use volumes::SoftVolumePass;

/// The renderer's colour format: 8-bit sRGB, as a window's swap chain would be.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The renderer's depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;
/// Side of the maps the impostor and the refractor ask the renderer to draw.
const MAP_RESOLUTION: u32 = 128;

/// The renderer's vertex: not the workspace's `gpu::Vertex` (no uv, a colour instead).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    color: [f32; 3],
}

/// The renderer's camera block: world to clip, and the eye (for the maps' distances).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraBlock {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
}

const SHADER: &str = r#"
struct Camera { view_proj: mat4x4f, eye: vec4f }
@group(0) @binding(0) var<uniform> camera: Camera;

struct Out {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) color: vec3f,
}

@vertex
fn vs(@location(0) position: vec3f, @location(1) normal: vec3f, @location(2) color: vec3f) -> Out {
    return Out(camera.view_proj * vec4f(position, 1.0), position, normal, color);
}

// One directional light and an ambient term: the renderer's own shading.
fn shade(in: Out) -> vec3f {
    let light = normalize(vec3f(0.4, 1.0, 0.6));
    let lambert = max(dot(normalize(in.normal), light), 0.0);
    return in.color * (0.25 + 0.75 * lambert);
}

@fragment
fn fs(in: Out) -> @location(0) vec4f {
    return vec4f(shade(in), 1.0);
}

// What a technique asks for (gpu::DrawScene): the same shading, and the distance from the
// view's eye in alpha.
@fragment
fn fs_map(in: Out) -> @location(0) vec4f {
    return vec4f(shade(in), distance(in.world, camera.eye.xyz));
}
"#;

/// Which of the six passes a frame adds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Passes {
    /// The glass ball through its distance impostor.
    pub impostor: bool,
    /// The glass ball of image-space refraction.
    pub refraction: bool,
    /// The two pawns of refractor distance maps.
    pub refractor_maps: bool,
    /// The pawn of refractor height maps.
    pub height_maps: bool,
    /// The building of interior mapping.
    pub interiors: bool,
    /// The smoke.
    pub volumes: bool,
}

impl Passes {
    /// All six.
    pub const ALL: Self = Self {
        impostor: true,
        refraction: true,
        refractor_maps: true,
        height_maps: true,
        interiors: true,
        volumes: true,
    };
    /// None: the renderer's own frame.
    pub const NONE: Self = Self {
        impostor: false,
        refraction: false,
        refractor_maps: false,
        height_maps: false,
        interiors: false,
        volumes: false,
    };
}

/// What can go wrong: one sentence each.
pub type Error = Box<dyn std::error::Error>;

/// The renderer: its device, pipelines, world and targets (which it lends the techniques as
/// [`DrawScene`]), and the six passes it adds.
pub struct Renderer {
    world: WorldGpu,
    impostor: ImpostorPass,
    refractor: RefractorPass,
    refractor_maps: RefractorMapsPass,
    height_maps: HeightMapPass,
    interiors: InteriorPass,
    volumes: SoftVolumePass,
    color: wgpu::Texture,
    depth: wgpu::Texture,
    size: u32,
}

/// The renderer's world on the GPU: what answers a technique's [`DrawScene`] requests.
struct WorldGpu {
    ctx: gpu::Context,
    layout: wgpu::BindGroupLayout,
    /// The frame's pipeline (its formats) and the maps' (`Rgba16Float` with the distance in
    /// alpha, `Depth32Float`: what the techniques ask for).
    frame_pipeline: wgpu::RenderPipeline,
    map_pipeline: (wgpu::TextureFormat, wgpu::RenderPipeline),
    vertices: wgpu::Buffer,
    /// Each opaque object's vertex range, by the renderer's object index.
    ranges: Vec<(usize, std::ops::Range<u32>)>,
}

impl Renderer {
    /// The renderer's own device (any backend this build has, GL aside), its pipelines and
    /// `size` x `size` targets, and the six passes made for its formats.
    pub fn new(world: &World, size: u32) -> Result<Self, Error> {
        let (instance, adapter, device, queue) = pollster::block_on(own_device())?;
        // The one step a technique crate asks of the renderer: wrap its device.
        let ctx = gpu::Context::from_parts(instance, adapter, device, queue)?;
        let formats = TargetFormats::new(COLOR_FORMAT, DEPTH_FORMAT);
        let impostor = SpecularObject {
            mesh: world.impostor.mesh(),
            surface: Surface::Glass { ior: 1.5 },
            host_index: world.impostor.index,
        };
        let mut impostor = ImpostorPass::new(
            &ctx,
            &impostor,
            ImpostorLookup::DoubleRefraction,
            formats,
            MAP_RESOLUTION,
        )?;
        impostor.set_position(world.impostor.center);
        let refractor = Refractor {
            mesh: world.refractor.mesh(),
            ior: 1.5,
            host_index: world.refractor.index,
        };
        let mut refractor =
            RefractorPass::new(&ctx, &refractor, Exit::HuQin, formats, MAP_RESOLUTION)?;
        refractor.set_position(world.refractor.center);
        let refractor_maps = pawns_pass(&ctx, world, Bounces::Multi { depth: 4 }, formats)?;
        let height_pawn = HeightPiece {
            mesh: Pawn::mesh(),
            ior: 1.5,
            host_index: world.height_pawn.index,
            position: world.height_pawn.base,
        };
        let maps = (MAP_RESOLUTION, MAP_RESOLUTION);
        let height_maps =
            HeightMapPass::new(&ctx, &[height_pawn], Refraction::Double, formats, maps)?;
        let interiors = house_pass(&ctx, world, Variant::Varied, formats)?;
        let volumes = SoftVolumePass::new(&ctx, COLOR_FORMAT)?;
        let texture = |label, format, usage| {
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
                format,
                usage,
                view_formats: &[],
            })
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = texture(
            "own colour",
            COLOR_FORMAT,
            attachment | wgpu::TextureUsages::COPY_SRC,
        );
        // The volume pass samples the depth buffer: TEXTURE_BINDING beside the attachment.
        let depth = texture(
            "own depth",
            DEPTH_FORMAT,
            attachment | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        Ok(Self {
            world: WorldGpu::new(ctx, world),
            impostor,
            refractor,
            refractor_maps,
            height_maps,
            interiors,
            volumes,
            color,
            depth,
            size,
        })
    }

    /// Moves the impostor's ball to `center` (its impostor follows in the next frame).
    pub fn move_impostor(&mut self, center: Vec3) {
        self.impostor.set_position(center);
    }

    /// Moves refractor-map pawn `index` (0 or 1) so that its base stands at `base` (its rays
    /// and the environment impostor follow in the next frame).
    pub fn move_pawn(&mut self, index: usize, base: Vec3) {
        self.refractor_maps.set_position_of(index, base);
    }

    /// Moves the height-map pawn so that its base stands at `base`.
    pub fn move_height_pawn(&mut self, base: Vec3) {
        self.height_maps.set_position_of(0, base);
    }

    /// Moves the building so that its corner stands at `corner`.
    pub fn move_house(&mut self, corner: Vec3) {
        self.interiors.set_position_of(0, corner);
    }

    /// The building's rooms shown as `variant` shows them from the next frame on.
    pub fn set_interiors(&mut self, world: &World, variant: Variant) -> Result<(), Error> {
        let formats = TargetFormats::new(COLOR_FORMAT, DEPTH_FORMAT);
        self.interiors = house_pass(&self.world.ctx, world, variant, formats)?;
        Ok(())
    }

    /// The pawns of refractor maps traced as far as `bounces` from the next frame on.
    pub fn set_pawn_bounces(&mut self, world: &World, bounces: Bounces) -> Result<(), Error> {
        let formats = TargetFormats::new(COLOR_FORMAT, DEPTH_FORMAT);
        self.refractor_maps = pawns_pass(&self.world.ctx, world, bounces, formats)?;
        Ok(())
    }

    /// One frame of `world` with `passes`, read back as sRGB8 RGBA rows.
    pub fn frame(&mut self, world: &World, passes: Passes) -> Result<Vec<u8>, Error> {
        let (view, projection) = world.camera();
        let eye = EyeView {
            view,
            projection,
            width: self.size,
            height: self.size,
        };
        let color = self.color.create_view(&Default::default());
        let depth = self.depth.create_view(&Default::default());
        let ctx = &self.world.ctx;
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        // The renderer does not time the techniques: a frame without a timer.
        Frame::untimed(ctx, &mut encoder, |frame| -> Result<(), Error> {
            // The renderer's own frame first: everything opaque, into its own targets.
            let view_frame = SceneView {
                view_proj: eye.view_proj(),
                eye: eye.eye(),
                objects: gpu::Objects::All,
                color: &color,
                color_format: COLOR_FORMAT,
                depth: &depth,
            };
            self.world
                .draw(frame, &view_frame, &self.world.frame_pipeline);
            // Then the techniques' passes, over it: the glass balls (which ask the world of
            // the renderer) and the smoke (which reads its depth).
            if passes.impostor {
                self.impostor
                    .draw(frame, &self.world, &eye, &color, &depth)?;
            }
            if passes.refraction {
                self.refractor
                    .draw(frame, &self.world, &eye, &color, &depth)?;
            }
            if passes.refractor_maps {
                self.refractor_maps
                    .draw(frame, &self.world, &eye, &color, &depth)?;
            }
            if passes.height_maps {
                self.height_maps
                    .draw(frame, &self.world, &eye, &color, &depth)?;
            }
            if passes.interiors {
                self.interiors
                    .draw(frame, &self.world, &eye, &color, &depth)?;
            }
            if passes.volumes {
                self.volumes
                    .draw(frame, &eye, &world.volumes, &color, &depth);
            }
            Ok(())
        })?;
        ctx.queue.submit([encoder.finish()]);
        Ok(gpu::read_texture_bytes(ctx, &self.color, 0, 4)?)
    }
}

/// The interior-mapping pass of `world`'s building, lit by its light.
fn house_pass(
    ctx: &gpu::Context,
    world: &World,
    variant: Variant,
    formats: TargetFormats,
) -> Result<InteriorPass, Error> {
    let house = world.house;
    let building = Building {
        min: Vec3::ZERO,
        max: house.size,
        room_size: house.room,
        facade: Vec3::new(0.55, 0.5, 0.45),
        host_index: house.index,
        position: house.corner,
    };
    let light = PointLight {
        position: world.house_light.0,
        intensity: world.house_light.1,
    };
    Ok(InteriorPass::new(
        ctx,
        &[building],
        &[light],
        variant,
        formats,
        64,
    )?)
}

/// The refractor-map pass of `world`'s two pawns, which share one map (one mesh).
fn pawns_pass(
    ctx: &gpu::Context,
    world: &World,
    bounces: Bounces,
    formats: TargetFormats,
) -> Result<RefractorMapsPass, Error> {
    let pieces: Vec<Piece> = world
        .pawns
        .iter()
        .map(|pawn| Piece {
            mesh: Pawn::mesh(),
            surface: Surface::Glass { ior: 1.5 },
            host_index: pawn.index,
            position: pawn.base,
        })
        .collect();
    let maps = (MAP_RESOLUTION, MAP_RESOLUTION);
    Ok(RefractorMapsPass::new(
        ctx, &pieces, bounces, formats, maps,
    )?)
}

impl WorldGpu {
    fn new(ctx: gpu::Context, world: &World) -> Self {
        let device = &ctx.device;
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("own renderer"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("own camera"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline =
            |entry, formats: TargetFormats| own_pipeline(device, &shader, &layout, entry, formats);
        let frame_pipeline = pipeline("fs", TargetFormats::new(COLOR_FORMAT, DEPTH_FORMAT));
        let map_format = wgpu::TextureFormat::Rgba16Float;
        let map_pipeline = pipeline("fs_map", TargetFormats::new(map_format, gpu::DEPTH_FORMAT));
        let (triangles, ranges) = world.opaque_triangles();
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("own vertices"),
            contents: bytemuck::cast_slice(&triangles),
            usage: wgpu::BufferUsages::VERTEX,
        });
        Self {
            layout,
            frame_pipeline,
            map_pipeline: (map_format, map_pipeline),
            vertices,
            ranges,
            ctx,
        }
    }

    /// Clears `view`'s targets (the background far away) and draws its opaque objects.
    fn draw(&self, frame: &mut Frame, view: &SceneView, pipeline: &wgpu::RenderPipeline) {
        let block = CameraBlock {
            view_proj: view.view_proj.to_cols_array_2d(),
            eye: view.eye.extend(1.0).to_array(),
        };
        // A buffer per view: the six faces of a map are recorded before one submission.
        let device = &self.ctx.device;
        let camera = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("own camera"),
            contents: bytemuck::bytes_of(&block),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("own camera"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera.as_entire_binding(),
            }],
        });
        let background = wgpu::Color {
            r: 0.02,
            g: 0.02,
            b: 0.03,
            a: gpu::host::BACKGROUND_DISTANCE as f64,
        };
        let mut pass = frame
            .encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("own world"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: view.color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(background),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: view.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        for (index, range) in &self.ranges {
            if view.objects.includes(*index) {
                pass.draw(range.clone(), 0..1);
            }
        }
    }
}

/// The renderer's answer to a technique: its world from the view asked, into the targets
/// given, with the distance from the view's eye in alpha (its map pipeline). Its glass balls
/// are the techniques' to draw, so it never draws them.
impl DrawScene for WorldGpu {
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView) {
        let (format, pipeline) = &self.map_pipeline;
        if view.color_format != *format {
            log::error!("own renderer: no map pipeline for {:?}", view.color_format);
            return;
        }
        self.draw(frame, view, pipeline);
    }
}

/// The renderer's own device: the platform's primary backends (Vulkan, Metal, DirectX 12),
/// the first adapter wgpu offers, default features and limits.
async fn own_device() -> Result<(wgpu::Instance, wgpu::Adapter, wgpu::Device, wgpu::Queue), Error> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    let instance = wgpu::Instance::new(desc);
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions::default())
        .await
        .map_err(|_| gpu::GpuError::NoAdapter)?;
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor::default())
        .await?;
    Ok((instance, adapter, device, queue))
}

fn own_pipeline(
    device: &wgpu::Device,
    shader: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    fragment_entry: &str,
    formats: TargetFormats,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("own world"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(fragment_entry),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(vertex_layout)],
        },
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(fragment_entry),
            compilation_options: Default::default(),
            targets: &[Some(formats.color.into())],
        }),
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: formats.depth,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

/// Writes `rgba` (`size` x `size`, sRGB8 RGBA rows) as a PNG, making its folder.
pub fn write_png(path: &std::path::Path, rgba: &[u8], size: u32) -> Result<(), Error> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    image::save_buffer(path, rgba, size, size, image::ExtendedColorType::Rgba8)?;
    Ok(())
}

#[cfg(test)]
mod tests;
