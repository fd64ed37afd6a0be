// ---------------------------------------------------------------------------------------------
// The exact GPU ray tracer: the CPU reference's model (truth::reference, whose module docs
// derive every formula used here) in compute shaders over the scene's BVH (raytracer::bvh) or
// the hardware's ray queries (raytracer::ray_query, with the definition RAY_QUERY), asked
// through raytracer::queries.
//
// * `eye_pass`: one thread per pixel follows the Whitted tree of its centre ray with an
//   explicit stack of pending rays (WGSL has no recursion). The tree is linear in what its
//   leaves see, so each pending ray carries the weight its radiance enters the pixel with
//   (Fresnel factors and the media's transmittance in front of it) and the throughput the
//   reference prunes by (Fresnel factors alone).
// * `photon_pass`: one thread per caustic photon, emitted in the cones of scene::emission,
//   followed through specular chains with Russian roulette on Fresnel, connected to the
//   pinhole where it lands on a diffuse surface and added to its pixel in 64-bit fixed point
//   (integer atomics: the sum does not depend on the order threads finish in).
// * `resolve_fs`: eye radiance plus the photons' into the target.
//
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::{PI, fresnel_dielectric, fresnel_nk, pcg_hash, ray_sphere, reflect_dir, refract_dir}
#import scene::medium::{EYE_CLEARANCE, Medium, henyey_greenstein, medium_clip, medium_extinction, medium_present, medium_transmittance, transmittance_of}
#import raytracer::triangles::{NO_HIT, SurfaceHit, surface_hit, texture_data}
#import raytracer::queries::{trace_any, trace_closest}

struct Params {
    // xyz: the eye; w: 1 for a pinhole, 0 for an orthographic camera.
    eye: vec4f,
    // xyz: forward; w: tan(fov_y / 2), or an orthographic view's half height.
    forward: vec4f,
    // xyz: right; w: aspect (width / height).
    right: vec4f,
    // xyz: up; w: area of one pixel (scene::Film::pixel_area).
    up: vec4f,
    view_proj: mat4x4f,
    // width, height, max_depth, 1 when caustics are traced.
    size: vec4u,
    // lights, volumes, emitters, objects.
    counts: vec4u,
    // Offsets into `tables` (vec4 units) of the lights, volumes, emitters and objects.
    offsets: vec4u,
    // total photons, seed, offset of the texture table, offset of the sRGB table.
    photons: vec4u,
    // rgb: background radiance; w: photon dispatch width in threads.
    background: vec4f,
    medium: Medium,
};

@group(0) @binding(0) var<uniform> params: Params;
// Binding 1: the traversal's structure (`bvh_nodes`, or `scene_tlas` for ray queries), declared
// by its module; bindings 2 to 4: the triangles, and the alpha cut-outs followed by the
// textures' texels (raytracer::triangles).
// Lights, volumes, emitters, objects, the texture table and the sRGB decoding table, at
// `params.offsets` (RayTracerTables in tracer.rs writes them).
@group(0) @binding(5) var<storage, read> tables: array<vec4f>;
// Every texture's RGBA8 texels, one u32 each (red in the low byte), follow the cut-out table in
// raytracer::triangles' `texture_data` (the texture table's offsets count from its start).
// Eye-pass radiance per pixel (row 0 at the top); w: the view-space depth of the pixel's
// first surface (infinity where its centre ray meets none), which hides photon beams.
@group(0) @binding(6) var<storage, read_write> radiance: array<vec4f>;
// Photon radiance per pixel: per channel a 64-bit fixed-point sum (low word, high word).
@group(0) @binding(7) var<storage, read_write> photon_sum: array<atomic<u32>>;
// Rays cast: camera, shadow, photon; photons stored.
@group(0) @binding(8) var<storage, read_write> stats: array<atomic<u32>, 4>;

const INFINITY: f32 = 3.4028235e38;
const MIN_THROUGHPUT: f32 = 1e-4;
const MAX_SHADING_CORRECTION: f32 = 10.0;
// 2^32 per unit of radiance: a quantum far below any photon's contribution at the counts the
// tracer takes (2^20 rounded a photon's share of a dim pixel by percents at 100 million photons),
// and still 2^32 units of radiance before the 64-bit sum overflows.
const FIXED_POINT_SCALE: f32 = 4294967296.0;
const TWO_32: f32 = 4294967296.0;
const PENDING_RAYS: u32 = 24u;
// Media (truth::media): steps per radius, minimum and maximum steps, transmittance cut-off.
const STEPS_PER_RADIUS: f32 = 64.0;
const MIN_STEPS: u32 = 32u;
const MAX_STEPS: u32 = 4096u;
const TRANSMITTANCE_CUTOFF: f32 = 1e-6;
const MAX_VOLUMES: u32 = 64u;
// Scattering medium (truth::scattering).
const INSCATTER_STEPS: u32 = 64u;

