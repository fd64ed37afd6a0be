//! What the README reports about the marchers and the shadow rays, measured on the built-in
//! scenes (run with `--nocapture` to see the tables):
//!
//! - lines against the DDA: the share of photons whose first hit is the same LDI sample (pixel
//!   and layer), from the hit buffers of the same transfer map (`bounces = 0`);
//! - screen-space shadow rays against exact ones: among the diffuse pixels that face a light,
//!   the share misclassified, and over those whose occluder lies in the view the share of the
//!   shadowed ones the mask finds and of the lit ones it darkens.

use glam::Vec3;
use scene::Technique;
use scene::bvh::SceneBvh;
use screen_photons::{ScreenPhotons, technique::variants};
use testkit::{Shot, context, render, render_shots};

const SIZE: u32 = 96;

fn variant(name: &str) -> ScreenPhotons {
    ScreenPhotons::new(
        variants()
            .into_iter()
            .find(|v| v.name == name)
            .expect("variant"),
    )
}

/// First hits of every photon of the transfer map at time 0, by `name`'s marcher.
fn first_hits(name: &str, scene: &scene::Scene) -> Vec<[f32; 4]> {
    let mut t = variant(name);
    t.set_param("bounces", 0.0).unwrap();
    render(&mut t, scene, Shot::along_path(scene, 0.0, SIZE));
    t.last_hits(context()).expect("hits")
}

