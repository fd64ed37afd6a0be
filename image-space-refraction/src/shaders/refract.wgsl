// Image-space refraction through two interfaces (Hu and Qin 2006, section 2.1) and its
// baselines: the module image_space_refraction::refract (its bindings at @group(2) and the
// refractor's shading), whose entry points are refract_passes.wgsl's and photon.wgsl's. The
// two-interface searches are image_space_refraction::search's, given the front and back
// buffers bound here.
//
// Each frame the refractor's front- and back-facing surfaces are drawn from the eye into two
// buffers (`front_buffer_fs`, `back_buffer_fs`: outward normal, view depth): nothing is
// precomputed, so a deforming refractor works. Then each pixel of a specular object splits at
// its visible surface P1 (specular_event) and follows the refracted ray T1:
//   VARIANT_ONE_INTERFACE: T1 looks the environment up (no second interface);
//   VARIANT_WYMAN:         P2 = P1 + d T1, d interpolated between d_V and the per-vertex d_N
//                          (the method the paper improves), N2 from the back buffer;
//   VARIANT_HU_QIN:        the side P2 lies on (silhouette search + angle test, or back side
//                          first), d_T iterated on that side's depth buffer, N2 from its normals;
//   VARIANT_THICKNESS:     the engine's screen-space refraction (HDRP's refraction models): the
//                          sphere model refracts into and out of a sphere of diameter
//                          `thickness` tangent at P1; the box model runs T1 through a slab of
//                          that thickness and leaves along the view ray. The ray then goes to a
//                          plane at the opaque depth behind the pixel, and the opaque scene's
//                          colour is read where that point projects.
// The exit ray T2 (or the reflected ray R) takes the radiance `outgoing_radiance(origin, dir)`
// gives: the environment map (or the room probe, box-projected), or with nearby geometry its
// rectangle impostors first (image_space_refraction::nearby_radiance overrides it).
#define_import_path image_space_refraction::refract

#import gpu::prelude::{box_project, refract_dir}
#import scene::shading::{SceneVertexOut, SpecularEvent, camera, geometric_facing_normal, objects}
#import image_space_refraction::search::{EyeParams, eye_project, Iteration, Exit, hu_qin_exit, wyman_exit, exit_direction}

struct RefractParams {
    variant: u32,
    strategy: u32,
    max_iterations: u32,
    // PROXY_SPHERE or PROXY_BOX.
    proxy: u32,
    tolerance: f32,
    initial_step: f32,
    // The thickness proxy's sphere diameter or slab thickness (m).
    thickness: f32,
    // 1: each photon leaves from a random point of its photon-buffer pixel (photon.wgsl).
    photon_jitter: u32,
    // The room probe's centre (w = 1: the environment map is that probe, looked up
    // box-projected against box_min..box_max).
    probe: vec4f,
    box_min: vec4f,
    box_max: vec4f,
};

@group(2) @binding(0) var env_map: texture_cube<f32>;
@group(2) @binding(1) var env_sampler: sampler;
@group(2) @binding(2) var<uniform> params: RefractParams;
@group(2) @binding(3) var<uniform> eye_params: EyeParams;
@group(2) @binding(4) var front_buffer: texture_2d<f32>;
@group(2) @binding(5) var back_buffer: texture_2d<f32>;
// The opaque scene drawn before the refractors (rgb radiance, a eye distance): what the
// thickness proxy samples.
@group(2) @binding(6) var scene_color: texture_2d<f32>;
// Wyman's d_N: the refractor's thickness along its inward normal at each vertex of the scene's
// vertex buffer (0 for other objects), computed once in prepare.
@group(2) @binding(7) var<storage, read> normal_thickness: array<f32>;

const VARIANT_ONE_INTERFACE: u32 = 0u;
const VARIANT_WYMAN: u32 = 1u;
const VARIANT_HU_QIN: u32 = 2u;
const VARIANT_THICKNESS: u32 = 3u;
const PROXY_SPHERE: u32 = 0u;
const PROXY_BOX: u32 = 1u;
// Exit rays start this far outside the surface they leave (metres).
const SURFACE_OFFSET: f32 = 1e-4;

struct RefractorOut {
    @invariant @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) uv: vec2f,
    @location(3) @interpolate(flat) object: u32,
    @location(4) d_n: f32,
};

// ---- front and back buffers -----------------------------------------------------------------

