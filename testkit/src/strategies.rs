//! The proptest strategies that the property tests of the Rust twins share: points in a box,
//! unit directions, and unit directions with components exactly zero (rays parallel to an
//! axis or a plane family, the cases a slab or plane search must treat apart).
//!
//! Each strategy says what it generates, including the degenerate values it draws on purpose;
//! what only one test needs (a ray aimed at its sphere, its scene distances) stays in that
//! test.
//!
//! ```
//! use proptest::prelude::*;
//! use testkit::strategies::{direction_with_zeros, unit_vector, vec3_in};
//!
//! proptest! {
//!     // `#[test]` in a test file.
//!     fn directions_are_unit(d in unit_vector(), p in vec3_in(-5.0, 5.0), z in direction_with_zeros()) {
//!         prop_assert!((d.length() - 1.0).abs() < 1e-5);
//!         prop_assert!((z.length() - 1.0).abs() < 1e-5);
//!         prop_assert!(p.abs().max_element() < 5.0);
//!     }
//! }
//! # directions_are_unit();
//! ```

use glam::Vec3;
use proptest::prelude::*;

/// Points of the box `[lo, hi)^3`: each coordinate uniform in `lo..hi`, independently.
/// `lo` itself can be drawn, `hi` cannot; nothing degenerate is added.
///
/// # Panics
/// When the strategy is used with `lo >= hi` (proptest's own check of an empty range).
pub fn vec3_in(lo: f32, hi: f32) -> impl Strategy<Value = Vec3> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Unit vectors distributed uniformly over the sphere, without rejection: `z` uniform in
/// `[-1, 1]` (the poles `z = ±1` included) and the azimuth uniform in `[0, 2π)` (Archimedes'
/// hat-box theorem). Normalised once more, so the length is 1 to f32 rounding also at the
/// poles. Components are never exactly zero on purpose; see [`direction_with_zeros`].
pub fn unit_vector() -> impl Strategy<Value = Vec3> {
    (-1.0f32..=1.0, 0.0f32..std::f32::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    })
}

/// Unit directions with components exactly zero on purpose: a [`unit_vector`] whose every
/// component is independently replaced by `+0.0` (probability 1/6), `-0.0` (1/6) or kept
/// (2/3), then renormalised. So 19 in 27 directions lie in at least one axis plane and 7 in
/// 27 are axis-aligned (two zero components), with both signs of zero: the cases where slab
/// tests divide by zero and grid walks must not step along a flat axis. A direction left with
/// all components below 1e-3 (all three zeroed) becomes `-Y`.
pub fn direction_with_zeros() -> impl Strategy<Value = Vec3> {
    (unit_vector(), [0u8..6, 0u8..6, 0u8..6]).prop_map(|(d, mask)| {
        let mut d = d;
        for a in 0..3 {
            match mask[a] {
                0 => d[a] = 0.0,
                1 => d[a] = -0.0,
                _ => {}
            }
        }
        if d.abs().max_element() < 1e-3 {
            d = Vec3::new(0.0, -1.0, 0.0);
        }
        d / d.length()
    })
}
