//! The screen-space march of a ray over a layered depth image (LDI): the Rust twin of
//! `shaders/ldi.wgsl`.
//!
//! Krüger, Bürger and Westermann (section 2) find where a photon ray first meets the scene
//! without any world-space structure: the ray is projected into the eye's view and walked
//! pixel by pixel, and at each pixel its distance from the eye is compared with the distances
//! stored in every layer of the LDI (depth peeling gives the surfaces behind the visible
//! ones). Both marchers here walk the same samples, one per pixel along the major axis of the
//! projected segment, at screen fractions `s = (k + 1/2) / n` (exactly the fragments a
//! rasterizer makes of a horizontal line `n` pixels long: the paper's "line into its own
//! row"). They differ in the test at a sample and in how the first hit is found:
//!
//! - [`Test::Tolerance`], the paper's: a layer is hit when the ray's distance at the sample
//!   is within a world-space tolerance of the layer's (section 5: "if the world space
//!   distance ... was less than 0.01"). Every sample is tested (each fragment of the line)
//!   and the horizontal reduction keeps the first run of hits; of that run, the sample where
//!   the gap between the ray and the layer stops shrinking (the sample nearest the crossing).
//!   The paper keeps the run's first sample. That sample lies up to a tolerance before the
//!   surface, and where a sample spans less than the tolerance (a fine screen, or a ray
//!   seen end-on) it lies several pixels before it: the exit point and normal are read there,
//!   which biased the caustic under cornell-sphere's sphere by 0.35, 0.62 and 1.26 pixels at
//!   64, 128 and 256 pixels (the crate README's "Line marcher" section).
//! - [`Test::Thickness`], the marcher engines use today (McGuire and Mara, JCGT 2014): the
//!   ray's distance range over the sample's pixel must overlap `[d, d + thickness]` of a
//!   layer, each surface being assumed that thick; the walk stops at the first hit.
//!
//! A hit on glass counts only if the ray meets it from the side it is on: a ray inside glass
//! leaves through a face whose authored normal points along it, a ray in air enters through
//! one facing it: what lets a photon refracted into an object find its exit instead of the
//! face it came in through. Diffuse and metal surfaces stop a ray from either side, and a
//! shadow ray ([`Side::Any`]) stops at anything. Samples closer than
//! `t_skip` to the ray's origin are skipped (the surface the ray starts on).

/// `shaders/ldi.wgsl`, the WGSL of this module.
pub const LDI_WGSL: &str = include_str!("shaders/ldi.wgsl");

/// [`LDI_WGSL`] as the module `screen_photons::ldi`, which the technique's passes and the
/// conformance kernel import. Its bindings are placed by the definitions `LDI_GROUP` and
/// `LDI_FIRST_BINDING` ([`LDI_DEFS`] for the technique's passes); an object's material kind comes from
/// the scene's materials unless the shader overrides `ldi_kind`.
pub static LDI: gpu::wgsl::Module = gpu::wgsl::Module::new(
    LDI_WGSL,
    "screen-photons/src/shaders/ldi.wgsl",
    &[&scene::SHADING],
);

/// Where the technique's passes bind the LDI: `@group(2)`, from `@binding(0)`.
pub const LDI_DEFS: [(&str, gpu::wgsl::Def); 2] = [
    ("LDI_GROUP", gpu::wgsl::Def::UInt(2)),
    ("LDI_FIRST_BINDING", gpu::wgsl::Def::UInt(0)),
];

use glam::{Mat4, Vec2, Vec3, Vec4};

/// One texel of one LDI layer: what `scene::DepthPeeler` writes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Texel {
    /// Euclidean distance from the eye; 0 = empty (no surface at this layer).
    pub distance: f32,
    /// Authored (not flipped) unit normal.
    pub normal: Vec3,
    /// Object index.
    pub object: u32,
    /// Whether the object is specular (glass or metal): a photon reflects or refracts here.
    pub specular: bool,
    /// Whether it is glass: the side rule applies ([`side_ok`]).
    pub glass: bool,
}

