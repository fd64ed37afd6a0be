//! `Hit()`: the approximate ray hit of a distance impostor (paper sections 2.1-2.2 and the
//! `Hit` listing of section 3), and its WGSL twin in `shaders/hit.wgsl` ([`HIT_WGSL`]).
//!
//! It lives in `gpu`, not in a technique crate, because every distance-map technique searches
//! with it: distance impostors (`impostors`), refractor distance maps and height maps
//! (`refractor-maps`, `height-maps`) build on exactly this search.
//!
//! Coordinates are relative to the reference point `o` of the map (the paper's origin). A
//! [`DistanceMap`] answers "how far from `o` is the environment surface in direction `u`?".
//! For a point `y` on the ray `x + R d` the ratio
//!
//! ```text
//!     g(d) = |y| / dist(y),   y = x + R d
//! ```
//!
//! (`llp`, `ppp` in the paper) is below 1 when `y` is in front of the surface
//! (*undershooting*) and above 1 behind it (*overshooting*); the hit is the root of
//! `g(d) = 1`. Against a plane `n.y = c` seen from `o`, `dist(u) = c / n.u`, so
//! `g(d) = n.(x + R d) / c` is *linear* in `d`: two samples on the same plane give the exact
//! hit in one secant step, which is why the method is exact for large planar faces.
//!
//! The steps, with the paper's symbols:
//!
//! 1. `|r| = dist(R)`: `r = R |r|` is what classic environment mapping would show.
//! 2. Perpendicular-surface first guess (eq. 2): `d_p = |r| - R.x`, `p = x + R d_p`.
//! 3. Planar second guess through `r` and `p'` (eq. 4): `d_l = d_p + |r| (1 - |p|/|p'|)`.
//! 4. Refinement (eq. 6), `iterations` times:
//!    `d_new = d_l + (d_l - d_a) (1 - g_l) / (g_l - g_a)` where the partner `a` is
//!    - [`Method::Secant`]: the previous approximation (`p` on the first step);
//!    - [`Method::FalsePosition`]: the last approximation of the *opposite* type. With no
//!      overshoot yet, the partner is the ideal point at infinity of `r`: its chord has slope
//!      `1/|r|`, giving `d_new = d_l + |r| (1 - g_l)` (the same planar step as eq. 4); with no
//!      undershoot yet the paper's "safe" choice substitutes `r` again, the same formula.
//!
//! Every new ray parameter is clamped to `[0, D_MAX]` (the paper's "avoid flip" clamp to the
//! non-negative domain, plus an upper bound that keeps a divergent secant finite).
//!
//! Departures from the listing, all for robustness, none changes a converging run:
//! - "no undershoot/overshoot yet" is a flag, not the listing's `d == 0` sentinel (a clamped
//!   `d = 0` undershoot would otherwise be mistaken for "none");
//! - `d_p` is clamped to be non-negative like every other ray parameter;
//! - distances read from the map are floored at [`DIST_EPSILON`] (a reference point on a
//!   wall reads 0), `|y|` below [`MIN_LENGTH`] counts as ratio 0 (`y` is at `o`: certainly
//!   in front of the surface), and a secant step whose denominator is below
//!   [`DENOM_EPSILON`] is skipped (the listing would divide by zero).

use glam::Vec3;

/// `Hit()` in WGSL, the module `gpu::distance_map`: `hit(x, R, map, sampler, channel, method,
/// iterations) -> vec4(l, d)` and `hit_from_outside`.
pub const HIT_WGSL: &str = include_str!("shaders/hit.wgsl");
/// [`HIT_WGSL`] as a module (always available to [`crate::shader`]).
pub static HIT: crate::wgsl::Module =
    crate::wgsl::Module::new(HIT_WGSL, "gpu/src/shaders/hit.wgsl", &[]);

