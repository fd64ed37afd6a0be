//! HDR render targets and read-back.

use crate::GpuError;

/// The colour format every technique renders its final image into: linear radiance.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Depth format for every depth buffer in the workspace.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The colour and depth formats of the targets a pass draws into: a renderer's own
/// ([`TargetFormats::new`]) or the harness's ([`TargetFormats::HDR`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormats {
    /// The colour attachment's format.
    pub color: wgpu::TextureFormat,
    /// The depth attachment's format.
    pub depth: wgpu::TextureFormat,
    /// Whether a pass leaves the colour's alpha as it was (a renderer's targets) or writes it
    /// (the harness's, whose alpha holds the surface's distance).
    pub keep_alpha: bool,
}

impl TargetFormats {
    /// The harness's targets: linear radiance in [`HDR_FORMAT`], depth in [`DEPTH_FORMAT`].
    pub const HDR: Self = Self {
        color: HDR_FORMAT,
        depth: DEPTH_FORMAT,
        keep_alpha: false,
    };

    /// A renderer's own formats: `color` renderable, `depth` a depth format; its alpha is kept.
    pub const fn new(color: wgpu::TextureFormat, depth: wgpu::TextureFormat) -> Self {
        Self {
            color,
            depth,
            keep_alpha: true,
        }
    }

    /// Whether `ctx`'s device can draw into targets of these formats: an error naming the
    /// format it cannot render into, or the depth format that has no depth.
    pub fn check(&self, ctx: &crate::Context) -> Result<(), GpuError> {
        let renderable = |format| {
            let usages = ctx.format_features(format).allowed_usages;
            usages.contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        };
        if !renderable(self.color) || self.color.has_depth_aspect() {
            return Err(GpuError::InvalidInput(format!(
                "this device cannot render colour into {:?}",
                self.color
            )));
        }
        if !self.depth.has_depth_aspect() || !renderable(self.depth) {
            return Err(GpuError::InvalidInput(format!(
                "{:?} is not a depth format this device renders into (Depth32Float, \
                 Depth24Plus, Depth16Unorm are)",
                self.depth
            )));
        }
        Ok(())
    }

    /// The colour target state of a pass that draws opaque surfaces into these targets: every
    /// channel in the harness's (whose alpha holds the surface's distance), rgb only in a
    /// renderer's own, whose alpha stays what the renderer wrote.
    pub fn color_target(&self) -> Option<wgpu::ColorTargetState> {
        let write_mask = if self.keep_alpha {
            wgpu::ColorWrites::COLOR
        } else {
            wgpu::ColorWrites::ALL
        };
        Some(wgpu::ColorTargetState {
            format: self.color,
            blend: None,
            write_mask,
        })
    }
}

/// A linear RGBA float image read back from the GPU (row 0 is the top).
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGBA, row by row from the top, `width * height` entries.
    pub pixels: Vec<[f32; 4]>,
}

impl HdrImage {
    /// A black, transparent image of `width` x `height` pixels.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 4]; (width * height) as usize],
        }
    }
    /// The pixel in column `x` of row `y` (row 0 is the top).
    pub fn get(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }
    /// Sets the pixel in column `x` of row `y`.
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
    /// The image as sRGB8 RGB (alpha dropped), rows tightly packed, row 0 the top: each
    /// channel through [`channel_to_srgb8`]. What every PNG of the workspace holds and FLIP
    /// reads.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]].map(channel_to_srgb8))
            .collect()
    }
}

/// sRGB transfer function of a linear value (IEC 61966-2-1), input already in [0, 1].
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// One linear channel to an sRGB byte: clamp to [0, 1] (NaN counts as 0, +inf as 1), sRGB
/// transfer, round to nearest. No tone mapping, so PNGs of two renderers compare.
pub fn channel_to_srgb8(v: f32) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (linear_to_srgb(v) * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8
}

