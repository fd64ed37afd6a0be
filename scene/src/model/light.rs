//! Lights: the three types of glTF's `KHR_lights_punctual` (point, spot, directional), and
//! the light each sends toward a point, which every renderer of the workspace evaluates the
//! same way (the CPU reference, the GPU ray tracer, `scene.wgsl`'s `light_toward`).

use glam::Vec3;

/// How a light emits: the three types of glTF's `KHR_lights_punctual`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Radiant intensity `intensity` (W/sr) in every direction from `position`, falling off
    /// with the inverse square of the distance.
    Point,
    /// A point light whose intensity is scaled by glTF's cone falloff about `direction` (unit,
    /// the way the light points): full inside the half-angle `inner_cone`, none beyond
    /// `outer_cone` (radians, `0 <= inner_cone <= outer_cone <= pi / 2`), between them the
    /// square of a linear ramp in the cosine ([`Light::emission_factor`]). Equal angles are a
    /// hard edge (the ramp's divisor is at least 0.001, as glTF's sample code has it).
    Spot {
        direction: Vec3,
        inner_cone: f32,
        outer_cone: f32,
    },
    /// Parallel light travelling along `direction` (unit) from infinitely far, a sun:
    /// `intensity` is the irradiance (W/m^2) on a surface facing it, with no falloff;
    /// `position` only records where the light was placed.
    Directional { direction: Vec3 },
}

/// A light: RGB `intensity` in W/sr (point and spot lights) or W/m^2 (directional lights).
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: String,
    pub position: Vec3,
    pub intensity: Vec3,
    pub kind: LightKind,
}

/// Where the light of one [`Light`] comes from, seen from a point ([`Light::toward`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toward {
    /// Unit direction from the point toward the light.
    pub dir: Vec3,
    /// The squared distance to the light, by which the intensity is divided (1 for a
    /// directional light, whose `intensity` is already an irradiance).
    pub distance_squared: f32,
    /// The spot's cone falloff in this direction ([`Light::emission_factor`]; 1 for point
    /// and directional lights).
    pub factor: f32,
}

impl Light {
    /// A point light.
    pub fn point(name: impl Into<String>, position: Vec3, intensity: Vec3) -> Self {
        Self {
            name: name.into(),
            position,
            intensity,
            kind: LightKind::Point,
        }
    }

    /// The unit direction the light travels along: a spot's axis, a directional light's
    /// direction; `None` for a point light.
    pub fn direction(&self) -> Option<Vec3> {
        match self.kind {
            LightKind::Point => None,
            LightKind::Spot { direction, .. } | LightKind::Directional { direction } => {
                Some(direction)
            }
        }
    }

    /// Whether light from it arrives in parallel (a directional light).
    pub fn is_directional(&self) -> bool {
        matches!(self.kind, LightKind::Directional { .. })
    }

    /// The fraction of `intensity` a point or spot light sends along the unit direction `w`
    /// leaving it: 1 for a point light; for a spot, `KHR_lights_punctual`'s recommended
    /// falloff `clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1)^2`, `cos` the cosine
    /// between `w` and the spot's axis (the divisor at least 0.001). 1 for a directional light.
    pub fn emission_factor(&self, w: Vec3) -> f32 {
        match self.kind {
            LightKind::Spot {
                direction,
                inner_cone,
                outer_cone,
            } => spot_falloff(direction.dot(w), inner_cone.cos(), outer_cone.cos()),
            _ => 1.0,
        }
    }

    /// Where this light's light comes from at `p`: `None` when `p` is where the light is.
    /// For a point or spot light `dir` is `(position - p) / |position - p|`; for a
    /// directional light, `-direction`.
    pub fn toward(&self, p: Vec3) -> Option<Toward> {
        if let LightKind::Directional { direction } = self.kind {
            return Some(Toward {
                dir: -direction,
                distance_squared: 1.0,
                factor: 1.0,
            });
        }
        let to_light = self.position - p;
        let d2 = to_light.length_squared();
        if !(d2 > 0.0) {
            return None;
        }
        let dir = to_light / d2.sqrt();
        Some(Toward {
            dir,
            distance_squared: d2,
            factor: self.emission_factor(-dir),
        })
    }

    /// The shadow ray from `origin` toward the light: its unit direction and length (infinite
    /// for a directional light); `None` when `origin` is where the light is.
    pub fn shadow_ray(&self, origin: Vec3) -> Option<(Vec3, f32)> {
        if let LightKind::Directional { direction } = self.kind {
            return Some((-direction, f32::INFINITY));
        }
        let seg = self.position - origin;
        let len = seg.length();
        (len > 0.0).then(|| (seg / len, len))
    }

    /// The light as both GPU renderers' records encode it (`scene.wgsl`'s `LightGpu`, the ray
    /// tracer's table): its kind (0 point, 1 spot, 2 directional), the direction it points or
    /// travels (zero for a point light) and a spot's cosines of its inner and outer half-angles
    /// (zero otherwise).
    pub fn shader_fields(&self) -> (f32, Vec3, [f32; 4]) {
        match self.kind {
            LightKind::Point => (0.0, Vec3::ZERO, [0.0; 4]),
            LightKind::Spot {
                direction,
                inner_cone,
                outer_cone,
            } => (
                1.0,
                direction,
                [inner_cone.cos(), outer_cone.cos(), 0.0, 0.0],
            ),
            LightKind::Directional { direction } => (2.0, direction, [0.0; 4]),
        }
    }

