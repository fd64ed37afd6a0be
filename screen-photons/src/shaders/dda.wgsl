// The per-photon marchers, one invocation per photon: the DDA (McGuire and Mara's screen-space
// march over every LDI layer with a thickness per layer), stopping at its first hit, and the
// paper's single-shader alternative (section 2.1), the lines' tolerance test walked in order
// (`march_tolerance`: from the first hit on to the sample nearest the crossing, the one the
// line raster and its reduction keep), stopping there.

@group(3) @binding(0) var<storage, read> photons: array<Photon>;
@group(3) @binding(1) var<storage, read_write> hits: array<vec4f>;

@compute @workgroup_size(64)
fn dda_main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&photons)) { return; }
    let p = photons[i];
    var h = no_hit();
    if (p.origin.w > 0.5) {
        h = march_dda(LDI_SCENE, photon_segment(p), side_of(photon_is_inside(p)));
    }
    hits[i] = pack_hit(h);
}

@compute @workgroup_size(64)
fn tolerance_main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&photons)) { return; }
    let p = photons[i];
    var h = no_hit();
    if (p.origin.w > 0.5) {
        h = march_tolerance(LDI_SCENE, photon_segment(p), side_of(photon_is_inside(p)));
    }
    hits[i] = pack_hit(h);
}
