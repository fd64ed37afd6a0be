//! The scene's BVH flattened for the GPU, and the Rust twin of its traversal.
//!
//! **Build.** The triangles are the reference's own ([`scene::bvh::WorldTriangles`]: every
//! object at the frame's time, world space, degenerate triangles dropped), and obvhs builds the
//! hierarchy with the reference's parameters (`BvhBuildParams::medium_build`: PLOC, then
//! reinsertion, leaves of up to 8 triangles). The reference then converts the binary tree into
//! an 8-wide compressed one (CWBVH) for SIMD traversal on the CPU; we keep the binary tree
//! (`Bvh2`), whose nodes a compute shader reads with one 32-byte load each. The hits are the
//! same: both trees bound the same triangles and both traversals return the nearest
//! intersection with the same triangle test.
//!
//! **Layout.** Three storage buffers (`shaders/bvh.wgsl` declares the matching structs):
//! `nodes` (bounds, triangle count, first child or first triangle: obvhs' `Bvh2Node` without
//! its metadata), `triangles` in leaf order (obvhs' `RtTriangle`: `v0`, `e1 = v0 - v1`,
//! `e2 = v2 - v0`, `ng = e1 x e2`, computed here once so that the GPU tests the same numbers
//! as the CPU) and their shading `attributes` in the same order.
//!
//! **Traversal** ([`FlatBvh::closest_hit`], `trace_closest` in WGSL): a stack of at most
//! [`STACK_SIZE`] node indices; at an inner node both children's boxes are tested (slabs with
//! obvhs' `safe_inverse` of the direction, so axis-parallel rays need no special case), the
//! nearer child is visited first and the farther pushed; at a leaf every triangle is tested
//! with the reference's watertight-on-shared-edges test ([`scene::bvh::intersect`]) against
//! the nearest hit so far. Boxes are tested with their far distance widened by
//! [`BOX_SLACK`] (relative), so rounding in the slab test never rejects a triangle lying in a
//! box's face (rays grazing an axis-aligned wall), and an axis the ray runs parallel to bounds
//! it only through the origin's position between the box's planes. The any-hit query stops at
//! the first hit.

use glam::{Vec2, Vec3};
use obvhs::{
    BvhBuildParams, bvh2::builder::build_bvh2_from_tris, ray::Ray, ray::safe_inverse,
    rt_triangle::RtTriangle,
};
use scene::Scene;
use scene::bvh::{Hit, TriangleInfo, WorldTriangles, intersect};
use std::time::Duration;

/// Node indices the traversal stack holds; a tree deeper than this is refused at build time
/// ([`FlatBvh::build`]), never overflowed.
pub const STACK_SIZE: usize = 48;

/// Relative widening of a box's far distance in the slab test (a few ulps: Ize's robust
/// traversal uses `1 + 2 gamma(3)`, about 4e-7).
pub const BOX_SLACK: f32 = 1.0 + 1e-6;

/// A node as the GPU reads it (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct NodeGpu {
    pub min: [f32; 3],
    /// Triangles in this leaf; 0 for an inner node.
    pub count: u32,
    pub max: [f32; 3],
    /// Inner node: index of the first child (the second follows it). Leaf: first triangle.
    pub first: u32,
}

/// A triangle in obvhs' `RtTriangle` layout (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleGpu {
    pub v0: [f32; 3],
    pub _a: u32,
    pub e1: [f32; 3],
    pub _b: u32,
    pub e2: [f32; 3],
    pub _c: u32,
    pub ng: [f32; 3],
    pub _d: u32,
}

/// A triangle's shading attributes (96 bytes): what [`TriangleInfo::hit`] interpolates.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AttributesGpu {
    pub n0: [f32; 3],
    pub object: u32,
    pub n1: [f32; 3],
    pub triangle: u32,
    pub n2: [f32; 3],
    pub _a: u32,
    pub geometric_normal: [f32; 3],
    pub _b: u32,
    /// uv of v0 and v1.
    pub uv01: [f32; 4],
    /// uv of v2.
    pub uv2: [f32; 2],
    pub _c: [f32; 2],
}

