//! The scene's shaders and the pipelines that draw it: the WGSL modules `scene::shading`
//! ([`SHADING`]: the scene's bindings and the shading model of the CPU reference) and
//! `scene::medium`, [`shader`] (a shader importing them; [`shader_importing`] with a technique's
//! own modules), the scene's vertex stage
//! ([`SCENE_VS_WGSL`]) and the pipelines that pair it with a technique's fragment entries.

use gpu::pass;
use gpu::wgpu;
use gpu::{Context, Vertex};

/// Scene bindings and the shared diffuse shading model, in WGSL: the module `scene::shading`
/// ([`SHADING`]), which shaders import what they use from.
pub const SHADING_WGSL: &str = include_str!("shaders/scene.wgsl");
/// [`SHADING_WGSL`] as a module (it imports `scene::medium`, [`crate::medium::MEDIUM`]).
pub static SHADING: gpu::wgsl::Module = gpu::wgsl::Module::new(
    SHADING_WGSL,
    "scene/src/shaders/scene.wgsl",
    &[&crate::medium::MEDIUM],
);
/// The scene's vertex stage, `scene_vs`: object `instance_index`'s vertices in world and clip
/// space. Scene pipelines ([`scene_pipeline`]) take it from its own module, so a technique's
/// shader holds only its fragment entries.
pub const SCENE_VS_WGSL: &str =
    "#import scene::shading::{SceneVertexIn, SceneVertexOut, scene_vertex}
@vertex
fn scene_vs(v: SceneVertexIn, @builtin(instance_index) object: u32) -> SceneVertexOut {
    return scene_vertex(v, object);
}
";

/// The scene's modules every shader [`shader`] composes may import: `scene::shading` (and the
/// `scene::medium` it imports) and the light-map modules `scene::chart`, `scene::receiver` and
/// `scene::footprint`.
const SCENE_MODULES: [&gpu::wgsl::Module; 4] = [
    &SHADING,
    &crate::lightmap::CHART,
    &crate::lightmap::RECEIVER,
    &crate::lightmap::FOOTPRINT,
];

/// Composes a shader of the scene's passes: `source` importing from the scene's modules
/// ([`SCENE_MODULES`]: shading, medium, light-map charts, receivers and footprints) and
/// `gpu`'s.
pub fn shader(ctx: &Context, label: &str, source: &str) -> wgpu::ShaderModule {
    shader_importing(ctx, label, source, &[])
}

/// [`shader`] importing a technique's own modules too (its searches, `modules`).
pub fn shader_importing(
    ctx: &Context,
    label: &str,
    source: &str,
    modules: &[&gpu::wgsl::Module],
) -> wgpu::ShaderModule {
    shader_of(
        ctx,
        gpu::wgsl::Shader::new(label, source).importing(modules),
    )
}

/// Composes `shader` (its own imports and definitions) with the scene's modules
/// ([`SCENE_MODULES`]) offered too: what [`shader`] and [`shader_importing`] do, for a shader
/// that also needs definitions.
pub fn shader_of(ctx: &Context, shader: gpu::wgsl::Shader<'_>) -> wgpu::ShaderModule {
    let imports: Vec<&gpu::wgsl::Module> = SCENE_MODULES
        .into_iter()
        .chain(shader.imports.iter().copied())
        .collect();
    gpu::shader(
        ctx,
        gpu::wgsl::Shader {
            imports: &imports,
            ..shader
        },
    )
}
/// The shared raster pass's fragment shaders (`raster_fs`: the diffuse shading model, distance
/// from the eye in alpha; `shadow_fs`), importing `scene::shading` ([`SHADING`]): a technique
/// that draws the diffuse scene inside its own passes uses `raster_fs`.
pub const RASTER_WGSL: &str = include_str!("shaders/raster.wgsl");

/// A render pipeline drawing scene objects with `scene_vs` and the given fragment entry:
/// depth test less, no culling (surfaces are two-sided, cube faces differ in handedness).
pub fn scene_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment_entry: &str,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    scene_pipeline_with(
        ctx,
        label,
        layout,
        module,
        fragment_entry,
        &[pass::color_target(format, None)],
        (true, wgpu::CompareFunction::Less),
    )
}

/// [`scene_pipeline`] into a renderer's own targets: one colour target of `formats.color`
/// (`TargetFormats::color_target`: a renderer's alpha is kept), depth written and tested with
/// `Less` on `formats.depth` (a technique's pass in a frame not the harness's).
pub fn scene_pipeline_for(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment_entry: &str,
    formats: gpu::TargetFormats,
) -> wgpu::RenderPipeline {
    let vertex = scene_vertex_module(ctx);
    let stages = ((&vertex, "scene_vs"), (module, fragment_entry));
    let depth = pass::depth_state_for(formats.depth, true, wgpu::CompareFunction::Less);
    scene_pipeline_with_depth(ctx, label, layout, stages, &[formats.color_target()], depth)
}

