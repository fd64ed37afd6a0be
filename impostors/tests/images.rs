//! Image tests against the CPU reference (`truth::reference`, caustic photons on) on small
//! images, metrics from `truth::metrics::compare` with the reference's mask (the pixels that
//! show the sphere). Each test prints its table (`--nocapture`) and writes a strip PNG
//! (reference, then the techniques in table order) under `target/impostors-tests/`.
//!
//! Stated bounds (96 x 96, default camera, time 0, impostor resolution 256):
//! - `localized_beats_classic_on_cornell_sphere`: the masked FLIP mean and the masked RMSE of
//!   the localized technique are below classic's (the paper's figures 5 and 7 claim) and its
//!   masked FLIP <= 0.05: false-position-4 on the mirror, double-refraction on glass-1.5.
//!   (Single-interface localized refraction, false-position-4 on glass, is *worse* than
//!   classic there: see README.md.)
//! - `stale_map_error_vs_iterations`: map made at time 0, sphere moved 0.5 m by time 1
//!   (paper figure 5): false-position-8 below classic on cornell-sphere and cornell-box.
//! - `error_vs_iterations`: cornell-sphere mirror / glass-1.5 / cornell-box mirror, masked
//!   FLIP and RMSE for initial-guess and 1, 2, 4, 8 iterations of each method; no NaN pixel
//!   anywhere; on cornell-box (concave: iterations matter) false-position-8 at least 0.004
//!   below the initial guess and every iterated variant at least 0.002 below it; on the
//!   cornell-sphere mirror one false-position step at least 0.001 below the guess and more
//!   steps within 0.001 of one; on glass (single interface) every variant within 0.002 of the
//!   guess.
//! - `moving_refractor_is_right_at_every_time`: glass-1.5, prepared at time 0, rendered at
//!   times 0.5 and 1 (the sphere moved 0.25 and 0.5 m): double-refraction and caustics within
//!   0.01 masked FLIP of their time-0 error against the reference at that time.
//! - `split_layout_matches_packed`: false-position-4 and false-position-4-split give the same
//!   image (both read the same f16 distances; max abs difference <= 1e-3).

mod common;

use std::sync::OnceLock;

use gpu::HdrImage;
use truth::metrics::{Metrics, compare};
use truth::reference::{ReferenceImage, ReferenceOptions};

const SIZE: u32 = 96;

fn reference(spec: &str) -> &'static ReferenceImage {
    reference_at(spec, 0.0)
}

fn reference_at(spec: &str, time: f32) -> &'static ReferenceImage {
    static CACHE: OnceLock<std::sync::Mutex<Vec<(String, &'static ReferenceImage)>>> =
        OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let mut cache = cache.lock().unwrap();
    let key = format!("{spec}@{time}");
    if let Some((_, r)) = cache.iter().find(|(s, _)| *s == key) {
        return r;
    }
    let scene = scene::load(spec).unwrap();
    let opts = ReferenceOptions::for_image(SIZE, SIZE);
    let r: &'static ReferenceImage = Box::leak(Box::new(truth::reference::render(
        &scene,
        &scene.camera,
        time,
        SIZE,
        SIZE,
        &opts,
    )));
    cache.push((key, r));
    r
}

struct Row {
    id: String,
    metrics: Metrics,
    image: HdrImage,
}

fn evaluate(spec: &str, ids: &[&str]) -> Vec<Row> {
    evaluate_stale(spec, ids, &[0.0])
}

/// Renders frames at `times` with the environment map made only at the first
/// (`regen_threshold` is set to 10 m when more than one time is given) and compares the last
/// with the reference at the last time.
fn evaluate_stale(spec: &str, ids: &[&str], times: &[f32]) -> Vec<Row> {
    evaluate_frames(spec, ids, times, times.len() > 1)
}

