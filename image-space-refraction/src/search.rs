//! The two-interface searches of Hu and Qin (2006, section 2.1) and of the earlier method they
//! improve (Wyman 2005), as Rust twins of `shaders/search.wgsl`: same algorithms, constants
//! and names, so that property tests of these functions say what the shader does.
//!
//! Everything works on the eye's *front/back buffers*: per pixel the outward unit normal and
//! the view depth (distance along the camera's forward axis) of the nearest front-facing and
//! the nearest back-facing surface of the refractor (depth 0: no refractor there). The paper
//! stores OpenGL window depth; we store linear view depth, so that the correction of `d_T`
//! (figure 9) is in metres and its tolerance a length (a departure: README).
//!
//! - [`silhouette_search`]: figure 7, the binary search along the projected refracted
//!   direction `t1` for the pixel `p_e` where the refractor's silhouette is crossed.
//! - [`exit_side`]: section 2.1.2, the angle test: the second hit is on the front-facing
//!   surface when the angle between the view ray and `T1` exceeds the angle between the view
//!   ray and `P_e - P1`.
//! - [`exit_distance`]: figure 9, the iterative `d_T` on the named side's depth buffer.
//! - [`hu_qin_exit`]: the whole search: angle test then `d_T`, or (section 4's acceleration)
//!   `d_T` on the back side first, falling back to the front side when `P2` leaves the
//!   silhouette.
//! - [`wyman_exit`]: the baseline's `P2 = P1 + d T1` with `d` interpolated between the
//!   view-ray thickness `d_V` and the precomputed per-vertex `d_N` by the angle ratio.

use glam::{Mat4, Vec2, Vec3, Vec3Swizzles, Vec4, Vec4Swizzles};

/// WGSL of the searches (`search.rs`'s twin): the module `image_space_refraction::search`
/// ([`SEARCH`]); they read the front and back buffers their caller passes.
pub const SEARCH_WGSL: &str = include_str!("shaders/search.wgsl");
/// [`SEARCH_WGSL`] as a module, which refract.wgsl and the conformance kernel import.
pub static SEARCH: gpu::wgsl::Module = gpu::wgsl::Module::new(
    SEARCH_WGSL,
    "image-space-refraction/src/shaders/search.wgsl",
    &[],
);

/// Which surface of the refractor a buffer holds (the WGSL `SIDE_FRONT`/`SIDE_BACK`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Surfaces facing the eye.
    Front = 0,
    /// Surfaces facing away from the eye.
    Back = 1,
}

/// The view the buffers were rendered from (the WGSL `EyeParams`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// World to clip (depth in [0, 1]).
    pub view_proj: Mat4,
    /// Eye position (world).
    pub position: Vec3,
    /// Unit forward axis: view depth is `dot(p - position, forward)`.
    pub forward: Vec3,
    /// Buffer size in pixels.
    pub width: u32,
    /// Buffer size in pixels.
    pub height: u32,
}

impl Eye {
    /// The eye of `camera` at `width` x `height`.
    pub fn of_camera(camera: &scene::Camera, width: u32, height: u32) -> Self {
        Self {
            view_proj: camera.view_proj(width, height),
            position: camera.eye,
            forward: camera.basis().0,
            width,
            height,
        }
    }

    /// Pixel coordinates (x right, y down, pixel centres at i + 0.5) and view depth of `p`.
    pub fn project(&self, p: Vec3) -> Vec3 {
        let clip = self.view_proj * p.extend(1.0);
        let ndc = clip.xy() / clip.w;
        Vec3::new(
            (ndc.x * 0.5 + 0.5) * self.width as f32,
            (0.5 - ndc.y * 0.5) * self.height as f32,
            (p - self.position).dot(self.forward),
        )
    }

    /// The world point at pixel coordinates `pixel` and view depth `depth`.
    pub fn unproject(&self, pixel: Vec2, depth: f32) -> Vec3 {
        let ndc = Vec2::new(
            pixel.x / self.width as f32 * 2.0 - 1.0,
            1.0 - pixel.y / self.height as f32 * 2.0,
        );
        let far = self.view_proj.inverse() * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let dir = (far.xyz() / far.w - self.position).normalize();
        self.position + dir * (depth / dir.dot(self.forward))
    }
}

/// One texel of a front/back buffer: outward unit normal and view depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    /// Outward unit normal of the surface (world).
    pub normal: Vec3,
    /// View depth of the surface.
    pub depth: f32,
}

/// The front and back buffers as the shader reads them: nearest texel, nothing outside.
pub trait Buffers {
    /// The texel of `side` under pixel coordinates `p` (`floor(p)`), `None` where the
    /// refractor does not cover it or `p` is outside the buffer.
    fn texel(&self, side: Side, p: Vec2) -> Option<Texel>;
}

