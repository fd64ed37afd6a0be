//! Refractor height maps of the kinds of piece (section 6): one orthographic picture per kind
//! of its representative, taken perpendicular to its plane of symmetry.
//!
//! The plane of symmetry is the representative's mesh-frame `z = 0` plane through its bounds
//! centre (the chess pieces are built so: revolved about `y`, the knight's head lofted along
//! `+x` symmetric in `z`). The map frame is the mesh frame at the object's scale, centred on
//! the bounds centre: `u` = mesh `x`, `v` = mesh `y`, `w` = mesh `z`. The billboard then stands
//! this frame upright (`v` vertical), so an object must keep its mesh `y` axis vertical.

use crate::search::Bounds;
use glam::{Mat3, Mat4, Vec3};
use gpu::pass::{self, CLEAR_FAR, Load};
use gpu::wgpu;
use gpu::{GpuError, Uniform, bind};
use scene::{Frame, GpuScene, Object, ObjectFilter};

const HEIGHT_MAP_WGSL: &str = include_str!("shaders/height_map.wgsl");

/// Format of the height maps: normal.xyz, height; read with `textureLoad` and filtered in the
/// shader exactly as [`crate::search::SampledField`] does.
pub const HEIGHT_MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Margin on the proxy's box around the mesh across and out of the plane (relative).
const BOX_MARGIN: f32 = 1.01;

/// The rotation of an object's transform (its linear part without scale), and the scale.
fn rotation_and_scale(o: &Object) -> (Mat3, Vec3) {
    let m = Mat3::from_mat4(o.transform);
    let scale = Vec3::new(m.x_axis.length(), m.y_axis.length(), m.z_axis.length());
    (
        Mat3::from_cols(m.x_axis / scale.x, m.y_axis / scale.y, m.z_axis / scale.z),
        scale,
    )
}

/// Whether `o` stands upright: its mesh `y` axis is the world's vertical (the billboard turns
/// about it).
pub fn upright(o: &Object) -> bool {
    let (r, _) = rotation_and_scale(o);
    (r * Vec3::Y - Vec3::Y).length() < 1e-3
}

/// The proxy's bounds of object `o` in its map frame (world units, about its bounds centre).
pub fn map_bounds(o: &Object) -> Bounds {
    let (_, scale) = rotation_and_scale(o);
    let (lo, hi) = o.mesh.bounds();
    let centre = (lo + hi) * 0.5;
    let (mut half_width, mut height) = (0.0f32, 0.0f32);
    let (mut v_min, mut v_max) = (f32::INFINITY, f32::NEG_INFINITY);
    for p in &o.mesh.positions {
        let q = (*p - centre) * scale;
        half_width = half_width.max(q.x.abs());
        height = height.max(q.z.abs());
        v_min = v_min.min(q.y);
        v_max = v_max.max(q.y);
    }
    // Across and out of the plane the surface only touches the box at its widest points, and
    // the margin keeps it inside. Along v the box is the mesh's extent: a flat top or
    // underside is then the box face, whose normal the search gives it (the map sees such
    // faces edge-on).
    let pad = |x: f32| x * BOX_MARGIN + 1e-6;
    Bounds {
        half_width: pad(half_width),
        v_min,
        v_max,
        height: pad(height),
    }
}

/// World -> map frame of `o` at `time` (a rotation about its centre).
pub fn world_to_map(o: &Object, time: f32) -> Mat4 {
    let (r, _) = rotation_and_scale(o);
    Mat4::from_mat3(r.transpose()) * Mat4::from_translation(-o.center_at(time))
}

/// Renders the height map of each of `representatives` into a layer of one
/// `resolution`-square texture array (at the scene's current time).
pub fn render_height_maps(
    frame: &mut Frame,
    scene: &GpuScene,
    representatives: &[usize],
    resolution: u32,
) -> Result<wgpu::Texture, GpuError> {
    let ctx = frame.gpu;
    let layers = representatives.len().max(1) as u32;
    let maps = ctx.allocating("refractor height maps", || {
        gpu::render_texture(
            ctx,
            "refractor height maps",
            (resolution, resolution, layers),
            HEIGHT_MAP_FORMAT,
            wgpu::TextureUsages::COPY_SRC,
        )
    })?;
    let depth = gpu::depth_texture(ctx, resolution, resolution, 1, "height map depth")
        .create_view(&Default::default());
    let layout = bind::layout(
        ctx,
        "height map pass",
        wgpu::ShaderStages::FRAGMENT,
        &[bind::uniform()],
    );
    let module = scene::shader(ctx, "height map", HEIGHT_MAP_WGSL);
    let pipeline = scene::scene_pipeline(
        ctx,
        "height map",
        &scene.pipeline_layout_with(ctx, &[&layout]),
        &module,
        "height_map_fs",
        HEIGHT_MAP_FORMAT,
    );
    let time = scene.time();
    for (layer, &rep) in representatives.iter().enumerate() {
        let o = &scene.scene.objects[rep];
        let b = map_bounds(o);
        let to_map = world_to_map(o, time);
        // Looking along -w from in front of the plane: clip x = u, clip y = v (row 0 at v_max).
        let margin = 0.5 * b.height;
        let view = Mat4::from_translation(-Vec3::Z * (b.height + margin));
        let proj = glam::camera::rh::proj::directx::orthographic(
            -b.half_width,
            b.half_width,
            b.v_min,
            b.v_max,
            0.5 * margin,
            2.0 * b.height + 2.0 * margin,
        );
        let camera = scene.camera_bind_group(ctx, proj * view * to_map, Vec3::ZERO);
        let uniform = Uniform::new(ctx, "height map pass", &to_map.to_cols_array_2d());
        let group = bind::group(ctx, "height map pass", &layout, &[uniform.binding()]);
        let target = gpu::layer_view(&maps, layer as u32);
        let empty = Load::Clear(wgpu::Color {
            r: 0.0,
            g: 0.0,
            b: 0.0,
            a: b.empty_height() as f64,
        });
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "height map",
            &[pass::color(&target, empty)],
            Some(pass::depth(&depth, CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![rep]));
    }
    Ok(maps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pieces_box_holds_its_mesh_about_its_centre() {
        let scene = scene::load("chess").unwrap();
        for o in scene.objects.iter().filter(|o| o.material.is_specular()) {
            assert!(upright(o), "{} is not upright", o.name);
            let b = map_bounds(o);
            let m = world_to_map(o, 0.0);
            for p in &o.mesh.positions {
                let q = m.transform_point3(o.world_at(0.0).transform_point3(*p));
                assert!(
                    q.x.abs() < b.half_width && q.z.abs() < b.height,
                    "{}",
                    o.name
                );
                assert!(q.y >= b.v_min - 1e-6 && q.y <= b.v_max + 1e-6, "{}", o.name);
            }
        }
    }
}
