//! The CPU reference renderer: the ground truth every technique is measured against.
//!
//! It computes, for each pixel, the light that the workspace's shading model says reaches
//! the eye, as exactly as a CPU can: exact ray/triangle queries on a BVH ([`SceneBvh`]),
//! specular chains followed to a stated depth, and caustics from a light tracer. It runs on
//! all cores with rayon and is deterministic: the same inputs and seed give bit-identical
//! images whatever the thread count.
//!
//! # What is computed
//!
//! The radiance `L(x <- w)` arriving at the eye is defined by three kinds of surface
//! (DESIGN.md) and glTF's three kinds of light (`scene::LightKind`: point, spot, directional;
//! below, `I` stands for a point light's intensity, for a spot's times its cone falloff
//! `f(-l)`, and for a directional light's irradiance with `d = 1` and `l` against its
//! direction, the shadow ray then unbounded: `scene::Light::toward`):
//!
//! * **Diffuse** (Lambertian, albedo `rho`, optionally times a texture): direct lighting only,
//!
//!   ```text
//!   L_o = L_e + sum_lights  rho / pi * I * max(0, n_s . l) / d^2 * V(x, light)
//!   ```
//!
//!   `L_e` the object's emission (`scene::Object::emission`: seen directly and through every
//!   specular chain, but no light source: it enters no direct lighting and no photon).
//!   with `n_s` the interpolated shading normal flipped to the side the ray arrives from
//!   (surfaces are two-sided), `l` the unit direction and `d` the distance to the light, and
//!   `V` a shadow ray. *Every* object blocks shadow rays, glass included: light that passes
//!   through glass arrives only as caustic photons (below). A light behind the geometric
//!   surface (`n_g . l <= 0`) contributes nothing even where a smooth shading normal would
//!   still face it. No ambient term, no diffuse inter-reflection. This is exactly the
//!   function the shared GPU raster pass evaluates (with its own visibility).
//! * **Metal / mirror** (per-channel `n`, `k`): perfect reflection weighted by the shared
//!   Fresnel approximation `fresnel_nk(cos_i, n, k)` ([`gpu::prelude`]).
//! * **Glass** (index `eta`, possibly below 1, in air): the Whitted split. At each
//!   interface the side is decided by the *geometric* normal (`dot(dir, n_g) < 0`: entering,
//!   relative index `eta_rel = n_t / n_i = eta`; otherwise exiting, `eta_rel = 1 / eta`),
//!   `F = fresnel_dielectric(cos_i, eta_rel)`, and *both* the reflected ray (weight `F`) and
//!   the refracted ray (weight `1 - F`) are traced; on total internal reflection only the
//!   reflected ray, with weight 1. There is no absorption inside glass. Radiance is not
//!   scaled by `(n_t / n_i)^2` at interfaces: every path that reaches the eye starts and
//!   ends in air, where the factors cancel.
//!
//! Reflection and refraction directions use the interpolated shading normal (what every
//! GPU technique sees from its interpolated vertex normals), so a finely tessellated sphere
//! refracts like a sphere; the side of the surface, and the direction in which new ray
//! origins are pushed off it, come from the geometric normal.
//!
//! # Eye pass: a Whitted-style tree per pixel
//!
//! A primary ray leaves the eye through each pixel centre `(x + 0.5, y + 0.5)`
//! ([`Camera::ray_dir`], row 0 at the top); with `samples_per_pixel > 1` the pixel is
//! instead sampled at a fixed, deterministic set of positions (a Hammersley set shifted so
//! that one sample falls on the centre when there is one) and the results averaged, while
//! `object_ids` and `mask` always come from the centre ray. A miss returns
//! `scene.background`. At a specular surface the tree splits as above. Two bounds keep it
//! finite:
//!
//! * **Depth**: `max_depth` counts specular interactions (each reflection or refraction is
//!   one). A ray that reaches a specular surface after `max_depth` interactions returns
//!   black. With `max_depth = 0` specular objects are black.
//! * **Throughput**: a branch whose accumulated weight (the product of Fresnel factors along
//!   it) falls below [`MIN_THROUGHPUT`] in every channel is dropped. For a glass sphere this
//!   drops the paths with three or more internal reflections (weight < 0.04^3 ~ 6e-5); the
//!   energy lost is below 1e-4 of the radiance behind the branch.
//!
//! New rays start `offset_epsilon(p) = 1e-4 * max(1, |p|)` metres off the surface along the
//! geometric normal, on the side the new ray travels into (the scene scale runs from 2 m
//! rooms to cities of hundreds of metres; single-precision hit points carry a relative
//! error near 1e-7, so the offset has three orders of magnitude of headroom).
//!
//! # Participating media
//!
//! The scene's volumes are emission-absorption media whose density fields are defined in
//! [`scene::density`] (independently of any technique). Every eye-pass ray, primary or
//! reflected or refracted, is composited through the media between its origin and its
//! first surface (or to infinity on a miss): `L = L_medium + T L_behind`, with `T` the
//! Beer-Lambert transmittance and `L_medium` the medium's emission (its `color` per unit
//! optical depth, so `color (1 - T)` for one colour), integrated by ray marching with the
//! accuracy stated in [`crate::media`] (transmittance within 1e-3 of the closed forms). A
//! surface in front of a medium hides it; a surface inside one is seen through the part in
//! front of it. A caustic photon seen by the eye is attenuated by the transmittance between
//! its landing point and the eye. The `mask` flags every pixel whose primary ray crosses a
//! volume sphere in front of its first surface.
//!
//! # The scattering medium: light shafts
//!
//! A scene's homogeneous scattering medium ([`scene::Medium`], the murky pool's water)
//! attenuates every eye-pass ray, shadow ray and photon segment by its Beer-Lambert
//! transmittance, and scatters light into the eye's rays once: light straight from the lights
//! is integrated along every eye-pass ray, light after specular events (shafts under the
//! waves) is light-traced as photon beams from the caustic photons' paths. The estimators,
//! their accuracy and what a beam sees are in [`crate::scattering`]. Without a medium nothing
//! of this runs and the image is unchanged bit for bit.
//!
//! # Light pass: caustics by light tracing
//!
//! Light that reaches a diffuse surface through one or more specular interactions (paths
//! `L S+ D E` in Heckbert's notation) cannot be found from the eye: the eye's shadow ray
//! to a point light through glass hits the glass. So it is traced from the light instead.
//!
//! **Emission.** Only the directions that can reach a caustic caster matter: the objects
//! with [`scene::Roles::CAUSTIC_CASTER`] or a specular material ([`caustic_casters`]). For each
//! light and caster, the caster's bounding sphere (`center_at`, `bounding_radius_at`) seen
//! from the light subtends a cone of half-angle `theta_max`, `sin theta_max = R / D`, with
//! solid angle `Omega = 2 pi (1 - cos theta_max)` (the whole sphere, `4 pi`, if the light is
//! inside). `N_j` photons are drawn uniformly in cone `j`, where the photon budget is split
//! between cones in proportion to the power each receives, `(I_r + I_g + I_b) Omega_j`.
//! The radiant flux of a point light into a cone is `I Omega` (intensity is flux per unit
//! solid angle), so a photon drawn in a cone alone carries `I Omega_j / N_j`. Cones of
//! different casters may overlap; a direction `w` inside several of them could then be
//! drawn from each, and the sum over cones would count it twice. The balance heuristic
//! (Veach 1997, one-sample form) fixes this: with the sampling densities
//! `p_j(w) = N_j / Omega_j` for the cones that contain `w`, a photon carries
//!
//! ```text
//! Phi = I / sum_{j : w in cone j} (N_j / Omega_j)            (per channel)
//! ```
//!
//! which is `I Omega_j / N_j` where cones do not overlap. A spot's photon carries its falloff
//! too, `I f(w) / ...`, and a cone wholly outside its outer cone is not drawn. A directional
//! light's photons are parallel: per caster a disc of the sphere's radius across the light's
//! direction, behind everything in the scene, of area `A_j`, with `N_j` photons uniform on it,
//! each carrying `E / sum_j (N_j / A_j)` over the discs its line crosses (`scene::emission`).
//!
//! **Transport.** A photon follows its path through specular surfaces. At glass it chooses
//! reflection with probability `F` and refraction with probability `1 - F` (Russian roulette
//! on the Fresnel split: the estimator weight `F / F = 1` leaves its power unchanged and
//! the expectation equals the split); on total internal reflection it reflects. At metal it
//! reflects and its power is multiplied by `fresnel_nk`. Flux, unlike radiance, is not
//! scaled at refractive interfaces. The photon stops at the first diffuse surface (it lands
//! there only if it made at least one specular interaction: zero-bounce light is the eye
//! pass's direct lighting), when it leaves the scene, or at a specular surface after
//! `max_depth` interactions.
//!
//! **Connection to the eye.** A photon of power `Phi` that lands at `x` is connected to
//! the pinhole; for a box pixel filter its contribution to the pixel `j` that `x` projects
//! into is
//!
//! ```text
//!                rho / pi * cos_s * W                                   1
//! dI_j  =  Phi * --------------------  V(x, eye),     W  =  ---------------------- .
//!                        d^2                                  A_pix * cos^3 theta_c
//! ```
//!
//! Derivation (pbrt-v4's `PerspectiveCamera::We`/`SampleWi` are the model): pixel `j`
//! shows the average radiance over its footprint on the image plane at unit distance in
//! front of the pinhole, `I_j = 1/A_pix * integral_{pixel} L(w(u)) du`, where
//! `A_pix = (2 tan(fov_y / 2))^2 * aspect / (width * height)`. A patch `du` of that plane
//! seen at angle `theta_c` from the optical axis lies at distance `1 / cos theta_c` and is
//! tilted by `theta_c`, so it subtends `dw = du cos^3 theta_c`; hence
//! `I_j = integral L(w) W(w) dw` with `W = 1 / (A_pix cos^3 theta_c)` inside the pixel
//! (pbrt's `We = 1 / (A cos^4 theta)` times the `cos theta` of its pinhole's area measure,
//! with `A` one pixel's area instead of the film's). Next, change variables from the eye's
//! directions to the surface points `x` they see: `dw = cos_s dA / d^2`, with `cos_s` the
//! cosine between the geometric normal at `x` and the direction to the eye and `d` the
//! distance, and write the radiance leaving a Lambertian surface as `L_o = rho / pi * E(x)`:
//! `I_j = integral_{x seen in pixel j} W rho / pi E(x) cos_s / d^2 V dA`. Finally, the
//! photons are an unbiased estimate of the incident flux, `E(x) dA`: for any patch `A`,
//! `E[sum_{photons landing in A} Phi_k] = integral_A E dA`. Replacing `E dA` by the photons
//! gives the formula above, one term per photon. The test
//! `light_tracing_matches_direct_lighting` checks this normalisation against the eye pass
//! on a plane lit directly.
//!
//! An orthographic camera's pixel `j` averages the radiance over its footprint on the film,
//! the plane through the eye, of area `A_pix` in the world: `I_j = 1/A_pix integral L dA_film`.
//! The film patch that sees `dA` of the surface along the view direction has
//! `dA_film = cos_s dA`, so `W / d^2` above becomes `1 / A_pix` (`scene::Film::importance`),
//! and the shadow ray goes from `x` straight back along the view direction to the film
//! (`Camera::toward_camera`); `..._through_an_orthographic_camera` checks it the same way. The photon is counted only if `x` is on the side of the surface
//! facing the eye (the side it arrived on), projects into the image, is in front of the
//! camera, and the segment to the eye is unoccluded (a shadow ray). For smooth-shaded
//! surfaces the irradiance is corrected to the shading normal like the direct term
//! (`max(0, n_s . w_i) / (n_g . w_i)`, capped at 10), so caustics and direct light agree.
//!
//! **Photon count.** `ReferenceOptions::default().photons` is 4 million: at 256 x 256 the
//! caustic under the glass sphere of `cornell-sphere` is smooth and its dim halo (light
//! through the sphere's rim, spread wide) shows only faint grain; 1 million is visibly
//! grainy. The noise per pixel depends on photons per pixel, so
//! [`ReferenceOptions::for_image`] scales the count with the image.
//!
//! # Determinism
//!
//! Pixels are independent. Photons are split into fixed chunks of [`PHOTON_CHUNK`], each
//! seeded from `(seed, cone, chunk)` with SplitMix64; each chunk returns its list of
//! splats, and the lists are added to the image in chunk order. (Per-thread images summed
//! at the end would be faster to reduce, but the floating-point sum would depend on how
//! rayon assigned chunks to threads; the ordered reduction is what makes 1 and 16 threads
//! give the same bits.) The per-pixel sums are kept in f64 and rounded to f32 once.
//!
//! # What the reference leaves out
//!
//! * Diffuse inter-reflection (no indirect diffuse light, no colour bleeding) and ambient.
//! * Caustics seen through a specular chain: a caustic on the floor seen in a mirror or
//!   through glass is not in the image (the photon's connection ray to the eye is blocked by
//!   the specular object, and the eye pass only gathers direct light at diffuse points).
//! * Light through glass other than as caustic photons (shadows of glass are black, then
//!   lit by photons).
//! * Specular chains longer than `max_depth` and eye-tree branches below
//!   [`MIN_THROUGHPUT`].
//! * Scattering in the volumes: media emit and absorb (below) but are not lit, cast no
//!   shadows and do not attenuate light on its way to a surface (shadow rays and photons
//!   pass through them). The scene's homogeneous *scattering* medium (`Scene::medium`) is
//!   another matter: it attenuates everything and scatters once (next section).
//! * Multiple scattering in the medium, and its single scattering seen through a specular
//!   chain (beams seen only through glass, like caustics seen only through glass).
//! * Area lights, and emissive surfaces lighting others; absorption in glass; dispersion; polarisation;
//!   anti-aliasing beyond `samples_per_pixel` (the default samples pixel centres only, like
//!   a rasterizer without MSAA).

