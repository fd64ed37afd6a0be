// Caustic textures on the GPU (Hu and Qin 2006, section 3.2, without the paper's read-back to
// the CPU): `scatter` adds each photon's power to its rectangle texel with atomics (fixed
// point, `unit` watts per count), `filter` applies the paper's filter
//   c(u, v) = s sum_{i,j=-k..k} p(u+i, v+j) sqrt(1 + 2k^2 - (i^2 + j^2))
// normalized by the sum of its weights (so that s = 1 keeps the photons' power), and turns
// power per texel into irradiance (W/m^2) with the texel's area on its rectangle. The Rust
// twin is `src/caustics.rs`.

struct CausticParams {
    // Side of each caustic texture.
    resolution: u32,
    // Texture array layers (rectangles).
    layers: u32,
    // Filter half size k.
    k: u32,
    // Side of the photon buffer.
    photon_size: u32,
    // Watts per fixed-point count.
    unit: f32,
    // The filter's scale s.
    scale: f32,
    _a: f32,
    _b: f32,
};

@group(0) @binding(0) var<uniform> cp: CausticParams;
@group(0) @binding(1) var photon_hit: texture_2d<f32>;
@group(0) @binding(2) var photon_power: texture_2d<f32>;
// [layer][row][column][rgb] fixed-point power.
@group(0) @binding(3) var<storage, read_write> counts: array<atomic<u32>>;
// [layer][row][column] irradiance (rgb, 0).
@group(0) @binding(4) var<storage, read_write> caustic: array<vec4f>;
// Area of one texel of each layer's rectangle (m^2).
@group(0) @binding(5) var<storage, read> texel_areas: array<f32>;

@compute @workgroup_size(8, 8)
fn scatter(@builtin(global_invocation_id) g: vec3u) {
    if (g.x >= cp.photon_size || g.y >= cp.photon_size) { return; }
    let hit = textureLoad(photon_hit, vec2i(g.xy), 0);
    if (hit.z < 0.5) { return; }
    let layer = u32(hit.z - 0.5);
    let res = f32(cp.resolution);
    let texel = vec2u(min(floor(hit.xy * res), vec2f(res - 1.0)));
    let base = ((layer * cp.resolution + texel.y) * cp.resolution + texel.x) * 3u;
    let p = textureLoad(photon_power, vec2i(g.xy), 0).rgb / cp.unit;
    atomicAdd(&counts[base], u32(round(p.r)));
    atomicAdd(&counts[base + 1u], u32(round(p.g)));
    atomicAdd(&counts[base + 2u], u32(round(p.b)));
}

fn filter_weight(i: i32, j: i32, k: i32) -> f32 {
    return sqrt(f32(1 + 2 * k * k - (i * i + j * j)));
}

@compute @workgroup_size(8, 8)
fn filter_caustics(@builtin(global_invocation_id) g: vec3u) {
    if (g.x >= cp.resolution || g.y >= cp.resolution || g.z >= cp.layers) { return; }
    let k = i32(cp.k);
    let res = i32(cp.resolution);
    var sum = vec3f(0.0);
    var weights = 0.0;
    for (var j = -k; j <= k; j++) {
        for (var i = -k; i <= k; i++) {
            let w = filter_weight(i, j, k);
            weights += w;
            let x = i32(g.x) + i;
            let y = i32(g.y) + j;
            if (x < 0 || y < 0 || x >= res || y >= res) { continue; }
            let base = ((g.z * cp.resolution + u32(y)) * cp.resolution + u32(x)) * 3u;
            sum += w * vec3f(f32(atomicLoad(&counts[base])), f32(atomicLoad(&counts[base + 1u])),
                             f32(atomicLoad(&counts[base + 2u])));
        }
    }
    let power = cp.scale * sum / weights * cp.unit;
    let area = texel_areas[g.z];
    caustic[(g.z * cp.resolution + g.y) * cp.resolution + g.x] =
        vec4f(select(vec3f(0.0), power / area, area > 0.0), 0.0);
}
