//! Rust twin of `shaders/path_length.wgsl`: the visible path length of a ray through the
//! volume primitives of the thesis (section 6.3.3, figure 6.18), clipped by the eye and by
//! the scene depth, and the path-length-to-opacity functions of figure 6.21.
//!
//! Same names, same constants, same branches as the WGSL; `tests/conformance.rs` runs the
//! WGSL in a compute shader on random inputs and compares it with these, and
//! `tests/path_length_properties.rs` states their properties with proptest. The tests' variant
//! model (`tests/common/mod.rs`) uses [`sphere_path_length`] and [`opacity_from_length`].
//!
//! A ray is `o + t d` with `d` unit length, so `t` is metres. `t_scene` is the distance along
//! the ray to the first opaque surface (`f32::INFINITY` or [`gpu::prelude::BIG`] when there is
//! none). Billboard coordinates `(u, v)` are in units of the volume radius `R` on the plane
//! through the volume centre that faces the eye.

use glam::{Vec2, Vec3};
use gpu::prelude::{ray_plane, ray_sphere};

/// The WGSL twin of this module: the module `volumes::path_length` ([`PATH_LENGTH`]).
pub const PATH_LENGTH_WGSL: &str = include_str!("shaders/path_length.wgsl");
/// [`PATH_LENGTH_WGSL`] as the module `volumes::path_length`, which the technique's shader and
/// the conformance kernels import.
pub static PATH_LENGTH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    PATH_LENGTH_WGSL,
    "volumes/src/shaders/path_length.wgsl",
    &[],
);

/// WGSL code of [`OpacityFn::Linear`] (the `OPACITY` pipeline constant).
pub const OPACITY_LINEAR: u32 = 0;
/// WGSL code of [`OpacityFn::Log`].
pub const OPACITY_LOG: u32 = 1;
/// WGSL code of [`OpacityFn::Sqrt`].
pub const OPACITY_SQRT: u32 = 2;

/// WGSL code of [`Primitive::Constant`] (the `PRIMITIVE` pipeline constant).
pub const PRIMITIVE_CONSTANT: u32 = 0;
/// WGSL code of [`Primitive::Linear`].
pub const PRIMITIVE_LINEAR: u32 = 1;
/// WGSL code of [`Primitive::Sphere`].
pub const PRIMITIVE_SPHERE: u32 = 2;
/// WGSL code of [`Primitive::Texture`].
pub const PRIMITIVE_TEXTURE: u32 = 3;

/// How the length of the visible path becomes opacity (thesis figure 6.21).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OpacityFn {
    /// `density * len`.
    Linear,
    /// `density * log2(1 + len)`: the thesis's default (tests 12-14 and 17).
    Log,
    /// `density * sqrt(len)`.
    Sqrt,
}

impl OpacityFn {
    /// The code the WGSL uses (`OPACITY_*`).
    pub fn code(self) -> u32 {
        match self {
            OpacityFn::Linear => OPACITY_LINEAR,
            OpacityFn::Log => OPACITY_LOG,
            OpacityFn::Sqrt => OPACITY_SQRT,
        }
    }
    /// The function's name in variant ids (`raytraced-sphere-log`) and tables.
    pub fn name(self) -> &'static str {
        match self {
            OpacityFn::Linear => "linear",
            OpacityFn::Log => "log",
            OpacityFn::Sqrt => "sqrt",
        }
    }
    /// [`opacity_from_length`] with this function.
    pub fn opacity(self, len: f32, density: f32) -> f32 {
        opacity_from_length(self.code(), len, density)
    }
    /// The function's shape `g(len)` (opacity = `scale * g(len)`, before clamping).
    fn shape(self, len: f32) -> f32 {
        let l = len.max(0.0);
        match self {
            OpacityFn::Linear => l,
            OpacityFn::Log => (1.0 + l).log2(),
            OpacityFn::Sqrt => l.sqrt(),
        }
    }
    /// The scale (opacity at one metre) for which a path of `len` metres has opacity `alpha`;
    /// 0 for a non-positive length.
    pub fn scale_for(self, alpha: f32, len: f32) -> f32 {
        let g = self.shape(len);
        if g > 0.0 && alpha.is_finite() {
            alpha.max(0.0) / g
        } else {
            0.0
        }
    }
    /// The path length at which this function with `scale` reaches `alpha` (the inverse of
    /// [`OpacityFn::opacity`] below saturation); 0 for a zero scale.
    pub fn length_for(self, alpha: f32, scale: f32) -> f32 {
        if scale.is_nan() || scale <= 0.0 {
            return 0.0;
        }
        let g = alpha.max(0.0) / scale;
        match self {
            OpacityFn::Linear => g,
            OpacityFn::Log => g.exp2() - 1.0,
            OpacityFn::Sqrt => g * g,
        }
    }
}

