//! HDR render targets and read-back.

use crate::GpuError;

/// The colour format every technique renders its final image into: linear radiance.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Depth format for every depth buffer in the workspace.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A linear RGBA float image read back from the GPU (row 0 is the top).
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl HdrImage {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 4]; (width * height) as usize],
        }
    }
    pub fn get(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }
    pub fn set(&mut self, x: u32, y: u32, value: [f32; 4]) {
        self.pixels[(y * self.width + x) as usize] = value;
    }
    /// Number of pixels with a NaN or infinite channel: always a defect to report.
    pub fn non_finite_count(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|c| !c.is_finite()))
            .count()
    }
}

/// The colour + depth pair a technique renders a frame into.
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
}

impl Target {
    pub fn new(ctx: &crate::Context, width: u32, height: u32) -> Result<Self, GpuError> {
        ctx.check_size(width, height)?;
        let color = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("target colour"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HDR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        let depth = depth_texture(ctx, width, height, 1, "target depth");
        Ok(Self {
            width,
            height,
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            color,
            depth,
        })
    }

    /// Copies the colour attachment back to the CPU.
    pub fn read(&self, ctx: &crate::Context) -> Result<HdrImage, GpuError> {
        let texels = read_texture_f32x4(ctx, &self.color, 0)?;
        Ok(HdrImage {
            width: self.width,
            height: self.height,
            pixels: texels,
        })
    }
}

/// A sampled depth texture (also usable as attachment), `layers` array layers.
pub fn depth_texture(
    ctx: &crate::Context,
    width: u32,
    height: u32,
    layers: u32,
    label: &str,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A single-layer 2D view of array layer `layer`: how a layer of an array or cube texture
/// is used as a render attachment.
pub fn layer_view(texture: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

/// Reads one array layer of an `Rgba32Float` (or any 16-byte-texel) texture; handles the
/// 256-byte row alignment of buffer copies.
pub fn read_texture_f32x4(
    ctx: &crate::Context,
    texture: &wgpu::Texture,
    layer: u32,
) -> Result<Vec<[f32; 4]>, GpuError> {
    let bytes = read_texture_bytes(ctx, texture, layer, 16)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Reads one array layer of a single-channel 32-bit texture (`R32Float`, `Depth32Float`).
pub fn read_texture_f32(
    ctx: &crate::Context,
    texture: &wgpu::Texture,
    layer: u32,
) -> Result<Vec<f32>, GpuError> {
    let bytes = read_texture_bytes(ctx, texture, layer, 4)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Raw texel bytes of one layer, rows tightly packed.
pub fn read_texture_bytes(
    ctx: &crate::Context,
    texture: &wgpu::Texture,
    layer: u32,
    bytes_per_texel: u32,
) -> Result<Vec<u8>, GpuError> {
    let (width, height) = (texture.width(), texture.height());
    let unpadded = width * bytes_per_texel;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let padded = unpadded.div_ceil(align) * align;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: (padded * height) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let aspect = if texture.format().is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([encoder.finish()]);
    let data = map_buffer(ctx, &buffer)?;
    let mut out = Vec::with_capacity((unpadded * height) as usize);
    for row in data.chunks(padded as usize) {
        out.extend_from_slice(&row[..unpadded as usize]);
    }
    Ok(out)
}

/// Maps a `MAP_READ` buffer and copies its bytes out.
pub fn map_buffer(ctx: &crate::Context, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.wait();
    rx.recv()
        .map_err(|_| GpuError::ReadBack("map callback never ran".into()))?
        .map_err(|e| GpuError::ReadBack(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::ReadBack(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Copies a storage buffer into a fresh mappable buffer and reads it back.
pub fn read_buffer(ctx: &crate::Context, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back staging"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    ctx.queue.submit([encoder.finish()]);
    map_buffer(ctx, &staging)
}
