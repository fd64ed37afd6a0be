//! Where caustic photons are emitted: cones from each point or spot light, discs across each
//! directional light, toward each caustic caster's bounding sphere; the photon budget split
//! between them, and the balance-heuristic weight of a photon drawn in one of several
//! overlapping cones or discs.
//!
//! The CPU reference's light pass (`truth::reference`, whose module docs derive the
//! estimator) and the GPU ray tracer (`raytracer`) emit through the same cones with the same
//! budgets, so their caustics estimate the same integral with the same variance per photon.
//!
//! For each light and caster the caster's bounding sphere (`center_at`,
//! `bounding_radius_at`) seen from the light subtends a cone of half-angle `theta_max`,
//! `sin theta_max = R / D`, solid angle `Omega = 2 pi (1 - cos theta_max)` (the whole sphere,
//! `4 pi`, if the light is inside it). `N_j` photons are drawn uniformly in cone `j`, the
//! budget split in proportion to the power each cone receives, `(I_r + I_g + I_b) Omega_j`. A
//! photon drawn in direction `w` carries `Phi = I f(w) / sum_{j : w in cone j} (N_j / Omega_j)`
//! (Veach's balance heuristic, one-sample form): `I Omega_j / N_j` where cones do not overlap.
//! `f(w)` is a spot's cone falloff ([`Light::emission_factor`], 1 for a point light); a cone
//! wholly outside a spot's outer cone is left out.
//!
//! A directional light's photons travel in parallel: for each caster, a disc of the sphere's
//! radius `R` perpendicular to the light's direction, placed behind every object of the scene,
//! of area `A = pi R^2`; `N_j` photons start uniformly on it and a photon carries
//! `Phi = E / sum_{j : its line crosses disc j} (N_j / A_j)`, `E` the irradiance.

use crate::technique::{Declared, ParamValue};
use crate::{Light, LightKind, Param, Roles, Scene};
use glam::Vec3;
use std::f32::consts::PI;

/// Photons per pixel of a light pass scaled to its image: 4 million over 256 x 256, the density
/// at which the caustic under `cornell-sphere`'s glass sphere is smooth (the reference's
/// default, `truth::reference::ReferenceOptions::for_image`, and the GPU tracer's).
pub const PHOTONS_PER_PIXEL: u64 = 61;
/// The fewest photons an image-scaled light pass traces (small test images).
pub const MIN_PHOTONS: u64 = 100_000;

/// The image-scaled photon count of a `width` x `height` image: [`PHOTONS_PER_PIXEL`] per
/// pixel, at least [`MIN_PHOTONS`].
pub fn photons_for_image(width: u32, height: u32) -> u64 {
    (PHOTONS_PER_PIXEL * width as u64 * height as u64).max(MIN_PHOTONS)
}

/// The parameter by which every family that emits photons from a light-view raster (one
/// photon per pixel) chooses where in its pixel a photon leaves: `jittered_emission` in
/// scene.wgsl (README.md, "Jittered emission").
pub const PHOTON_JITTER_PARAM: &str = "photon_jitter";
/// [`PHOTON_JITTER_PARAM`]'s help line.
const PHOTON_JITTER_HELP: &str = "1: each photon leaves from a random point of its pixel \
     (stratified jittered emission: noise, not moire rings); 0: from the pixel centre";

/// The parameter by which a family that splats photons chooses each photon's kernel: widened
/// to the footprint of its lattice cell on the receiver (`lightmap::Footprint` for light maps)
/// or the fixed splat radius. Footprints measure the cell from the landing points of the
/// photon's lattice neighbours, so they need the lattice: they and [`PHOTON_JITTER_PARAM`] do
/// not mix well (the jitter makes the measured cells noisy).
pub const PHOTON_FOOTPRINT_PARAM: &str = "photon_footprint";
/// [`PHOTON_FOOTPRINT_PARAM`]'s help line.
const PHOTON_FOOTPRINT_HELP: &str = "1: each photon's splat widened to the footprint of its \
     lattice cell on the receiver (photon differentials by finite differences); 0: the fixed \
     splat radius";

