//! The scene model shared by the reference renderer, the GPU upload and every technique.
//!
//! Units are metres, right-handed, +Y up. Meshes are stored in object space; an object's
//! world transform is its `transform` followed by its animated translation at time t. An
//! object may also deform: its [`Morph`] blends the mesh's vertices toward a second set over
//! time, and [`Object::positions_at`]/[`Object::normals_at`] give the object-space vertices
//! at a time (what the BVH, the bounds and the GPU upload place in the world).

use glam::{Mat3, Mat4, Vec2, Vec3};
use std::borrow::Cow;

mod camera;
mod light;
mod world;
pub use camera::*;
pub use light::*;
pub use world::*;

/// A triangle mesh in object space. `normals` and `uvs` have one entry per position.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Replaces every zero-length or non-finite normal by the geometric normal at its vertex:
    /// the area-weighted sum of the face normals of the triangles that use it (+Y for a vertex
    /// no triangle with an area uses). Returns how many normals it replaced. An all-zero
    /// `NORMAL` accessor in a glTF file is the case this is for: the renderers normalize the
    /// interpolated normal, and a zero one would be a NaN pixel.
    pub fn repair_normals(&mut self) -> usize {
        let bad: Vec<bool> = self
            .normals
            .iter()
            .map(|n| !(n.length_squared().is_finite() && n.length_squared() >= 1e-12))
            .collect();
        if !bad.contains(&true) {
            return 0;
        }
        let mut geometric = vec![Vec3::ZERO; self.positions.len()];
        for tri in self.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
            let (Some(pa), Some(pb), Some(pc)) = (
                self.positions.get(a),
                self.positions.get(b),
                self.positions.get(c),
            ) else {
                continue;
            };
            // |cross| is twice the area: the sum weights each face by its area.
            let face = (*pb - *pa).cross(*pc - *pa);
            if face.is_finite() {
                for v in [a, b, c] {
                    geometric[v] += face;
                }
            }
        }
        let mut replaced = 0;
        for (i, normal) in self.normals.iter_mut().enumerate() {
            if bad[i] {
                *normal = geometric[i].normalize_or(Vec3::Y);
                replaced += 1;
            }
        }
        replaced
    }

    /// Axis-aligned bounds in object space (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }
}

/// Surface materials (DESIGN.md): diffuse with optional texture, metal/mirror with n and k
/// per channel, glass with an index of refraction (which may be below 1).
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian; `texture` indexes `Scene::textures` and multiplies `albedo`.
    Diffuse {
        albedo: Vec3,
        texture: Option<usize>,
        /// An alpha cut-out (glTF's `MASK`): the surface is absent wherever the texture's
        /// alpha, filtered as its colour is ([`Texture::sample_alpha`]), is below this value.
        /// Only with a texture, in (0, 1]: a constant alpha is decided at import (the
        /// primitive is kept or left out). Every renderer skips the hole: the reference's
        /// and the tracer's rays pass through it, rasterized passes discard it.
        cutout: Option<f32>,
    },
    /// Conductor with the seeds' Fresnel approximation; n = 0, k = 1 is a perfect mirror.
    Metal { n: Vec3, k: Vec3 },
    /// Dielectric, ior relative to the surrounding air.
    Glass { ior: f32 },
}