// ---- Scene tables ---------------------------------------------------------------------------

// kind: 0 point, 1 spot, 2 directional (scene::LightKind); direction: a spot's axis or the
// way a directional light travels; cone: a spot's cosines of its inner and outer half-angles.
struct Light { position: vec3f, kind: u32, intensity: vec3f, direction: vec3f, cone: vec2f, };

const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;

fn light(i: u32) -> Light {
    let o = params.offsets.x + 4u * i;
    let a = tables[o];
    return Light(a.xyz, u32(a.w), tables[o + 1u].xyz, tables[o + 2u].xyz, tables[o + 3u].xy);
}

// The fraction of a light's intensity it sends along w (scene::Light::emission_factor): a
// spot's cone falloff (KHR_lights_punctual's), else 1.
fn emission_factor(l: Light, w: vec3f) -> f32 {
    if (l.kind != LIGHT_SPOT) { return 1.0; }
    let scale = 1.0 / max(l.cone.x - l.cone.y, 0.001);
    let t = clamp((dot(l.direction, w) - l.cone.y) * scale, 0.0, 1.0);
    return t * t;
}

// The shadow ray from `origin` toward the light (scene::Light::shadow_ray): xyz its unit
// direction, w its length (infinite for a directional light; 0 at the light).
fn shadow_ray(l: Light, origin: vec3f) -> vec4f {
    if (l.kind == LIGHT_DIRECTIONAL) { return vec4f(-l.direction, INFINITY); }
    let seg = l.position - origin;
    let len = length(seg);
    if (len <= 0.0) { return vec4f(0.0); }
    return vec4f(seg / len, len);
}

struct Material {
    // 0 diffuse, 1 metal, 2 glass.
    kind: u32,
    albedo: vec3f,
    // Texture index, or -1.
    texture: i32,
    ior: f32,
    n: vec3f,
    k: vec3f,
    // Radiance a diffuse surface emits (scene::Object::emission).
    emission: vec3f,
};

fn material(object: u32) -> Material {
    let o = params.offsets.w + 5u * object;
    let a = tables[o];
    let m = tables[o + 1u];
    return Material(u32(m.x), a.rgb, bitcast<i32>(a.w), m.y, tables[o + 2u].xyz, tables[o + 3u].xyz, tables[o + 4u].xyz);
}

fn srgb_to_linear(v: u32) -> f32 {
    let t = tables[params.photons.w + v / 4u];
    return t[v % 4u];
}

fn texel(table: vec4u, i: i32, j: i32) -> vec3f {
    let w = i32(table.y);
    let h = i32(table.z);
    let x = ((i % w) + w) % w;
    let y = ((j % h) + h) % h;
    let c = texture_data[table.x + u32(y * w + x)];
    return vec3f(
        srgb_to_linear(c & 0xffu),
        srgb_to_linear((c >> 8u) & 0xffu),
        srgb_to_linear((c >> 16u) & 0xffu),
    );
}

fn lerp3(a: vec3f, b: vec3f, t: f32) -> vec3f {
    return a + (b - a) * t;
}

// scene::Texture::sample: bilinear between texel centres, wrapping.
fn sample_texture(index: i32, uv: vec2f) -> vec3f {
    let table = bitcast<vec4u>(tables[params.photons.z + u32(index)]);
    let x = uv.x * f32(table.y) - 0.5;
    let y = uv.y * f32(table.z) - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i = i32(x0);
    let j = i32(y0);
    let top = lerp3(texel(table, i, j), texel(table, i + 1, j), fx);
    let bottom = lerp3(texel(table, i, j + 1), texel(table, i + 1, j + 1), fx);
    return lerp3(top, bottom, fy);
}

fn albedo(m: Material, uv: vec2f) -> vec3f {
    if (m.texture < 0) { return m.albedo; }
    return m.albedo * sample_texture(m.texture, uv);
}

// ---- Surfaces and the specular split (truth::reference: Surface, scatter) -------------------

struct Surface {
    p: vec3f,
    // Normals on the side the ray came from (decided by the geometric normal).
    ng: vec3f,
    ns: vec3f,
    front: bool,
    eps: f32,
    object: u32,
    uv: vec2f,
};

fn surface(h: SurfaceHit, dir: vec3f) -> Surface {
    let front = dot(h.geometric_normal, dir) < 0.0;
    let s = select(-1.0, 1.0, front);
    return Surface(h.position, h.geometric_normal * s, h.normal * s, front,
                   1e-4 * max(length(h.position), 1.0), h.object, h.uv);
}

fn above(s: Surface) -> vec3f { return s.p + s.ng * s.eps; }
fn below(s: Surface) -> vec3f { return s.p - s.ng * s.eps; }

