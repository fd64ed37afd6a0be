//! Rust twin of `shaders/prelude.wgsl`: the same functions, same names, same constants.
//! The CPU reference renderer uses these, so the reference and every technique agree on
//! Fresnel and on cube-map addressing by construction; `tests/prelude_conformance.rs` runs the
//! WGSL versions in a compute shader and compares them with these.

use glam::{IVec2, Vec2, Vec3, Vec4};

/// The WGSL prelude source, the module `gpu::prelude`: a shader takes what it uses with
/// `#import gpu::prelude::{PI, ray_box}` (see [`crate::wgsl`]).
pub const PRELUDE_WGSL: &str = include_str!("shaders/prelude.wgsl");
/// The prelude as a module (always available to [`crate::shader`]).
pub static PRELUDE: crate::wgsl::Module =
    crate::wgsl::Module::new(PRELUDE_WGSL, "gpu/src/shaders/prelude.wgsl", &[]);

pub const PI: f32 = std::f32::consts::PI;
/// Empty interval returned by [`ray_sphere`] and [`ray_box`] on a miss (t_near > t_far).
pub const MISS: Vec2 = Vec2::new(1.0, -1.0);
/// Stand-in for infinity (WGSL implementations may assume no infinities): the bound of a slab
/// that does not limit a ray in [`ray_box`].
pub const BIG: f32 = 1e30;

/// Ray / plane `dot(n, x) = c`: the ray parameter, or -1 when the ray is parallel.
pub fn ray_plane(o: Vec3, d: Vec3, n: Vec3, c: f32) -> f32 {
    let denom = n.dot(d);
    if denom.abs() < 1e-12 {
        return -1.0;
    }
    (c - n.dot(o)) / denom
}

/// Ray / sphere: (t_near, t_far) or [`MISS`].
pub fn ray_sphere(o: Vec3, d: Vec3, center: Vec3, radius: f32) -> Vec2 {
    let oc = o - center;
    let b = oc.dot(d);
    let c = oc.dot(oc) - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return MISS;
    }
    let s = disc.sqrt();
    Vec2::new(-b - s, -b + s)
}

/// Ray / axis-aligned box by slabs: (t_near, t_far) or [`MISS`]. A direction component below
/// 1e-30 in magnitude is "flat": its slab does not limit t when the origin lies in it (boundary
/// planes included: the box is closed) and empties the interval otherwise, so there is no
/// division by zero and no NaN (an origin on a slab plane would give 0 * inf).
#[inline]
pub fn ray_box(o: Vec3, d: Vec3, bmin: Vec3, bmax: Vec3) -> Vec2 {
    let flat = d.abs().cmplt(Vec3::splat(1e-30));
    let inside = o.cmpge(bmin) & o.cmple(bmax);
    let inv = Vec3::select(flat, Vec3::ONE, d).recip();
    let t0 = (bmin - o) * inv;
    let t1 = (bmax - o) * inv;
    let open = Vec3::select(inside, Vec3::splat(-BIG), Vec3::splat(BIG));
    let tmin = Vec3::select(flat, open, t0.min(t1));
    let tmax = Vec3::select(flat, -open, t0.max(t1));
    let t_near = tmin.max_element();
    let t_far = tmax.min_element();
    if t_near > t_far {
        return MISS;
    }
    Vec2::new(t_near, t_far)
}

/// Parallax-corrected ("box-projected") cube-map lookup (Lagarde and Zanuttini 2012, the
/// localized reflection probes of Unreal, Unity and Bevy): the ray `x + t r` is intersected
/// with the proxy box `[bmin, bmax]` and the cube map captured at `probe` is looked up toward
/// the point where the ray leaves the box. Returns (exit point - probe, t_exit): xyz is the
/// unnormalised lookup direction. When the ray leaves the box nowhere ahead of `x` (x outside,
/// the box behind or missed) or exits at the probe itself, the direction-only lookup
/// `(r, -1)` is returned.
pub fn box_project(x: Vec3, r: Vec3, probe: Vec3, bmin: Vec3, bmax: Vec3) -> Vec4 {
    let t = ray_box(x, r, bmin, bmax);
    if t.x > t.y || t.y <= 0.0 {
        return r.extend(-1.0);
    }
    let l = x + r * t.y - probe;
    if l.dot(l) < 1e-12 {
        return r.extend(-1.0);
    }
    l.extend(t.y)
}