impl Material {
    /// The alpha cut-out of a textured diffuse material: (texture index, the alpha below which
    /// the surface is absent). See [`Material::Diffuse`].
    pub fn cutout(&self) -> Option<(usize, f32)> {
        match *self {
            Material::Diffuse {
                texture: Some(t),
                cutout: Some(c),
                ..
            } => Some((t, c)),
            _ => None,
        }
    }
    pub fn diffuse(r: f32, g: f32, b: f32) -> Self {
        Material::Diffuse {
            albedo: Vec3::new(r, g, b),
            texture: None,
            cutout: None,
        }
    }
    /// F = 1 at every angle with the seeds' approximation: ((0-1)^2 + 1) / ((0+1)^2 + 1).
    pub fn perfect_mirror() -> Self {
        Material::Metal {
            n: Vec3::ZERO,
            k: Vec3::ONE,
        }
    }
    /// Gold (n, k at roughly 650/550/450 nm).
    pub fn gold() -> Self {
        Material::Metal {
            n: Vec3::new(0.143, 0.374, 1.442),
            k: Vec3::new(3.983, 2.385, 1.603),
        }
    }
    /// Copper.
    pub fn copper() -> Self {
        Material::Metal {
            n: Vec3::new(0.200, 0.924, 1.102),
            k: Vec3::new(3.912, 2.452, 2.142),
        }
    }
    pub fn glass(ior: f32) -> Self {
        Material::Glass { ior }
    }
    pub fn is_specular(&self) -> bool {
        !matches!(self, Material::Diffuse { .. })
    }
    /// The word a message names the material's kind with.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Material::Diffuse { .. } => "diffuse",
            Material::Metal { .. } => "metal",
            Material::Glass { .. } => "glass",
        }
    }

    /// Glass indices of refraction the renderers accept: below 1 is an interface seen from
    /// the denser side (`glass-0.75`), 2.42 is diamond.
    pub const IOR_RANGE: std::ops::RangeInclusive<f32> = 0.25..=4.0;
    /// Metal refractive indices `n` the renderers accept, per channel (real metals lie in
    /// 0.05-3 in the visible; 0 with k = 1 is the perfect mirror).
    pub const METAL_N_RANGE: std::ops::RangeInclusive<f32> = 0.0..=10.0;
    /// Metal extinction coefficients `k` the renderers accept, per channel (real metals
    /// lie in 0-9 in the visible).
    pub const METAL_K_RANGE: std::ops::RangeInclusive<f32> = 0.0..=10.0;
    /// Diffuse albedos the renderers accept, per channel: above 1 a surface would reflect
    /// more light than it receives.
    pub const ALBEDO_RANGE: std::ops::RangeInclusive<f32> = 0.0..=1.0;

    /// `None` if every parameter is finite and physical (the ranges above), else what is
    /// wrong, with the range, as the end of a sentence.
    pub fn check(&self) -> Option<String> {
        let outside = |v: Vec3, r: &std::ops::RangeInclusive<f32>| {
            !v.to_array().iter().all(|c| r.contains(c))
        };
        let range = |r: &std::ops::RangeInclusive<f32>| format!("[{}, {}]", r.start(), r.end());
        match *self {
            Material::Diffuse { albedo, .. } if outside(albedo, &Self::ALBEDO_RANGE) => {
                Some(format!(
                    "diffuse albedo {albedo} outside {}",
                    range(&Self::ALBEDO_RANGE)
                ))
            }
            Material::Metal { n, .. } if outside(n, &Self::METAL_N_RANGE) => Some(format!(
                "metal n {n} outside {}",
                range(&Self::METAL_N_RANGE)
            )),
            Material::Metal { k, .. } if outside(k, &Self::METAL_K_RANGE) => Some(format!(
                "metal k {k} outside {}",
                range(&Self::METAL_K_RANGE)
            )),
            Material::Glass { ior } if !Self::IOR_RANGE.contains(&ior) => Some(format!(
                "glass ior {ior} outside {}",
                range(&Self::IOR_RANGE)
            )),
            _ => None,
        }
    }
}

/// An sRGB-encoded RGBA8 texture, sampled with wrap-around addressing.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row 0 is v = 0 (the top of the image), as in glTF.
    pub rgba8: Vec<u8>,
}

impl Texture {
    /// Bilinear lookup returning linear RGB (the GPU samples an `Rgba8UnormSrgb` view the
    /// same way: decode each texel, then filter).
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        self.bilinear(uv, |t| {
            Vec3::new(
                srgb_to_linear(t[0]),
                srgb_to_linear(t[1]),
                srgb_to_linear(t[2]),
            )
        })
    }

    /// Bilinear lookup of the alpha channel, which sRGB formats store linearly (byte / 255).
    pub fn sample_alpha(&self, uv: Vec2) -> f32 {
        self.bilinear(uv, |t| Vec3::splat(t[3] as f32 / 255.0)).x
    }

    /// Filters `decode(texel)` between the four texel centres around `uv`, wrapping around.
    fn bilinear(&self, uv: Vec2, decode: impl Fn(&[u8]) -> Vec3) -> Vec3 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |i: i64, j: i64| {
            let i = i.rem_euclid(self.width as i64) as usize;
            let j = j.rem_euclid(self.height as i64) as usize;
            let o = 4 * (j * self.width as usize + i);
            decode(&self.rgba8[o..o + 4])
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j).lerp(texel(i + 1, j), fx);
        let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// sRGB 8-bit to linear, exactly as the GPU's `*UnormSrgb` formats decode.
