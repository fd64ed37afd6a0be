// The horizontal reduction of the line buffer: one workgroup per row; each invocation finds
// the first hit among its texels, then log2(64) halving steps keep the row's first.

struct Batch {
    first: u32,
    rows: u32,
    width: u32,
    _pad: u32,
};

@group(3) @binding(0) var rows_texture: texture_2d<f32>;
@group(3) @binding(1) var<storage, read_write> hits: array<vec4f>;
@group(3) @binding(2) var<uniform> batch: Batch;

const REDUCE_WIDTH: u32 = 64u;
const NONE: u32 = 0xffffffffu;
var<workgroup> first_x: array<u32, 64>;

@compute @workgroup_size(64)
fn reduce_main(@builtin(workgroup_id) wg: vec3u, @builtin(local_invocation_index) lid: u32) {
    let row = wg.x;
    var best = NONE;
    for (var x = lid; x < batch.width; x += REDUCE_WIDTH) {
        if (textureLoad(rows_texture, vec2u(x, row), 0).x > 0.0) {
            best = x;
            break;
        }
    }
    first_x[lid] = best;
    workgroupBarrier();
    for (var stride = REDUCE_WIDTH / 2u; stride > 0u; stride /= 2u) {
        if (lid < stride) {
            first_x[lid] = min(first_x[lid], first_x[lid + stride]);
        }
        workgroupBarrier();
    }
    let i = batch.first + row;
    if (lid == 0u && i < arrayLength(&hits)) {
        var h = vec4f(0.0);
        if (first_x[0] != NONE) {
            h = textureLoad(rows_texture, vec2u(first_x[0], row), 0);
        }
        hits[i] = h;
    }
}
