//! Nearby geometry as rectangle impostors (Hu and Qin 2006, section 2.2): the Rust twin of
//! `shaders/nearby.wgsl`.
//!
//! Each nearby object stands in as a [`Rect`]: a rectangle through the object's centre,
//! perpendicular to the projection direction, with a texture of the object rendered by a
//! parallel projection along that direction (colour + normalized depth). For a planar
//! rectangular object (a wall, a floor) the rectangle *is* the object: exact. For any other
//! object it is the paper's square of side `2 d` (d: the object's largest vertex distance
//! from its centre) perpendicular to the refractor-to-object direction.
//!
//! A ray (the reflected `R` or the exit ray `T2`) meets the rectangles ([`rect_hit`]); the
//! uncorrected lookup reads the texture where it meets the nearest one (figure 13). The
//! corrected lookup (figure 16) starts from a seed on the ray chosen by the paper's rules
//! ([`select_seed`]) and moves the point along the ray by the difference between the stored
//! depth under it and its own depth, divided by the cosine between ray and projection
//! ([`correct`]), until that difference is within a tolerance.

use glam::{Vec2, Vec3};

/// A rectangle impostor's placement, projection and ray hit (`nearby.rs`'s `Rect`): the module
/// `image_space_refraction::rect`, which the nearby lookups and caustic mapping import.
pub static RECT: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/rect.wgsl"),
    "image-space-refraction/src/shaders/rect.wgsl",
    &[],
);
/// The nearby-geometry lookups (`nearby.rs`'s twin) and their resources: the module
/// `image_space_refraction::nearby`, placed by the definitions [`NEARBY_DEFS`].
pub static NEARBY: gpu::wgsl::Module = gpu::wgsl::Module::new(
    include_str!("shaders/nearby.wgsl"),
    "image-space-refraction/src/shaders/nearby.wgsl",
    &[&RECT],
);
/// Where the technique binds [`NEARBY`]'s resources: `@group(3)` from binding 0 (the
/// rectangle impostors' group, `rectangles::group_layout`).
pub const NEARBY_DEFS: [(&str, gpu::wgsl::Def); 2] = [
    ("NEARBY_GROUP", gpu::wgsl::Def::UInt(3)),
    ("NEARBY_FIRST_BINDING", gpu::wgsl::Def::UInt(0)),
];

/// One rectangle impostor (the WGSL `Rect`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Centre of the rectangle (world).
    pub centre: Vec3,
    /// Unit axis of texture u (right), and half the rectangle's extent along it.
    pub axis_u: Vec3,
    /// Half extent along `axis_u`.
    pub half_u: f32,
    /// Unit axis of texture v (up: texel row 0 is at `+half_v`).
    pub axis_v: Vec3,
    /// Half extent along `axis_v`.
    pub half_v: f32,
    /// Unit projection direction (into the object, away from the refractor).
    pub direction: Vec3,
    /// Where the projection's depth is measured from: depth = dot(p - origin, direction).
    pub origin: Vec3,
    /// Depth of the texture's near plane (normalized depth 0).
    pub near: f32,
    /// Depth of the texture's far plane (normalized depth 1).
    pub far: f32,
}

impl Rect {
    /// The paper's square for an object of centre `centre` and largest vertex distance
    /// `radius`, seen from the refractor's centre `from` (figure 13's initial pass).
    pub fn square(from: Vec3, centre: Vec3, radius: f32) -> Self {
        // A point-sized object still gets a rectangle with a proper projection.
        let radius = radius.max(1e-4);
        let direction = (centre - from).normalize_or(Vec3::NEG_Z);
        let hint = if direction.y.abs() < 0.99 {
            Vec3::Y
        } else {
            Vec3::X
        };
        let axis_u = direction.cross(hint).normalize();
        let axis_v = axis_u.cross(direction);
        let distance = (centre - from).dot(direction);
        Self {
            centre,
            axis_u,
            half_u: radius,
            axis_v,
            half_v: radius,
            direction,
            origin: from,
            near: (distance - radius).max(1e-3),
            far: distance + radius,
        }
    }