/// Front and back buffers in memory, rows top to bottom, `[nx, ny, nz, depth]` per texel,
/// depth 0 where empty: the layout of the GPU's `Rgba32Float` buffers.
#[derive(Clone, Debug, PartialEq)]
pub struct FrontBack {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Nearest front-facing surface per pixel.
    pub front: Vec<[f32; 4]>,
    /// Nearest back-facing surface per pixel.
    pub back: Vec<[f32; 4]>,
}

impl FrontBack {
    /// The buffers of a sphere seen by `eye`, each pixel sampled at its centre exactly (what
    /// the rasterizer gives for a finely tessellated sphere).
    pub fn sphere(eye: &Eye, centre: Vec3, radius: f32) -> Self {
        let n = (eye.width * eye.height) as usize;
        let mut front = vec![[0.0; 4]; n];
        let mut back = vec![[0.0; 4]; n];
        for y in 0..eye.height {
            for x in 0..eye.width {
                let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let dir = (eye.unproject(pixel, 1.0) - eye.position).normalize();
                let t = gpu::prelude::ray_sphere(eye.position, dir, centre, radius);
                if !(t.x <= t.y) || t.x <= 0.0 {
                    continue;
                }
                let texel = |t: f32| {
                    let p = eye.position + dir * t;
                    let n = (p - centre) / radius;
                    [n.x, n.y, n.z, (p - eye.position).dot(eye.forward)]
                };
                let i = (y * eye.width + x) as usize;
                front[i] = texel(t.x);
                back[i] = texel(t.y);
            }
        }
        Self {
            width: eye.width,
            height: eye.height,
            front,
            back,
        }
    }
}

impl Buffers for FrontBack {
    fn texel(&self, side: Side, p: Vec2) -> Option<Texel> {
        let (x, y) = (p.x.floor(), p.y.floor());
        if !(x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32) {
            return None;
        }
        let i = y as usize * self.width as usize + x as usize;
        let t = match side {
            Side::Front => self.front[i],
            Side::Back => self.back[i],
        };
        (t[3] > 0.0).then(|| Texel {
            normal: Vec3::new(t[0], t[1], t[2]),
            depth: t[3],
        })
    }
}

/// Is the refractor under pixel coordinates `p` (the back buffer, as figure 7 reads it)?
pub fn covered(buffers: &impl Buffers, p: Vec2) -> bool {
    buffers.texel(Side::Back, p).is_some()
}

/// Most halvings of the silhouette search (its bracket starts at most 1.5 x the buffer's
/// larger side long, so 24 halvings reach 1/4 texel at 16384 pixels).
pub const MAX_SILHOUETTE_STEPS: u32 = 24;

/// Result of [`silhouette_search`]: `inside` is covered, `outside` is not (or off the
/// buffer), both on the ray `p1 + s t1`, at most `tolerance` apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Silhouette {
    /// Last covered test point: the paper's `p_e`.
    pub inside: Vec2,
    /// First uncovered test point beyond it.
    pub outside: Vec2,
    /// Test points looked up.
    pub steps: u32,
}

/// Figure 7: the pixel `p_e` where the ray `p1 + s t1` (pixels, `t1` unit) leaves the
/// refractor's silhouette, by binary search from 75% of the buffer's larger side (twice that
/// if the first test point is still covered: off the buffer then), down to `tolerance`
/// pixels. `p1` must be covered.
pub fn silhouette_search(
    buffers: &impl Buffers,
    eye: &Eye,
    p1: Vec2,
    t1: Vec2,
    tolerance: f32,
) -> Silhouette {
    let initial = 0.75 * eye.width.max(eye.height) as f32;
    let mut lo = 0.0;
    let mut hi = initial;
    let mut steps = 1;
    if covered(buffers, p1 + hi * t1) {
        lo = hi;
        hi = 2.0 * initial;
    }
    while hi - lo > tolerance.max(1e-3) && steps < MAX_SILHOUETTE_STEPS {
        let mid = 0.5 * (lo + hi);
        if covered(buffers, p1 + mid * t1) {
            lo = mid;
        } else {
            hi = mid;
        }
        steps += 1;
    }
    Silhouette {
        inside: p1 + lo * t1,
        outside: p1 + hi * t1,
        steps,
    }
}

/// Section 2.1.2: the side of the refractor that the ray `P1 + d T1` leaves through, from the
/// silhouette point `pe` (world): front-facing when the angle between the view direction `v`
/// and `T1` is larger than the angle between `v` and `pe - P1`.
pub fn exit_side(v: Vec3, p1: Vec3, t1: Vec3, pe: Vec3) -> Side {
    let d = pe - p1;
    let l2 = d.length_squared();
    let to_silhouette = if l2 > 0.0 && l2 < 1e30 {
        d / l2.sqrt()
    } else {
        t1
    };
    // theta1 > theta2 <=> cos(theta1) < cos(theta2).
    if v.dot(t1) < v.dot(to_silhouette) {
        Side::Front
    } else {
        Side::Back
    }
}

