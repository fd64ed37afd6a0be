// The transfer map's pixels into the photon buffer (photon i = pixel (i % width, i / width)).
#import gpu::prelude::oct_decode
#import screen_photons::photon::{Photon, Receiver}

// The flux of a unit weight: the light's intensity times a pixel's solid angle on its axis.
struct GatherParams {
    flux: vec4f,
};

@group(3) @binding(0) var transfer_origin: texture_2d<f32>;
@group(3) @binding(1) var transfer_dir: texture_2d<f32>;
@group(3) @binding(2) var<storage, read_write> photons: array<Photon>;
@group(3) @binding(3) var<storage, read_write> receivers: array<Receiver>;
@group(3) @binding(4) var<uniform> gather: GatherParams;

@compute @workgroup_size(64)
fn gather_main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&photons)) { return; }
    let width = textureDimensions(transfer_origin).x;
    let px = vec2u(i % width, i / width);
    // Decoded as transfer.wgsl wrote it.
    let a = textureLoad(transfer_origin, px, 0);
    let b = textureLoad(transfer_dir, px, 0);
    let weight = vec3f(abs(a.w), b.z, b.w);
    let alive = max(weight.r, max(weight.g, weight.b)) > 0.0;
    var p: Photon;
    p.origin = vec4f(a.xyz, select(0.0, 1.0, alive));
    p.dir = vec4f(oct_decode(b.xy), select(0.0, 1.0, a.w < 0.0));
    p.power = vec4f(gather.flux.rgb * weight, 0.0);
    photons[i] = p;
    receivers[i] = Receiver(vec4f(0.0), vec4f(0.0), vec4f(0.0));
}