use crate::media::Media;
use crate::offset_epsilon;
use crate::scattering::{BeamSplatter, direct_inscatter, view_depths};
use glam::{DVec3, Vec2, Vec3};
use gpu::HdrImage;
use gpu::prelude::{fresnel_dielectric, fresnel_nk, ray_sphere, reflect_dir, refract_dir};
use rayon::prelude::*;
use scene::bvh::{Hit, SceneBvh};
use scene::emission::{emitters, photon_power};
use scene::{Camera, Film, Material, Medium, Scene};
use std::f32::consts::FRAC_1_PI;
use std::time::Instant;

mod eye;
mod light_trace;
mod parts;
use eye::*;
pub(crate) use light_trace::SplitMix64;
pub use light_trace::photon_rays;
use light_trace::*;
use parts::{Part, PartClock};
pub use parts::{ReferenceStats, RenderParts, RenderPhases};

/// Eye-tree branches whose accumulated throughput is below this in every channel are
/// dropped (documented bias below 1e-4 of the radiance behind them).
pub const MIN_THROUGHPUT: f32 = 1e-4;

/// Photons per deterministic work unit of the light pass.
pub const PHOTON_CHUNK: u64 = 8192;

/// Largest shading-normal correction `n_s . w_i / n_g . w_i` applied to a landed photon.
const MAX_SHADING_CORRECTION: f32 = 10.0;

