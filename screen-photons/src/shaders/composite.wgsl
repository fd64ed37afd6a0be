// ---------------------------------------------------------------------------------------------
// What every variant does in a scene with a scattering medium, after its image is complete:
// the image times the medium's transmittance from the eye to each pixel's first surface, then
// plus the in-scattered light (the god rays' blurred bands, the froxels' lookup; none for the
// variants without shafts).
// ---------------------------------------------------------------------------------------------
#import scene::shading::scene_medium
#import scene::medium::medium_transmittance
#import screen_photons::ldi::{ldi, ldi_point}
#import screen_photons::photon::surface_distance
#import gpu::fullscreen::FullscreenOut

@group(3) @binding(0) var inscatter: texture_2d<f32>;

// The image times the medium's transmittance from the eye to its first surface (blended as
// dst * src).
@fragment
fn attenuate_fs(in: FullscreenOut) -> @location(0) vec4f {
    let xy = vec2u(in.position.xy);
    let dir = normalize(ldi_point(xy.x, xy.y, 1.0) - ldi.eye.xyz);
    let t = medium_transmittance(scene_medium(), ldi.eye.xyz, dir, surface_distance(xy.x, xy.y));
    return vec4f(t, 1.0);
}

// Plus the in-scattered light (blended as dst + src, alpha kept).
@fragment
fn inscatter_fs(in: FullscreenOut) -> @location(0) vec4f {
    return vec4f(textureLoad(inscatter, vec2u(in.position.xy), 0).rgb, 0.0);
}
