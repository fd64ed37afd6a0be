// ---------------------------------------------------------------------------------------------
// The paper's line marcher (section 2.1): each photon ray of a batch is drawn as a horizontal
// line into its own row of an offscreen buffer, as many fragments long as the ray covers
// pixels on the screen; each fragment tests its sample against every LDI layer (tolerance
// test) and writes (t, layer, pixel, gap) where it finds a surface. `reduce_main` then keeps
// the first hit of each row, moved on to the nearest sample of its run (the paper's reduction,
// as a scan per row; see reduce.wgsl).
// ---------------------------------------------------------------------------------------------
#import screen_photons::ldi::{ldi, LDI_SCENE, Segment, side_of, TEST_TOLERANCE, test_sample}
#import screen_photons::photon::{Photon, photon_is_inside, photon_segment}

struct Batch {
    // First photon of the batch, rows of the buffer, width of the buffer (samples).
    first: u32,
    rows: u32,
    width: u32,
    _pad: u32,
};

@group(3) @binding(0) var<storage, read> photons: array<Photon>;
@group(3) @binding(1) var<uniform> batch: Batch;

struct LineOut {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) photon: u32,
    @location(1) @interpolate(flat) ends: vec4f,   // t0, t1, w0, w1
    @location(2) @interpolate(flat) pixels: vec4f, // p0, p1
    @location(3) @interpolate(flat) steps: u32,
};

@vertex
fn line_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) row: u32) -> LineOut {
    var out: LineOut;
    let i = batch.first + row;
    out.photon = i;
    out.position = vec4f(-2.0, -2.0, 0.5, 1.0);
    out.steps = 0u;
    if (i >= arrayLength(&photons)) { return out; }
    let p = photons[i];
    if (p.origin.w < 0.5) { return out; }
    let s = photon_segment(p);
    if (!s.visible) { return out; }
    // Row `row`, from the left edge to `steps` samples: n_f fragments at x = k + 1/2.
    let x = select(0.0, f32(s.steps), v == 1u);
    let width = f32(batch.width);
    let rows = f32(batch.rows);
    out.position = vec4f(2.0 * x / width - 1.0, 1.0 - 2.0 * (f32(row) + 0.5) / rows, 0.5, 1.0);
    out.ends = vec4f(s.t_start, s.t_end, s.w_start, s.w_end);
    out.pixels = vec4f(s.p_start, s.p_end);
    out.steps = s.steps;
    return out;
}

@fragment
fn line_fs(in: LineOut) -> @location(0) vec4f {
    let p = photons[in.photon];
    var s: Segment;
    s.origin = p.origin.xyz;
    s.dir = p.dir.xyz;
    s.t_start = in.ends.x;
    s.t_end = in.ends.y;
    s.w_start = in.ends.z;
    s.w_end = in.ends.w;
    s.p_start = in.pixels.xy;
    s.p_end = in.pixels.zw;
    s.steps = max(in.steps, 1u);
    s.visible = true;
    let k = min(u32(in.position.x), s.steps - 1u);
    let h = test_sample(LDI_SCENE, s, k, TEST_TOLERANCE, side_of(photon_is_inside(p)));
    // No discard: a fragment without a hit writes zero (t = 0 is "none"). The pixel is packed
    // as y * width + x (exact in f32 up to 2^24 pixels) to leave room for the gap.
    let pixel = f32(h.pixel.y * ldi.size.x + h.pixel.x);
    return select(vec4f(0.0), vec4f(h.t, f32(h.layer), pixel, h.gap), h.found && u32(in.position.x) < in.steps);
}
