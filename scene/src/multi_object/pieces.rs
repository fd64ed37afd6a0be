//! The piece table of the many-object tracer: where each specular object stands at a time,
//! its kind, the rotation into its kind's frame and its bounding box there (`Piece` in
//! `shaders/pieces.wgsl`).

use crate::Scene;
use crate::kinds::{Kinds, linear, rotation_between};
use glam::{Mat3, Vec2, Vec3};

/// WGSL of the piece table (`Piece`, its binding `pieces`, `to_map`, `from_map`, `piece_kind`,
/// `piece_object`) and of the per-object search's three virtual functions, which an
/// [`super::ObjectSearch`]'s module overrides: the module `scene::pieces` ([`PIECES`]).
pub const PIECES_WGSL: &str = include_str!("../shaders/pieces.wgsl");
/// [`PIECES_WGSL`] as a module.
pub static PIECES: gpu::wgsl::Module =
    gpu::wgsl::Module::new(PIECES_WGSL, "scene/src/shaders/pieces.wgsl", &[]);

/// One piece as the shaders read it (`Piece` in pieces.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PieceGpu {
    /// World centre now (the map's reference point moved with the piece); w: kind.
    pub centre: [f32; 4],
    /// Rows of the rotation from world directions to the kind map's frame.
    pub to_map: [[f32; 4]; 3],
    /// The piece's bounding box in the map's frame, relative to the centre; w: object index.
    pub box_min: [f32; 4],
    /// w: unused.
    pub box_max: [f32; 4],
}

/// Every piece of `kinds` at `time`, and each one's xz footprint (for the board grid).
pub fn pieces_at(scene: &Scene, kinds: &Kinds, time: f32) -> (Vec<PieceGpu>, Vec<(Vec2, Vec2)>) {
    let mut gpu = Vec::new();
    let mut footprints = Vec::new();
    for &(object, kind) in &kinds.pieces {
        let o = &scene.objects[object];
        let rep = &scene.objects[kinds.representative[kind]];
        // World -> map: undo this piece's rotation, apply the representative's.
        let to_map = rotation_between(linear(rep), linear(o)).unwrap_or(Mat3::IDENTITY);
        let (box_min, box_max) = map_box(rep);
        let centre = o.center_at(time);
        let rows = [to_map.row(0), to_map.row(1), to_map.row(2)];
        gpu.push(PieceGpu {
            centre: centre.extend(kind as f32).to_array(),
            to_map: rows.map(|r| r.extend(0.0).to_array()),
            box_min: box_min.extend(object as f32).to_array(),
            box_max: box_max.extend(0.0).to_array(),
        });
        let (lo, hi) = world_box(o, time);
        footprints.push((Vec2::new(lo.x, lo.z), Vec2::new(hi.x, hi.z)));
    }
    (gpu, footprints)
}

/// The representative's world-space bounding box about its centre: the box the search from
/// outside clips rays to, in the map's frame.
pub fn map_box(rep: &crate::Object) -> (Vec3, Vec3) {
    let (lo, hi) = world_box(rep, 0.0);
    let centre = rep.center_at(0.0);
    (lo - centre, hi - centre)
}

/// World bounds of an object's vertices at `time` (a deforming object's at that time; the
/// kind's map itself is made of the base mesh, which a deformation invalidates).
fn world_box(o: &crate::Object, time: f32) -> (Vec3, Vec3) {
    let world = o.world_at(time);
    o.positions_at(time).iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| {
            let w = world.transform_point3(*p);
            (lo.min(w), hi.max(w))
        },
    )
}

#[cfg(test)]
mod tests {
    /// The searches' WGSL places its bindings after the drivers' with the piece table's
    /// constant: it must be the Rust one.
    #[test]
    fn the_wgsl_search_binding_is_the_rust_one() {
        let declared = format!(
            "const SEARCH_FIRST_BINDING: u32 = {}u;",
            super::super::SEARCH_FIRST_BINDING
        );
        assert!(
            super::PIECES_WGSL.contains(&declared),
            "pieces.wgsl lacks `{declared}`"
        );
    }
}