struct Scatter {
    // Reflected weight: per channel for metals, f in every channel for glass (1 under total
    // internal reflection).
    f: vec3f,
    reflected: vec3f,
    // w = 1 when a refracted ray exists.
    refracted: vec4f,
};

fn scatter(m: Material, s: Surface, dir: vec3f) -> Scatter {
    let cos_i = clamp(dot(-dir, s.ns), 0.0, 1.0);
    let reflected = normalize(reflect_dir(dir, s.ns));
    if (m.kind == 1u) {
        return Scatter(fresnel_nk(cos_i, m.n, m.k), reflected, vec4f(0.0));
    }
    let eta_rel = select(1.0 / m.ior, m.ior, s.front);
    let f = fresnel_dielectric(cos_i, eta_rel);
    let t = refract_dir(dir, s.ns, 1.0 / eta_rel);
    if (t.w == 0.0 || f >= 1.0) {
        return Scatter(vec3f(1.0), reflected, vec4f(0.0));
    }
    return Scatter(vec3f(f), reflected, vec4f(t.xyz, 1.0));
}

// ---- Volumes: emission-absorption (truth::media, scene::density) ----------------------------

struct Volume {
    center: vec3f,
    radius: f32,
    color: vec3f,
    density: f32,
    // falloff k, noise amplitude a, noise frequency f.
    profile: vec3f,
};

fn volume(i: u32) -> Volume {
    let o = params.offsets.y + 3u * i;
    let a = tables[o];
    let b = tables[o + 1u];
    return Volume(a.xyz, a.w, b.rgb, b.w, tables[o + 2u].xyz);
}

fn lattice_value(i: i32, j: i32, k: i32) -> f32 {
    var h = (bitcast<u32>(i) * 0x8da6b343u) ^ (bitcast<u32>(j) * 0xd8163841u)
        ^ (bitcast<u32>(k) * 0xcb1ab31fu);
    h ^= h >> 16u;
    h *= 0x85ebca6bu;
    h ^= h >> 13u;
    h *= 0xc2b2ae35u;
    h ^= h >> 16u;
    return f32(h >> 8u) * (2.0 / 16777216.0) - 1.0;
}

fn value_noise(q: vec3f) -> f32 {
    let base = floor(q);
    let f = q - base;
    let w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let i = i32(base.x);
    let j = i32(base.y);
    let k = i32(base.z);
    let x00 = mix_lin(lattice_value(i, j, k), lattice_value(i + 1, j, k), w.x);
    let x10 = mix_lin(lattice_value(i, j + 1, k), lattice_value(i + 1, j + 1, k), w.x);
    let x01 = mix_lin(lattice_value(i, j, k + 1), lattice_value(i + 1, j, k + 1), w.x);
    let x11 = mix_lin(lattice_value(i, j + 1, k + 1), lattice_value(i + 1, j + 1, k + 1), w.x);
    return mix_lin(mix_lin(x00, x10, w.y), mix_lin(x01, x11, w.y), w.z);
}

fn mix_lin(a: f32, b: f32, t: f32) -> f32 {
    return a + (b - a) * t;
}

fn density_noise(q: vec3f) -> f32 {
    let second = value_noise(2.0 * q + vec3f(17.31, 5.17, 9.73));
    return (value_noise(q) + 0.5 * second) / 1.5;
}

// DensityProfile::shape.
fn profile_shape(profile: vec3f, q: vec3f) -> f32 {
    let r2 = dot(q, q);
    if (r2 >= 1.0) { return 0.0; }
    var falloff = 1.0;
    if (profile.x > 0.0) { falloff = pow(1.0 - r2, profile.x); }
    var texture = 1.0;
    if (profile.y > 0.0) { texture = 1.0 + profile.y * density_noise(q * profile.z); }
    return max(falloff * texture, 0.0);
}

struct Segment {
    emitted: vec3f,
    transmittance: f32,
};

