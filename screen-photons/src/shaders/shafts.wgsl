// ---------------------------------------------------------------------------------------------
// God rays (section 3.2): the photon beams of the march drawn as bands into the in-scattering
// buffer, then blurred by a separable Gaussian (composite.wgsl blends them over the image).
// The bands' arithmetic is screen_photons::beam's (beam.wgsl), given this pass's view and the
// scene's medium.
// ---------------------------------------------------------------------------------------------
#import scene::shading::scene_medium
#import screen_photons::beam::{BAND_HALF_WIDTH, Beam, ShaftView, beam_band, beam_fragment}
#import screen_photons::photon::surface_distance
#import gpu::fullscreen::FullscreenOut

@group(3) @binding(0) var<storage, read> beams: array<Beam>;
@group(3) @binding(1) var<uniform> shaft: ShaftView;
@group(3) @binding(2) var shafts_in: texture_2d<f32>;

struct BandOut {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) beam: u32,
};

// A band: the projected segment widened by BAND_HALF_WIDTH pixels along the minor axis.
@vertex
fn band_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> BandOut {
    var out: BandOut;
    out.beam = i;
    let band = beam_band(shaft, scene_medium(), beams[i]);
    let corner = array<vec2f, 6>(
        vec2f(0.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
        vec2f(0.0, -1.0), vec2f(1.0, 1.0), vec2f(0.0, 1.0),
    )[v];
    let across = select(vec2f(1.0, 0.0), vec2f(0.0, 1.0), band.x_major) * BAND_HALF_WIDTH;
    let p = mix(band.p_start, band.p_end, corner.x) + across * corner.y;
    let size = vec2f(shaft.size.xy);
    out.position = select(
        vec4f(2.0, 2.0, 0.0, 1.0),
        vec4f(2.0 * p.x / size.x - 1.0, 1.0 - 2.0 * p.y / size.y, 0.0, 1.0),
        band.ok,
    );
    return out;
}

@fragment
fn band_fs(in: BandOut) -> @location(0) vec4f {
    let b = beams[in.beam];
    let m = scene_medium();
    let band = beam_band(shaft, m, b);
    let xy = vec2u(in.position.xy);
    let l = beam_fragment(shaft, m, b, band, in.position.xy, surface_distance(xy.x, xy.y));
    return vec4f(l, 0.0);
}

// One direction of the separable Gaussian blur (sigma = shaft.forward.w pixels, 3 sigma, at
// most 64 pixels), normalised over the taps inside the image (a uniform image stays uniform
// up to its edges, which a fixed normalisation would darken).
@fragment
fn blur_fs(in: FullscreenOut) -> @location(0) vec4f {
    let sigma = shaft.forward.w;
    let xy = vec2i(in.position.xy);
    let size = vec2i(shaft.size.xy);
    let step = select(vec2i(1, 0), vec2i(0, 1), shaft.size.w == 1u);
    let radius = min(i32(ceil(3.0 * sigma)), 64);
    var sum = vec3f(0.0);
    var weights = 0.0;
    for (var k = -radius; k <= radius; k++) {
        let w = exp(-0.5 * f32(k * k) / max(sigma * sigma, 1e-6));
        let q = xy + step * k;
        let inside = all(q >= vec2i(0)) && all(q < size);
        weights += select(0.0, w, inside);
        sum += select(0.0, w, inside) * textureLoad(shafts_in, vec2u(clamp(q, vec2i(0), size - 1)), 0).rgb;
    }
    return vec4f(sum / weights, 0.0);
}
