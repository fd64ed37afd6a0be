// ---------------------------------------------------------------------------------------------
// Billboards, slices and ray-traced volumes (thesis chapter 6.3). Imports gpu::prelude,
// scene::shading and volumes::path_length.
//
// Every volume is drawn as camera-facing quads from one instanced draw: instance i is slice
// (i % SLICES) of volume (i / SLICES); volumes are sorted back to front on the CPU and slices
// are emitted back to front within a volume, so blending in primitive order composites
// correctly. Colours are premultiplied: out = (colour * a, a), blended with
// (One, OneMinusSrcAlpha) on rgb; the destination alpha is left as it is.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{BIG, ray_plane}
#import volumes::path_length::{PRIMITIVE_SPHERE, PRIMITIVE_TEXTURE, opacity_from_length, depth_fade, sphere_path_length, billboard_coords, half_thickness, billboard_path_length, slice_alpha}

// 1 for billboards and ray-traced volumes, N for N slices (thesis 6.3.2).
override SLICES: u32 = 1u;
// OPACITY_* of path_length.wgsl.
override OPACITY: u32 = 1u;
// PRIMITIVE_* of path_length.wgsl (ray-traced volumes only).
override PRIMITIVE: u32 = 2u;
// Where the ray-traced pass reads the scene distance: 0 = the R16Float distance texture of
// the depth pre-pass (thesis 6.3.3), 1 = the depth buffer of the raster pass.
override DEPTH_SOURCE: u32 = 0u;
// Depth-fade particles: the fade distance in units of the volume radius.
override FADE: f32 = 1.0;

// Billboard coordinates covered by the thickness texture: [-E, E]^2 (Rust:
// THICKNESS_TEXTURE_EXTENT).
const THICKNESS_EXTENT: f32 = 1.0625;

struct Globals {
    view_proj: mat4x4f,
    inv_view_proj: mat4x4f,
    // xyz: eye position.
    eye: vec4f,
    // x, y: viewport size in pixels; z, w: unused.
    viewport: vec4f,
};

struct VolumeGpu {
    // xyz: centre at this frame's time; w: radius R.
    center: vec4f,
    // Billboard axes (unit): right and up in the plane, normal toward the eye.
    // right.w: opacity scale (opacity reached over one metre, `technique::opacity_scale` or the
    // baked texture's scale; not the scene's extinction); up.w: billboard half size (metres);
    // normal.w: 1 = draw a screen-filling quad instead of the billboard (ray-traced only).
    right: vec4f,
    up: vec4f,
    normal: vec4f,
    // rgb: colour of the medium.
    color: vec4f,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> volumes: array<VolumeGpu>;
@group(0) @binding(2) var thickness_texture: texture_2d<f32>;
@group(0) @binding(3) var thickness_sampler: sampler;
@group(0) @binding(4) var scene_distance_texture: texture_2d<f32>;
@group(0) @binding(5) var scene_depth_texture: texture_depth_2d;

struct VolumeOut {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    // Quad coordinate in [-1, 1]^2 (slices: |local| <= 1 is the slice's disc).
    @location(1) local: vec2f,
    // Coordinates on the volume's centre plane in units of R, where the eye ray through this
    // point meets it (for billboards the point itself).
    @location(2) uv: vec2f,
    @location(3) @interpolate(flat) volume: u32,
    // Slices: the slab [near, far] this slice stands for, metres along the view axis from the
    // centre plane (negative toward the eye).
    @location(4) @interpolate(flat) slab: vec2f,
};

@vertex
fn volume_vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> VolumeOut {
    var corners = array<vec2f, 6>(
        vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
        vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0),
    );
    let corner = corners[vertex];
    let index = instance / SLICES;
    let v = volumes[index];
    let c = v.center.xyz;
    let r = v.center.w;
    let n = v.normal.xyz;
    var offset = 0.0;
    var half_size = v.up.w;
    var slab = vec2f(-r, r);
    if (SLICES > 1u) {
        // Slice k = 0 is nearest the eye; instances run from the back (thesis figure 6.17:
        // parallel slices scaled so that together they form a sphere).
        let k = SLICES - 1u - instance % SLICES;
        let delta = 2.0 * r / f32(SLICES);
        let near = -r + f32(k) * delta;
        slab = vec2f(near, near + delta);
        offset = near + 0.5 * delta;
        // The disc covers the slab's largest cross-section of the sphere.
        let z = max(abs(offset) - 0.5 * delta, 0.0);
        half_size = sqrt(max(r * r - z * z, 0.0));
    }
    let world = c - n * offset + (v.right.xyz * corner.x + v.up.xyz * corner.y) * half_size;
    // Perspective correction (thesis 6.3.2, figure 6.17): cast the ray from the eye through
    // this vertex onto the centre slice's plane and use that point as texture coordinate.
    // Slices are parallel to the centre plane, so this map is a similarity and interpolating
    // it across the slice is exact.
    let eye = globals.eye.xyz;
    let to_vertex = world - eye;
    let t = ray_plane(eye, to_vertex, n, dot(n, c));
    let q = eye + t * to_vertex - c;
    var out: VolumeOut;
    out.clip = globals.view_proj * vec4f(world, 1.0);
    out.world = world;
    if (SLICES == 1u && v.normal.w > 0.5) {
        // The eye is inside or next to the sphere: cover the screen; the fragment shader only
        // needs a point on each pixel's eye ray.
        out.clip = vec4f(corner, 0.5, 1.0);
        let p = globals.inv_view_proj * out.clip;
        out.world = p.xyz / p.w;
    }
    out.local = corner;
    out.uv = vec2f(dot(q, v.right.xyz), dot(q, v.up.xyz)) / r;
    out.volume = index;
    out.slab = slab;
    return out;
}