pub fn srgb_to_linear(v: u8) -> f32 {
    let c = v as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The special roles a technique may treat differently from the shared diffuse raster pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Roles(u32);

impl Roles {
    pub const NONE: Roles = Roles(0);
    pub const REFLECTOR: Roles = Roles(1);
    pub const REFRACTOR: Roles = Roles(2);
    pub const CAUSTIC_CASTER: Roles = Roles(4);
    pub const BUILDING: Roles = Roles(8);
    pub const VOLUME: Roles = Roles(16);
    pub const HEIGHT_FIELD: Roles = Roles(32);
    pub const ALL: [(Roles, &'static str); 6] = [
        (Roles::REFLECTOR, "reflector"),
        (Roles::REFRACTOR, "refractor"),
        (Roles::CAUSTIC_CASTER, "caustic-caster"),
        (Roles::BUILDING, "building"),
        (Roles::VOLUME, "volume"),
        (Roles::HEIGHT_FIELD, "height-field"),
    ];

    pub fn contains(self, other: Roles) -> bool {
        self.0 & other.0 == other.0 && other.0 != 0
    }
    pub fn intersects(self, other: Roles) -> bool {
        self.0 & other.0 != 0
    }
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    pub fn names(self) -> Vec<&'static str> {
        Roles::ALL
            .iter()
            .filter(|(r, _)| self.contains(*r))
            .map(|(_, n)| *n)
            .collect()
    }
    pub fn from_name(name: &str) -> Option<Roles> {
        Roles::ALL.iter().find(|(_, n)| *n == name).map(|(r, _)| *r)
    }
    pub fn bits(self) -> u32 {
        self.0
    }
}

impl std::ops::BitOr for Roles {
    type Output = Roles;
    fn bitor(self, rhs: Roles) -> Roles {
        Roles(self.0 | rhs.0)
    }
}

/// How an object moves: piecewise-linear translation keyframes (time in seconds, offset
/// added after the object's transform). Empty means static.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub keys: Vec<(f32, Vec3)>,
}

impl Motion {
    pub fn offset(&self, time: f32) -> Vec3 {
        sample_keys(&self.keys, time, |a, b, s| a.lerp(*b, s)).unwrap_or(Vec3::ZERO)
    }
    pub fn is_static(&self) -> bool {
        self.keys.iter().all(|(_, v)| *v == Vec3::ZERO)
    }
}

/// How an object deforms: a morph target, an object-space copy of the mesh's vertices
/// displaced into another shape (one position and one normal per vertex of the object's mesh,
/// same order; the triangles, uvs and everything else stay the mesh's), and piecewise-linear
/// weight keyframes (time in seconds, weight in [0, 1]), sampled like [`Motion`]'s. At weight
/// `w` a vertex lies at `(1 - w) base + w target` and its normal is the renormalised
/// `(1 - w) base + w target` normal. No keys is weight 0 (the base mesh) at every time.
///
/// The object's world transform and [`Motion`] apply after the blend. Precomputation made from
/// the base mesh ([`crate::kinds::Kinds`], light-map charts) knows nothing of the deformation:
/// a deforming object ([`Object::is_deforming`]) simply invalidates it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Morph {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub keys: Vec<(f32, f32)>,
}

impl Morph {
    /// The weight of the target at `time` (0 without keys).
    pub fn weight(&self, time: f32) -> f32 {
        sample_keys(&self.keys, time, |a, b, s| a + (b - a) * s).unwrap_or(0.0)
    }
    /// Whether the weight changes over time (keys with different weights).
    pub fn is_animated(&self) -> bool {
        self.keys.windows(2).any(|k| k[0].1 != k[1].1)
    }
}

/// Interior layout of a building hull (for interior mapping): room size per axis, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Building {
    pub room_size: Vec3,
}

/// One renderable object.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub name: String,
    pub mesh: Mesh,
    pub material: Material,
    pub transform: Mat4,
    pub roles: Roles,
    pub motion: Motion,
    pub building: Option<Building>,
    /// A morph target that deforms the mesh over time, or none (a rigid object).
    pub morph: Option<Morph>,
    /// Radiance (linear RGB, W m^-2 sr^-1) a diffuse surface emits from both sides on top of
    /// what it reflects: glTF's emission. It is seen directly and in every reflection and
    /// refraction, but it is not a light: it lights no other surface and casts no caustic, as
    /// engines treat emissive materials without baked lighting. Zero for metal and glass
    /// ([`Scene::validate`]).
    pub emission: Vec3,
}

