//! Which refractor map each specular object uses, and the maps themselves.
//!
//! The paper keeps one refractor distance map per *kind* of piece (six for a chess set,
//! "built once during initialization") and searches it for every piece of that kind. Here a
//! kind is a set of specular objects with the same mesh and the same scale: the map is
//! rendered around one of them (the kind's representative), in its world orientation, and a
//! piece of the kind turned differently (the black knights face the other way) is searched
//! with its ray turned into the representative's frame. Objects only translate over time
//! (`scene::Motion`), so the maps never change. The kinds and the piece table (where each
//! piece stands at a time) are `scene`'s (`scene::Kinds`, `scene::multi_object::pieces`),
//! shared with the height maps.

/// Most kinds the search's maps hold: cube k of one cube-map array is kind k's refractor map,
/// and wgpu's default limit is 256 array layers (42 cubes of six).
pub const MAX_KINDS: usize = 42;

/// Format of the refractor maps (normal + distance) and the environment impostor.
pub const MAP_FORMAT: gpu::wgpu::TextureFormat = gpu::wgpu::TextureFormat::Rgba16Float;

pub use scene::kinds::Kinds;
pub use scene::multi_object::pieces::{PIECES_WGSL, PieceGpu, map_box, pieces_at};

/// WGSL of the refractor map pass (`refractor_map_fs`, importing `scene::shading`).
pub const REFRACTOR_MAP_WGSL: &str = include_str!("shaders/refractor_map.wgsl");

/// Renders each kind's refractor map around its representative (at the scene's current
/// time): outward normal in rgb, distance from the centre in alpha, `resolution` texels per
/// cube face, in the format [`MAP_FORMAT`]. Made once per scene.
pub fn render_kind_maps(
    frame: &mut scene::Frame,
    scene: &scene::GpuScene,
    kinds: &Kinds,
    resolution: u32,
) -> Result<Vec<gpu::cube::CubeTarget>, gpu::GpuError> {
    let ctx = frame.gpu;
    let module = scene::shader(ctx, "refractor map", REFRACTOR_MAP_WGSL);
    let pipeline = scene::scene_pipeline(
        ctx,
        "refractor map",
        &scene.pipeline_layout_with(ctx, &[]),
        &module,
        "refractor_map_fs",
        MAP_FORMAT,
    );
    let time = scene.time();
    let mut maps = Vec::new();
    for &rep in &kinds.representative {
        let cube = gpu::cube::CubeTarget::new(ctx, resolution, MAP_FORMAT, "refractor map")?;
        let centre = scene.scene.objects[rep].center_at(time);
        scene.draw_cube(
            frame,
            &cube,
            centre,
            1e-4,
            &pipeline,
            &[],
            &scene::ObjectFilter::Only(vec![rep]),
            "refractor map",
        );
        maps.push(cube);
    }
    Ok(maps)
}