/// [`layered_hit_wgsl`] as the module `gpu::layered_distance_map` (always available to
/// [`crate::shader`]); its constants and `hit_clamp_d` are `gpu::distance_map`'s.
pub fn hit_layered() -> &'static crate::wgsl::Module {
    static MODULE: std::sync::OnceLock<crate::wgsl::Module> = std::sync::OnceLock::new();
    MODULE.get_or_init(|| {
        // The layered functions read hit.wgsl's constants and hit_clamp_d from gpu::distance_map.
        let constants: Vec<&str> = HIT_WGSL
            .lines()
            .filter_map(|line| line.strip_prefix("const "))
            .filter_map(|rest| rest.split(':').next())
            .collect();
        let source = format!(
            "#define_import_path gpu::layered_distance_map\n\
             #import gpu::prelude::ray_box\n\
             #import gpu::distance_map::{{{}, hit_clamp_d}}\n{}",
            constants.join(", "),
            layered_hit_wgsl()
        );
        crate::wgsl::Module {
            source: source.into(),
            file: "gpu::distance_map::layered_hit_wgsl()",
            imports: &[],
        }
    })
}

/// `Hit()` and the search from outside for maps stored as layers of a cube-map array
/// (`texture_cube_array<f32>`): `hit_layered(x, R, map, layer, sampler, channel, method,
/// iterations)` and `hit_from_outside_layered(y, R, map, layer, sampler, ...)`, the functions of
/// [`HIT_WGSL`] with the layer passed after the map. Generated from the same text, so the two
/// cannot drift apart (`gpu/tests/hit_outside_conformance.rs` checks that they return the same
/// bits); include it after [`HIT_WGSL`], whose constants it uses. One bind group can then
/// hold the maps of many objects, which one draw call can shade.
pub fn layered_hit_wgsl() -> String {
    let functions = &HIT_WGSL[HIT_WGSL.find("fn hit_distance").expect("hit.wgsl layout")..];
    // Drop what does not read a map (hit_clamp_d) and the constants: HIT_WGSL has them.
    let clamp = functions.find("fn hit_clamp_d").expect("hit.wgsl layout");
    let clamp_end = clamp + functions[clamp..].find("\n}\n").expect("hit.wgsl layout") + 3;
    let body: String = format!("{}{}", &functions[..clamp], &functions[clamp_end..])
        .lines()
        .filter(|line| !line.starts_with("const "))
        .map(|line| format!("{line}\n"))
        .collect();
    let replacements: [(&str, &str, usize); 9] = [
        (
            "map: texture_cube<f32>, smp: sampler",
            "map: texture_cube_array<f32>, layer: i32, smp: sampler",
            4,
        ),
        (
            "textureSampleLevel(map, smp, dir, 0.0)",
            "textureSampleLevel(map, smp, dir, layer, 0.0)",
            1,
        ),
        (
            "hit_distance(map, smp",
            "hit_distance_layered(map, layer, smp",
            3,
        ),
        ("hit_ratio(map, smp", "hit_ratio_layered(map, layer, smp", 2),
        (
            "hit(x, -R, map, smp",
            "hit_layered(x, -R, map, layer, smp",
            1,
        ),
        ("fn hit_distance(", "fn hit_distance_layered(", 1),
        ("fn hit_ratio(", "fn hit_ratio_layered(", 1),
        ("fn hit(", "fn hit_layered(", 1),
        ("fn hit_from_outside(", "fn hit_from_outside_layered(", 1),
    ];
    let mut out = body;
    for (from, to, count) in replacements {
        assert_eq!(
            out.matches(from).count(),
            count,
            "hit.wgsl changed: update layered_hit_wgsl's replacement of `{from}`"
        );
        out = out.replace(from, to);
    }
    out
}

/// Floor of a distance read from the map (metres).
pub const DIST_EPSILON: f32 = 1e-6;
/// Points closer than this to the reference point have ratio 0 (undershooting).
pub const MIN_LENGTH: f32 = 1e-6;
/// Secant steps with `|g_l - g_a|` below this are skipped (the two ratios are equal).
pub const DENOM_EPSILON: f32 = 1e-7;
/// Upper clamp of the ray parameter (metres); beyond the raster pass's background distance.
pub const D_MAX: f32 = 1.0e5;

/// Distance from the reference point to the environment surface in a direction.
pub trait DistanceMap {
    /// Distance along `dir` (any non-zero length; implementations normalise if they need
    /// to). `dir` is relative to the reference point.
    fn distance(&self, dir: Vec3) -> f32;
}

impl<F: Fn(Vec3) -> f32> DistanceMap for F {
    fn distance(&self, dir: Vec3) -> f32 {
        self(dir)
    }
}

/// How the two initial guesses are refined.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Pair the newest approximation with the previous one (eq. 6 as derived).
    Secant,
    /// Pair it with the last approximation of the opposite type (the `Hit` listing).
    FalsePosition,
}