/// The volume primitive a ray-traced billboard intersects (thesis figure 6.18).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Primitive {
    /// 6.18a: constant thickness `2R` along every ray through the sprite's disc.
    Constant,
    /// 6.18b: thickness decreasing linearly toward the billboard's edges (a square pyramid
    /// in front of and behind the billboard).
    Linear,
    /// 6.18d: the true sphere.
    Sphere,
    /// 6.18c: half thickness read from a texture (here: an 8-bit texture holding the sphere's
    /// profile, the thesis's "almost spherical thickness texture" of figure 6.22n).
    Texture,
}

impl Primitive {
    /// The code the WGSL uses (`PRIMITIVE_*`).
    pub fn code(self) -> u32 {
        match self {
            Primitive::Constant => PRIMITIVE_CONSTANT,
            Primitive::Linear => PRIMITIVE_LINEAR,
            Primitive::Sphere => PRIMITIVE_SPHERE,
            Primitive::Texture => PRIMITIVE_TEXTURE,
        }
    }
}

/// Opacity of a path of `len` metres through a medium whose `density` is the opacity reached
/// over one metre (the technique's opacity scale, [`crate::technique::opacity_scale`], not the
/// scene's extinction coefficient): linear `density * len`, logarithmic `density * log2(1 + len)`, square root
/// `density * sqrt(len)` (all give `density` at 1 m and 0 at 0 m), clamped to [0, 1].
/// An unknown `kind` is linear.
pub fn opacity_from_length(kind: u32, len: f32, density: f32) -> f32 {
    let l = len.max(0.0);
    let g = match kind {
        OPACITY_LOG => (1.0 + l).log2(),
        OPACITY_SQRT => l.sqrt(),
        _ => l,
    };
    (density * g).clamp(0.0, 1.0)
}

/// The part of `[t_front, t_back]` in front of the eye (`t >= 0`) and in front of the scene
/// (`t <= t_scene`). Never negative.
pub fn visible_length(t_front: f32, t_back: f32, t_scene: f32) -> f32 {
    (t_back.min(t_scene) - t_front.max(0.0)).max(0.0)
}

/// The depth fade of soft particles, as every engine's particle system ships it (Unreal's
/// `DepthFade`, Unity's soft particles): a billboard's opacity is multiplied by
/// `clamp((t_scene - t_particle) / fade, 0, 1)`, distances along the eye ray. It is 0 where the
/// billboard lies behind the scene (it takes the place of the depth test) and reaches 1 once the
/// scene is `fade` metres behind the billboard, so a billboard cutting into geometry fades out
/// instead of showing a hard intersection line. `fade <= 0` is the plain depth test (1 in
/// front, 0 behind).
pub fn depth_fade(t_particle: f32, t_scene: f32, fade: f32) -> f32 {
    let gap = t_scene - t_particle;
    if fade <= 0.0 {
        return if gap > 0.0 { 1.0 } else { 0.0 };
    }
    (gap / fade).clamp(0.0, 1.0)
}

/// True sphere (figure 6.18d): exact entry and exit, clipped by the eye and the scene. A miss
/// or a tangent ray gives 0.
pub fn sphere_path_length(o: Vec3, d: Vec3, center: Vec3, radius: f32, t_scene: f32) -> f32 {
    let t = ray_sphere(o, d, center, radius);
    if t.x > t.y {
        return 0.0;
    }
    visible_length(t.x, t.y, t_scene)
}