// Half thickness (units of R) stored in the thickness texture's alpha at billboard coordinates.
fn thickness_at(uv: vec2f) -> f32 {
    let st = uv / THICKNESS_EXTENT * 0.5 + 0.5;
    return textureSampleLevel(thickness_texture, thickness_sampler, st, 0.0).a;
}

fn premultiplied(v: VolumeGpu, a: f32) -> vec4f {
    return vec4f(v.color.rgb * a, a);
}

// Thesis 6.3.1: a plain billboard whose texture alpha is the opacity of the whole sphere at
// that texel (the pre-integrated chord); depth tested against the scene at its own plane.
@fragment
fn billboard_fs(in: VolumeOut) -> @location(0) vec4f {
    let v = volumes[in.volume];
    return premultiplied(v, billboard_opacity(v, in.uv));
}

// The billboard's opacity at `uv`: the pre-integrated chord of the thickness texture.
fn billboard_opacity(v: VolumeGpu, uv: vec2f) -> f32 {
    return opacity_from_length(OPACITY, 2.0 * v.center.w * thickness_at(uv), v.right.w);
}

// Thesis 6.3.2: one of N slices, depth tested against the scene; its share of the opacity
// comes from the same texture (at the perspective-corrected centre-plane coordinates).
@fragment
fn slice_fs(in: VolumeOut) -> @location(0) vec4f {
    if (dot(in.local, in.local) > 1.0) { discard; }
    let v = volumes[in.volume];
    let r = v.center.w;
    let d = normalize(in.world - globals.eye.xyz);
    let obliquity = 1.0 / max(abs(dot(d, v.normal.xyz)), 1e-3);
    let a = slice_alpha(OPACITY, v.right.w, r * thickness_at(in.uv), in.slab.x, in.slab.y, obliquity);
    return premultiplied(v, a);
}

// Distance along the eye ray through pixel `p` (framebuffer coordinates) to the scene.
fn scene_distance(p: vec2f) -> f32 {
    let texel = vec2i(p);
    if (DEPTH_SOURCE == 0u) {
        return textureLoad(scene_distance_texture, texel, 0).r;
    }
    let z = textureLoad(scene_depth_texture, texel, 0);
    if (z >= 1.0) { return BIG; }
    let ndc = vec2f(2.0 * p.x / globals.viewport.x - 1.0, 1.0 - 2.0 * p.y / globals.viewport.y);
    let w = globals.inv_view_proj * vec4f(ndc, z, 1.0);
    return distance(w.xyz / w.w, globals.eye.xyz);
}

// Thesis 6.3.3: the billboard is drawn without depth test; the ray through the pixel is
// intersected with the volume primitive and the visible length, clipped by the scene
// distance, becomes the opacity.
@fragment
fn raytraced_fs(in: VolumeOut) -> @location(0) vec4f {
    let v = volumes[in.volume];
    let c = v.center.xyz;
    let r = v.center.w;
    let o = globals.eye.xyz;
    let d = normalize(in.world - o);
    let t_scene = scene_distance(in.clip.xy);
    var len: f32;
    if (PRIMITIVE == PRIMITIVE_SPHERE) {
        len = sphere_path_length(o, d, c, r, t_scene);
    } else {
        let b = billboard_coords(o, d, c, v.right.xyz, v.up.xyz, v.normal.xyz, r);
        var texture_value = 0.0;
        if (PRIMITIVE == PRIMITIVE_TEXTURE) { texture_value = thickness_at(b.xy); }
        len = billboard_path_length(b.z, r * half_thickness(PRIMITIVE, b.xy, texture_value), t_scene);
    }
    return premultiplied(v, opacity_from_length(OPACITY, len, v.right.w));
}

// Engine baseline: the depth-fade soft particle. The billboard of billboard_fs (the same
// pre-integrated texture), drawn without depth test: its opacity is multiplied by the depth fade
// of the scene distance behind the pixel (the raster pass's depth buffer, DEPTH_SOURCE 1), which
// is 0 behind the scene and ramps to 1 over FADE radii in front of it.
@fragment
fn depth_fade_fs(in: VolumeOut) -> @location(0) vec4f {
    let v = volumes[in.volume];
    let t_particle = distance(in.world, globals.eye.xyz);
    let fade = depth_fade(t_particle, scene_distance(in.clip.xy), FADE * v.center.w);
    return premultiplied(v, billboard_opacity(v, in.uv) * fade);
}
