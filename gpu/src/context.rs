//! The one headless wgpu context every technique, the harness and the tests share.
//!
//! Adapter choice: `WGPU_BACKEND` selects backends (default the platform's primary ones,
//! Vulkan, Metal or DirectX 12, of those the application's wgpu was built with; not GL, because
//! wgpu would otherwise fall back silently to GL on llvmpipe, which lacks `FLOAT32_FILTERABLE`
//! and `Rgba32Float` targets); `WGPU_ADAPTER_NAME` picks an adapter by case-insensitive substring;
//! otherwise a discrete GPU is preferred, then an integrated one, then anything else, and a
//! software adapter (lavapipe) last.
//!
//! An application that owns its wgpu device (an engine using one technique crate) does not
//! let the context choose: it wraps its own instance, adapter, device and queue with
//! [`Context::from_parts`]. Both constructors end in the same code (adapter summary, shared
//! samplers, the `Rgba32Float` render check).

use crate::GpuError;

/// Features we use when the adapter has them; none is strictly required by the context itself.
/// Techniques declare what they need through [`Context::require`].
const WANTED_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::FLOAT32_FILTERABLE)
    .union(wgpu::Features::FLOAT32_BLENDABLE)
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    .union(wgpu::Features::SHADER_FLOAT32_ATOMIC)
    .union(wgpu::Features::TEXTURE_ATOMIC)
    .union(wgpu::Features::IMMEDIATES)
    .union(wgpu::Features::PIPELINE_CACHE)
    .union(wgpu::Features::INDIRECT_FIRST_INSTANCE);

/// What a user sees about the adapter in every results table.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    /// The adapter's name (`llvmpipe (LLVM 15.0.6, 256 bits)`, a GPU's product name).
    pub name: String,
    /// The backend, lower case (`vulkan`, `metal`, `dx12`, `gl`).
    pub backend: String,
    /// `DiscreteGpu`, `IntegratedGpu`, `VirtualGpu`, `Cpu` or `Other`.
    pub device_type: String,
    /// Driver name and version, as the adapter reports them.
    pub driver: String,
    /// Whether the adapter is a software rasterizer (lavapipe): timings are then CPU timings.
    pub is_software: bool,
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({}, {})", self.name, self.backend, self.device_type)
    }
}

/// The shared GPU context: adapter, device and queue, plus what the adapter can do.
pub struct Context {
    /// The instance the adapter came from.
    pub instance: wgpu::Instance,
    /// The adapter the device was created on.
    pub adapter: wgpu::Adapter,
    /// The device every resource of the workspace is created on.
    pub device: wgpu::Device,
    /// The device's queue: every submission and upload.
    pub queue: wgpu::Queue,
    /// What results tables print about the adapter.
    pub summary: AdapterSummary,
    /// The shared samplers, made once with the device.
    pub samplers: crate::bind::Samplers,
    /// The cache every pipeline of the workspace is made with ([`Context::pipeline_cache`]).
    pipeline_cache: Option<wgpu::PipelineCache>,
}

/// What the last dropped device's pipeline cache held, by adapter: a fresh device of the same
/// adapter ([`Context::fresh_device`]) starts from it, so a pipeline made on one device is not
/// compiled again on the next.
static PIPELINE_DATA: std::sync::Mutex<Option<(String, Vec<u8>)>> = std::sync::Mutex::new(None);

impl Context {
    /// Creates the context on the best adapter (see the module documentation).
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        desc.flags = wgpu::InstanceFlags::from_env_or_default();
        let instance = wgpu::Instance::new(desc);
        let adapters = instance.enumerate_adapters(backends).await;
        let wanted_name = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .map(|s| s.to_lowercase());
        let adapter = choose_adapter(adapters, wanted_name.as_deref())?;