/// Where the ray meets the billboard plane through `center` (unit `normal`, unit in-plane
/// axes `right`, `up`): `(u, v, t_plane)` with `(u, v)` in units of `radius`. A ray parallel to
/// the plane gives `t_plane = -1`.
pub fn billboard_coords(
    o: Vec3,
    d: Vec3,
    center: Vec3,
    right: Vec3,
    up: Vec3,
    normal: Vec3,
    radius: f32,
) -> Vec3 {
    let t = ray_plane(o, d, normal, normal.dot(center));
    let p = o + t * d - center;
    Vec3::new(p.dot(right) / radius, p.dot(up) / radius, t)
}

/// 6.18a: half thickness 1 (units of R) inside the sprite's disc `|uv| <= 1`, 0 outside.
pub fn half_thickness_constant(uv: Vec2) -> f32 {
    if uv.dot(uv) <= 1.0 { 1.0 } else { 0.0 }
}

/// 6.18b: a square pyramid `1 - max(|u|, |v|)` inside the sprite's disc.
pub fn half_thickness_linear(uv: Vec2) -> f32 {
    if uv.dot(uv) > 1.0 {
        return 0.0;
    }
    (1.0 - uv.x.abs().max(uv.y.abs())).max(0.0)
}

/// The sphere's profile `sqrt(1 - |uv|^2)`: what the thickness texture (6.18c) stores.
pub fn half_thickness_sphere(uv: Vec2) -> f32 {
    (1.0 - uv.dot(uv)).max(0.0).sqrt()
}

/// Half thickness (units of R) of billboard primitive `kind` at `uv`; `texture_value` is the
/// thickness texture sampled at `uv` (used by [`PRIMITIVE_TEXTURE`] only). The sphere is not
/// a billboard primitive and gives 0.
pub fn half_thickness(kind: u32, uv: Vec2, texture_value: f32) -> f32 {
    match kind {
        PRIMITIVE_CONSTANT => half_thickness_constant(uv),
        PRIMITIVE_LINEAR => half_thickness_linear(uv),
        PRIMITIVE_TEXTURE => texture_value.clamp(0.0, 1.0),
        _ => 0.0,
    }
}

/// Billboard primitives (6.18a-c): the volume reaches `half_len` metres in front of and
/// behind the billboard along the ray, which meets the billboard at `t_plane`. A billboard
/// behind the eye shows nothing.
pub fn billboard_path_length(t_plane: f32, half_len: f32, t_scene: f32) -> f32 {
    if half_len <= 0.0 || t_plane <= 0.0 {
        return 0.0;
    }
    visible_length(t_plane - half_len, t_plane + half_len, t_scene)
}

/// Opacity of one slice of a stack of slabs forming a volume of half thickness `half_len`
/// (metres along the view axis; the volume spans `[-half_len, half_len]`). The slice stands
/// for the slab `[slab_near, slab_far]` (negative toward the eye); `obliquity` (>= 1) turns
/// view-axis lengths into lengths along the ray. The share is chosen so that the slices from
/// the front face up to this one composite to the opacity of the path from the front face to
/// the far side of this slab: `1 - (1 - a_far) / (1 - a_near)`. A slab outside the volume
/// gives 0; one behind an already opaque front gives 1 (hidden whenever it is drawn).
pub fn slice_alpha(
    kind: u32,
    density: f32,
    half_len: f32,
    slab_near: f32,
    slab_far: f32,
    obliquity: f32,
) -> f32 {
    let h = half_len.max(0.0);
    let l_near = (slab_near + h).clamp(0.0, 2.0 * h) * obliquity;
    let l_far = (slab_far + h).clamp(0.0, 2.0 * h) * obliquity;
    if l_far <= l_near {
        return 0.0;
    }
    let a_near = opacity_from_length(kind, l_near, density);
    let a_far = opacity_from_length(kind, l_far, density);
    if a_near >= 1.0 {
        return 1.0;
    }
    (1.0 - (1.0 - a_far) / (1.0 - a_near)).clamp(0.0, 1.0)
}