/// A layered depth image: `layers` layers of `width` x `height` texels, layer 0 nearest.
#[derive(Clone, Debug)]
pub struct Ldi {
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    /// Texel `(x, y)` of layer `l` at `(l * height + y) * width + x`.
    pub texels: Vec<Texel>,
}

impl Ldi {
    /// An empty LDI.
    pub fn new(width: u32, height: u32, layers: u32) -> Self {
        Self {
            width,
            height,
            layers,
            texels: vec![Texel::default(); (width * height * layers) as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32, layer: u32) -> Texel {
        self.texels[((layer * self.height + y) * self.width + x) as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, layer: u32, texel: Texel) {
        self.texels[((layer * self.height + y) * self.width + x) as usize] = texel;
    }

    /// Number of non-empty layers at pixel `(x, y)`: its depth complexity (layers are
    /// filled front to back, so the first empty one ends the list).
    pub fn complexity(&self, x: u32, y: u32) -> u32 {
        (0..self.layers)
            .find(|&l| self.get(x, y, l).distance <= 0.0)
            .unwrap_or(self.layers)
    }
}

/// The eye the LDI was peeled from.
#[derive(Clone, Copy, Debug)]
pub struct Eye {
    /// World to clip, depth in [0, 1] (`Camera::view_proj`).
    pub view_proj: Mat4,
    pub position: Vec3,
    pub width: u32,
    pub height: u32,
}

impl Eye {
    /// Pixel coordinates of clip-space point `c` (`w > 0`), row 0 at the top.
    pub fn pixel(&self, c: Vec4) -> Vec2 {
        Vec2::new(
            (c.x / c.w + 1.0) * 0.5 * self.width as f32,
            (1.0 - c.y / c.w) * 0.5 * self.height as f32,
        )
    }
}

/// A sphere for [`Ldi::of_spheres`]: centre, radius, object index, glass (specular) or
/// diffuse.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub centre: Vec3,
    pub radius: f32,
    pub object: u32,
    pub specular: bool,
}

impl Ldi {
    /// The exact LDI of `spheres` seen from `eye`: at each pixel centre every intersection of
    /// the view ray with every sphere (front and back), nearest first, with outward normals;
    /// what depth peeling of finely tessellated spheres gives. Surfaces beyond `layers` are
    /// dropped.
    pub fn of_spheres(eye: &Eye, layers: u32, spheres: &[Sphere]) -> Self {
        let mut ldi = Ldi::new(eye.width, eye.height, layers);
        for y in 0..eye.height {
            for x in 0..eye.width {
                let dir = eye.pixel_ray(x, y);
                let mut found: Vec<Texel> = Vec::new();
                for s in spheres {
                    let t = gpu::prelude::ray_sphere(eye.position, dir, s.centre, s.radius);
                    if t.x > t.y {
                        continue;
                    }
                    for t in [t.x, t.y] {
                        if t > 0.0 && t.is_finite() && t < 1e29 {
                            let p = eye.position + dir * t;
                            found.push(Texel {
                                distance: t,
                                normal: (p - s.centre) / s.radius,
                                object: s.object,
                                specular: s.specular,
                                glass: s.specular,
                            });
                        }
                    }
                }
                found.sort_by(|a, b| a.distance.total_cmp(&b.distance));
                for (l, texel) in found.into_iter().take(layers as usize).enumerate() {
                    ldi.set(x, y, l as u32, texel);
                }
            }
        }
        ldi
    }
}

impl Eye {
    /// The unit view ray through the centre of pixel `(x, y)`.
    pub fn pixel_ray(&self, x: u32, y: u32) -> Vec3 {
        let ndc = Vec2::new(
            2.0 * (x as f32 + 0.5) / self.width as f32 - 1.0,
            1.0 - 2.0 * (y as f32 + 0.5) / self.height as f32,
        );
        let far = self.view_proj.inverse() * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.position).normalize()
    }
}

/// A ray clipped to the view frustum and projected: what the line's vertex shader computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub origin: Vec3,
    pub dir: Vec3,
    /// Ray parameters of the visible part's ends.
    pub t_start: f32,
    pub t_end: f32,
    /// Clip-space `w` at the ends (the perspective-correct interpolation needs them).
    pub w_start: f32,
    pub w_end: f32,
    /// Pixel coordinates of the ends.
    pub p_start: Vec2,
    pub p_end: Vec2,
    /// Samples (fragments of the line): one per pixel along the major axis, at least 1.
    pub steps: u32,
}

