//! The search in a refractor height map (paper section 6): the Rust twin of
//! `shaders/height_search.wgsl` (same algorithm, constants and names).
//!
//! A piece with a plane of symmetry is stored as a *height map*: an orthographic picture taken
//! perpendicular to that plane, holding per texel the distance `h(u, v)` of the surface from
//! the plane and its normal. By symmetry the piece is the solid `|w| < h(u, v)` in the frame
//! `(u, v, w)` of the plane (`u` across, `v` up, `w` out of the plane). At render time the map
//! stands on a *billboard* through the piece's centre, turned about the vertical axis to face
//! the ray's origin ([`Billboard::facing`]), so rays meet it at moderate angles.
//!
//! A ray is searched from outside in three steps:
//!
//! 1. *Segment selection* ([`select_segment`], the paper's figure 7): the distances to the
//!    plane (`d_plane`) and to the bounding box of the proxy (`d_near < d_far`). Case 1:
//!    `d_near <= d_plane <= d_far`, the segment in front of the plane `[d_near, d_plane]`.
//!    Case 2: the ray leaves the box before the plane, `[d_near, d_far]`. Case 3a: the plane
//!    lies before the box (`d_plane < d_near`), the whole segment is behind the plane; it is
//!    reflected through the plane (3b), which for the symmetric solid means evaluating the
//!    height test with `|w|`.
//! 2. *Binary search* ([`binary_search`]) on the segment for the change from outside to
//!    inside, `steps.binary` halvings. It assumes that the segment's start is outside and its
//!    end inside; when the end is outside the search fails. It returns *a* crossing, not
//!    necessarily the first. With `steps.linear > 0` (not in the paper: relief mapping's
//!    bracket, Policarpo et al. 2005) the segment is first sampled at `steps.linear` even
//!    steps and the binary search runs between the first sample inside and the one before.
//! 3. *The second search behind the plane*: when case 1's search fails, `[d_plane, d_far]`
//!    (reflected) is searched. A hit behind the plane has its normal reflected back through
//!    the plane of symmetry (`n_w -> -n_w`).
//!
//! A ray inside the piece (after refraction) finds its exit with the same binary search on
//! `[0, d_far]`, from inside to outside ([`exit_from_inside`]).

use glam::{Vec2, Vec3};
use gpu::prelude::{BIG, ray_box};

/// WGSL of the search: the module `height_maps::search` ([`SEARCH`]); its searches read the
/// maps their caller passes (the twin's `field`).
pub const HEIGHT_SEARCH_WGSL: &str = include_str!("shaders/height_search.wgsl");
/// [`HEIGHT_SEARCH_WGSL`] as a module, which the billboards, the object search of the chess
/// variants and the conformance kernel import.
pub static SEARCH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    HEIGHT_SEARCH_WGSL,
    "height-maps/src/shaders/height_search.wgsl",
    &[],
);

/// The steps of a search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Steps {
    /// Even samples along a segment before the binary search (0: the paper's search, binary
    /// only).
    pub linear: u32,
    /// Halvings of the binary search.
    pub binary: u32,
}

impl Steps {
    /// The paper's search: `binary` halvings, no linear bracket.
    pub const fn paper(binary: u32) -> Self {
        Self { linear: 0, binary }
    }
}

/// Rays whose direction has a `w` component below this are parallel to the plane.
pub const PARALLEL: f32 = 1e-6;

/// The proxy's extent in the plane's frame, relative to the piece's centre: `u` in
/// `[-half_width, half_width]`, `v` in `[v_min, v_max]`, `|w| <= height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Half the width across the plane (`u`).
    pub half_width: f32,
    /// Lowest and highest `v`.
    pub v_min: f32,
    /// See `v_min`.
    pub v_max: f32,
    /// Largest height above the plane (`w`).
    pub height: f32,
}

impl Bounds {
    /// The proxy's bounding box `(min, max)` in the plane's frame.
    pub fn box_corners(&self) -> (Vec3, Vec3) {
        (
            Vec3::new(-self.half_width, self.v_min, -self.height),
            Vec3::new(self.half_width, self.v_max, self.height),
        )
    }