// Media::march: the union of the sphere intervals on [0, t_max], merged where they overlap,
// each marched with the midpoint rule (steps from its smallest radius).
fn march(o: vec3f, d: vec3f, t_max: f32) -> Segment {
    var seg = Segment(vec3f(0.0), 1.0);
    let n = min(params.counts.y, MAX_VOLUMES);
    if (n == 0u) { return seg; }
    var starts: array<f32, MAX_VOLUMES>;
    var ends: array<f32, MAX_VOLUMES>;
    var ids: array<u32, MAX_VOLUMES>;
    var count = 0u;
    for (var i = 0u; i < n; i++) {
        let v = volume(i);
        let t = ray_sphere(o, d, v.center, v.radius);
        let a = max(t.x, 0.0);
        let b = min(t.y, t_max);
        if (t.x <= t.y && a < b) {
            // Insertion sort by (start, index): indices arrive in order, so ties stay put.
            var k = count;
            while (k > 0u && starts[k - 1u] > a) {
                starts[k] = starts[k - 1u];
                ends[k] = ends[k - 1u];
                ids[k] = ids[k - 1u];
                k -= 1u;
            }
            starts[k] = a;
            ends[k] = b;
            ids[k] = i;
            count += 1u;
        }
    }
    var first = 0u;
    while (first < count) {
        // Merge the spans overlapping [starts[first], end].
        var end = ends[first];
        var min_radius = volume(ids[first]).radius;
        var last = first + 1u;
        while (last < count && starts[last] <= end) {
            end = max(end, ends[last]);
            min_radius = min(min_radius, volume(ids[last]).radius);
            last += 1u;
        }
        let start = starts[first];
        let len = end - start;
        let max_step = min_radius / STEPS_PER_RADIUS;
        let steps = clamp(u32(ceil(len / max_step)), MIN_STEPS, MAX_STEPS);
        let dt = len / f32(steps);
        for (var s = 0u; s < steps; s++) {
            let p = o + d * (start + (f32(s) + 0.5) * dt);
            var sigma = 0.0;
            var weighted = vec3f(0.0);
            for (var m = first; m < last; m++) {
                let v = volume(ids[m]);
                let x = v.density * profile_shape(v.profile, (p - v.center) / v.radius);
                sigma += x;
                weighted += x * v.color;
            }
            if (sigma > 0.0) {
                let step_t = exp(-sigma * dt);
                seg.emitted += seg.transmittance * (1.0 - step_t) * (weighted / sigma);
                seg.transmittance *= step_t;
            }
            if (seg.transmittance < TRANSMITTANCE_CUTOFF) {
                seg.transmittance = 0.0;
                return seg;
            }
        }
        first = last;
    }
    return seg;
}

// ---- The scattering medium: direct in-scattering (truth::scattering::direct_inscatter) ------

fn direct_inscatter(o: vec3f, d: vec3f, span_in: vec2f, clearance: f32, shadow_rays: ptr<function, u32>) -> vec3f {
    let m = params.medium;
    let entry = span_in.x;
    let span = vec2f(max(span_in.x, clearance), span_in.y);
    if (span.x >= span.y) { return vec3f(0.0); }
    let sigma_t = medium_extinction(m);
    let g = m.max.w;
    var sum = vec3f(0.0);
    for (var li = 0u; li < params.counts.x; li++) {
        let l = light(li);
        if (max(max(l.intensity.x, l.intensity.y), l.intensity.z) <= 0.0) { continue; }
        let along = dot(l.position - o, d);
        let foot = o + d * along;
        let dist_to_line = distance(foot, l.position);
        let directional = l.kind == LIGHT_DIRECTIONAL;
        let uniform_steps = directional
            || dist_to_line < 1e-4 * max(1e-4 * max(length(l.position), 1.0), 1.0);
        let theta_a = atan((span.x - along) / dist_to_line);
        let theta_b = atan((span.y - along) / dist_to_line);
        for (var i = 0u; i < INSCATTER_STEPS; i++) {
            let f = (f32(i) + 0.5) / f32(INSCATTER_STEPS);
            var t: f32;
            var weight: f32;
            if (uniform_steps) {
                let dt = (span.y - span.x) / f32(INSCATTER_STEPS);
                t = span.x + f * (span.y - span.x);
                let x = o + d * t - l.position;
                weight = select(dt / max(dot(x, x), 1e-12), dt, directional);
            } else {
                let theta = theta_a + f * (theta_b - theta_a);
                let dtheta = (theta_b - theta_a) / f32(INSCATTER_STEPS);
                t = along + dist_to_line * tan(theta);
                weight = dtheta / dist_to_line;
            }
            let x = o + d * t;
            let ray = shadow_ray(l, x);
            let len = ray.w;
            if (len <= 0.0) { continue; }
            let dl = ray.xyz;
            let factor = emission_factor(l, -dl);
            if (factor <= 0.0) { continue; }
            *shadow_rays += 1u;
            if (trace_any(x, dl, len)) { continue; }
            let phase = henyey_greenstein(dot(-dl, -d), g);
            let toward_light = medium_transmittance(m, x, dl, len);
            let toward_eye = transmittance_of(sigma_t, t - entry);
            sum += l.intensity * factor * m.scattering.rgb * toward_light * toward_eye * (phase * weight);
        }
    }
    return sum;
}

// ---- Direct light at a diffuse point (Tracer::direct_light) ---------------------------------