/// [`scene_pipeline`] with its own colour targets (several, or blended) and depth state
/// (`(write, compare)`): for passes that add to what the raster pass drew, or write several
/// maps at once. No culling.
pub fn scene_pipeline_with(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment_entry: &str,
    targets: &[Option<wgpu::ColorTargetState>],
    depth: (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    let vertices = [Some(Vertex::layout())];
    let vertex = scene_vertex_module(ctx);
    render_pipeline(
        ctx,
        label,
        layout,
        ((&vertex, "scene_vs"), (module, fragment_entry)),
        &vertices,
        targets,
        depth,
    )
}

/// The module of the scene's vertex stage, [`SCENE_VS_WGSL`] (entry `scene_vs`), for a pipeline
/// whose fragment stage is a technique's own.
pub fn scene_vertex_module(ctx: &Context) -> wgpu::ShaderModule {
    shader(ctx, "scene_vs", SCENE_VS_WGSL)
}

/// [`scene_pipeline_with`] with a vertex stage of the caller's own in place of `scene_vs` (one
/// that places the scene's vertices as `scene_vs` does and passes more along, per-vertex data
/// read from a storage buffer by vertex index, say): `(vertex, fragment)` stages, each a module
/// and its entry point.
pub fn scene_pipeline_entries(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    stages: (Stage<'_>, Stage<'_>),
    targets: &[Option<wgpu::ColorTargetState>],
    depth: (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    let vertices = [Some(Vertex::layout())];
    render_pipeline(ctx, label, layout, stages, &vertices, targets, depth)
}

/// [`scene_pipeline_entries`] on the caller's depth state, its format included (a renderer's
/// own depth buffer: `gpu::pass::depth_state_for`).
pub fn scene_pipeline_with_depth(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    stages: (Stage<'_>, Stage<'_>),
    targets: &[Option<wgpu::ColorTargetState>],
    depth: wgpu::DepthStencilState,
) -> wgpu::RenderPipeline {
    let vertices = [Some(Vertex::layout())];
    render_pipeline_on(ctx, label, layout, stages, &vertices, targets, depth)
}

/// A pipeline that draws no vertex buffer: the vertex entry makes each vertex from its vertex
/// and instance indices (a proxy of an object, such as a height map's billboard box, one
/// instance per object), the fragment entry may write its own depth. One colour target of
/// `format`, depth written and tested with `Less`, no culling.
pub fn proxy_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let targets = [pass::color_target(format, None)];
    let depth = (true, wgpu::CompareFunction::Less);
    let stages = ((module, entries.0), (module, entries.1));
    render_pipeline(ctx, label, layout, stages, &[], &targets, depth)
}

/// [`proxy_pipeline`] into a renderer's own targets: one colour target of `formats.color`
/// (`TargetFormats::color_target`: a renderer's alpha is kept), depth written and tested with
/// `Less` on `formats.depth`.
pub fn proxy_pipeline_for(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    formats: gpu::TargetFormats,
) -> wgpu::RenderPipeline {
    let depth = pass::depth_state_for(formats.depth, true, wgpu::CompareFunction::Less);
    let stages = ((module, entries.0), (module, entries.1));
    let targets = [formats.color_target()];
    render_pipeline_on(ctx, label, layout, stages, &[], &targets, depth)
}

/// The one render-pipeline descriptor of the scene's pipelines: the vertex and fragment stages
/// (module and entry each), `buffers` of vertices, the caller's targets and depth state, no
/// culling.
fn render_pipeline(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    stages: (Stage<'_>, Stage<'_>),
    buffers: &[Option<wgpu::VertexBufferLayout>],
    targets: &[Option<wgpu::ColorTargetState>],
    depth: (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    let depth = pass::depth_state(depth.0, depth.1);
    render_pipeline_on(ctx, label, layout, stages, buffers, targets, depth)
}

/// [`render_pipeline`] on the caller's depth state (its format included).
fn render_pipeline_on(
    ctx: &Context,
    label: &str,
    layout: &wgpu::PipelineLayout,
    stages: (Stage<'_>, Stage<'_>),
    buffers: &[Option<wgpu::VertexBufferLayout>],
    targets: &[Option<wgpu::ColorTargetState>],
    depth: wgpu::DepthStencilState,
) -> wgpu::RenderPipeline {
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: stages.0.0,
                entry_point: Some(stages.0.1),
                compilation_options: Default::default(),
                buffers,
            },
            fragment: Some(wgpu::FragmentState {
                module: stages.1.0,
                entry_point: Some(stages.1.1),
                compilation_options: Default::default(),
                targets,
            }),
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(depth),
            multisample: Default::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        })
}

/// A pipeline stage: a shader module and its entry point.
pub type Stage<'a> = (&'a wgpu::ShaderModule, &'a str);

#[cfg(test)]
mod tests {
    use super::*;

    /// The value of `const NAME: f32 = value;` in `source`.
    fn wgsl_f32(source: &str, name: &str) -> f32 {
        let prefix = format!("const {name}: f32 = ");
        let line = source
            .lines()
            .find_map(|line| line.trim().strip_prefix(prefix.as_str()))
            .unwrap_or_else(|| panic!("no `{prefix}…` in the WGSL"));
        line.trim_end_matches(';').parse().expect("a number")
    }

    /// The constants the WGSL modules spell out for the passes that import them are the Rust
    /// ones, bit for bit.
    #[test]
    fn the_wgsl_constants_are_the_rust_ones() {
        let medium = crate::medium::MEDIUM_WGSL;
        let eye_clearance = wgsl_f32(medium, "EYE_CLEARANCE");
        assert_eq!(eye_clearance, crate::medium::EYE_CLEARANCE);
        assert_eq!(wgsl_f32(SHADING_WGSL, "CAMERA_NEAR"), crate::Camera::NEAR);
        let background = wgsl_f32(SHADING_WGSL, "BACKGROUND_DISTANCE");
        assert_eq!(background, crate::BACKGROUND_DISTANCE);
    }
}