/// As [`evaluate_stale`], but each technique keeps its own regeneration threshold.
fn evaluate_stale_regenerating(spec: &str, ids: &[&str], times: &[f32]) -> Vec<Row> {
    evaluate_frames(spec, ids, times, false)
}

fn evaluate_frames(spec: &str, ids: &[&str], times: &[f32], keep_first_map: bool) -> Vec<Row> {
    let scene = scene::load(spec).unwrap();
    let reference = reference_at(spec, *times.last().unwrap());
    let mut rows = Vec::new();
    for id in ids {
        let mut t = common::technique(id);
        if keep_first_map {
            t.set_param("regen_threshold", 10.0).unwrap();
        }
        let image = {
            let _g = common::gpu_lock();
            common::render_frames(t.as_mut(), &scene, times, SIZE)
        };
        let (metrics, _) = compare(&image, &reference.image, Some(&reference.mask));
        assert_eq!(metrics.nan_pixels, 0, "{id} on {spec}: non-finite pixels");
        rows.push(Row {
            id: id.to_string(),
            metrics,
            image,
        });
    }
    // One header line per table, naming it, so that a run's output has no two alike.
    println!(
        "{spec} at times {times:?} ({SIZE}x{SIZE}, {} masked pixels): technique, masked FLIP, \
         FLIP, RMSE",
        rows[0].metrics.masked_pixels
    );
    for r in &rows {
        println!(
            "  {:<34} {:.4}        {:.4}    {:.5}",
            r.id, r.metrics.flip_mean_masked, r.metrics.flip_mean, r.metrics.rmse
        );
    }
    let mut strip: Vec<&HdrImage> = vec![&reference.image];
    strip.extend(rows.iter().map(|r| &r.image));
    // Named after the test (libtest names each test's thread after it): several tests render
    // the same scene at the same times with other techniques, and one strip each is kept.
    let test = std::thread::current()
        .name()
        .unwrap_or("images")
        .to_string();
    let name = format!(
        "{}-{}-t{}-at{}{}.png",
        test.rsplit("::").next().unwrap_or("images"),
        spec.replace([':', '=', ','], "_"),
        times.len(),
        times.last().unwrap(),
        if keep_first_map { "-stale" } else { "" }
    );
    common::save_strip(&strip, &name, 2);
    println!("  strip: {name} (target/impostors-tests/)");
    rows
}

fn get<'a>(rows: &'a [Row], id: &str) -> &'a Metrics {
    &rows.iter().find(|r| r.id == id).unwrap().metrics
}