/// The declared [`PHOTON_JITTER_PARAM`] at its current `value`.
pub fn jitter_param(value: bool) -> Param {
    Param::new(
        PHOTON_JITTER_PARAM,
        f64::from(u8::from(value)),
        (0.0, 1.0),
        true,
        PHOTON_JITTER_HELP,
    )
}

/// The declared [`PHOTON_FOOTPRINT_PARAM`] at its current `value`.
pub fn footprint_param(value: bool) -> Param {
    Param::new(
        PHOTON_FOOTPRINT_PARAM,
        f64::from(u8::from(value)),
        (0.0, 1.0),
        true,
        PHOTON_FOOTPRINT_HELP,
    )
}

/// [`PHOTON_JITTER_PARAM`] declared once in a family's [`crate::Settings`], on the switch
/// `setting` finds.
pub const fn jitter_declared<S>(setting: fn(&mut S) -> Option<&mut dyn ParamValue>) -> Declared<S> {
    Declared::new(PHOTON_JITTER_PARAM, (0.0, 1.0), PHOTON_JITTER_HELP, setting)
}

/// [`PHOTON_FOOTPRINT_PARAM`] declared once in a family's [`crate::Settings`], on the switch
/// `setting` finds.
pub const fn footprint_declared<S>(
    setting: fn(&mut S) -> Option<&mut dyn ParamValue>,
) -> Declared<S> {
    Declared::new(
        PHOTON_FOOTPRINT_PARAM,
        (0.0, 1.0),
        PHOTON_FOOTPRINT_HELP,
        setting,
    )
}

/// The objects photons are aimed at: caustic casters by role, and every specular object.
pub fn caustic_casters(scene: &Scene) -> Vec<usize> {
    (0..scene.objects.len())
        .filter(|&i| {
            let o = &scene.objects[i];
            o.roles.contains(Roles::CAUSTIC_CASTER) || o.material.is_specular()
        })
        .collect()
}

/// Where one share of a light's photons leaves: a cone of directions from a point or spot
/// light toward a target's bounding sphere, or a disc across a directional light's beam,
/// behind the scene, whose photons all travel along `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    pub light: usize,
    /// The cone's axis, or the direction a disc's photons travel.
    pub axis: Vec3,
    /// A cone's `1 - cos theta_max` (2 for the whole sphere), kept apart for precision; 0 for
    /// a disc.
    pub one_minus_cos: f32,
    /// Where the photons leave: the light, or the disc's centre.
    pub origin: Vec3,
    /// The disc's radius; 0 for a cone.
    pub radius: f32,
    /// The cone's solid angle (sr) or the disc's area (m^2), over which its photons are
    /// spread uniformly; times the light's intensity, the power the emitter covers (W).
    pub measure: f32,
    /// Photons drawn in this cone or on this disc.
    pub photons: u64,
}

impl Emitter {
    /// Whether it is a disc of parallel photons (else a cone from a point).
    pub fn is_disc(&self) -> bool {
        self.radius > 0.0
    }

    /// Whether a photon leaving `from` in direction `w` could have been drawn here: `w` inside
    /// the cone, or (a disc) the photon's line crossing the disc.
    pub fn contains(&self, from: Vec3, w: Vec3) -> bool {
        if self.is_disc() {
            let d = from - self.origin;
            let across = d - self.axis * d.dot(self.axis);
            return across.length_squared() <= self.radius * self.radius;
        }
        self.one_minus_cos >= 2.0 || 1.0 - w.dot(self.axis) <= self.one_minus_cos
    }

    /// Where a photon leaves and its direction, from two uniform numbers in [0, 1): in a cone
    /// `cos theta = 1 - u (1 - cos theta_max)`, `phi = 2 pi v`; on a disc, radius `R sqrt(u)`
    /// at angle `2 pi v`.
    pub fn sample(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let phi = 2.0 * PI * v;
        let (t, b) = self.axis.any_orthonormal_pair();
        if self.is_disc() {
            let r = self.radius * u.sqrt();
            return (self.origin + (t * phi.cos() + b * phi.sin()) * r, self.axis);
        }
        let omc = u * self.one_minus_cos; // 1 - cos theta
        let cos_t = 1.0 - omc;
        let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
        let w = (self.axis * cos_t + (t * phi.cos() + b * phi.sin()) * sin_t).normalize();
        (self.origin, w)
    }
}

