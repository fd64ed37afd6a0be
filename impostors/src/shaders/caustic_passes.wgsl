// The caustic passes' entry points (impostors::caustic explains them): the caustic map of
// either path, the receiver cube, and the apply onto the diffuse surfaces in direct view.
#import gpu::prelude::PI
#import scene::shading::{MATERIAL_DIFFUSE, SceneVertexOut, camera, facing_normal, in_cutout_hole, objects, surface_albedo}
#import scene::chart::chart_uv
#import scene::receiver::{world_to_local, texel_area, light_map_power}
#import impostors::localized::{env_distance, env_sampler, params}
#import impostors::lightmap::{charts, fragment_chart}
#import impostors::caustic::{PhotonTargets, ReceiverTargets, caustic, emitted_photon, grid_irradiance, light_map, light_map_sampler, receiver_info, receiver_texel, trace_photon}

// Grid path: the photon's landing point.
@fragment
fn caustic_map_fs(in: SceneVertexOut) -> PhotonTargets {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    var out: PhotonTargets;
    out.address = vec4f(0.0);
    out.power = vec4f(0.0);
    let photon = trace_photon(emitted_photon(in));
    if (!photon.alive) { return out; }
    out.address = vec4f(params.reference.xyz + photon.l * photon.distance, 1.0);
    out.power = vec4f(photon.power, 0.0);
    return out;
}

// Light-map path (the paper's caustic map): the light-map address of the landing point. The
// receiver cube names the chart (the paper's texture id); the uv is computed from the landing
// point itself, so it is not quantised to the cube's texels.
@fragment
fn caustic_uv_fs(in: SceneVertexOut) -> PhotonTargets {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    var out: PhotonTargets;
    out.address = vec4f(0.0);
    out.power = vec4f(0.0);
    let photon = trace_photon(emitted_photon(in));
    if (!photon.alive) { return out; }
    let t = receiver_texel(photon.l);
    let info = textureLoad(receiver_info, t.xy, t.z, 0);
    let chart = i32(round(info.x));
    if (chart < 0) { return out; } // landed on a surface without a light map
    let landing = params.reference.xyz + photon.l * photon.distance;
    let uv = chart_uv(charts[chart], world_to_local(u32(round(info.y)), landing));
    out.address = vec4f(uv, f32(chart), 1.0);
    out.power = vec4f(photon.power, 0.0);
    return out;
}

@fragment
fn receiver_fs(in: SceneVertexOut) -> ReceiverTargets {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let chart = fragment_chart(in.object, in.world, in.normal);
    var out: ReceiverTargets;
    let to_surface = normalize(in.world - camera.eye.xyz);
    let n = facing_normal(in.normal, in.world, camera.eye.xyz);
    let diffuse = objects[in.object].material.x == MATERIAL_DIFFUSE;
    out.info = vec4f(-1.0, f32(in.object), 0.0, 0.0);
    if (diffuse) {
        var inv_area = 0.0;
        if (chart.index >= 0) {
            inv_area = 1.0 / texel_area(charts[chart.index], in.object, chart.local_normal);
        }
        out.info = vec4f(f32(chart.index), f32(in.object), inv_area, abs(dot(n, to_surface)));
    }
    out.albedo = vec4f(surface_albedo(in.object, in.uv), 1.0);
    return out;
}

// Light-map path, direct view: diffuse surfaces add albedo / pi * E, E = power per texel /
// the texel's area on the surface.
@fragment
fn lightmap_apply_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let chart = fragment_chart(in.object, in.world, in.normal);
    if (chart.index < 0) { return vec4f(0.0); }
    let c = charts[chart.index];
    let power = light_map_power(light_map, light_map_sampler, caustic.lightmap, c, chart.uv);
    let irradiance = power / texel_area(c, in.object, chart.local_normal);
    return vec4f(surface_albedo(in.object, in.uv) / PI * irradiance, 0.0);
}

// Grid path, direct view: only where the reference point sees this surface (the grid is
// indexed by its view).
@fragment
fn caustic_apply_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let d = in.world - params.reference.xyz;
    let dist = length(d);
    let seen = textureSampleLevel(env_distance, env_sampler, d, 0.0)[params.distance_channel];
    if (dist < 1e-4 || abs(seen - dist) > 0.02 * dist + 0.01) { return vec4f(0.0); }
    let n = facing_normal(in.normal, in.world, params.reference.xyz);
    let irradiance = grid_irradiance(d, abs(dot(n, d / dist)));
    return vec4f(surface_albedo(in.object, in.uv) / PI * irradiance, 0.0);
}