/// Longest line in samples: a segment clipped to the screen spans at most the screen's larger
/// side along its major axis; the row texture of the line marcher is this wide.
pub fn max_steps(eye: &Eye) -> u32 {
    eye.width.max(eye.height)
}

/// Clips the ray `origin + t dir`, `t` in `[t_min, t_max]`, to the view frustum (Liang-Barsky
/// on the six clip-space planes, in which the ray is linear in `t`) and projects it; `None`
/// when no part of it is in view.
///
/// The samples are one per pixel along the major axis, but at least one per `spacing` of ray
/// length (the paper's minimum line length for rays "almost parallel to the view direction"
/// that "only cover a very few fragments": a sample must not step over a surface's tolerance
/// window), and at most [`max_steps`] (the row buffer's width).
pub fn clip(
    eye: &Eye,
    origin: Vec3,
    dir: Vec3,
    (t_min, t_max): (f32, f32),
    spacing: f32,
) -> Option<Segment> {
    let a = eye.view_proj * origin.extend(1.0);
    let b = eye.view_proj * dir.extend(0.0);
    // Each plane f(c) >= 0: w + x, w - x, w + y, w - y, z, w - z.
    let planes = [
        (a.w + a.x, b.w + b.x),
        (a.w - a.x, b.w - b.x),
        (a.w + a.y, b.w + b.y),
        (a.w - a.y, b.w - b.y),
        (a.z, b.z),
        (a.w - a.z, b.w - b.z),
    ];
    let (mut t0, mut t1) = (t_min, t_max);
    for (fa, fb) in planes {
        if fb == 0.0 {
            if fa < 0.0 {
                return None;
            }
        } else {
            let t = -fa / fb;
            if fb > 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if !(t0 < t1) {
        return None;
    }
    let (c0, c1) = (a + b * t0, a + b * t1);
    if !(c0.w > 0.0 && c1.w > 0.0) {
        return None;
    }
    let (p0, p1) = (eye.pixel(c0), eye.pixel(c1));
    let span = (p1 - p0).abs();
    let along = ((t1 - t0) / spacing).ceil();
    let steps = (span.x.max(span.y).ceil().max(along).min(1e6) as u32).clamp(1, max_steps(eye));
    Some(Segment {
        origin,
        dir,
        t_start: t0,
        t_end: t1,
        w_start: c0.w,
        w_end: c1.w,
        p_start: p0,
        p_end: p1,
        steps,
    })
}

impl Segment {
    /// The ray parameter at screen fraction `s` of the projected segment: `1/w` is linear in
    /// screen space, so the fraction `u` of the clipped ray is `s w0 / ((1 - s) w1 + s w0)`.
    pub fn t_at(&self, s: f32) -> f32 {
        let u = s * self.w_start / ((1.0 - s) * self.w_end + s * self.w_start);
        self.t_start + u * (self.t_end - self.t_start)
    }

    /// Screen fraction of sample `k`.
    pub fn fraction(&self, k: u32) -> f32 {
        (k as f32 + 0.5) / self.steps as f32
    }

    /// The pixel of sample `k` (clamped to the screen).
    pub fn pixel(&self, eye: &Eye, k: u32) -> (u32, u32) {
        let p = self.p_start + (self.p_end - self.p_start) * self.fraction(k);
        (
            (p.x.floor().max(0.0) as u32).min(eye.width - 1),
            (p.y.floor().max(0.0) as u32).min(eye.height - 1),
        )
    }

    /// Distance from the eye of the ray point at parameter `t`.
    pub fn distance(&self, eye: &Eye, t: f32) -> f32 {
        (self.origin + self.dir * t - eye.position).length()
    }
}

/// The hit test at a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Test {
    /// The paper's: `|distance - layer distance| < tolerance` at the sample.
    Tolerance(f32),
    /// Engines' (McGuire and Mara): the ray's distance range over the sample's pixel overlaps
    /// `[layer distance, layer distance + thickness]`.
    Thickness(f32),
}

/// What a march found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit (the sample's).
    pub t: f32,
    pub x: u32,
    pub y: u32,
    pub layer: u32,
    /// Sample index along the segment.
    pub step: u32,
}

