//! Photon emission against the regular lattice (the caustic rings), for every family that
//! emits caustic photons from a light-view raster, one photon per pixel: distance impostors
//! (light maps and the compute grid), refractor distance maps, image-space refraction and
//! screen-space photons.
//!
//! At the pixel centres the photons leave the light on a regular lattice; where the glass
//! sphere of `cornell-sphere` spreads them, the lattice shows under the sphere as concentric
//! moire rings. Two remedies, at the same photon count (scene README, "Photon emission"):
//! `photon_jitter` moves each photon to a random point of its pixel (`jittered_emission` in
//! scene.wgsl), which turns the rings into noise; `photon_footprint` widens each photon's
//! splat to the footprint of its lattice cell on the receiver, which fills the gaps between
//! the rows (light maps and screen-space splats).
//!
//! The figure is the mean FLIP over the caustic region (the pixels the reference's caustic
//! brightens). The test fails if jitter leaves an image unchanged or moves its caustic's
//! light, or if footprints do not lower the error where a family has them.
//!
//! `cargo test -p workspace-tests --test caustic_emission -- --nocapture` prints the table and
//! writes the images (reference, lattice, jittered, footprints, both) per variant to
//! `target/caustic-emission/<variant>.png`.

use gpu::HdrImage;
use scene::Technique;
use scene::emission::{PHOTON_FOOTPRINT_PARAM, PHOTON_JITTER_PARAM};
use testkit::Shot;

const SPEC: &str = "cornell-sphere";
const SIZE: u32 = 128;
/// The caustic region: pixels the reference's caustic brightens by more than this share of its
/// brightest pixel's gain (the focus is ~2000 times brighter than the rim the rings are in).
const REGION_SHARE: f32 = 5e-4;

/// The variants whose photons leave a light-view raster.
const VARIANTS: [&str; 5] = [
    "impostors/caustics",
    "impostors/caustics-compute",
    "refractor-maps/caustics",
    "image-space-refraction/caustics",
    "screen-photons/dda",
];

/// How a variant's photons leave the light and land.
#[derive(Clone, Copy, PartialEq)]
struct Emission {
    jitter: bool,
    footprint: bool,
}

/// The four ways the table compares, in its column order: lattice, jittered, footprints, both.
const EMISSIONS: [Emission; 4] = [
    Emission::new(false, false),
    Emission::new(true, false),
    Emission::new(false, true),
    Emission::new(true, true),
];

impl Emission {
    const fn new(jitter: bool, footprint: bool) -> Self {
        Self { jitter, footprint }
    }
}

fn technique(id: &str, emission: Emission) -> Option<Box<dyn Technique>> {
    let mut t = harness::registry()
        .into_iter()
        .find(|t| t.id() == id)
        .unwrap_or_else(|| panic!("no technique {id}"));
    t.set_param(PHOTON_JITTER_PARAM, emission.jitter as u32 as f64)
        .unwrap_or_else(|e| panic!("{id} has no {PHOTON_JITTER_PARAM}: {e}"));
    let has_footprints = t.params().iter().any(|p| p.name == PHOTON_FOOTPRINT_PARAM);
    if has_footprints {
        t.set_param(PHOTON_FOOTPRINT_PARAM, emission.footprint as u32 as f64)
            .unwrap();
    }
    (has_footprints || !emission.footprint).then_some(t)
}

fn luminance(p: &[f32; 4]) -> f32 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// The pixels `with` (the reference with caustics) is brighter than `without` by more than
/// [`REGION_SHARE`] of the largest gain.
fn caustic_region(with: &HdrImage, without: &HdrImage) -> Vec<bool> {
    let gain: Vec<f32> = with
        .pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| luminance(a) - luminance(b))
        .collect();
    let peak = gain.iter().copied().fold(0.0f32, f32::max);
    gain.iter().map(|&g| g > REGION_SHARE * peak).collect()
}

/// Mean FLIP over the caustic region and the light it holds (summed luminance).
struct Figures {
    flip: f64,
    light: f64,
}

fn figures(image: &HdrImage, reference: &HdrImage, region: &[bool]) -> Figures {
    let (metrics, _) = truth::metrics::compare(image, reference, Some(region));
    let light = image
        .pixels
        .iter()
        .zip(region)
        .filter(|(_, m)| **m)
        .map(|(p, _)| luminance(p) as f64)
        .sum();
    Figures {
        flip: metrics.flip_mean_masked,
        light,
    }
}

#[test]
fn footprints_and_jitter_remove_the_lattice_rings() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load(SPEC).expect("built-in scene");
    let shot = Shot::along_path(&scene, 0.0, SIZE);
    let photons = scene::emission::photons_for_image(SIZE, SIZE);
    let with = testkit::reference(SPEC, &scene, shot, photons).image;
    let without = testkit::reference(SPEC, &scene, shot, 0).image;
    let region = caustic_region(&with, &without);
    let pixels = region.iter().filter(|&&m| m).count();
    assert!(
        pixels > 200,
        "the caustic region holds {pixels} pixels: too few to measure"
    );
    println!("{SPEC} at {SIZE}x{SIZE}: mean FLIP over the caustic region ({pixels} pixels)");
    println!("| variant | lattice | jittered | footprints | footprints + jittered |");
    println!("| --- | --- | --- | --- | --- |");
    let dir = testkit::out_dir("caustic-emission");
    let mut failures = Vec::new();
    for id in VARIANTS {
        let mut images = vec![&with];
        let mut renders = Vec::new();
        let mut row = Vec::new();
        for emission in EMISSIONS {
            let Some(mut t) = technique(id, emission) else {
                row.push(None);
                continue;
            };
            let image = testkit::render(t.as_mut(), &scene, shot);
            row.push(Some(figures(&image, &with, &region)));
            renders.push(image);
        }
        images.extend(renders.iter());
        let cell =
            |f: &Option<Figures>| f.as_ref().map_or("-".into(), |f| format!("{:.4}", f.flip));
        println!(
            "| {id} | {} | {} | {} | {} |",
            cell(&row[0]),
            cell(&row[1]),
            cell(&row[2]),
            cell(&row[3])
        );
        testkit::save_png(
            &testkit::strip(&images, 2),
            &dir.join(format!("{}.png", id.replace('/', "__"))),
        );
        // Jitter moves photons within their pixels: the caustic changes, its light does not
        // (each photon keeps its pixel's flux).
        let (lattice, jittered) = (row[0].as_ref().unwrap(), row[1].as_ref().unwrap());
        let ratio = jittered.light / lattice.light;
        if renders[0].pixels == renders[1].pixels || (ratio - 1.0).abs() > 0.03 {
            failures.push(format!(
                "{id}: jitter left the image unchanged or moved its caustic's light ({ratio:.4})"
            ));
        }
        // Footprints end the rings where they are made: lower FLIP over the caustic.
        if let Some(footprints) = &row[2]
            && footprints.flip >= lattice.flip
        {
            failures.push(format!(
                "{id}: FLIP {:.4} with footprints, {:.4} without",
                footprints.flip, lattice.flip
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("; "));
}