    /// The height a map stores where there is no surface: below the plane by the whole
    /// height, so that a bilinear lookup between a covered and an empty texel crosses zero
    /// inside the texel (a smooth silhouette).
    pub fn empty_height(&self) -> f32 {
        -self.height
    }

    /// Map coordinates `(s, t)` in `[0, 1]` of plane point `(u, v)` (`t = 0` at the top row).
    pub fn map_coords(&self, u: f32, v: f32) -> Vec2 {
        Vec2::new(
            (u + self.half_width) / (2.0 * self.half_width),
            (self.v_max - v) / (self.v_max - self.v_min),
        )
    }
}

/// What a refractor height map answers: the height of the surface above the plane of
/// symmetry at plane point `(u, v)` (negative where there is none) and the surface normal
/// there, in the plane's frame, for the half in front of the plane (`w > 0`).
pub trait HeightField {
    /// The proxy's extent.
    fn bounds(&self) -> Bounds;
    /// `(height, normal)` at `(u, v)`; the normal need not be unit length.
    fn sample(&self, u: f32, v: f32) -> (f32, Vec3);
}

/// Whether plane-frame point `p` lies inside the solid `|w| < h(u, v)`.
pub fn inside<F: HeightField + ?Sized>(field: &F, p: Vec3) -> bool {
    p.z.abs() < field.sample(p.x, p.y).0
}

/// A billboard: the plane of symmetry through `centre`, turned about the vertical axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Billboard {
    /// Where the plane stands (the piece's centre), world.
    pub centre: Vec3,
    /// Unit axes of the plane's frame in the world: `u` across, `v` up, `w` out of the plane.
    pub u: Vec3,
    /// See `u`.
    pub v: Vec3,
    /// See `u`.
    pub w: Vec3,
}

impl Billboard {
    /// The billboard at `centre` whose `w` axis points horizontally toward `origin` (straight
    /// above or below the centre: toward +z).
    pub fn facing(centre: Vec3, origin: Vec3) -> Self {
        let to = Vec3::new(origin.x - centre.x, 0.0, origin.z - centre.z);
        let w = if to.length() > 1e-6 {
            to / to.length()
        } else {
            Vec3::Z
        };
        let v = Vec3::Y;
        Self {
            centre,
            u: v.cross(w),
            v,
            w,
        }
    }

    /// World point -> plane frame.
    pub fn to_plane(&self, p: Vec3) -> Vec3 {
        self.dir_to_plane(p - self.centre)
    }

    /// World direction -> plane frame.
    pub fn dir_to_plane(&self, d: Vec3) -> Vec3 {
        Vec3::new(d.dot(self.u), d.dot(self.v), d.dot(self.w))
    }

    /// Plane-frame direction -> world.
    pub fn dir_to_world(&self, d: Vec3) -> Vec3 {
        self.u * d.x + self.v * d.y + self.w * d.z
    }
}

/// Which part of the ray the search examines (figure 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Case {
    /// Case 1: the ray meets the plane inside the box; `[near, plane]` first, then
    /// `[plane, far]` reflected.
    InFront,
    /// Case 2: the ray leaves the box before the plane (or never meets it): `[near, far]`.
    BoxInFront,
    /// Cases 3a/3b: the plane lies before the box: `[near, far]`, behind the plane, reflected.
    Behind,
}

/// The distances along the ray that select its segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segments {
    /// Which case of figure 7.
    pub case: Case,
    /// Where the ray enters the box (0 if it starts inside).
    pub near: f32,
    /// Where it meets the plane ([`BIG`] when parallel or behind the origin).
    pub plane: f32,
    /// Where it leaves the box.
    pub far: f32,
}

/// The segment selection of figure 7 for the ray `o + t d` in the plane's frame, `None` when
/// it misses the box.
pub fn select_segment(o: Vec3, d: Vec3, bounds: &Bounds) -> Option<Segments> {
    let (bmin, bmax) = bounds.box_corners();
    let hit = ray_box(o, d, bmin, bmax);
    if hit.x > hit.y || hit.y < 0.0 {
        return None;
    }
    let near = hit.x.max(0.0);
    let far = hit.y;
    let plane = if d.z.abs() < PARALLEL {
        BIG
    } else {
        let t = -o.z / d.z;
        if t >= 0.0 { t } else { BIG }
    };
    let case = if plane < near {
        Case::Behind
    } else if plane <= far {
        Case::InFront
    } else {
        Case::BoxInFront
    };
    Some(Segments {
        case,
        near,
        plane,
        far,
    })
}