/// Which surfaces may stop a ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// A ray in air (or the medium outside glass): specular surfaces from their front.
    Outside,
    /// A ray inside glass: specular surfaces from their back (its way out).
    Inside,
    /// A shadow ray: any surface.
    Any,
}

/// The state of the ray being marched.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayState {
    pub side: Side,
    /// Samples with `t < t_skip` are not tested.
    pub t_skip: f32,
}

/// Whether a ray travelling along `dir` may stop at `texel`: any diffuse or metal surface
/// (opaque, two-sided); glass only from the side the ray is on (see the module
/// documentation); anything for a shadow ray.
pub fn side_ok(texel: &Texel, dir: Vec3, side: Side) -> bool {
    side == Side::Any || !texel.glass || ((texel.normal.dot(dir) > 0.0) == (side == Side::Inside))
}

/// The layer hit at sample `k` under `test`, if any: for the tolerance test the layer whose
/// distance is nearest the ray's, for the thickness test the first (nearest) layer that
/// overlaps.
pub fn test_sample(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    k: u32,
    test: Test,
    state: RayState,
) -> Option<Hit> {
    test_sample_gap(ldi, eye, seg, k, test, state).map(|(hit, _)| hit)
}

/// [`test_sample`] with the hit's gap: `|ray distance - layer distance|` for the tolerance
/// test, 0 for the thickness test.
fn test_sample_gap(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    k: u32,
    test: Test,
    state: RayState,
) -> Option<(Hit, f32)> {
    let s = seg.fraction(k);
    let t = seg.t_at(s);
    if t < state.t_skip {
        return None;
    }
    let (x, y) = seg.pixel(eye, k);
    let d = seg.distance(eye, t);
    let (lo, hi) = match test {
        Test::Tolerance(_) => (d, d),
        Test::Thickness(_) => {
            let half = 0.5 / seg.steps as f32;
            let da = seg.distance(eye, seg.t_at((s - half).max(0.0)));
            let db = seg.distance(eye, seg.t_at((s + half).min(1.0)));
            (da.min(db).min(d), da.max(db).max(d))
        }
    };
    let mut best: Option<(u32, f32)> = None;
    for layer in 0..ldi.layers {
        let texel = ldi.get(x, y, layer);
        if texel.distance <= 0.0 {
            break;
        }
        if !side_ok(&texel, seg.dir, state.side) {
            continue;
        }
        match test {
            Test::Tolerance(tolerance) => {
                let gap = (d - texel.distance).abs();
                if gap < tolerance && best.is_none_or(|(_, g)| gap < g) {
                    best = Some((layer, gap));
                }
            }
            Test::Thickness(thickness) => {
                if lo <= texel.distance + thickness && hi >= texel.distance {
                    best = Some((layer, 0.0));
                    break;
                }
            }
        }
    }
    best.map(|(layer, gap)| {
        let hit = Hit {
            t,
            x,
            y,
            layer,
            step: k,
        };
        (hit, gap)
    })
}

