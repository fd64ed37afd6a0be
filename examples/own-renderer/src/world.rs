//! The renderer's world: a floor, two walls, two boxes, two glass balls, three glass pawns, a
//! building with rooms behind its windows and a ball of smoke, described with its own types.

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
        mesh.indices = ring_triangles(rings, segments);
        mesh
    }
}

/// The triangles between `rings + 1` rings of `segments + 1` vertices each (the last vertex of
/// a ring on its first, for the seam), ring after ring.
fn ring_triangles(rings: u32, segments: u32) -> Vec<u32> {
    let row = segments + 1;
    let mut indices = Vec::new();
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * row + segment;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            indices.extend([a, b, c, b, d, c]);
        }
    }
    indices
}

/// A glass pawn standing on the floor: a lathed piece, where its base stands, and its index
/// among the renderer's objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pawn {
    /// The centre of its base, on the floor (world).
    pub base: Vec3,
    /// Index among the renderer's objects.
    pub index: usize,
}

impl Pawn {
    /// Its height.
    pub const HEIGHT: f32 = 1.15;

    /// The centre of its bounds (world).
    pub fn center(&self) -> Vec3 {
        self.base + Vec3::Y * Self::HEIGHT * 0.5
    }

    /// Its triangles with the centre of its base at the origin, y up (the passes place it at
    /// `base`): a profile of (radius, height) turned about the y axis.
    pub fn mesh() -> HostedMesh {
        let scale = Self::HEIGHT / 0.88;
        let mut profile: Vec<(f32, f32)> = vec![(0.0, 0.0), (0.15, 0.0), (0.3, 0.0)];
        profile.extend([(0.3, 0.06), (0.26, 0.1), (0.2, 0.14)]);
        profile.extend((1..=4).map(|i| {
            let t = i as f32 / 4.0;
            (0.2 - 0.09 * t, 0.14 + 0.36 * t)
        }));
        profile.extend([(0.18, 0.54), (0.18, 0.57), (0.11, 0.6)]);
        // The head: a ball of radius 0.15 about (0, 0.72), from 40 degrees below its equator
        // to its pole.
        profile.extend((0..=8).map(|i| {
            let a = (-40.0f32 + 130.0 * i as f32 / 8.0).to_radians();
            (0.15 * a.cos().max(0.0), 0.72 + 0.15 * a.sin())
        }));
        lathe(&profile, scale)
    }
}

/// The surface of `profile` ((radius, height) points from the bottom's centre to the top's,
/// `scale`d) turned about the y axis, normals outward.
fn lathe(profile: &[(f32, f32)], scale: f32) -> HostedMesh {
    let segments = 32u32;
    let points: Vec<glam::Vec2> = profile
        .iter()
        .map(|&(r, y)| glam::Vec2::new(r, y) * scale)
        .collect();
    let mut mesh = HostedMesh::default();
    for (i, p) in points.iter().enumerate() {
        // The profile's tangent by central differences; outward is its clockwise normal.
        let (before, after) = (
            points[i.saturating_sub(1)],
            points[(i + 1).min(points.len() - 1)],
        );
        let tangent = after - before;
        let normal = glam::Vec2::new(tangent.y, -tangent.x).normalize_or(glam::Vec2::Y);
        for segment in 0..=segments {
            let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
            let (sin, cos) = phi.sin_cos();
            mesh.positions.push(Vec3::new(p.x * cos, p.y, p.x * sin));
            mesh.normals
                .push(Vec3::new(normal.x * cos, normal.y, normal.x * sin).normalize());
        }
    }
    mesh.indices = ring_triangles(points.len() as u32 - 1, segments);
    mesh
}

/// A building with rooms behind its windows: a box standing on the floor, its facade facing the
/// camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct House {
    /// The corner of its base with the least coordinates (world).
    pub corner: Vec3,
    /// Its width (x), height (y) and depth (z).
    pub size: Vec3,
    /// The size of a room.
    pub room: Vec3,
    /// Index among the renderer's objects.
    pub index: usize,
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
    /// The two glass pawns of refractor distance maps, which see each other.
    pub pawns: [Pawn; 2],
    /// The glass pawn of refractor height maps.
    pub height_pawn: Pawn,
    /// The building of interior mapping.
    pub house: House,
    /// The point light that lights the building and its rooms (position, intensity).
    pub house_light: (Vec3, Vec3),
}

/// Objects 0-3 are opaque (floor with the wall behind the camera, the wall ahead, the front
/// box, the back box); the balls and the pawns follow.
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
                center: Vec3::new(-1.25, 0.5, 1.0),
                radius: 0.5,
                index: OPAQUE_OBJECTS + 1,
            },
            pawns: [
                Pawn {
                    base: Vec3::new(-2.4, 0.0, -1.9),
                    index: OPAQUE_OBJECTS + 2,
                },
                Pawn {
                    base: Vec3::new(-1.65, 0.0, -2.3),
                    index: OPAQUE_OBJECTS + 3,
                },
            ],
            height_pawn: Pawn {
                base: Vec3::new(-0.75, 0.0, -2.4),
                index: OPAQUE_OBJECTS + 4,
            },
            house: House {
                corner: Vec3::new(1.8, 0.0, -2.95),
                size: Vec3::new(1.0, 1.6, 0.5),
                room: Vec3::new(0.333, 0.4, 0.25),
                index: OPAQUE_OBJECTS + 5,
            },
            house_light: (Vec3::new(1.0, 3.5, 2.5), Vec3::splat(40.0)),
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
