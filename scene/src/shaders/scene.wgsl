#define_import_path scene::shading
// ---------------------------------------------------------------------------------------------
// Shared scene bindings and the diffuse shading model (DESIGN.md): identical to the CPU
// reference's direct lighting: albedo / pi * I * max(0, n.l) / d^2 * visibility, summed over
// the lights (a spot's I times its cone falloff, a directional light's d = 1: light_toward),
// no ambient, visibility from one distance shadow map per light (a cube map, or a 2D map
// fitted to the scene for a light outside it or a directional one: see light_visibility).
// The module `scene::shading`: technique shaders import what they use from it; they draw objects
// with `scene_vs` (scene::SCENE_VS_WGSL, instance index = object index) and shade diffuse
// surfaces with `shade_diffuse`.
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{PI, fresnel_dielectric, fresnel_nk, hash_to_unit, pcg_hash, reflect_dir, refract_dir}
#import scene::medium::Medium

struct CameraUniform {
    view_proj: mat4x4f,
    eye: vec4f,
};

struct ObjectGpu {
    model: mat4x4f,
    normal_matrix: mat4x4f,
    // rgb: diffuse albedo; w: texture layer, or -1 when untextured.
    albedo: vec4f,
    // x: material kind (0 diffuse, 1 metal, 2 glass); y: ior; z: role bits; w: the alpha
    // cut-out's threshold, 0 for none (in_cutout_hole).
    material: vec4f,
    // Metal n and k per channel.
    n: vec4f,
    k: vec4f,
    // rgb: the radiance a diffuse surface emits (scene::Object::emission); 0 elsewhere.
    emission: vec4f,
};

struct LightGpu {
    // w: shadow kind, 0 = cube map around the light, 1 = one 2D map fitted to the scene. A
    // directional light's xyz is its orthographic map's eye, whence its distances are measured.
    position: vec4f,
    intensity: vec4f,
    // Fitted 2D map: world -> clip of the light's view, and (tan of half the field of view,
    // half the width of an orthographic map or 0 for a perspective one).
    shadow_view_proj: mat4x4f,
    shadow_params: vec4f,
    // xyz: the direction a spot points or a directional light travels; w: LIGHT_POINT,
    // LIGHT_SPOT or LIGHT_DIRECTIONAL (scene::LightKind).
    direction: vec4f,
    // A spot's cone: cosines of the inner and outer half-angles.
    cone: vec4f,
};

const LIGHT_SPOT: f32 = 1.0;
const LIGHT_DIRECTIONAL: f32 = 2.0;

struct SceneInfo {
    light_count: u32,
    shadow_size: f32,
    // Raster technique: 1 = shade specular objects as plain grey diffuse.
    specular_as_diffuse: u32,
    _pad: u32,
    background: vec4f,
    // The scene's scattering medium (medium.wgsl); min.w = 0 when it has none.
    medium: Medium,
};

const MATERIAL_DIFFUSE: f32 = 0.0;
const MATERIAL_METAL: f32 = 1.0;
const MATERIAL_GLASS: f32 = 2.0;
// Distance written for texels that see no geometry (fits Rgba16Float).
const BACKGROUND_DISTANCE: f32 = 60000.0;
// The eye's near plane (scene::Camera::NEAR).
const CAMERA_NEAR: f32 = 0.01;

@group(0) @binding(0) var<uniform> camera: CameraUniform;
@group(1) @binding(0) var<storage, read> objects: array<ObjectGpu>;
@group(1) @binding(1) var<storage, read> lights: array<LightGpu>;
@group(1) @binding(2) var albedo_textures: texture_2d_array<f32>;
@group(1) @binding(3) var albedo_sampler: sampler;
@group(1) @binding(4) var shadow_maps: texture_cube_array<f32>;
@group(1) @binding(5) var shadow_sampler: sampler;
@group(1) @binding(6) var<uniform> scene_info: SceneInfo;
@group(1) @binding(7) var fitted_shadow_maps: texture_2d_array<f32>;

// The scene's homogeneous scattering medium (scene::Medium); medium_present() is false when it
// has none. The shared raster pass ignores it (as it ignores the volumes): a technique that
// renders media applies it.
fn scene_medium() -> Medium {
    return scene_info.medium;
}

struct SceneVertexIn {
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) uv: vec2f,
};