/// Binary search on `[a, b]` along `o + t d` for the boundary of the solid: `steps` halvings
/// keeping `a` on the start's side and `b` on the other (`entering`: `a` outside, `b`
/// inside; else the reverse). Returns the final bracket's midpoint.
pub fn binary_search<F: HeightField + ?Sized>(
    field: &F,
    o: Vec3,
    d: Vec3,
    a: f32,
    b: f32,
    steps: u32,
    entering: bool,
) -> f32 {
    let (mut a, mut b) = (a, b);
    for _ in 0..steps {
        let m = 0.5 * (a + b);
        if inside(field, o + d * m) == entering {
            b = m;
        } else {
            a = m;
        }
    }
    0.5 * (a + b)
}

/// One segment's search for the boundary (from outside when `entering`, else from inside):
/// its start if that is already on the far side (the box face is the surface
/// there); with a linear bracket, the binary search between the first sample on the far side
/// and the one before; without, nothing if its end is on the start's side, else the binary
/// search over the whole segment.
fn search_segment<F: HeightField + ?Sized>(
    field: &F,
    o: Vec3,
    d: Vec3,
    a: f32,
    b: f32,
    steps: Steps,
    entering: bool,
) -> Option<f32> {
    // An entry whose start is inside: the box face is the surface there. (An exit starts
    // where an entry was found, within the bisection's tolerance of the surface: it is taken
    // to be inside.)
    if entering && inside(field, o + d * a) {
        return Some(a);
    }
    if steps.linear == 0 {
        if inside(field, o + d * b) != entering {
            return None;
        }
        return Some(binary_search(field, o, d, a, b, steps.binary, entering));
    }
    let dt = (b - a) / steps.linear as f32;
    let mut previous = a;
    for k in 1..=steps.linear {
        let t = if k == steps.linear {
            b
        } else {
            a + dt * k as f32
        };
        if inside(field, o + d * t) == entering {
            return Some(binary_search(
                field,
                o,
                d,
                previous,
                t,
                steps.binary,
                entering,
            ));
        }
        previous = t;
    }
    None
}

/// A point found on the proxy: ray parameter, plane-frame point and unit normal (reflected
/// through the plane for a point behind it; outward).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightHit {
    /// Ray parameter.
    pub t: f32,
    /// The point in the plane's frame.
    pub point: Vec3,
    /// Unit outward normal in the plane's frame.
    pub normal: Vec3,
}

/// The outward normal of the box face nearest to plane-frame point `p`: where the solid
/// reaches its box (the flat underside of a piece's base, edge-on to the map and so absent
/// from it), the box face is the surface.
pub fn box_face_normal(bounds: &Bounds, p: Vec3) -> Vec3 {
    let (lo, hi) = bounds.box_corners();
    let faces = [
        (p.x - lo.x, Vec3::NEG_X),
        (hi.x - p.x, Vec3::X),
        (p.y - lo.y, Vec3::NEG_Y),
        (hi.y - p.y, Vec3::Y),
        (p.z - lo.z, Vec3::NEG_Z),
        (hi.z - p.z, Vec3::Z),
    ];
    let mut best = faces[0];
    for f in &faces[1..] {
        if f.0.abs() < best.0.abs() {
            best = *f;
        }
    }
    best.1
}

/// A hit where the solid reaches the box face: that face's normal.
fn box_face_hit<F: HeightField + ?Sized>(field: &F, o: Vec3, d: Vec3, t: f32) -> HeightHit {
    let point = o + d * t;
    HeightHit {
        t,
        point,
        normal: box_face_normal(&field.bounds(), point),
    }
}