/// The paper's line march (section 2.1): every sample of the line is tested with the
/// tolerance test (one fragment each), then the row reduction (`reduce.wgsl`) keeps the first
/// run of hits and, within it, the sample nearest the crossing: from the run's first sample
/// it moves on while the next sample hits with a smaller gap (see the module documentation).
/// Returns the hit and the number of samples tested.
pub fn march_lines(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    tolerance: f32,
    state: RayState,
) -> (Option<Hit>, u32) {
    let tested: Vec<Option<(Hit, f32)>> = (0..seg.steps)
        .map(|k| test_sample_gap(ldi, eye, seg, k, Test::Tolerance(tolerance), state))
        .collect();
    (nearest_of_first_run(&tested), seg.steps)
}

/// The reduction of a row of tolerance-test results: the first hit, then each following hit
/// whose gap is smaller than the last one kept, up to the first that is not.
fn nearest_of_first_run(row: &[Option<(Hit, f32)>]) -> Option<Hit> {
    let first = row.iter().position(Option::is_some)?;
    let mut kept = row[first]?;
    for next in row[first + 1..].iter() {
        match next {
            Some(next) if next.1 < kept.1 => kept = *next,
            _ => break,
        }
    }
    Some(kept.0)
}

/// The DDA march: samples in order, the thickness test, stopping at the first hit. Returns
/// the hit and the number of samples tested.
pub fn march_dda(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    thickness: f32,
    state: RayState,
) -> (Option<Hit>, u32) {
    for k in 0..seg.steps {
        if let Some(hit) = test_sample(ldi, eye, seg, k, Test::Thickness(thickness), state) {
            return (Some(hit), k + 1);
        }
    }
    (None, seg.steps)
}

/// Section 4's refraction march through the LDI of one refractor: the `n`-th intersection
/// along a ray is assumed to be in layer `n + 1` ("monotonic" layers), so each sample reads
/// the layer the ray is between: `layer` (the next) and `layer - 1` (the current, the one it
/// entered through). The ray meets a surface where "the depth along the ray is either greater
/// than the depth in the next layer or less than the depth in the current layer": it passed
/// behind `layer` (the exit in the back) or came out in front of `layer - 1` (the exit through
/// a surface facing the eye, where a ray bent sideways leaves). Samples before `t_skip` are
/// not tested: the ray starts on a surface of one of the two layers. Returns the hit (its
/// `layer` says which of the two), or `None` when the ray leaves the view, or both layers'
/// pixels, first.
pub fn march_monotone(ldi: &Ldi, eye: &Eye, seg: &Segment, layer: u32, t_skip: f32) -> Option<Hit> {
    if layer >= ldi.layers {
        return None;
    }
    (0..seg.steps).find_map(|k| {
        let t = seg.t_at(seg.fraction(k));
        if t < t_skip {
            return None;
        }
        let (x, y) = seg.pixel(eye, k);
        let d = seg.distance(eye, t);
        let hit = |layer| Hit {
            t,
            x,
            y,
            layer,
            step: k,
        };
        let next = ldi.get(x, y, layer);
        if next.distance > 0.0 && d >= next.distance {
            return Some(hit(layer));
        }
        let current = ldi.get(x, y, layer.saturating_sub(1));
        (layer > 0 && current.distance > 0.0 && d <= current.distance).then(|| hit(layer - 1))
    })
}