/// Why a scene's BVH cannot be traced on the GPU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooDeep {
    pub depth: usize,
}

/// The scene at one time: a binary BVH in GPU layout, with the CPU twin of the traversal.
#[derive(Clone, Default)]
pub struct FlatBvh {
    pub nodes: Vec<NodeGpu>,
    /// Intersection-ready triangles in leaf order.
    pub triangles: Vec<RtTriangle>,
    /// Attributes in the same order.
    pub info: Vec<TriangleInfo>,
    /// Longest root-to-leaf path (nodes): the traversal stack never holds more than this.
    pub depth: usize,
    /// The objects' alpha cut-outs ([`cutout_table`]); empty (as [`FlatBvh::from_triangles`]
    /// leaves it) or `[0]`: none.
    pub cutouts: Vec<u32>,
}

impl FlatBvh {
    /// Flattens the BVH of `scene` at `time` (an empty scene gives no node: every query
    /// misses). Fails if the tree is deeper than the GPU's [`STACK_SIZE`].
    pub fn build(scene: &Scene, time: f32) -> Result<Self, TooDeep> {
        let mut flat = Self::from_triangles(WorldTriangles::of(scene, time))?;
        flat.cutouts = cutout_table(scene);
        Ok(flat)
    }

    /// Flattens the BVH over `world` (the triangles of one time).
    pub fn from_triangles(world: WorldTriangles) -> Result<Self, TooDeep> {
        if world.triangles.is_empty() {
            return Ok(Self::default());
        }
        let bvh = build_bvh2_from_tris(
            &world.triangles,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let nodes: Vec<NodeGpu> = bvh
            .nodes
            .iter()
            .map(|n| NodeGpu {
                min: n.aabb.min.into(),
                count: n.prim_count,
                max: n.aabb.max.into(),
                first: n.first_index,
            })
            .collect();
        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| RtTriangle::from(&world.triangles[i as usize]))
            .collect();
        let info = bvh
            .primitive_indices
            .iter()
            .map(|&i| world.info[i as usize])
            .collect();
        let depth = tree_depth(&nodes);
        if depth > STACK_SIZE {
            return Err(TooDeep { depth });
        }
        Ok(Self {
            nodes,
            triangles,
            info,
            depth,
            cutouts: Vec::new(),
        })
    }

    /// The triangles of `world` in scene order, without a tree (`nodes` empty): what the
    /// hardware's acceleration structure is built over, where a hit's primitive index names
    /// the triangle.
    pub fn in_scene_order(world: WorldTriangles) -> Self {
        Self {
            nodes: Vec::new(),
            triangles: world.triangles.iter().map(RtTriangle::from).collect(),
            info: world.info,
            depth: 0,
            cutouts: Vec::new(),
        }
    }

    pub fn triangle_gpu(&self) -> Vec<TriangleGpu> {
        self.triangles
            .iter()
            .map(|t| TriangleGpu {
                v0: t.v0.into(),
                e1: t.e1.into(),
                e2: t.e2.into(),
                ng: t.ng.into(),
                ..Default::default()
            })
            .collect()
    }

    pub fn attributes_gpu(&self) -> Vec<AttributesGpu> {
        self.info
            .iter()
            .map(|i| AttributesGpu {
                n0: i.normals[0].into(),
                object: i.object,
                n1: i.normals[1].into(),
                triangle: i.triangle,
                n2: i.normals[2].into(),
                geometric_normal: i.geometric_normal.into(),
                uv01: [i.uvs[0].x, i.uvs[0].y, i.uvs[1].x, i.uvs[1].y],
                uv2: i.uvs[2].into(),
                ..Default::default()
            })
            .collect()
    }