/// Masked RMSE: RMSE over the mask's pixels only.
fn masked_rmse(a: &HdrImage, b: &HdrImage, mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for ((p, q), m) in a.pixels.iter().zip(&b.pixels).zip(mask) {
        if *m {
            for c in 0..3 {
                sum += (p[c] as f64 - q[c] as f64).powi(2);
            }
            n += 3;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

#[test]
fn localized_beats_classic_on_cornell_sphere() {
    for material in ["mirror", "glass-1.5"] {
        let spec = format!("cornell-sphere:material={material}");
        let glass = material.starts_with("glass");
        // Glass: the localized variant that follows the ray through the sphere is
        // double-refraction; the single-interface variants are printed for the record.
        let localized_id = if glass {
            "impostors/double-refraction"
        } else {
            "impostors/false-position-4"
        };
        let mut ids = vec!["impostors/classic", "impostors/false-position-4"];
        if glass {
            ids.push("impostors/double-refraction");
        }
        let rows = evaluate(&spec, &ids);
        let mask = &reference(&spec).mask;
        let reference = &reference(&spec).image;
        let rmse = |id: &str| {
            masked_rmse(
                &rows.iter().find(|r| r.id == id).unwrap().image,
                reference,
                mask,
            )
        };
        for id in &ids {
            println!("  masked RMSE {id}: {:.5}", rmse(id));
        }
        let (classic, localized) = (get(&rows, "impostors/classic"), get(&rows, localized_id));
        assert!(
            localized.flip_mean_masked < classic.flip_mean_masked,
            "{spec}: {localized_id} masked FLIP {} not below classic {}",
            localized.flip_mean_masked,
            classic.flip_mean_masked
        );
        assert!(
            rmse(localized_id) < rmse("impostors/classic"),
            "{spec}: masked RMSE"
        );
        assert!(
            localized.flip_mean_masked <= 0.05,
            "{spec}: {localized_id} masked FLIP {}",
            localized.flip_mean_masked
        );
    }
}

/// The paper's figure 5 set-up: the map is made with the sphere at time 0 and reused at
/// time 1, when the sphere has moved 0.5 m toward the red wall (regen_threshold 10 m), so
/// rays start far from the reference point and iterations matter.
#[test]
fn stale_map_error_vs_iterations() {
    let ids = [
        "impostors/classic",
        "impostors/initial-guess",
        "impostors/secant-1",
        "impostors/secant-2",
        "impostors/secant-4",
        "impostors/secant-8",
        "impostors/false-position-1",
        "impostors/false-position-2",
        "impostors/false-position-4",
        "impostors/false-position-8",
    ];
    for spec in [
        "cornell-sphere:material=mirror",
        "cornell-box:material=mirror",
    ] {
        let rows = evaluate_stale(spec, &ids, &[0.0, 1.0]);
        let classic = get(&rows, "impostors/classic").flip_mean_masked;
        let fp8 = get(&rows, "impostors/false-position-8").flip_mean_masked;
        assert!(
            fp8 < classic,
            "{spec}: false-position-8 {fp8} vs classic {classic}"
        );
    }
}

/// Error as the sphere moves away from the map's reference point (paper section 2: the
/// localization corrects for the offset of the ray origin): the map is made at time 0 and
/// reused at time t, when the sphere has moved 0.5 t metres; beside it, the same variant
/// with the map regenerated at t. Classic mapping degrades with the offset; localized
/// lookups keep most of the geometry right and what remains is mostly stale lighting.
#[test]
fn error_vs_displacement() {
    let ids = [
        "impostors/classic",
        "impostors/initial-guess",
        "impostors/secant-4",
        "impostors/false-position-4",
    ];
    let spec = "cornell-sphere:material=mirror";
    let mut table = Vec::new();
    for t in [0.1f32, 0.2, 0.4, 0.6, 1.0] {
        let stale = evaluate_stale(spec, &ids, &[0.0, t]);
        let fresh = evaluate_stale(spec, &ids, &[t]);
        let reference = reference_at(spec, t);
        let rmse: Vec<f64> = ids
            .iter()
            .map(|id| {
                let row = stale.iter().find(|r| r.id == *id).unwrap();
                masked_rmse(&row.image, &reference.image, &reference.mask)
            })
            .collect();
        table.push((0.5 * t, stale, fresh, rmse));
    }
    println!(
        "displacement (m) | variant | masked FLIP stale | masked FLIP regenerated | masked RMSE stale"
    );
    for (d, stale, fresh, rmse) in &table {
        for (id, rmse) in ids.iter().zip(rmse) {
            println!(
                "{d:.2} | {id} | {:.4} | {:.4} | {rmse:.4}",
                get(stale, id).flip_mean_masked,
                get(fresh, id).flip_mean_masked,
            );
        }
    }
    for (d, stale, _, _) in &table {
        let classic = get(stale, "impostors/classic").flip_mean_masked;
        let fp4 = get(stale, "impostors/false-position-4").flip_mean_masked;
        assert!(
            fp4 < classic,
            "offset {d} m: false-position-4 {fp4} vs classic {classic}"
        );
    }
    let classic: Vec<f64> = table
        .iter()
        .map(|(_, stale, _, _)| get(stale, "impostors/classic").flip_mean_masked)
        .collect();
    assert!(
        classic.last() > classic.first(),
        "classic error should grow with the offset: {classic:?}"
    );
}

#[test]
fn error_vs_iterations() {
    let ids = [
        "impostors/classic",
        "impostors/initial-guess",
        "impostors/secant-1",
        "impostors/secant-2",
        "impostors/secant-4",
        "impostors/secant-8",
        "impostors/false-position-1",
        "impostors/false-position-2",
        "impostors/false-position-4",
        "impostors/false-position-8",
    ];
    for spec in [
        "cornell-sphere:material=mirror",
        "cornell-sphere:material=glass-1.5",
        "cornell-box:material=mirror",
    ] {
        let rows = evaluate(spec, &ids);
        let masked = |id: &str| get(&rows, id).flip_mean_masked;
        let guess = masked("impostors/initial-guess");
        let iterated = ids
            .iter()
            .filter(|id| id.contains("secant") || id.contains("position"));
        match spec {
            // The concave room, where the tall box hides parts of the walls from the sphere's
            // centre and the guess misses near the corners: iterations must pay. Measured
            // (96 x 96): guess 0.0515, false-position-8 0.0450, every iterated variant at
            // least 0.0037 below the guess (secant-4 0.0478).
            "cornell-box:material=mirror" => {
                let fp8 = masked("impostors/false-position-8");
                assert!(
                    fp8 <= guess - 0.004,
                    "{spec}: false-position-8 {fp8} vs guess {guess}"
                );
                for id in iterated {
                    assert!(
                        masked(id) < guess - 0.002,
                        "{spec}: {id} {} vs guess {guess}",
                        masked(id)
                    );
                }
            }
            // The convex room: the guess is good and one step is nearly enough (paper).
            // Measured: guess 0.0110, false-position-1 0.0084, 8 iterations 0.0085.
            "cornell-sphere:material=mirror" => {
                let fp1 = masked("impostors/false-position-1");
                assert!(
                    fp1 <= guess - 0.001,
                    "{spec}: false-position-1 {fp1} vs guess {guess}"
                );
                for id in iterated {
                    assert!(
                        masked(id) <= fp1 + 0.001,
                        "{spec}: {id} {} vs one step {fp1}",
                        masked(id)
                    );
                }
            }
            // Single-interface refraction: the search is not what limits the error (the ray
            // goes on straight inside the sphere), so iterations change nothing. Measured:
            // guess 0.1668, every iterated variant 0.1662-0.1663.
            _ => {
                for id in iterated {
                    assert!(
                        (masked(id) - guess).abs() <= 0.002,
                        "{spec}: {id} {} vs guess {guess}",
                        masked(id)
                    );
                }
            }
        }
    }
}

#[test]
fn split_layout_matches_packed() {
    let scene = scene::load("cornell-sphere:material=gold").unwrap();
    let _g = common::gpu_lock();
    let packed = common::render(
        common::technique("impostors/false-position-4").as_mut(),
        &scene,
        0.0,
        64,
    );
    let split = common::render(
        common::technique("impostors/false-position-4-split").as_mut(),
        &scene,
        0.0,
        64,
    );
    let max = packed
        .pixels
        .iter()
        .zip(&split.pixels)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    assert!(max <= 1e-3, "split and packed layouts differ by {max}");
}

/// Caustics (paper section 5): the reference's caustic photons land on the floor under the
/// glass sphere and in its shadow; without caustics every variant misses them. Outside the
/// mask (the sphere), the caustics variant must bring the image closer to the reference
/// than double-refraction alone, and the caustic energy it adds must be within a factor of 2
/// of the reference's.
#[test]
fn caustics_reduce_the_error_outside_the_sphere() {
    for spec in [
        "cornell-sphere:material=glass-1.5",
        "cornell-sphere:material=gold",
    ] {
        let ids = [
            "impostors/double-refraction",
            "impostors/caustics",
            "impostors/caustics-compute",
        ];
        let rows = evaluate(spec, &ids);
        let reference = reference(spec);
        let outside: Vec<bool> = reference.mask.iter().map(|m| !m).collect();
        let image = |id: &str| &rows.iter().find(|r| r.id == id).unwrap().image;
        let plain = image("impostors/double-refraction");
        let e_plain = masked_rmse(plain, &reference.image, &outside);
        let energy = |img: &HdrImage| -> f64 {
            img.pixels
                .iter()
                .zip(&plain.pixels)
                .zip(&outside)
                .filter(|(_, o)| **o)
                .map(|((a, b), _)| (0..3).map(|c| (a[c] - b[c]) as f64).sum::<f64>())
                .sum()
        };
        let expected = energy(&reference.image);
        for id in &ids[1..] {
            let caustics = image(id);
            let e_caustics = masked_rmse(caustics, &reference.image, &outside);
            let added = energy(caustics);
            println!(
                "  {id}, outside the sphere: RMSE without caustics {e_plain:.5}, with {e_caustics:.5}; caustic energy added {added:.2}, reference {expected:.2}"
            );
            assert!(
                e_caustics < e_plain,
                "{id} on {spec}: caustics did not reduce the error ({e_caustics} vs {e_plain})"
            );
            assert!(
                added > 0.5 * expected && added < 2.0 * expected,
                "{id} on {spec}: caustic energy {added} vs reference {expected}"
            );
        }
    }
}

/// A moving refractor must be right in every frame (issue: the refractor map was searched
/// from the object's centre at prepare time, so after time 0 double refraction looked up the
/// sphere 0.5 m from where it stood). Prepared at time 0 and rendered along the sphere's
/// motion (it moves 0.5 m along -x by time 1 and back by time 2), every frame's masked error
/// against the reference *at that time* must stay at the time-0 level. Double refraction
/// regenerates its environment map by its threshold; the refractor map is never re-rendered.
#[test]
fn moving_refractor_is_right_at_every_time() {
    let spec = "cornell-sphere:material=glass-1.5";
    let ids = ["impostors/double-refraction", "impostors/caustics"];
    let at_start = evaluate_stale(spec, &ids, &[0.0]);
    for t in [0.5f32, 1.0] {
        let moved = evaluate_stale_regenerating(spec, &ids, &[0.0, t]);
        for id in ids {
            let start = get(&at_start, id).flip_mean_masked;
            let now = get(&moved, id).flip_mean_masked;
            // Measured (96 x 96), t = 0 / 0.5 / 1: double-refraction 0.0130 / 0.0143 /
            // 0.0176, caustics 0.0085 / 0.0096 / 0.0118; searched from the prepare-time
            // centre, double-refraction was 0.518 at t = 0.5. Bound: time-0 error + 0.01.
            assert!(
                now <= start + 0.01,
                "{id} at time {t}: masked FLIP {now:.4} vs {start:.4} at time 0"
            );
        }
    }
}

/// The engine baseline, parallax-corrected cube maps, against `Hit()` at the same map
/// resolution (256), at times 0, 1 and 2 of the camera path. `box-projected-object` (and
/// `box-projected-double` through glass) use the impostor's own map, so only the lookup
/// differs: in the box room of cornell-sphere the proxy box *is* the room, box projection finds
/// every wall point exactly and equals `Hit()` (measured masked FLIP differences 0.0000-0.0003,
/// bound 0.001); in cornell-box the tall box stands inside the proxy and is reflected where the
/// walls behind it are, so `Hit()` is better at every time (by 0.0012, 0.0094, 0.0012 at
/// t = 0, 1, 2, 96 x 96; asserted: never worse, and by 0.005 at t = 1). The probe as engines
/// ship it (`box-projected`: captured once, where `scene::probe_centre` puts it, the sphere's
/// centre at time 0, each frame here being its first) is nearly as good in the box room
/// (mirror 0.0088, 0.0117, 0.0088 against Hit()'s 0.0085-0.0087; bound 0.004: from where the
/// sphere stood at t = 0 the room's texels are spread differently) and never better than the
/// object's own map in cornell-box, which it equals where the object stood when it was
/// captured (0.0482, 0.0489, 0.0482 against 0.0482, 0.0354, 0.0482). Everything is far
/// below classic. Rendered along the path from t = 0 to 1 (mirror sphere), the probe captured
/// once reflects the sphere's shadow where it was at t = 0: masked FLIP 0.1016 against the
/// object map's 0.0087 (asserted: over 3x).
#[test]
fn box_projection_equals_hit_in_a_box_room_and_loses_in_a_concave_one() {
    let pairs = [
        (
            "cornell-sphere:material=mirror",
            "impostors/false-position-4",
            "impostors/box-projected-object",
        ),
        (
            "cornell-sphere:material=glass-1.5",
            "impostors/double-refraction",
            "impostors/box-projected-double",
        ),
        (
            "cornell-box",
            "impostors/false-position-4",
            "impostors/box-projected-object",
        ),
    ];
    for (spec, hit_id, box_id) in pairs {
        for t in [0.0f32, 1.0, 2.0] {
            let rows = evaluate_frames(
                spec,
                &[
                    "impostors/classic",
                    hit_id,
                    box_id,
                    "impostors/box-projected",
                ],
                &[t],
                false,
            );
            let (classic, hit, boxed) = (
                get(&rows, "impostors/classic").flip_mean_masked,
                get(&rows, hit_id).flip_mean_masked,
                get(&rows, box_id).flip_mean_masked,
            );
            assert!(
                boxed < 0.5 * classic,
                "{spec} t {t}: {box_id} {boxed} must be well below classic {classic}"
            );
            let room = get(&rows, "impostors/box-projected").flip_mean_masked;
            println!(
                "{spec} t {t}: classic {classic:.4}, Hit() {hit:.4}, {box_id} {boxed:.4}, room \
                 probe {room:.4}"
            );
            if spec.starts_with("cornell-sphere") {
                assert!(
                    (boxed - hit).abs() <= 0.001,
                    "{spec} t {t}: box projection {boxed} vs Hit() {hit} differ in a box room"
                );
                if spec.ends_with("mirror") {
                    assert!(
                        (room - hit).abs() <= 0.004,
                        "{spec} t {t}: the room probe {room} vs Hit() {hit} in a box room"
                    );
                }
            } else {
                // At t = 0 and 2 the object stands where the probe was captured: the two maps
                // are the same; at t = 1 it has moved and the probe must lose.
                if t == 1.0 {
                    assert!(
                        room > boxed,
                        "{spec} t {t}: the room probe {room} should lose to the object's map \
                         {boxed}"
                    );
                }
                let margin = if t == 1.0 { 0.005 } else { 0.0 };
                assert!(
                    boxed > hit + margin,
                    "{spec} t {t}: Hit() {hit} should beat box projection {boxed} by {margin}"
                );
            }
        }
    }
    // What moves: the probe captured at t = 0 still shows the sphere's shadow where the sphere
    // stood then (an engine's baked probe has no moving objects or their shadows at all; either
    // way the reflection is wrong once the sphere moved). Rendered along the path to t = 1 the
    // room probe's error grows; the object's own map is re-captured every frame.
    let rows = evaluate_frames(
        "cornell-sphere:material=mirror",
        &["impostors/box-projected-object", "impostors/box-projected"],
        &[0.0, 0.5, 1.0],
        false,
    );
    let (object_map, stale_probe) = (
        get(&rows, "impostors/box-projected-object").flip_mean_masked,
        get(&rows, "impostors/box-projected").flip_mean_masked,
    );
    assert!(
        stale_probe > 3.0 * object_map,
        "the probe captured at t = 0 should be far off at t = 1: {stale_probe} vs {object_map}"
    );
}
