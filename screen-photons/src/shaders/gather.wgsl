// The transfer map's pixels into the photon buffer (photon i = pixel (i % width, i / width)).

@group(3) @binding(0) var transfer_origin: texture_2d<f32>;
@group(3) @binding(1) var transfer_dir: texture_2d<f32>;
@group(3) @binding(2) var transfer_power: texture_2d<f32>;
@group(3) @binding(3) var<storage, read_write> photons: array<Photon>;
@group(3) @binding(4) var<storage, read_write> receivers: array<Receiver>;

@compute @workgroup_size(64)
fn gather_main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&photons)) { return; }
    let width = textureDimensions(transfer_origin).x;
    let px = vec2u(i % width, i / width);
    var p: Photon;
    p.origin = textureLoad(transfer_origin, px, 0);
    p.dir = textureLoad(transfer_dir, px, 0);
    p.power = textureLoad(transfer_power, px, 0);
    photons[i] = p;
    receivers[i] = Receiver(vec4f(0.0), vec4f(0.0), vec4f(0.0));
}
