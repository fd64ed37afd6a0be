// ---------------------------------------------------------------------------------------------
// Froxel volumetric fog (Wronski 2014, Hillaire 2015), the engine counterpart of god rays: a
// grid of `froxel_size`-pixel tiles by exponential depth slices. In the engine baseline
// (`froxel-fog`) light reaches a froxel straight from the lights through shadow maps in which
// transparent surfaces cast no shadow, as engines draw them; each frame samples every froxel
// at a jittered point (Halton) and blends it with the last frame's grid reprojected to it
// (an exponential moving average). The hybrid (`froxel-fog-photons`) uses the scene's
// shadow maps and adds the light through the specular surfaces from a caustic map: where
// the photons landed, seen from the first light (flux and mean direction per texel). The
// grid is integrated front to back per tile and looked up per pixel at its surface's
// distance. `src/shafts.rs` (`Slices`, `integrate_tile`) is the CPU model of the slicing and
// the integration, unit-tested there; this pass is checked as a whole by the shafts' energy
// against the reference (tests/diagnostics.rs).
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::ray_box
#import scene::shading::{light_visibility_in, lights, scene_info, scene_medium}
#import scene::medium::{henyey_greenstein, medium_clip, medium_extinction, medium_present, medium_transmittance, transmittance_of}
#import screen_photons::ldi::ldi
#import screen_photons::photon::surface_distance
#import screen_photons::beam::Beam
#import gpu::fullscreen::FullscreenOut

struct FroxelParams {
    // The caustic map's light view (world to clip).
    light_view_proj: mat4x4f,
    // xyz: the light; w: a caustic-map texel's area on the image plane at unit distance.
    light: vec4f,
    // xyz: the light view's axis; w: 1 when the caustic map holds photons.
    axis: vec4f,
    // Tiles x, tiles y, slices, froxel size (pixels).
    grid: vec4u,
    // near, far of the slices; image width, height.
    slices: vec4f,
    // The last frame's view (world to clip), eye (w: 1 when there is a last frame) and
    // slices (near, far): where this frame's froxels were in its grid.
    prev_view_proj: mat4x4f,
    prev_eye: vec4f,
    prev_slices: vec4f,
    // xyz: the sample's position in its froxel (across, down, depth; 0.5 the centre);
    // w: its weight against the history (1: no history).
    temporal: vec4f,
};

@group(3) @binding(0) var<uniform> fog: FroxelParams;
@group(3) @binding(1) var<storage, read> beams: array<Beam>;
@group(3) @binding(2) var caustic_flux: texture_2d<f32>;
@group(3) @binding(3) var caustic_dir: texture_2d<f32>;
@group(3) @binding(4) var froxels_in: texture_3d<f32>;
@group(3) @binding(5) var froxels_out: texture_storage_3d<rgba32float, write>;
// The last frame's in-scattering grid.
@group(3) @binding(6) var froxels_history: texture_3d<f32>;
// The lights' visibility: the engine's shadow maps, or the scene's own (the hybrid).
@group(3) @binding(7) var fog_cube_shadows: texture_cube_array<f32>;
@group(3) @binding(8) var fog_fitted_shadows: texture_2d_array<f32>;

fn slice_boundary(k: f32) -> f32 {
    return fog.slices.x * pow(fog.slices.y / fog.slices.x, k / f32(fog.grid.z));
}

fn slice_index_of(d: f32) -> f32 {
    let k = log(max(d, fog.slices.x) / fog.slices.x) / log(fog.slices.y / fog.slices.x);
    return clamp(k * f32(fog.grid.z), 0.0, f32(fog.grid.z));
}

// The eye's ray through the image point `pixel` (pixels, row 0 at the top).
fn view_ray(pixel: vec2f) -> vec3f {
    let size = fog.slices.zw;
    let ndc = vec2f(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
    let far = ldi.inv_view_proj * vec4f(ndc, 1.0, 1.0);
    return normalize(far.xyz / far.w - ldi.eye.xyz);
}

fn tile_ray(tile: vec2u) -> vec3f {
    let size = fog.slices.zw;
    let centre = min((vec2f(tile) + 0.5) * f32(fog.grid.w), size - 0.5);
    return view_ray(centre);
}

// The caustic map: every photon's last beam adds its flux (at the beam's start) and direction
// at the texel of its end: where it landed on a diffuse surface, or, for a photon the view
// lost, where it leaves the scene's box (an engine's caustic map, made in light space, does
// not depend on the view). One point per beam.
struct MapOut {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) beam: u32,
};

@vertex
fn caustic_map_vs(@builtin(vertex_index) i: u32) -> MapOut {
    var out: MapOut;
    out.beam = i;
    out.position = vec4f(2.0, 2.0, 0.0, 1.0);
    let b = beams[i];
    if (b.origin.w < 0.5 || b.power.w < 0.5) { return out; }  // no beam, or not the last
    let end = b.origin.xyz + b.dir.xyz * b.dir.w;
    let c = fog.light_view_proj * vec4f(end, 1.0);
    if (c.w <= 0.0) { return out; }
    out.position = vec4f(c.xy / c.w, 0.5, 1.0);
    return out;
}

