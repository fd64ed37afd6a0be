//! A BVH over every triangle of a scene at one instant, with exact ray queries.
//!
//! The reference renderer, the photon tracer and several tests need to ask "what does this
//! ray hit first?" (closest hit) and "does anything block this segment?" (any hit). Both are
//! answered by one acceleration structure over *all* world-space triangles of the scene:
//!
//! 1. **Flatten.** Each object's mesh, at `time` (a deforming object's vertices and normals
//!    are [`Object::positions_at`](crate::Object::positions_at) and
//!    [`Object::normals_at`](crate::Object::normals_at)), is transformed to world space with
//!    [`Object::world_at`](crate::Object::world_at)`(time)`. Each triangle remembers where it
//!    came from (object index, triangle index within that object's mesh) and carries the
//!    attributes shading needs: the three vertex normals, transformed by
//!    [`Object::normal_matrix_at`](crate::Object::normal_matrix_at) and normalised per vertex
//!    (the GPU upload does the same, so both interpolate the same vectors), the three uvs, and
//!    the unit geometric normal. Zero-area triangles are dropped: no ray can hit them.
//! 2. **Build.** obvhs builds a compressed-wide BVH (8-wide "CWBVH", Ylitie et al. 2017)
//!    from the triangles' bounds (padded by a few ulps, so that node tests never reject a ray
//!    through an edge or vertex) with PLOC and reinsertion (`BvhBuildParams::medium_build`).
//!    The BVH's leaves refer to primitives through `primitive_indices`; we reorder our
//!    triangle arrays once by that table so a leaf's primitive id indexes them directly.
//! 3. **Query.** Traversal calls back for each candidate triangle; we intersect it in
//!    obvhs' `RtTriangle` layout (Möller-Trumbore as in madmann91's `bvh`, with an inside
//!    test that keeps hits exactly on shared edges, see `intersect` below), and
//!    `RtTriangle::compute_barycentric` gives accurate barycentrics `(u, v)` such that the
//!    hit point is `(1 - u - v) v0 + u v1 + v v2`. (`Triangle::compute_barycentric` normalises its normal
//!    and is off by up to 6e-2, see NOTES-platform.md; it is not used.)
//!
//! Conventions of a [`Hit`]:
//! - `t` is the ray parameter in units of `|dir|` (callers pass unit directions, so it is a
//!   distance in metres). Rays start at `t = 0`: callers offset their origins to avoid
//!   self-intersection.
//! - `geometric_normal` follows the triangle's winding in *object space* (counter-clockwise
//!   seen from the front, as `mesh.rs` generates and glTF specifies). Under a transform with
//!   a negative determinant (a mirroring) the world-space winding flips, so the world
//!   winding normal is negated back: the geometric normal then always lies on the same side
//!   as the authored shading normals.
//! - Neither normal is flipped toward the ray: surfaces are two-sided, and the caller decides
//!   which side it is on (`dot(dir, geometric_normal) > 0` means it hit the back).

use crate::{Scene, Texture};
use glam::{Mat3, Vec2, Vec3, Vec3A};
use obvhs::{
    BvhBuildParams,
    aabb::Aabb,
    cwbvh::{CwBvh, builder::build_cwbvh},
    ray::{Ray, RayHit},
    rt_triangle::RtTriangle,
    triangle::Triangle,
};
use std::time::Duration;

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

/// Per-triangle shading attributes (stored in BVH primitive order by [`SceneBvh`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleInfo {
    pub object: u32,
    /// Triangle index within the object's mesh.
    pub triangle: u32,
    /// World-space unit vertex normals.
    pub normals: [Vec3; 3],
    pub uvs: [Vec2; 3],
    /// Unit geometric normal (winding in object space, see the module docs).
    pub geometric_normal: Vec3,
}

