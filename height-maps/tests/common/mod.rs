//! Analytic height fields of surfaces of revolution about the `v` axis, and their exact
//! entry and exit points: the yardsticks of the search's tests.

#![allow(dead_code)]

use glam::Vec3;
use height_maps::search::{Bounds, HeightField, SampledField, inside, select_segment};

/// A solid of revolution `u^2 + w^2 < r(v)^2` for `|v| < v_half`: its height field is
/// `h(u, v) = sqrt(r(v)^2 - u^2)`, its normal the gradient `(u, -r r', w)`.
pub struct Revolution {
    pub r: fn(f32) -> f32,
    pub dr: fn(f32) -> f32,
    pub v_half: f32,
    pub r_max: f32,
}

impl HeightField for Revolution {
    fn bounds(&self) -> Bounds {
        Bounds {
            half_width: self.r_max * 1.01,
            v_min: -self.v_half * 1.01,
            v_max: self.v_half * 1.01,
            height: self.r_max * 1.01,
        }
    }

    fn sample(&self, u: f32, v: f32) -> (f32, Vec3) {
        let empty = (self.bounds().empty_height(), Vec3::ZERO);
        if v.abs() >= self.v_half {
            return empty;
        }
        let r = (self.r)(v);
        if u.abs() >= r {
            return empty;
        }
        let h = (r * r - u * u).sqrt();
        (h, Vec3::new(u, -r * (self.dr)(v), h))
    }
}

/// A convex solid: the ellipsoid of radius 0.6 and half-height 0.9.
pub fn ellipsoid() -> Revolution {
    Revolution {
        r: |v| 0.6 * (1.0 - (v / 0.9) * (v / 0.9)).max(0.0).sqrt(),
        dr: |v| {
            let s = (1.0 - (v / 0.9) * (v / 0.9)).max(1e-6);
            -0.6 * v / (0.81 * s.sqrt())
        },
        v_half: 0.9,
        r_max: 0.6,
    }
}

/// A solid that is not convex: a vase whose radius swings between 0.15 and 0.55 (a neck, two
/// bellies, flat ends).
pub fn vase() -> Revolution {
    Revolution {
        r: |v| 0.35 + 0.2 * (2.5 * v).cos(),
        dr: |v| -0.5 * (2.5 * v).sin(),
        v_half: 0.9,
        r_max: 0.55,
    }
}

/// The analytic field sampled into a `resolution`-square map.
pub fn sample(field: &dyn HeightField, resolution: u32) -> SampledField {
    SampledField::from_fn(field.bounds(), resolution, resolution, |u, v| {
        let (h, n) = field.sample(u, v);
        (h > 0.0).then_some((h, n))
    })
}

/// The first `t` in `[a, b]` where `inside` changes from `from` (dense march, then 60
/// bisections).
fn first_change(
    field: &dyn HeightField,
    o: Vec3,
    d: Vec3,
    a: f32,
    b: f32,
    from: bool,
) -> Option<f32> {
    const MARCH: usize = 20_000;
    let mut previous = a;
    for k in 1..=MARCH {
        let t = a + (b - a) * k as f32 / MARCH as f32;
        if inside(field, o + d * t) != from {
            let (mut lo, mut hi) = (previous, t);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if inside(field, o + d * m) != from {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            return Some(0.5 * (lo + hi));
        }
        previous = t;
    }
    None
}

/// The exact first hit of the solid along a ray from outside.
pub fn exact_entry(field: &dyn HeightField, o: Vec3, d: Vec3) -> Option<f32> {
    let s = select_segment(o, d, &field.bounds())?;
    first_change(field, o, d, s.near, s.far, false)
}

/// The exact exit of the solid along a ray from inside.
pub fn exact_exit(field: &dyn HeightField, o: Vec3, d: Vec3) -> f32 {
    let (lo, hi) = field.bounds().box_corners();
    let far = gpu::prelude::ray_box(o, d, lo, hi).y;
    first_change(field, o, d, 0.0, far, true).unwrap_or(far)
}