/// The cones and discs of `scene` at `time` toward `targets`, sharing `photons` in all.
pub fn emitters(scene: &Scene, time: f32, targets: &[usize], photons: u64) -> Vec<Emitter> {
    let mut out = Vec::new();
    // Only a directional light needs it: where its discs stand behind the scene.
    let mut scene_sphere = None;
    for (li, light) in scene.lights.iter().enumerate() {
        if light.intensity.max_element() <= 0.0 {
            continue;
        }
        for &ti in targets {
            let Some(object) = scene.objects.get(ti) else {
                continue;
            };
            if object.mesh.indices.is_empty() {
                continue;
            }
            let center = object.center_at(time);
            let radius = object.bounding_radius_at(time) * (1.0 + 1e-4) + 1e-6;
            let emitter = match light.kind {
                LightKind::Directional { direction } => {
                    let (c, r) = *scene_sphere.get_or_insert_with(|| bounding_sphere(scene, time));
                    disc(li, direction, center, radius, (c, r))
                }
                _ => match cone(li, light, center, radius) {
                    Some(e) => e,
                    None => continue,
                },
            };
            out.push(emitter);
        }
    }
    // Split the budget in proportion to the power into each cone or disc.
    let weight =
        |e: &Emitter| scene.lights[e.light].intensity.element_sum() as f64 * e.measure as f64;
    let total: f64 = out.iter().map(weight).sum();
    if total > 0.0 {
        for e in &mut out {
            e.photons = ((photons as f64 * weight(e) / total).round() as u64).max(1);
        }
    }
    out
}

/// The cone from a point or spot light toward the sphere (`center`, `radius`); `None` when a
/// spot's outer cone misses it.
fn cone(li: usize, light: &Light, center: Vec3, radius: f32) -> Option<Emitter> {
    let to = center - light.position;
    let dist = to.length();
    let (axis, one_minus_cos) = if dist <= radius {
        (Vec3::Y, 2.0)
    } else {
        let sin2 = (radius / dist) * (radius / dist);
        (to / dist, sin2 / (1.0 + (1.0 - sin2).sqrt()))
    };
    if let LightKind::Spot {
        direction,
        outer_cone,
        ..
    } = light.kind
        && one_minus_cos < 2.0
    {
        let off_axis = axis.dot(direction).clamp(-1.0, 1.0).acos();
        let half_angle = (1.0 - one_minus_cos).clamp(-1.0, 1.0).acos();
        if off_axis - half_angle > outer_cone {
            return None;
        }
    }
    Some(Emitter {
        light: li,
        axis,
        one_minus_cos,
        origin: light.position,
        radius: 0.0,
        measure: 2.0 * PI * one_minus_cos,
        photons: 0,
    })
}

/// The disc of a directional light travelling along `direction` across the sphere (`center`,
/// `radius`), placed behind everything in the scene's sphere.
fn disc(li: usize, direction: Vec3, center: Vec3, radius: f32, scene: (Vec3, f32)) -> Emitter {
    let behind = center.distance(scene.0) + scene.1 + radius + 1e-3;
    Emitter {
        light: li,
        axis: direction,
        one_minus_cos: 0.0,
        origin: center - direction * behind,
        radius,
        measure: PI * radius * radius,
        photons: 0,
    }
}

/// A sphere holding every object of `scene` at `time` and its scattering medium (whose
/// attenuation a photon must meet all of, as a shadow ray toward the sun does).
fn bounding_sphere(scene: &Scene, time: f32) -> (Vec3, f32) {
    let medium = scene
        .medium
        .as_ref()
        .map(|m| ((m.min + m.max) * 0.5, (m.max - m.min).length() * 0.5));
    let spheres: Vec<(Vec3, f32)> = scene
        .objects
        .iter()
        .filter(|o| !o.mesh.positions.is_empty())
        .map(|o| (o.center_at(time), o.bounding_radius_at(time)))
        .chain(medium)
        .collect();
    let Some(&(first, _)) = spheres.first() else {
        return (Vec3::ZERO, 0.0);
    };
    let radius = spheres
        .iter()
        .map(|(c, r)| c.distance(first) + r)
        .fold(0.0, f32::max);
    (first, radius)
}