// Outward normal and view depth of a fragment on the wanted side; the side is the authored
// normal against the geometric normal turned to the eye (robust to smooth normals at the
// silhouette). View depth is clip w (= distance along the camera's forward axis).
fn buffer_fragment(in: SceneVertexOut, want_front: bool) -> vec4f {
    let eye = camera.eye.xyz;
    let n = normalize(in.normal);
    let front = dot(n, geometric_facing_normal(in.world, eye)) > 0.0;
    if (front != want_front) { discard; }
    return vec4f(n, (camera.view_proj * vec4f(in.world, 1.0)).w);
}

// ---- the refractor --------------------------------------------------------------------------

fn env_lookup(dir: vec3f) -> vec3f {
    return textureSampleLevel(env_map, env_sampler, dir, 0.0).rgb;
}

virtual fn outgoing_radiance(origin: vec3f, dir: vec3f) -> vec3f {
    // Radiance along a ray leaving the refractor, without nearby geometry: the environment
    // map in the ray's direction (the paper's distant environment), or the room probe where
    // the ray leaves its proxy box (the engine's parallax-corrected lookup).
    if (params.probe.w > 0.5) {
        let l = box_project(origin, dir, params.probe.xyz, params.box_min.xyz, params.box_max.xyz);
        return env_lookup(l.xyz);
    }
    return env_lookup(dir);
}

// HDRP's RefractionModelSphere / RefractionModelBox, then its EstimateRaycast: see the header.
// n1 faces the eye; ior is the object's.
fn thickness_proxy(pixel: vec2f, p1: vec3f, n1: vec3f, t1: vec3f, v: vec3f, ior: f32) -> vec3f {
    let eye = camera.eye.xyz;
    var p_out = p1;
    var dir = v;
    if (params.proxy == PROXY_BOX) {
        p_out = p1 + t1 * (params.thickness / max(dot(t1, -n1), 1e-5));
    } else {
        // The tangent sphere's centre, the chord through it, the refraction out of it.
        let c = p1 - n1 * (0.5 * params.thickness);
        p_out = p1 + t1 * (-dot(n1, t1) * params.thickness);
        let to_centre = c - p_out;
        let len = length(to_centre);
        dir = t1;
        if (len > 1e-6) {
            let out = refract_dir(t1, to_centre / len, ior);
            dir = select(t1, out.xyz, out.w > 0.5);
        }
    }
    let opaque = textureLoad(scene_color, vec2i(floor(pixel)), 0).a;
    let along = dot(v, p_out - eye);
    let denom = dot(v, dir);
    if (denom <= 1e-4) { return outgoing_radiance(p_out, dir); }
    let hit = p_out + dir * (max(opaque - along, 0.0) / denom);
    let q = eye_project(eye_params, hit);
    if (q.z <= 0.0 || q.x < 0.0 || q.y < 0.0 || q.x >= eye_params.size.x || q.y >= eye_params.size.y) {
        return outgoing_radiance(p_out, dir);
    }
    return textureLoad(scene_color, vec2i(floor(q.xy)), 0).rgb;
}

// Radiance arriving at the eye along the refracted ray T1 entering at p1.
fn through_refractor(in: RefractorOut, e: SpecularEvent, v: vec3f) -> vec3f {
    let t1 = e.refracted.xyz;
    let p1 = in.world;
    let ior = objects[in.object].material.y;
    if (params.variant == VARIANT_ONE_INTERFACE) {
        return outgoing_radiance(p1, t1);
    }
    if (params.variant == VARIANT_THICKNESS) {
        return thickness_proxy(in.clip.xy, p1, e.normal, t1, v, ior);
    }
    var exit: Exit;
    if (params.variant == VARIANT_WYMAN) {
        exit = wyman_exit(front_buffer, back_buffer, eye_params, p1, v, e.normal, t1, in.d_n);
    } else {
        let it = Iteration(params.tolerance, params.max_iterations, params.initial_step);
        exit = hu_qin_exit(front_buffer, back_buffer, eye_params, p1, v, t1, params.strategy, it);
    }
    let t2 = exit_direction(exit, t1, ior);
    // Leaving (w = 1) the ray starts just outside; totally reflected (w = 0) it would stay
    // inside: its radiance is approximated by the environment in that direction.
    let n = normalize(exit.normal);
    let outward = select(-n, n, dot(n, t1) > 0.0);
    let origin = exit.point + outward * select(-SURFACE_OFFSET, SURFACE_OFFSET, t2.w > 0.5);
    return outgoing_radiance(origin, t2.xyz);
}