fn direct_light(s: Surface, rho: vec3f, shadow_rays: ptr<function, u32>) -> vec3f {
    let origin = above(s);
    var sum = vec3f(0.0);
    for (var li = 0u; li < params.counts.x; li++) {
        let l = light(li);
        // scene::Light::toward: a directional light comes from -direction, without falloff.
        var dl = -l.direction;
        var d2 = 1.0;
        if (l.kind != LIGHT_DIRECTIONAL) {
            let to_light = l.position - s.p;
            d2 = dot(to_light, to_light);
            if (d2 <= 0.0) { continue; }
            dl = to_light / sqrt(d2);
        }
        let factor = emission_factor(l, -dl);
        let cos_l = dot(s.ns, dl);
        if (cos_l <= 0.0 || dot(s.ng, dl) <= 0.0 || factor <= 0.0) { continue; }
        let ray = shadow_ray(l, origin);
        if (ray.w <= 0.0) { continue; }
        *shadow_rays += 1u;
        if (trace_any(origin, ray.xyz, ray.w)) { continue; }
        var through = vec3f(1.0);
        if (medium_present(params.medium)) {
            through = medium_transmittance(params.medium, origin, ray.xyz, ray.w);
        }
        sum += l.intensity * factor * through * (cos_l / d2);
    }
    return rho * (1.0 / PI) * sum;
}

// ---- Eye pass -------------------------------------------------------------------------------

struct Pending {
    origin: vec3f,
    depth: u32,
    dir: vec3f,
    // What this ray's radiance is multiplied by on its way into the pixel.
    weight: vec3f,
    // Product of the Fresnel factors along the path (the reference prunes by it).
    throughput: vec3f,
};

struct Ray {
    origin: vec3f,
    dir: vec3f,
};

// Whether the camera is orthographic (scene::Camera::orthographic): params.eye.w is 0.
fn orthographic() -> bool { return params.eye.w == 0.0; }

// Camera::ray's coordinates of pixel (x, y) across the view, along right and up: on the image
// plane at unit distance for a pinhole, on the plane through the eye for an orthographic
// camera (forward.w is then the view's half height).
fn pixel_coordinates(x: f32, y: f32) -> vec2f {
    let w = f32(params.size.x);
    let h = f32(params.size.y);
    let sx = (2.0 * x / w - 1.0) * params.forward.w * params.right.w;
    let sy = (1.0 - 2.0 * y / h) * params.forward.w;
    return vec2f(sx, sy);
}

// Camera::ray: the primary ray through pixel (x, y).
fn camera_ray(x: f32, y: f32) -> Ray {
    let s = pixel_coordinates(x, y);
    if (orthographic()) {
        return Ray(params.eye.xyz + s.x * params.right.xyz + s.y * params.up.xyz, params.forward.xyz);
    }
    return Ray(params.eye.xyz, normalize(params.forward.xyz + s.x * params.right.xyz + s.y * params.up.xyz));
}

// Camera::toward_camera: light leaving p for the camera goes along w_c for dist, to `film`
// (the eye of a pinhole, a point of an orthographic camera's plane).
struct CameraLink {
    w_c: vec3f,
    dist: f32,
    film: vec3f,
};

fn toward_camera(p: vec3f) -> CameraLink {
    let forward = params.forward.xyz;
    if (orthographic()) {
        let dist = dot(p - params.eye.xyz, forward);
        return CameraLink(-forward, dist, p - forward * dist);
    }
    let to_eye = params.eye.xyz - p;
    let dist = sqrt(dot(to_eye, to_eye));
    return CameraLink(to_eye / dist, dist, params.eye.xyz);
}

// Film::importance: one pixel's importance for light arriving at cos_camera from dist away,
// its spreading included (params.up.w: the pixel's area, Camera::film).
fn film_importance(cos_camera: f32, dist: f32) -> f32 {
    if (orthographic()) { return 1.0 / params.up.w; }
    return 1.0 / (params.up.w * cos_camera * cos_camera * cos_camera) / (dist * dist);
}

fn max3(v: vec3f) -> f32 { return max(max(v.x, v.y), v.z); }

