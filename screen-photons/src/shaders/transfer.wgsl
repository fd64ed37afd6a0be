// ---------------------------------------------------------------------------------------------
// The transfer map (section 2): every object drawn from the light into a photon grid; a pixel
// whose nearest surface is specular is one photon, refracted (the transmitted share 1 - F) or
// reflected (metal, weighted by its Fresnel term) there. Diffuse surfaces only occlude.
// Camera at @group(0) is the light's view.
// ---------------------------------------------------------------------------------------------

struct TransferParams {
    // Light position; w unused.
    light: vec4f,
    // Light intensity (W/sr).
    intensity: vec4f,
    // xyz: unit axis of the light's view; w: area of one pixel on its image plane at unit
    // distance, (2 tan(fov / 2) / grid)^2.
    axis: vec4f,
};

@group(2) @binding(0) var<uniform> transfer: TransferParams;

struct TransferTargets {
    @location(0) origin: vec4f,
    @location(1) dir: vec4f,
    @location(2) power: vec4f,
};

@fragment
fn transfer_fs(in: SceneVertexOut) -> TransferTargets {
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
    // Flux through this pixel: I * solid angle, solid angle = area * cos^3 off the axis.
    let cos_axis = dot(dir, transfer.axis.xyz);
    let solid_angle = transfer.axis.w * cos_axis * cos_axis * cos_axis;
    let alive = select(0.0, 1.0, glass || metal);
    var out: TransferTargets;
    out.origin = vec4f(in.world, alive);
    out.dir = vec4f(out_dir, select(0.0, 1.0, inside));
    out.power = vec4f(transfer.intensity.rgb * solid_angle * weight, 0.0);
    return out;
}