impl Object {
    pub fn new(name: &str, mesh: Mesh, material: Material, transform: Mat4) -> Self {
        Self {
            name: name.to_string(),
            mesh,
            material,
            transform,
            roles: Roles::NONE,
            motion: Motion::default(),
            building: None,
            morph: None,
            emission: Vec3::ZERO,
        }
    }
    /// The object emitting `radiance` ([`Object::emission`]).
    pub fn with_emission(mut self, radiance: Vec3) -> Self {
        self.emission = radiance;
        self
    }
    pub fn with_roles(mut self, roles: Roles) -> Self {
        self.roles = roles;
        self
    }
    /// The object with a [`Morph`] target (same vertex count as its mesh: see
    /// [`Scene::validate`]).
    pub fn with_morph(mut self, morph: Morph) -> Self {
        self.morph = Some(morph);
        self
    }
    /// Whether the object's shape changes over time: it has a [`Morph`] whose weight varies.
    /// Such an object moves for everything that caches its geometry (the GPU scene rewrites
    /// its vertices and re-renders the shadow maps at every new time).
    pub fn is_deforming(&self) -> bool {
        self.morph.as_ref().is_some_and(Morph::is_animated)
    }
    /// The morph weight at `time` (0 without a usable morph: none, or one whose vertex
    /// count differs from the mesh's, which [`Scene::validate`] refuses).
    fn morph_at(&self, time: f32) -> Option<(&Morph, f32)> {
        let m = self.morph.as_ref()?;
        let n = self.mesh.positions.len();
        if m.positions.len() != n || m.normals.len() != self.mesh.normals.len() {
            return None;
        }
        let w = m.weight(time);
        (w != 0.0).then_some((m, w))
    }
    /// Object-space vertex positions at `time`: the mesh's, blended toward the [`Morph`]
    /// target by its weight (`(1 - w) base + w target`). Borrowed from the mesh when there is
    /// no morph or its weight is 0.
    pub fn positions_at(&self, time: f32) -> Cow<'_, [Vec3]> {
        match self.morph_at(time) {
            None => Cow::Borrowed(&self.mesh.positions),
            Some((m, w)) => Cow::Owned(
                self.mesh
                    .positions
                    .iter()
                    .zip(&m.positions)
                    .map(|(a, b)| a.lerp(*b, w))
                    .collect(),
            ),
        }
    }
    /// Object-space vertex normals at `time`: the mesh's, or, with a [`Morph`] of non-zero
    /// weight, the blend `(1 - w) base + w target` renormalised (the base normal, normalised,
    /// where the blend vanishes). Borrowed from the mesh when there is no morph or its weight
    /// is 0.
    pub fn normals_at(&self, time: f32) -> Cow<'_, [Vec3]> {
        match self.morph_at(time) {
            None => Cow::Borrowed(&self.mesh.normals),
            Some((m, w)) => Cow::Owned(
                self.mesh
                    .normals
                    .iter()
                    .zip(&m.normals)
                    .map(|(a, b)| a.lerp(*b, w).normalize_or(a.normalize_or(Vec3::Y)))
                    .collect(),
            ),
        }
    }
    /// Object-space bounds (min, max) of the vertices at `time` ([`Self::positions_at`],
    /// without allocating); empty bounds are (+inf, -inf).
    pub fn bounds_at(&self, time: f32) -> (Vec3, Vec3) {
        let fold = |(lo, hi): (Vec3, Vec3), p: Vec3| (lo.min(p), hi.max(p));
        let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        match self.morph_at(time) {
            None => self.mesh.positions.iter().copied().fold(empty, fold),
            Some((m, w)) => self
                .mesh
                .positions
                .iter()
                .zip(&m.positions)
                .map(|(a, b)| a.lerp(*b, w))
                .fold(empty, fold),
        }
    }
    /// Object-to-world matrix at `time`.
    pub fn world_at(&self, time: f32) -> Mat4 {
        Mat4::from_translation(self.motion.offset(time)) * self.transform
    }
    /// Matrix that transforms object-space normals to world space at `time`.
    pub fn normal_matrix_at(&self, time: f32) -> Mat3 {
        Mat3::from_mat4(self.world_at(time)).inverse().transpose()
    }
    /// World-space centre of the object's bounding box at `time` (the reference point of
    /// environment maps taken "from the object's centre"): the centre of the object-space box
    /// of the vertices at that time ([`Self::bounds_at`], which follows a [`Morph`]), placed by
    /// the world transform at that time. One pass over the vertices, no allocation.
    pub fn center_at(&self, time: f32) -> Vec3 {
        let (lo, hi) = self.bounds_at(time);
        self.world_at(time).transform_point3((lo + hi) * 0.5)
    }
    /// The largest absolute world coordinate any vertex reaches over the object's motion and
    /// deformation (`None` for an empty mesh): what [`Scene::validate`] holds against
    /// [`MAX_WORLD_COORDINATE`]. A morphed vertex lies between its base and target positions,
    /// so both are counted.
    pub fn world_extent(&self) -> Option<f32> {
        let travel = self
            .motion
            .keys
            .iter()
            .map(|(_, v)| v.abs().max_element())
            .fold(0.0, f32::max);
        let target = self.morph.iter().flat_map(|m| &m.positions);
        self.mesh
            .positions
            .iter()
            .chain(target)
            .map(|p| self.transform.transform_point3(*p).abs().max_element())
            .reduce(f32::max)
            .map(|e| e + travel)
    }

    /// Radius of a world-space sphere around `center_at` that bounds the object at `time`
    /// (its vertices at that time, [`Self::positions_at`]).
    pub fn bounding_radius_at(&self, time: f32) -> f32 {
        let world = self.world_at(time);
        let c = self.center_at(time);
        self.positions_at(time)
            .iter()
            .map(|p| world.transform_point3(*p).distance(c))
            .fold(0.0, f32::max)
    }
}