#[test]
fn lines_and_dda_mostly_find_the_same_first_hits() {
    let _lock = testkit::gpu_lock();
    println!(
        "| scene | photons hitting (lines / DDA) | same sample | same layer, pixels 1 apart | \
         lines only | DDA only | elsewhere |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    // Bounds: the measured shares of photons whose hits are the same sample or a pixel apart on
    // the same layer (the thickness test reports the first sample past the crossing, the lines
    // the one nearest it), 0.578, 0.803 and 1.000, rounded down. The lines' first hit of a run
    // (the reduction before it kept the nearest sample) gave 0.550, 0.701 and 0.879.
    for (spec, min_near) in [
        ("pool", 0.55),
        ("refraction-bunny", 0.8),
        ("cornell-sphere", 0.99),
    ] {
        let scene = scene::load(spec).unwrap();
        let lines = first_hits("lines", &scene);
        let dda = first_hits("dda", &scene);
        assert_eq!(lines.len(), dda.len());
        let (mut either, mut same, mut near, mut lines_only, mut dda_only, mut different) =
            (0, 0, 0, 0, 0, 0);
        let (mut n_lines, mut n_dda) = (0, 0);
        for (a, b) in lines.iter().zip(&dda) {
            let (ha, hb) = (a[0] > 0.0, b[0] > 0.0);
            n_lines += ha as usize;
            n_dda += hb as usize;
            if !(ha || hb) {
                continue;
            }
            either += 1;
            match (ha, hb) {
                (true, true) if a[1..] == b[1..] => same += 1,
                (true, true)
                    if a[1] == b[1] && (a[2] - b[2]).abs() <= 1.0 && (a[3] - b[3]).abs() <= 1.0 =>
                {
                    near += 1
                }
                (true, true) => different += 1,
                (true, false) => lines_only += 1,
                _ => dda_only += 1,
            }
        }
        let share = |n: usize| n as f64 / either.max(1) as f64;
        println!(
            "| {spec} | {n_lines} / {n_dda} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
            share(same),
            share(near),
            share(lines_only),
            share(dda_only),
            share(different)
        );
        assert!(either > 1000, "{spec}: only {either} photons hit anything");
        let close = share(same + near);
        assert!(
            close >= min_near,
            "{spec}: {close:.3} the same or a pixel apart"
        );
    }
}

/// How the screen-space shadow mask classified the diffuse pixels facing the light, against
/// the BVH's shadow rays from the same surface points (layer 0 of the LDI).
#[derive(Default)]
struct ShadowCounts {
    /// Pixels facing the light, and how many of them the mask misclassified.
    candidates: usize,
    wrong: usize,
    /// The pixels whose shadow ray meets nothing or first meets an occluder that projects
    /// inside the image (the frustum's sides; the LDI may still lack it past its layers): the
    /// method's own error, without the occluders it cannot see by design (README, "Known
    /// failure cases"), split by the truth and the mask.
    in_view_shadowed: usize,
    in_view_shadowed_found: usize,
    in_view_lit: usize,
    in_view_lit_shadowed: usize,
}

impl ShadowCounts {
    /// The share of the shadowed pixels the mask finds (0 for a mask without shadows).
    fn found(&self) -> f64 {
        self.in_view_shadowed_found as f64 / self.in_view_shadowed.max(1) as f64
    }
    /// The share of the lit pixels the mask puts in shadow.
    fn false_shadows(&self) -> f64 {
        self.in_view_lit_shadowed as f64 / self.in_view_lit.max(1) as f64
    }
}

fn shadow_counts(spec: &str) -> ShadowCounts {
    let scene = scene::load(spec).unwrap();
    let mut t = variant("shadows");
    let camera = scene.camera_at(0.0);
    render(&mut t, &scene, Shot::along_path(&scene, 0.0, SIZE));
    let ctx = context();
    let mask = t.last_shadow_mask(ctx).unwrap();
    let layer0 = t.last_ldi_layer(ctx, 0).unwrap();
    let bvh = SceneBvh::build(&scene, 0.0);
    let light = &scene.lights[0];
    let view_proj = camera.view_proj(SIZE, SIZE);
    let seen = |p: Vec3| {
        let clip = view_proj * p.extend(1.0);
        clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w
    };
    let mut c = ShadowCounts::default();
    for y in 0..SIZE {
        for x in 0..SIZE {
            let i = (y * SIZE + x) as usize;
            let [nx, ny, nz, d] = layer0[i];
            if d <= 0.0 {
                continue;
            }
            let view = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, SIZE, SIZE);
            let Some(hit) = bvh.closest_hit(camera.eye, view, f32::INFINITY) else {
                continue;
            };
            if scene.objects[hit.object].material.is_specular() {
                continue;
            }
            let p = camera.eye + view * d;
            let mut n = Vec3::new(nx, ny, nz).normalize();
            if n.dot(view) > 0.0 {
                n = -n;
            }
            let to_light = light.position - p;
            if n.dot(to_light) <= 0.0 {
                continue;
            }
            let origin = p + n * 1e-4 * p.length().max(1.0);
            let dist = to_light.length();
            let dir = to_light / dist;
            let occluder = bvh.closest_hit(origin, dir, dist * (1.0 - 1e-4));
            let masked = mask[i][0] < 0.5;
            c.candidates += 1;
            c.wrong += (masked != occluder.is_some()) as usize;
            match occluder {
                None => {
                    c.in_view_lit += 1;
                    c.in_view_lit_shadowed += masked as usize;
                }
                Some(h) if seen(origin + dir * h.t) => {
                    c.in_view_shadowed += 1;
                    c.in_view_shadowed_found += masked as usize;
                }
                Some(_) => {}
            }
        }
    }
    c
}

