// ---------------------------------------------------------------------------------------------
// Screen-space shadow rays (the paper's figures 11 and 12): for every pixel whose nearest
// surface (LDI layer 0) is diffuse, a ray from that point back to each light (the first four)
// marched over the scene's LDI with the paper's tolerance test and the in-out test over
// consecutive layers it proposes (`march_shadow`); any surface it meets, glass included (as in
// the reference), and any solid it passes through shadows the point. The part of a ray that leaves the view
// cannot be tested: occluders off screen cast no shadow (README, "Failure cases").
// ---------------------------------------------------------------------------------------------
#import scene::shading::{lights, scene_info}
#import screen_photons::ldi::{ldi, LDI_SCENE, ldi_texel, scene_range, clip_segment, ldi_point, march_shadow}

@group(3) @binding(0) var<storage, read_write> shadow_mask: array<vec4f>;

// Shadow rays start this many tolerances off their surface (a ray leaving the surface at a
// grazing angle stays within the tolerance of it for a while: self-shadowing).
const SHADOW_START: f32 = 3.0;

@compute @workgroup_size(8, 8)
fn shadow_main(@builtin(global_invocation_id) g: vec3u) {
    if (g.x >= ldi.size.x || g.y >= ldi.size.y) { return; }
    let texel = ldi_texel(LDI_SCENE, g.x, g.y, 0u);
    var v = vec4f(1.0);
    if (texel.distance > 0.0 && !texel.specular) {
        let p = ldi_point(g.x, g.y, texel.distance);
        for (var i = 0u; i < min(scene_info.light_count, 4u); i++) {
            let to_l = lights[i].position.xyz - p;
            let dist = length(to_l);
            let dir = to_l / dist;
            let range = scene_range(p, dir);
            let s = clip_segment(p, dir, max(range.x, SHADOW_START * ldi.tests.x), min(range.y, dist));
            let h = march_shadow(LDI_SCENE, s);
            v[i] = select(1.0, 0.0, h.found);
        }
    }
    shadow_mask[g.y * ldi.size.x + g.x] = v;
}
