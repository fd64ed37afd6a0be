//! One-shot compute kernels over plain arrays: what every GPU conformance test does (run a
//! WGSL routine on random inputs, read the results back, compare with its Rust twin).
//!
//! Kernel convention: `@group(0) @binding(0) var<storage, read> inputs: array<I>;`,
//! `@group(0) @binding(1) var<storage, read_write> outputs: array<O>;`, entry point with
//! `@workgroup_size(64)` indexed by `global_invocation_id.x` (guard `i < arrayLength(&inputs)`).
//! [`kernel_header`] and [`kernel_entry`] write those lines, so that a test writes only what
//! its kernel computes.

use crate::{Context, GpuError};
use wgpu::util::DeviceExt;

/// Threads per workgroup the kernels are written for.
pub const WORKGROUP_SIZE: u32 = 64;

/// Compiles `source` (prefix the prelude yourself if the kernel needs it), runs `entry` over
/// `inputs` and returns `outputs_per_input * inputs.len()` outputs. Shader and validation
/// A compute pipeline of `module`'s entry point `entry` over the bind groups `layouts` (group
/// `i` = `layouts[i]`), labelled `label`: the one place the workspace's compute passes are made.
pub fn pipeline(
    ctx: &Context,
    label: &str,
    layouts: &[&wgpu::BindGroupLayout],
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    let layout = ctx
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
    pipeline_with_layout(ctx, label, &layout, module, entry)
}

/// [`pipeline`] with a pipeline layout the caller made (shared by several entry points).
pub fn pipeline_with_layout(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    ctx.device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: ctx.pipeline_cache(),
        })
}

/// errors come back as `GpuError::Validation`.
pub fn run_kernel<'s, I: bytemuck::Pod, O: bytemuck::Pod>(
    ctx: &Context,
    source: impl Into<crate::wgsl::Shader<'s>>,
    entry: &str,
    inputs: &[I],
    outputs_per_input: usize,
) -> Result<Vec<O>, GpuError> {
    run_kernel_with(ctx, source, entry, inputs, outputs_per_input, &[])
}

/// [`run_kernel`] with more resources bound after the two buffers: `extra[k]` (its binding
/// type and resource) at `@group(0) @binding(k + 2)`, for kernels that read textures and
/// samplers (a distance map searched by the routine under test).
pub fn run_kernel_with<'s, I: bytemuck::Pod, O: bytemuck::Pod>(
    ctx: &Context,
    source: impl Into<crate::wgsl::Shader<'s>>,
    entry: &str,
    inputs: &[I],
    outputs_per_input: usize,
    extra: &[(wgpu::BindingType, wgpu::BindingResource<'_>)],
) -> Result<Vec<O>, GpuError> {
    if inputs.is_empty() {
        return Ok(Vec::new());
    }
    let source = source.into();
    let output_bytes = (std::mem::size_of::<O>() * outputs_per_input * inputs.len()) as u64;
    let (pipeline, group_layout, input, output) = ctx.validated(|| {
        let module = crate::shader(
            ctx,
            crate::wgsl::Shader {
                label: entry,
                ..source
            },
        );
        let mut types = vec![crate::bind::storage(true), crate::bind::storage(false)];
        types.extend(extra.iter().map(|(ty, _)| *ty));
        let group_layout = crate::bind::layout(ctx, entry, wgpu::ShaderStages::COMPUTE, &types);
        let pipeline = pipeline(ctx, entry, &[&group_layout], &module, entry);
        let input = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("kernel inputs"),
                contents: bytemuck::cast_slice(inputs),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let output = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel outputs"),
            size: output_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        (pipeline, group_layout, input, output)
    })?;
    ctx.validated(|| {
        let mut resources = vec![input.as_entire_binding(), output.as_entire_binding()];
        resources.extend(extra.iter().map(|(_, resource)| resource.clone()));
        let bind_group = crate::bind::group(ctx, entry, &group_layout, &resources);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups((inputs.len() as u32).div_ceil(WORKGROUP_SIZE), 1, 1);
        }
        ctx.queue.submit([encoder.finish()]);
    })?;
    let bytes = crate::read_buffer(ctx, &output)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// The binding header of a kernel for [`run_kernel`]: `inputs: array<input_type>` (read-only
/// storage, `@group(0) @binding(0)`) and `outputs: array<output_type>` (read-write storage,
/// `@binding(1)`), where the types are WGSL type names whose layout matches the Rust `I` and
/// `O` given to [`run_kernel`] (`vec4f` for `[f32; 4]`, `array<vec4f, 4>` for `[[f32; 4]; 4]`,
/// a struct declared by the caller). Entry points follow with [`kernel_entry`].
///
/// ```no_run
/// use gpu::compute::{kernel_entry, kernel_header, run_kernel};
/// # fn main() -> Result<(), gpu::GpuError> {
/// let ctx = gpu::Context::new()?;
/// // One `vec2f` in, one `f32` out per case.
/// let source = format!(
///     "{}{}",
///     kernel_header("vec2f", "f32"),
///     kernel_entry("sum", "outputs[i] = inputs[i].x + inputs[i].y;"),
/// );
/// let sums: Vec<f32> = run_kernel(&ctx, &source, "sum", &[[1.0f32, 2.0], [3.0, 4.0]], 1)?;
/// assert_eq!(sums, [3.0, 7.0]);
/// # Ok(())
/// # }
/// ```
pub fn kernel_header(input_type: &str, output_type: &str) -> String {
    format!(
        "@group(0) @binding(0) var<storage, read> inputs: array<{input_type}>;\n\
         @group(0) @binding(1) var<storage, read_write> outputs: array<{output_type}>;\n"
    )
}

/// A compute entry point `name` of the kernel convention: `@workgroup_size(64)`, one
/// invocation per input, `i` the index of the input (`global_invocation_id.x`), returning
/// before `body` when `i` is past the end of `inputs` (the last workgroup's spare
/// invocations). `body` is WGSL statements using `i`, `inputs` and `outputs`, inserted as
/// written (see [`kernel_header`], whose example uses it).
pub fn kernel_entry(name: &str, body: &str) -> String {
    format!(
        "@compute @workgroup_size({WORKGROUP_SIZE})\n\
         fn {name}(@builtin(global_invocation_id) g: vec3u) {{\n    \
         let i = g.x;\n    \
         if (i >= arrayLength(&inputs)) {{ return; }}\n\
         {body}\n\
         }}\n"
    )
}