#[test]
fn screen_space_shadows_against_ray_traced_ones() {
    let _lock = testkit::gpu_lock();
    println!(
        "| scene | pixels facing the light | misclassified | in shadow, occluder in view | \
         found by the mask | lit | put in shadow by the mask |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    // Over the pixels whose occluder (if any) the view holds: the share of the shadowed ones
    // the mask finds (a mask without shadows finds none) and the share of the lit ones it
    // darkens, bounded at the measured shares rounded down and up (found 0.9991, 0.9130,
    // 0.7451 of 51 pixels, 0.3442; darkened 0.0091, 0.0036, 0.0045; the pool has no lit pixel
    // facing the light). The tolerance test alone, without section 5's in-out test, found
    // 0.8882 on refraction-bunny and 0.7059 on chess: both below their bounds. Pixels whose
    // occluder lies outside the view are the method's known failure (README, "Known failure
    // cases": the pool's water, mostly above the view, casts almost none of its shadow):
    // counted in "misclassified", not bounded. Even with the water in view the mask finds only
    // a third of the pool's shadow (not yet explained: the water is an open surface, which the
    // in-out test cannot pair). Chess's share rests on 51 pixels (38 found, 36 without the
    // in-out test): its bound, 37, leaves room for one pixel on another driver. The pool has
    // no lit pixel to darken.
    for (spec, min_found, max_false) in [
        ("cornell-sphere", 0.99, Some(0.012)),
        ("refraction-bunny", 0.9, Some(0.005)),
        ("chess", 0.72, Some(0.006)),
        ("pool", 0.3, None),
    ] {
        let c = shadow_counts(spec);
        println!(
            "| {spec} | {} | {:.4} | {} | {:.4} | {} | {:.4} |",
            c.candidates,
            c.wrong as f64 / c.candidates.max(1) as f64,
            c.in_view_shadowed,
            c.found(),
            c.in_view_lit,
            c.false_shadows()
        );
        assert!(c.candidates > 500, "{spec}: {} pixels", c.candidates);
        assert!(
            c.in_view_shadowed > 20,
            "{spec}: {} pixels in shadow",
            c.in_view_shadowed
        );
        assert!(
            c.found() >= min_found,
            "{spec}: the mask finds {:.4} of the shadowed pixels, bound {min_found}",
            c.found()
        );
        if let Some(max_false) = max_false {
            assert!(c.in_view_lit > 500, "{spec}: {} lit pixels", c.in_view_lit);
            assert!(
                c.false_shadows() <= max_false,
                "{spec}: the mask darkens {:.4} of the lit pixels, bound {max_false}",
                c.false_shadows()
            );
        }
    }
}

/// The depth complexity of each view (section 2.2: the paper counts it to choose the number
/// of peels, and finds eight layers enough): per pixel the number of non-empty LDI layers,
/// with 16 layers peeled so that the default cap of 8 can be judged.
#[test]
fn depth_complexity_of_the_built_in_views() {
    let _lock = testkit::gpu_lock();
    println!("| scene | mean layers per covered pixel | deepest pixel | pixels over 8 layers |");
    println!("| --- | --- | --- | --- |");
    for spec in ["pool", "refraction-bunny", "cornell-sphere", "chess"] {
        let scene = scene::load(spec).unwrap();
        let mut t = variant("refraction");
        t.set_param("layers", 16.0).unwrap();
        render(&mut t, &scene, Shot::along_path(&scene, 0.0, SIZE));
        let layers: Vec<_> = (0..16)
            .map(|l| t.last_ldi_layer(context(), l).unwrap())
            .collect();
        let counts: Vec<usize> = (0..(SIZE * SIZE) as usize)
            .map(|p| layers.iter().take_while(|layer| layer[p][3] > 0.0).count())
            .collect();
        let covered: Vec<_> = counts.iter().filter(|&&c| c > 0).collect();
        let mean = covered.iter().map(|&&c| c as f64).sum::<f64>() / covered.len() as f64;
        let deepest = counts.iter().max().copied().unwrap_or(0);
        let over = counts.iter().filter(|&&c| c > 8).count() as f64 / counts.len() as f64;
        println!("| {spec} | {mean:.2} | {deepest} | {over:.4} |");
        assert!(mean >= 1.0 && deepest >= 2, "{spec}: {mean} {deepest}");
        // Every layer past the deepest is empty: the peel stopped finding surfaces.
        assert!(deepest < 16, "{spec}: 16 layers were not enough to count");
    }
}

/// The light shafts' energy against the reference's photon beams on `murky-pool` (run with
/// `--nocapture` for the README's figures): `god-rays` minus `dda` (the same frame without
/// shafts: same photons, same transmittance) is the drawn bands after the blur;
/// `froxel-fog-photons` minus `dda` the hybrid froxels' in-scattering (the same photons through
/// a caustic map); `froxel-fog` minus `dda` the engine's (no photons: the light straight
/// through the water, which casts no shadow); the reference's `beam_radiance` the ground truth
/// of the same light (single scattering after the waves). Sums over the image, per channel.
#[test]
fn shafts_carry_the_reference_beams_energy() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load("murky-pool").unwrap();
    let size = 64;
    let shot = Shot::along_path(&scene, 0.0, size);
    let without = image_sum(&render(&mut variant("dda"), &scene, shot));
    let shafts = |name: &str| image_sum(&render(&mut variant(name), &scene, shot)) - without;
    let god_rays = shafts("god-rays");
    let hybrid = shafts("froxel-fog-photons");
    let engine = shafts("froxel-fog");
    let opts = truth::reference::ReferenceOptions {
        photons: 1_000_000,
        ..Default::default()
    };
    let beams = truth::reference::light_trace(
        &scene,
        &scene.camera_at(0.0),
        0.0,
        size,
        size,
        &opts,
        &truth::reference::PhotonSetup::caustics(&scene),
    )
    .beam_radiance
    .iter()
    .fold(Vec3::ZERO, |a, b| a + *b);
    println!(
        "| in-scattered light, summed over the image (64 x 64) | red | ratio to the reference |"
    );
    println!("| --- | --- | --- |");
    println!(
        "| reference (photon beams, 1 000 000 photons) | {:.3} | 1 |",
        beams.x
    );
    for (name, sum) in [
        ("god-rays (bands, blurred)", god_rays),
        ("froxel-fog-photons (hybrid)", hybrid),
        ("froxel-fog (engine, first frame)", engine),
    ] {
        println!("| {name} | {:.3} | {:.3} |", sum.x, sum.x / beams.x);
    }
    assert!(beams.x > 1.0, "the reference has shafts: {beams}");
    // Bounds: the measured ratios with a margin.
    let ratio = god_rays / beams;
    assert!(
        (ratio - Vec3::ONE).abs().max_element() < 0.2,
        "god rays carry {ratio} of the reference's in-scattering"
    );
    let ratio = hybrid / beams;
    assert!(
        (ratio - Vec3::ONE).abs().max_element() < 0.1,
        "the hybrid froxels carry {ratio} of the reference's in-scattering"
    );
    let ratio = engine / beams;
    assert!(
        (ratio - Vec3::ONE).abs().max_element() < 0.25,
        "the engine froxels carry {ratio} of the reference's in-scattering"
    );
}