    /// A planar rectangle (corner `corner`, edges `u` and `v`) seen from the side of `from`:
    /// its texture is the rectangle itself.
    pub fn planar(corner: Vec3, u: Vec3, v: Vec3, from: Vec3) -> Self {
        let centre = corner + 0.5 * (u + v);
        let mut normal = u.cross(v).normalize();
        if normal.dot(from - centre) < 0.0 {
            normal = -normal;
        }
        let direction = -normal;
        // Right-handed frame looking along `direction`: u x v must equal -direction.
        let (axis_u, axis_v, half_u, half_v) = if u.cross(v).dot(direction) < 0.0 {
            (
                u.normalize(),
                v.normalize(),
                0.5 * u.length(),
                0.5 * v.length(),
            )
        } else {
            (
                v.normalize(),
                u.normalize(),
                0.5 * v.length(),
                0.5 * u.length(),
            )
        };
        let depth = 0.5 * (half_u + half_v).max(1e-2);
        Self {
            centre,
            axis_u,
            half_u,
            axis_v,
            half_v,
            direction,
            origin: centre - direction * 2.0 * depth,
            near: depth,
            far: 3.0 * depth,
        }
    }

    /// Texture coordinates ([0, 1]^2 on the rectangle, v = 0 at the top) of the parallel
    /// projection of `p`, and its depth along the projection.
    pub fn project(&self, p: Vec3) -> (Vec2, f32) {
        let local = p - self.centre;
        let uv = Vec2::new(
            0.5 + local.dot(self.axis_u) / (2.0 * self.half_u),
            0.5 - local.dot(self.axis_v) / (2.0 * self.half_v),
        );
        (uv, (p - self.origin).dot(self.direction))
    }

    /// Depth of a normalized depth value of the texture.
    pub fn depth_of(&self, normalized: f32) -> f32 {
        self.near + normalized * (self.far - self.near)
    }
}

/// Where a ray meets a rectangle: the distance along the ray and the texture coordinates.
pub fn rect_hit(rect: &Rect, origin: Vec3, dir: Vec3) -> Option<(f32, Vec2)> {
    let denom = dir.dot(rect.direction);
    if denom.abs() < 1e-8 {
        return None;
    }
    let t = (rect.centre - origin).dot(rect.direction) / denom;
    if !(t > 0.0 && t < 3.0e38) {
        return None;
    }
    let (uv, _) = rect.project(origin + dir * t);
    (uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all()).then_some((t, uv))
}

/// The stored (normalized) depth of an impostor texture under texture coordinates `uv`,
/// `None` where the object does not cover it: what the shader's `textureLoad` reads.
pub trait ImpostorDepth {
    /// Normalized depth at `uv` of rectangle `rect`.
    fn depth(&self, rect: usize, uv: Vec2) -> Option<f32>;
}

/// Figure 17's rules for the first point of the correction: of `seeds` points evenly spaced
/// on the ray from its origin to its rectangle hit `t_rect` (both ends included), the first
/// one lying behind the stored surface (deeper than the depth under it: the ray has crossed
/// the object), else the one closest to the stored surface; `t_rect` when no seed projects
/// onto the object.
pub fn select_seed(
    rects: &[Rect],
    depths: &impl ImpostorDepth,
    index: usize,
    origin: Vec3,
    dir: Vec3,
    t_rect: f32,
    seeds: u32,
) -> f32 {
    let rect = &rects[index];
    let mut closest = (f32::INFINITY, t_rect);
    let n = seeds.max(1);
    for j in 0..=n {
        // j / n first: exactly 1 for the last seed, which is then the rectangle hit itself.
        let t = t_rect * (j as f32 / n as f32);
        let (uv, depth) = rect.project(origin + dir * t);
        let Some(stored) = depths.depth(index, uv) else {
            continue;
        };
        let gap = depth - rect.depth_of(stored);
        if gap >= 0.0 {
            return t;
        }
        if -gap < closest.0 {
            closest = (-gap, t);
        }
    }
    closest.1
}

