// ---------------------------------------------------------------------------------------------
// After a march: a photon that met a specular surface in the LDI reflects or refracts there
// and travels on (the recursive specular-to-specular transfer of section 2.3: the updated
// photon is the next transfer map); one that met a diffuse surface becomes a receiver point;
// one that met nothing (it left the view) is done. In a scene with a scattering medium the
// photon loses the medium's transmittance along the way, and each photon ray of the round is
// kept as a beam for the light shafts (section 3.2) when the variant draws them.
// ---------------------------------------------------------------------------------------------
#import scene::shading::{scene_medium, specular_event}
#import scene::medium::medium_transmittance_between
#import screen_photons::ldi::{ldi, LDI_SCENE, ldi_texel, scene_range, point_on_surface, segment_step}
#import screen_photons::photon::{Photon, Receiver, photon_is_inside, photon_segment}
#import screen_photons::beam::Beam

struct ResolveParams {
    // Specular events allowed after the transfer map.
    max_bounces: u32,
    // The march round (0 for the transfer map's photons): beam i of this round is
    // beams[round * photons + i].
    round: u32,
    // 1: write the beams.
    keep_beams: u32,
    _pad: u32,
};

@group(3) @binding(0) var<storage, read_write> photons: array<Photon>;
@group(3) @binding(1) var<storage, read> hits: array<vec4f>;
@group(3) @binding(2) var<storage, read_write> receivers: array<Receiver>;
@group(3) @binding(3) var<uniform> resolve: ResolveParams;
@group(3) @binding(4) var<storage, read_write> beams: array<Beam>;

fn keep_beam(i: u32, b: Beam) {
    if (resolve.keep_beams == 0u) { return; }
    let at = resolve.round * arrayLength(&photons) + i;
    if (at < arrayLength(&beams)) { beams[at] = b; }
}

@compute @workgroup_size(64)
fn resolve_main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&photons)) { return; }
    var p = photons[i];
    var beam = Beam(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    if (p.origin.w < 0.5) {
        keep_beam(i, beam);
        return;
    }
    let h = hits[i];
    beam = Beam(vec4f(p.origin.xyz, 1.0), vec4f(p.dir.xyz, 0.0), vec4f(p.power.rgb, 0.0));
    if (h.x <= 0.0) {
        // Lost by the view: the beam runs to where it leaves the scene's box.
        beam.dir.w = max(scene_range(p.origin.xyz, p.dir.xyz).y, 0.0);
        beam.power.w = 2.0;
        keep_beam(i, beam);
        p.origin.w = 0.0;
        photons[i] = p;
        return;
    }
    let texel = ldi_texel(LDI_SCENE, u32(h.z), u32(h.w), u32(h.y));
    // The sample is up to a pixel's travel off the surface: put the point on it.
    let reach = segment_step(photon_segment(p)) + ldi.tests.x;
    let at = point_on_surface(p.origin.xyz, p.dir.xyz, h.x, texel, u32(h.z), u32(h.w), reach);
    beam.dir.w = length(at - p.origin.xyz);
    beam.power.w = select(0.0, 1.0, !texel.specular);
    keep_beam(i, beam);
    p.power = vec4f(
        p.power.rgb * medium_transmittance_between(scene_medium(), p.origin.xyz, at),
        p.power.w,
    );
    if (!texel.specular) {
        let n = normalize(texel.normal);
        receivers[i] = Receiver(
            vec4f(at, 1.0),
            vec4f(select(n, -n, dot(n, p.dir.xyz) > 0.0), 0.0),
            vec4f(p.power.rgb, 0.0),
        );
        p.origin.w = 0.0;
        photons[i] = p;
        return;
    }
    if (u32(p.power.w) >= resolve.max_bounces) {
        p.origin.w = 0.0;
        photons[i] = p;
        return;
    }
    let e = specular_event(texel.object, texel.normal, at, p.origin.xyz, p.dir.xyz);
    var weight = e.reflectance;
    var dir = e.reflected;
    var inside = photon_is_inside(p);
    if (!e.is_metal && e.refracted.w > 0.5) {
        weight = vec3f(1.0 - e.reflectance.x);
        dir = e.refracted.xyz;
        inside = e.entering;
    } else if (!e.is_metal) {
        weight = vec3f(1.0);
    }
    p.origin = vec4f(at, 1.0);
    p.dir = vec4f(dir, select(0.0, 1.0, inside));
    p.power = vec4f(p.power.rgb * weight, p.power.w + 1.0);
    photons[i] = p;
}