impl TriangleInfo {
    /// The hit at barycentrics `(u, v)` (weights `(1 - u - v, u, v)` of `(v0, v1, v2)`) of a
    /// ray `origin + t dir`: the interpolation every tracer of the workspace shares.
    pub fn hit(&self, origin: Vec3, dir: Vec3, t: f32, bary: Vec2) -> Hit {
        let (u, v) = (bary.x, bary.y);
        let w = 1.0 - u - v;
        let interpolated = self.normals[0] * w + self.normals[1] * u + self.normals[2] * v;
        Hit {
            t,
            object: self.object as usize,
            triangle: self.triangle as usize,
            position: origin + dir * t,
            normal: interpolated.normalize_or(self.geometric_normal),
            geometric_normal: self.geometric_normal,
            uv: self.uvs[0] * w + self.uvs[1] * u + self.uvs[2] * v,
        }
    }
}

/// Every non-degenerate world-space triangle of a scene at one time, with its attributes,
/// in scene order (objects in order, triangles in mesh order): step 1 of the module docs,
/// shared by [`SceneBvh::build`] and the GPU ray tracer's BVH.
#[derive(Clone, Debug, Default)]
pub struct WorldTriangles {
    pub triangles: Vec<Triangle>,
    pub info: Vec<TriangleInfo>,
    /// World-space bounds (min, max); zero when there is no triangle.
    pub bounds: (Vec3, Vec3),
}

impl WorldTriangles {
    /// The triangles of every object of `scene` placed at `time`.
    pub fn of(scene: &Scene, time: f32) -> Self {
        let mut tris: Vec<Triangle> = Vec::with_capacity(scene.triangle_count());
        let mut info: Vec<TriangleInfo> = Vec::with_capacity(scene.triangle_count());
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for (oi, object) in scene.objects.iter().enumerate() {
            let world = object.world_at(time);
            let normal_matrix: Mat3 = object.normal_matrix_at(time);
            let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
            let mesh = &object.mesh;
            // The vertices at `time`: a deforming object's morph blended in.
            let normals = object.normals_at(time);
            let positions: Vec<Vec3> = object
                .positions_at(time)
                .iter()
                .map(|p| world.transform_point3(*p))
                .collect();
            for (ti, idx) in mesh.indices.chunks_exact(3).enumerate() {
                let [a, b, c] = [idx[0] as usize, idx[1] as usize, idx[2] as usize];
                let (v0, v1, v2) = (positions[a], positions[b], positions[c]);
                let cross = (v1 - v0).cross(v2 - v0);
                let len2 = cross.length_squared();
                if !(len2 > 0.0 && len2.is_finite()) {
                    continue; // degenerate (or non-finite): cannot be hit
                }
                let mut geometric_normal = cross / len2.sqrt();
                if mirrored {
                    geometric_normal = -geometric_normal;
                }
                let vertex_normal = |i: usize| {
                    normals
                        .get(i)
                        .map(|n| (normal_matrix * *n).normalize_or(geometric_normal))
                        .unwrap_or(geometric_normal)
                };
                let vertex_uv = |i: usize| mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
                tris.push(Triangle {
                    v0: v0.into(),
                    v1: v1.into(),
                    v2: v2.into(),
                });
                info.push(TriangleInfo {
                    object: oi as u32,
                    triangle: ti as u32,
                    normals: [vertex_normal(a), vertex_normal(b), vertex_normal(c)],
                    uvs: [vertex_uv(a), vertex_uv(b), vertex_uv(c)],
                    geometric_normal,
                });
                lo = lo.min(v0.min(v1).min(v2));
                hi = hi.max(v0.max(v1).max(v2));
            }
        }
        let bounds = if tris.is_empty() {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (lo, hi)
        };
        Self {
            triangles: tris,
            info,
            bounds,
        }
    }
}

/// All triangles of a scene at one time, in a CWBVH.
pub struct SceneBvh {
    /// `None` when the scene has no (non-degenerate) triangle: every query misses.
    bvh: Option<CwBvh>,
    /// Intersection-ready triangles in BVH primitive order.
    triangles: Vec<RtTriangle>,
    /// Attributes in the same order as `triangles`.
    info: Vec<TriangleInfo>,
    bounds: (Vec3, Vec3),
    /// The objects' alpha cut-outs; none when no object has one (every candidate hit then
    /// stands).
    cutouts: Option<Cutouts>,
}

