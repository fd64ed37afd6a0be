//! A technique's error frames against the references at their times: the figures of its row
//! and the FLIP maps of its images.

use crate::Reference;
use crate::measure::TechniqueRun;
use crate::report::{ErrorAt, ResultRow};
use scene::{Scene, Technique};

/// The reference at one error-frame time.
pub struct TimedReference {
    pub time: f32,
    pub reference: Reference,
}

/// Share of pixels that must show light (a channel above [`LIT_RADIANCE`]) for a reference
/// to be scored against: below it the reference is (nearly) black, and every technique that
/// draws black too would score a perfect, meaningless, 0 error.
pub const MIN_LIT_SHARE: f64 = 0.01;
/// Linear radiance above which a reference pixel counts as lit (sRGB 8-bit value 3).
pub const LIT_RADIANCE: f32 = 1e-3;

/// `Some(reason)` when `image` is too dark to score against (see [`MIN_LIT_SHARE`]).
pub fn black_reference(image: &gpu::HdrImage) -> Option<String> {
    let lit = image
        .pixels
        .iter()
        .filter(|p| p[..3].iter().any(|&c| c > LIT_RADIANCE))
        .count();
    let share = lit as f64 / image.pixels.len().max(1) as f64;
    (share < MIN_LIT_SHARE).then(|| {
        format!(
            "invalid comparison: the reference is (nearly) black ({:.2}% of pixels above \
             {LIT_RADIANCE} radiance, {}% needed), so no error is scored; does the scene \
             have lights that reach what the camera sees?",
            share * 100.0,
            MIN_LIT_SHARE * 100.0
        )
    })
}

/// The row with the run's times and, where references exist, each error frame's figures
/// against the reference at its time (through the technique's `ground_truth` hook), and the
/// FLIP maps in the error frames' order.
pub fn score(
    technique: &dyn Technique,
    scene: &Scene,
    references: &[TimedReference],
    row: ResultRow,
    run: &TechniqueRun,
) -> (ResultRow, Vec<truth::metrics::FlipMap>) {
    let row = row.with_run(run);
    if references.is_empty() {
        return (row, Vec::new());
    }
    if let Some(reason) = references
        .iter()
        .find_map(|r| black_reference(&r.reference.image))
    {
        return (row.with_error(reason), Vec::new());
    }
    let mut errors = Vec::new();
    let mut flips = Vec::new();
    for frame in &run.error_frames {
        let Some(r) = references.iter().find(|r| r.time == frame.time) else {
            return (
                row.with_error(format!("no reference at time {}", frame.time)),
                flips,
            );
        };
        let view = scene::View {
            camera: scene.camera_at(frame.time),
            time: frame.time,
            width: row.width,
            height: row.height,
        };
        let reference = &r.reference;
        let truth = technique.ground_truth(scene, &view, &reference.image);
        let (m, map) = truth::metrics::compare(
            &frame.image,
            truth.as_ref().unwrap_or(&reference.image),
            Some(&reference.mask),
        );
        errors.push(ErrorAt::new(frame.time, &m));
        flips.push(map);
    }
    (row.with_errors_along(errors), flips)
}