/// Options of a reference render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceOptions {
    /// Specular interactions (reflections and refractions) followed along a path; beyond it
    /// a path returns black (eye pass) or stops (photons).
    pub max_depth: u32,
    /// Light-traced caustic photons in total over all lights and casters; 0 disables
    /// caustics. The default, 4 million, gives a smooth caustic under the sphere of
    /// `cornell-sphere` at 256 x 256 (about [`PHOTONS_PER_PIXEL`] per pixel); use
    /// [`ReferenceOptions::for_image`] to keep that density at other sizes.
    pub photons: u64,
    /// Seed of the light pass (the eye pass uses no random numbers).
    pub seed: u64,
    /// Eye samples per pixel; 1 (the default) samples the pixel centre only.
    pub samples_per_pixel: u32,
}

/// Photon density of the default options: 4 million photons over 256 x 256 pixels.
pub use scene::emission::PHOTONS_PER_PIXEL;

impl Default for ReferenceOptions {
    fn default() -> Self {
        Self {
            max_depth: 8,
            photons: 4_000_000,
            seed: 0x5eed_0fca_0571_c5e5,
            samples_per_pixel: 1,
        }
    }
}

impl ReferenceOptions {
    /// The defaults with the photon count scaled to the image, [`PHOTONS_PER_PIXEL`] per
    /// pixel (at least 100 000), so caustic noise per pixel is about the same at every size
    /// and small test images do not pay for 4 million photons.
    pub fn for_image(width: u32, height: u32) -> Self {
        let photons = scene::emission::photons_for_image(width, height);
        Self {
            photons,
            ..Self::default()
        }
    }
}