impl SceneBvh {
    /// Builds the BVH over every object of `scene` placed at `time`.
    pub fn build(scene: &Scene, time: f32) -> Self {
        let WorldTriangles {
            triangles: tris,
            info,
            bounds,
        } = WorldTriangles::of(scene, time);
        if tris.is_empty() {
            return Self {
                bvh: None,
                triangles: vec![],
                info: vec![],
                bounds: (Vec3::ZERO, Vec3::ZERO),
                cutouts: None,
            };
        }
        // The boxes are built around each triangle's bounds padded by a few ulps: a ray through
        // a triangle's edge or vertex can enter the triangle's box exactly at its surface, where
        // rounding in the node test (entry a hair beyond exit) would reject it; the triangle
        // test itself keeps such hits (see `intersect`).
        let padded: Vec<Aabb> = tris.iter().map(|t| padded_bounds(t.aabb())).collect();
        let bvh = build_cwbvh(
            &padded,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        // Reorder so that a leaf's primitive id indexes our arrays without indirection.
        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| RtTriangle::from(&tris[i as usize]))
            .collect();
        let info = bvh
            .primitive_indices
            .iter()
            .map(|&i| info[i as usize])
            .collect();
        Self {
            bvh: Some(bvh),
            triangles,
            info,
            bounds,
            cutouts: Cutouts::of(scene),
        }
    }

    /// The ray parameter of `ray`'s hit on primitive `id`, or infinity: a miss, or a hit in a
    /// hole of its object's alpha cut-out (the surface is not there, the ray goes on).
    fn candidate(&self, id: usize, ray: &Ray) -> f32 {
        let t = intersect(&self.triangles[id], ray);
        if t.is_finite() && self.in_hole(id, ray) {
            return f32::INFINITY;
        }
        t
    }

    /// Whether `ray` meets primitive `id` where its texture's alpha is below its cut-out.
    fn in_hole(&self, id: usize, ray: &Ray) -> bool {
        let info = &self.info[id];
        let Some(cutouts) = &self.cutouts else {
            return false;
        };
        let Some(Some((texture, cutoff))) = cutouts.objects.get(info.object as usize) else {
            return false;
        };
        let b = self.triangles[id].compute_barycentric(ray);
        let uv = info.uvs[0] * (1.0 - b.x - b.y) + info.uvs[1] * b.x + info.uvs[2] * b.y;
        cutouts.textures[*texture].sample_alpha(uv) < *cutoff
    }

    /// Number of triangles in the BVH (degenerate triangles are left out).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// World-space bounds (min, max) of all triangles; zero for an empty scene.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    /// The first surface along `origin + t dir`, `0 <= t <= t_max`.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        self.closest_hit_where(origin, dir, t_max, |_| true)
    }

    /// The first surface of an object for which `accept(object index)` holds.
    pub fn closest_hit_where(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        accept: impl Fn(usize) -> bool,
    ) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = ray(origin, dir, t_max)?;
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut hit, |r, id| {
            if accept(self.info[id].object as usize) {
                self.candidate(id, r)
            } else {
                f32::INFINITY
            }
        });
        if !found {
            return None;
        }
        let id = hit.primitive_id as usize;
        // Barycentrics of the hit: weights (1 - u - v, u, v) of (v0, v1, v2).
        let bary = self.triangles[id].compute_barycentric(&ray);
        Some(self.info[id].hit(origin, dir, hit.t, bary))
    }

    /// Whether any surface lies on `origin + t dir`, `0 <= t <= t_max` (shadow rays).
    pub fn any_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.any_hit_where(origin, dir, t_max, |_| true)
    }

    /// Whether any surface of an object for which `blocks(object index)` holds lies on the
    /// segment (for example a shadow ray that ignores the objects a technique handles itself).
    pub fn any_hit_where(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        blocks: impl Fn(usize) -> bool,
    ) -> bool {
        let (Some(bvh), Some(ray)) = (self.bvh.as_ref(), ray(origin, dir, t_max)) else {
            return false;
        };
        !bvh.ray_traverse_miss(ray, |r, id| {
            if blocks(self.info[id].object as usize) {
                self.candidate(id, r)
            } else {
                f32::INFINITY
            }
        })
    }

    /// World-space vertices of the triangle behind a hit (for tests and debugging).
    pub fn hit_triangle_vertices(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<[Vec3; 3]> {
        let bvh = self.bvh.as_ref()?;
        let ray = ray(origin, dir, t_max)?;
        let mut hit = RayHit::none();
        if !bvh.ray_traverse(ray, &mut hit, |r, id| self.candidate(id, r)) {
            return None;
        }
        let t = &self.triangles[hit.primitive_id as usize];
        let v0: Vec3A = t.v0;
        Some([v0.into(), (v0 - t.e1).into(), (v0 + t.e2).into()])
    }
}

