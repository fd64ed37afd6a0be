//! Light shafts (section 3.2): the twin of `shaders/shafts.wgsl` (photon beams drawn as bands)
//! and of `shaders/froxels.wgsl` (the engine counterpart's slices and integration).
//!
//! **God rays.** Every photon ray of the march is a beam from where it left its last specular
//! surface to its first hit. The paper draws each as a line primitive with exponential
//! attenuation per fragment, blurs the lines with a Gaussian and blends them over the image.
//! Here a beam is drawn as a band one pixel either side of its projection, and a fragment at
//! pixel `(px, py)` of an x-major beam (y-major: the roles swap) takes the beam's point `x(s)`
//! that projects into the pixel's column (`s` solved exactly from the projection) and adds
//!
//! ```text
//! Phi T_beam(s) sigma_s p(w . w_c) T_eye(x) W / d^2 |ds/dx_pixel| tent(py - y(s))
//! ```
//!
//! the photon-beam estimate of the reference (`truth::scattering`: the pixel importance `W`,
//! the phase function, both transmittances) per pixel of the beam's major axis, spread over
//! the column by a tent of half-width 1, whose samples at the column's pixel centres add up to
//! exactly 1 wherever the line passes. So a beam deposits its whole in-scattered energy
//! whatever the driver's line rules (Vulkan's `strictLines` changes how many fragments a line
//! primitive makes), and the blur only moves it.
//!
//! **Froxel fog** (Wronski 2014, Hillaire 2015). A grid of `froxel_size`-pixel tiles by
//! `slices` exponential depth slices: slice `k` spans the distances `[d_k, d_{k+1}]` along the
//! tile's centre ray, `d_k = near (far / near)^(k / slices)`. Each froxel holds the in-scattered
//! radiance per metre at its centre (on the GPU, with a history, the running mean over jittered
//! points of it); the integration walks each tile's slices front to back and
//! stores at slice `k` the radiance scattered toward the eye between `near` and `d_{k+1}`,
//! each slice integrated in closed form (Hillaire's energy-conserving `S (1 - T) / sigma_t`)
//! over its part inside the medium's box, attenuated by the exact transmittance from the eye.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// `shaders/beam.wgsl`: [`beam_band`] and [`beam_fragment`] in WGSL, with the same arguments.
pub const BEAM_WGSL: &str = include_str!("shaders/beam.wgsl");

/// [`BEAM_WGSL`] as the module `screen_photons::beam` (no bindings), which the god-ray pass and
/// the conformance test import.
pub static BEAM: gpu::wgsl::Module = gpu::wgsl::Module::new(
    BEAM_WGSL,
    "screen-photons/src/shaders/beam.wgsl",
    &[&scene::SHADING],
);
use scene::Medium;
use scene::medium::{henyey_greenstein, transmittance_of};

/// The tent's half-width across a beam's band (pixels): samples of `1 - |u|` at unit spacing
/// sum to 1 for any offset.
pub const BAND_HALF_WIDTH: f32 = 1.0;

/// The eye as the shaft passes see it (the uniform `ShaftView` of shafts.wgsl).
#[derive(Clone, Copy, Debug)]
pub struct ShaftView {
    pub view_proj: Mat4,
    pub eye: Vec3,
    pub forward: Vec3,
    pub width: u32,
    pub height: u32,
    /// Area of one pixel on the image plane at unit distance.
    pub pixel_area: f32,
}

impl ShaftView {
    pub fn new(camera: &scene::Camera, width: u32, height: u32) -> Self {
        let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = width as f32 / height as f32;
        Self {
            view_proj: camera.view_proj(width, height),
            eye: camera.eye,
            forward: camera.basis().0,
            width,
            height,
            pixel_area: (2.0 * tan_half) * (2.0 * tan_half) * aspect
                / (width as f32 * height as f32),
        }
    }

    /// Pixel coordinates of a clip-space point (row 0 at the top).
    fn pixel_of_clip(&self, c: Vec4) -> Vec2 {
        Vec2::new(
            (c.x / c.w + 1.0) * 0.5 * self.width as f32,
            (1.0 - c.y / c.w) * 0.5 * self.height as f32,
        )
    }
}

/// A photon beam: `origin + s dir`, `s` in `[0, length]`, flux `power` at `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    pub origin: Vec3,
    pub dir: Vec3,
    pub length: f32,
    pub power: Vec3,
}