@compute @workgroup_size(8, 8)
fn eye_pass(@builtin(global_invocation_id) gid: vec3u) {
    if (gid.x >= params.size.x || gid.y >= params.size.y) { return; }
    var stack: array<Pending, PENDING_RAYS>;
    let primary = camera_ray(f32(gid.x) + 0.5, f32(gid.y) + 0.5);
    stack[0] = Pending(primary.origin, 0u, primary.dir, vec3f(1.0), vec3f(1.0));
    var top = 1u;
    var l = vec3f(0.0);
    // View-space depth of the centre ray's first surface (photon beams hide behind it).
    var view_depth = INFINITY;
    var camera_rays = 0u;
    var shadow_rays = 0u;
    let max_depth = params.size.z;
    while (top > 0u) {
        top -= 1u;
        let r = stack[top];
        camera_rays += 1u;
        let h = trace_closest(r.origin, r.dir, INFINITY);
        let t_hit = select(INFINITY, h.t, h.triangle != NO_HIT);
        if (r.depth == 0u) {
            view_depth = t_hit * dot(r.dir, params.forward.xyz);
        }
        // The media in front of the hit: `through_media` of the reference.
        let seg = march(r.origin, r.dir, t_hit);
        var medium_t = vec3f(1.0);
        var inscatter = vec3f(0.0);
        let span = medium_clip(params.medium, r.origin, r.dir, t_hit);
        if (span.x < span.y) {
            let clearance = select(0.0, EYE_CLEARANCE, r.depth == 0u);
            inscatter = direct_inscatter(r.origin, r.dir, span, clearance, &shadow_rays);
            medium_t = transmittance_of(medium_extinction(params.medium), span.y - span.x);
        }
        l += r.weight * (inscatter + medium_t * seg.emitted);
        let w = r.weight * medium_t * seg.transmittance;
        if (h.triangle == NO_HIT) {
            l += w * params.background.rgb;
            continue;
        }
        let s = surface(surface_hit(h, r.origin, r.dir), r.dir);
        let m = material(s.object);
        if (m.kind == 0u) {
            l += w * (m.emission + direct_light(s, albedo(m, s.uv), &shadow_rays));
            continue;
        }
        if (r.depth >= max_depth) { continue; } // the chain is longer than max_depth
        let sc = scatter(m, s, r.dir);
        let tr = r.throughput * sc.f;
        if (max3(tr) >= MIN_THROUGHPUT && top < PENDING_RAYS) {
            stack[top] = Pending(above(s), r.depth + 1u, sc.reflected, w * sc.f, tr);
            top += 1u;
        }
        if (sc.refracted.w > 0.5) {
            let tt = r.throughput * (1.0 - sc.f);
            if (max3(tt) >= MIN_THROUGHPUT && top < PENDING_RAYS) {
                stack[top] = Pending(below(s), r.depth + 1u, sc.refracted.xyz, w * (1.0 - sc.f), tt);
                top += 1u;
            }
        }
    }
    radiance[gid.y * params.size.x + gid.x] = vec4f(l, view_depth);
    atomicAdd(&stats[0], camera_rays);
    atomicAdd(&stats[1], shadow_rays);
}

// ---- Photon pass ----------------------------------------------------------------------------

// A cone from a point or spot light, or a disc (radius > 0) of a directional light's parallel
// photons (scene::emission::Emitter); measure: its solid angle or area.
struct Emitter {
    axis: vec3f,
    one_minus_cos: f32,
    light: u32,
    measure: f32,
    photons: u32,
    first: u32,
    origin: vec3f,
    radius: f32,
};

fn emitter(i: u32) -> Emitter {
    let o = params.offsets.z + 3u * i;
    let a = tables[o];
    let b = tables[o + 1u];
    let c = tables[o + 2u];
    return Emitter(a.xyz, a.w, bitcast<u32>(b.x), b.y, bitcast<u32>(b.z), bitcast<u32>(b.w), c.xyz, c.w);
}

// Emitter::contains: w inside the cone, or the photon's line (from `start`) crossing the disc.
fn emitter_contains(e: Emitter, start: vec3f, w: vec3f) -> bool {
    if (e.radius > 0.0) {
        let d = start - e.origin;
        let across = d - e.axis * dot(d, e.axis);
        return dot(across, across) <= e.radius * e.radius;
    }
    return e.one_minus_cos >= 2.0 || 1.0 - dot(w, e.axis) <= e.one_minus_cos;
}

// Duff et al. 2017, "Building an orthonormal basis, revisited" (what glam's
// any_orthonormal_pair computes).
fn orthonormal_pair(n: vec3f) -> array<vec3f, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3f, 2>(
        vec3f(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3f(b, sign + n.y * n.y * a, -n.y),
    );
}

// Emitter::sample: uniform in the cone.
fn cone_sample(e: Emitter, u: f32, v: f32) -> vec3f {
    let omc = u * e.one_minus_cos;
    let cos_t = 1.0 - omc;
    let sin_t = sqrt(max(omc * (2.0 - omc), 0.0));
    let phi = 2.0 * PI * v;
    let tb = orthonormal_pair(e.axis);
    return normalize(e.axis * cos_t + (tb[0] * cos(phi) + tb[1] * sin(phi)) * sin_t);
}

// Emitter::sample on a disc: radius R sqrt(u) at angle 2 pi v.
fn disc_sample(e: Emitter, u: f32, v: f32) -> vec3f {
    let phi = 2.0 * PI * v;
    let tb = orthonormal_pair(e.axis);
    return e.origin + (tb[0] * cos(phi) + tb[1] * sin(phi)) * (e.radius * sqrt(u));
}