/// The projected direction of `t1` at `p1` on the buffer (pixels, unit), or zero when `t1`
/// runs along the view ray.
pub fn projected_direction(eye: &Eye, p1: Vec3, t1: Vec3) -> Vec2 {
    let a = eye.project(p1).xy();
    let reach = 1e-2 * (p1 - eye.position).length().max(1e-3);
    let b = eye.project(p1 + t1 * reach).xy();
    let d = b - a;
    let len = d.length();
    if len > 1e-6 && len < 1e30 {
        d / len
    } else {
        Vec2::ZERO
    }
}

/// Parameters of the `d_T` iteration (figure 9).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iteration {
    /// Stop when the correction is at most this (metres of view depth).
    pub tolerance: f32,
    /// Most corrections.
    pub max_iterations: u32,
    /// The first `d_T` ("a small positive value", metres).
    pub initial_step: f32,
}

/// What [`exit_distance`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exit {
    /// `P2` (world).
    pub point: Vec3,
    /// Outward unit normal `N2` at `P2`, from the side's normal buffer.
    pub normal: Vec3,
    /// The side `N2` was read from.
    pub side: Side,
    /// `d_T`.
    pub distance: f32,
    /// Corrections made.
    pub iterations: u32,
    /// The last correction, or the bracket of the exit, was within the tolerance.
    pub converged: bool,
    /// `P2` fell outside the silhouette at some step (the acceleration's fallback signal).
    pub left_silhouette: bool,
}

/// Figure 9: `d_T` along `t1` from `p1` (world, on the refractor) such that `P2 = P1 + d_T T1`
/// lies on the `side` surface: `d_T += flag (depth(P2) - z(P2))`, flag 1 on the back side and
/// -1 on the front side, until the correction is within the tolerance.
///
/// The correction is positive while `P2` is inside (in front of the back surface, behind the
/// front one) and negative past the surface, so every step also narrows a bracket of the
/// exit: `lo` (inside) and `hi` (past the surface, or off the silhouette). The paper's step
/// is taken while it stays inside the bracket; one that would leave it, or that landed off
/// the silhouette, is replaced by the bracket's midpoint. Where the paper's iteration
/// converges this changes nothing; near the silhouette, where the depth buffer's slope makes
/// it overshoot and oscillate, it keeps converging (a departure: README).
pub fn exit_distance(
    buffers: &impl Buffers,
    eye: &Eye,
    p1: Vec3,
    t1: Vec3,
    side: Side,
    iteration: &Iteration,
) -> Exit {
    let flag = if side == Side::Back { 1.0 } else { -1.0 };
    let mut exit = Exit {
        point: p1,
        normal: -t1,
        side,
        distance: 0.0,
        iterations: 0,
        converged: false,
        left_silhouette: false,
    };
    let (mut lo, mut hi) = (0.0f32, f32::INFINITY);
    let mut d = 0.0;
    let mut step = iteration.initial_step;
    for _ in 0..iteration.max_iterations {
        exit.iterations += 1;
        let mut candidate = d + step;
        if hi.is_finite() && !(candidate > lo && candidate < hi) {
            candidate = 0.5 * (lo + hi);
        }
        let p2 = p1 + t1 * candidate;
        let q = eye.project(p2);
        let Some(texel) = buffers.texel(side, q.xy()) else {
            exit.left_silhouette = true;
            hi = hi.min(candidate);
            step = 0.0;
            continue;
        };
        d = candidate;
        exit.point = p2;
        exit.normal = texel.normal;
        exit.distance = d;
        step = flag * (texel.depth - q.z);
        if step.abs() <= iteration.tolerance {
            exit.converged = true;
            break;
        }
        if step > 0.0 {
            lo = lo.max(d);
        } else {
            hi = hi.min(d);
        }
        // The nearest-texel depths are steps: on a slanted surface the correction may never
        // fall below a small tolerance, but the bracket closes on the exit.
        if hi - lo <= iteration.tolerance {
            exit.converged = true;
            break;
        }
    }
    exit
}

/// How [`hu_qin_exit`] picks the side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Silhouette search and angle test first (sections 2.1.2-2.1.3).
    AngleTest,
    /// Section 4: iterate on the back side; when `P2` leaves the silhouette, start again on
    /// the front side.
    BackFirst,
}