/// A reference image with the per-pixel bookkeeping the metrics need.
#[derive(Clone, Debug)]
pub struct ReferenceImage {
    /// Linear radiance, alpha 1, row 0 at the top.
    pub image: HdrImage,
    /// Object index of each pixel's primary (centre) hit, -1 for background.
    pub object_ids: Vec<i32>,
    /// The pixel shows a special object (any non-empty roles) or its primary ray crosses a
    /// volume sphere before its hit.
    pub mask: Vec<bool>,
    pub stats: ReferenceStats,
}

/// Renders the ground truth of `scene` seen by `camera` at `time`.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
    opts: &ReferenceOptions,
) -> ReferenceImage {
    let frame = (camera, time, width, height);
    render_with(scene, frame, opts, &PartClock::new(false))
}

/// [`render`], with the time of its parts measured on every thread (the image is the same).
pub fn render_profiled(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
    opts: &ReferenceOptions,
) -> (ReferenceImage, RenderParts) {
    let clock = PartClock::new(true);
    let image = render_with(scene, (camera, time, width, height), opts, &clock);
    (image, clock.parts(rayon::current_num_threads()))
}

fn render_with(
    scene: &Scene,
    (camera, time, width, height): (&Camera, f32, u32, u32),
    opts: &ReferenceOptions,
    clock: &PartClock,
) -> ReferenceImage {
    let start = Instant::now();
    let bvh = SceneBvh::build(scene, time);
    let media = Media::new(scene, time);
    let tracer = Tracer::new(scene, &bvh, &media, opts, clock);
    let bvh_seconds = start.elapsed().as_secs_f64();
    let eye_pass = EyePass {
        tracer: &tracer,
        camera,
        forward: camera.basis().0,
        volumes: scene
            .volumes
            .iter()
            .map(|v| (v.center + v.motion.offset(time), v.radius))
            .collect(),
        width,
        height,
        spp: opts.samples_per_pixel.max(1),
    };
    // Eye pass, one row per task; rows come back in order.
    let eye_start = Instant::now();
    let rows: Vec<Row> = (0..height)
        .into_par_iter()
        .map(|y| eye_pass.row(y))
        .collect();
    let eye_seconds = eye_start.elapsed().as_secs_f64();

    let mut image = HdrImage {
        width,
        height,
        pixels: Vec::with_capacity((width * height) as usize),
    };
    let mut object_ids = Vec::with_capacity((width * height) as usize);
    let mut mask = Vec::with_capacity((width * height) as usize);
    let mut depths = Vec::with_capacity((width * height) as usize);
    let mut counts = Counts::default();
    for row in rows {
        image.pixels.extend(row.pixels);
        object_ids.extend(row.ids);
        mask.extend(row.mask);
        depths.extend(row.depths);
        counts.add(&row.counts);
    }

    // Light pass: caustics.
    let light_start = Instant::now();
    let mut photons_stored = 0;
    if opts.photons > 0 {
        let setup = PhotonSetup::caustics(scene);
        let frame = (camera, time, width, height);
        let lt = light_trace_with(scene, &bvh, frame, opts, &setup, &depths, clock);
        for (px, add) in image.pixels.iter_mut().zip(&lt.radiance) {
            px[0] += add.x;
            px[1] += add.y;
            px[2] += add.z;
        }
        counts.photon += lt.rays;
        photons_stored = lt.photons_stored;
    }

    let light_seconds = light_start.elapsed().as_secs_f64();
    let seconds = start.elapsed().as_secs_f64();
    let rays = counts.camera + counts.shadow + counts.photon;
    ReferenceImage {
        image,
        object_ids,
        mask,
        stats: ReferenceStats {
            camera_rays: counts.camera,
            shadow_rays: counts.shadow,
            photon_rays: counts.photon,
            seconds,
            phases: RenderPhases {
                bvh_seconds,
                eye_seconds,
                light_seconds,
            },
            rays_per_second: if seconds > 0.0 {
                rays as f64 / seconds
            } else {
                0.0
            },
            photons_stored,
        },
    }
}