fn image_sum(img: &gpu::HdrImage) -> Vec3 {
    img.pixels
        .iter()
        .fold(Vec3::ZERO, |a, p| a + Vec3::from_slice(&p[..3]))
}

/// The in-scattering a shafts variant adds to `dda`'s frame on `murky-pool` (64 x 64, t = 0)
/// with `photons`^2 photons: the variant's image minus `dda`'s with the same photons, which
/// share every other pass.
fn inscattering(name: &str, photons: u32, shots: &[Shot], scene: &scene::Scene) -> Vec<Vec3> {
    let with_photons = |name: &str| {
        let mut t = variant(name);
        t.set_param("photons", photons as f64).unwrap();
        render_shots(&mut t, scene, shots)
    };
    let (shafts, without) = (with_photons(name), with_photons("dda"));
    let pixel = |p: &[f32; 4]| Vec3::from_slice(&p[..3]);
    (shafts.pixels.iter().zip(&without.pixels))
        .map(|(a, b)| pixel(a) - pixel(b))
        .collect()
}

fn largest_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0, f32::max)
}

/// The engine baseline's fog is the engine's: no photon reaches it, so its in-scattering is
/// the same whatever the photon count (the hybrid's, fed a caustic map of the photons, is
/// not: the same check on it fails, which shows the check can).
#[test]
fn engine_froxels_take_no_photons() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load("murky-pool").unwrap();
    let shots = [Shot::along_path(&scene, 0.0, 64)];
    let peak = |v: &[Vec3]| v.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    for (name, independent) in [("froxel-fog", true), ("froxel-fog-photons", false)] {
        let few = inscattering(name, 32, &shots, &scene);
        let many = inscattering(name, 128, &shots, &scene);
        let difference = largest_difference(&few, &many) / peak(&many);
        println!("{name}: in-scattering with 32^2 and 128^2 photons differs by {difference}");
        assert!(peak(&many) > 0.0, "{name} draws shafts");
        assert_eq!(
            difference < 1e-4,
            independent,
            "{name}: relative difference {difference}"
        );
    }
}

