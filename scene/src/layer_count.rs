//! The depth complexity of a view, counted on the GPU to choose how many layers to peel
//! (Krüger, Bürger and Westermann, "Interactive Screen-Space Accurate Photon Tracing on GPUs",
//! EGSR 2006, section 2.2: "The depth complexity can be determined by rendering the object
//! once and by counting at each pixel the number of fragments falling into it during
//! scan-conversion. The maximum over all pixels is then collected by a texture reduce-max
//! operation.").
//!
//! Three passes, all on the GPU, no read-back:
//!
//! 1. *Count*: the selected objects drawn once with both faces and no depth test; each fragment
//!    adds one to its pixel's counter (`count_fs`).
//! 2. *Reduce-max*: every pixel's count folded into one maximum (`max_main`).
//! 3. *Arguments*: the peel passes draw through an indirect buffer, one block of draw
//!    arguments per layer; `args_main` gives every draw of layer `l` one instance when `l` is
//!    below the maximum and none otherwise, so the passes past the view's depth complexity
//!    draw nothing (they still clear their layer: it reads as empty).
//!
//! The count is the number of surfaces at a pixel, which is what peeling finds there (both
//! faces drawn; surfaces closer together than the peeler's epsilon count twice but peel once,
//! so the count can only be higher: never a layer too few). The indirect draws name the object
//! as their first instance, which needs the adapter's `INDIRECT_FIRST_INSTANCE`; without it
//! [`LayerCounter::new`] says so and the peeler peels every layer.

use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, GpuError, Uniform, bind};

use crate::{GpuScene, ObjectFilter, scene_pipeline_with};

/// The counter's bindings, at `@group(#{COUNT_GROUP})`: the same four buffers for the count's
/// fragment stage and the two compute passes; the module `scene::layer_count` ([`BINDINGS`]).
const BINDINGS_WGSL: &str = r#"#define_import_path scene::layer_count

struct CountParams {
    width: u32,
    height: u32,
    layers: u32,
    draws: u32,
};

