//! Soft volumes: billboards, slices and ray-traced volumes against the scene depth, after
//! chapter 6 of van Dongen's thesis "Using raycasting in GPU shaders to enhance real-time
//! graphics" (`raycasting-in-shaders-interior-mapping-and-volumes.md`).
//!
//! - [`path_length`]: the visible path length through each volume primitive, clipped by the
//!   eye and the scene depth, and the path-length-to-opacity functions; the WGSL in
//!   `shaders/path_length.wgsl` is its twin.
//! - [`pass`]: the ray-traced soft volumes as one pass of a renderer's own frame
//!   ([`SoftVolumePass`]: its colour and depth targets in its formats, its camera, no scene).
//! - [`technique`]: the variants (the 17 of the thesis's figure 6.23 plus particle-system
//!   versions) behind `scene::Technique`.
//!
//! What the variants are measured against is not in the library: the scene's reference with
//! its participating media (the `truth` crate, a dev-dependency), and, as a second figure for
//! tests, each variant's own model (uniform spheres with its opacity function) in
//! `tests/common/mod.rs`, which the tests and the example share.
//!
//! See `README.md` for how each variant maps to the thesis and where it departs from it.

// Every public item says what it is for: users lift this crate into their own renderers.
#![warn(missing_docs)]

pub mod pass;
pub mod path_length;
pub mod technique;

pub use pass::{SoftVolume, SoftVolumePass};
pub use path_length::{OpacityFn, Primitive};
pub use technique::{Method, Variant, VolumeSet, VolumeTechnique};

/// This crate's family: [`techniques`] and [`image_checks`], listed once by the harness.
pub const FAMILY: scene::Family = scene::Family {
    name: "volumes",
    techniques,
    image_checks,
};

/// All technique variants of this crate: the 17 of the thesis's figure 6.23 in its order,
/// then the particle-system versions.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::all_variants()
        .into_iter()
        .map(|v| Box::new(VolumeTechnique::new(v)) as Box<dyn scene::Technique>)
        .collect()
}

/// The image checks of this crate (run by the tests crate against the reference, participating
/// media included, along the camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    use scene::ImageCheck;
    let check =
        |technique, flip, rmse, reason| ImageCheck::new(technique, "smoke", flip, rmse, reason);
    vec![
        check(
            "volumes/slices-19-float",
            0.34,
            0.21,
            "uniform-density slices against the reference's textured, falling-off medium; the \
             error grows as the camera nears the smoke: measured FLIP 0.127 / 0.190 / 0.271 at \
             t = 0 / 1 / 2, RMSE up to 0.164 (64 x 64)",
        ),
        check(
            "volumes/raytraced-thickness",
            0.34,
            0.21,
            "the thesis's best sphere variant; same model limit as the slices: measured FLIP \
             up to 0.272, RMSE up to 0.164",
        ),
        check(
            "volumes/depth-fade",
            0.37,
            0.21,
            "the engine baseline (depth-fade billboard) on the large volume: the billboard's \
             model limit plus the fade; measured FLIP 0.156 / 0.221 / 0.295 at t = 0 / 1 / 2, \
             RMSE up to 0.169, beside raytraced-thickness's 0.272 / 0.164",
        ),
        check(
            "volumes/particles-depth-fade",
            0.15,
            0.062,
            "depth-fade particles: measured FLIP up to 0.118, RMSE up to 0.050, beside \
             particles-slices-9's 0.104 / 0.038",
        ),
        check(
            "volumes/particles-slices-9",
            0.14,
            0.048,
            "the particle system, whose many small spheres follow the medium's falloff: \
             measured FLIP up to 0.104, RMSE up to 0.038",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each opacity function, with its scale, gives the true centre opacity of the built-in
    /// smoke over the diameter (closed form of the `k = 1` chord, `scene::density`).
    #[test]
    fn opacity_scale_matches_the_true_centre_opacity() {
        let smoke = scene::load("smoke").unwrap();
        let v = &smoke.volumes[0];
        let smooth = scene::DensityProfile {
            noise: 0.0,
            ..v.profile
        };
        let tau = scene::density::chord_optical_depth(v.density, v.radius, &smooth, 0.0).unwrap();
        assert!(
            (technique::centre_optical_depth(v) - tau).abs() < 1e-4,
            "{tau}"
        );
        let alpha = 1.0 - (-tau).exp();
        for f in [OpacityFn::Linear, OpacityFn::Log, OpacityFn::Sqrt] {
            let s = technique::opacity_scale(v, f);
            assert!((f.opacity(2.0 * v.radius, s) - alpha).abs() < 1e-4, "{f:?}");
        }
    }

    #[test]
    fn ids_are_the_thesis_tests() {
        let ids: Vec<String> = technique::thesis_variants()
            .iter()
            .map(|v| v.id())
            .collect();
        let expected = [
            "volumes/billboard",
            "volumes/slices-5",
            "volumes/slices-9",
            "volumes/slices-19",
            "volumes/slices-39",
            "volumes/slices-79",
            "volumes/slices-5-float",
            "volumes/slices-9-float",
            "volumes/slices-19-float",
            "volumes/slices-39-float",
            "volumes/slices-79-float",
            "volumes/raytraced-constant",
            "volumes/raytraced-linear",
            "volumes/raytraced-sphere-log",
            "volumes/raytraced-sphere-linear",
            "volumes/raytraced-sphere-sqrt",
            "volumes/raytraced-thickness",
        ];
        assert_eq!(ids, expected);
        for (i, v) in technique::thesis_variants().iter().enumerate() {
            assert_eq!(v.thesis_test(), Some(i as u32 + 1), "{}", v.id());
        }
        let all: Vec<String> = techniques().iter().map(|t| t.id()).collect();
        let mut unique = all.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), all.len(), "ids are unique: {all:?}");
        assert!(all.contains(&"volumes/particles-billboard".to_string()));
        assert!(all.contains(&"volumes/particles-raytraced-sphere-log".to_string()));
    }
}