/// The eye pass of one image, a row at a time: each pixel's radiance (one ray through its
/// centre, or `spp` jittered ones), object id, view depth and mask.
struct EyePass<'a> {
    tracer: &'a Tracer<'a>,
    camera: &'a Camera,
    /// The camera's unit forward axis (depths are along it).
    forward: Vec3,
    /// The volumes' spheres at the frame's time: a pixel whose ray meets one is masked.
    volumes: Vec<(Vec3, f32)>,
    width: u32,
    height: u32,
    spp: u32,
}

impl EyePass<'_> {
    fn row(&self, y: u32) -> Row {
        let mut counts = Counts::default();
        let mut pixels = Vec::with_capacity(self.width as usize);
        let mut ids = Vec::with_capacity(self.width as usize);
        let mut mask = Vec::with_capacity(self.width as usize);
        let mut depths = Vec::with_capacity(self.width as usize);
        for x in 0..self.width {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            let (origin, dir) = self.camera.ray(px, py, self.width, self.height);
            counts.camera += 1;
            let centre_hit = self.tracer.bvh.closest_hit(origin, dir, f32::INFINITY);
            let t_hit = centre_hit.map_or(f32::INFINITY, |h| h.t);
            let special =
                centre_hit.is_some_and(|h| !self.tracer.scene.objects[h.object].roles.is_empty());
            let in_volume = self.volumes.iter().any(|&(c, r)| {
                let s = ray_sphere(origin, dir, c, r);
                s.x <= s.y && s.y > 0.0 && s.x < t_hit
            });
            ids.push(centre_hit.map_or(-1, |h| h.object as i32));
            depths.push(t_hit * dir.dot(self.forward));
            mask.push(special || in_volume);
            let l = if self.spp == 1 {
                let behind = match &centre_hit {
                    Some(h) => self.tracer.shade(h, dir, 0, Vec3::ONE, &mut counts),
                    None => self.tracer.scene.background,
                };
                self.tracer
                    .through_media(origin, dir, t_hit, behind, true, &mut counts)
            } else {
                let mut sum = Vec3::ZERO;
                for i in 0..self.spp {
                    let o = pixel_sample(i, self.spp);
                    let (origin, d) =
                        self.camera
                            .ray(x as f32 + o.x, y as f32 + o.y, self.width, self.height);
                    sum += self.tracer.radiance(origin, d, 0, Vec3::ONE, &mut counts);
                }
                sum / self.spp as f32
            };
            pixels.push([l.x, l.y, l.z, 1.0]);
        }
        Row {
            pixels,
            ids,
            mask,
            depths,
            counts,
        }
    }
}

pub use scene::emission::caustic_casters;

/// How the light pass emits and which landings it keeps.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonSetup {
    /// Objects whose bounding-sphere cones photons are emitted into.
    pub targets: Vec<usize>,
    /// Specular interactions a photon must have made before a diffuse landing counts: 1 for
    /// caustics; 0 turns the light pass into a light tracer of direct lighting too (for
    /// checking the camera normalisation against the eye pass).
    pub min_specular_bounces: u32,
}