/// Section 5's in-out test over consecutive layer pairs, at pixel `(x, y)` and distance `d`
/// from the eye: the layer `l` that opens a solid the point is inside, if any. A solid is
/// entered through a face turned to the eye (layer `l`) and left through the next layer, a
/// face turned away (`l + 1`); the point is inside when its distance lies between theirs.
/// The paper pairs the layers (0, 1), (2, 3), ...; the faces' orientation pairs them here,
/// so that an open surface (the pool's water, a floor) does not shift every pair behind it.
pub fn solid_layer_at(ldi: &Ldi, eye: &Eye, x: u32, y: u32, d: f32) -> Option<u32> {
    let view = eye.pixel_ray(x, y);
    // The pairs before the first empty layer (the WGSL stops there too).
    let filled = (0..ldi.layers.saturating_sub(1))
        .take_while(|&l| ldi.get(x, y, l).distance > 0.0 && ldi.get(x, y, l + 1).distance > 0.0);
    filled.into_iter().find(|&l| {
        let (front, back) = (ldi.get(x, y, l), ldi.get(x, y, l + 1));
        front.normal.dot(view) < 0.0
            && back.normal.dot(view) > 0.0
            && front.distance <= d
            && d <= back.distance
    })
}

/// The paper's screen-space shadow ray (section 5, figures 11 and 12) with the in-out test it
/// proposes: the first sample at which a layer lies within the tolerance of the ray (any
/// surface, glass included) or the ray is inside a solid ([`solid_layer_at`]). The tolerance
/// test alone misses a thick occluder whenever the samples step over both of its faces' windows
/// ("the artifacts in the shadow of some of the thick branches"); inside it, the in-out test
/// finds every sample. Samples before `t_skip` are not tested.
pub fn march_shadow(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    tolerance: f32,
    t_skip: f32,
) -> Option<Hit> {
    let any = RayState {
        side: Side::Any,
        t_skip,
    };
    (0..seg.steps).find_map(|k| {
        if let Some(hit) = test_sample(ldi, eye, seg, k, Test::Tolerance(tolerance), any) {
            return Some(hit);
        }
        let t = seg.t_at(seg.fraction(k));
        if t < t_skip {
            return None;
        }
        let (x, y) = seg.pixel(eye, k);
        let layer = solid_layer_at(ldi, eye, x, y, seg.distance(eye, t))?;
        Some(Hit {
            t,
            x,
            y,
            layer,
            step: k,
        })
    })
}

/// Whether the monotone-layer assumption held for a ray inside a refractor: the first surface
/// it leaves through, found by the DDA over every layer (the thickness test, back faces only:
/// [`Side::Inside`]), is in the layer the monotone march stops at (`layer` or `layer - 1`;
/// or neither finds one). A `false` is a violation: the monotone march reads the wrong
/// surface (another refractor in front, a concave refractor, a ray bent across a
/// silhouette). `thickness` and `t_skip` are the DDA's.
pub fn monotone_holds(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    layer: u32,
    thickness: f32,
    t_skip: f32,
) -> bool {
    let inside = RayState {
        side: Side::Inside,
        t_skip,
    };
    let dda = march_dda(ldi, eye, seg, thickness, inside).0;
    let monotone = march_monotone(ldi, eye, seg, layer, t_skip);
    dda.map(|h| h.layer) == monotone.map(|h| h.layer)
}