impl Method {
    /// The value of `method` in `shaders/hit.wgsl`.
    pub fn wgsl_id(self) -> u32 {
        match self {
            Method::Secant => 0,
            Method::FalsePosition => 1,
        }
    }
    pub fn from_wgsl_id(id: u32) -> Self {
        if id == 0 {
            Method::Secant
        } else {
            Method::FalsePosition
        }
    }
}

/// One evaluated approximation: ray parameter and its ratio `g(d) = |y| / dist(y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub d: f32,
    pub ratio: f32,
}

impl Sample {
    pub fn undershooting(&self) -> bool {
        self.ratio < 1.0
    }
}

/// What [`hit_traced`] records: every ray parameter produced, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// `d_p`, its ratio.
    pub perpendicular: Option<Sample>,
    /// Ray parameters after the planar guess (`d_l`) and after each iteration.
    pub d: Vec<f32>,
    /// Ratio of each evaluated iterate (one per iteration: the ratio of `d[i]`).
    pub ratios: Vec<f32>,
    /// The bracket `[d_under, d_over]` after each iteration (`None` where no sample of that
    /// type exists yet; false position only, secant leaves both `None`).
    pub brackets: Vec<(Option<f32>, Option<f32>)>,
}

/// Result of [`hit`]: the ray parameter `d` and the point `l = x + R d` (relative to the
/// reference point), whose direction is what the radiance lookup uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitResult {
    pub d: f32,
    pub l: Vec3,
}

/// Ratio `|y| / dist(y)` of a point relative to the reference point.
pub fn ratio(map: &impl DistanceMap, y: Vec3) -> f32 {
    let len = y.length();
    if len < MIN_LENGTH {
        return 0.0;
    }
    len / map.distance(y).max(DIST_EPSILON)
}

// `max`/`min` return the non-NaN operand (`f32::clamp` would pass a NaN through), as WGSL's
// `max`/`min` do on the implementations we run; the step formulas cannot make NaN anyway.
#[allow(clippy::manual_clamp)]
fn clamp_d(d: f32) -> f32 {
    d.max(0.0).min(D_MAX)
}

/// Approximate hit of the ray `x + R d` (x relative to the reference point, `R` unit length).
pub fn hit(
    map: &impl DistanceMap,
    x: Vec3,
    r_dir: Vec3,
    method: Method,
    iterations: u32,
) -> HitResult {
    hit_traced(map, x, r_dir, method, iterations, None)
}

/// [`hit`] recording every step into `trace` when given.
pub fn hit_traced(
    map: &impl DistanceMap,
    x: Vec3,
    r_dir: Vec3,
    method: Method,
    iterations: u32,
    mut trace: Option<&mut Trace>,
) -> HitResult {
    // |r|: the point r = R |r| is what classic environment mapping shows.
    let r_len = map.distance(r_dir).max(DIST_EPSILON);
    // First guess: the surface at r is perpendicular to R (eq. 2).
    let d_p = clamp_d(r_len - r_dir.dot(x));
    let p = Sample {
        d: d_p,
        ratio: ratio(map, x + r_dir * d_p),
    };
    // Second guess: the surface is planar between r and p' (eq. 4).
    let mut d_l = clamp_d(d_p + r_len * (1.0 - p.ratio));

    // Last undershooting / overshooting samples (false position), previous sample (secant).
    let mut under: Option<Sample> = p.undershooting().then_some(p);
    let mut over: Option<Sample> = (!p.undershooting()).then_some(p);
    let mut previous = p;
    if let Some(t) = trace.as_deref_mut() {
        t.perpendicular = Some(p);
        t.d.push(d_l);
    }

    for _ in 0..iterations {
        let l = Sample {
            d: d_l,
            ratio: ratio(map, x + r_dir * d_l),
        };
        let partner = match method {
            Method::Secant => {
                let a = previous;
                previous = l;
                Some(a)
            }
            Method::FalsePosition => {
                if l.undershooting() {
                    under = Some(l);
                    over
                } else {
                    over = Some(l);
                    under
                }
            }
        };
        let step = match partner {
            // Chord through l and the partner (eq. 6).
            Some(a) => {
                let denom = l.ratio - a.ratio;
                if denom.abs() < DENOM_EPSILON {
                    0.0
                } else {
                    (l.d - a.d) * (1.0 - l.ratio) / denom
                }
            }
            // Chord through l and the ideal point at infinity of r (slope 1/|r|).
            None => r_len * (1.0 - l.ratio),
        };
        d_l = clamp_d(d_l + step);
        if let Some(t) = trace.as_deref_mut() {
            t.ratios.push(l.ratio);
            t.d.push(d_l);
            t.brackets.push(match method {
                Method::Secant => (None, None),
                Method::FalsePosition => (under.map(|s| s.d), over.map(|s| s.d)),
            });
        }
    }
    HitResult {
        d: d_l,
        l: x + r_dir * d_l,
    }
}