/// The alpha cut-outs of a scene's objects ([`crate::Material::cutout`]): per object, the index
/// of its texture in `textures` and its threshold; each texture copied once, however many
/// objects share it (a forest's leaves share one atlas).
struct Cutouts {
    objects: Vec<Option<(usize, f32)>>,
    textures: Vec<Texture>,
}

impl Cutouts {
    /// `None` when no object of `scene` is cut out.
    fn of(scene: &Scene) -> Option<Self> {
        let mut slots: std::collections::BTreeMap<usize, usize> = Default::default();
        let mut textures = Vec::new();
        let objects: Vec<_> = scene
            .objects
            .iter()
            .map(|o| {
                let (t, cutoff) = o.material.cutout()?;
                let texture = scene.textures.get(t)?;
                let slot = *slots.entry(t).or_insert_with(|| {
                    textures.push(texture.clone());
                    textures.len() - 1
                });
                Some((slot, cutoff))
            })
            .collect();
        (!textures.is_empty()).then_some(Self { objects, textures })
    }
}

/// The obvhs ray for a query, or `None` (the query misses) for a ray no traversal can follow:
/// a non-finite or zero direction, a non-finite origin, or a NaN or negative `t_max`. Zero
/// direction *components* are fine: obvhs stores their inverse as a large finite number
/// (`safe_inverse`), never an infinity. A NaN ray would fail obvhs' debug assertion on the
/// inverse direction instead of missing, so no caller may pass one; this is the last guard.
///
/// A direction component of `-0.0` is made `+0.0`: obvhs' CWBVH node test orders each slab by
/// `direction < 0.0` (false for `-0.0`) but inverts the direction with the sign of zero
/// (`safe_inverse(-0.0)` is a large *negative* number), so with a `-0.0` component the two
/// disagreed and the ray missed every node box it started inside (the tracer's property tests,
/// `raytracer/tests/bvh_properties.rs`, found rays from inside a box that passed through it).
fn ray(origin: Vec3, dir: Vec3, t_max: f32) -> Option<Ray> {
    let usable = origin.is_finite() && dir.is_finite() && dir != Vec3::ZERO && t_max >= 0.0;
    let dir = dir + Vec3::ZERO; // -0.0 + 0.0 = +0.0 (IEEE 754, round to nearest)
    usable.then(|| Ray::new(origin.into(), dir.into(), 0.0, t_max))
}

/// `b` grown on every side by `BOX_PADDING` of its largest coordinate's magnitude (at least of
/// 1): a few ulps of the node test's arithmetic at that scale.
fn padded_bounds(b: Aabb) -> Aabb {
    let scale = b.min.abs().max(b.max.abs()).max_element().max(1.0);
    let pad = Vec3A::splat(BOX_PADDING * scale);
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}

/// Relative padding of the triangles' boxes (`padded_bounds`).
const BOX_PADDING: f32 = 4.0 * f32::EPSILON;