// PCG (O'Neill) as a stream: 24-bit uniform numbers in [0, 1).
fn next_uniform(state: ptr<function, u32>) -> f32 {
    *state = *state * 747796405u + 2891336453u;
    let w = ((*state >> ((*state >> 28u) + 4u)) ^ *state) * 277803737u;
    return f32(((w >> 22u) ^ w) >> 8u) * (1.0 / 16777216.0);
}

// Adds v to channel c of pixel p in 64-bit fixed point.
fn add_fixed(p: u32, c: u32, v: f32) {
    let q = round(v * FIXED_POINT_SCALE);
    if (!(q > 0.0) || q >= 1.8e19) { return; } // zero, NaN or beyond 64 bits: nothing to add
    let hi = floor(q / TWO_32);
    let lo = u32(q - hi * TWO_32);
    let i = 2u * (3u * p + c);
    let old = atomicAdd(&photon_sum[i], lo);
    let carry = select(0u, 1u, old + lo < old);
    if (hi > 0.0 || carry > 0u) {
        atomicAdd(&photon_sum[i + 1u], u32(hi) + carry);
    }
}

// ---- Photon beams: single scattering after specular events (truth::scattering) ------------

const NEAR: f32 = 0.01;
const BEAM_STEPS_PER_PIXEL: f32 = 2.0;
const MAX_BEAM_STEPS: u32 = 16384u;

// Pixel coordinates (continuous) of x, as Camera::project computes them; z < 0 behind the eye
// (behind the plane through an orthographic camera's eye).
fn project(x: vec3f) -> vec3f {
    let clip = params.view_proj * vec4f(x, 1.0);
    let depth = select(clip.w - 1e-6, dot(x - params.eye.xyz, params.forward.xyz), orthographic());
    if (depth <= 0.0) { return vec3f(0.0, 0.0, -1.0); }
    let ndc = clip.xyz / clip.w;
    return vec3f((ndc.x + 1.0) * 0.5 * f32(params.size.x), (1.0 - ndc.y) * 0.5 * f32(params.size.y), 1.0);
}

// BeamSplatter::splat: the beam o + s d, s in [0, length], of flux `power` at o, added to the
// pixels it is seen in (in front of their first surface). Returns the steps taken.
fn splat_beam(o: vec3f, d: vec3f, length: f32, power: vec3f) -> u32 {
    let m = params.medium;
    let inside = medium_clip(m, o, d, length);
    if (inside.x >= inside.y) { return 0u; }
    // The part in front of the eye's near plane.
    let forward = params.forward.xyz;
    let eye = params.eye.xyz;
    let z0 = dot(o - eye, forward);
    let dz = dot(d, forward);
    var a = inside.x;
    var b = inside.y;
    if (abs(dz) < 1e-12) {
        if (z0 <= NEAR) { return 0u; }
    } else {
        let s_near = (NEAR - z0) / dz;
        if (dz > 0.0) { a = max(a, s_near); } else { b = min(b, s_near); }
    }
    if (a >= b) { return 0u; }
    let pa = project(o + d * a);
    let pb = project(o + d * b);
    var pixels = f32(max(params.size.x, params.size.y));
    if (pa.z > 0.0 && pb.z > 0.0) { pixels = distance(pa.xy, pb.xy); }
    let wanted = ceil(pixels * BEAM_STEPS_PER_PIXEL);
    var steps = MAX_BEAM_STEPS;
    if (wanted < f32(MAX_BEAM_STEPS)) { steps = max(u32(wanted), 1u); }
    let ds = (b - a) / f32(steps);
    let sigma_t = medium_extinction(m);
    let g = m.max.w;
    let w = f32(params.size.x);
    let h = f32(params.size.y);
    for (var i = 0u; i < steps; i++) {
        let s = a + (f32(i) + 0.5) * ds;
        let x = o + d * s;
        let link = toward_camera(x);
        let dist = link.dist;
        if (!(dist >= EYE_CLEARANCE)) { continue; }
        let w_c = link.w_c;
        let cos_camera = dot(forward, -w_c);
        if (cos_camera <= 0.0) { continue; }
        let p = project(x);
        if (p.z < 0.0 || !(p.x >= 0.0 && p.y >= 0.0 && p.x < w && p.y < h)) { continue; }
        let pixel = min(u32(p.y), params.size.y - 1u) * params.size.x + min(u32(p.x), params.size.x - 1u);
        if (!(cos_camera * dist < radiance[pixel].w)) { continue; }
        let importance = film_importance(cos_camera, dist);
        let beam = transmittance_of(sigma_t, s - inside.x);
        let seen = medium_transmittance(m, x, w_c, dist);
        let phase = henyey_greenstein(dot(d, w_c), g);
        add_fixed_rgb(pixel, power * beam * m.scattering.rgb * seen * (phase * importance * ds));
    }
    return steps;
}

