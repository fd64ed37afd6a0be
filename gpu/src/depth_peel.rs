//! Depth peeling: N layers of depth + normal of a triangle set seen from a camera.
//!
//! Layer 0 holds the nearest surface at each pixel, layer k the nearest surface strictly
//! behind layer k-1: pass k compares each fragment's clip depth with layer k-1's depth texture
//! (read with `textureLoad`) and discards it unless it lies more than
//! [`DepthPeeler::epsilon`] behind, then keeps the nearest survivor with an ordinary depth test.
//! Both faces are drawn (no culling), so a closed object gives its front and back surfaces in
//! successive layers.
//!
//! Per layer the peeler produces, in two 2D-array textures with one array layer per peel layer:
//!
//! - colour ([`DepthPeeler::FORMAT`], `Rgba32Float`): `xyz` = the interpolated vertex normal,
//!   normalised, in world space and as stored in the mesh (not flipped toward the viewer, so a
//!   closed mesh with outward normals gives outward normals on back surfaces too); `w` = the
//!   Euclidean distance from the eye to the surface point (not the clip depth). Empty texels
//!   are `(0, 0, 0, 0)`: a visible surface always has `w > 0`.
//! - depth ([`crate::DEPTH_FORMAT`]): the clip-space depth in [0, 1] of the same fragment; empty
//!   texels hold the clear value 1.
//!
//! Vertices are [`crate::Vertex`] in world space (there is no model matrix) and indices `u32`.

use glam::{Mat4, Vec3};

use crate::{Context, GpuError, Vertex};

const SHADER: &str = r#"
struct Peel {
    view_proj: mat4x4f,
    eye: vec4f,
    layer: u32,
    epsilon: f32,
};

@group(0) @binding(0) var<uniform> peel: Peel;
@group(0) @binding(1) var previous_depth: texture_depth_2d;

struct PeelVertex {
    @invariant @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
};

@vertex
fn peel_vs(@location(0) position: vec3f, @location(1) normal: vec3f) -> PeelVertex {
    var out: PeelVertex;
    out.clip = peel.view_proj * vec4f(position, 1.0);
    out.world = position;
    out.normal = normal;
    return out;
}

@fragment
fn peel_fs(in: PeelVertex) -> @location(0) vec4f {
    if (peel.layer > 0u) {
        // Keep only what lies strictly behind the previous layer (an empty texel there holds
        // depth 1, so everything is discarded and this layer stays empty too).
        let previous = textureLoad(previous_depth, vec2i(in.clip.xy), 0);
        if (in.clip.z <= previous + peel.epsilon) {
            discard;
        }
    }
    return vec4f(normalize(in.normal), distance(in.world, peel.eye.xyz));
}
"#;

/// The uniform block of one peel pass (matches `Peel` in the shader).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PeelUniforms {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    layer: u32,
    epsilon: f32,
    _pad: [u32; 2],
}

/// Renders `layers` depth layers of a mesh; see the module documentation for what each layer
/// holds. Create once per size and layer count, then call [`DepthPeeler::peel`] per frame.
pub struct DepthPeeler {
    width: u32,
    height: u32,
    layers: u32,
    epsilon: f32,
    color: wgpu::Texture,
    depth: wgpu::Texture,
    color_layer_views: Vec<wgpu::TextureView>,
    depth_layer_views: Vec<wgpu::TextureView>,
    color_array_view: wgpu::TextureView,
    depth_array_view: wgpu::TextureView,
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    uniform_stride: u64,
    bind_groups: Vec<wgpu::BindGroup>,
}

impl DepthPeeler {
    /// Format of the normal + distance layers.
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
    /// Default separation in clip depth between successive layers: a few ulps of depth
    /// values near 1. Re-rasterising the same triangle gives bit-identical depth (the position
    /// is `@invariant`), so this only guards against drivers that differ between passes.
    pub const DEFAULT_EPSILON: f32 = 2e-7;

    /// Creates the layer textures (`width` x `height`, `layers` array layers) and the pipeline.
    /// Fails on a size over the adapter's limits or a layer count of 0 or over
    /// `max_texture_array_layers`.
    pub fn new(ctx: &Context, width: u32, height: u32, layers: u32) -> Result<Self, GpuError> {
        ctx.check_size(width, height)?;
        let max_layers = ctx.device.limits().max_texture_array_layers;
        if layers == 0 || layers > max_layers {
            return Err(GpuError::InvalidInput(format!(
                "depth peeling needs 1 to {max_layers} layers on this adapter, not {layers}"
            )));
        }
        ctx.validated(|| Self::create(ctx, width, height, layers))
    }