/// Möller-Trumbore on obvhs' `RtTriangle` layout (`e1 = v0 - v1`, `e2 = v2 - v0`,
/// `ng = e1 x e2`): the ray parameter of the hit, or infinity.
///
/// Same arithmetic as `RtTriangle::intersect`, but the inside test compares values instead of
/// sign bits: obvhs rejects a barycentric of -0.0, which a ray from behind produces exactly on
/// a shared edge, so an axis-aligned ray through the diagonal of an axis-aligned quad (the
/// centre of a Cornell floor, for one) passed between its two triangles.
#[inline(always)]
pub fn intersect(tri: &RtTriangle, ray: &Ray) -> f32 {
    let c = tri.v0 - ray.origin;
    let r = ray.direction.cross(c);
    let det = tri.ng.dot(ray.direction);
    if det == 0.0 {
        return f32::INFINITY;
    }
    let inv_det = 1.0 / det;
    let u = r.dot(tri.e2) * inv_det;
    let v = r.dot(tri.e1) * inv_det;
    if u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
        let t = tri.ng.dot(c) * inv_det;
        if t >= ray.tmin && t <= ray.tmax {
            return t;
        }
    }
    f32::INFINITY
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{cuboid, quad, uv_sphere};
    use crate::{Camera, CameraPath, Material, Motion, Object};
    use glam::{Mat4, Quat};
    use proptest::prelude::*;

    fn scene_of(objects: Vec<Object>) -> Scene {
        Scene {
            name: "test".into(),
            objects,
            textures: vec![],
            lights: vec![],
            camera: Camera {
                eye: Vec3::Z,
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 60.0,
                orthographic: None,
            },
            camera_path: CameraPath::default(),
            volumes: vec![],
            medium: None,
            background: Vec3::ZERO,
        }
    }

    fn white() -> Material {
        Material::diffuse(0.5, 0.5, 0.5)
    }

    /// A ray with `-0.0` direction components from inside a closed box hits its wall (obvhs
    /// alone let it through: see `ray`).
    #[test]
    fn negative_zero_directions_from_inside_a_box_hit_it() {
        let bvh = SceneBvh::build(
            &scene_of(vec![Object::new(
                "box",
                cuboid(Vec3::splat(-1.0), Vec3::ONE),
                white(),
                Mat4::IDENTITY,
            )]),
            0.0,
        );
        for d in [
            Vec3::new(-0.0, 1.0, 0.0),
            Vec3::new(0.0, -0.0, 1.0),
            Vec3::new(-0.0, -0.0, -1.0),
            Vec3::new(-0.6, -0.0, -0.8),
        ] {
            let hit = bvh.closest_hit(Vec3::new(0.1, -0.2, 0.05), d, f32::INFINITY);
            assert!(hit.is_some(), "{d:?} passed through the box");
        }
    }

    #[test]
    fn unit_quad_hit_at_analytic_t_with_uv_and_normals() {
        // Quad in the plane z = 0 from (0,0) to (1,1), normal +Z.
        let q = quad(Vec3::ZERO, Vec3::X, Vec3::Y, Vec2::ONE);
        let bvh = SceneBvh::build(
            &scene_of(vec![Object::new("q", q, white(), Mat4::IDENTITY)]),
            0.0,
        );
        assert_eq!(bvh.triangle_count(), 2);
        // (0.25, 0.25) and (0.5, 0.5) lie on the diagonal both triangles share: the rays from
        // behind hit it exactly (a regression test for the inside test in `intersect`).
        for (x, y) in [
            (0.25, 0.25),
            (0.75, 0.2),
            (0.1, 0.9),
            (0.5, 0.5),
            (0.9, 0.6),
        ] {
            let o = Vec3::new(x, y, 3.0);
            let h = bvh.closest_hit(o, Vec3::NEG_Z, f32::INFINITY).expect("hit");
            assert!((h.t - 3.0).abs() < 1e-6, "t = {}", h.t);
            assert!((h.position - Vec3::new(x, y, 0.0)).length() < 1e-6);
            assert!((h.normal - Vec3::Z).length() < 1e-6);
            assert!((h.geometric_normal - Vec3::Z).length() < 1e-6);
            // quad uvs: u along the first edge, v = 1 at the origin and 0 at the far edge.
            assert!(
                (h.uv - Vec2::new(x, 1.0 - y)).length() < 1e-5,
                "uv {:?} at {x},{y}",
                h.uv
            );
            assert_eq!(h.object, 0);
            // From behind: same t, normals still as authored.
            let back = bvh
                .closest_hit(Vec3::new(x, y, -2.0), Vec3::Z, f32::INFINITY)
                .expect("hit");
            assert!((back.t - 2.0).abs() < 1e-6);
            assert!(back.geometric_normal.dot(Vec3::Z) > 0.999);
        }
        // Misses outside the quad and beyond t_max.
        assert!(
            bvh.closest_hit(Vec3::new(1.5, 0.5, 1.0), Vec3::NEG_Z, f32::INFINITY)
                .is_none()
        );
        assert!(
            bvh.closest_hit(Vec3::new(0.5, 0.5, 1.0), Vec3::NEG_Z, 0.9)
                .is_none()
        );
        assert!(!bvh.any_hit(Vec3::new(0.5, 0.5, 1.0), Vec3::NEG_Z, 0.9));
        assert!(bvh.any_hit(Vec3::new(0.5, 0.5, 1.0), Vec3::NEG_Z, 1.1));
    }

    #[test]
    fn box_hits_and_object_bookkeeping() {
        // A unit box moved to (0, 0.5, -3) by its transform, plus a scaled, rotated, moving box.
        let unit = cuboid(Vec3::splat(-0.5), Vec3::splat(0.5));
        let a = Object::new(
            "a",
            unit.clone(),
            white(),
            Mat4::from_translation(Vec3::new(0.0, 0.5, -3.0)),
        );
        let mut b = Object::new(
            "b",
            unit,
            white(),
            Mat4::from_scale_rotation_translation(
                Vec3::new(2.0, 1.0, 1.0),
                Quat::from_rotation_y(0.3),
                Vec3::ZERO,
            ),
        );
        b.motion = Motion {
            keys: vec![(0.0, Vec3::ZERO), (1.0, Vec3::new(10.0, 0.0, 0.0))],
        };
        let scene = scene_of(vec![a, b]);
        let bvh = SceneBvh::build(&scene, 1.0); // b sits at x = 10
        let h = bvh
            .closest_hit(Vec3::new(0.1, 0.6, 5.0), Vec3::NEG_Z, f32::INFINITY)
            .unwrap();
        assert_eq!(h.object, 0);
        assert!((h.t - (5.0 + 2.5)).abs() < 1e-5);
        assert!((h.normal - Vec3::Z).length() < 1e-5);
        // From inside the box, the far wall.
        let h = bvh
            .closest_hit(Vec3::new(0.0, 0.5, -3.0), Vec3::X, f32::INFINITY)
            .unwrap();
        assert!((h.t - 0.5).abs() < 1e-6);
        assert!((h.geometric_normal - Vec3::X).length() < 1e-5);
        // The moved box: hit along -x from x = 20 at its +X face; its world normal is the
        // rotated +X face normal (rotation by 0.3 about Y; the scale does not tilt a face normal
        // it is aligned with).
        let h = bvh
            .closest_hit(Vec3::new(20.0, 0.0, 0.0), Vec3::NEG_X, f32::INFINITY)
            .unwrap();
        assert_eq!(h.object, 1);
        let n = Quat::from_rotation_y(0.3) * Vec3::X;
        assert!((h.normal - n).length() < 1e-5, "{:?} vs {n:?}", h.normal);
        assert!((h.geometric_normal - n).length() < 1e-5);
        // Face at x' = 1 in the rotated frame: t = 20 - 10 - 1/cos(0.3).
        assert!(
            (h.t - (10.0 - 1.0 / 0.3f32.cos())).abs() < 1e-4,
            "t = {}",
            h.t
        );
        // The triangle index refers to the object's own mesh.
        let [p0, p1, p2] = bvh
            .hit_triangle_vertices(Vec3::new(20.0, 0.0, 0.0), Vec3::NEG_X, f32::INFINITY)
            .unwrap();
        let world = scene.objects[1].world_at(1.0);
        let tri = &scene.objects[1].mesh.indices[3 * h.triangle..3 * h.triangle + 3];
        for (p, i) in [p0, p1, p2].iter().zip(tri) {
            assert!(
                (world.transform_point3(scene.objects[1].mesh.positions[*i as usize]) - *p)
                    .length()
                    < 1e-5
            );
        }
        // A filter that ignores object 0 sees through it.
        let o = Vec3::new(0.0, 0.5, 5.0);
        assert!(bvh.any_hit(o, Vec3::NEG_Z, 100.0));
        assert!(!bvh.any_hit_where(o, Vec3::NEG_Z, 100.0, |i| i != 0));
        assert!(
            bvh.closest_hit_where(o, Vec3::NEG_Z, 100.0, |i| i != 0)
                .is_none()
        );
    }

    /// A unit sphere whose morph target is the sphere of radius 2 (weight 0 -> 1 over one
    /// second): the BVH at time t holds the sphere of radius 1 + w(t). The ray along -z
    /// through the centre meets the mesh at a vertex (the equator vertex at phi = 3 pi / 2),
    /// so the distance is exact up to rounding.
    #[test]
    fn bvh_at_a_time_hits_the_morphed_surface() {
        let mesh = uv_sphere(1.0, 16, 64);
        let morph = crate::Morph {
            positions: mesh.positions.iter().map(|p| *p * 2.0).collect(),
            normals: mesh.normals.clone(),
            keys: vec![(0.0, 0.0), (1.0, 1.0)],
        };
        let centre = Vec3::new(1.0, 0.5, 0.0);
        let sphere = Object::new("morphing", mesh, white(), Mat4::from_translation(centre))
            .with_morph(morph);
        let scene = scene_of(vec![sphere]);
        scene.validate().unwrap();
        for (time, radius) in [(0.0, 1.0), (0.5, 1.5), (1.0, 2.0), (3.0, 2.0)] {
            let bvh = SceneBvh::build(&scene, time);
            let origin = centre + Vec3::Z * 10.0;
            let h = bvh.closest_hit(origin, Vec3::NEG_Z, f32::INFINITY).unwrap();
            assert!(
                (h.t - (10.0 - radius)).abs() < 1e-5,
                "t = {time}: hit at {} for radius {radius}",
                h.t
            );
            assert!((h.normal - Vec3::Z).length() < 1e-5, "{}", h.normal);
            let (lo, hi) = bvh.bounds();
            assert!((hi.y - lo.y - 2.0 * radius).abs() < 1e-4);
            // From the centre, every direction meets the surface within the mesh's sagitta.
            let h = bvh.closest_hit(centre, Vec3::new(0.3, 0.8, -0.2).normalize(), 100.0);
            let t = h.unwrap().t;
            assert!(t <= radius + 1e-5 && t > radius * 0.98, "{t} vs {radius}");
        }
    }

    #[test]
    fn mirrored_transform_keeps_normals_consistent() {
        let q = quad(Vec3::ZERO, Vec3::X, Vec3::Y, Vec2::ONE);
        let o = Object::new("m", q, white(), Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        let bvh = SceneBvh::build(&scene_of(vec![o]), 0.0);
        let h = bvh
            .closest_hit(Vec3::new(-0.5, 0.5, 1.0), Vec3::NEG_Z, 10.0)
            .unwrap();
        assert!(h.normal.dot(Vec3::Z) > 0.999);
        assert!(h.geometric_normal.dot(Vec3::Z) > 0.999);
    }

    #[test]
    fn empty_scene_misses() {
        let bvh = SceneBvh::build(&scene_of(vec![]), 0.0);
        assert!(
            bvh.closest_hit(Vec3::ZERO, Vec3::X, f32::INFINITY)
                .is_none()
        );
        assert!(!bvh.any_hit(Vec3::ZERO, Vec3::X, f32::INFINITY));
    }

    fn sphere_bvh() -> &'static SceneBvh {
        static BVH: std::sync::OnceLock<SceneBvh> = std::sync::OnceLock::new();
        BVH.get_or_init(|| {
            let s = Object::new(
                "s",
                uv_sphere(1.0, 32, 64),
                white(),
                Mat4::from_translation(Vec3::new(0.2, -0.1, 0.3)),
            );
            SceneBvh::build(&scene_of(vec![s]), 0.0)
        })
    }

    fn unit_dir(theta: f64, phi: f64) -> Vec3 {
        let (t, p) = (theta as f32, phi as f32);
        Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin())
    }

    proptest! {
        /// Against the analytic sphere: the mesh is inscribed, its largest gap to the sphere
        /// (the sagitta over a cell diagonal) is below 1 - cos(0.07) = 2.5e-3 for 32 x 64
        /// cells, and along a ray that meets the surface at incidence cosine c the distance
        /// error is at most gap / c (tolerance 3e-3 / c). Rays are aimed at an impact parameter b <= 0.9, so c >= 0.43.
        #[test]
        fn closest_hit_agrees_with_analytic_sphere(
            theta in 0.0f64..std::f64::consts::PI, phi in 0.0f64..std::f64::consts::TAU,
            dist in 1.5f32..20.0,
            aim_theta in 0.0f64..std::f64::consts::PI, aim_phi in 0.0f64..std::f64::consts::TAU,
            aim_r in 0.0f32..0.9,
        ) {
            let center = Vec3::new(0.2, -0.1, 0.3);
            let origin = center + unit_dir(theta, phi) * dist;
            let aim = center + unit_dir(aim_theta, aim_phi) * aim_r;
            let dir = (aim - origin).normalize();
            let analytic = gpu::prelude::ray_sphere(origin, dir, center, 1.0);
            prop_assume!(analytic.x <= analytic.y && analytic.x > 0.0);
            let b = (origin - center).cross(dir).length();
            prop_assume!(b <= 0.9);
            let cos_i = (1.0 - b * b).sqrt();
            let h = sphere_bvh().closest_hit(origin, dir, f32::INFINITY);
            prop_assert!(h.is_some());
            let h = h.unwrap();
            let tol = 3e-3 / cos_i + 1e-4;
            prop_assert!((h.t - analytic.x).abs() <= tol, "t {} vs {} (tol {})", h.t, analytic.x, tol);
            // Smooth normal within a cell's angular size of the true normal.
            let n_true = (origin + dir * analytic.x - center).normalize();
            prop_assert!(h.normal.dot(n_true) > 0.1f32.cos(), "normal {:?} vs {:?}", h.normal, n_true);
            prop_assert!(h.geometric_normal.dot(n_true) > 0.1f32.cos());
            // any_hit agrees with closest_hit on either side of the hit distance.
            prop_assert!(sphere_bvh().any_hit(origin, dir, h.t + 1e-3));
            prop_assert!(!sphere_bvh().any_hit(origin, dir, h.t - 1e-3));
        }

        /// From inside, every ray hits, at about the radius.
        #[test]
        fn from_inside_every_ray_hits(theta in 0.0f64..std::f64::consts::PI, phi in 0.0f64..std::f64::consts::TAU) {
            let center = Vec3::new(0.2, -0.1, 0.3);
            let dir = unit_dir(theta, phi);
            let h = sphere_bvh().closest_hit(center, dir, f32::INFINITY);
            prop_assert!(h.is_some());
            let t = h.unwrap().t;
            prop_assert!((1.0 - 2.5e-3..=1.0 + 1e-5).contains(&t), "t = {}", t);
        }
    }

    #[test]
    fn any_hit_agrees_with_closest_hit_on_random_rays() {
        let scene = scene_of(vec![
            Object::new(
                "box",
                cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)),
                white(),
                Mat4::IDENTITY,
            ),
            Object::new(
                "s",
                uv_sphere(0.4, 12, 24),
                white(),
                Mat4::from_translation(Vec3::new(1.2, 0.3, 0.0)),
            ),
        ]);
        let bvh = SceneBvh::build(&scene, 0.0);
        let mut state = 12345u32;
        let mut rnd = || {
            state = gpu::prelude::pcg_hash(state);
            state as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let o = Vec3::new(rnd(), rnd(), rnd()) * 3.0;
            let d = Vec3::new(rnd(), rnd(), rnd()).normalize_or(Vec3::X);
            let t_max = 2.0 + 2.0 * rnd();
            let closest = bvh.closest_hit(o, d, t_max);
            assert_eq!(
                closest.is_some(),
                bvh.any_hit(o, d, t_max),
                "ray {o:?} {d:?} {t_max}"
            );
            if let Some(h) = closest {
                assert!(h.t >= 0.0 && h.t <= t_max);
            }
        }
    }
}
