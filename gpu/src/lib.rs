//! The shared GPU layer of the workspace: one headless wgpu [`Context`] with its shared
//! samplers, bind-group lists ([`bind`]), one-line attachments and passes ([`pass`]), the
//! per-frame recording context [`Frame`], HDR render targets and read-back, cube-map targets,
//! the distance-map search `Hit()` ([`distance_map`], Rust twin of `shaders/hit.wgsl`), a
//! full-screen pass, GPU timers (optional: `GpuTimer::off`), what a technique asks of the
//! renderer that hosts it ([`host`]: `DrawScene`, `EyeView`, `HostedMesh`), the formats a pass
//! draws into ([`TargetFormats`]), and the WGSL prelude (with its Rust twin in [`prelude`])
//! that every technique's shaders include.

pub mod bind;
pub mod compute;
mod context;
pub mod cube;
pub mod distance_map;
pub mod fullscreen;
pub mod host;
pub mod pass;
pub mod prelude;
mod target;
mod timer;
pub mod wgsl;

pub use bind::{Samplers, Uniform};
pub use context::{AdapterSummary, Context};
pub use host::{DrawScene, EyeView, HostedMesh, Objects, SceneView};
pub use target::{
    DEPTH_FORMAT, HDR_FORMAT, HdrImage, Target, TargetFormats, channel_to_srgb8, depth_texture,
    layer_view, linear_to_srgb, map_buffer, read_buffer, read_texture_bytes, read_texture_f32,
    read_texture_f32x4, render_texture,
};
pub use timer::{GpuTimer, TimeStats, TimerKind};
pub use wgpu;

/// The per-frame GPU recording context: the harness opens the encoder and times it; a
/// technique records passes into it and may bracket named parts (for example "regenerate")
/// with the timer so they are reported apart from the frame.
pub struct Frame<'a> {
    pub gpu: &'a Context,
    pub encoder: &'a mut wgpu::CommandEncoder,
    pub timer: &'a mut GpuTimer,
}

impl Frame<'_> {
    /// Records `passes` into `encoder` with a timer that measures nothing ([`GpuTimer::off`]):
    /// how a renderer that does not time a technique hands it a frame.
    pub fn untimed<R>(
        gpu: &Context,
        encoder: &mut wgpu::CommandEncoder,
        passes: impl FnOnce(&mut Frame<'_>) -> R,
    ) -> R {
        let mut timer = GpuTimer::off();
        passes(&mut Frame {
            gpu,
            encoder,
            timer: &mut timer,
        })
    }

    /// Records `passes` inside the timer span `label` (an encoder-level span, reported apart
    /// from the frame): the span's end cannot be forgotten or misnamed, and a span opened in a
    /// branch closes in it. Passes that time themselves (`GpuTimer::render_pass`) may nest
    /// inside.
    pub fn span<R>(&mut self, label: &str, passes: impl FnOnce(&mut Self) -> R) -> R {
        self.timer.begin(self.encoder, label);
        let result = passes(self);
        self.timer.end(self.encoder, label);
        result
    }
}

/// Everything that can go wrong in the GPU layer, each as one sentence a user can act on.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("no GPU adapter found: {}", no_adapter_advice())]
    NoAdapter,
    #[error("no adapter name contains \"{0}\" (WGPU_ADAPTER_NAME); adapters found: {1}")]
    NoNamedAdapter(String, String),
    #[error("could not create the GPU device: {0}")]
    Device(String),
    #[error("adapter {1} lacks required features {0}")]
    MissingFeatures(String, String),
    #[error(
        "image size {width}x{height} is outside this adapter's limit (1 to {max} pixels per side)"
    )]
    SizeOverLimit { width: u32, height: u32, max: u32 },
    #[error("GPU read-back failed: {0}")]
    ReadBack(String),
    #[error("GPU validation error: {0}")]
    Validation(String),
    #[error("invalid input: {0}")]
    InvalidInput(String),
    #[error("the GPU is out of memory: {0}")]
    OutOfMemory(String),
}

/// What to do when no adapter is found, for the platform this runs on and the backends this
/// build of wgpu has (a library crate asks wgpu for none: the binary chooses).
pub fn no_adapter_advice() -> String {
    let compiled = wgpu::Instance::enabled_backend_features();
    if compiled.is_empty() {
        return "this build of wgpu has no backend: enable wgpu's `vulkan`, `metal`, `dx12` or \
                `gles` feature in the application's Cargo.toml (the libraries ask for none)"
            .into();
    }
    let platform = if cfg!(target_os = "macos") {
        "wgpu found no Metal device; Metal needs macOS 10.13 or later and wgpu's `metal` \
         feature in the application's Cargo.toml"
    } else if cfg!(target_os = "windows") {
        "wgpu could load neither a DirectX 12 nor a Vulkan driver; update the GPU driver, or \
         set WGPU_BACKEND=gl to try OpenGL"
    } else {
        "wgpu could not load a Vulkan driver; on Debian/Ubuntu install the Mesa software \
         driver with `sudo apt-get install mesa-vulkan-drivers libvulkan1` (or run `cargo xtask \
         test`, which does it), or set WGPU_BACKEND=gl to try OpenGL"
    };
    format!("{platform} (backends in this build: {compiled:?})")
}

/// The vertex layout shared by the scene upload and every technique: position, shading
/// normal, texture coordinate.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

impl Vertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];

    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// The modules of `gpu` every shader may import without naming them: `gpu::prelude`,
/// `gpu::fullscreen`, `gpu::distance_map` and `gpu::layered_distance_map`.
pub(crate) fn gpu_modules() -> [&'static wgsl::Module; 4] {
    [
        &prelude::PRELUDE,
        &fullscreen::FULLSCREEN,
        &distance_map::HIT,
        distance_map::hit_layered(),
    ]
}

/// Composes `shader` (its own WGSL and the modules it imports, see [`wgsl`]) into a wgpu
/// shader module. The shaders are part of the program: one that does not compose is a bug,
/// reported with the composer's message (file, line and text).
pub fn shader(ctx: &Context, shader: wgsl::Shader<'_>) -> wgpu::ShaderModule {
    let module = wgsl::compose(&shader)
        .unwrap_or_else(|message| panic!("shader {}: {message}", shader.label));
    ctx.device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shader.label),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        })
}
