//! The renderer's world: a floor, two walls, two boxes, two glass balls and a ball of smoke,
//! described with its own types.

use crate::Vertex;
use glam::{Mat4, Vec3};
use gpu::HostedMesh;
use volumes::SoftVolume;

/// A glass ball: where it stands, its size, and its index among the renderer's objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Centre (world).
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
    /// Index among the renderer's objects (the opaque ones come first).
    pub index: usize,
}

impl Ball {
    /// The ball's triangles around the origin (the passes place it at `center`).
    pub fn mesh(&self) -> HostedMesh {
        let (rings, segments) = (24u32, 48u32);
        let mut mesh = HostedMesh::default();
        for ring in 0..=rings {
            let theta = std::f32::consts::PI * ring as f32 / rings as f32;
            for segment in 0..=segments {
                let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
                let normal = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                mesh.positions.push(normal * self.radius);
                mesh.normals.push(normal);
            }
        }
        let row = segments + 1;
        for ring in 0..rings {
            for segment in 0..segments {
                let a = ring * row + segment;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                mesh.indices.extend([a, b, c, b, d, c]);
            }
        }
        mesh
    }
}

/// Everything the renderer draws, and its camera.
pub struct World {
    /// The camera's eye.
    pub eye: Vec3,
    /// The point it looks at.
    pub target: Vec3,
    /// The soft volumes drawn over the frame.
    pub volumes: Vec<SoftVolume>,
    /// The front box: centre and half size.
    pub front_box: (Vec3, f32),
    /// The glass ball seen through its distance impostor.
    pub impostor: Ball,
    /// The glass ball of image-space refraction.
    pub refractor: Ball,
}

/// Objects 0-3 are opaque (floor with the wall behind the camera, the wall ahead, the front
/// box, the back box); the balls follow.
const OPAQUE_OBJECTS: usize = 4;

impl Default for World {
    fn default() -> Self {
        Self {
            eye: Vec3::new(0.0, 1.7, 5.2),
            target: Vec3::new(0.0, 0.5, 0.0),
            volumes: vec![SoftVolume {
                center: Vec3::new(0.3, 0.5, 0.0),
                radius: 0.9,
                color: Vec3::new(0.9, 0.9, 0.95),
                density: 1.5,
            }],
            front_box: (Vec3::new(-0.25, 0.35, 1.4), 0.35),
            impostor: Ball {
                center: Vec3::new(1.15, 0.45, 1.3),
                radius: 0.45,
                index: OPAQUE_OBJECTS,
            },
            refractor: Ball {
                center: Vec3::new(-1.3, 0.5, 0.6),
                radius: 0.5,
                index: OPAQUE_OBJECTS + 1,
            },
        }
    }
}

impl World {
    /// World-to-view and view-to-clip for a square image.
    pub fn camera(&self) -> (Mat4, Mat4) {
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, Vec3::Y);
        let fov_y = 45f32.to_radians();
        let projection = glam::camera::rh::proj::directx::perspective(fov_y, 1.0, 0.1, 50.0);
        (view, projection)
    }

    /// The pixel (column, row from the top) a world point projects to in a `size` image.
    pub fn pixel_of(&self, point: Vec3, size: u32) -> (u32, u32) {
        let (view, projection) = self.camera();
        let ndc = (projection * view).project_point3(point);
        let x = (ndc.x * 0.5 + 0.5) * size as f32;
        let y = (0.5 - ndc.y * 0.5) * size as f32;
        (x as u32, y as u32)
    }

    /// The opaque objects' triangles, and each object's index and vertex range.
    pub(crate) fn opaque_triangles(&self) -> (Vec<Vertex>, Vec<(usize, std::ops::Range<u32>)>) {
        let (mut out, mut ranges) = (Vec::new(), Vec::new());
        let mut object = |out: &mut Vec<Vertex>, add: &dyn Fn(&mut Vec<Vertex>)| {
            let start = out.len() as u32;
            add(out);
            ranges.push((ranges.len(), start..out.len() as u32));
        };
        // The room: a floor, the wall the camera faces, and a warm wall behind the camera that
        // only the glass balls show.
        let grey = [0.7, 0.7, 0.7];
        let warm = [0.8, 0.6, 0.35];
        object(&mut out, &|o| {
            quad(
                o,
                [-6.0, 0.0, -3.0],
                [12.0, 0.0, 0.0],
                [0.0, 0.0, 12.0],
                grey,
            );
            quad(o, [-6.0, 0.0, 9.0], [12.0, 0.0, 0.0], [0.0, 6.0, 0.0], warm);
        });
        let wall = [0.5, 0.6, 0.7];
        object(&mut out, &|o| {
            quad(
                o,
                [-6.0, 0.0, -3.0],
                [0.0, 6.0, 0.0],
                [12.0, 0.0, 0.0],
                wall,
            )
        });
        let (centre, half) = self.front_box;
        object(&mut out, &|o| cube(o, centre, half, [0.8, 0.2, 0.15]));
        object(&mut out, &|o| {
            cube(o, Vec3::new(1.2, 0.5, -1.8), 0.5, [0.2, 0.3, 0.8])
        });
        debug_assert_eq!(ranges.len(), OPAQUE_OBJECTS);
        (out, ranges)
    }
}

/// Two triangles spanning `a`, `a + u`, `a + v`, `a + u + v`, with normal `v x u`
/// (no culling: either winding is drawn).
fn quad(out: &mut Vec<Vertex>, a: [f32; 3], u: [f32; 3], v: [f32; 3], color: [f32; 3]) {
    let (a, u, v) = (Vec3::from(a), Vec3::from(u), Vec3::from(v));
    let normal = v.cross(u).normalize().to_array();
    for p in [a, a + u, a + u + v, a, a + u + v, a + v] {
        out.push(Vertex {
            position: p.to_array(),
            normal,
            color,
        });
    }
}

/// The six faces of an axis-aligned cube, normals outward.
fn cube(out: &mut Vec<Vertex>, centre: Vec3, half: f32, color: [f32; 3]) {
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = Vec3::AXES[axis] * sign;
            let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
            let (u, v) = if sign > 0.0 { (v, u) } else { (u, v) };
            let a = centre + (n - u - v) * half;
            quad(
                out,
                a.into(),
                (u * 2.0 * half).into(),
                (v * 2.0 * half).into(),
                color,
            );
        }
    }
}
