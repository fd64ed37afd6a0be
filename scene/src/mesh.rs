//! Procedural meshes for the built-in scenes: quads, boxes, spheres, cylinders, lofts
//! (surfaces through a stack of elliptical cross-sections: a surface of revolution is the case
//! of circles on the axis) and tubes (circles swept along a curve), and smooth normals of a
//! mesh whose vertices repeat along seams.

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

/// One cross-section of a [`loft`]: the ellipse at height `y` centred on (`x`, `y`, 0), with
/// half-axis `rx` along x and `rz` along z. A ring with both half-axes zero is a point (an
/// apex that closes the surface).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ring {
    pub y: f32,
    pub x: f32,
    pub rx: f32,
    pub rz: f32,
}

impl Ring {
    /// A circle of radius `r` about the y axis: the ring of a surface of revolution.
    pub fn circle(y: f32, r: f32) -> Ring {
        Ring {
            y,
            x: 0.0,
            rx: r,
            rz: r,
        }
    }

    fn is_point(&self) -> bool {
        self.rx == 0.0 && self.rz == 0.0
    }

    /// The point at angle `phi`, in the convention of [`cylinder`] and [`uv_sphere`].
    fn at(&self, phi: f32) -> Vec3 {
        Vec3::new(self.x + self.rx * phi.cos(), self.y, -self.rz * phi.sin())
    }
}

/// A closed surface through `rings`, listed along the outline from the bottom to the top of the
/// solid (the outline may step down, like a rook's recessed top; the solid lies on the axis
/// side of it). `slices` vertices go round each ring. Normals
/// are smooth along runs of rings and break at a crease: a ring where the outline (seen at
/// angles 0, 90 and 180 degrees) turns by more than `crease_deg`. A first ring that is not a
/// point is closed by a flat cap facing down, a last one by a cap facing up. The result is watertight: every edge (by position) is
/// shared by two triangles that use it in opposite directions.
pub fn loft(rings: &[Ring], slices: u32, crease_deg: f32) -> Mesh {
    assert!(
        rings.len() >= 2 && slices >= 3,
        "a loft needs 2 rings and 3 slices"
    );
    let crease = crease_deg.to_radians();
    let turn = |i: usize| {
        [0.0, 0.5 * PI, PI]
            .iter()
            .map(|&phi| {
                let (a, b, c) = (rings[i - 1].at(phi), rings[i].at(phi), rings[i + 1].at(phi));
                (b - a).angle_between(c - b)
            })
            .fold(0.0f32, f32::max)
    };
    let mut parts = Vec::new();
    let mut start = 0;
    for i in 1..rings.len() {
        if i == rings.len() - 1 || turn(i) > crease {
            parts.push(loft_band(&rings[start..=i], slices));
            start = i;
        }
    }
    let (first, last) = (rings[0], rings[rings.len() - 1]);
    if !first.is_point() {
        parts.push(ring_cap(first, slices, false));
    }
    if !last.is_point() {
        parts.push(ring_cap(last, slices, true));
    }
    merge(&parts)
}

/// The side surface through `rings` with smooth (area-weighted) normals. A point ring is one
/// vertex, so an apex gets the average normal of the triangles around it.
fn loft_band(rings: &[Ring], slices: u32) -> Mesh {
    let mut m = Mesh::default();
    let mut first_vertex = Vec::with_capacity(rings.len());
    for (k, ring) in rings.iter().enumerate() {
        first_vertex.push(m.positions.len() as u32);
        let count = if ring.is_point() { 1 } else { slices };
        for j in 0..count {
            let phi = 2.0 * PI * j as f32 / slices as f32;
            m.positions.push(ring.at(phi));
            m.uvs.push(Vec2::new(
                j as f32 / slices as f32,
                k as f32 / (rings.len() - 1) as f32,
            ));
        }
    }
    let index = |k: usize, j: u32| {
        if rings[k].is_point() {
            first_vertex[k]
        } else {
            first_vertex[k] + j % slices
        }
    };
    for k in 0..rings.len() - 1 {
        for j in 0..slices {
            let (a, a1) = (index(k, j), index(k, j + 1));
            let (b, b1) = (index(k + 1, j), index(k + 1, j + 1));
            // The quad (a, a1, b1, b) as two triangles; at an apex one of them is degenerate.
            if !rings[k].is_point() {
                m.indices.extend([a, a1, b]);
            }
            if !rings[k + 1].is_point() {
                m.indices.extend([b, a1, b1]);
            }
        }
    }
    m.normals = vec![Vec3::ZERO; m.positions.len()];
    m.repair_normals();
    m
}

