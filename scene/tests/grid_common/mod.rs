//! A world of disjoint spheres standing over the xz plane: pieces whose exact hit is known, for
//! the board-grid search's properties and its GPU conformance.

#![allow(dead_code)]

use glam::{Vec2, Vec3};
use gpu::prelude::{MISS, ray_sphere};
use proptest::prelude::*;
use scene::multi_object::grid::BoardGrid;

#[derive(Clone, Debug)]
pub struct Sphere {
    pub centre: Vec3,
    pub radius: f32,
}

/// The nearest positive ray parameter of the ray `o + t d` on the sphere (from inside: the
/// exit), or `None`.
pub fn sphere_hit(s: &Sphere, o: Vec3, d: Vec3) -> Option<f32> {
    let t = ray_sphere(o, d, s.centre, s.radius);
    if t == MISS {
        return None;
    }
    [t.x, t.y].into_iter().find(|&t| t > 0.0)
}

/// How close the ray comes to grazing the sphere: the half chord length (0 for a tangent).
pub fn half_chord(s: &Sphere, o: Vec3, d: Vec3) -> f32 {
    let t = ray_sphere(o, d, s.centre, s.radius);
    if t == MISS { 0.0 } else { 0.5 * (t.y - t.x) }
}

pub fn footprints(spheres: &[Sphere]) -> Vec<(Vec2, Vec2)> {
    spheres
        .iter()
        .map(|s| {
            let c = Vec2::new(s.centre.x, s.centre.z);
            (c - s.radius, c + s.radius)
        })
        .collect()
}

pub fn grid_of(spheres: &[Sphere]) -> BoardGrid {
    // Disjoint spheres fit unless more than CELL_CAPACITY stack over one point of the xz
    // plane at different heights, which the generators do not produce in practice.
    BoardGrid::build(&footprints(spheres)).expect("the spheres fit a board grid")
}

/// 1-24 spheres of radius 0.03-0.15 over [-1, 1]^2 at heights 0.1-0.4, none touching another
/// (candidates that would are dropped).
pub fn spheres() -> impl Strategy<Value = Vec<Sphere>> {
    proptest::collection::vec(
        (-1.0f32..1.0, 0.1f32..0.4, -1.0f32..1.0, 0.03f32..0.15),
        1..24,
    )
    .prop_map(|candidates| {
        let mut out: Vec<Sphere> = Vec::new();
        for (x, y, z, r) in candidates {
            let s = Sphere {
                centre: Vec3::new(x, y, z),
                radius: r,
            };
            if out
                .iter()
                .all(|o| o.centre.distance(s.centre) > o.radius + s.radius + 1e-3)
            {
                out.push(s);
            }
        }
        out
    })
}

/// A ray from a point around the spheres (outside all of them), mostly aimed into the region.
pub fn ray_among(spheres: Vec<Sphere>) -> impl Strategy<Value = (Vec<Sphere>, Vec3, Vec3)> {
    (
        (-1.5f32..1.5, 0.0f32..0.8, -1.5f32..1.5),
        (-1.0f32..1.0, 0.0f32..0.5, -1.0f32..1.0),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        any::<bool>(),
    )
        .prop_filter_map(
            "origin inside a sphere or zero direction",
            move |(o, target, free, aimed)| {
                let o = Vec3::from(o);
                let d = if aimed {
                    Vec3::from(target) - o
                } else {
                    Vec3::from(free)
                };
                let d = d.try_normalize()?;
                spheres
                    .iter()
                    .all(|s| s.centre.distance(o) > s.radius + 1e-3)
                    .then(|| (spheres.clone(), o, d))
            },
        )
}