// The three channels of `v` added to pixel p.
fn add_fixed_rgb(p: u32, v: vec3f) {
    add_fixed(p, 0u, v.x);
    add_fixed(p, 1u, v.y);
    add_fixed(p, 2u, v.z);
}

// Eye::connect: the pixel a photon landed at `s` is seen in, and what it adds there.
fn connect(s: Surface, rho: vec3f, photon_dir: vec3f, power: vec3f, rays: ptr<function, u32>) -> bool {
    let link = toward_camera(s.p);
    if (!(link.dist > 0.0)) { return false; }
    let w_c = link.w_c;
    let cos_surface = dot(s.ng, w_c);
    let cos_camera = dot(params.forward.xyz, -w_c);
    if (cos_surface <= 0.0 || cos_camera <= 0.0) { return false; }
    let p = project(s.p);
    let w = f32(params.size.x);
    let h = f32(params.size.y);
    if (p.z < 0.0 || !(p.x >= 0.0 && p.y >= 0.0 && p.x < w && p.y < h)) { return false; }
    let x = min(u32(p.x), params.size.x - 1u);
    let y = min(u32(p.y), params.size.y - 1u);
    *rays += 1u;
    let origin = above(s);
    let seg = link.film - origin;
    let len = length(seg);
    if (trace_any(origin, seg / len, len)) { return false; }
    let w_i = -photon_dir;
    let cos_i_g = max(dot(s.ng, w_i), 1e-6);
    let correction = min(max(dot(s.ns, w_i), 0.0) / cos_i_g, MAX_SHADING_CORRECTION);
    let importance = film_importance(cos_camera, link.dist);
    var seen = vec3f(march(link.film, -w_c, link.dist).transmittance);
    if (medium_present(params.medium)) {
        seen *= medium_transmittance(params.medium, link.film, -w_c, link.dist);
    }
    let value = power * rho * (1.0 / PI) * (correction * cos_surface * importance) * seen;
    add_fixed_rgb(y * params.size.x + x, value);
    return true;
}

@compute @workgroup_size(64)
fn photon_pass(@builtin(global_invocation_id) gid: vec3u) {
    let index = gid.y * u32(params.background.w) + gid.x;
    if (index >= params.photons.x) { return; }
    // The cone this photon belongs to (emitters hold consecutive ranges of indices).
    var ei = 0u;
    while (ei + 1u < params.counts.z && index >= emitter(ei + 1u).first) { ei += 1u; }
    let e = emitter(ei);
    var rng = pcg_hash(index ^ pcg_hash(params.photons.y));
    let u = next_uniform(&rng);
    let v = next_uniform(&rng);
    var w = e.axis;
    var origin = e.origin;
    if (e.radius > 0.0) {
        origin = disc_sample(e, u, v);
    } else {
        w = cone_sample(e, u, v);
    }
    // Balance heuristic over the emitters of this light that could draw the photon
    // (emission::balance_density), times a spot's falloff (emission::photon_power).
    var density = f32(e.photons) / e.measure;
    for (var j = 0u; j < params.counts.z; j++) {
        let o = emitter(j);
        if (j != ei && o.light == e.light && emitter_contains(o, origin, w)) {
            density += f32(o.photons) / o.measure;
        }
    }
    let l = light(e.light);
    var power = l.intensity * emission_factor(l, w) / density;
    var dir = w;
    var rays = 0u;
    var stored = 0u;
    var bounces = 0u;
    loop {
        rays += 1u;
        let h = trace_closest(origin, dir, INFINITY);
        if (bounces >= 1u && medium_present(params.medium)) {
            splat_beam(origin, dir, select(INFINITY, h.t, h.triangle != NO_HIT), power);
        }
        if (h.triangle == NO_HIT) { break; }
        if (medium_present(params.medium)) {
            power *= medium_transmittance(params.medium, origin, dir, h.t);
        }
        let s = surface(surface_hit(h, origin, dir), dir);
        let m = material(s.object);
        if (m.kind == 0u) {
            if (bounces >= 1u && connect(s, albedo(m, s.uv), dir, power, &rays)) {
                stored += 1u;
            }
            break;
        }
        if (bounces >= params.size.z) { break; }
        bounces += 1u;
        let sc = scatter(m, s, dir);
        if (m.kind == 1u) {
            power *= sc.f;
            if (max3(power) <= 0.0) { break; }
            origin = above(s);
            dir = sc.reflected;
        } else if (sc.refracted.w > 0.5 && next_uniform(&rng) >= sc.f.x) {
            origin = below(s);
            dir = sc.refracted.xyz;
        } else {
            origin = above(s);
            dir = sc.reflected;
        }
    }
    atomicAdd(&stats[2], rays);
    atomicAdd(&stats[3], stored);
}