/// The brute-force answer the marchers are held to, written apart from [`test_sample`]: every
/// sample and every layer are examined (no early exit, no skipping past an empty layer's
/// followers), each hit condition spelled out again. For the thickness test the hit with the
/// smallest `t` is returned (the nearest overlapping layer there); for the tolerance test the
/// first sample that hits (the layer nearest the ray's distance there), then each next sample
/// for as long as it hits with a smaller gap.
pub fn first_hit_brute(
    ldi: &Ldi,
    eye: &Eye,
    seg: &Segment,
    test: Test,
    state: RayState,
) -> Option<Hit> {
    // Each sample's hit, with the gap (tolerance) or the layer (thickness) that ranks it.
    let mut per_sample: Vec<Option<(Hit, f32)>> = vec![None; seg.steps as usize];
    for k in 0..seg.steps {
        let s = (k as f32 + 0.5) / seg.steps as f32;
        let t = seg.t_at(s);
        if t < state.t_skip {
            continue;
        }
        let p = seg.p_start + (seg.p_end - seg.p_start) * s;
        let x = (p.x.floor().max(0.0) as u32).min(eye.width - 1);
        let y = (p.y.floor().max(0.0) as u32).min(eye.height - 1);
        let d = (seg.origin + seg.dir * t - eye.position).length();
        // The layers before the first empty one: what the peeler wrote at this pixel.
        let filled = (0..ldi.layers).take_while(|&l| ldi.get(x, y, l).distance > 0.0);
        for layer in filled {
            let texel = ldi.get(x, y, layer);
            let facing_out = texel.normal.dot(seg.dir) > 0.0;
            let allowed = match state.side {
                Side::Any => true,
                _ if !texel.glass => true,
                Side::Inside => facing_out,
                Side::Outside => !facing_out,
            };
            if !allowed {
                continue;
            }
            let rank = match test {
                Test::Tolerance(tolerance) => {
                    let gap = (d - texel.distance).abs();
                    if gap >= tolerance {
                        continue;
                    }
                    gap
                }
                Test::Thickness(thickness) => {
                    let half = 0.5 / seg.steps as f32;
                    let ends = [seg.t_at((s - half).max(0.0)), seg.t_at((s + half).min(1.0))]
                        .map(|t| (seg.origin + seg.dir * t - eye.position).length());
                    let lo = ends[0].min(ends[1]).min(d);
                    let hi = ends[0].max(ends[1]).max(d);
                    if lo > texel.distance + thickness || hi < texel.distance {
                        continue;
                    }
                    // The first overlapping layer wins: order by layer.
                    layer as f32
                }
            };
            let hit = Hit {
                t,
                x,
                y,
                layer,
                step: k,
            };
            let slot = &mut per_sample[k as usize];
            if slot.is_none_or(|(_, r)| rank < r) {
                *slot = Some((hit, rank));
            }
        }
    }
    let mut k = per_sample.iter().position(|h| h.is_some())?;
    if let Test::Tolerance(_) = test {
        // Walk down the gap while it keeps shrinking.
        while let (Some((_, here)), Some(Some((_, next)))) = (per_sample[k], per_sample.get(k + 1))
        {
            if *next >= here {
                break;
            }
            k += 1;
        }
    }
    per_sample[k].map(|(h, _)| h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene::Camera;

    fn eye() -> Eye {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            orthographic: None,
        };
        Eye {
            view_proj: cam.view_proj(64, 48),
            position: cam.eye,
            width: 64,
            height: 48,
        }
    }

    #[test]
    fn a_ray_across_the_view_covers_one_sample_per_pixel() {
        let e = eye();
        let seg = clip(&e, Vec3::new(-50.0, 0.0, 0.0), Vec3::X, (0.0, 100.0), 100.0).unwrap();
        assert_eq!(seg.steps, 64);
        assert!(seg.p_start.x.abs() < 1e-3 && (seg.p_end.x - 64.0).abs() < 1e-3);
        let (x0, _) = seg.pixel(&e, 0);
        let (x1, _) = seg.pixel(&e, 63);
        assert_eq!((x0, x1), (0, 63));
    }

    #[test]
    fn a_ray_behind_the_eye_is_not_in_view() {
        let e = eye();
        assert!(clip(&e, Vec3::new(0.0, 0.0, 6.0), Vec3::Z, (0.0, 100.0), 1.0).is_none());
    }

    #[test]
    fn t_at_inverts_the_projection() {
        let e = eye();
        let dir = Vec3::new(0.3, 0.2, -1.0).normalize();
        let seg = clip(&e, Vec3::new(-1.0, -0.5, 2.0), dir, (0.0, 20.0), 1.0).unwrap();
        for s in [0.1, 0.37, 0.8] {
            let t = seg.t_at(s);
            let p = seg.origin + seg.dir * t;
            let c = e.view_proj * p.extend(1.0);
            let expect = seg.p_start + (seg.p_end - seg.p_start) * s;
            assert!((e.pixel(c) - expect).length() < 1e-3, "{s}");
        }
    }
}
