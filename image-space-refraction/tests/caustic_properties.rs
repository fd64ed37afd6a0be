//! Properties of the caustic twins (`image_space_refraction::caustics`, section 3.2); their GPU
//! conformance, and that of `shaders/nearby.wgsl`, is in `conformance.rs`.

use glam::{Vec2, Vec3};
use image_space_refraction::caustics::{filter, filter_weight, scatter};
use proptest::prelude::*;

/// Sparse counts: `(x, y, rgb)` at texels of a `res`^2 layer, at least `border` from its edges.
fn sparse_counts(res: u32, border: u32, photons: &[(f32, f32, [f32; 3])]) -> Vec<[f32; 3]> {
    let mut counts = vec![[0.0f32; 3]; (res * res) as usize];
    let span = (res - 2 * border) as f32;
    for &(a, b, c) in photons {
        let x = border + ((a * span) as u32).min(res - 2 * border - 1);
        let y = border + ((b * span) as u32).min(res - 2 * border - 1);
        let t = &mut counts[(y * res + x) as usize];
        for ch in 0..3 {
            t[ch] += c[ch];
        }
    }
    counts
}

fn sums(counts: &[[f32; 3]]) -> [f64; 3] {
    let mut s = [0.0f64; 3];
    for c in counts {
        for ch in 0..3 {
            s[ch] += f64::from(c[ch]);
        }
    }
    s
}

fn photon_list() -> impl Strategy<Value = Vec<(f32, f32, [f32; 3])>> {
    proptest::collection::vec(
        (
            0.0f32..1.0,
            0.0f32..1.0,
            [0u32..5000, 0u32..5000, 0u32..5000].prop_map(|c| c.map(|c| c as f32)),
        ),
        0..40,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The normalized filter keeps a layer's power times `s` when no photon lies within `k`
    /// texels of the border, and never adds power otherwise.
    #[test]
    fn filter_keeps_power_times_scale(
        res in 16u32..=64,
        k in 0u32..=3,
        scale in 0.1f32..10.0,
        photons in photon_list(),
    ) {
        let inside = sparse_counts(res, k, &photons);
        let (sin, sout) = (sums(&inside), sums(&filter(&inside, res, k, scale)));
        for ch in 0..3 {
            let want = f64::from(scale) * sin[ch];
            prop_assert!(
                (sout[ch] - want).abs() <= 1e-4 * want,
                "channel {ch}: filtered {} vs s x photons {want}", sout[ch]
            );
        }
        let anywhere = sparse_counts(res, 0, &photons);
        let (sin, sout) = (sums(&anywhere), sums(&filter(&anywhere, res, k, scale)));
        for ch in 0..3 {
            let bound = f64::from(scale) * sin[ch];
            prop_assert!(sout[ch] <= bound * (1.0 + 1e-4), "channel {ch}: {} > {bound}", sout[ch]);
        }
    }

    /// The paper's weights are positive over the whole window and symmetric in i, j and
    /// their signs.
    #[test]
    fn filter_weights_are_positive_and_symmetric(k in 0i32..=64, a in 0.0f64..=1.0, b in 0.0f64..=1.0) {
        let i = (a * f64::from(2 * k)).round() as i32 - k;
        let j = (b * f64::from(2 * k)).round() as i32 - k;
        let w = filter_weight(i, j, k);
        prop_assert!(w > 0.0 && w.is_finite(), "w({i}, {j}, {k}) = {w}");
        for other in [filter_weight(j, i, k), filter_weight(-i, j, k), filter_weight(i, -j, k)] {
            prop_assert_eq!(w, other);
        }
    }

    /// Each photon's power lands in texel floor(uv res) (clamped to the last texel) of its
    /// layer, as round(power / unit) counts; the total counts times `unit` equal the total
    /// power within unit / 2 per photon.
    #[test]
    fn scatter_puts_power_in_the_photon_texel(
        res in 1u32..=48,
        layers in 1u32..=3,
        unit in 1e-3f32..1.0,
        photons in proptest::collection::vec(
            (
                prop_oneof![3 => 0.0f32..=1.0, 1 => Just(1.0f32), 1 => (0u32..=48).prop_map(|i| i as f32 / 48.0)],
                prop_oneof![3 => 0.0f32..=1.0, 1 => Just(1.0f32), 1 => Just(0.0f32)],
                0u32..3,
                [0.0f32..100.0, 0.0f32..100.0, 0.0f32..100.0],
            ),
            0..30,
        ),
    ) {
        let photons: Vec<(Vec2, u32, Vec3)> = photons
            .into_iter()
            .map(|(u, v, l, p)| (Vec2::new(u, v), l % layers, Vec3::from(p)))
            .collect();
        let r = res as usize;
        for &(uv, layer, power) in &photons {
            let counts = scatter(&[(uv, layer, power)], res, layers, unit);
            let x = ((uv.x * res as f32).floor() as usize).min(r - 1);
            let y = ((uv.y * res as f32).floor() as usize).min(r - 1);
            let at = (layer as usize * r + y) * r + x;
            let want = power.to_array().map(|p| (p / unit).round() as u32);
            prop_assert_eq!(counts[at], want);
            prop_assert!(counts.iter().enumerate().all(|(i, c)| i == at || *c == [0; 3]));
        }
        let counts = scatter(&photons, res, layers, unit);
        for ch in 0..3 {
            let total: f64 = counts.iter().map(|c| f64::from(c[ch])).sum::<f64>() * f64::from(unit);
            let power: f64 = photons.iter().map(|p| f64::from(p.2[ch])).sum();
            let slack = photons.len() as f64 * f64::from(unit) * (0.5 + 1e-5) + 1e-9;
            prop_assert!((total - power).abs() <= slack, "channel {ch}: {total} vs {power}");
        }
    }
}
