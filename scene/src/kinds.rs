//! Kinds of specular object: the objects that share one precomputed map.
//!
//! Techniques that precompute a map per refracting object (refractor distance maps, refractor
//! height maps) keep one per *kind*: a set of specular objects with the same mesh and the same
//! scale, differing only by a rotation and a translation (a chess set has six kinds for 32
//! pieces). The map is made around one object of the kind (its representative) and used for
//! every other, with a ray turned into the representative's frame where the objects differ by
//! a rotation (the black knights face the other way).
//!
//! Kinds are grouped, and their maps made, from the base meshes: a deforming object
//! ([`crate::Object::is_deforming`]) is a precomputation its map does not follow (its
//! [`crate::Morph`] simply invalidates the map while it deforms).

use crate::Scene;
use glam::Mat3;

/// The specular objects of a scene grouped into kinds.
#[derive(Clone, Debug, PartialEq)]
pub struct Kinds {
    /// The object each kind's map is rendered around.
    pub representative: Vec<usize>,
    /// The specular objects (the tracer's pieces, in this order) and their kinds.
    pub pieces: Vec<(usize, usize)>,
}

impl Kinds {
    /// Groups `scene`'s specular objects by mesh and scale.
    pub fn of(scene: &Scene) -> Kinds {
        let mut representative: Vec<usize> = Vec::new();
        let mut pieces = Vec::new();
        for object in scene.specular_objects() {
            let o = &scene.objects[object];
            let kind = representative.iter().position(|&r| {
                let rep = &scene.objects[r];
                rep.mesh == o.mesh && rotation_between(linear(rep), linear(o)).is_some()
            });
            let kind = kind.unwrap_or_else(|| {
                representative.push(object);
                representative.len() - 1
            });
            pieces.push((object, kind));
        }
        Kinds {
            representative,
            pieces,
        }
    }
}

/// The linear part of an object's transform.
pub fn linear(o: &crate::Object) -> Mat3 {
    Mat3::from_mat4(o.transform)
}

/// `M` with `from = M to` when it is a rotation (the two linear maps differ by a turn, not by
/// scale or handedness), else `None`: applied to a world direction, it takes it from the
/// frame of an object transformed by `to` into that of one transformed by `from`.
pub fn rotation_between(from: Mat3, to: Mat3) -> Option<Mat3> {
    if to.determinant().abs() < 1e-12 {
        return None;
    }
    let m = from * to.inverse();
    let orthonormal = (m * m.transpose() - Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|v| v.abs() < 1e-4);
    (orthonormal && m.determinant() > 0.0).then_some(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chess_set_has_six_kinds_and_the_sphere() {
        let scene = crate::load("chess").unwrap();
        let kinds = Kinds::of(&scene);
        assert_eq!(kinds.representative.len(), 7);
        assert_eq!(kinds.pieces.len(), 33);
        for &(object, kind) in &kinds.pieces {
            let rep = &scene.objects[kinds.representative[kind]];
            assert!(rep.mesh == scene.objects[object].mesh);
        }
    }
}
