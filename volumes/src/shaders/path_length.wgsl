#define_import_path volumes::path_length
// ---------------------------------------------------------------------------------------------
// Visible path length through the volume primitives of van Dongen's thesis, section 6.3.3, and the
// path-length-to-opacity functions of figure 6.21: the module volumes::path_length, importing
// gpu::prelude (ray_sphere, ray_plane). Every function has a Rust twin of the same name in `volumes::path_length`,
// checked against it on the GPU by `volumes/tests/conformance.rs`.
//
// Conventions: a ray is o + t d with d unit length, so t is a distance in metres; `t_scene` is
// the distance along the ray to the first opaque surface (BIG or more when there is none).
// Billboard coordinates (u, v) are in units of the volume radius R, measured on the plane
// through the volume centre that faces the eye.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{ray_plane, ray_sphere}

const OPACITY_LINEAR: u32 = 0u;
const OPACITY_LOG: u32 = 1u;
const OPACITY_SQRT: u32 = 2u;

const PRIMITIVE_CONSTANT: u32 = 0u;
const PRIMITIVE_LINEAR: u32 = 1u;
const PRIMITIVE_SPHERE: u32 = 2u;
const PRIMITIVE_TEXTURE: u32 = 3u;

// Opacity of a path of `len` metres through a medium whose `density` is the opacity reached
// over one metre (the technique's opacity scale, not the scene's extinction coefficient) (thesis figure 6.21; all three give `density` at 1 m and 0 at 0 m):
// linear density * len, logarithmic density * log2(1 + len), square root density * sqrt(len),
// clamped to [0, 1].
fn opacity_from_length(kind: u32, len: f32, density: f32) -> f32 {
    let l = max(len, 0.0);
    var g: f32;
    if (kind == OPACITY_LOG) {
        g = log2(1.0 + l);
    } else if (kind == OPACITY_SQRT) {
        g = sqrt(l);
    } else {
        g = l;
    }
    return clamp(density * g, 0.0, 1.0);
}

// The part of the ray interval [t_front, t_back] inside the volume that the eye sees: in
// front of the eye (t >= 0) and in front of the scene (t <= t_scene). Never negative.
fn visible_length(t_front: f32, t_back: f32, t_scene: f32) -> f32 {
    return max(min(t_back, t_scene) - max(t_front, 0.0), 0.0);
}

// Soft particles' depth fade (engines' DepthFade): clamp((t_scene - t_particle) / fade, 0, 1);
// fade <= 0 is the plain depth test. Twin: path_length.rs `depth_fade`.
fn depth_fade(t_particle: f32, t_scene: f32, fade: f32) -> f32 {
    let gap = t_scene - t_particle;
    if (fade <= 0.0) { return select(0.0, 1.0, gap > 0.0); }
    return clamp(gap / fade, 0.0, 1.0);
}

// True sphere (figure 6.18d): exact entry and exit of the ray, clipped by the eye and the
// scene. A miss or a tangent ray gives 0.
fn sphere_path_length(o: vec3f, d: vec3f, center: vec3f, radius: f32, t_scene: f32) -> f32 {
    let t = ray_sphere(o, d, center, radius);
    if (t.x > t.y) { return 0.0; }
    return visible_length(t.x, t.y, t_scene);
}

// Where the ray meets the billboard plane through `center` with unit normal `normal` and
// unit in-plane axes `right`, `up`: (u, v, t_plane) with (u, v) in units of `radius`.
// A ray parallel to the plane gives t_plane = -1 (ray_plane's convention).
fn billboard_coords(o: vec3f, d: vec3f, center: vec3f, right: vec3f, up: vec3f, normal: vec3f,
                    radius: f32) -> vec3f {
    let t = ray_plane(o, d, normal, dot(normal, center));
    let p = o + t * d - center;
    return vec3f(dot(p, right) / radius, dot(p, up) / radius, t);
}

// Half thickness of the billboard primitives in units of R at billboard coordinates uv, where
// the sprite covers the disc |uv| <= 1 (the thesis's round smoke texture):
// constant (figure 6.18a): 1 inside the disc;
// linearly decreasing (6.18b): a square pyramid 1 - max(|u|, |v|), inside the disc;
// sphere profile: sqrt(1 - |uv|^2), what the thickness texture of 6.18c stores.
fn half_thickness_constant(uv: vec2f) -> f32 {
    return select(0.0, 1.0, dot(uv, uv) <= 1.0);
}

fn half_thickness_linear(uv: vec2f) -> f32 {
    if (dot(uv, uv) > 1.0) { return 0.0; }
    return max(1.0 - max(abs(uv.x), abs(uv.y)), 0.0);
}

fn half_thickness_sphere(uv: vec2f) -> f32 {
    return sqrt(max(1.0 - dot(uv, uv), 0.0));
}

// Half thickness (units of R) of billboard primitive `kind` at uv; `texture_value` is the
// thickness texture sampled at uv (used by PRIMITIVE_TEXTURE only). The sphere is not a
// billboard primitive: it gives 0 here.
fn half_thickness(kind: u32, uv: vec2f, texture_value: f32) -> f32 {
    if (kind == PRIMITIVE_CONSTANT) { return half_thickness_constant(uv); }
    if (kind == PRIMITIVE_LINEAR) { return half_thickness_linear(uv); }
    if (kind == PRIMITIVE_TEXTURE) { return clamp(texture_value, 0.0, 1.0); }
    return 0.0;
}

// Billboard primitives (6.18a-c): the volume reaches `half_len` metres in front of and behind
// the billboard along the ray, which meets the billboard at t_plane. This is why the thesis
// calls them tapered: the thickness is measured along rays from the eye. A billboard behind
// the eye (t_plane <= 0) shows nothing.
fn billboard_path_length(t_plane: f32, half_len: f32, t_scene: f32) -> f32 {
    if (half_len <= 0.0 || t_plane <= 0.0) { return 0.0; }
    return visible_length(t_plane - half_len, t_plane + half_len, t_scene);
}

// Opacity of one slice of a stack of slabs that together form a volume of half thickness
// `half_len` (metres along the view axis at this texel, the volume spans [-half_len,
// half_len] around the centre plane). The slice stands for the slab [slab_near, slab_far]
// (metres along the view axis, negative toward the eye); `obliquity` (>= 1) turns lengths
// along the view axis into lengths along the ray. The slice's share is chosen so that the
// slices from the front of the volume up to and including this one composite (with the
// `over` operator) to exactly the opacity of the path from the front face to the far side of
// this slab: 1 - (1 - a_far) / (1 - a_near). Slabs outside the volume give 0; a slab
// behind an already opaque front gives 1 (it is hidden whenever it is drawn).
fn slice_alpha(kind: u32, density: f32, half_len: f32, slab_near: f32, slab_far: f32,
               obliquity: f32) -> f32 {
    let h = max(half_len, 0.0);
    let l_near = clamp(slab_near + h, 0.0, 2.0 * h) * obliquity;
    let l_far = clamp(slab_far + h, 0.0, 2.0 * h) * obliquity;
    if (l_far <= l_near) { return 0.0; }
    let a_near = opacity_from_length(kind, l_near, density);
    let a_far = opacity_from_length(kind, l_far, density);
    if (a_near >= 1.0) { return 1.0; }
    return clamp(1.0 - (1.0 - a_far) / (1.0 - a_near), 0.0, 1.0);
}