/// An exact distance function of an axis-aligned box room seen from inside: the environment
/// of the property tests (planar walls, convex from every interior reference point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxRoom {
    pub min: Vec3,
    pub max: Vec3,
    /// Reference point (inside the room, walls included).
    pub reference: Vec3,
}

impl BoxRoom {
    /// Exact ray parameter from `origin` (world) along unit `dir` to the first wall, for an
    /// origin inside the room.
    pub fn exact_t(&self, origin: Vec3, dir: Vec3) -> f32 {
        let mut t = f32::INFINITY;
        for axis in 0..3 {
            let d = dir[axis];
            if d > 0.0 {
                t = t.min((self.max[axis] - origin[axis]) / d);
            } else if d < 0.0 {
                t = t.min((self.min[axis] - origin[axis]) / d);
            }
        }
        t.max(0.0)
    }
}

impl DistanceMap for BoxRoom {
    fn distance(&self, dir: Vec3) -> f32 {
        self.exact_t(self.reference, dir.normalize())
    }
}

/// A cube distance map read back from the GPU: six faces of `size` x `size` texels in
/// layer order +X,-X,+Y,-Y,+Z,-Z, looked up *nearest texel* through the prelude's
/// `cube_dir_to_face_uv` (what a `Nearest` sampler does on the GPU); [`Self::filtered`] looks
/// it up bilinearly instead (what the technique's `Linear` sampler does).
#[derive(Clone, Debug)]
pub struct CubeDistanceMap {
    pub size: u32,
    /// `faces[f][j * size + i]`: distance of texel (i, j) of face f.
    pub faces: Vec<Vec<f32>>,
}

impl CubeDistanceMap {
    /// From read-back RGBA faces, taking channel `channel` (3: packed alpha).
    pub fn from_rgba_faces(size: u32, faces: &[Vec<[f32; 4]>], channel: usize) -> Self {
        Self {
            size,
            faces: faces
                .iter()
                .map(|f| f.iter().map(|t| t[channel]).collect())
                .collect(),
        }
    }

    /// Texel (face, i, j) that a nearest lookup of `dir` reads.
    pub fn texel(&self, dir: Vec3) -> (usize, u32, u32) {
        let fuv = crate::prelude::cube_dir_to_face_uv(dir);
        let s = self.size as f32;
        let i = ((fuv.y * s).floor().max(0.0) as u32).min(self.size - 1);
        let j = ((fuv.z * s).floor().max(0.0) as u32).min(self.size - 1);
        (fuv.x as usize, i, j)
    }
}

impl DistanceMap for CubeDistanceMap {
    fn distance(&self, dir: Vec3) -> f32 {
        let (f, i, j) = self.texel(dir);
        self.faces[f][(j * self.size + i) as usize]
    }
}

/// The 2 x 2 texels and weights that a bilinear lookup blends, on the face the prelude's
/// `cube_dir_to_face_uv` selects: Vulkan's texel-centre convention (`x = u size - 0.5`,
/// columns `floor(x)` and `floor(x) + 1`, weight `frac(x)` on the second; rows likewise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    pub face: usize,
    /// First column and row of the footprint, before clamping: -1 when the lookup lies in the
    /// outer half of a texel of column or row 0, in which case the footprint's other column
    /// (or row) is `size`, past the face.
    pub i0: i32,
    pub j0: i32,
    /// Weights of column `i0 + 1` and row `j0 + 1`, in [0, 1).
    pub wu: f32,
    pub wv: f32,
}

