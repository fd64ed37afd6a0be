// ---------------------------------------------------------------------------------------------
// Screen-space refraction tracing (section 4) of the specular surfaces seen by the eye. At the
// visible surface the view ray splits (specular_event). The refracted ray, when it enters a
// refractor, is traced to its exit (through_refractor): the paper's monotone rule in the
// refractors' LDI (the n-th intersection is in layer n + 1; `mode` 0) or the DDA over every
// layer of the scene's LDI with a thickness (`mode` 1); the exit normal comes from that
// layer, and a ray reflected there (total internal reflection) tries the next layer once
// more. The rays that leave (reflected
// at the surface, refracted out) are retraced into the scene's LDI with the same test as the
// mode's photons (the tolerance test walked in order, or the DDA) and shaded there with the
// shared diffuse model; a ray that meets nothing there, or leaves the view, sees the
// background (the paper's environment lookup). In a scene with a scattering medium every
// traced segment is attenuated by its transmittance (what the eye's own segment loses is
// composite.wgsl's; light scattered into these rays is not added).
// ---------------------------------------------------------------------------------------------
#import scene::shading::{SceneVertexOut, camera, facing_normal, in_cutout_hole, object_emission, scene_info, scene_medium, shade_diffuse, specular_event, specular_shade, surface_albedo}
#import scene::medium::{medium_transmittance, medium_transmittance_between}
#import screen_photons::ldi::{ldi, ldi_surfaces, refractor_surfaces, LdiTexel, LDI_SCENE, LDI_REFRACTORS, ldi_texel, Segment, scene_range, clip_segment, point_on_surface, segment_step, SIDE_INSIDE, side_of, LdiHit, march_dda, march_tolerance, march_monotone}

struct SpecularParams {
    // 0: the paper's monotone layers and tolerance test; 1: the DDA with thickness.
    mode: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(3) @binding(0) var<uniform> specular: SpecularParams;

const EXIT_CHORDS: u32 = 2u;

// The diffuse surface a march hit, shaded with direct light (what the reference computes
// there); `s` is the marched segment (its step bounds how far the sample is off the surface).
fn shade_hit(which: u32, h: LdiHit, texel: LdiTexel, origin: vec3f, dir: vec3f, s: Segment) -> vec3f {
    // The sample is up to a step off the surface (behind it, for the thickness test): shade
    // the point on the surface, or the shadow test would put it behind the wall it lights.
    let p = point_on_surface(origin, dir, h.t, texel, h.pixel.x, h.pixel.y, segment_step(s) + ldi.tests.x);
    var uv: vec2f;
    if (which == LDI_SCENE) {
        uv = textureLoad(ldi_surfaces, h.pixel, h.layer, 0).yz;
    } else {
        uv = textureLoad(refractor_surfaces, h.pixel, h.layer, 0).yz;
    }
    let n = facing_normal(texel.normal, p, origin);
    return (shade_diffuse(p, n, surface_albedo(texel.object, uv)) + object_emission(texel.object))
        * medium_transmittance_between(scene_medium(), origin, p);
}

// Radiance arriving at `origin` from direction `dir`: the first diffuse surface of the scene's
// LDI along it, else the background (also for a second specular surface: not followed).
fn retrace(origin: vec3f, dir: vec3f, inside: bool) -> vec3f {
    let side = side_of(inside);
    let range = scene_range(origin, dir);
    let s = clip_segment(origin, dir, range.x, range.y);
    var h: LdiHit;
    if (specular.mode == 1u) {
        h = march_dda(LDI_SCENE, s, side);
    } else {
        h = march_tolerance(LDI_SCENE, s, side);
    }
    // The background (the paper's environment lookup) is seen through all of the medium the
    // ray crosses, as the reference sees it.
    let background = scene_info.background.rgb
        * medium_transmittance(scene_medium(), origin, dir, 1e30);
    if (!h.found) { return background; }
    let texel = ldi_texel(LDI_SCENE, h.pixel.x, h.pixel.y, h.layer);
    if (texel.specular) { return background; }
    return shade_hit(LDI_SCENE, h, texel, origin, dir, s);
}

// The radiance leaving a refractor toward `origin` along a ray refracted into it there. The
// DDA marches the scene's layers from inside (side rule: glass back faces are the way out,
// diffuse surfaces inside the refractor stop the ray); the paper's monotone rule reads the
// refractors' layers 0 and 1 (the ray leaves behind layer 1 or in front of layer 0), and
// where they have nothing along the ray (an open surface such as the pool's water, or an exit
// outside the view) the ray is retraced into the scene from inside. At the exit the refracted
// share (1 - F) is followed; under total internal reflection the reflected ray, still inside
// the same solid, marches between the same two layers again, up to EXIT_CHORDS chords (the
// paper's numbering would send it to layers 1 and 2, which assumes rays moving away from the
// eye: a reflected ray turns back, and would stop at once in front of layer 1).
fn through_refractor(origin: vec3f, dir_in: vec3f) -> vec3f {
    var o = origin;
    var dir = dir_in;
    var radiance = vec3f(0.0);
    var throughput = vec3f(1.0);
    var travelling = true;
    for (var chord = 0u; chord < EXIT_CHORDS; chord++) {
        if (!travelling) { break; }
        let range = scene_range(o, dir);
        let s = clip_segment(o, dir, range.x, range.y);
        var h: LdiHit;
        var which = LDI_SCENE;
        if (specular.mode == 1u) {
            h = march_dda(LDI_SCENE, s, SIDE_INSIDE);
        } else {
            // Between layers 0 and 1 on every chord: a ray reflected inside stays inside.
            h = march_monotone(LDI_REFRACTORS, s, 1u);
            which = LDI_REFRACTORS;
        }
        if (!h.found) {
            if (specular.mode == 1u) {
                radiance = scene_info.background.rgb
                    * medium_transmittance(scene_medium(), o, dir, 1e30);
            } else {
                radiance = retrace(o, dir, true);
            }
            travelling = false;
        } else {
            let texel = ldi_texel(which, h.pixel.x, h.pixel.y, h.layer);
            if (!texel.specular) {
                radiance = shade_hit(which, h, texel, o, dir, s);
                travelling = false;
            } else {
                let p = point_on_surface(o, dir, h.t, texel, h.pixel.x, h.pixel.y, segment_step(s) + ldi.tests.x);
                let e = specular_event(texel.object, texel.normal, p, o, dir);
                throughput *= medium_transmittance_between(scene_medium(), o, p);
                if (e.refracted.w > 0.5) {
                    radiance = (1.0 - e.reflectance.x) * retrace(p, e.refracted.xyz, false);
                    travelling = false;
                } else {
                    o = p;
                    dir = e.reflected;
                }
            }
        }
    }
    return radiance * throughput;
}

@fragment
fn specular_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let eye = camera.eye.xyz;
    let view = normalize(in.world - eye);
    let e = specular_event(in.object, in.normal, in.world, eye, view);
    // The reflected ray stays in the medium of the view ray; the refracted one crosses.
    let reflected = retrace(in.world, e.reflected, !e.entering);
    var refracted = vec3f(0.0);
    if (e.refracted.w > 0.5) {
        if (e.entering) {
            refracted = through_refractor(in.world, e.refracted.xyz);
        } else {
            refracted = retrace(in.world, e.refracted.xyz, false);
        }
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(in.world, eye));
}
