//! Every image check the technique crates declare (`harness::image_checks`, one line per
//! crate), run against the reference along the camera path: the generic "each technique is
//! within its stated error" test, like the wgpu examples' image tests.
//!
//! Each check renders its technique at the start, middle and end of the scene's camera path
//! (`scene::technique::check_times`) and compares every frame with the CPU reference of the
//! same view (photon density of the harness, `ReferenceOptions::for_image`). A failure names
//! the check, the frame and both measured values; the check's `reason` says where its bound
//! comes from.
//!
//! A check whose technique needs a device feature the adapter lacks cannot run there: it is
//! listed as not run, with the feature, and the test says how many of the checks ran. With
//! `IMAGE_CHECKS_ALL=require` (what `cargo xtask test` sets on Mesa 25's lavapipe, which has
//! every feature the techniques ask for) a check that cannot run fails the test instead, so
//! that CI's adapter runs every check.

use scene::technique::check_times;
use std::collections::BTreeMap;
use testkit::{Shot, context, render};

#[test]
fn every_declared_image_check_holds_along_the_camera_path() {
    let checks = harness::image_checks();
    assert!(!checks.is_empty(), "no image checks declared");
    let mut references: BTreeMap<(String, u32, u32), gpu::HdrImage> = BTreeMap::new();
    let mut failures = Vec::new();
    let mut not_run = Vec::new();
    for check in &checks {
        let scene = scene::load(check.scene).unwrap_or_else(|e| panic!("{check:?}: {e}"));
        let mut technique = harness::registry()
            .into_iter()
            .find(|t| t.id() == check.technique)
            .unwrap_or_else(|| panic!("image check names unknown technique {}", check.technique));
        for (name, value) in check.params {
            technique
                .set_param(name, *value)
                .unwrap_or_else(|e| panic!("{check:?}: {e}"));
        }
        assert!(
            technique.supports(&scene),
            "{} does not support {}",
            check.technique,
            check.scene
        );
        let times = check_times(scene.camera_path.duration());
        assert!(
            check.rmse_per_frame.is_empty() || check.rmse_per_frame.len() == times.len(),
            "{check:?}: {} per-frame RMSE bounds for {} frames",
            check.rmse_per_frame.len(),
            times.len()
        );
        assert!(
            check.rmse_per_frame.iter().all(|&b| b <= check.max_rmse),
            "{check:?}: a per-frame RMSE bound above max_rmse"
        );
        if let Err(e) = context().require(technique.required_features()) {
            not_run.push(format!("{} on {}: {e}", check.technique, check.scene));
            continue;
        }
        for (frame, time) in times.into_iter().enumerate() {
            let max_rmse = check.rmse_bound(frame);
            let camera = scene.camera_at(time);
            let key = (check.scene.to_string(), check.size, time.to_bits());
            let truth = references.entry(key).or_insert_with(|| {
                let options = truth::reference::ReferenceOptions::for_image(check.size, check.size);
                truth::reference::render(&scene, &camera, time, check.size, check.size, &options)
                    .image
            });
            let image = render(
                technique.as_mut(),
                &scene,
                Shot {
                    camera,
                    time,
                    size: check.size,
                },
            );
            let (m, _) = truth::metrics::compare(&image, truth, None);
            println!(
                "{} on {} at t={time}: FLIP {:.4} (bound {}), RMSE {:.4} (bound {})",
                check.technique, check.scene, m.flip_mean, check.max_flip_mean, m.rmse, max_rmse
            );
            if m.nan_pixels > 0
                || m.flip_mean > check.max_flip_mean as f64
                || m.rmse > max_rmse as f64
            {
                failures.push(format!(
                    "{} on {} at t={time}: FLIP {:.4} > {} or RMSE {:.4} > {} or {} NaN pixels \
                     ({})",
                    check.technique,
                    check.scene,
                    m.flip_mean,
                    check.max_flip_mean,
                    m.rmse,
                    max_rmse,
                    m.nan_pixels,
                    check.reason
                ));
            }
        }
    }
    let adapter = &context().summary;
    println!(
        "image checks: {} of {} ran on {} ({}){}",
        checks.len() - not_run.len(),
        checks.len(),
        adapter.name,
        adapter.driver,
        if not_run.is_empty() {
            String::new()
        } else {
            format!("; not run: {not_run:#?}")
        }
    );
    if std::env::var("IMAGE_CHECKS_ALL").is_ok_and(|v| v == "require") {
        failures.extend(
            not_run
                .iter()
                .map(|n| format!("not run, but IMAGE_CHECKS_ALL=require: {n}")),
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
