//! BVH over all scene triangles (obvhs) with exact closest-hit and any-hit queries.
//! (Being written: see the helper task.)
use crate::Scene;
use glam::{Vec2, Vec3};

/// A ray hit with everything shading needs, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub object: usize,
    /// Triangle index within the object's mesh.
    pub triangle: usize,
    pub position: Vec3,
    /// Interpolated shading normal, unit length, as authored (not flipped toward the ray).
    pub normal: Vec3,
    /// Unit geometric normal from the triangle winding.
    pub geometric_normal: Vec3,
    pub uv: Vec2,
}

pub struct SceneBvh {}

impl SceneBvh {
    pub fn build(_scene: &Scene, _time: f32) -> Self {
        todo!()
    }
    pub fn closest_hit(&self, _origin: Vec3, _dir: Vec3, _t_max: f32) -> Option<Hit> {
        todo!()
    }
    pub fn any_hit(&self, _origin: Vec3, _dir: Vec3, _t_max: f32) -> bool {
        todo!()
    }
}