    /// The nearest hit on `origin + t dir`, `0 <= t <= t_max`: the twin of `trace_closest`.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        let (id, t) = self.traverse(origin, dir, t_max, false)?;
        let ray = Ray::new(origin.into(), dir.into(), 0.0, t);
        let bary: Vec2 = self.triangles[id].compute_barycentric(&ray);
        Some(self.info[id].hit(origin, dir, t, bary))
    }

    /// Whether any surface lies on the segment: the twin of `trace_any`.
    pub fn any_hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.traverse(origin, dir, t_max, true).is_some()
    }

    /// The traversal both queries share: (triangle index, t) of the nearest hit, or of the
    /// first found when `any`.
    fn traverse(&self, origin: Vec3, dir: Vec3, t_max: f32, any: bool) -> Option<(usize, f32)> {
        let usable = origin.is_finite() && dir.is_finite() && dir != Vec3::ZERO && t_max >= 0.0;
        if self.nodes.is_empty() || !usable {
            return None;
        }
        let mut ray = Ray::new(origin.into(), dir.into(), 0.0, t_max);
        let inv = Vec3::new(
            safe_inverse(dir.x),
            safe_inverse(dir.y),
            safe_inverse(dir.z),
        );
        let mut stack = [0u32; STACK_SIZE];
        let mut top = 0;
        let mut node = 0u32;
        let mut found = None;
        loop {
            let n = &self.nodes[node as usize];
            if n.count > 0 {
                for i in n.first..n.first + n.count {
                    let t = intersect(&self.triangles[i as usize], &ray);
                    // `intersect` returns t <= tmax for a hit, infinity for none.
                    if t.is_finite()
                        && (found.is_none() || t < ray.tmax)
                        && !self.in_hole(i as usize, &ray)
                    {
                        ray.tmax = t;
                        found = Some((i as usize, t));
                        if any {
                            return found;
                        }
                    }
                }
            } else {
                let near_far = |c: u32| slab(&self.nodes[c as usize], origin, dir, inv, ray.tmax);
                let (a, b) = (n.first, n.first + 1);
                let (ta, tb) = (near_far(a), near_far(b));
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if tb < ta { (b, a) } else { (a, b) };
                        stack[top] = far;
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if top == 0 {
                return found;
            }
            top -= 1;
            node = stack[top];
        }
    }
}

impl FlatBvh {
    /// Whether `ray` meets triangle `id` in a hole of its object's alpha cut-out.
    fn in_hole(&self, id: usize, ray: &Ray) -> bool {
        !self.cutouts.is_empty()
            && in_hole(
                &self.cutouts,
                &self.info[id],
                self.triangles[id].compute_barycentric(ray),
            )
    }
}

/// The objects' alpha cut-outs ([`scene::Material::cutout`]) as the traversals read them
/// (`cutouts` in `shaders/triangles.wgsl`): word 0 the number of object records (0 when no
/// object is cut out), then per object its threshold (f32 bits; 0 for none), the first word of
/// its texture's alpha, the texture's width and height; then those alphas, one byte per texel
/// (row 0 first), four to a word, lowest byte first.
pub fn cutout_table(scene: &Scene) -> Vec<u32> {
    let cut: Vec<_> = scene
        .objects
        .iter()
        .map(|o| {
            let (t, c) = o.material.cutout()?;
            scene.textures.get(t).map(|texture| (t, texture, c))
        })
        .collect();
    if cut.iter().all(Option::is_none) {
        return vec![0];
    }
    let mut table = vec![cut.len() as u32];
    let mut alphas: Vec<u32> = Vec::new();
    // Each texture's alphas once, however many objects share it.
    let mut first_word: std::collections::BTreeMap<usize, u32> = Default::default();
    let alphas_start = 1 + 4 * cut.len();
    for object in &cut {
        let Some((index, texture, threshold)) = object else {
            table.extend([0; 4]);
            continue;
        };
        let first = *first_word.entry(*index).or_insert_with(|| {
            let first = (alphas_start + alphas.len()) as u32;
            let bytes: Vec<u8> = texture.rgba8.chunks_exact(4).map(|c| c[3]).collect();
            alphas.extend(bytes.chunks(4).map(|w| {
                w.iter()
                    .enumerate()
                    .fold(0u32, |word, (k, &a)| word | (a as u32) << (8 * k))
            }));
            first
        });
        table.extend([threshold.to_bits(), first, texture.width, texture.height]);
    }
    table.extend(alphas);
    table
}