/// A walk through a uniform grid of square cells on the xz plane by a ray, in the order the
/// ray crosses them (2D DDA, Amanatides and Woo 1987): cell `(i, j)` spans
/// `[min + (i, j) size, min + (i + 1, j + 1) size]` in x and z, unbounded in y. The
/// many-object tracer of refractor maps looks for the first non-empty square of a chessboard
/// this way (Dancsik and Minarik, section 4.2). The walk is over once `t_enter >= t_end`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridWalk {
    /// The current cell (column along x, row along z).
    pub cell: IVec2,
    /// Where the ray enters the current cell (clipped to `t >= 0`).
    pub t_enter: f32,
    /// Where it leaves it (the next boundary, or the grid's end).
    pub t_exit: f32,
    /// +1 / -1 per axis in the ray's direction, 0 for a flat component.
    pub step: IVec2,
    /// Ray parameters of the next x and z cell boundaries.
    pub t_next: Vec2,
    /// Ray parameter between two boundaries per axis ([`BIG`] when flat).
    pub t_delta: Vec2,
    /// Where the ray leaves the grid's rectangle.
    pub t_end: f32,
}

impl GridWalk {
    /// Whether the walk has left the grid (or never entered it).
    pub fn done(&self) -> bool {
        self.t_enter >= self.t_end
    }
}

/// Starts the walk of the ray `o + t d` through the grid of `count` cells of side `size` from
/// `grid_min` (x, z): the first cell is where the ray enters the grid's rectangle, or the cell
/// holding `o` when it starts inside. A ray missing the rectangle (or with it behind) gives a
/// finished walk. A direction component below 1e-30 in magnitude never steps.
pub fn grid_walk(o: Vec3, d: Vec3, grid_min: Vec2, size: f32, count: IVec2) -> GridWalk {
    let grid_max = grid_min + size * count.as_vec2();
    let t = ray_box(
        o,
        d,
        Vec3::new(grid_min.x, -BIG, grid_min.y),
        Vec3::new(grid_max.x, BIG, grid_max.y),
    );
    if t.x > t.y || t.y <= 0.0 || count.x <= 0 || count.y <= 0 {
        return GridWalk {
            cell: IVec2::ZERO,
            t_enter: BIG,
            t_exit: BIG,
            step: IVec2::ZERO,
            t_next: Vec2::ZERO,
            t_delta: Vec2::ZERO,
            t_end: BIG,
        };
    }
    let t_enter = t.x.max(0.0);
    let p = Vec2::new(o.x, o.z) + Vec2::new(d.x, d.z) * t_enter;
    let cell = ((p - grid_min) / size)
        .floor()
        .as_ivec2()
        .clamp(IVec2::ZERO, count - 1);
    let dxz = Vec2::new(d.x, d.z);
    let flat = dxz.abs().cmplt(Vec2::splat(1e-30));
    let step = IVec2::select(
        flat,
        IVec2::ZERO,
        IVec2::select(dxz.cmpgt(Vec2::ZERO), IVec2::ONE, IVec2::NEG_ONE),
    );
    let boundary = grid_min
        + size * (cell + IVec2::select(step.cmpgt(IVec2::ZERO), IVec2::ONE, IVec2::ZERO)).as_vec2();
    let safe = Vec2::select(flat, Vec2::ONE, dxz);
    let t_next = Vec2::select(
        flat,
        Vec2::splat(BIG),
        (boundary - Vec2::new(o.x, o.z)) / safe,
    );
    let t_delta = Vec2::select(flat, Vec2::splat(BIG), size / safe.abs());
    GridWalk {
        cell,
        t_enter,
        t_exit: t_next.x.min(t_next.y).min(t.y),
        step,
        t_next,
        t_delta,
        t_end: t.y,
    }
}

/// The next cell of the walk: across the nearer boundary (x first on a tie). Leaving the grid
/// finishes the walk.
pub fn grid_walk_next(w: GridWalk, count: IVec2) -> GridWalk {
    let mut w = w;
    if w.t_next.x <= w.t_next.y {
        w.cell.x += w.step.x;
        w.t_enter = w.t_next.x;
        w.t_next.x += w.t_delta.x;
    } else {
        w.cell.y += w.step.y;
        w.t_enter = w.t_next.y;
        w.t_next.y += w.t_delta.y;
    }
    if w.cell.cmplt(IVec2::ZERO).any() || w.cell.cmpge(count).any() {
        w.t_enter = w.t_end;
    }
    w.t_exit = w.t_next.x.min(w.t_next.y).min(w.t_end);
    w
}

