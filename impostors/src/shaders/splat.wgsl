// Adds each photon of the caustic map into the accumulation grid (6 faces x grid^2 texels x
// RGB, fixed point) at the texel of its landing point's direction from the reference point.
// Imports gpu::prelude.
#import gpu::prelude::cube_dir_to_face_uv

struct SplatParams {
    reference: vec4f,
    grid: u32,
    scale: f32,
    size: u32,
    _pad: u32,
};

@group(0) @binding(0) var landing_map: texture_2d<f32>;
@group(0) @binding(1) var power_map: texture_2d<f32>;
@group(0) @binding(2) var<storage, read_write> grid_data: array<atomic<u32>>;
@group(0) @binding(3) var<uniform> splat: SplatParams;

@compute @workgroup_size(8, 8)
fn splat_main(@builtin(global_invocation_id) g: vec3u) {
    if (g.x >= splat.size || g.y >= splat.size) { return; }
    let landing = textureLoad(landing_map, vec2i(g.xy), 0);
    if (landing.w < 0.5) { return; }
    let d = landing.xyz - splat.reference.xyz;
    if (dot(d, d) < 1e-12) { return; }
    let fuv = cube_dir_to_face_uv(d);
    let n = splat.grid;
    let i = min(u32(fuv.y * f32(n)), n - 1u);
    let j = min(u32(fuv.z * f32(n)), n - 1u);
    let base = 3u * ((u32(fuv.x) * n + j) * n + i);
    let power = textureLoad(power_map, vec2i(g.xy), 0).rgb * splat.scale;
    atomicAdd(&grid_data[base], u32(power.r + 0.5));
    atomicAdd(&grid_data[base + 1u], u32(power.g + 0.5));
    atomicAdd(&grid_data[base + 2u], u32(power.b + 0.5));
}
