//! The frame's resources that follow the view's size: the LDIs, photon buffers, transfer
//! maps, irradiance buffer and (with a medium) the in-scattering and froxel targets.

use super::*;

/// Size-dependent resources: the LDIs, the irradiance buffer, the photon buffers.
pub(super) struct Sized {
    pub(super) key: (u32, u32),
    pub(super) scene_ldi: DepthPeeler,
    pub(super) refractor_ldi: DepthPeeler,
    pub(super) irradiance: wgpu::TextureView,
    pub(super) photons: PhotonBuffers,
    /// The line buffer: `max_steps` wide, `rows` high.
    pub(super) line_rows: wgpu::TextureView,
    pub(super) line_width: u32,
    pub(super) line_rows_count: u32,
    /// Transfer map targets: origin, direction (transfer.wgsl says what they hold), depth.
    pub(super) transfer: [wgpu::TextureView; 3],
    /// Screen-space visibility of the first four lights per pixel (the `shadows` variant
    /// only).
    pub(super) shadow_mask: Option<wgpu::Buffer>,
    /// The LDI uniform of the last frame (diagnostics).
    pub(super) ldi_params: std::cell::Cell<Option<LdiParamsGpu>>,
    /// The medium's resources (a scene with a scattering medium only).
    pub(super) media: Option<MediaTargets>,
    /// The resolve's beam binding when no beams are kept (one unused beam).
    pub(super) no_beams: wgpu::Buffer,
}

/// What a frame in a scattering medium uses: the in-scattering buffer every variant blends
/// (cleared to nothing for the variants without shafts), and the shafts' own.
pub(super) struct MediaTargets {
    /// In-scattered radiance per pixel (god rays: the bands, then blurred; froxels: the
    /// lookup).
    pub(super) inscatter: wgpu::TextureView,
    /// The blur's intermediate (god rays).
    pub(super) blurred: wgpu::TextureView,
    /// `photons * rounds` beams (god rays, the hybrid froxels), or one unused beam.
    pub(super) beams: wgpu::Buffer,
    /// Froxels: the in-scattering grid of even frames, its integral, the grid of odd frames
    /// (each frame's history is the other's grid), and the hybrid's caustic map (flux,
    /// direction); 1-texel stand-ins for the other variants.
    pub(super) froxels: [wgpu::TextureView; 3],
    pub(super) froxel_grid: [u32; 3],
    pub(super) caustic_maps: [wgpu::TextureView; 2],
    /// Froxels: frames drawn so far (the jitter sequence and the grids' parity) and the last
    /// frame's view, which its grid is reprojected from (`None` before the first frame).
    pub(super) froxel_history: std::cell::Cell<(u32, Option<FroxelView>)>,
}

/// The view a froxel grid was drawn from: what reprojecting it needs.
#[derive(Clone, Copy, Debug)]
pub(super) struct FroxelView {
    pub(super) view_proj: Mat4,
    pub(super) eye: glam::Vec3,
    /// The slices' near and far distances.
    pub(super) near: f32,
    pub(super) far: f32,
}

/// A froxel frame's temporal terms: where in its froxel each sample is taken, how much of it
/// enters the running mean, and the view the history was drawn from.
#[derive(Clone, Copy, Debug)]
pub(super) struct FroxelTemporal {
    /// Position of the sample in its froxel: across, down, in depth (0.5: the centre).
    pub(super) jitter: glam::Vec3,
    /// Weight of this frame's sample (1: the history is not read).
    pub(super) blend: f32,
    pub(super) previous: Option<FroxelView>,
}

impl FroxelTemporal {
    /// The centre, no history (a pass that does not light the grid).
    pub(super) const NONE: Self = Self {
        jitter: glam::Vec3::splat(0.5),
        blend: 1.0,
        previous: None,
    };

    /// Frame `index`'s terms (frames counted from the first of this grid): with a history
    /// (`blend` < 1), the sample moves through its froxel along the Halton (3, 5, 2)
    /// sequence, Wronski's and Hillaire's jitter, and the grid is the running mean of what
    /// each froxel saw, which tends to its average over the froxel: the plain mean of the
    /// frames so far while they are fewer than `1 / blend`, an exponential moving average of
    /// weight `blend` after (a young history is not weighted as a full one); without, the
    /// centre every frame.
    pub(super) fn of_frame(index: u32, previous: Option<FroxelView>, blend: f32) -> Self {
        if blend >= 1.0 {
            return Self::NONE;
        }
        // Index 0 of the sequence is 0: start at 1 so that no frame samples a corner.
        let i = index + 1;
        Self {
            jitter: glam::Vec3::new(halton(i, 3), halton(i, 5), halton(i, 2)),
            blend: blend.max(1.0 / i as f32),
            previous,
        }
    }
}