/// Visible path length of `primitive` for the ray `(o, d)` through a volume of `radius` at
/// `center` whose billboard has axes `right`, `up`, `normal`; `texture_value` is the
/// thickness texture at the ray's billboard coordinates (PRIMITIVE_TEXTURE only). This is
/// what the ray-traced fragment shader computes.
#[allow(clippy::too_many_arguments)]
pub fn primitive_path_length(
    primitive: Primitive,
    o: Vec3,
    d: Vec3,
    center: Vec3,
    radius: f32,
    basis: [Vec3; 3],
    texture_value: f32,
    t_scene: f32,
) -> f32 {
    if primitive == Primitive::Sphere {
        return sphere_path_length(o, d, center, radius, t_scene);
    }
    let [right, up, normal] = basis;
    let b = billboard_coords(o, d, center, right, up, normal, radius);
    let h = half_thickness(primitive.code(), Vec2::new(b.x, b.y), texture_value);
    billboard_path_length(b.z, h * radius, t_scene)
}

/// Side of the thickness texture in texels.
pub const THICKNESS_TEXTURE_SIZE: u32 = 128;
/// The thickness texture covers billboard coordinates `[-E, E]^2` with `E` this value; the
/// outermost texels lie outside the unit disc, so clamp-to-edge sampling reads 0 beyond it.
pub const THICKNESS_TEXTURE_EXTENT: f32 = 1.0625;

/// Texels (RGBA8, row 0 at v = -E) of the thickness texture: white, alpha = the sphere
/// profile [`half_thickness_sphere`] at the texel centre, quantised to 8 bits as the thesis
/// stores thickness in the alpha of the diffuse texture.
pub fn thickness_texels() -> Vec<u8> {
    let n = THICKNESS_TEXTURE_SIZE;
    let mut out = Vec::with_capacity((4 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let uv = Vec2::new(texel_coord(i), texel_coord(j));
            let a = (half_thickness_sphere(uv) * 255.0).round() as u8;
            out.extend_from_slice(&[255, 255, 255, a]);
        }
    }
    out
}

/// Column steps per texel of [`bake_thickness`].
const BAKE_STEPS: u32 = 48;

/// The thickness texture of `volume` as an artist would paint it for the view along
/// `-basis[2]` (billboard axes `right`, `up`, `normal` toward the eye, as
/// `technique::placed_volumes` gives them): per texel, the true opacity `alpha(uv) = 1 -
/// exp(-tau)` of the column through the point `c + R (u right + v up)` along the normal
/// (`tau` by the midpoint rule, `BAKE_STEPS` (48) steps, with the scene's own density field
/// `Volume::extinction_at` at time 0), stored as the half thickness `h = L / 2R` at which
/// `opacity` reaches it, `L = opacity.length_for(alpha, scale)`. `scale` (returned) is chosen
/// so that the densest column has `h = 1`: nothing is clipped by the 8-bit range, and a
/// billboard with this texture and this scale shows `alpha(uv)` exactly (up to 8 bits).
pub fn bake_thickness(
    volume: &scene::Volume,
    basis: [Vec3; 3],
    opacity: OpacityFn,
) -> (Vec<u8>, f32) {
    let [right, up, normal] = basis;
    let (c, r) = (volume.center + volume.motion.offset(0.0), volume.radius);
    let n = THICKNESS_TEXTURE_SIZE;
    let mut alphas = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let uv = Vec2::new(texel_coord(i), texel_coord(j));
            let half = r * (1.0 - uv.dot(uv)).max(0.0).sqrt();
            let p0 = c + r * (uv.x * right + uv.y * up);
            let dt = 2.0 * half / BAKE_STEPS as f32;
            let tau: f32 = (0..BAKE_STEPS)
                .map(|k| {
                    volume.extinction_at(p0 + normal * (-half + (k as f32 + 0.5) * dt), 0.0) * dt
                })
                .sum();
            alphas.push(1.0 - (-tau).exp());
        }
    }
    let max_alpha = alphas.iter().copied().fold(0.0f32, f32::max);
    let scale = opacity.scale_for(max_alpha, 2.0 * r);
    let mut out = Vec::with_capacity(4 * alphas.len());
    for a in alphas {
        let h = (opacity.length_for(a, scale) / (2.0 * r)).clamp(0.0, 1.0);
        out.extend_from_slice(&[255, 255, 255, (h * 255.0).round() as u8]);
    }
    (out, scale)
}