/// The engine froxels' temporal filter on a still view: every frame samples each froxel at a
/// new jittered point and the grid is their running mean (plain while the frames are fewer
/// than `1 / temporal_blend`), so 8 frames are nearer the mean over the froxels (64 frames)
/// than one is, and the mean keeps the light's total of the unjittered frame (it does not
/// drift or ghost). Without history (`temporal_blend` 1) two frames are the same.
#[test]
fn engine_froxels_settle_on_a_still_view() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load("murky-pool").unwrap();
    let shot = Shot::along_path(&scene, 0.0, 64);
    let frames = |n: usize, blend: f64| {
        let mut t = variant("froxel-fog");
        t.set_param("temporal_blend", blend).unwrap();
        t.set_param("photons", 16.0).unwrap();
        let image = render_shots(&mut t, &scene, &vec![shot; n]);
        (image.pixels.iter())
            .map(|p| Vec3::from_slice(&p[..3]))
            .collect::<Vec<_>>()
    };
    let total = |v: &[Vec3]| v.iter().fold(Vec3::ZERO, |a, p| a + *p).x;
    let rms = |a: &[Vec3], b: &[Vec3]| {
        let sum: f32 = a
            .iter()
            .zip(b)
            .map(|(a, b)| (*a - *b).length_squared())
            .sum();
        (sum / a.len() as f32).sqrt()
    };
    assert_eq!(largest_difference(&frames(1, 1.0), &frames(2, 1.0)), 0.0);
    let converged = frames(64, 0.01);
    let one = rms(&frames(1, 0.01), &converged);
    let eight = rms(&frames(8, 0.01), &converged);
    let drift = total(&converged) / total(&frames(1, 1.0)) - 1.0;
    println!(
        "RMS from the 64-frame mean: one frame {one}, eight frames {eight}; its total against \
         the unjittered frame's: {drift:+.4}"
    );
    assert!(one > 0.0, "the jitter moves the samples");
    assert!(
        eight < 0.5 * one,
        "the running mean settles: {eight} against {one}"
    );
    assert!(
        drift.abs() < 0.05,
        "the running mean keeps the light's total"
    );
}

/// Reprojection: a view reached by turning the camera, its grid blended with the last view's
/// reprojected, is close to the same view converged in place (measured: relative RMS 0.0106,
/// 0.16 of the start view's own difference from it, 0.0658). A history read at the same
/// froxel, the camera's turn ignored (tried by giving the pass this frame's view as the
/// last), measured 0.0230, 0.35 of it: the bound, a quarter, tells the two apart.
#[test]
fn engine_froxels_reproject_their_history() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load("murky-pool").unwrap();
    // The same scene time, the camera turned sideways by a few froxels' width.
    let start = Shot::along_path(&scene, 0.0, 64);
    let mut end = start;
    let forward = start.camera.target - start.camera.eye;
    let side = forward.cross(start.camera.up).normalize();
    end.camera.target += side * 0.12 * forward.length();
    let path = [vec![start; 12], vec![end]].concat();
    let moved = inscattering("froxel-fog", 32, &path, &scene);
    let in_place = inscattering("froxel-fog", 32, &vec![end; 13], &scene);
    let norm = in_place.iter().map(|p| p.x).sum::<f32>() / in_place.len() as f32;
    let rms = |a: &[Vec3], b: &[Vec3]| {
        let sum: f32 = a.iter().zip(b).map(|(a, b)| (a.x - b.x).powi(2)).sum();
        (sum / a.len() as f32).sqrt() / norm
    };
    let error = rms(&moved, &in_place);
    let stale = inscattering("froxel-fog", 32, &vec![start; 13], &scene);
    let unmoved = rms(&stale, &in_place);
    println!(
        "relative RMS in-scattering after the move: {error}; the start view's grid as it \
         was: {unmoved}"
    );
    assert!(unmoved > 0.03, "the camera moves enough to tell: {unmoved}");
    assert!(
        error < 0.25 * unmoved,
        "reprojected history: {error} against {unmoved}"
    );
}