/// Element `index` of the Halton sequence of `base` (the radical inverse), in [0, 1).
pub(super) fn halton(mut index: u32, base: u32) -> f32 {
    let (mut result, mut fraction) = (0.0, 1.0 / base as f32);
    while index > 0 {
        result += (index % base) as f32 * fraction;
        index /= base;
        fraction /= base as f32;
    }
    result
}

pub(super) struct PhotonBuffers {
    pub(super) count: u32,
    pub(super) photons: wgpu::Buffer,
    pub(super) hits: wgpu::Buffer,
    pub(super) receivers: wgpu::Buffer,
}

/// GPU memory one frame's resources may take together (the LDIs dominate: 36 bytes per pixel
/// and layer, twice).
pub const FRAME_BUDGET_BYTES: u64 = scene::technique::MAP_BUDGET_BYTES;

/// At most this many line batches per march: `rows` is raised to fit (each batch is a render
/// pass and a compute pass).
pub const MAX_LINE_BATCHES: u32 = 256;

impl Sized {
    /// The bytes of a frame's resources at `width` x `height` (`medium`: the scene has a
    /// scattering medium).
    pub fn bytes(
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
        medium: bool,
    ) -> u64 {
        let pixels = width as u64 * height as u64;
        let photons = settings.photons as u64 * settings.photons as u64;
        let ldis = 2 * pixels * settings.layers as u64 * (2 * 16 + 4);
        let per_photon = 48 + 16 + 48 + 2 * 16 + 4;
        let rows = Self::line_rows(settings) as u64 * width.max(height) as u64 * 16;
        let shadows = variant.screen_space_shadows as u64;
        let mut bytes = ldis + pixels * 16 * (1 + shadows) + photons * per_photon + rows;
        if medium {
            bytes += 2 * pixels * 16;
            if variant.shafts.is_some_and(Shafts::from_photons) {
                bytes += photons * (settings.bounces as u64 + 1) * 48;
            }
            if variant.shafts.is_some_and(Shafts::froxels) {
                let [x, y, z] = froxel_grid(settings, (width, height));
                bytes += 3 * (x * y * z) as u64 * 16;
            }
            if variant.shafts == Some(Shafts::FroxelsWithPhotons) {
                bytes += 2 * (settings.caustic_map as u64).pow(2) * 16;
            }
        }
        bytes
    }

    /// Rows of the line buffer: `rows`, raised so that a march takes at most
    /// [`MAX_LINE_BATCHES`] batches, and no more than the photons.
    pub(super) fn line_rows(settings: &Settings) -> u32 {
        let count = settings.photons * settings.photons;
        settings
            .rows
            .max(count.div_ceil(MAX_LINE_BATCHES))
            .min(count)
    }