struct MapTexels {
    @location(0) flux: vec4f,
    @location(1) dir: vec4f,
};

@fragment
fn caustic_map_fs(in: MapOut) -> MapTexels {
    let b = beams[in.beam];
    let weight = dot(b.power.rgb, vec3f(1.0 / 3.0));
    return MapTexels(vec4f(b.power.rgb, 1.0), vec4f(b.dir.xyz * weight, weight));
}

// Bilinear read of a caustic map at uv (texel centres at (i + 0.5) / size).
fn caustic_lookup(map: texture_2d<f32>, uv: vec2f) -> vec4f {
    let size = vec2f(textureDimensions(map));
    let q = uv * size - 0.5;
    let i = floor(q);
    let f = q - i;
    var sum = vec4f(0.0);
    for (var k = 0u; k < 4u; k++) {
        let o = vec2f(f32(k & 1u), f32(k >> 1u));
        let t = i + o;
        let w = mix(1.0 - f, f, o);
        if (all(t >= vec2f(0.0)) && all(t < size)) {
            sum += w.x * w.y * textureLoad(map, vec2u(t), 0);
        }
    }
    return sum;
}

// The light a point p of the medium scatters toward the eye per metre (direction -view).
fn froxel_inscatter(p: vec3f, view: vec3f) -> vec3f {
    let m = scene_medium();
    if (!medium_present(m) || any(p < m.min.xyz) || any(p > m.max.xyz)) { return vec3f(0.0); }
    let g = m.max.w;
    var sum = vec3f(0.0);
    // Straight from the lights, through the shadow maps.
    for (var i = 0u; i < scene_info.light_count; i++) {
        let to_l = lights[i].position.xyz - p;
        let d = length(to_l);
        let l = to_l / d;
        let v = light_visibility_in(fog_cube_shadows, fog_fitted_shadows, i, p, l);
        if (v <= 0.0) { continue; }
        sum += lights[i].intensity.rgb / (d * d) * v * henyey_greenstein(dot(-l, -view), g)
            * medium_transmittance(m, p, l, d);
    }
    // Through the specular surfaces: the caustic map's irradiance, perpendicular to the
    // photons' mean direction, attenuated from where that direction enters the medium.
    if (fog.axis.w > 0.5) {
        let c = fog.light_view_proj * vec4f(p, 1.0);
        if (c.w > 0.0 && all(abs(c.xy / c.w) < vec2f(1.0))) {
            let uv = vec2f(0.5 + 0.5 * c.x / c.w, 0.5 - 0.5 * c.y / c.w);
            let flux = caustic_lookup(caustic_flux, uv);
            let dir_sum = caustic_lookup(caustic_dir, uv);
            if (flux.w > 0.0 && dir_sum.w > 0.0) {
                let dir = normalize(dir_sum.xyz);
                let to_p = p - fog.light.xyz;
                let r = length(to_p);
                let cos_axis = dot(to_p / r, fog.axis.xyz);
                let texel_solid_angle = fog.light.w * cos_axis * cos_axis * cos_axis;
                let irradiance = flux.rgb / (texel_solid_angle * r * r);
                let back = ray_box(p, -dir, m.min.xyz, m.max.xyz).y;
                sum += irradiance * henyey_greenstein(dot(dir, -view), g)
                    * transmittance_of(medium_extinction(m), max(back, 0.0));
            }
        }
    }
    return sum * m.scattering.rgb;
}

@compute @workgroup_size(4, 4, 4)
fn froxel_scatter_main(@builtin(global_invocation_id) g: vec3u) {
    if (any(g >= fog.grid.xyz)) { return; }
    let jitter = fog.temporal.xyz;
    let size = fog.slices.zw;
    let dir = view_ray(min((vec2f(g.xy) + jitter.xy) * f32(fog.grid.w), size - 0.5));
    // A point of the slice's part inside the medium (the integration credits that part
    // alone), else of the slice: its centre, or the jittered point of this frame.
    let whole = medium_clip(scene_medium(), ldi.eye.xyz, dir, 1e30);
    let d0 = slice_boundary(f32(g.z));
    let d1 = slice_boundary(f32(g.z) + 1.0);
    let a = max(d0, whole.x);
    let b = min(d1, whole.y);
    let inside = b > a;
    let d = mix(select(d0, a, inside), select(d1, b, inside), jitter.z);
    var s = froxel_inscatter(ldi.eye.xyz + dir * d, dir);
    let blend = fog.temporal.w;
    if (blend < 1.0 && fog.prev_eye.w > 0.5) {
        // The froxel's centre in slice space (the slices are exponential, as history_at reads).
        let centre = ldi.eye.xyz + tile_ray(g.xy) * slice_boundary(f32(g.z) + 0.5);
        let h = history_at(centre);
        if (h.w > 0.0) {
            s = mix(h.rgb, s, blend);
        }
    }
    textureStore(froxels_out, g, vec4f(s, 1.0));
}