impl PhotonSetup {
    /// The caustic setup [`render`] uses.
    pub fn caustics(scene: &Scene) -> Self {
        Self {
            targets: caustic_casters(scene),
            min_specular_bounces: 1,
        }
    }
}

/// The result of a light pass.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTrace {
    /// Radiance added per pixel (`width * height`, row 0 at the top): the landed photons and
    /// the photon beams.
    pub radiance: Vec<Vec3>,
    /// The photon beams' part of `radiance` (single scattering in the scene's medium after
    /// specular events, [`crate::scattering`]); empty when the scene has no medium.
    pub beam_radiance: Vec<Vec3>,
    /// Per light: total power (W) of the photons that landed on diffuse surfaces (after
    /// `min_specular_bounces`), whether or not the eye sees the landing point.
    pub deposited: Vec<Vec3>,
    /// Per light: `sum_j I Omega_j` over its cones (W; overlapping cones each count in
    /// full, so this bounds the emitted power from above).
    pub emitted: Vec<Vec3>,
    pub photons_traced: u64,
    /// Landed photons added to a pixel.
    pub photons_stored: u64,
    /// Rays cast (path segments plus visibility rays to the eye).
    pub rays: u64,
    /// The path segments among them ([`photon_rays`] replays them).
    pub segments: u64,
}

/// Runs the light pass on its own (the caustic part of [`render`] with
/// [`PhotonSetup::caustics`]); `opts.photons` photons in all.
pub fn light_trace(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
    opts: &ReferenceOptions,
    setup: &PhotonSetup,
) -> LightTrace {
    let bvh = SceneBvh::build(scene, time);
    let depths = if scene.medium.is_some() {
        view_depths(&bvh, camera, width, height)
    } else {
        vec![]
    };
    let frame = (camera, time, width, height);
    let clock = PartClock::new(false);
    light_trace_with(scene, &bvh, frame, opts, setup, &depths, &clock)
}

/// One row of the eye pass.
struct Row {
    pixels: Vec<[f32; 4]>,
    ids: Vec<i32>,
    mask: Vec<bool>,
    /// View-space depth of the centre ray's first surface (infinite for none).
    depths: Vec<f32>,
    counts: Counts,
}

/// Ray counters of one task.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    camera: u64,
    shadow: u64,
    photon: u64,
}

impl Counts {
    fn add(&mut self, o: &Counts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.photon += o.photon;
    }
}

/// Sample `i` of `n` inside a pixel, in [0, 1)^2: a Hammersley set shifted by half a cell
/// so that `n = 1` gives the pixel centre.
fn pixel_sample(i: u32, n: u32) -> Vec2 {
    let x = (i as f32 + 0.5) / n as f32;
    let y = (i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0) + 0.5).fract();
    Vec2::new(x, y)
}

/// A hit seen from the direction a ray or photon arrived from.
struct Surface {
    p: Vec3,
    /// Geometric normal on the side the ray came from (`dot(ng, dir) <= 0`).
    ng: Vec3,
    /// Shading normal flipped together with `ng`.
    ns: Vec3,
    /// The ray hit the front (the side the authored normals point to).
    front: bool,
    eps: f32,
}

impl Surface {
    fn new(hit: &Hit, dir: Vec3) -> Self {
        let front = hit.geometric_normal.dot(dir) < 0.0;
        let s = if front { 1.0 } else { -1.0 };
        Surface {
            p: hit.position,
            ng: hit.geometric_normal * s,
            ns: hit.normal * s,
            front,
            eps: offset_epsilon(hit.position),
        }
    }
    /// Origin for a ray leaving on the side the incoming ray came from.
    fn above(&self) -> Vec3 {
        self.p + self.ng * self.eps
    }
    /// Origin for a ray continuing through the surface.
    fn below(&self) -> Vec3 {
        self.p - self.ng * self.eps
    }
}

/// What a specular surface does to a ray arriving along `dir`.
enum Scatter {
    /// Glass: reflect with weight `f`, refract with `1 - f` (`refracted` is `None` on total
    /// internal reflection, where `f` is 1).
    Dielectric {
        f: f32,
        reflected: Vec3,
        refracted: Option<Vec3>,
    },
    /// Metal: reflect with per-channel weight.
    Conductor { f: Vec3, reflected: Vec3 },
}

