// The per-photon marchers, one invocation per photon: the DDA (McGuire and Mara's screen-space
// march over every LDI layer with a thickness per layer), stopping at its first hit, and the
// paper's single-shader alternative (section 2.1), the lines' tolerance test walked in order
// (`march_tolerance`: from the first hit on to the sample nearest the crossing, the one the
// line raster and its reduction keep), stopping there.
#import screen_photons::ldi::{LDI_SCENE, side_of, no_hit, march_dda, march_tolerance}
#import screen_photons::photon::{Photon, pack_hit, photon_is_inside, photon_segment}

@group(3) @binding(0) var<storage, read> photons: array<Photon>;
@group(3) @binding(1) var<storage, read_write> hits: array<vec4f>;

const TEST_DDA: u32 = 0u;
const TEST_LINES: u32 = 1u;

// Marches photon i (if it still travels) with `test` and writes its hit.
fn march_photon(i: u32, test: u32) {
    if (i >= arrayLength(&photons)) { return; }
    let p = photons[i];
    var h = no_hit();
    if (p.origin.w > 0.5) {
        let s = photon_segment(p);
        let side = side_of(photon_is_inside(p));
        if (test == TEST_DDA) {
            h = march_dda(LDI_SCENE, s, side);
        } else {
            h = march_tolerance(LDI_SCENE, s, side);
        }
    }
    hits[i] = pack_hit(h);
}

@compute @workgroup_size(64)
fn dda_main(@builtin(global_invocation_id) g: vec3u) {
    march_photon(g.x, TEST_DDA);
}

@compute @workgroup_size(64)
fn tolerance_main(@builtin(global_invocation_id) g: vec3u) {
    march_photon(g.x, TEST_LINES);
}