/// Mirror direction of `i` about unit normal `n`.
pub fn reflect_dir(i: Vec3, n: Vec3) -> Vec3 {
    i - 2.0 * n.dot(i) * n
}

/// Snell refraction, `eta = n_incident / n_transmitted`, `n` facing against `i`.
/// Returns (direction, 1) or on total internal reflection (reflected direction, 0).
pub fn refract_dir(i: Vec3, n: Vec3, eta: f32) -> Vec4 {
    let cos_i = -n.dot(i);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return reflect_dir(i, n).extend(0.0);
    }
    (eta * i + (eta * cos_i - k.sqrt()) * n)
        .normalize()
        .extend(1.0)
}

/// The seeds' Fresnel approximation with refractive index `n` and extinction `k` per channel.
pub fn fresnel_nk(cos_theta: f32, n: Vec3, k: Vec3) -> Vec3 {
    let c = cos_theta.clamp(0.0, 1.0);
    let m = (1.0 - c).powf(5.0);
    let k2 = k * k;
    ((n - 1.0) * (n - 1.0) + k2 + 4.0 * n * m) / ((n + 1.0) * (n + 1.0) + k2)
}

/// Dielectric Fresnel reflectance with the same approximation; `eta_rel = n_t / n_i`.
pub fn fresnel_dielectric(cos_i: f32, eta_rel: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0);
    if eta_rel >= 1.0 {
        return fresnel_nk(c, Vec3::splat(eta_rel), Vec3::ZERO).x;
    }
    let sin2_t = (1.0 - c * c) / (eta_rel * eta_rel);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    fresnel_nk(
        (1.0 - sin2_t).sqrt(),
        Vec3::splat(1.0 / eta_rel),
        Vec3::ZERO,
    )
    .x
}

/// Direction -> (face, u, v), faces +X,-X,+Y,-Y,+Z,-Z, v = 0 on texel row 0.
pub fn cube_dir_to_face_uv(d: Vec3) -> Vec3 {
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x >= 0.0 {
            (0.0, -d.z, -d.y, a.x)
        } else {
            (1.0, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y >= 0.0 {
            (2.0, d.x, d.z, a.y)
        } else {
            (3.0, d.x, -d.z, a.y)
        }
    } else if d.z >= 0.0 {
        (4.0, d.x, -d.y, a.z)
    } else {
        (5.0, -d.x, -d.y, a.z)
    };
    Vec3::new(face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
}

/// (face, u, v) -> unnormalised direction; inverse of [`cube_dir_to_face_uv`].
pub fn cube_face_uv_to_dir(face: u32, u: f32, v: f32) -> Vec3 {
    let sc = 2.0 * u - 1.0;
    let tc = 2.0 * v - 1.0;
    match face {
        0 => Vec3::new(1.0, -tc, -sc),
        1 => Vec3::new(-1.0, -tc, sc),
        2 => Vec3::new(sc, 1.0, tc),
        3 => Vec3::new(sc, -1.0, -tc),
        4 => Vec3::new(sc, -tc, 1.0),
        _ => Vec3::new(-sc, -tc, -1.0),
    }
}

fn sign_not_neg(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

/// Octahedral encoding of a unit vector into [-1,1]^2.
pub fn oct_encode(n: Vec3) -> Vec2 {
    let p = Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs());
    if n.z >= 0.0 {
        return p;
    }
    (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign_not_neg(p)
}

/// Inverse of [`oct_encode`].
pub fn oct_decode(e: Vec2) -> Vec3 {
    let mut n = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    if n.z < 0.0 {
        let xy = (Vec2::ONE - Vec2::new(n.y, n.x).abs()) * sign_not_neg(Vec2::new(n.x, n.y));
        n = Vec3::new(xy.x, xy.y, n.z);
    }
    n.normalize()
}

/// PCG hash (O'Neill).
pub fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// Uniform float in [0, 1) from [`pcg_hash`].
pub fn hash_to_unit(x: u32) -> f32 {
    (pcg_hash(x) >> 8) as f32 * (1.0 / 16777216.0)
}

/// Relative luminance of linear RGB (Rec. 709).
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}