/// A flat disk (fan from the centre) closing `ring`, facing +y when `up`.
fn ring_cap(ring: Ring, slices: u32, up: bool) -> Mesh {
    let n = if up { Vec3::Y } else { Vec3::NEG_Y };
    let mut c = Mesh::default();
    c.positions.push(Vec3::new(ring.x, ring.y, 0.0));
    c.uvs.push(Vec2::splat(0.5));
    for j in 0..slices {
        let phi = 2.0 * PI * j as f32 / slices as f32;
        c.positions.push(ring.at(phi));
        c.uvs
            .push(Vec2::new(0.5 + 0.5 * phi.cos(), 0.5 - 0.5 * phi.sin()));
    }
    c.normals = vec![n; c.positions.len()];
    for j in 0..slices {
        let (a, b) = (1 + j, 1 + (j + 1) % slices);
        if up {
            c.indices.extend([0, a, b]);
        } else {
            c.indices.extend([0, b, a]);
        }
    }
    c
}

/// A closed tube along the polyline `path` (at least two points): a circle of radius
/// `radii[i]` round each point, in the plane perpendicular to the path there (the tangent is
/// the direction between the neighbouring points), turned from point to point by the least
/// rotation (a rotation-minimising frame, so the tube does not twist), with `slices` vertices
/// round each circle; flat caps close both ends. Normals are smooth along the tube (area
/// weighted, like [`loft`]'s) and flat on the caps; triangles wind counter-clockwise seen from
/// outside. Like a loft it is watertight: every edge (by position) is shared by two triangles
/// that use it in opposite directions.
pub fn tube(path: &[Vec3], radii: &[f32], slices: u32) -> Mesh {
    assert!(
        path.len() >= 2 && radii.len() == path.len() && slices >= 3,
        "a tube needs 2 points, one radius per point and 3 slices"
    );
    let last = path.len() - 1;
    let tangent = |i: usize| (path[(i + 1).min(last)] - path[i.saturating_sub(1)]).normalize();
    // (normal, binormal, tangent) right-handed: the circle turns counter-clockwise about the
    // tangent, as a loft's rings turn about +y, so the loft's winding faces outwards here too.
    let mut frames = Vec::with_capacity(path.len());
    let mut normal = tangent(0).any_orthonormal_vector();
    for i in 0..path.len() {
        if i > 0 {
            normal = glam::Quat::from_rotation_arc(tangent(i - 1), tangent(i)) * normal;
        }
        let t = tangent(i);
        let n = (normal - t * t.dot(normal)).normalize();
        frames.push((n, t.cross(n), t));
    }
    let at = |i: usize, j: u32| {
        let phi = 2.0 * PI * j as f32 / slices as f32;
        let (n, b, _) = frames[i];
        path[i] + radii[i] * (n * phi.cos() + b * phi.sin())
    };
    let mut band = Mesh::default();
    for i in 0..path.len() {
        for j in 0..slices {
            band.positions.push(at(i, j));
            band.uvs
                .push(Vec2::new(j as f32 / slices as f32, i as f32 / last as f32));
        }
    }
    for k in 0..last as u32 {
        for j in 0..slices {
            let (a, a1) = (k * slices + j, k * slices + (j + 1) % slices);
            let (b, b1) = (a + slices, a1 + slices);
            band.indices.extend([a, a1, b, b, a1, b1]);
        }
    }
    band.normals = vec![Vec3::ZERO; band.positions.len()];
    band.repair_normals();
    let cap = |i: usize, forward: bool| {
        let (_, _, t) = frames[i];
        let n = if forward { t } else { -t };
        let mut c = Mesh::default();
        c.positions.push(path[i]);
        c.uvs.push(Vec2::splat(0.5));
        for j in 0..slices {
            let phi = 2.0 * PI * j as f32 / slices as f32;
            c.positions.push(at(i, j));
            c.uvs
                .push(Vec2::new(0.5 + 0.5 * phi.cos(), 0.5 - 0.5 * phi.sin()));
        }
        c.normals = vec![n; c.positions.len()];
        for j in 0..slices {
            let (a, b) = (1 + j, 1 + (j + 1) % slices);
            if forward {
                c.indices.extend([0, a, b]);
            } else {
                c.indices.extend([0, b, a]);
            }
        }
        c
    };
    merge(&[band, cap(0, false), cap(last, true)])
}