/// Billboard coordinate of the centre of texel `i` of the thickness texture.
fn texel_coord(i: u32) -> f32 {
    ((i as f32 + 0.5) / THICKNESS_TEXTURE_SIZE as f32 * 2.0 - 1.0) * THICKNESS_TEXTURE_EXTENT
}

/// Bilinear, clamp-to-edge lookup of [`thickness_texels`]' alpha at billboard coordinates
/// `uv`, as the GPU's filtering sampler does it (up to the GPU's 8-bit filter precision).
pub fn sample_thickness(texels: &[u8], uv: Vec2) -> f32 {
    let n = THICKNESS_TEXTURE_SIZE as i64;
    let to_tex = |c: f32| (c / THICKNESS_TEXTURE_EXTENT * 0.5 + 0.5) * n as f32 - 0.5;
    let (x, y) = (to_tex(uv.x), to_tex(uv.y));
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let a = |i: i64, j: i64| {
        let (i, j) = (i.clamp(0, n - 1), j.clamp(0, n - 1));
        texels[(4 * (j * n + i) + 3) as usize] as f32 / 255.0
    };
    let (i, j) = (x0 as i64, y0 as i64);
    let top = a(i, j) + (a(i + 1, j) - a(i, j)) * fx;
    let bottom = a(i, j + 1) + (a(i + 1, j + 1) - a(i, j + 1)) * fx;
    top + (bottom - top) * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opacity_functions_reach_density_at_one_metre() {
        for kind in [OPACITY_LINEAR, OPACITY_LOG, OPACITY_SQRT] {
            assert_eq!(opacity_from_length(kind, 0.0, 0.6), 0.0);
            assert!((opacity_from_length(kind, 1.0, 0.6) - 0.6).abs() < 1e-6);
            assert_eq!(opacity_from_length(kind, 100.0, 0.6), 1.0);
        }
    }

    #[test]
    fn scale_and_length_invert_each_other() {
        for f in [OpacityFn::Linear, OpacityFn::Log, OpacityFn::Sqrt] {
            let s = f.scale_for(0.6, 3.0);
            assert!((f.opacity(3.0, s) - 0.6).abs() < 1e-5);
            assert!((f.length_for(0.6, s) - 3.0).abs() < 1e-4);
            assert_eq!(f.length_for(0.5, 0.0), 0.0);
        }
    }

    /// A baked uniform ball seen along its normal: the billboard with the returned scale
    /// shows the ball's true opacity `1 - exp(-sigma chord)`.
    #[test]
    fn baked_texture_reproduces_the_true_opacity() {
        let v = scene::Volume {
            name: "v".into(),
            center: Vec3::new(0.5, 1.0, -2.0),
            radius: 1.5,
            color: Vec3::ONE,
            density: 0.4,
            profile: scene::DensityProfile::UNIFORM,
            particle: false,
            motion: Default::default(),
        };
        let (texels, scale) = bake_thickness(&v, [Vec3::X, Vec3::Y, Vec3::Z], OpacityFn::Log);
        for uv in [Vec2::ZERO, Vec2::new(0.5, 0.0), Vec2::new(0.3, -0.6)] {
            let h = sample_thickness(&texels, uv);
            let shown = OpacityFn::Log.opacity(2.0 * v.radius * h, scale);
            let truth = 1.0 - (-v.density * 2.0 * v.radius * (1.0 - uv.dot(uv)).sqrt()).exp();
            assert!((shown - truth).abs() < 0.01, "{uv}: {shown} vs {truth}");
        }
    }

    #[test]
    fn thickness_texture_is_the_sphere_profile() {
        let t = thickness_texels();
        assert!((sample_thickness(&t, Vec2::ZERO) - 1.0).abs() < 0.01);
        assert!((sample_thickness(&t, Vec2::new(0.6, 0.0)) - 0.8).abs() < 0.01);
        assert_eq!(sample_thickness(&t, Vec2::new(1.06, 0.0)), 0.0);
        assert_eq!(sample_thickness(&t, Vec2::new(3.0, 2.0)), 0.0);
    }
}