fn height_hit<F: HeightField + ?Sized>(field: &F, o: Vec3, d: Vec3, t: f32) -> HeightHit {
    let point = o + d * t;
    let n = field.sample(point.x, point.y).1;
    let n = if point.z < 0.0 {
        Vec3::new(n.x, n.y, -n.z)
    } else {
        n
    };
    HeightHit {
        t,
        point,
        normal: if n.length() > 1e-6 {
            n.normalize()
        } else {
            -d.normalize_or_zero()
        },
    }
}

/// The first surface along `o + t d` (plane frame, origin outside the solid) by the paper's
/// search: segment selection, binary search, the second search behind the plane.
pub fn search_from_outside<F: HeightField + ?Sized>(
    field: &F,
    o: Vec3,
    d: Vec3,
    steps: Steps,
) -> Option<HeightHit> {
    let s = select_segment(o, d, &field.bounds())?;
    let first_end = match s.case {
        Case::InFront => s.plane,
        Case::BoxInFront | Case::Behind => s.far,
    };
    let t = search_segment(field, o, d, s.near, first_end, steps, true).or_else(|| {
        (s.case == Case::InFront)
            .then(|| search_segment(field, o, d, s.plane, s.far, steps, true))
            .flatten()
    })?;
    if t == s.near && inside(field, o + d * t) {
        return Some(box_face_hit(field, o, d, t));
    }
    Some(height_hit(field, o, d, t))
}

/// Where a ray from `o` inside the solid leaves it (plane frame): the same search from
/// inside to outside on `[0, d_far]`; the box face itself, with its normal, when the solid
/// reaches it there.
pub fn exit_from_inside<F: HeightField + ?Sized>(
    field: &F,
    o: Vec3,
    d: Vec3,
    steps: Steps,
) -> Option<HeightHit> {
    let (bmin, bmax) = field.bounds().box_corners();
    let far = ray_box(o, d, bmin, bmax).y;
    if !(far > 0.0) || far >= BIG {
        return None;
    }
    match search_segment(field, o, d, 0.0, far, steps, false) {
        Some(t) => Some(height_hit(field, o, d, t)),
        // Still inside where the ray leaves the box: out through the box face.
        None => Some(box_face_hit(field, o, d, far)),
    }
}

/// A height map's texels sampled like the shader: bilinear between texel centres, clamped at
/// the edges, empty outside the map. Texel `(i, j)` holds `(normal.xyz, height)`, row 0 at
/// the top (`v_max`).
#[derive(Clone, Debug, PartialEq)]
pub struct SampledField {
    /// The proxy's extent.
    pub bounds: Bounds,
    /// Texels across (`u`) and down (`v`).
    pub width: u32,
    /// See `width`.
    pub height: u32,
    /// `width * height` texels, row by row from the top.
    pub texels: Vec<[f32; 4]>,
}

impl SampledField {
    /// The field of `h(u, v)` and its normal sampled at texel centres; `None` from `f` is no
    /// surface.
    pub fn from_fn(
        bounds: Bounds,
        width: u32,
        height: u32,
        f: impl Fn(f32, f32) -> Option<(f32, Vec3)>,
    ) -> Self {
        let mut texels = Vec::with_capacity((width * height) as usize);
        for j in 0..height {
            for i in 0..width {
                let s = (i as f32 + 0.5) / width as f32;
                let t = (j as f32 + 0.5) / height as f32;
                let u = -bounds.half_width + s * 2.0 * bounds.half_width;
                let v = bounds.v_max - t * (bounds.v_max - bounds.v_min);
                texels.push(match f(u, v) {
                    Some((h, n)) => [n.x, n.y, n.z, h],
                    None => [0.0, 0.0, 0.0, bounds.empty_height()],
                });
            }
        }
        Self {
            bounds,
            width,
            height,
            texels,
        }
    }

    fn texel(&self, i: i32, j: i32) -> [f32; 4] {
        let i = i.clamp(0, self.width as i32 - 1) as usize;
        let j = j.clamp(0, self.height as i32 - 1) as usize;
        self.texels[j * self.width as usize + i]
    }
}

impl HeightField for SampledField {
    fn bounds(&self) -> Bounds {
        self.bounds
    }