/// Smooth vertex normals of `mesh` from its positions: the area-weighted sum of the face
/// normals of the triangles round each *position*, so that vertices repeated at the same
/// place (the seam and the poles of [`uv_sphere`], the seam of a loft) share one normal and
/// the surface shades without a crease there. Positions closer than a millionth of the mesh's
/// size count as one (the sines of a UV sphere's last ring and seam are not exactly zero). A
/// position no triangle with an area uses gets +Y. Replaces every normal; the positions, uvs
/// and triangles stay.
pub fn smooth_normals(mesh: &mut Mesh) {
    let (lo, hi) = mesh.bounds();
    let cell = ((hi - lo).max_element() * 1e-6).max(f32::MIN_POSITIVE);
    let key = |p: Vec3| (p / cell).round().as_i64vec3().to_array();
    let mut sums: std::collections::HashMap<[i64; 3], Vec3> = Default::default();
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
        let face = (b - a).cross(c - a);
        if face.is_finite() {
            for p in [a, b, c] {
                *sums.entry(key(p)).or_insert(Vec3::ZERO) += face;
            }
        }
    }
    mesh.normals = mesh
        .positions
        .iter()
        .map(|p| {
            sums.get(&key(*p))
                .copied()
                .unwrap_or(Vec3::ZERO)
                .normalize_or(Vec3::Y)
        })
        .collect();
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
            loft(&test_outline(), 12, 30.0),
            test_tube(),
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

    /// A solid with a cap at the bottom, a crease, a leaning elliptical section, a step down
    /// (a recess) and an apex at the top.
    fn test_outline() -> Vec<Ring> {
        vec![
            Ring::circle(0.0, 1.0),
            Ring::circle(0.2, 1.0),
            Ring::circle(0.4, 0.6),
            Ring {
                y: 0.8,
                x: 0.3,
                rx: 0.7,
                rz: 0.4,
            },
            Ring::circle(1.0, 0.5),
            Ring::circle(0.9, 0.3),
            Ring::circle(0.9, 0.0),
        ]
    }

    /// A tube that bends through a half turn and tapers.
    fn test_tube() -> Mesh {
        let path: Vec<Vec3> = (0..=12)
            .map(|i| {
                let a = PI * i as f32 / 12.0;
                Vec3::new(a.sin(), -a.cos(), 0.3 * a)
            })
            .collect();
        let radii: Vec<f32> = (0..=12).map(|i| 0.2 - 0.01 * i as f32).collect();
        tube(&path, &radii, 10)
    }

    /// Every edge of a tube is used once in each direction, and it encloses a positive
    /// volume close to that of its circles swept along the path (a closed, outward surface).
    #[test]
    fn a_tube_is_closed_and_faces_outwards() {
        let mesh = test_tube();
        assert_watertight(&mesh);
        let volume: f32 = mesh
            .indices
            .chunks(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        // Path length of the helix-like arc: pi * sqrt(1 + 0.3^2); mean radius 0.14.
        let swept = PI * 0.14f32 * 0.14 * PI * (1.0f32 + 0.09).sqrt();
        assert!(
            volume > 0.8 * swept && volume < 1.1 * swept,
            "{volume} vs {swept}"
        );
    }

    /// The smooth normals of a UV sphere are its radial directions, seam and poles included.
    #[test]
    fn smooth_normals_weld_the_seam_and_poles() {
        let mut mesh = uv_sphere(2.0, 12, 24);
        let radial = mesh.normals.clone();
        mesh.normals.iter_mut().for_each(|n| *n = Vec3::ZERO);
        smooth_normals(&mut mesh);
        for (n, r) in mesh.normals.iter().zip(&radial) {
            assert!(n.dot(*r) > 0.995, "{n} vs {r}");
        }
    }

    fn assert_watertight(mesh: &Mesh) {
        let key = |i: u32| mesh.positions[i as usize].to_array().map(f32::to_bits);
        let mut edges = std::collections::HashMap::new();
        for t in mesh.indices.chunks(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((key(a), key(b))).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge used {count} times one way");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its twin");
        }
        assert!(mesh.normals.iter().all(|n| n.is_normalized()));
    }

    /// Every edge of a loft, keyed by its end positions, is used once in each direction.
    #[test]
    fn a_loft_is_watertight() {
        for rings in [
            test_outline(),
            vec![
                Ring::circle(0.0, 0.0),
                Ring::circle(0.5, 1.0),
                Ring::circle(1.0, 0.0),
            ],
            vec![Ring::circle(0.0, 1.0), Ring::circle(1.0, 1.0)],
        ] {
            let mesh = loft(&rings, 9, 30.0);
            let key = |i: u32| mesh.positions[i as usize].to_array().map(f32::to_bits);
            let mut edges = std::collections::HashMap::new();
            for t in mesh.indices.chunks(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    *edges.entry((key(a), key(b))).or_insert(0) += 1;
                }
            }
            for (&(a, b), &count) in &edges {
                assert_eq!(count, 1, "edge used {count} times one way");
                assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its twin");
            }
            assert!(mesh.normals.iter().all(|n| n.is_normalized()));
        }
    }

    /// The enclosed volume of a lofted cylinder (divergence theorem over the triangles) is the
    /// polygon's area times the height: the surface faces outwards and is closed.
    #[test]
    fn a_lofted_cylinder_encloses_its_volume() {
        let mesh = loft(&[Ring::circle(0.0, 1.0), Ring::circle(2.0, 1.0)], 16, 30.0);
        let volume: f32 = mesh
            .indices
            .chunks(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        let polygon = 0.5 * 16.0 * (2.0 * PI / 16.0).sin();
        assert!((volume - 2.0 * polygon).abs() < 1e-4, "{volume}");
    }
}