/// The part of a beam that is drawn: inside the medium and in front of the eye's near plane,
/// projected. `None` when nothing is left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamBand {
    /// The beam's parameter range drawn.
    pub s_start: f32,
    pub s_end: f32,
    /// Where the beam enters the medium (its transmittance counts from there).
    pub s_enter: f32,
    /// The projected end points (pixels).
    pub p_start: Vec2,
    pub p_end: Vec2,
    /// True when the projection runs more along x than along y.
    pub x_major: bool,
}

/// The drawn part of `beam` ([`BeamBand`]).
pub fn beam_band(view: &ShaftView, medium: &Medium, beam: &Beam) -> Option<BeamBand> {
    let inside = medium.clip(beam.origin, beam.dir, beam.length)?;
    // In front of the near plane (a little beyond the camera's, so no end point projects to
    // infinity).
    let near = 2.0 * scene::Camera::NEAR;
    let z0 = (beam.origin - view.eye).dot(view.forward);
    let dz = beam.dir.dot(view.forward);
    let (mut s0, mut s1) = (inside.x, inside.y);
    if dz.abs() < 1e-9 {
        if z0 <= near {
            return None;
        }
    } else {
        let s_near = (near - z0) / dz;
        if dz > 0.0 {
            s0 = s0.max(s_near);
        } else {
            s1 = s1.min(s_near);
        }
    }
    if s0 >= s1 {
        return None;
    }
    let clip = |s: f32| view.view_proj * (beam.origin + beam.dir * s).extend(1.0);
    let (p0, p1) = (view.pixel_of_clip(clip(s0)), view.pixel_of_clip(clip(s1)));
    let d = (p1 - p0).abs();
    Some(BeamBand {
        s_start: s0,
        s_end: s1,
        s_enter: inside.x,
        p_start: p0,
        p_end: p1,
        x_major: d.x >= d.y,
    })
}

/// What the band of `beam` adds at the pixel whose centre is `pixel` (pixels, row 0 at the
/// top), before the blur; `surface` is the distance from the eye to the pixel's first surface
/// (the beam is hidden behind it).
pub fn beam_fragment(
    view: &ShaftView,
    medium: &Medium,
    beam: &Beam,
    band: &BeamBand,
    pixel: Vec2,
    surface: f32,
) -> Vec3 {
    // Solve for s where the projection's major coordinate equals the pixel's: the clip
    // coordinates are linear in s, c(s) = c0 + s cd, and ndc = c / c.w.
    let c0 = view.view_proj * beam.origin.extend(1.0);
    let cd = view.view_proj * beam.dir.extend(0.0);
    let (major, size, sign) = if band.x_major {
        (pixel.x, view.width as f32, 1.0)
    } else {
        (pixel.y, view.height as f32, -1.0)
    };
    let ndc = sign * (2.0 * major / size - 1.0);
    let (a0, ad) = if band.x_major {
        (c0.x, cd.x)
    } else {
        (c0.y, cd.y)
    };
    let denom = ad - ndc * cd.w;
    if denom.abs() < 1e-20 {
        return Vec3::ZERO;
    }
    let s = (ndc * c0.w - a0) / denom;
    if !(s >= band.s_start && s <= band.s_end) {
        return Vec3::ZERO;
    }
    // ds / d(major pixel): d s / d ndc = (c0.w ad - a0 cd.w) / denom^2, d ndc / d pixel = 2 / size.
    let ds_dpixel = ((c0.w * ad - a0 * cd.w) / (denom * denom) * 2.0 / size).abs();
    let x = beam.origin + beam.dir * s;
    let p = view.pixel_of_clip(c0 + cd * s);
    let across = if band.x_major {
        pixel.y - p.y
    } else {
        pixel.x - p.x
    };
    let tent = (1.0 - across.abs() / BAND_HALF_WIDTH).max(0.0) / BAND_HALF_WIDTH;
    let to_eye = view.eye - x;
    let d = to_eye.length();
    if tent <= 0.0 || d < scene::medium::EYE_CLEARANCE || d >= surface {
        return Vec3::ZERO;
    }
    let w_c = to_eye / d;
    let cos_camera = view.forward.dot(-w_c);
    if cos_camera <= 0.0 {
        return Vec3::ZERO;
    }
    let importance = 1.0 / (view.pixel_area * cos_camera * cos_camera * cos_camera);
    let sigma_t = medium.extinction();
    let along_beam = transmittance_of(sigma_t, s - band.s_enter);
    let toward_eye = medium.transmittance(x, w_c, d);
    let phase = henyey_greenstein(beam.dir.dot(w_c), medium.anisotropy);
    beam.power
        * along_beam
        * medium.scattering
        * toward_eye
        * (phase * importance / (d * d) * ds_dpixel * tent)
}