/// Figure 16: from `t`, move along the ray by `(stored depth - own depth) / cos` until the
/// difference is within `tolerance` or `iterations` corrections are made. Returns the final
/// distance and texture coordinates, `None` when the point ends off the object (the ray
/// misses it) or the ray runs perpendicular to the projection.
pub fn correct(
    rect: &Rect,
    depths: &impl ImpostorDepth,
    index: usize,
    origin: Vec3,
    dir: Vec3,
    mut t: f32,
    iterations: u32,
    tolerance: f32,
) -> Option<(f32, Vec2)> {
    let cos = dir.dot(rect.direction);
    if cos.abs() < 1e-3 {
        return None;
    }
    for _ in 0..iterations {
        let (uv, depth) = rect.project(origin + dir * t);
        let stored = rect.depth_of(depths.depth(index, uv)?);
        let gap = stored - depth;
        if gap.abs() <= tolerance {
            return Some((t, uv));
        }
        t = (t + gap / cos).max(0.0);
    }
    // Out of corrections: the last point, if it is still on the object.
    let (uv, _) = rect.project(origin + dir * t);
    depths.depth(index, uv).map(|_| (t, uv))
}

/// How the nearby lookup treats a rectangle hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// Figure 13: the texel where the ray meets the rectangle.
    Uncorrected,
    /// Figure 16 from figure 17's seed.
    Corrected {
        /// Seeds on the ray (figure 17).
        seeds: u32,
        /// Most corrections.
        iterations: u32,
    },
}

/// The nearest nearby surface along the ray: (rectangle index, distance, texture coordinates),
/// `None` when no rectangle's object is met (the environment map then answers). A rectangle
/// whose texel under the (corrected) point is empty is passed over.
pub fn nearby_hit(
    rects: &[Rect],
    depths: &impl ImpostorDepth,
    origin: Vec3,
    dir: Vec3,
    lookup: Lookup,
    tolerance: f32,
) -> Option<(usize, f32, Vec2)> {
    let mut best: Option<(usize, f32, Vec2)> = None;
    for (i, rect) in rects.iter().enumerate() {
        let Some((t_rect, uv)) = rect_hit(rect, origin, dir) else {
            continue;
        };
        let found = match lookup {
            Lookup::Uncorrected => depths.depth(i, uv).map(|_| (t_rect, uv)),
            Lookup::Corrected { seeds, iterations } => {
                let t0 = select_seed(rects, depths, i, origin, dir, t_rect, seeds);
                correct(rect, depths, i, origin, dir, t0, iterations, tolerance)
            }
        };
        if let Some((t, uv)) = found
            && best.is_none_or(|b| t < b.1)
        {
            best = Some((i, t, uv));
        }
    }
    best
}

/// Impostor depth textures in memory, as the shader reads them: one square layer per
/// rectangle, normalized depth per texel (rows top to bottom), 1 where the object does not
/// cover it; nearest texel.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthLayers {
    /// Side of each layer.
    pub resolution: u32,
    /// One layer per rectangle.
    pub layers: Vec<Vec<f32>>,
}

impl ImpostorDepth for DepthLayers {
    fn depth(&self, rect: usize, uv: Vec2) -> Option<f32> {
        if !(uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all()) {
            return None;
        }
        let res = self.resolution as f32;
        let x = (uv.x * res).floor().min(res - 1.0) as usize;
        let y = (uv.y * res).floor().min(res - 1.0) as usize;
        let d = self.layers[rect][y * self.resolution as usize + x];
        (d < 1.0).then_some(d)
    }
}
