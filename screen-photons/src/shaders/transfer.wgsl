// ---------------------------------------------------------------------------------------------
// The transfer map (section 2): every object drawn from the light into a photon grid; a pixel
// whose nearest surface is specular is one photon, refracted (the transmitted share 1 - F) or
// reflected (metal, weighted by its Fresnel term) there. Diffuse surfaces only occlude.
// Camera at @group(0) is the light's view.
//
// Two Rgba32Float targets (32 bytes per pixel: WebGPU's default limit of colour bytes per
// sample), decoded by gather.wgsl:
//   origin: xyz the point, w the red weight, negative when the photon travels inside glass;
//   dir:    xy the octahedral direction, zw the green and blue weights;
// a weight is the share of the light's flux through the pixel: the transmitted or reflected
// share times cos^3 off the view's axis (0 everywhere: no photon).
// ---------------------------------------------------------------------------------------------
#import gpu::prelude::oct_encode
#import scene::shading::{MATERIAL_GLASS, MATERIAL_METAL, SceneVertexOut, emission_jitter, in_cutout_hole, jittered_emission, objects, specular_event}

struct TransferParams {
    // Light position; w unused.
    light: vec4f,
    // Light intensity (W/sr).
    intensity: vec4f,
    // xyz: unit axis of the light's view; w: area of one pixel on its image plane at unit
    // distance, (2 tan(fov / 2) / grid)^2.
    axis: vec4f,
    // 1: each photon leaves from a random point of its pixel (jittered_emission in
    // scene.wgsl); 0: from the pixel centre.
    jitter: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(2) @binding(0) var<uniform> transfer: TransferParams;

struct TransferTargets {
    @location(0) origin: vec4f,
    @location(1) dir: vec4f,
};

@fragment
fn transfer_fs(pixel_in: SceneVertexOut) -> TransferTargets {
    // Derivatives first: naga's discard ends the invocation, so none may follow it.
    let in = jittered_emission(pixel_in, emission_jitter(pixel_in.clip.xy, 0u) * f32(transfer.jitter));
    if (in_cutout_hole(pixel_in.object, pixel_in.uv)) { discard; }
    let light = transfer.light.xyz;
    let dir = normalize(in.world - light);
    let e = specular_event(in.object, in.normal, in.world, light, dir);
    let kind = objects[in.object].material.x;
    let glass = kind == MATERIAL_GLASS && e.refracted.w > 0.5;
    let metal = kind == MATERIAL_METAL;
    var weight = vec3f(0.0);
    var out_dir = e.reflected;
    var inside = false;
    if (glass) {
        weight = vec3f(1.0 - e.reflectance.x);
        out_dir = e.refracted.xyz;
        inside = e.entering;
    } else if (metal) {
        weight = e.reflectance;
    }
    // Flux through this pixel: I * solid angle, solid angle = area * cos^3 off the axis (the
    // gather multiplies by I * area).
    let cos_axis = dot(dir, transfer.axis.xyz);
    let w = weight * cos_axis * cos_axis * cos_axis;
    var out: TransferTargets;
    out.origin = vec4f(in.world, select(w.r, -w.r, inside));
    out.dir = vec4f(oct_encode(out_dir), w.g, w.b);
    return out;
}
