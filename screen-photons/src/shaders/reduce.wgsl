// The horizontal reduction of the line buffer: the first hit of each row (the photon's first
// surface along its ray), one invocation per row scanning from the left. From that hit the scan
// moves on while the next texel hits with a smaller gap, to the sample nearest the crossing
// (`march_tolerance` in ldi.wgsl and `march::march_lines` do the same; march.rs says why).
//
// The paper reduces each row to its leftmost hit by log-step halving passes, as a 2005 GPU
// without compute shaders must; this scan keeps a later texel of the same run where its gap is
// smaller (a departure: README, "Departures"). A scan that stops where the run's gap stops
// shrinking reads no more texels than the halving reads and needs no barriers: on a software
// rasterizer, 4096 barrier-synchronised workgroups per batch cost more than the lines
// themselves.
#import screen_photons::ldi::ldi

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
    // Texels: (t, layer, y * width + x, gap); t = 0 where the fragment found nothing.
    var h = vec4f(0.0);
    var x = 0u;
    for (; x < batch.width; x++) {
        h = textureLoad(rows_texture, vec2u(x, row), 0);
        if (h.x > 0.0) { break; }
    }
    for (x++; x < batch.width && h.x > 0.0; x++) {
        let next = textureLoad(rows_texture, vec2u(x, row), 0);
        if (!(next.x > 0.0) || next.w >= h.w) { break; }
        h = next;
    }
    // The hit buffer's layout: (t, layer, pixel x, pixel y); zero for none.
    let pixel = u32(h.z);
    hits[i] = select(vec4f(0.0), vec4f(h.x, h.y, f32(pixel % ldi.size.x), f32(pixel / ldi.size.x)), h.x > 0.0);
}