    fn sample(&self, u: f32, v: f32) -> (f32, Vec3) {
        let c = self.bounds.map_coords(u, v);
        if c.x < 0.0 || c.y < 0.0 || c.x > 1.0 || c.y > 1.0 {
            return (self.bounds.empty_height(), Vec3::ZERO);
        }
        let x = c.x * self.width as f32 - 0.5;
        let y = c.y * self.height as f32 - 0.5;
        let (i, j) = (x.floor(), y.floor());
        let (fx, fy) = (x - i, y - j);
        let (i, j) = (i as i32, j as i32);
        let lerp = |a: [f32; 4], b: [f32; 4], f: f32| -> [f32; 4] {
            [0, 1, 2, 3].map(|k| a[k] + (b[k] - a[k]) * f)
        };
        let top = lerp(self.texel(i, j), self.texel(i + 1, j), fx);
        let bottom = lerp(self.texel(i, j + 1), self.texel(i + 1, j + 1), fx);
        let t = lerp(top, bottom, fy);
        (t[3], Vec3::new(t[0], t[1], t[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball() -> SampledField {
        let bounds = Bounds {
            half_width: 1.0,
            v_min: -1.0,
            v_max: 1.0,
            height: 1.0,
        };
        SampledField::from_fn(bounds, 64, 64, |u, v| {
            let h2 = 1.0 - u * u - v * v;
            (h2 > 0.0).then(|| (h2.sqrt(), Vec3::new(u, v, h2.sqrt())))
        })
    }

    #[test]
    fn the_cases_of_figure_7() {
        let b = ball().bounds;
        // Straight at the plane: case 1.
        let s = select_segment(Vec3::new(0.0, 0.0, 3.0), Vec3::NEG_Z, &b).unwrap();
        assert_eq!(s.case, Case::InFront);
        assert_eq!((s.near, s.plane, s.far), (2.0, 3.0, 4.0));
        // Parallel to the plane through the box: case 2, the plane never met.
        let s = select_segment(Vec3::new(-3.0, 0.0, 0.5), Vec3::X, &b).unwrap();
        assert_eq!(s.case, Case::BoxInFront);
        assert_eq!(s.plane, BIG);
        // Crossing the plane beside the box, then into it from behind: case 3.
        let d = Vec3::new(1.0, 0.0, -1.0).normalize();
        let s = select_segment(Vec3::new(-3.5, 0.0, 1.5), d, &b).unwrap();
        assert_eq!(s.case, Case::Behind);
        assert!(s.plane < s.near);
        // Past the box: nothing.
        assert!(select_segment(Vec3::new(0.0, 3.0, 3.0), Vec3::NEG_Z, &b).is_none());
    }

    #[test]
    fn a_ray_at_the_ball_finds_its_front() {
        let f = ball();
        let h = search_from_outside(&f, Vec3::new(0.0, 0.0, 3.0), Vec3::NEG_Z, Steps::paper(16))
            .unwrap();
        assert!((h.t - 2.0).abs() < 1e-3, "{h:?}");
        assert!((h.normal - Vec3::Z).length() < 1e-2);
        let e = exit_from_inside(&f, h.point, Vec3::NEG_Z, Steps::paper(16)).unwrap();
        assert!((e.point.z + 1.0).abs() < 1e-2, "{e:?}");
        assert!(
            (e.normal - Vec3::NEG_Z).length() < 1e-2,
            "reflected normal {e:?}"
        );
    }

    #[test]
    fn the_billboard_faces_the_origin() {
        let b = Billboard::facing(Vec3::new(1.0, 0.5, 0.0), Vec3::new(1.0, 3.0, 2.0));
        assert!((b.w - Vec3::Z).length() < 1e-6);
        assert!((b.u.cross(b.v) - b.w).length() < 1e-6, "right-handed");
        let p = Vec3::new(1.2, 0.7, 0.3);
        let q = b.to_plane(p);
        assert!((b.centre + b.dir_to_world(q) - p).length() < 1e-6);
        // Straight above: a fixed axis, not NaN.
        let b = Billboard::facing(Vec3::ZERO, Vec3::Y);
        assert!(b.u.is_finite() && b.w == Vec3::Z);
    }
}