        let (device, queue) = request_device(&adapter).await?;
        Self::from_parts(instance, adapter, device, queue)
    }

    /// A new device (and queue) on this context's adapter, with the same features and limits,
    /// and nothing else shared: what a run uses to give each measurement a driver in its first
    /// state (`harness compare --device per-row`). Mesa 22.3's lavapipe keeps megabytes for
    /// every descriptor set a draw binds until its device is dropped (see the harness's README,
    /// "Cost"); a device costs 25-55 ms to create there.
    pub fn fresh_device(&self) -> Result<Self, GpuError> {
        let (device, queue) = pollster::block_on(request_device(&self.adapter))?;
        Self::from_parts(self.instance.clone(), self.adapter.clone(), device, queue)
    }

    /// Wraps a device the application created itself: what an engine that already owns its
    /// wgpu instance, adapter, device and queue passes to this workspace's crates (see
    /// `impostors/examples/standalone.rs`). Computes the same [`AdapterSummary`] and shared
    /// samplers as [`Context::new`], which ends here too.
    ///
    /// Use [`Context::new`] when this workspace may choose the adapter (the harness, the
    /// tests): it honours `WGPU_BACKEND` and `WGPU_ADAPTER_NAME`, prefers a hardware adapter,
    /// and turns on every optional feature the adapter has that the workspace uses
    /// (timestamps, 32-bit float filtering and blending, ...). Use `from_parts` in your own
    /// renderer: the device keeps exactly the features and limits you requested, so request at
    /// least the technique's `scene::Technique::required_features()` (a technique checks what
    /// it needs with [`Context::require`]); [`GpuTimer`](crate::GpuTimer) falls back to
    /// wall-clock times without `TIMESTAMP_QUERY`.
    ///
    /// `device` and `queue` must come from `adapter`, and `adapter` from `instance`. Fails,
    /// with one sentence, when the adapter cannot render into [`HDR_FORMAT`](crate::HDR_FORMAT)
    /// targets (OpenGL on llvmpipe, for example), which every technique renders into.
    pub fn from_parts(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Result<Self, GpuError> {
        let info = adapter.get_info();
        let hdr = adapter.get_texture_format_features(crate::HDR_FORMAT);
        if !hdr
            .allowed_usages
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        {
            return Err(GpuError::Device(format!(
                "adapter {} ({:?}) cannot render into {:?} targets, which every technique \
                 renders into; use a Vulkan, Metal or DX12 adapter",
                info.name,
                info.backend,
                crate::HDR_FORMAT
            )));
        }
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend).to_lowercase(),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info),
            is_software: info.device_type == wgpu::DeviceType::Cpu,
        };
        let samplers = crate::bind::Samplers::new(&device);
        let pipeline_cache = pipeline_cache(&device, &info);
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            summary,
            samplers,
            pipeline_cache,
        })
    }

    /// The pipeline cache of this device, where the adapter has one (wgpu's `PIPELINE_CACHE`,
    /// Vulkan): every pipeline the workspace makes passes it, and the data it gathers carries
    /// over to the next device made on the same adapter in this process.
    pub fn pipeline_cache(&self) -> Option<&wgpu::PipelineCache> {
        self.pipeline_cache.as_ref()
    }

    /// The features the device was created with.
    pub fn features(&self) -> wgpu::Features {
        self.device.features()
    }

    /// Whether GPU timestamps can bracket passes on this device.
    /// What this device can do with `format`: the adapter's own answer where the device
    /// enabled `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`, else what WebGPU guarantees with
    /// the device's features (`FLOAT32_BLENDABLE` makes `Rgba32Float` blendable, say).
    pub fn format_features(&self, format: wgpu::TextureFormat) -> wgpu::TextureFormatFeatures {
        let features = self.features();
        if features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
            self.adapter.get_texture_format_features(format)
        } else {
            format.guaranteed_format_features(features)
        }
    }

    pub fn has_timestamps(&self) -> bool {
        self.features().contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Fails with a sentence naming the missing features, so the harness can skip a technique
    /// on an adapter without them and say why.
    pub fn require(&self, features: wgpu::Features) -> Result<(), GpuError> {
        let missing = features - self.features();
        if missing.is_empty() {
            Ok(())
        } else {
            Err(GpuError::MissingFeatures(
                format!("{missing:?}"),
                self.summary.name.clone(),
            ))
        }
    }

    /// Checks a requested 2D image size against the device limit.
    pub fn check_size(&self, width: u32, height: u32) -> Result<(), GpuError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(GpuError::SizeOverLimit { width, height, max });
        }
        Ok(())
    }

    /// Blocks until all submitted work is done.
    pub fn wait(&self) {
        // An error here means the device was lost; the next call surfaces it properly.
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }

    /// Runs `f`, which creates resources, with out-of-memory and validation errors captured:
    /// a texture or buffer the device cannot give is a [`GpuError::OutOfMemory`] naming
    /// `what`, never the default handler's panic.
    pub fn allocating<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let out_of_memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        let invalid = pollster::block_on(validation.pop());
        if let Some(err) = pollster::block_on(out_of_memory.pop()) {
            return Err(GpuError::OutOfMemory(format!("{what}: {err}")));
        }
        match invalid {
            Some(err) => Err(GpuError::Validation(format!("{what}: {err}"))),
            None => Ok(value),
        }
    }

    /// Runs `f` with validation and out-of-memory errors captured, turning them into a
    /// `GpuError` instead of the default handler's panic (every step `scene::runner` records,
    /// a technique's prepare and frames included, runs inside it).
    pub fn validated<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        self.allocating("recorded work", f)
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        let key = wgpu::util::pipeline_cache_key(&self.adapter.get_info());
        if let (Some(cache), Some(key)) = (&self.pipeline_cache, key)
            && let Some(data) = cache.get_data()
            && let Ok(mut shared) = PIPELINE_DATA.lock()
        {
            *shared = Some((key, data));
        }
    }
}