pub(super) fn sample_keys<T: Copy>(
    keys: &[(f32, T)],
    time: f32,
    lerp: impl Fn(&T, &T, f32) -> T,
) -> Option<T> {
    let first = keys.first()?;
    if time <= first.0 {
        return Some(first.1);
    }
    for pair in keys.windows(2) {
        let ((t0, a), (t1, b)) = (pair[0], pair[1]);
        if time <= t1 {
            let s = if t1 > t0 {
                (time - t0) / (t1 - t0)
            } else {
                1.0
            };
            return Some(lerp(&a, &b, s));
        }
    }
    keys.last().map(|k| k.1)
}

/// How a volume's extinction varies inside its bounding sphere: a smooth radial falloff
/// modulated by a deterministic 3D noise (the thesis's smoke with a diffuse texture, figure
/// 6.22). [`crate::density`] evaluates it; the reference (`truth::media`) integrates it, and
/// every technique is measured against that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityProfile {
    /// Exponent `k` of the radial falloff `(1 - (r/R)^2)^k`: 0 is a uniform ball, 1 falls to
    /// zero at the sphere with a kink, 2 and more fall smoothly (zero slope at the sphere).
    pub falloff: f32,
    /// Relative amplitude `a` of the noise, in [0, 1]: the falloff is multiplied by
    /// `1 + a n(q)` with `n` in [-1, 1], so 0 is no texture and the density stays >= 0.
    pub noise: f32,
    /// Noise lattice cells per radius: the texture's features are about `R / frequency`.
    pub noise_frequency: f32,
}

impl DensityProfile {
    /// A uniform ball: the medium the thesis's techniques assume.
    pub const UNIFORM: DensityProfile = DensityProfile {
        falloff: 0.0,
        noise: 0.0,
        noise_frequency: 1.0,
    };
}

impl Default for DensityProfile {
    fn default() -> Self {
        Self::UNIFORM
    }
}