    /// The words a message names the light's type with.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            LightKind::Point => "point",
            LightKind::Spot { .. } => "spot",
            LightKind::Directional { .. } => "directional",
        }
    }

    /// What is wrong with the light's direction or cone, if anything (`Scene::validate`).
    pub(crate) fn kind_problem(&self) -> Option<String> {
        let direction = self.direction()?;
        if !direction.is_finite() || (direction.length() - 1.0).abs() > 1e-3 {
            return Some(format!(
                "{} light \"{}\" has direction {direction}, which is not a unit vector",
                self.kind_name(),
                self.name
            ));
        }
        if let LightKind::Spot {
            inner_cone,
            outer_cone,
            ..
        } = self.kind
            && !(0.0 <= inner_cone
                && inner_cone <= outer_cone
                && 0.0 < outer_cone
                && outer_cone <= std::f32::consts::FRAC_PI_2)
        {
            return Some(format!(
                "spot light \"{}\" has cone angles {inner_cone} and {outer_cone} rad; they need \
                 0 <= inner <= outer <= pi/2 and outer > 0 (glTF's rule)",
                self.name
            ));
        }
        None
    }
}

/// `KHR_lights_punctual`'s spot falloff from the cosine to the axis and the cosines of the
/// cone's half-angles (the twin of `spot_falloff` in `scene.wgsl` and the ray tracer's).
pub fn spot_falloff(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
    let t = ((cos - cos_outer) * scale).clamp(0.0, 1.0);
    t * t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot() -> Light {
        Light {
            kind: LightKind::Spot {
                direction: Vec3::NEG_Y,
                inner_cone: 0.3,
                outer_cone: 0.5,
            },
            ..Light::point("spot", Vec3::new(0.0, 2.0, 0.0), Vec3::ONE)
        }
    }

    #[test]
    fn spot_is_full_inside_the_inner_cone_and_dark_outside_the_outer() {
        let s = spot();
        let at = |angle: f32| s.emission_factor(Vec3::new(angle.sin(), -angle.cos(), 0.0));
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(0.29), 1.0);
        assert_eq!(at(0.51), 0.0);
        // Between the cones, glTF's ramp: the square of a linear ramp in the cosine.
        let mid = at(0.4);
        let ramp = (0.4f32.cos() - 0.5f32.cos()) / (0.3f32.cos() - 0.5f32.cos());
        assert!((mid - ramp * ramp).abs() < 1e-6, "{mid} vs {}", ramp * ramp);
        // Monotone between the cones.
        let mut last = 1.0;
        for i in 0..=100 {
            let v = at(0.3 + 0.2 * i as f32 / 100.0);
            assert!(v <= last + 1e-6);
            last = v;
        }
    }

    #[test]
    fn toward_matches_each_kind() {
        let p = Vec3::new(1.0, 0.0, 0.0);
        let point = Light::point("p", Vec3::new(1.0, 2.0, 0.0), Vec3::ONE);
        let t = point.toward(p).unwrap();
        assert_eq!((t.dir, t.distance_squared, t.factor), (Vec3::Y, 4.0, 1.0));
        assert_eq!(point.shadow_ray(p), Some((Vec3::Y, 2.0)));
        // The spot points down from (0, 2, 0): (2, 0, 0) is 45 degrees off its axis, outside
        // the 0.5 rad cone; p, 26.6 degrees off, is between the cones.
        assert_eq!(spot().toward(Vec3::new(2.0, 0.0, 0.0)).unwrap().factor, 0.0);
        let between = spot().toward(p).unwrap().factor;
        assert!(between > 0.0 && between < 1.0, "{between}");
        assert_eq!(spot().toward(Vec3::ZERO).unwrap().factor, 1.0);
        let sun = Light {
            kind: LightKind::Directional {
                direction: Vec3::NEG_Y,
            },
            ..point.clone()
        };
        let t = sun.toward(p).unwrap();
        assert_eq!((t.dir, t.distance_squared, t.factor), (Vec3::Y, 1.0, 1.0));
        assert_eq!(sun.shadow_ray(p), Some((Vec3::Y, f32::INFINITY)));
        assert_eq!(point.toward(point.position), None);
    }

    #[test]
    fn bad_directions_and_cones_are_named() {
        let mut s = spot();
        assert_eq!(s.kind_problem(), None);
        s.kind = LightKind::Spot {
            direction: Vec3::NEG_Y,
            inner_cone: 0.6,
            outer_cone: 0.5,
        };
        assert!(s.kind_problem().unwrap().contains("cone angles"));
        s.kind = LightKind::Directional {
            direction: Vec3::ZERO,
        };
        assert!(s.kind_problem().unwrap().contains("not a unit vector"));
    }
}
