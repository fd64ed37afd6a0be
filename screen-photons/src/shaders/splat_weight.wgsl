#define_import_path screen_photons::splat_weight
// The splat kernel and weight (section 3.1): the WGSL twin of `src/splat.rs`.
#import gpu::prelude::PI

// The cone kernel of radius s, normalised to integrate to 1 over its plane.
fn splat_kernel(d: f32, s: f32) -> f32 {
    return 3.0 / (PI * s * s) * max(0.0, 1.0 - d / s);
}

// The splat weight at a pixel whose unit view ray from `eye` is `view`: the kernel at the
// point of the splat's plane (normal n through c) that the ray meets, and that point's
// distance from the eye (0 when the ray misses the plane).
fn splat_weight(eye: vec3f, view: vec3f, c: vec3f, n: vec3f, s: f32) -> vec2f {
    let denom = dot(view, n);
    if (abs(denom) < 1e-6) { return vec2f(0.0); }
    let tau = dot(c - eye, n) / denom;
    if (tau <= 0.0) { return vec2f(0.0); }
    let x = eye + view * tau;
    return vec2f(splat_kernel(distance(x, c), s), tau);
}

// Footprints (photon differentials by finite differences; `photon_footprint`): the photons
// leave the light on the transfer map's lattice, so each stands for one lattice cell, and
// where the caustic spreads the cell lands much larger than a splat of radius s, and
// stretched, and a lattice of fixed splats draws its rows as rings. A footprint is the cone
// stretched over the cell: in the receiver's tangent basis its radius matrix is
//   M = s^2 I + FOOTPRINT_CELLS^2 (ex ex^T + ey ey^T),
// ex and ey the cell's edges (from the neighbours' receiver points), and its kernel
//   k(u) = 3 / (pi sqrt(det M)) max(0, 1 - sqrt(u^T M^-1 u)),
// which integrates to 1 over the plane (with no cell it is splat_kernel). A lattice of cones
// two cells wide sums to within 4 % of flat (src/splat.rs's tests).
const FOOTPRINT_CELLS: f32 = 2.0;
// The widest footprint in splat radii: a cell measured across a fold or a silhouette can be
// arbitrarily large; its cone is shrunk to fit.
const MAX_FOOTPRINT_SPLATS: f32 = 8.0;

// The footprint's reach: its ellipse's semi-major axis, sqrt of M's larger eigenvalue.
fn footprint_reach(m: vec3f) -> f32 {
    let half_trace = 0.5 * (m.x + m.z);
    let half_gap = 0.5 * (m.x - m.z);
    return sqrt(half_trace + sqrt(half_gap * half_gap + m.y * m.y));
}

// M (xx, xy, yy) for splat radius s and cell edges ex, ey in the tangent basis, its reach at
// most MAX_FOOTPRINT_SPLATS s.
fn footprint_matrix(s: f32, ex: vec2f, ey: vec2f) -> vec3f {
    let c2 = FOOTPRINT_CELLS * FOOTPRINT_CELLS;
    var m = vec3f(s * s + c2 * (ex.x * ex.x + ey.x * ey.x),
                  c2 * (ex.x * ex.y + ey.x * ey.y),
                  s * s + c2 * (ex.y * ex.y + ey.y * ey.y));
    let reach = footprint_reach(m);
    let most = MAX_FOOTPRINT_SPLATS * s;
    if (reach > most) {
        m *= (most / reach) * (most / reach);
    }
    return m;
}

// The footprint's kernel at offset u (tangent basis) from the receiver point.
fn footprint_kernel(u: vec2f, m: vec3f) -> f32 {
    let det = m.x * m.z - m.y * m.y;
    let q2 = (m.z * u.x * u.x - 2.0 * m.y * u.x * u.y + m.x * u.y * u.y) / det;
    return 3.0 / (PI * sqrt(det)) * max(0.0, 1.0 - sqrt(q2));
}

// An orthonormal tangent of unit normal n (Duff et al. 2017): the basis is (t, cross(n, t)).
fn footprint_tangent(n: vec3f) -> vec3f {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return vec3f(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
}