/// The colour + depth pair a technique renders a frame into: [`Target::new`] makes both
/// textures, [`Target::from_textures`] wraps textures an application made itself.
pub struct Target {
    /// Width in pixels (of both textures).
    pub width: u32,
    /// Height in pixels (of both textures).
    pub height: u32,
    /// The colour texture ([`HDR_FORMAT`]): linear radiance.
    pub color: wgpu::Texture,
    /// The view a technique renders the colour into (mip level 0).
    pub color_view: wgpu::TextureView,
    /// The depth texture ([`DEPTH_FORMAT`]).
    pub depth: wgpu::Texture,
    /// The view a technique renders the depth into (mip level 0).
    pub depth_view: wgpu::TextureView,
}

impl Target {
    /// A colour target of [`HDR_FORMAT`] (usable as attachment, copy source and destination,
    /// sampled and storage texture) and a [`depth_texture`] of [`DEPTH_FORMAT`], both
    /// `width` x `height` (checked against the device limit).
    ///
    /// A device that cannot give the memory is a [`GpuError::OutOfMemory`], not a panic.
    pub fn new(ctx: &crate::Context, width: u32, height: u32) -> Result<Self, GpuError> {
        ctx.check_size(width, height)?;
        let megabytes = (width as f64 * height as f64 * 20.0 / 1e6).ceil();
        let what = format!("a {width}x{height} target ({megabytes} MB)");
        ctx.allocating(&what, || Self::create(ctx, width, height))
    }

    fn create(ctx: &crate::Context, width: u32, height: u32) -> Self {
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
        Self {
            width,
            height,
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            color,
            depth,
        }
    }

    /// Wraps a colour and a depth texture that the application created itself (its own
    /// render target, which it then samples, copies or presents as it likes).
    ///
    /// `color` must have the format [`HDR_FORMAT`] (linear radiance) and `depth`
    /// [`DEPTH_FORMAT`]; both must be 2D, one array layer, one sample, of the same width and
    /// height, and usable as `RENDER_ATTACHMENT` (the mip level 0 is rendered into). Anything
    /// else is an error naming what is wrong, not a validation panic in a later frame.
    ///
    /// Usages the techniques need beyond `RENDER_ATTACHMENT` on both textures:
    ///
    /// | usage | on | needed by |
    /// | --- | --- | --- |
    /// | `COPY_SRC` | colour | [`Target::read`] (checked there) |
    /// | `TEXTURE_BINDING` | depth | `volumes` ray-traced variants with `free_depth = 1` (they sample the depth the scene pass wrote) |
    /// | `COPY_DST` | colour | the CPU reference (`truth`'s `reference` technique, `scene::foundation::upload_image`) |
    ///
    /// Every other technique (`impostors/*`, `interior-mapping/*`, the other `volumes/*`,
    /// `raster`, `envmap/classic`) only renders into the two attachments.
    pub fn from_textures(color: wgpu::Texture, depth: wgpu::Texture) -> Result<Self, GpuError> {
        let bad = |what: String| Err(GpuError::InvalidInput(what));
        if color.format() != HDR_FORMAT {
            return bad(format!(
                "the colour texture of a Target has format {:?}, not {HDR_FORMAT:?} (gpu::HDR_FORMAT)",
                color.format()
            ));
        }
        if depth.format() != DEPTH_FORMAT {
            return bad(format!(
                "the depth texture of a Target has format {:?}, not {DEPTH_FORMAT:?} (gpu::DEPTH_FORMAT)",
                depth.format()
            ));
        }
        for (name, t) in [("colour", &color), ("depth", &depth)] {
            if t.dimension() != wgpu::TextureDimension::D2
                || t.depth_or_array_layers() != 1
                || t.sample_count() != 1
            {
                return bad(format!(
                    "the {name} texture of a Target must be 2D with one layer and one sample, \
                     not {:?} with {} layers and {} samples",
                    t.dimension(),
                    t.depth_or_array_layers(),
                    t.sample_count()
                ));
            }
            if !t.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
                return bad(format!(
                    "the {name} texture of a Target lacks the RENDER_ATTACHMENT usage (it has {:?})",
                    t.usage()
                ));
            }
        }
        if (color.width(), color.height()) != (depth.width(), depth.height()) {
            return bad(format!(
                "the colour texture of a Target is {}x{} but its depth texture is {}x{}",
                color.width(),
                color.height(),
                depth.width(),
                depth.height()
            ));
        }
        let level0 = wgpu::TextureViewDescriptor {
            mip_level_count: Some(1),
            ..Default::default()
        };
        Ok(Self {
            width: color.width(),
            height: color.height(),
            color_view: color.create_view(&level0),
            depth_view: depth.create_view(&level0),
            color,
            depth,
        })
    }

    /// Copies the colour attachment back to the CPU (the colour texture needs `COPY_SRC`).
    pub fn read(&self, ctx: &crate::Context) -> Result<HdrImage, GpuError> {
        if !self.color.usage().contains(wgpu::TextureUsages::COPY_SRC) {
            return Err(GpuError::InvalidInput(format!(
                "cannot read the Target back: its colour texture lacks the COPY_SRC usage (it has {:?})",
                self.color.usage()
            )));
        }
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
    render_texture(
        ctx,
        label,
        (width, height, layers),
        DEPTH_FORMAT,
        wgpu::TextureUsages::COPY_SRC,
    )
}