    pub(super) fn new(
        ctx: &Context,
        scene: &GpuScene,
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
    ) -> TechniqueResult<Self> {
        let shadows = variant.screen_space_shadows;
        let medium = scene.scene.medium.is_some();
        Self::check_fits(ctx, settings, (width, height), variant, medium)?;
        let mask_bytes = width as u64 * height as u64 * 16;
        let mut scene_ldi = DepthPeeler::new(ctx, scene, width, height, settings.layers)?;
        let mut refractor_ldi = DepthPeeler::new(ctx, scene, width, height, settings.layers)?;
        // Without indirect first instances the peelers peel every layer: the same LDI. Any
        // other failure to make the counters is an error.
        if settings.count_layers && scene::layer_count::LayerCounter::available(ctx) {
            scene_ldi.count_layers(ctx, scene)?;
            refractor_ldi.count_layers(ctx, scene)?;
        }
        let grid = settings.photons;
        ctx.check_size(grid, grid)?;
        let count = grid * grid;
        let storage = |label: &str, bytes: u64| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let photons = ctx.allocating("screen-photons buffers", || PhotonBuffers {
            count,
            photons: storage("photons", count as u64 * 48),
            hits: storage("photon hits", count as u64 * 16),
            receivers: storage("receivers", count as u64 * 48),
        })?;
        let line_width = width.max(height);
        let line_rows_count = Self::line_rows(settings);
        ctx.check_size(line_width, line_rows_count)?;
        let texture = |label: &str, w: u32, h: u32, format| {
            gpu::render_texture(ctx, label, (w, h, 1), format, wgpu::TextureUsages::empty())
                .create_view(&Default::default())
        };
        let media = if medium {
            Some(ctx.allocating("screen-photons medium targets", || {
                MediaTargets::new(ctx, settings, (width, height), variant, count)
            })?)
        } else {
            None
        };
        Ok(Self {
            media,
            no_beams: storage("no beams", 48),
            key: (width, height),
            scene_ldi,
            refractor_ldi,
            irradiance: texture("caustic irradiance", width, height, MAP_FORMAT),
            photons,
            line_rows: texture("line rows", line_width, line_rows_count, MAP_FORMAT),
            line_width,
            line_rows_count,
            ldi_params: std::cell::Cell::new(None),
            shadow_mask: shadows.then(|| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("shadow mask"),
                    size: mask_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            }),
            transfer: [
                texture("transfer origin", grid, grid, MAP_FORMAT),
                texture("transfer direction", grid, grid, MAP_FORMAT),
                gpu::depth_texture(ctx, grid, grid, 1, "transfer depth")
                    .create_view(&Default::default()),
            ],
        })
    }

    /// Checks that the frame's resources fit: the whole within the frame budget, the shadow
    /// mask and the photon beams each within the adapter's largest storage binding. A size
    /// that does not fit is an error that says what to lower.
    fn check_fits(
        ctx: &Context,
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
        medium: bool,
    ) -> TechniqueResult<()> {
        let shadows = variant.screen_space_shadows;
        let bytes = Self::bytes(settings, (width, height), variant, medium);
        if bytes > FRAME_BUDGET_BYTES {
            return Err(TechniqueError::OverBudget(format!(
                "screen-photons at {width}x{height} with {} layers and {}^2 photons needs {:.2} GB \
                 of GPU memory, over its {} MB budget: lower the size, `layers` or `photons`",
                settings.layers,
                settings.photons,
                bytes as f64 / 1e9,
                FRAME_BUDGET_BYTES >> 20
            )));
        }
        let max_binding = ctx.device.limits().max_storage_buffer_binding_size as u64;
        let mask_bytes = width as u64 * height as u64 * 16;
        if shadows && mask_bytes > max_binding {
            return Err(TechniqueError::Unsupported(format!(
                "the shadow mask of {width}x{height} pixels ({} MB) is larger than the adapter's \
                 largest storage binding ({} MB): lower the size",
                mask_bytes >> 20,
                max_binding >> 20
            )));
        }
        let beam_bytes = (settings.photons as u64).pow(2) * (settings.bounces as u64 + 1) * 48;
        if medium && variant.shafts.is_some_and(Shafts::from_photons) && beam_bytes > max_binding {
            return Err(TechniqueError::OverBudget(format!(
                "the photon beams of {}^2 photons and {} bounces ({} MB) are larger than the \
                 adapter's largest storage binding ({} MB): lower `photons` or `bounces`",
                settings.photons,
                settings.bounces,
                beam_bytes >> 20,
                max_binding >> 20
            )));
        }
        Ok(())
    }
}

/// The froxel grid at `width` x `height`: tiles across, tiles down, slices.
pub(super) fn froxel_grid(settings: &Settings, (width, height): (u32, u32)) -> [u32; 3] {
    let size = settings.froxel_size.max(1);
    [
        width.div_ceil(size),
        height.div_ceil(size),
        settings.slices.max(1),
    ]
}

impl MediaTargets {
    pub(super) fn new(
        ctx: &Context,
        settings: &Settings,
        (width, height): (u32, u32),
        variant: &Variant,
        photons: u32,
    ) -> Self {
        let texture = |label: &str, (w, h): (u32, u32)| {
            gpu::render_texture(
                ctx,
                label,
                (w, h, 1),
                MAP_FORMAT,
                wgpu::TextureUsages::empty(),
            )
            .create_view(&Default::default())
        };
        let beams = if variant.shafts.is_some_and(Shafts::from_photons) {
            photons as u64 * (settings.bounces as u64 + 1)
        } else {
            1
        };
        let froxels = variant.shafts.is_some_and(Shafts::froxels);
        let grid = if froxels {
            froxel_grid(settings, (width, height))
        } else {
            [1, 1, 1]
        };
        let volume = |label: &str| {
            ctx.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: grid[0],
                        height: grid[1],
                        depth_or_array_layers: grid[2],
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D3,
                    format: MAP_FORMAT,
                    usage: wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let map = if variant.shafts == Some(Shafts::FroxelsWithPhotons) {
            settings.caustic_map
        } else {
            1
        };
        Self {
            inscatter: texture("in-scattering", (width, height)),
            blurred: texture("in-scattering blur", (width, height)),
            beams: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("photon beams"),
                size: beams * 48,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            froxels: [
                volume("froxel scattering (even frames)"),
                volume("froxel integral"),
                volume("froxel scattering (odd frames)"),
            ],
            froxel_grid: grid,
            froxel_history: Default::default(),
            caustic_maps: [
                texture("caustic map flux", (map, map)),
                texture("caustic map direction", (map, map)),
            ],
        }
    }
}