@group(#{COUNT_GROUP}) @binding(0) var<uniform> count_params: CountParams;
@group(#{COUNT_GROUP}) @binding(1) var<storage, read_write> counts: array<atomic<u32>>;
@group(#{COUNT_GROUP}) @binding(2) var<storage, read_write> complexity: array<atomic<u32>>;
@group(#{COUNT_GROUP}) @binding(3) var<storage, read_write> args: array<u32>;
"#;

/// [`BINDINGS_WGSL`] as a module, which the count and the reduce import.
static BINDINGS: gpu::wgsl::Module =
    gpu::wgsl::Module::new(BINDINGS_WGSL, "scene/src/layer_count.rs", &[]);

/// A shader of the counter, its bindings at `@group(group)`.
fn counter_shader(ctx: &Context, label: &str, source: &str, group: u32) -> wgpu::ShaderModule {
    let (defs, imports) = (
        [("COUNT_GROUP", gpu::wgsl::Def::UInt(group))],
        [&crate::SHADING, &BINDINGS],
    );
    let shader = gpu::wgsl::Shader::new(label, source).importing(&imports);
    gpu::shader(ctx, shader.with_defs(&defs))
}

const COUNT_WGSL: &str = r#"
#import scene::shading::{SceneVertexOut, in_cutout_hole}
#import scene::layer_count::{count_params, counts}
// Every fragment of every selected surface, whatever its depth, adds one to its pixel (but
// for an alpha cut-out's holes, which no layer holds).
@fragment
fn count_fs(in: SceneVertexOut) {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let pixel = vec2u(in.clip.xy);
    atomicAdd(&counts[pixel.y * count_params.width + pixel.x], 1u);
}
"#;

const REDUCE_WGSL: &str = r#"
#import scene::layer_count::{args, complexity, count_params, counts}
// The texture reduce-max of the paper, as one atomic maximum per covered pixel. The
// invocations stride over the pixels: a dispatch has at most 65 535 workgroups, fewer than
// 4K images have groups of 64 pixels.
@compute @workgroup_size(64)
fn max_main(
    @builtin(global_invocation_id) id: vec3u,
    @builtin(num_workgroups) groups: vec3u,
) {
    let pixels = count_params.width * count_params.height;
    for (var i = id.x; i < pixels; i += groups.x * 64u) {
        let c = atomicLoad(&counts[i]);
        if (c > 0u) { atomicMax(&complexity[0], c); }
    }
}

// Draw i of layer l (arguments at (l * draws + i) * 5): one instance below the maximum.
@compute @workgroup_size(64)
fn args_main(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= count_params.layers * count_params.draws) { return; }
    let layer = id.x / count_params.draws;
    args[id.x * 5u + 1u] = select(0u, 1u, layer < atomicLoad(&complexity[0]));
}
"#;

/// Most workgroups the reduce-max dispatches (the WebGPU limit per dimension); its
/// invocations stride over the pixels beyond.
const MAX_GROUPS: u32 = 65_535;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CountParams {
    width: u32,
    height: u32,
    layers: u32,
    draws: u32,
}

/// Counts a view's depth complexity and writes the peel passes' indirect draws: see the module
/// documentation.
pub struct LayerCounter {
    width: u32,
    height: u32,
    layers: u32,
    draws: u32,
    counts: wgpu::Buffer,
    complexity: wgpu::Buffer,
    args: wgpu::Buffer,
    _params: Uniform<CountParams>,
    count_pipeline: wgpu::RenderPipeline,
    max_pipeline: wgpu::ComputePipeline,
    args_pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
}

impl LayerCounter {
    /// Whether `ctx`'s adapter can draw the peel passes indirectly with the object as the first
    /// instance (`INDIRECT_FIRST_INSTANCE`), which counting needs.
    pub fn available(ctx: &Context) -> bool {
        ctx.features()
            .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE)
    }

    /// A counter for `width` x `height` views of `gpu_scene`, peeled into at most `layers`
    /// layers. Fails where the adapter lacks `INDIRECT_FIRST_INSTANCE`.
    pub fn new(
        ctx: &Context,
        gpu_scene: &GpuScene,
        width: u32,
        height: u32,
        layers: u32,
    ) -> Result<Self, GpuError> {
        if !Self::available(ctx) {
            return Err(GpuError::InvalidInput(
                "counting the depth complexity needs the adapter's INDIRECT_FIRST_INSTANCE \
                 feature, which this one lacks"
                    .into(),
            ));
        }
        ctx.validated(|| Self::create(ctx, gpu_scene, width, height, layers))
    }

    fn create(ctx: &Context, gpu_scene: &GpuScene, width: u32, height: u32, layers: u32) -> Self {
        let storage = |label, size: u64, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
                mapped_at_creation: false,
            })
        };
        let counts = storage(
            "depth complexity counts",
            4 * (width * height) as u64,
            wgpu::BufferUsages::empty(),
        );
        let complexity = storage("depth complexity", 4, wgpu::BufferUsages::COPY_SRC);
        let one_layer = gpu_scene.indirect_draw_args();
        let draws = one_layer.len() as u32;
        let all: Vec<[u32; 5]> = (0..layers).flat_map(|_| one_layer.clone()).collect();
        let args = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("depth peel draws"),
                // At least one block: a scene without objects still binds a buffer.
                contents: bytemuck::cast_slice(if all.is_empty() { &[[0u32; 5]] } else { &all }),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            });
        let params = Uniform::new(
            ctx,
            "depth complexity",
            &CountParams {
                width,
                height,
                layers,
                draws,
            },
        );
        let storage_rw = bind::storage(false);
        let layout = bind::layout(
            ctx,
            "depth complexity",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[bind::uniform(), storage_rw, storage_rw, storage_rw],
        );
        let group = bind::group(
            ctx,
            "depth complexity",
            &layout,
            &[
                params.binding(),
                counts.as_entire_binding(),
                complexity.as_entire_binding(),
                args.as_entire_binding(),
            ],
        );
        let count_module = counter_shader(ctx, "depth complexity count", COUNT_WGSL, 2);
        let count_pipeline = scene_pipeline_with(
            ctx,
            "depth complexity count",
            &gpu_scene.pipeline_layout_with(ctx, &[&layout]),
            &count_module,
            "count_fs",
            &[],
            (false, wgpu::CompareFunction::Always),
        );
        let reduce_module = counter_shader(ctx, "depth complexity max", REDUCE_WGSL, 0);
        let compute = |entry| {
            gpu::compute::pipeline(ctx, "depth complexity", &[&layout], &reduce_module, entry)
        };
        Self {
            width,
            height,
            layers,
            draws,
            counts,
            complexity,
            args,
            _params: params,
            count_pipeline,
            max_pipeline: compute("max_main"),
            args_pipeline: compute("args_main"),
            group,
        }
    }

    /// Records the three passes: the count of the objects `filter` selects, seen through
    /// `camera` (a bind group of `gpu_scene`'s camera layout), into `depth` (any depth
    /// attachment of the view's size: cleared, not tested); then the maximum and the
    /// arguments.
    pub fn count(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        gpu_scene: &GpuScene,
        filter: &ObjectFilter,
        camera: &wgpu::BindGroup,
        depth: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        encoder.clear_buffer(&self.counts, 0, None);
        encoder.clear_buffer(&self.complexity, 0, None);
        {
            let mut pass = gpu::pass::begin(
                encoder,
                "depth complexity count",
                &[],
                Some(gpu::pass::depth(depth, gpu::pass::CLEAR_FAR)),
                timestamps,
            );
            pass.set_pipeline(&self.count_pipeline);
            pass.set_bind_group(0, camera, &[]);
            pass.set_bind_group(1, gpu_scene.bind_group(), &[]);
            pass.set_bind_group(2, &self.group, &[]);
            gpu_scene.draw_objects(&mut pass, filter);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("depth complexity max"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_pipeline(&self.max_pipeline);
        let groups = (self.width * self.height).div_ceil(64);
        pass.dispatch_workgroups(groups.min(MAX_GROUPS), 1, 1);
        pass.set_pipeline(&self.args_pipeline);
        pass.dispatch_workgroups((self.layers * self.draws).div_ceil(64).max(1), 1, 1);
    }

    /// The number of objects (draws per layer) the counter was made for.
    pub fn draws(&self) -> usize {
        self.draws as usize
    }

    /// The indirect buffer of the peel passes: layer `l`'s draws from byte
    /// [`LayerCounter::layer_offset`]`(l)`, laid out as [`GpuScene::indirect_draw_args`].
    pub fn args(&self) -> &wgpu::Buffer {
        &self.args
    }

    /// Where layer `layer`'s draw arguments start in [`LayerCounter::args`].
    pub fn layer_offset(&self, layer: u32) -> u64 {
        layer as u64 * self.draws as u64 * std::mem::size_of::<[u32; 5]>() as u64
    }

    /// The depth complexity the last submitted count found (the deepest pixel's number of
    /// surfaces; read back, for tests and diagnostics).
    pub fn complexity(&self, ctx: &Context) -> Result<u32, GpuError> {
        let bytes = gpu::read_buffer(ctx, &self.complexity)?;
        Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }
}
