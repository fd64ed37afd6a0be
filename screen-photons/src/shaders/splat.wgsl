// ---------------------------------------------------------------------------------------------
// Energy splats (section 3.1): one quad per receiver point covering its splat's footprint on
// the screen; each pixel receives the photon's flux times a cone kernel of the distance d
// between the receiver point C and the point X its view ray meets on the splat's plane:
//   E += flux * 3 / (pi s^2) * max(0, 1 - d / s)
// (the paper's "s - d" normalised so that the kernel integrates to 1 over the plane: the
// flux is conserved). `oriented`: the plane is the receiver's tangent plane (the paper's
// sprite ray caster, equation 1) and X must be the visible surface (its distance within the
// tolerance of LDI layer 0). `sprite`: the plane faces the viewer (screen-aligned point
// sprites, the naive variant), drawn where C is not hidden.
// ---------------------------------------------------------------------------------------------
#import scene::shading::camera
#import scene::footprint::lattice_cell_edge
#import screen_photons::splat_weight::{splat_weight, footprint_reach, footprint_matrix, footprint_kernel, footprint_tangent}
#import screen_photons::ldi::ldi_layers
#import screen_photons::photon::Receiver

struct SplatParams {
    inv_view_proj: mat4x4f,
    // xyz: the eye's forward axis; w: focal length in pixels (height / (2 tan(fov / 2))) times
    // the secant of the angle between the axis and the view's corner.
    forward: vec4f,
    // Width, height (pixels), splat radius s (m), depth tolerance of the visibility test (m).
    size: vec4f,
    // 0: oriented (tangent plane), 1: screen-aligned sprite.
    mode: u32,
    // Oriented splats: the photon lattice's width (receiver i is lattice point (i % lattice,
    // i / lattice)), each splat the footprint of its cell (splat_weight.wgsl); 0: radius s.
    lattice: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(3) @binding(0) var<storage, read> receivers: array<Receiver>;
@group(3) @binding(1) var<uniform> splat: SplatParams;

struct SplatOut {
    @builtin(position) position: vec4f,
    @location(0) @interpolate(flat) receiver: u32,
    // The footprint's radius matrix (footprint_matrix); zero: the cone of radius s.
    @location(1) @interpolate(flat) footprint: vec3f,
};

// The receiver point of lattice neighbour j of receiver i (centre c, normal n) as an offset in
// the tangent basis (t, b); z = 0 where j is off the lattice's row or grid, has no point, or
// lies on another surface (a normal turned away, or off the tangent plane).
fn lattice_neighbour(i: u32, j: i32, same_row: bool, c: vec3f, n: vec3f, t: vec3f, b: vec3f) -> vec3f {
    let count = i32(arrayLength(&receivers));
    let lattice = splat.lattice;
    if (j < 0 || j >= count || (same_row && u32(j) / lattice != i / lattice)) {
        return vec3f(0.0);
    }
    let r = receivers[j];
    let e = r.position.xyz - c;
    let on_surface = r.position.w >= 0.5 && dot(r.normal.xyz, n) > 0.9
        && abs(dot(e, n)) <= 0.25 * length(e);
    return select(vec3f(0.0), vec3f(dot(e, t), dot(e, b), 1.0), on_surface);
}

// One edge of receiver i's lattice cell along `step` (1: the row, lattice: the column), in
// the tangent basis (scene's footprint.wgsl, lattice_cell_edge of its two neighbours).
fn lattice_edge(i: u32, step: i32, c: vec3f, n: vec3f, t: vec3f, b: vec3f) -> vec2f {
    let same_row = step == 1;
    let ahead = lattice_neighbour(i, i32(i) + step, same_row, c, n, t, b);
    let behind = lattice_neighbour(i, i32(i) - step, same_row, c, n, t, b);
    return lattice_cell_edge(ahead, behind);
}

const SPLAT_CORNERS = array<vec2f, 6>(
    vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
    vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0),
);

@vertex
fn splat_vs(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> SplatOut {
    var out: SplatOut;
    out.receiver = i;
    out.position = vec4f(-2.0, -2.0, 0.5, 1.0);
    out.footprint = vec3f(0.0);
    let r = receivers[i];
    if (r.position.w < 0.5) { return out; }
    let c = r.position.xyz;
    let eye = camera.eye.xyz;
    var s = splat.size.z;
    if (splat.lattice > 0u && splat.mode == 0u) {
        let n = normalize(r.normal.xyz);
        let t = footprint_tangent(n);
        let b = cross(n, t);
        let ex = lattice_edge(i, 1, c, n, t, b);
        let ey = lattice_edge(i, i32(splat.lattice), c, n, t, b);
        out.footprint = footprint_matrix(s, ex, ey);
        // The sphere that holds the footprint: its ellipse's semi-major axis.
        s = footprint_reach(out.footprint);
    }
    let z = dot(c - eye, splat.forward.xyz);
    if (z <= s * 1.01) { return out; }
    // The footprint of the sphere of radius s about C holds every point of either plane. On
    // the view axis its radius is f s / (z - s); off the axis the projection stretches, up to
    // the secant of the view's corner angle, which `forward.w` includes.
    let radius_px = splat.forward.w * s / (z - s);
    let clip = camera.view_proj * vec4f(c, 1.0);
    let centre = vec2f(clip.x / clip.w, clip.y / clip.w);
    let scale = vec2f(2.0 * radius_px / splat.size.x, 2.0 * radius_px / splat.size.y);
    out.position = vec4f(centre + SPLAT_CORNERS[v] * scale, 0.5, 1.0);
    return out;
}

@fragment
fn splat_fs(in: SplatOut) -> @location(0) vec4f {
    let r = receivers[in.receiver];
    let c = r.position.xyz;
    let eye = camera.eye.xyz;
    let px = vec2u(in.position.xy);
    let ndc = vec2f(2.0 * in.position.x / splat.size.x - 1.0, 1.0 - 2.0 * in.position.y / splat.size.y);
    let far = splat.inv_view_proj * vec4f(ndc, 1.0, 1.0);
    let view = normalize(far.xyz / far.w - eye);
    let visible_distance = textureLoad(ldi_layers, px, 0, 0).w;
    let sprite = splat.mode == 1u;
    let n = select(r.normal.xyz, normalize(eye - c), sprite);
    var w = splat_weight(eye, view, c, n, splat.size.z);
    if (in.footprint.x > 0.0) {
        // The footprint on the tangent plane, where the view ray meets it.
        let normal = normalize(n);
        let t = footprint_tangent(normal);
        let along = w.y * view + eye - c;
        let u = vec2f(dot(along, t), dot(along, cross(normal, t)));
        w = vec2f(select(0.0, footprint_kernel(u, in.footprint), w.y > 0.0), w.y);
    }
    let tolerance = splat.size.w;
    let oriented_visible = abs(w.y - visible_distance) < tolerance;
    let sprite_visible = distance(c, eye) <= visible_distance + tolerance;
    let visible = visible_distance > 0.0 && select(oriented_visible, sprite_visible, sprite);
    return vec4f(r.power.rgb * select(0.0, w.x, visible), 0.0);
}