impl Footprint {
    /// Whether the footprint reaches past the face (within half a texel of its edge). The GPU
    /// (seamless cube sampling) reads the neighbouring face there; [`FilteredCube`] clamps to
    /// the face's own edge texel instead.
    pub fn crosses_face_edge(&self, size: u32) -> bool {
        self.i0 < 0 || self.j0 < 0 || self.i0 + 1 >= size as i32 || self.j0 + 1 >= size as i32
    }
}

impl CubeDistanceMap {
    /// Bilinear footprint of a lookup of `dir` (see [`Footprint`]).
    pub fn footprint(&self, dir: Vec3) -> Footprint {
        let fuv = crate::prelude::cube_dir_to_face_uv(dir);
        let s = self.size as f32;
        let x = fuv.y * s - 0.5;
        let y = fuv.z * s - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        Footprint {
            face: fuv.x as usize,
            i0: x0 as i32,
            j0: y0 as i32,
            wu: x - x0,
            wv: y - y0,
        }
    }

    /// Texel (i, j) of face `face`, clamped to the face (clamp-to-edge within the face).
    pub fn texel_clamped(&self, face: usize, i: i32, j: i32) -> f32 {
        let last = self.size as i32 - 1;
        let (i, j) = (i.clamp(0, last) as u32, j.clamp(0, last) as u32);
        self.faces[face][(j * self.size + i) as usize]
    }

    /// Bilinearly filtered distance in direction `dir` (what a `Linear` sampler returns away
    /// from face edges; at a face edge the footprint is clamped to the face, see
    /// [`Footprint::crosses_face_edge`]).
    pub fn bilinear(&self, dir: Vec3) -> f32 {
        let fp = self.footprint(dir);
        let t = |di: i32, dj: i32| self.texel_clamped(fp.face, fp.i0 + di, fp.j0 + dj);
        let top = t(0, 0) * (1.0 - fp.wu) + t(1, 0) * fp.wu;
        let bottom = t(0, 1) * (1.0 - fp.wu) + t(1, 1) * fp.wu;
        top * (1.0 - fp.wv) + bottom * fp.wv
    }

    /// This map looked up with bilinear filtering (the technique's `Linear` sampler); the map
    /// itself stays nearest-texel.
    pub fn filtered(&self) -> FilteredCube<'_> {
        FilteredCube(self)
    }
}

/// A [`CubeDistanceMap`] looked up through [`CubeDistanceMap::bilinear`].
#[derive(Clone, Copy, Debug)]
pub struct FilteredCube<'a>(pub &'a CubeDistanceMap);

impl DistanceMap for FilteredCube<'_> {
    fn distance(&self, dir: Vec3) -> f32 {
        self.0.bilinear(dir)
    }
}

// ---------------------------------------------------------------------------------------------
// Search from outside (Dancsik and Minarik, "Real-time multi-bounce many-object ray tracing
// with distance-normal impostors", section 4.1)
// ---------------------------------------------------------------------------------------------

/// What [`hit_from_outside`] found: the ray parameter on the *original* ray, the point on the
/// ray (`point = y + R d`) and the surface point the map shows in its direction (`surface`),
/// all relative to the map's reference point. `surface` is within the epsilon of `point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutsideHit {
    /// Ray parameter along the original ray `y + R d` (`d >= 0`).
    pub d: f32,
    /// The approximation on the ray.
    pub point: Vec3,
    /// The map's surface point in the direction of `point`: `point / |point| * dist(point)`.
    pub surface: Vec3,
}