/// A soft volume: a participating medium (emission-absorption) bounded by a sphere.
///
/// Its extinction coefficient at a point `r` metres from the centre is
/// `density * (1 - (r/R)^2)^k * (1 + a n(q))` per metre ([`DensityProfile`], `q` the point in
/// the volume's own frame, so the texture moves with it) and zero outside the sphere. The
/// medium emits `color` per unit optical depth: along a path of transmittance `T` it adds
/// `color (1 - T)` over what lies behind it, so an infinitely thick medium shows `color`.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    pub name: String,
    pub center: Vec3,
    pub radius: f32,
    /// Linear RGB radiance of the medium where it is opaque (what it adds, scaled by 1 - T).
    pub color: Vec3,
    /// Extinction coefficient `sigma` at the centre, per metre (before the noise): a uniform
    /// ball of radius R seen through its centre has transmittance `exp(-2 R density)`.
    pub density: f32,
    /// How the extinction varies inside the sphere.
    pub profile: DensityProfile,
    /// True for members of a particle cloud, false for a single large volume.
    pub particle: bool,
    pub motion: Motion,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit sphere whose morph target is the sphere of radius 2 (same normals), weight
    /// 0 -> 1 over one second.
    fn growing_sphere() -> Object {
        let mesh = crate::mesh::uv_sphere(1.0, 8, 16);
        let morph = Morph {
            positions: mesh.positions.iter().map(|p| *p * 2.0).collect(),
            normals: mesh.normals.clone(),
            keys: vec![(0.0, 0.0), (1.0, 1.0)],
        };
        Object::new(
            "growing",
            mesh,
            Material::diffuse(0.5, 0.5, 0.5),
            Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
        )
        .with_morph(morph)
    }

    #[test]
    fn positions_at_blends_and_normals_at_renormalises() {
        let mut o = growing_sphere();
        assert!(o.is_deforming());
        // Weight 0: the mesh itself, borrowed.
        assert!(matches!(o.positions_at(0.0), Cow::Borrowed(_)));
        assert!(matches!(o.normals_at(-1.0), Cow::Borrowed(_)));
        // Weight 0.5 at t = 0.5: radius 1.5.
        let p = o.positions_at(0.5);
        for (q, base) in p.iter().zip(&o.mesh.positions) {
            assert!((*q - *base * 1.5).length() < 1e-6, "{q} vs {base}");
        }
        assert!((o.bounds_at(0.5).1 - Vec3::splat(1.5)).abs().max_element() < 1e-5);
        assert!((o.bounding_radius_at(1.0) - 2.0).abs() < 1e-5);
        assert!((o.center_at(1.0) - Vec3::Y).length() < 1e-5);
        // Normals: blend a target that turns every normal by 90 degrees; the halfway normal
        // is the unit bisector, not the half-length sum.
        let turned: Vec<Vec3> = o
            .mesh
            .normals
            .iter()
            .map(|n| n.any_orthonormal_vector())
            .collect();
        o.morph.as_mut().unwrap().normals = turned.clone();
        let n = o.normals_at(0.5);
        for ((m, a), b) in n.iter().zip(&o.mesh.normals).zip(&turned) {
            assert!((m.length() - 1.0).abs() < 1e-5);
            assert!((*m - (*a + *b).normalize()).length() < 1e-5);
        }
        // Keys past the end hold the last weight; a constant weight does not deform.
        assert_eq!(o.morph.as_ref().unwrap().weight(7.0), 1.0);
        o.morph.as_mut().unwrap().keys = vec![(0.0, 0.3), (2.0, 0.3)];
        assert!(!o.is_deforming());
        assert!(matches!(o.positions_at(1.0), Cow::Owned(_)));
        // Without a morph nothing changes.
        o.morph = None;
        assert!(matches!(o.positions_at(1.0), Cow::Borrowed(_)));
        assert!(!o.is_deforming());
    }

    fn scene_with(object: Object) -> Scene {
        Scene {
            name: "morph".into(),
            objects: vec![object],
            textures: vec![],
            lights: vec![],
            camera: Camera {
                eye: Vec3::new(0.0, 1.0, 5.0),
                target: Vec3::Y,
                up: Vec3::Y,
                fov_y_deg: 45.0,
                orthographic: None,
            },
            camera_path: CameraPath::default(),
            volumes: vec![],
            medium: None,
            background: Vec3::ZERO,
        }
    }

    fn invalid(object: Object) -> String {
        match scene_with(object).validate() {
            Err(crate::SceneError::Invalid(why)) => why,
            other => panic!("expected an invalid scene, got {other:?}"),
        }
    }

    #[test]
    fn validate_checks_morph_targets() {
        scene_with(growing_sphere()).validate().unwrap();
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().positions.pop();
        let why = invalid(o);
        assert!(
            why.contains("morph target of") && why.contains("vertices"),
            "{why}"
        );
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().normals.push(Vec3::Y);
        assert!(invalid(o).contains("morph target of"));
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().keys[1].1 = 1.5;
        let why = invalid(o);
        assert!(why.contains("morph weight 1.5"), "{why}");
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().keys[0].1 = f32::NAN;
        assert!(invalid(o).contains("morph weight"));
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().keys = vec![(1.0, 0.0), (0.5, 1.0)];
        assert!(invalid(o).contains("increasing"));
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().keys[0].0 = f32::INFINITY;
        assert!(invalid(o).contains("increasing"));
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().positions[3].x = f32::NAN;
        assert!(invalid(o).contains("non-finite morph target position"));
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().normals[2] = Vec3::ZERO;
        assert!(invalid(o).contains("morph target normal at vertex 2"));
        // The target counts toward the world extent.
        let mut o = growing_sphere();
        o.morph.as_mut().unwrap().positions[0] = Vec3::new(2.0e4, 0.0, 0.0);
        assert!(invalid(o).contains("from the origin"));
    }
}
