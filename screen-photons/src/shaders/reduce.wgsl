// The horizontal reduction of the line buffer: the first hit of each row (the photon's first
// surface along its ray), one invocation per row scanning from the left.
//
// The paper reduces each row by log-step halving passes, as a 2005 GPU without compute shaders
// must; the result is the same texel (the leftmost with a hit). A scan that stops at the first
// hit reads no more texels than the halving reads and needs no barriers: on a software
// rasterizer, 4096 barrier-synchronised workgroups per batch cost more than the lines
// themselves.

struct Batch {
    first: u32,
    rows: u32,
    width: u32,
    _pad: u32,
};

@group(3) @binding(0) var rows_texture: texture_2d<f32>;
@group(3) @binding(1) var<storage, read_write> hits: array<vec4f>;
@group(3) @binding(2) var<uniform> batch: Batch;

@compute @workgroup_size(64)
fn reduce_main(@builtin(global_invocation_id) id: vec3u) {
    let row = id.x;
    let i = batch.first + row;
    if (row >= batch.rows || i >= arrayLength(&hits)) { return; }
    var h = vec4f(0.0);
    for (var x = 0u; x < batch.width; x++) {
        let texel = textureLoad(rows_texture, vec2u(x, row), 0);
        if (texel.x > 0.0) {
            h = texel;
            break;
        }
    }
    hits[i] = h;
}