/// The froxel grid's depth slicing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slices {
    pub near: f32,
    pub far: f32,
    pub count: u32,
}

impl Slices {
    /// Distance of slice boundary `k` (0 = `near`, `count` = `far`).
    pub fn boundary(&self, k: f32) -> f32 {
        self.near * (self.far / self.near).powf(k / self.count as f32)
    }

    /// The continuous boundary index of distance `d` (clamped to `[0, count]`).
    pub fn index_of(&self, d: f32) -> f32 {
        let k = (d.max(self.near) / self.near).ln() / (self.far / self.near).ln();
        (k * self.count as f32).clamp(0.0, self.count as f32)
    }

    /// The slicing of the medium seen from `eye`: from [`scene::medium::EYE_CLEARANCE`] (or
    /// where the medium begins) to its farthest corner.
    pub fn of_medium(medium: &Medium, eye: Vec3, count: u32) -> Self {
        let corners = (0..8).map(|i| {
            Vec3::new(
                if i & 1 == 0 {
                    medium.min.x
                } else {
                    medium.max.x
                },
                if i & 2 == 0 {
                    medium.min.y
                } else {
                    medium.max.y
                },
                if i & 4 == 0 {
                    medium.min.z
                } else {
                    medium.max.z
                },
            )
        });
        let far = corners.map(|c| c.distance(eye)).fold(0.0, f32::max);
        let nearest = eye.clamp(medium.min, medium.max).distance(eye);
        let near = nearest
            .max(scene::medium::EYE_CLEARANCE)
            .min(far * 0.5)
            .max(1e-3);
        Self {
            near,
            far: far.max(near * 2.0),
            count: count.max(1),
        }
    }
}

/// Front-to-back integration of one tile's froxels: `inscatter[k]` is the in-scattered
/// radiance per metre at slice `k`'s centre (constant over the slice); returns, per slice, the
/// radiance scattered toward the eye from `near` to the slice's far boundary, along the ray
/// `eye + t dir`.
pub fn integrate_tile(
    medium: &Medium,
    slices: &Slices,
    eye: Vec3,
    dir: Vec3,
    inscatter: &[Vec3],
) -> Vec<Vec3> {
    let sigma_t = medium.extinction();
    let whole = medium.clip(eye, dir, f32::INFINITY);
    let mut sum = Vec3::ZERO;
    let mut out = Vec::with_capacity(inscatter.len());
    for (k, s) in inscatter.iter().enumerate() {
        let (d0, d1) = (slices.boundary(k as f32), slices.boundary(k as f32 + 1.0));
        if let Some(box_span) = whole {
            let (a, b) = (d0.max(box_span.x), d1.min(box_span.y));
            if b > a {
                let before = transmittance_of(sigma_t, a - box_span.x);
                sum += *s * before * slice_integral(sigma_t, b - a);
            }
        }
        out.push(sum);
    }
    out
}

