//! Procedural meshes for the built-in scenes: quads, boxes, spheres, cylinders.

use crate::Mesh;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A quad with corner `origin`, edges `u` and `v`; normal is u x v (normalised).
pub fn quad(origin: Vec3, u: Vec3, v: Vec3, uv_scale: Vec2) -> Mesh {
    let n = u.cross(v).normalize();
    Mesh {
        positions: vec![origin, origin + u, origin + u + v, origin + v],
        normals: vec![n; 4],
        uvs: vec![
            Vec2::new(0.0, uv_scale.y),
            Vec2::new(uv_scale.x, uv_scale.y),
            Vec2::new(uv_scale.x, 0.0),
            Vec2::ZERO,
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// Concatenates meshes.
pub fn merge(meshes: &[Mesh]) -> Mesh {
    let mut out = Mesh::default();
    for m in meshes {
        let base = out.positions.len() as u32;
        out.positions.extend_from_slice(&m.positions);
        out.normals.extend_from_slice(&m.normals);
        out.uvs.extend_from_slice(&m.uvs);
        out.indices.extend(m.indices.iter().map(|i| i + base));
    }
    out
}

/// Axis-aligned box between `lo` and `hi`, outward normals, 24 vertices.
pub fn cuboid(lo: Vec3, hi: Vec3) -> Mesh {
    let s = hi - lo;
    let (x, y, z) = (
        Vec3::new(s.x, 0.0, 0.0),
        Vec3::new(0.0, s.y, 0.0),
        Vec3::new(0.0, 0.0, s.z),
    );
    let one = Vec2::ONE;
    merge(&[
        quad(lo, z, y, one),          // -X
        quad(lo + x + z, -z, y, one), // +X
        quad(lo, x, z, one),          // -Y
        quad(lo + y + z, x, -z, one), // +Y
        quad(lo + x, -x, y, one),     // -Z
        quad(lo + z, x, y, one),      // +Z
    ])
}

/// The inside of a box room: the six walls of `cuboid` facing inwards.
pub fn inward(mut mesh: Mesh) -> Mesh {
    for tri in mesh.indices.chunks_mut(3) {
        tri.swap(1, 2);
    }
    for n in &mut mesh.normals {
        *n = -*n;
    }
    mesh
}

/// UV sphere of radius `r` centred at the origin, smooth normals.
pub fn uv_sphere(r: f32, stacks: u32, slices: u32) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=stacks {
        let theta = PI * i as f32 / stacks as f32;
        for j in 0..=slices {
            let phi = 2.0 * PI * j as f32 / slices as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            m.positions.push(n * r);
            m.normals.push(n);
            m.uvs.push(Vec2::new(
                j as f32 / slices as f32,
                i as f32 / stacks as f32,
            ));
        }
    }
    let row = slices + 1;
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b) = (i * row + j, (i + 1) * row + j);
            if i != 0 {
                m.indices.extend([a, b, a + 1]);
            }
            if i != stacks - 1 {
                m.indices.extend([a + 1, b, b + 1]);
            }
        }
    }
    m
}

/// Capped cylinder of radius `r` from y = 0 to y = `h`, axis +Y.
pub fn cylinder(r: f32, h: f32, slices: u32) -> Mesh {
    let mut side = Mesh::default();
    for j in 0..=slices {
        let phi = 2.0 * PI * j as f32 / slices as f32;
        let n = Vec3::new(phi.cos(), 0.0, -phi.sin());
        for (y, v) in [(0.0, 1.0), (h, 0.0)] {
            side.positions.push(n * r + Vec3::Y * y);
            side.normals.push(n);
            side.uvs.push(Vec2::new(j as f32 / slices as f32, v));
        }
    }
    for j in 0..slices {
        let a = 2 * j;
        side.indices.extend([a, a + 2, a + 1, a + 1, a + 2, a + 3]);
    }
    let cap = |y: f32, up: bool| {
        let n = if up { Vec3::Y } else { Vec3::NEG_Y };
        let mut c = Mesh::default();
        c.positions.push(Vec3::Y * y);
        c.normals.push(n);
        c.uvs.push(Vec2::splat(0.5));
        for j in 0..=slices {
            let phi = 2.0 * PI * j as f32 / slices as f32;
            c.positions
                .push(Vec3::new(phi.cos() * r, y, -phi.sin() * r));
            c.normals.push(n);
            c.uvs
                .push(Vec2::new(0.5 + 0.5 * phi.cos(), 0.5 - 0.5 * phi.sin()));
        }
        for j in 1..=slices {
            if up {
                c.indices.extend([0, j, j + 1])
            } else {
                c.indices.extend([0, j + 1, j])
            }
        }
        c
    };
    merge(&[side, cap(h, true), cap(0.0, false)])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every generator winds its triangles counter-clockwise seen from where the normal points.
    #[test]
    fn winding_agrees_with_normals() {
        for mesh in [
            cuboid(Vec3::ZERO, Vec3::ONE),
            inward(cuboid(Vec3::ZERO, Vec3::ONE)),
            uv_sphere(1.0, 8, 12),
            cylinder(0.5, 2.0, 12),
        ] {
            for t in mesh.indices.chunks(3) {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                let face = (b - a).cross(c - a);
                if face.length() < 1e-9 {
                    continue;
                }
                let n = mesh.normals[t[0] as usize]
                    + mesh.normals[t[1] as usize]
                    + mesh.normals[t[2] as usize];
                assert!(face.dot(n) > 0.0, "triangle {t:?} winds against its normal");
            }
        }
    }
}