struct SceneVertexOut {
    // Invariant so that passes re-drawing the same objects (depth peeling) get bit-identical
    // depths.
    @invariant @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) uv: vec2f,
    @location(3) @interpolate(flat) object: u32,
};

// The scene's vertex stage (`scene_vs` in SCENE_VS_WGSL calls it): object `object`'s vertex
// `v` in world space and clip space.
fn scene_vertex(v: SceneVertexIn, object: u32) -> SceneVertexOut {
    let o = objects[object];
    let world = (o.model * vec4f(v.position, 1.0)).xyz;
    var out: SceneVertexOut;
    out.clip = camera.view_proj * vec4f(world, 1.0);
    out.world = world;
    out.normal = (o.normal_matrix * vec4f(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.object = object;
    return out;
}

// Stratified jittered emission. A photon pass rasterizes the caustic casters from the light,
// one photon per pixel; at pixel centres the photons leave on a regular lattice, and where a
// caster spreads them (the caustic's rim under a glass sphere) the lattice shows as
// concentric moire rings. This moves the fragment to a random point of its own pixel (one
// stratum per pixel), `jitter` in [-0.5, 0.5)^2 pixels, on the surface's tangent plane: the
// world position and the interpolated normal are extended to first order with their
// screen-space derivatives. The photon keeps its pixel's flux (each stratum is one pixel),
// so the estimate stays unbiased and the rings become noise. Call in uniform control flow.
fn jittered_emission(in: SceneVertexOut, jitter: vec2f) -> SceneVertexOut {
    let point = jittered_point(in.world, in.normal, jitter);
    var out = in;
    out.world = point.world;
    out.normal = point.normal;
    return out;
}

// jittered_emission for a pass with its own vertex output: the interpolated `world` and
// `normal` moved by `jitter` pixels. Uniform control flow (derivatives).
struct EmissionPoint {
    world: vec3f,
    normal: vec3f,
};

fn jittered_point(world: vec3f, normal: vec3f, jitter: vec2f) -> EmissionPoint {
    let world_dx = dpdx(world);
    let world_dy = dpdy(world);
    let normal_dx = dpdx(normal);
    let normal_dy = dpdy(normal);
    return EmissionPoint(world + world_dx * jitter.x + world_dy * jitter.y,
                         normal + normal_dx * jitter.x + normal_dy * jitter.y);
}

// This pixel's jitter for jittered_emission: white noise, fixed per pixel and `seed`.
fn emission_jitter(pixel: vec2f, seed: u32) -> vec2f {
    let key = pcg_hash(u32(pixel.x) ^ pcg_hash(u32(pixel.y) ^ pcg_hash(seed)));
    return vec2f(hash_to_unit(key), hash_to_unit(key ^ 0x9e3779b9u)) - 0.5;
}

// The shading normal turned to face the viewer (surfaces are two-sided, as in the reference).
// Simple form for technique shaders; the raster pass uses the geometric rule below.
fn facing_normal(n: vec3f, p: vec3f, eye: vec3f) -> vec3f {
    let nn = normalize(n);
    return select(nn, -nn, dot(nn, eye - p) < 0.0);
}

// Unit geometric normal of the triangle under this fragment, turned toward the eye. From
// screen-space derivatives of the world position, so it needs no winding convention (cube
// faces are mirrored views) and must be called in uniform control flow.
fn geometric_facing_normal(p: vec3f, eye: vec3f) -> vec3f {
    let ng = normalize(cross(dpdx(p), dpdy(p)));
    return select(ng, -ng, dot(ng, eye - p) < 0.0);
}

// The reference's rule: the shading normal is turned to the side of the geometric normal the
// viewer sees.
fn shading_normal(n: vec3f, ng_facing: vec3f) -> vec3f {
    let nn = normalize(n);
    return select(nn, -nn, dot(nn, ng_facing) < 0.0);
}

// Whether the surface of `object` is absent at `uv`: its alpha cut-out (scene::Material's
// `cutout`, in material.w, 0 for none) is above its texture's alpha there. Every fragment
// shader that draws the scene's surfaces discards such fragments, as the reference's and the
// tracer's rays pass through them: first, or right after any derivative it takes (naga
// writes `discard` as OpKill, which ends the invocation, so no derivative may follow it).
fn in_cutout_hole(object: u32, uv: vec2f) -> bool {
    let o = objects[object];
    if (o.material.w <= 0.0) { return false; }
    let alpha = textureSampleLevel(albedo_textures, albedo_sampler, uv, i32(o.albedo.w), 0.0).a;
    return alpha < o.material.w;
}

fn surface_albedo(object: u32, uv: vec2f) -> vec3f {
    let o = objects[object];
    if (o.albedo.w < 0.0) { return o.albedo.rgb; }
    let t = textureSampleLevel(albedo_textures, albedo_sampler, uv, i32(o.albedo.w), 0.0).rgb;
    return o.albedo.rgb * t;
}

// Visibility of light `i` from p. The shadow map stores the distance from the light to the
// nearest surface per direction: a cube map around a light inside the scene, or one 2D map
// fitted to the scene's bounding sphere for a light outside it (a cube face would spend
// almost all its texels on empty space), orthographic for a directional light (distances from
// the map's eye behind the sphere, scene::LightKind::Directional). p is lit when it is not farther than the stored
// distance, with a bias of the texel's footprint at that distance, grown with the slope.
fn light_visibility(i: u32, p: vec3f, n: vec3f) -> f32 {
    return light_visibility_in(shadow_maps, fitted_shadow_maps, i, p, n);
}

// light_visibility against other maps of the same layout: those of a chosen set of casters
// (scene::CasterShadowMaps), or the scene's own.
fn light_visibility_in(
    cube_maps: texture_cube_array<f32>,
    fitted_maps: texture_2d_array<f32>,
    i: u32,
    p: vec3f,
    n: vec3f,
) -> f32 {
    let position = lights[i].position;
    let shadow_params = lights[i].shadow_params;
    let to_p = p - position.xyz;
    let d = length(to_p);
    var stored: f32;
    var texel_angle: f32;
    if (position.w < 0.5) {
        stored = textureSampleLevel(cube_maps, shadow_sampler, to_p, i32(i), 0.0).r;
        texel_angle = 2.0 / scene_info.shadow_size;
    } else {
        let clip = lights[i].shadow_view_proj * vec4f(p, 1.0);
        let ndc = clip.xy / clip.w;
        if (clip.w <= 0.0 || any(abs(ndc) > vec2f(1.0))) { return 1.0; }
        let uv = vec2f(0.5 * ndc.x + 0.5, 0.5 - 0.5 * ndc.y);
        stored = textureSampleLevel(fitted_maps, shadow_sampler, uv, i32(i), 0.0).r;
        texel_angle = 2.0 * shadow_params.x / scene_info.shadow_size;
        if (shadow_params.y > 0.0) {
            // Orthographic: a texel is the same width at every distance.
            texel_angle = 2.0 * shadow_params.y / (scene_info.shadow_size * d);
        }
    }
    // The slope against the light's rays: along a directional light's direction in its
    // orthographic map (the map's eye sees the point from a little aside).
    var toward_light = -to_p / d;
    if (shadow_params.y > 0.0) { toward_light = -lights[i].direction.xyz; }
    let cos_l = clamp(dot(n, toward_light), 0.05, 1.0);
    let bias = d * texel_angle * (1.5 + sqrt(1.0 - cos_l * cos_l) / cos_l) + 1e-4 * max(1.0, d);
    return select(0.0, 1.0, d - bias <= stored);
}

// Direct diffuse radiance toward the viewer with shading normal n and geometric normal ng,
// both facing the viewer: a light behind the geometric face contributes nothing, even where
// the smooth normal still faces it (the reference's rule).
fn shade_diffuse_ng(p: vec3f, n: vec3f, ng: vec3f, albedo: vec3f) -> vec3f {
    var sum = vec3f(0.0);
    for (var i = 0u; i < scene_info.light_count; i++) {
        let to_l = light_toward(i, p);
        let d2 = dot(to_l, to_l);
        let cos_l = dot(n, to_l) * inverseSqrt(d2);
        if (cos_l <= 0.0 || dot(ng, to_l) <= 0.0) { continue; }
        let intensity = light_intensity_toward(i, to_l * inverseSqrt(d2));
        sum += albedo / PI * intensity * cos_l / d2 * light_visibility(i, p, ng);
    }
    return sum;
}

// The vector from p toward light i (scene::Light::toward): to the light's position, whose
// squared length divides the intensity, or the unit vector against a directional light's
// direction (no falloff: its intensity is an irradiance).
// (Fields are read one by one, not the record whole: a copy of the record costs lavapipe a
// load of all its 12 vec4s per call, which showed in every raster pass.)
fn light_toward(i: u32, p: vec3f) -> vec3f {
    let direction = lights[i].direction;
    if (direction.w == LIGHT_DIRECTIONAL) { return -direction.xyz; }
    return lights[i].position.xyz - p;
}

// Light i's intensity toward a point seen in the unit direction l from it: a spot's cone
// falloff applied (scene::Light::emission_factor).
fn light_intensity_toward(i: u32, l: vec3f) -> vec3f {
    let direction = lights[i].direction;
    if (direction.w != LIGHT_SPOT) { return lights[i].intensity.rgb; }
    let cone = lights[i].cone;
    return lights[i].intensity.rgb * spot_falloff(dot(direction.xyz, -l), cone.x, cone.y);
}

// KHR_lights_punctual's spot falloff (scene::spot_falloff).
fn spot_falloff(cos_axis: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / max(cos_inner - cos_outer, 0.001);
    let t = clamp((cos_axis - cos_outer) * scale, 0.0, 1.0);
    return t * t;
}

// The radiance object `object`'s diffuse surface emits toward any viewer, on top of what
// shade_diffuse reflects (scene::Object::emission: it lights nothing else).
fn object_emission(object: u32) -> vec3f {
    return objects[object].emission.rgb;
}

// The same with the shading normal standing in for the geometric one.
fn shade_diffuse(p: vec3f, n: vec3f, albedo: vec3f) -> vec3f {
    return shade_diffuse_ng(p, n, n, albedo);
}

// ---------------------------------------------------------------------------------------------
// The specular half of the shading model (DESIGN.md), shared by every technique that shades a
// metal or glass surface: a metal reflects with the conductor Fresnel term of its per-channel
// n, k; glass splits into a reflected part f and a refracted part 1 - f (Fresnel of the
// dielectric interface; under total internal reflection the refracted ray does not exist and
// its share is reflected too). A technique's only job is to say what radiance arrives along
// the two directions: `specular_event` gives the directions and weights, `specular_shade`
// combines the two radiances.
// ---------------------------------------------------------------------------------------------

struct SpecularEvent {
    // The normal facing the incoming ray.
    normal: vec3f,
    // Unit mirror direction.
    reflected: vec3f,
    // xyz: unit refracted direction; w = 1 when it exists (glass without total internal
    // reflection), 0 otherwise (always 0 for metals).
    refracted: vec4f,
    // Weight of the reflected radiance: the conductor Fresnel term per channel (metal) or f
    // in every channel (glass).
    reflectance: vec3f,
    // Cosine of the incidence angle.
    cos_i: f32,
    // Relative index of refraction across the interface (glass; 1 for metals).
    eta_rel: f32,
    is_metal: bool,
    // Glass: the ray enters the object (its authored outward normal faces the ray).
    entering: bool,
};

// The specular event of a ray travelling along unit `dir` and meeting `object` at `p`, whose
// interpolated authored normal there is `authored_normal`; `origin` is the ray's origin (the
// eye, or a light for photons).
fn specular_event(object: u32, authored_normal: vec3f, p: vec3f, origin: vec3f, dir: vec3f) -> SpecularEvent {
    let o = objects[object];
    var e: SpecularEvent;
    e.normal = facing_normal(authored_normal, p, origin);
    e.cos_i = -dot(dir, e.normal);
    e.reflected = reflect_dir(dir, e.normal);
    e.is_metal = o.material.x == MATERIAL_METAL;
    e.entering = dot(normalize(authored_normal), dir) < 0.0;
    if (e.is_metal) {
        e.reflectance = fresnel_nk(e.cos_i, o.n.xyz, o.k.xyz);
        e.refracted = vec4f(0.0);
        e.eta_rel = 1.0;
    } else {
        e.eta_rel = select(1.0 / o.material.y, o.material.y, e.entering);
        e.reflectance = vec3f(fresnel_dielectric(e.cos_i, e.eta_rel));
        e.refracted = refract_dir(dir, e.normal, 1.0 / e.eta_rel);
    }
    return e;
}

// Radiance leaving the surface toward the ray's origin, given the radiance arriving along the
// reflected and (when it exists) the refracted direction.
fn specular_shade(e: SpecularEvent, reflected: vec3f, refracted: vec3f) -> vec3f {
    if (e.is_metal) {
        return e.reflectance * reflected;
    }
    let f = e.reflectance.x;
    let through = select(reflected, refracted, e.refracted.w > 0.5);
    return f * reflected + (1.0 - f) * through;
}