// The last frame's grid at world point p (trilinear; w = 0 where p was outside it).
fn history_at(p: vec3f) -> vec4f {
    let c = fog.prev_view_proj * vec4f(p, 1.0);
    if (c.w <= 0.0) { return vec4f(0.0); }
    let pixel = vec2f(0.5 + 0.5 * c.x / c.w, 0.5 - 0.5 * c.y / c.w) * fog.slices.zw;
    let near = fog.prev_slices.x;
    let far = fog.prev_slices.y;
    let d = distance(p, fog.prev_eye.xyz);
    let k = log(max(d, near) / near) / log(far / near) * f32(fog.grid.z);
    // Froxel coordinates with cell centres at integers.
    let q = vec3f(pixel / f32(fog.grid.w), k) - 0.5;
    let top = vec3f(fog.grid.xyz) - 0.5;
    if (any(q < vec3f(-0.5)) || any(q > top) || d < near) { return vec4f(0.0); }
    let i = floor(q);
    let f = q - i;
    var sum = vec3f(0.0);
    for (var corner = 0u; corner < 8u; corner++) {
        let o = vec3f(f32(corner & 1u), f32((corner >> 1u) & 1u), f32(corner >> 2u));
        let t = clamp(vec3i(i + o), vec3i(0), vec3i(fog.grid.xyz) - 1);
        let w = mix(1.0 - f, f, o);
        sum += w.x * w.y * w.z * textureLoad(froxels_history, vec3u(t), 0).rgb;
    }
    return vec4f(sum, 1.0);
}

// Front to back over one tile's slices: slice k stores what is scattered toward the eye from
// `near` to its far boundary (Hillaire's S (1 - T) / sigma_t per slice, over its part inside
// the medium, times the transmittance from the eye).
@compute @workgroup_size(8, 8, 1)
fn froxel_integrate_main(@builtin(global_invocation_id) g: vec3u) {
    if (any(g.xy >= fog.grid.xy)) { return; }
    let m = scene_medium();
    let sigma_t = medium_extinction(m);
    let dir = tile_ray(g.xy);
    let whole = medium_clip(m, ldi.eye.xyz, dir, 1e30);
    var sum = vec3f(0.0);
    for (var k = 0u; k < fog.grid.z; k++) {
        let d0 = slice_boundary(f32(k));
        let d1 = slice_boundary(f32(k) + 1.0);
        let a = max(d0, whole.x);
        let b = min(d1, whole.y);
        if (b > a) {
            let s = textureLoad(froxels_in, vec3u(g.xy, k), 0).rgb;
            sum += s * transmittance_of(sigma_t, a - whole.x) * slice_integral(sigma_t, b - a);
        }
        textureStore(froxels_out, vec3u(g.xy, k), vec4f(sum, 1.0));
    }
}

fn slice_integral(sigma_t: vec3f, len: f32) -> vec3f {
    let small = sigma_t * len < vec3f(1e-6);
    return select((1.0 - exp(-sigma_t * len)) / max(sigma_t, vec3f(1e-30)), vec3f(len), small);
}

// The integrated grid at tile column `tile` (clamped), boundary `k` (0: nothing yet).
fn froxel_boundary(tile: vec2i, k: u32) -> vec3f {
    if (k == 0u) { return vec3f(0.0); }
    let t = clamp(tile, vec2i(0), vec2i(fog.grid.xy) - 1);
    return textureLoad(froxels_in, vec3u(vec2u(t), k - 1u), 0).rgb;
}

// Per pixel: the in-scattering in front of its first surface, trilinear in the grid.
@fragment
fn froxel_lookup_fs(in: FullscreenOut) -> @location(0) vec4f {
    let xy = vec2u(in.position.xy);
    let j = slice_index_of(surface_distance(xy.x, xy.y));
    let k0 = u32(floor(j));
    let k1 = min(k0 + 1u, fog.grid.z);
    let fz = j - f32(k0);
    let q = in.position.xy / f32(fog.grid.w) - 0.5;
    let i = vec2i(floor(q));
    let f = q - floor(q);
    var sum = vec3f(0.0);
    for (var c = 0u; c < 4u; c++) {
        let o = vec2i(i32(c & 1u), i32(c >> 1u));
        let w = mix(1.0 - f, f, vec2f(o));
        let v = mix(froxel_boundary(i + o, k0), froxel_boundary(i + o, k1), fz);
        sum += w.x * w.y * v;
    }
    return vec4f(sum, 0.0);
}