/// The whole second-interface search of Hu and Qin from `p1` (world, on the refractor's
/// visible surface) along the refracted direction `t1`, seen along `v` from the eye.
pub fn hu_qin_exit(
    buffers: &impl Buffers,
    eye: &Eye,
    p1: Vec3,
    v: Vec3,
    t1: Vec3,
    strategy: Strategy,
    iteration: &Iteration,
) -> Exit {
    match strategy {
        Strategy::BackFirst => {
            let back = exit_distance(buffers, eye, p1, t1, Side::Back, iteration);
            if back.left_silhouette {
                exit_distance(buffers, eye, p1, t1, Side::Front, iteration)
            } else {
                back
            }
        }
        Strategy::AngleTest => {
            let side = side_by_angle(buffers, eye, p1, v, t1);
            exit_distance(buffers, eye, p1, t1, side, iteration)
        }
    }
}

/// Sections 2.1.2's whole test: the silhouette point along the projected `t1`, unprojected
/// at the mean of its front and back depths, then [`exit_side`]. A `t1` along the view ray
/// (no projected direction) leaves through the back.
pub fn side_by_angle(buffers: &impl Buffers, eye: &Eye, p1: Vec3, v: Vec3, t1: Vec3) -> Side {
    let dir = projected_direction(eye, p1, t1);
    if dir == Vec2::ZERO {
        return Side::Back;
    }
    let start = eye.project(p1).xy();
    let s = silhouette_search(buffers, eye, start, dir, 1.0);
    let depth = match (
        buffers.texel(Side::Front, s.inside),
        buffers.texel(Side::Back, s.inside),
    ) {
        (Some(f), Some(b)) => 0.5 * (f.depth + b.depth),
        (_, Some(b)) => b.depth,
        _ => return Side::Back,
    };
    let pe = eye.unproject(s.inside, depth);
    exit_side(v, p1, t1, pe)
}

/// Wyman's (2005) estimate of the exit point, the baseline: `d = r d_V + (1 - r) d_N` with
/// `r = theta_t / theta_i` (the refraction angle over the incidence angle, both against the
/// inward normal `-n1`), `d_V` the distance from `p1` to the back surface along the view ray
/// `v`, `d_N` the thickness along the inward normal precomputed at the vertices and
/// interpolated; `N2` is read from the back buffer where `P2` projects. Without a back
/// texel there (`P2` off the silhouette) the normal is `t1`: the ray leaves unbent.
pub fn wyman_exit(
    buffers: &impl Buffers,
    eye: &Eye,
    p1: Vec3,
    v: Vec3,
    n1: Vec3,
    t1: Vec3,
    d_n: f32,
) -> Exit {
    let q1 = eye.project(p1);
    let d_v = buffers.texel(Side::Back, q1.xy()).map_or(0.0, |b| {
        (b.depth - q1.z).max(0.0) / v.dot(eye.forward).max(1e-4)
    });
    let inward = -n1;
    let theta_i = v.dot(inward).clamp(-1.0, 1.0).acos();
    let theta_t = t1.dot(inward).clamp(-1.0, 1.0).acos();
    let ratio = if theta_i > 1e-4 {
        theta_t / theta_i
    } else {
        1.0
    };
    let d = ratio * d_v + (1.0 - ratio) * d_n;
    let point = p1 + t1 * d;
    let texel = buffers.texel(Side::Back, eye.project(point).xy());
    Exit {
        point,
        normal: texel.map_or(t1, |t| t.normal),
        side: Side::Back,
        distance: d,
        iterations: 0,
        converged: texel.is_some(),
        left_silhouette: texel.is_none(),
    }
}

/// The ray leaving the refractor at `exit` (travelling along `t1` inside glass of index
/// `ior`): the refracted direction `T2` (w = 1) or, under total internal reflection, the
/// reflected one (w = 0).
pub fn exit_direction(exit: &Exit, t1: Vec3, ior: f32) -> Vec4 {
    let n = exit.normal.normalize_or(t1);
    let facing = if n.dot(t1) > 0.0 { -n } else { n };
    gpu::prelude::refract_dir(t1, facing, ior)
}

/// The WGSL `EyeParams` (search.wgsl).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EyeGpu {
    view_proj: [[f32; 4]; 4],
    inverse_view_proj: [[f32; 4]; 4],
    position: [f32; 4],
    forward: [f32; 4],
    size: [f32; 4],
}

impl EyeGpu {
    /// A light's view for the photon pass: `size.z` its pixel size at unit distance, `size.w`
    /// the light's index.
    pub fn for_light(mut self, pixel_size: f32, light: u32) -> Self {
        self.size[2] = pixel_size;
        self.size[3] = light as f32;
        self
    }
}

impl From<&Eye> for EyeGpu {
    fn from(e: &Eye) -> Self {
        Self {
            view_proj: e.view_proj.to_cols_array_2d(),
            inverse_view_proj: e.view_proj.inverse().to_cols_array_2d(),
            position: e.position.extend(1.0).to_array(),
            forward: e.forward.extend(0.0).to_array(),
            size: [e.width as f32, e.height as f32, 0.0, 0.0],
        }
    }
}