/// A 2D texture of `(width, height, layers)` in `format` that passes render into and shaders
/// sample (render attachment + texture binding), with `extra` usages (`COPY_SRC` to read it
/// back): the maps a technique renders once and reads later.
pub fn render_texture(
    ctx: &crate::Context,
    label: &str,
    (width, height, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
    extra: wgpu::TextureUsages,
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
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | extra,
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

#[cfg(test)]
mod tests {
    use super::*;

    fn texture(
        ctx: &crate::Context,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("test"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    fn message(result: Result<Target, GpuError>) -> String {
        match result {
            Ok(_) => panic!("accepted a bad pair of textures"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn from_textures_checks_formats_sizes_and_usages() {
        let ctx = crate::Context::new().expect("a GPU adapter (lavapipe will do)");
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = |size, format, usage| texture(&ctx, size, format, usage);
        let depth = |size| texture(&ctx, size, DEPTH_FORMAT, attach);

        let ok = Target::from_textures(
            color((8, 4), HDR_FORMAT, attach | wgpu::TextureUsages::COPY_SRC),
            depth((8, 4)),
        )
        .expect("a valid pair");
        assert_eq!((ok.width, ok.height), (8, 4));
        assert_eq!(ok.read(&ctx).expect("read back").pixels.len(), 32);

        let e = message(Target::from_textures(
            color((8, 4), wgpu::TextureFormat::Rgba8Unorm, attach),
            depth((8, 4)),
        ));
        assert!(e.contains("Rgba8Unorm") && e.contains("HDR_FORMAT"), "{e}");
        let e = message(Target::from_textures(
            color((8, 4), HDR_FORMAT, attach),
            texture(&ctx, (8, 4), HDR_FORMAT, attach),
        ));
        assert!(e.contains("DEPTH_FORMAT"), "{e}");
        let e = message(Target::from_textures(
            color((8, 4), HDR_FORMAT, attach),
            depth((4, 8)),
        ));
        assert!(e.contains("8x4") && e.contains("4x8"), "{e}");
        let e = message(Target::from_textures(
            color((8, 4), HDR_FORMAT, wgpu::TextureUsages::TEXTURE_BINDING),
            depth((8, 4)),
        ));
        assert!(e.contains("RENDER_ATTACHMENT"), "{e}");

        let unreadable = Target::from_textures(color((8, 4), HDR_FORMAT, attach), depth((8, 4)))
            .expect("COPY_SRC is only needed to read back");
        let e = unreadable.read(&ctx).expect_err("no COPY_SRC").to_string();
        assert!(e.contains("COPY_SRC"), "{e}");
    }
}