/// The ray `y + R d` (relative to the map's reference point, `R` unit length) against an object
/// represented by its refractor distance map, searched from outside (paper section 4.1):
///
/// 1. intersect the object's bounding box `[bmin, bmax]` (relative to the reference point): no
///    box hit ahead of `y`, no hit;
/// 2. run [`hit`] from the box's far point `x = y + R t_far` along the *reversed* ray `-R`:
///    its first guess reads the map in direction `-R`, the side of the object that faces the
///    ray's origin, so the search converges to the surface where the original ray enters;
/// 3. accept the result only if the map's surface point in its direction lies within
///    `epsilon` of it ("the search method selects a point on the surface even if the ray
///    actually does not intersect the object"), and it lies ahead of `y`. The gap is measured
///    radially (surface point to the found point, along their common direction from the
///    reference point), which is at least the surface point's distance to the ray: stricter
///    than the paper's "farther from the ray than epsilon" by up to `1 / sin` of the angle
///    between that direction and the ray, which rejects some slowly converging grazing hits.
///
/// On a convex object with an exact map it finds the entry point, except where the search
/// pins itself at the far box point: from there an overshooting first guess makes every step
/// backward, and the clamp to `d >= 0` holds it (1.1% of non-grazing rays on flat ellipsoids
/// with false position and 16 iterations, `tests/hit_outside_properties.rs`). An object that
/// is not star-shaped from its reference point has surface the map does not hold, and rays
/// that meet only that surface are missed or land on the wrong point: the failure the paper
/// answers with height maps (section 6).
#[allow(clippy::too_many_arguments)]
pub fn hit_from_outside(
    map: &impl DistanceMap,
    y: Vec3,
    r_dir: Vec3,
    bmin: Vec3,
    bmax: Vec3,
    method: Method,
    iterations: u32,
    epsilon: f32,
) -> Option<OutsideHit> {
    let t = crate::prelude::ray_box(y, r_dir, bmin, bmax);
    if t.x > t.y || t.y <= 0.0 {
        return None;
    }
    let x = y + r_dir * t.y;
    let h = hit(map, x, -r_dir, method, iterations);
    let d = t.y - h.d;
    let len = h.l.length();
    if len < MIN_LENGTH || d < 0.0 {
        return None;
    }
    let surface = h.l / len * map.distance(h.l);
    ((surface - h.l).length() <= epsilon).then_some(OutsideHit {
        d,
        point: h.l,
        surface,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room() -> BoxRoom {
        BoxRoom {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 2.0, 1.0),
            reference: Vec3::new(0.1, 0.7, -0.2),
        }
    }

    #[test]
    fn planar_guess_is_exact_when_r_and_p_prime_share_the_hit_wall() {
        // Looking straight at the back wall from near the reference point: r, p' and q all lie
        // on the plane z = -1.
        let room = room();
        let x = Vec3::new(0.05, 0.05, 0.1);
        let r = Vec3::new(0.1, 0.05, -1.0).normalize();
        let h = hit(&room, x, r, Method::FalsePosition, 0);
        let exact = room.exact_t(room.reference + x, r);
        assert!((h.d - exact).abs() < 1e-5, "{} vs {exact}", h.d);
    }

    /// A 4 x 4 cube whose texel (f, i, j) holds `100 f + 10 j + i`.
    fn ramp_cube() -> CubeDistanceMap {
        CubeDistanceMap {
            size: 4,
            faces: (0..6)
                .map(|f| {
                    (0..16)
                        .map(|k| (100 * f + 10 * (k / 4) + k % 4) as f32)
                        .collect()
                })
                .collect(),
        }
    }

    #[test]
    fn bilinear_reads_texel_centres_exactly_and_blends_between_them() {
        let cube = ramp_cube();
        let dir = |f, u: f32, v: f32| crate::prelude::cube_face_uv_to_dir(f, u / 4.0, v / 4.0);
        for f in 0..6u32 {
            // Texel centre (1, 2): weight 0 on the neighbours.
            let d = dir(f, 1.5, 2.5);
            assert_eq!(cube.bilinear(d), cube.distance(d));
            assert_eq!(cube.bilinear(d), (100 * f + 21) as f32);
            // A quarter of the way from (1, 1) to (2, 2): the ramp is linear in i and j.
            let b = cube.bilinear(dir(f, 1.75, 1.75));
            assert!((b - (100 * f) as f32 - 11.0 - 2.75).abs() < 1e-4, "{b}");
            // Within half a texel of the face edge the footprint clamps to the face.
            let fp = cube.footprint(dir(f, 0.25, 1.5));
            assert!(fp.crosses_face_edge(4) && fp.i0 == -1);
            assert_eq!(cube.bilinear(dir(f, 0.25, 1.5)), (100 * f + 10) as f32);
            assert!(!cube.footprint(dir(f, 0.5, 3.49)).crosses_face_edge(4));
            assert!(cube.footprint(dir(f, 0.5, 3.51)).crosses_face_edge(4));
        }
    }

    #[test]
    fn ray_at_the_reference_point_reads_the_map() {
        let room = room();
        let r = Vec3::new(0.3, -0.4, 0.5).normalize();
        for method in [Method::Secant, Method::FalsePosition] {
            let h = hit(&room, Vec3::ZERO, r, method, 3);
            assert!((h.d - room.distance(r)).abs() < 1e-5);
        }
    }
}