    fn create(ctx: &Context, width: u32, height: u32, layers: u32) -> Self {
        let device = &ctx.device;
        let color = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth peel layers"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: Self::FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let depth = crate::depth_texture(ctx, width, height, layers, "depth peel depth");
        // Layer 0 compares against nothing, but its bind group still needs a depth view.
        let unused_depth = crate::depth_texture(ctx, 1, 1, 1, "depth peel unused depth");
        let array_view = |texture: &wgpu::Texture| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("depth peel layers"),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let color_layer_views: Vec<_> = (0..layers).map(|l| crate::layer_view(&color, l)).collect();
        let depth_layer_views: Vec<_> = (0..layers).map(|l| crate::layer_view(&depth, l)).collect();

        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("depth peel"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<PeelUniforms>() as u64,
                        ),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let size = std::mem::size_of::<PeelUniforms>() as u64;
        let align = device.limits().min_uniform_buffer_offset_alignment as u64;
        let uniform_stride = size.div_ceil(align) * align;
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("depth peel uniforms"),
            size: uniform_stride * layers as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let unused_depth_view = unused_depth.create_view(&Default::default());
        let bind_groups = (0..layers)
            .map(|l| {
                let previous = if l == 0 {
                    &unused_depth_view
                } else {
                    &depth_layer_views[l as usize - 1]
                };
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("depth peel layer"),
                    layout: &bind_group_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &uniforms,
                                offset: l as u64 * uniform_stride,
                                size: wgpu::BufferSize::new(size),
                            }),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(previous),
                        },
                    ],
                })
            })
            .collect();

        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("depth peel"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("depth peel"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("depth peel"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("peel_vs"),
                compilation_options: Default::default(),
                buffers: &[Some(Vertex::layout())],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: crate::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("peel_fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: Self::FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });

        Self {
            width,
            height,
            layers,
            epsilon: Self::DEFAULT_EPSILON,
            color_array_view: array_view(&color),
            depth_array_view: array_view(&depth),
            color,
            depth,
            color_layer_views,
            depth_layer_views,
            pipeline,
            uniforms,
            uniform_stride,
            bind_groups,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of layers peeled by [`DepthPeeler::peel`].
    pub fn layers(&self) -> u32 {
        self.layers
    }

    /// Clip-depth separation required between successive layers.
    pub fn epsilon(&self) -> f32 {
        self.epsilon
    }

    /// Sets the clip-depth separation between layers (default [`Self::DEFAULT_EPSILON`]);
    /// surfaces closer than this behind a layer are skipped.
    pub fn set_epsilon(&mut self, epsilon: f32) {
        self.epsilon = epsilon;
    }

    /// Records the `layers` peel passes into `encoder`. `view_proj` maps world to clip space
    /// with depth in [0, 1] (e.g. `glam::camera::rh::proj::directx::perspective(..) *
    /// glam::camera::rh::view::look_at_mat4(..)`, or `scene`'s `Camera::view_proj`); `eye` is
    /// the camera position that the distances in `w` are measured from. `vertices` holds
    /// [`Vertex`] in world space, `indices` `u32` triangle lists.
    ///
    /// The camera goes through `queue.write_buffer`, which takes effect at the next submit:
    /// submit `encoder` before calling `peel` again on the same peeler.
    #[allow(clippy::too_many_arguments)]
    pub fn peel(
        &self,
        ctx: &Context,
        encoder: &mut wgpu::CommandEncoder,
        vertices: &wgpu::Buffer,
        indices: &wgpu::Buffer,
        index_count: u32,
        view_proj: Mat4,
        eye: Vec3,
    ) -> Result<(), GpuError> {
        if !view_proj.is_finite() || !eye.is_finite() {
            return Err(GpuError::InvalidInput(
                "depth peeling needs a finite view-projection matrix and eye position".into(),
            ));
        }
        if index_count % 3 != 0 || index_count as u64 * 4 > indices.size() {
            return Err(GpuError::InvalidInput(format!(
                "depth peeling draws {index_count} indices, which must be a multiple of 3 and fit \
                 the {}-byte index buffer",
                indices.size()
            )));
        }
        for layer in 0..self.layers {
            let uniforms = PeelUniforms {
                view_proj: view_proj.to_cols_array_2d(),
                eye: eye.extend(1.0).to_array(),
                layer,
                epsilon: self.epsilon,
                _pad: [0; 2],
            };
            ctx.queue.write_buffer(
                &self.uniforms,
                layer as u64 * self.uniform_stride,
                bytemuck::bytes_of(&uniforms),
            );
        }
        for layer in 0..self.layers as usize {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("depth peel layer"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.color_layer_views[layer],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth_layer_views[layer],
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
            if index_count == 0 {
                continue;
            }
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_groups[layer], &[]);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..index_count, 0, 0..1);
        }
        Ok(())
    }

    /// All layers as one `D2Array` view of [`Self::FORMAT`] (normal, distance), for
    /// `texture_2d_array<f32>` bindings (unfilterable: read with `textureLoad` or a
    /// non-filtering sampler).
    pub fn layers_view(&self) -> &wgpu::TextureView {
        &self.color_array_view
    }

    /// All layers' clip depths as one `D2Array` view, for `texture_depth_2d_array` bindings.
    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.depth_array_view
    }

    /// The normal + distance texture (one array layer per peel layer).
    pub fn layers_texture(&self) -> &wgpu::Texture {
        &self.color
    }

    /// The depth texture (one array layer per peel layer).
    pub fn depth_texture(&self) -> &wgpu::Texture {
        &self.depth
    }

    /// Reads one layer back: `[nx, ny, nz, distance]` per pixel, row 0 at the top.
    pub fn read_layer(&self, ctx: &Context, layer: u32) -> Result<Vec<[f32; 4]>, GpuError> {
        self.check_layer(layer)?;
        crate::read_texture_f32x4(ctx, &self.color, layer)
    }

    /// Reads one layer's clip depth back (1 where the layer is empty), row 0 at the top.
    pub fn read_depth(&self, ctx: &Context, layer: u32) -> Result<Vec<f32>, GpuError> {
        self.check_layer(layer)?;
        crate::read_texture_f32(ctx, &self.depth, layer)
    }

    fn check_layer(&self, layer: u32) -> Result<(), GpuError> {
        if layer >= self.layers {
            return Err(GpuError::InvalidInput(format!(
                "layer {layer} does not exist: the peeler has {} layers",
                self.layers
            )));
        }
        Ok(())
    }
}