fn scatter(material: &Material, s: &Surface, dir: Vec3) -> Option<Scatter> {
    let cos_i = (-dir).dot(s.ns).clamp(0.0, 1.0);
    let reflected = reflect_dir(dir, s.ns).normalize();
    match *material {
        Material::Diffuse { .. } => None,
        Material::Metal { n, k } => Some(Scatter::Conductor {
            f: fresnel_nk(cos_i, n, k),
            reflected,
        }),
        Material::Glass { ior } => {
            // eta_rel = n_t / n_i: entering the glass from air, or leaving it.
            let eta_rel = if s.front { ior } else { 1.0 / ior };
            let f = fresnel_dielectric(cos_i, eta_rel);
            let t = refract_dir(dir, s.ns, 1.0 / eta_rel);
            if t.w == 0.0 || f >= 1.0 {
                Some(Scatter::Dielectric {
                    f: 1.0,
                    reflected,
                    refracted: None,
                })
            } else {
                Some(Scatter::Dielectric {
                    f,
                    reflected,
                    refracted: Some(t.truncate()),
                })
            }
        }
    }
}

struct Tracer<'a> {
    scene: &'a Scene,
    bvh: &'a SceneBvh,
    /// The participating media every eye-pass ray is composited through.
    media: &'a Media,
    /// The scattering medium every ray, photon and shadow ray is attenuated by.
    medium: Option<&'a Medium>,
    max_depth: u32,
    /// Times the parts of a profiled render ([`render_profiled`]).
    clock: &'a PartClock,
}