/// A pipeline cache for `device` (None without the feature), from the data the last device of
/// the same adapter left.
fn pipeline_cache(device: &wgpu::Device, info: &wgpu::AdapterInfo) -> Option<wgpu::PipelineCache> {
    if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
        return None;
    }
    let key = wgpu::util::pipeline_cache_key(info)?;
    let shared = PIPELINE_DATA.lock().ok()?;
    let data = shared
        .as_ref()
        .filter(|(k, _)| *k == key)
        .map(|(_, data)| data.as_slice());
    // SAFETY: `data` came from `PipelineCache::get_data` of a device of an adapter with the same
    // `pipeline_cache_key` in this process (the driver validates it too, and `fallback` makes
    // an empty cache of data it does not take).
    Some(unsafe {
        device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
            label: Some("workspace pipelines"),
            data,
            fallback: true,
        })
    })
}

fn adapter_rank(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

fn choose_adapter(
    adapters: Vec<wgpu::Adapter>,
    wanted_name: Option<&str>,
) -> Result<wgpu::Adapter, GpuError> {
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter);
    }
    let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
    let mut candidates: Vec<wgpu::Adapter> = match wanted_name {
        Some(wanted) => adapters
            .into_iter()
            .filter(|a| a.get_info().name.to_lowercase().contains(wanted))
            .collect(),
        None => adapters,
    };
    if candidates.is_empty() {
        return Err(GpuError::NoNamedAdapter(
            wanted_name.unwrap_or_default().to_string(),
            names.join(", "),
        ));
    }
    candidates.sort_by_key(|a| adapter_rank(a.get_info().device_type));
    Ok(candidates.remove(0))
}

/// The device [`Context::new`] asks `adapter` for: every feature of [`WANTED_FEATURES`] the
/// adapter has, ray queries where offered, and the adapter's own limits.
async fn request_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue), GpuError> {
    let features = adapter.features() & WANTED_FEATURES;
    // Hardware ray queries (the exact ray tracer's `ray-query` variant) are one of wgpu's
    // experimental features, which a device only gets after opting in; we opt in exactly
    // when the adapter offers ray queries, so no other device changes.
    let ray_queries = adapter
        .features()
        .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
    let (features, experimental_features) = if ray_queries {
        // SAFETY: the opt-in acknowledges that wgpu's experimental ray-query API may still
        // have bugs; only the ray tracer's ray-query variant uses it, and its images are
        // tested against the reference (raytracer/tests/images.rs).
        (features | wgpu::Features::EXPERIMENTAL_RAY_QUERY, unsafe {
            wgpu::ExperimentalFeatures::enabled()
        })
    } else {
        (features, wgpu::ExperimentalFeatures::disabled())
    };
    // The adapter's own limits: big cube maps and storage buffers on real GPUs, and
    // `check_size` reports the true bound to the user.
    let limits = adapter.limits();
    adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("shared device"),
            required_features: features,
            required_limits: limits,
            experimental_features,
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        })
        .await
        .map_err(|e| GpuError::Device(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An application's own device, wrapped: the same summary as `Context::new` on the same
    /// adapter, exactly the requested features, and a target renders and reads back on it.
    #[test]
    fn from_parts_wraps_an_application_device() {
        let shared = Context::new().expect("a GPU adapter (lavapipe will do)");
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::PRIMARY))
            .into_iter()
            .find(|a| a.get_info().name == shared.summary.name)
            .expect("the shared context's adapter");
        let (device, queue) =
            pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default()))
                .expect("a device with default features and limits");
        let ctx = Context::from_parts(instance, adapter, device, queue).expect("wrapped");
        assert_eq!(ctx.summary.name, shared.summary.name);
        assert_eq!(ctx.summary.backend, shared.summary.backend);
        assert_eq!(ctx.summary.driver, shared.summary.driver);
        assert_eq!(ctx.summary.is_software, shared.summary.is_software);
        assert!(ctx.features().is_empty(), "exactly the features requested");
        let target = crate::Target::new(&ctx, 4, 4).expect("a target on the wrapped device");
        assert_eq!(target.read(&ctx).expect("read back").pixels.len(), 16);
    }
}