/// `integral_0^len exp(-sigma_t t) dt` per channel: `(1 - exp(-sigma_t len)) / sigma_t`, and
/// `len` where there is no extinction.
pub fn slice_integral(sigma_t: Vec3, len: f32) -> Vec3 {
    let one = |s: f32| {
        if s * len < 1e-6 {
            len
        } else {
            (1.0 - (-s * len).exp()) / s
        }
    };
    Vec3::new(one(sigma_t.x), one(sigma_t.y), one(sigma_t.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn medium() -> Medium {
        Medium {
            name: "m".into(),
            min: Vec3::new(-2.0, -2.0, -6.0),
            max: Vec3::new(2.0, 0.0, -1.0),
            scattering: Vec3::splat(0.3),
            absorption: Vec3::new(0.1, 0.05, 0.0),
            anisotropy: 0.3,
        }
    }

    fn view() -> ShaftView {
        let camera = scene::Camera {
            eye: Vec3::new(0.1, -0.5, 0.5),
            target: Vec3::new(0.0, -1.0, -4.0),
            up: Vec3::Y,
            fov_y_deg: 60.0,
            orthographic: None,
        };
        ShaftView::new(&camera, 96, 64)
    }

    /// The beam's energy on the image by the midpoint rule along it (the reference's
    /// estimator with no visibility), for a beam wholly in view.
    fn integral(view: &ShaftView, m: &Medium, beam: &Beam, band: &BeamBand) -> Vec3 {
        let n = 200_000;
        let ds = (band.s_end - band.s_start) / n as f32;
        (0..n)
            .map(|i| {
                let s = band.s_start + (i as f32 + 0.5) * ds;
                let x = beam.origin + beam.dir * s;
                let to_eye = view.eye - x;
                let d = to_eye.length();
                let w_c = to_eye / d;
                let cos = view.forward.dot(-w_c);
                beam.power
                    * transmittance_of(m.extinction(), s - band.s_enter)
                    * m.scattering
                    * m.transmittance(x, w_c, d)
                    * (henyey_greenstein(beam.dir.dot(w_c), m.anisotropy)
                        / (view.pixel_area * cos * cos * cos)
                        / (d * d)
                        * ds)
            })
            .sum()
    }

    #[test]
    fn a_band_deposits_the_beams_whole_energy() {
        let (view, m) = (view(), medium());
        for (origin, dir) in [
            (Vec3::new(-1.0, 1.0, -3.0), Vec3::new(0.2, -1.0, -0.1)),
            (Vec3::new(-1.5, -1.0, -2.0), Vec3::new(1.0, -0.1, -0.6)),
            (Vec3::new(0.5, 0.5, -4.0), Vec3::new(-0.3, -1.0, 0.7)),
        ] {
            let beam = Beam {
                origin,
                dir: dir.normalize(),
                length: 3.0,
                power: Vec3::new(1.0, 0.8, 0.5),
            };
            let band = beam_band(&view, &m, &beam).expect("in view");
            let mut sum = Vec3::ZERO;
            for y in 0..view.height {
                for x in 0..view.width {
                    let px = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    sum += beam_fragment(&view, &m, &beam, &band, px, f32::INFINITY);
                }
            }
            let want = integral(&view, &m, &beam, &band);
            let rel = ((sum - want) / want).abs().max_element();
            // One pixel column at each end is where the midpoint rule over columns differs.
            let columns = (band.p_end - band.p_start).abs().max_element();
            assert!(
                rel < 2.0 / columns,
                "{sum} vs {want} over {columns} columns"
            );
        }
    }

    #[test]
    fn surfaces_hide_beams_behind_them() {
        let (view, m) = (view(), medium());
        let beam = Beam {
            origin: Vec3::new(-1.0, 1.0, -3.0),
            dir: Vec3::new(0.2, -1.0, -0.1).normalize(),
            length: 3.0,
            power: Vec3::ONE,
        };
        let band = beam_band(&view, &m, &beam).unwrap();
        let mid = (band.p_start + band.p_end) * 0.5;
        let pixel = mid.floor() + Vec2::splat(0.5);
        let seen = beam_fragment(&view, &m, &beam, &band, pixel, f32::INFINITY);
        assert!(seen.max_element() > 0.0);
        assert_eq!(
            beam_fragment(&view, &m, &beam, &band, pixel, 0.5),
            Vec3::ZERO
        );
    }

    #[test]
    fn slices_cover_the_medium_and_the_integral_is_exact_for_constant_inscatter() {
        let (view, m) = (view(), medium());
        let slices = Slices::of_medium(&m, view.eye, 64);
        assert!((slices.boundary(0.0) - slices.near).abs() < 1e-5);
        assert!((slices.boundary(64.0) - slices.far).abs() < 1e-3 * slices.far);
        assert!((slices.index_of(slices.boundary(17.0)) - 17.0).abs() < 1e-3);
        let dir = (Vec3::new(0.3, -1.2, -5.0) - view.eye).normalize();
        let s = Vec3::new(0.2, 0.1, 0.05);
        let out = integrate_tile(&m, &slices, view.eye, dir, &[s; 64]);
        // Constant in-scattering: integral of S T(entry, t) dt over the part inside the box
        // beyond `near`, by a fine midpoint rule (independent of `slice_integral`).
        let span = m.clip(view.eye, dir, f32::INFINITY).unwrap();
        let sigma_t = m.extinction();
        let (a, b) = (span.x.max(slices.near), span.y);
        let n = 100_000;
        let dt = (b - a) / n as f32;
        let want = (0..n).fold(Vec3::ZERO, |sum, i| {
            let t = a + (i as f32 + 0.5) * dt;
            sum + s * transmittance_of(sigma_t, t - span.x) * dt
        });
        let got = *out.last().unwrap();
        assert!((got - want).abs().max_element() < 1e-4, "{got} vs {want}");
        // Monotone non-decreasing.
        assert!(out.windows(2).all(|w| w[1].cmpge(w[0]).all()));
    }
}