/// The sampling density `sum_j N_j / M_j` over the cones or discs of `emitters[drawn]`'s
/// light that could have drawn a photon leaving `from` in direction `w` (the balance
/// heuristic's denominator).
pub fn balance_density(emitters: &[Emitter], drawn: usize, from: Vec3, w: Vec3) -> f32 {
    let e = &emitters[drawn];
    let mut density = e.photons as f32 / e.measure;
    for (oj, o) in emitters.iter().enumerate() {
        if oj != drawn && o.light == e.light && o.contains(from, w) {
            density += o.photons as f32 / o.measure;
        }
    }
    density
}

/// The power a photon drawn in `emitters[drawn]` carries when it leaves `from` in direction
/// `w`: the light's intensity times its falloff in `w`, over the balance heuristic's density.
pub fn photon_power(
    light: &Light,
    emitters: &[Emitter],
    drawn: usize,
    from: Vec3,
    w: Vec3,
) -> Vec3 {
    light.intensity * light.emission_factor(w) / balance_density(emitters, drawn, from, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cone sampling: every direction inside the cone, and uniform in solid angle (the mean
    /// of cos theta over a uniform cone is 1 - (1 - cos theta_max) / 2).
    #[test]
    fn cone_samples_are_uniform_inside_the_cone() {
        for (axis, omc) in [
            (Vec3::new(0.3, -1.0, 0.2).normalize(), 0.05f32),
            (Vec3::Z, 1.2),
            (Vec3::Y, 2.0),
        ] {
            let e = Emitter {
                light: 0,
                axis,
                one_minus_cos: omc,
                origin: Vec3::ZERO,
                radius: 0.0,
                measure: 2.0 * PI * omc,
                photons: 1,
            };
            let n = 200_000u32;
            let mut mean_cos = 0.0f64;
            for i in 0..n {
                // A Hammersley set: deterministic and uniform.
                let u = (i as f32 + 0.5) / n as f32;
                let v = i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
                let (from, w) = e.sample(u, v);
                assert_eq!(from, Vec3::ZERO);
                assert!((w.length() - 1.0).abs() < 1e-5);
                assert!(e.contains(from, w) || 1.0 - w.dot(axis) <= omc * (1.0 + 1e-4) + 1e-6);
                mean_cos += w.dot(axis) as f64;
            }
            mean_cos /= n as f64;
            let want = 1.0 - omc as f64 / 2.0;
            assert!(
                (mean_cos - want).abs() < 3e-3 * omc as f64 + 1e-4,
                "{mean_cos} vs {want}"
            );
        }
    }

    fn ball_at(center: Vec3) -> crate::Object {
        crate::Object::new(
            "ball",
            crate::mesh::uv_sphere(0.5, 12, 8),
            crate::Material::glass(1.5),
            glam::Mat4::from_translation(center),
        )
    }

    fn lit_by(light: Light, objects: Vec<crate::Object>) -> Scene {
        Scene {
            lights: vec![light],
            objects,
            ..crate::hosted::empty_scene()
        }
    }

    /// A directional light's photons leave uniformly from a disc behind the whole scene, all
    /// along its direction, and each disc's share of the light is `E A`.
    #[test]
    fn directional_light_emits_parallel_photons_from_discs_behind_the_scene() {
        let direction = Vec3::new(0.3, -1.0, 0.1).normalize();
        let sun = Light {
            kind: LightKind::Directional { direction },
            ..Light::point("sun", Vec3::ZERO, Vec3::splat(2.0))
        };
        let scene = lit_by(
            sun,
            vec![ball_at(Vec3::ZERO), ball_at(Vec3::new(3.0, 0.0, 0.0))],
        );
        let es = emitters(&scene, 0.0, &[0, 1], 10_000);
        assert_eq!(es.len(), 2);
        for (e, object) in es.iter().zip(&scene.objects) {
            assert!(e.is_disc());
            assert_eq!(e.axis, direction);
            // Behind every object: the disc's plane is farther back than any vertex.
            let behind = |p: Vec3| (p - e.origin).dot(direction);
            for o in &scene.objects {
                let c = o.center_at(0.0);
                assert!(behind(c) > o.bounding_radius_at(0.0), "{c}");
            }
            let r = object.bounding_radius_at(0.0);
            assert!(e.radius >= r && e.radius < r * 1.01);
            let n = 4000;
            let mut mean_r2 = 0.0;
            for i in 0..n {
                let u = (i as f32 + 0.5) / n as f32;
                let v = (i as u32).reverse_bits() as f32 / 4_294_967_296.0;
                let (from, w) = e.sample(u, v);
                assert_eq!(w, direction);
                assert!(e.contains(from, w));
                let d = from - e.origin;
                assert!(d.dot(direction).abs() < 1e-4, "on the disc's plane");
                mean_r2 += d.length_squared() / n as f32;
            }
            // Uniform over the disc: the mean of r^2 is R^2 / 2.
            let want = e.radius * e.radius / 2.0;
            assert!((mean_r2 - want).abs() < 0.01 * want, "{mean_r2} vs {want}");
        }
        // Equal discs share the budget equally; a photon through one disc alone counts its
        // density, E A / N.
        assert_eq!(es[0].photons, es[1].photons);
        let alone = balance_density(&es, 0, es[0].origin, direction);
        assert_eq!(alone, es[0].photons as f32 / es[0].measure);
        let power = photon_power(&scene.lights[0], &es, 0, es[0].origin, direction);
        assert!((power.x - 2.0 * es[0].measure / es[0].photons as f32).abs() < 1e-6);
        // One ball behind the other along the sun: their discs share an axis, so a photon
        // through them counts both densities (the balance heuristic); one past their rims,
        // neither.
        let behind = direction * 3.0;
        let scene = lit_by(
            scene.lights[0].clone(),
            vec![ball_at(Vec3::ZERO), ball_at(behind)],
        );
        let es = emitters(&scene, 0.0, &[0, 1], 10_000);
        let both = es[0].photons as f32 / es[0].measure + es[1].photons as f32 / es[1].measure;
        let density = balance_density(&es, 0, es[0].origin, direction);
        assert!((density - both).abs() < 1e-6 * both, "{density} vs {both}");
        let (t, _) = direction.any_orthonormal_pair();
        let inside = es[0].origin + t * (es[0].radius * 0.99);
        let past = es[0].origin + t * (es[0].radius * 1.5);
        assert!(es[0].contains(inside, direction) && es[1].contains(inside, direction));
        assert!(!es[0].contains(past, direction) && !es[1].contains(past, direction));
    }

    /// A spot aims no cone at a caster wholly outside its outer cone, and weighs each photon
    /// by its falloff.
    #[test]
    fn spot_light_skips_casters_outside_its_cone_and_weighs_photons_by_its_falloff() {
        let spot = Light {
            kind: LightKind::Spot {
                direction: Vec3::NEG_Y,
                inner_cone: 0.2,
                outer_cone: 0.4,
            },
            ..Light::point("spot", Vec3::new(0.0, 3.0, 0.0), Vec3::ONE)
        };
        let below = ball_at(Vec3::ZERO);
        let aside = ball_at(Vec3::new(4.0, 2.5, 0.0));
        let scene = lit_by(spot, vec![below, aside]);
        let es = emitters(&scene, 0.0, &[0, 1], 1000);
        assert_eq!(es.len(), 1, "only the ball below is lit");
        assert_eq!(es[0].origin, scene.lights[0].position);
        let light = &scene.lights[0];
        let axis_power = photon_power(light, &es, 0, light.position, Vec3::NEG_Y);
        let edge = Vec3::new(0.35f32.sin(), -0.35f32.cos(), 0.0);
        let edge_power = photon_power(light, &es, 0, light.position, edge);
        let want = es[0].measure / es[0].photons as f32;
        assert!((axis_power - Vec3::splat(want)).abs().max_element() < 1e-6 * want);
        let falloff = light.emission_factor(edge);
        assert!(falloff > 0.0 && falloff < 1.0);
        assert!((edge_power.x - axis_power.x * falloff).abs() < 1e-6);
    }
}