/// Whether the hit at barycentrics `b` (weights `(1 - u - v, u, v)`) of a triangle with
/// attributes `info` lies where its object's cut-out texture (bilinear, wrapping, as
/// [`scene::Texture::sample_alpha`]) has alpha below the threshold: the twin of `in_hole` in
/// `shaders/triangles.wgsl`.
pub fn in_hole(table: &[u32], info: &TriangleInfo, b: Vec2) -> bool {
    let record = 1 + 4 * info.object as usize;
    if table[0] == 0 || record + 4 > table.len() {
        return false;
    }
    let threshold = f32::from_bits(table[record]);
    if threshold <= 0.0 {
        return false;
    }
    let [first, width, height] = [table[record + 1], table[record + 2], table[record + 3]];
    let (w, h) = (width as i64, height as i64);
    let alpha = |i: i64, j: i64| {
        let k = (j.rem_euclid(h) * w + i.rem_euclid(w)) as usize;
        ((table[first as usize + k / 4] >> (8 * (k % 4))) & 0xff) as f32 / 255.0
    };
    let uv = info.uvs[0] * (1.0 - b.x - b.y) + info.uvs[1] * b.x + info.uvs[2] * b.y;
    let x = uv.x * width as f32 - 0.5;
    let y = uv.y * height as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i, j) = (x0 as i64, y0 as i64);
    let lerp = |a: f32, b: f32, t: f32| a * (1.0 - t) + b * t; // glam's Vec3::lerp
    let top = lerp(alpha(i, j), alpha(i + 1, j), fx);
    let bottom = lerp(alpha(i, j + 1), alpha(i + 1, j + 1), fx);
    lerp(top, bottom, fy) < threshold
}

/// Entry distance of the ray into a node's box if it enters before `t_max`: the slab test of
/// `bvh.wgsl` (`slab`). An axis the ray runs parallel to (`|d| <= f32::EPSILON`, where
/// `safe_inverse` gives a large finite inverse) does not bound the ray when the origin lies
/// between the box's planes (on them included) and excludes it otherwise: the product
/// `(max - o) * inv` would be 0 for an origin exactly on a face and wrongly end the slab there.
fn slab(n: &NodeGpu, origin: Vec3, dir: Vec3, inv: Vec3, t_max: f32) -> Option<f32> {
    let (lo, hi) = (Vec3::from(n.min), Vec3::from(n.max));
    let t0 = (lo - origin) * inv;
    let t1 = (hi - origin) * inv;
    let parallel = dir.abs().cmple(Vec3::splat(f32::EPSILON));
    let between = origin.cmpge(lo) & origin.cmple(hi);
    if (parallel & !between).any() {
        return None;
    }
    let near = Vec3::select(parallel, Vec3::splat(f32::MIN), t0.min(t1));
    let far = Vec3::select(parallel, Vec3::splat(f32::MAX), t0.max(t1));
    let near = near.max_element().max(0.0);
    let far = far.min_element() * BOX_SLACK;
    (near <= far && near <= t_max).then_some(near)
}

/// Longest root-to-leaf path in nodes.
fn tree_depth(nodes: &[NodeGpu]) -> usize {
    let mut deepest = 0;
    let mut todo = vec![(0u32, 1usize)];
    while let Some((i, d)) = todo.pop() {
        let n = &nodes[i as usize];
        deepest = deepest.max(d);
        if n.count == 0 {
            todo.push((n.first, d + 1));
            todo.push((n.first + 1, d + 1));
        }
    }
    deepest
}

/// A ray for the WGSL conformance kernel and the property tests (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RayGpu {
    pub origin: [f32; 3],
    pub t_max: f32,
    pub dir: [f32; 3],
    pub _pad: f32,
}

/// What the conformance kernel returns per ray (32 bytes): `t` (negative for a miss), the
/// triangle's object and index, any-hit, the barycentrics.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TraceResultGpu {
    pub t: f32,
    pub object: i32,
    pub triangle: i32,
    pub any: u32,
    pub bary: [f32; 2],
    pub _pad: [f32; 2],
}