impl Tracer<'_> {
    /// Radiance arriving at `origin` from direction `-dir`; `depth` specular interactions
    /// so far, `throughput` the product of weights along the path from the eye.
    fn radiance(
        &self,
        origin: Vec3,
        dir: Vec3,
        depth: u32,
        throughput: Vec3,
        c: &mut Counts,
    ) -> Vec3 {
        c.camera += 1;
        let hit = self.bvh.closest_hit(origin, dir, f32::INFINITY);
        let behind = match &hit {
            Some(hit) => self.shade(hit, dir, depth, throughput, c),
            None => self.scene.background,
        };
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        self.through_media(origin, dir, t_hit, behind, depth == 0, c)
    }

    /// `behind` (the radiance at `origin + t_hit dir`) seen from `origin` through the volumes
    /// (`media`) and the scattering medium (its transmittance and its direct in-scattering,
    /// `scattering`). A scene with both has the medium composited in front of the volumes (no
    /// built-in scene has both).
    /// `primary`: the ray leaves the eye (the medium within `EYE_CLEARANCE` of it scatters
    /// nothing into it).
    fn through_media(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_hit: f32,
        behind: Vec3,
        primary: bool,
        c: &mut Counts,
    ) -> Vec3 {
        // Timed only where there are media (a clock read costs about what a ray step does).
        let has_media = !self.media.is_empty() || self.medium.is_some();
        let _timer = has_media.then(|| self.clock.timer(Part::EyeMedia));
        let l = self.media.composite(origin, dir, t_hit, behind);
        let Some(m) = self.medium else {
            return l;
        };
        let Some(span) = m.clip(origin, dir, t_hit) else {
            return l;
        };
        let clearance = if primary {
            scene::medium::EYE_CLEARANCE
        } else {
            0.0
        };
        let inscatter = direct_inscatter(
            self.scene,
            self.bvh,
            m,
            origin,
            dir,
            span,
            clearance,
            &mut c.shadow,
        );
        scene::medium::transmittance_of(m.extinction(), span.y - span.x) * l + inscatter
    }

    /// Radiance leaving `hit` back along `dir`.
    fn shade(&self, hit: &Hit, dir: Vec3, depth: u32, throughput: Vec3, c: &mut Counts) -> Vec3 {
        let s = Surface::new(hit, dir);
        let object = &self.scene.objects[hit.object];
        let Some(sc) = scatter(&object.material, &s, dir) else {
            return object.emission + self.direct_light(&s, self.albedo(hit), c);
        };
        if depth >= self.max_depth {
            return Vec3::ZERO; // the chain is longer than max_depth
        }
        match sc {
            Scatter::Conductor { f, reflected } => {
                let t = throughput * f;
                if t.max_element() < MIN_THROUGHPUT {
                    return Vec3::ZERO;
                }
                f * self.radiance(s.above(), reflected, depth + 1, t, c)
            }
            Scatter::Dielectric {
                f,
                reflected,
                refracted,
            } => {
                let mut l = Vec3::ZERO;
                let tr = throughput * f;
                if tr.max_element() >= MIN_THROUGHPUT {
                    l += f * self.radiance(s.above(), reflected, depth + 1, tr, c);
                }
                if let Some(t_dir) = refracted {
                    let tt = throughput * (1.0 - f);
                    if tt.max_element() >= MIN_THROUGHPUT {
                        l += (1.0 - f) * self.radiance(s.below(), t_dir, depth + 1, tt, c);
                    }
                }
                l
            }
        }
    }

    /// Diffuse albedo at a hit (albedo times the texture, if any).
    fn albedo(&self, hit: &Hit) -> Vec3 {
        match &self.scene.objects[hit.object].material {
            Material::Diffuse {
                albedo, texture, ..
            } => match texture.and_then(|t| self.scene.textures.get(t)) {
                Some(tex) => *albedo * tex.sample(hit.uv),
                None => *albedo,
            },
            _ => Vec3::ZERO,
        }
    }

    /// `sum_lights rho / pi * I * max(0, n_s . l) / d^2 * V`.
    fn direct_light(&self, s: &Surface, albedo: Vec3, c: &mut Counts) -> Vec3 {
        let _timer = self.clock.timer(Part::DirectLight);
        let origin = s.above();
        let mut sum = Vec3::ZERO;
        for light in &self.scene.lights {
            let Some(toward) = light.toward(s.p) else {
                continue;
            };
            let (l, d2) = (toward.dir, toward.distance_squared);
            let cos = s.ns.dot(l);
            if cos <= 0.0 || s.ng.dot(l) <= 0.0 || toward.factor <= 0.0 {
                continue;
            }
            let Some((dir, len)) = light.shadow_ray(origin) else {
                continue;
            };
            c.shadow += 1;
            if self.bvh.any_hit(origin, dir, len) {
                continue;
            }
            let through = self
                .medium
                .map_or(Vec3::ONE, |m| m.transmittance(origin, dir, len));
            sum += light.intensity * toward.factor * through * (cos / d2);
        }
        albedo * FRAC_1_PI * sum
    }

    /// Follows one photon from `origin` along `dir` with `power`; calls `land` at the diffuse
    /// surface where it stops if it made at least `min_bounces` specular interactions, and
    /// `beam(origin, dir, length, power)` for every straight segment it travels after
    /// `min_bounces` of them (with its power at the segment's start; `length` infinite for
    /// the last segment of a photon that leaves the scene). The scattering medium attenuates
    /// its power along every segment.
    #[allow(clippy::too_many_arguments)]
    fn trace_photon(
        &self,
        mut origin: Vec3,
        mut dir: Vec3,
        mut power: Vec3,
        min_bounces: u32,
        rng: &mut SplitMix64,
        rays: &mut u64,
        mut land: impl FnMut(&Hit, &Surface, Vec3, Vec3, Vec3),
        mut beam: impl FnMut(Vec3, Vec3, f32, Vec3),
    ) {
        let mut bounces = 0;
        loop {
            *rays += 1;
            let hit = self.bvh.closest_hit(origin, dir, f32::INFINITY);
            if bounces >= min_bounces {
                beam(origin, dir, hit.map_or(f32::INFINITY, |h| h.t), power);
            }
            let Some(hit) = hit else {
                return;
            };
            if let Some(m) = self.medium {
                power *= m.transmittance(origin, dir, hit.t);
            }
            let s = Surface::new(&hit, dir);
            let material = &self.scene.objects[hit.object].material;
            let Some(sc) = scatter(material, &s, dir) else {
                if bounces >= min_bounces {
                    land(&hit, &s, self.albedo(&hit), dir, power);
                }
                return;
            };
            if bounces >= self.max_depth {
                return;
            }
            bounces += 1;
            match sc {
                Scatter::Conductor { f, reflected } => {
                    power *= f;
                    if power.max_element() <= 0.0 {
                        return;
                    }
                    (origin, dir) = (s.above(), reflected);
                }
                Scatter::Dielectric {
                    f,
                    reflected,
                    refracted,
                } => match refracted {
                    Some(t_dir) if rng.next_f32() >= f => (origin, dir) = (s.below(), t_dir),
                    _ => (origin, dir) = (s.above(), reflected),
                },
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_is_the_pixel_centre_and_many_stay_inside() {
        assert_eq!(pixel_sample(0, 1), Vec2::splat(0.5));
        for n in [2, 4, 9, 16] {
            for i in 0..n {
                let s = pixel_sample(i, n);
                assert!(s.x > 0.0 && s.x < 1.0 && s.y >= 0.0 && s.y < 1.0, "{s:?}");
            }
        }
    }

    #[test]
    fn chunk_seeds_differ_and_repeat() {
        assert_eq!(chunk_seed(1, 2, 3), chunk_seed(1, 2, 3));
        let seeds: std::collections::HashSet<u64> = (0..4)
            .flat_map(|e| (0..64).map(move |c| chunk_seed(9, e, c * PHOTON_CHUNK)))
            .collect();
        assert_eq!(seeds.len(), 4 * 64);
    }

    #[test]
    fn photons_scale_with_the_image() {
        assert_eq!(ReferenceOptions::for_image(256, 256).photons, 61 * 65536);
        assert_eq!(ReferenceOptions::for_image(16, 16).photons, 100_000);
        assert_eq!(
            ReferenceOptions::for_image(64, 64).max_depth,
            ReferenceOptions::default().max_depth
        );
    }
}
