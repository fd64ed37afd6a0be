// Caustics with distance impostors (paper section 5), after prelude + scene.wgsl + hit.wgsl +
// localized.wgsl.
//
// 1. caustic_map_fs: the caustic generator is drawn from the light (camera.eye = light) into a
//    small "caustic map"; each pixel is one photon: the light ray refracts (glass: in, then out
//    through the refractor map) or reflects (metal) at x, and Hit() in the environment
//    impostor gives the photon's landing point l' = o + |l'| l/|l| (the surface point the map
//    shows in direction l). Target 0: (landing point, 1), target 1: (photon power, 0); pixels
//    without the object keep w = 0.
// 2. splat.wgsl (compute): photons are added into a per-face grid indexed by the direction of
//    the landing point from the reference point o: the paper's "uvmap" is the environment map's
//    own parameterisation here.
// 3. caustic_apply_fs: diffuse surfaces add albedo / pi * E, E = photon power per area of the
//    grid texel's footprint (tent-filtered over 3 x 3 texels), where the surface is what the
//    reference point sees (else no caustic: a limitation of one map).

struct CausticParams {
    // Light position (w unused) and RGB intensity (W/sr).
    light: vec4f,
    intensity: vec4f,
    // Unit axis of the caustic map's view; w: area of one caustic-map pixel on the image plane
    // at unit distance, (2 tan(fov/2) / C)^2.
    axis: vec4f,
    // Face size of the accumulation grid, fixed-point scale of the accumulated power (units
    // per watt), caustic map size C, and the light count.
    grid: u32,
    scale: f32,
    size: u32,
    _pad: u32,
};

@group(3) @binding(0) var<uniform> caustic: CausticParams;
@group(3) @binding(1) var<storage, read> caustic_grid: array<u32>;

struct PhotonOut {
    @location(0) landing: vec4f,
    @location(1) power: vec4f,
};

@fragment
fn caustic_map_fs(in: SceneVertexOut) -> PhotonOut {
    var out: PhotonOut;
    out.landing = vec4f(0.0);
    out.power = vec4f(0.0);
    let light = caustic.light.xyz;
    let l_dir = normalize(in.world - light);
    let n = facing_normal(in.normal, in.world, light);
    let o = objects[in.object];
    let cos_i = -dot(l_dir, n);
    var origin = in.world;
    var dir: vec3f;
    var weight = vec3f(1.0);
    if (o.material.x == MATERIAL_METAL) {
        dir = reflect_dir(l_dir, n);
        weight = fresnel_nk(cos_i, o.n.xyz, o.k.xyz);
    } else {
        let entering = dot(normalize(in.normal), l_dir) < 0.0;
        let eta_rel = select(1.0 / o.material.y, o.material.y, entering);
        let t = refract_dir(l_dir, n, 1.0 / eta_rel);
        if (t.w < 0.5) { return out; }
        weight = vec3f(1.0 - fresnel_dielectric(cos_i, eta_rel));
        dir = t.xyz;
        origin = in.world - n * SURFACE_OFFSET;
        if (entering && params.mode == MODE_DOUBLE) {
            // Out through the refractor: the first chord that leaves (TIR chords reflect on).
            var left = false;
            for (var s = 0u; s < MAX_SEGMENTS; s++) {
                let chord = refractor_chord(origin, dir, o.material.y);
                if (chord.out.w > 0.5) {
                    weight *= 1.0 - chord.fresnel;
                    origin = chord.exit_point + chord.out.xyz * SURFACE_OFFSET;
                    dir = chord.out.xyz;
                    left = true;
                    break;
                }
                dir = reflect_dir(dir, -chord.normal);
                origin = chord.exit_point - chord.normal * SURFACE_OFFSET;
            }
            if (!left) { return out; }
        }
    }
    let x = origin - params.reference.xyz;
    var l = hit(x, dir, env_distance, env_sampler, params.distance_channel, params.method,
                params.iterations).xyz;
    if (dot(l, l) < 1e-12) { l = dir; }
    let shown = textureSampleLevel(env_distance, env_sampler, l, 0.0)[params.distance_channel];
    if (shown >= 0.5 * BACKGROUND_DISTANCE) { return out; } // leaves the scene
    let landing = params.reference.xyz + normalize(l) * shown;
    // Flux through this pixel: I * solid angle, solid angle = area * cos^3 off the axis.
    let cos_axis = dot(l_dir, caustic.axis.xyz);
    let solid_angle = caustic.axis.w * cos_axis * cos_axis * cos_axis;
    out.landing = vec4f(landing, 1.0);
    out.power = vec4f(caustic.intensity.rgb * solid_angle * weight, 0.0);
    return out;
}

fn grid_power(face: u32, i: i32, j: i32) -> vec3f {
    let g = i32(caustic.grid);
    if (i < 0 || j < 0 || i >= g || j >= g) { return vec3f(0.0); }
    let base = 3u * ((face * caustic.grid + u32(j)) * caustic.grid + u32(i));
    return vec3f(f32(caustic_grid[base]), f32(caustic_grid[base + 1u]), f32(caustic_grid[base + 2u])) / caustic.scale;
}

@fragment
fn caustic_apply_fs(in: SceneVertexOut) -> @location(0) vec4f {
    let eye = camera.eye.xyz;
    let d = in.world - params.reference.xyz;
    let dist = length(d);
    let seen = textureSampleLevel(env_distance, env_sampler, d, 0.0)[params.distance_channel];
    // Only where the reference point sees this surface (the grid is indexed by its view).
    if (dist < 1e-4 || abs(seen - dist) > 0.02 * dist + 0.01) { return vec4f(0.0); }
    let fuv = cube_dir_to_face_uv(d);
    let face = u32(fuv.x);
    let g = f32(caustic.grid);
    let ci = fuv.y * g;
    let cj = fuv.z * g;
    let i0 = i32(floor(ci));
    let j0 = i32(floor(cj));
    // Tent filter over 3 x 3 texels (weights 1 2 1), renormalised at the face's border.
    var power = vec3f(0.0);
    var wsum = 0.0;
    for (var dj = -1; dj <= 1; dj++) {
        for (var di = -1; di <= 1; di++) {
            let i = i0 + di;
            let j = j0 + dj;
            let w = f32(2 - abs(di)) * f32(2 - abs(dj));
            if (i >= 0 && j >= 0 && i < i32(caustic.grid) && j < i32(caustic.grid)) {
                power += w * grid_power(face, i, j);
                wsum += w;
            }
        }
    }
    power /= max(wsum, 1.0);
    // Solid angle of the texel around this direction, and its footprint on the surface.
    let sc = 2.0 * (f32(i0) + 0.5) / g - 1.0;
    let tc = 2.0 * (f32(j0) + 0.5) / g - 1.0;
    let texel_solid_angle = (4.0 / (g * g)) / pow(1.0 + sc * sc + tc * tc, 1.5);
    let n = facing_normal(in.normal, in.world, params.reference.xyz);
    let cos_s = max(abs(dot(n, d / dist)), 0.05);
    let area = texel_solid_angle * dist * dist / cos_s;
    let irradiance = power / area;
    let albedo = surface_albedo(in.object, in.uv);
    return vec4f(albedo / PI * irradiance, 0.0);
}
