//! The `pool` scene: a tiled swimming pool under a sun-like point light, its water surface a
//! glass height field (a sum of travelling waves), a ladder and a ball in the water. Built for
//! screen-space photon tracing (Krüger, Bürger and Westermann: the pool of their figure 13).
//!
//! Under water nothing is lit directly: the water surface is glass, and glass blocks shadow
//! rays (DESIGN.md), so the floor, the walls below the water line, the ladder and the ball
//! receive the sun only as caustic photons through the waves. The default view (`view=below`)
//! is a swimmer's, under the surface, where the reference sees those caustics directly. From
//! above (`view=above`) the floor is seen through the surface, and the reference leaves out
//! caustics seen through a specular chain (truth's "What the reference leaves out"): there only
//! the coping and the surface's reflections and refractions can be compared.
//!
//! The waves move by translation: scene objects move rigidly ([`Motion`]), so the wave field is
//! a fixed sum of sines drifting 0.3 m in x and 0.2 m in z over the camera path, and the
//! caustic pattern moves with it. The surface is larger than the pool so that it covers the
//! pool at every time; from below, what lies outside the walls is hidden by them (from above,
//! the strip beyond the near wall is in view: a sheet of water outside the pool).

use super::textures::from_texels;
use crate::mesh::{cuboid, merge, quad, uv_sphere};
use crate::{
    Camera, CameraPath, Light, Material, Medium, Mesh, Motion, Object, Roles, Scene, SceneError,
};
use glam::{Mat4, Vec2, Vec3};

/// Half-width (x) and half-length (z) of the pool's inside, metres.
pub const HALF_WIDTH: f32 = 2.0;
pub const HALF_LENGTH: f32 = 3.0;
/// Depth of the floor below the mean water level (y = 0), and the coping's height above it.
pub const DEPTH: f32 = 1.6;
pub const COPING: f32 = 0.3;
/// Index of refraction of the water.
pub const WATER_IOR: f32 = 1.33;

/// The water's scattering (`murky-pool`, or `pool:extinction=..`): a homogeneous medium in the
/// pool below the lowest trough of the waves ([`water_medium`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Murk {
    /// Extinction coefficient `sigma_t` per metre (every channel).
    pub extinction: f32,
    /// Single-scattering albedo `sigma_s / sigma_t`.
    pub albedo: f32,
    /// Henyey-Greenstein asymmetry `g`.
    pub anisotropy: f32,
}

/// The top of the water's medium: just below the lowest trough (the sum of the amplitudes), so
/// that the medium is water at every time and everywhere the waves drift.
pub fn medium_top() -> f32 {
    -waves().iter().map(|w| w.amplitude).sum::<f32>() - 0.002
}

/// The water's medium: the pool's inside from the floor to [`medium_top`]. The thin layer of
/// water above it (at most 13 cm under a crest) is clear: a box cannot follow the waves, and a
/// medium reaching above a trough would put it in the air.
pub fn water_medium(murk: Murk) -> Medium {
    let sigma_s = murk.extinction * murk.albedo;
    Medium {
        name: "water".into(),
        min: Vec3::new(-HALF_WIDTH, -DEPTH, -HALF_LENGTH),
        max: Vec3::new(HALF_WIDTH, medium_top(), HALF_LENGTH),
        scattering: Vec3::splat(sigma_s),
        absorption: Vec3::splat(murk.extinction - sigma_s),
        anisotropy: murk.anisotropy,
    }
}

/// One travelling wave of the surface: height `amplitude * sin(k . (x, z) + phase)`.
#[derive(Clone, Copy, Debug)]
pub struct Wave {
    pub amplitude: f32,
    /// Wave vector (radians per metre along x and z).
    pub k: Vec2,
    pub phase: f32,
}

/// The four waves of the surface: amplitudes 8-25 mm, wavelengths 0.45-1.6 m.
pub fn waves() -> [Wave; 4] {
    let wave = |amplitude: f32, wavelength: f32, heading: f32, phase: f32| Wave {
        amplitude,
        k: Vec2::from_angle(heading) * (std::f32::consts::TAU / wavelength),
        phase,
    };
    [
        wave(0.025, 1.6, 0.3, 0.0),
        wave(0.018, 1.1, 1.9, 1.3),
        wave(0.012, 0.7, -0.8, 2.1),
        wave(0.008, 0.45, 2.6, 0.7),
    ]
}

/// Height of the water surface above the mean level at `(x, z)` (object space), and its
/// gradient.
pub fn surface_height(x: f32, z: f32) -> (f32, Vec2) {
    waves().iter().fold((0.0, Vec2::ZERO), |(h, g), w| {
        let arg = w.k.dot(Vec2::new(x, z)) + w.phase;
        (
            h + w.amplitude * arg.sin(),
            g + w.k * (w.amplitude * arg.cos()),
        )
    })
}

/// The water surface: a `cells_x` x `cells_z` grid over `[-hx, hx] x [-hz, hz]` displaced by
/// [`surface_height`], normals from its gradient, facing up.
fn water_mesh(hx: f32, hz: f32, cells_x: u32, cells_z: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for j in 0..=cells_z {
        for i in 0..=cells_x {
            let (u, v) = (i as f32 / cells_x as f32, j as f32 / cells_z as f32);
            let (x, z) = (-hx + 2.0 * hx * u, -hz + 2.0 * hz * v);
            let (h, g) = surface_height(x, z);
            mesh.positions.push(Vec3::new(x, h, z));
            mesh.normals.push(Vec3::new(-g.x, 1.0, -g.y).normalize());
            mesh.uvs.push(Vec2::new(u, v));
        }
    }
    let row = cells_x + 1;
    for j in 0..cells_z {
        for i in 0..cells_x {
            let a = j * row + i;
            let (b, c, d) = (a + row, a + 1, a + row + 1);
            // (b - a) x (c - a) = z x x = +y: counter-clockwise from above.
            mesh.indices.extend_from_slice(&[a, b, c, c, b, d]);
        }
    }
    mesh
}

/// Pool tiles: 16-pixel tiles with a 1-pixel grout line, 4 x 4 tiles per texture (one texture
/// repeat per metre: 0.25 m tiles).
fn tile_texture() -> crate::Texture {
    from_texels("pool tiles", 64, |i, j| {
        if i % 16 == 0 || j % 16 == 0 {
            [200, 205, 200]
        } else if (i / 16 + j / 16) % 2 == 0 {
            [120, 190, 210]
        } else {
            [100, 170, 200]
        }
    })
}

/// `pool` seen from `view`: "below" (under the surface, the default) or "above"; with `murk`
/// the water scatters ([`water_medium`]), with `None` (or no extinction) it is clear.
pub fn pool(view: &str, murk: Option<Murk>) -> Result<Scene, SceneError> {
    let (below, above) = cameras();
    let keys = match view {
        "below" => below,
        "above" => above,
        other => {
            return Err(SceneError::BadParam(format!(
                "view={other} is not a pool view (below, above)"
            )));
        }
    };
    let id = Mat4::IDENTITY;
    let tiles = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    let (hx, hz, height) = (HALF_WIDTH, HALF_LENGTH, DEPTH + COPING);
    let floor_y = -DEPTH;
    let wall = |origin: Vec3, along: Vec3| {
        let width = along.length();
        quad(origin, along, Vec3::Y * height, Vec2::new(width, height))
    };
    let mut objects = vec![
        Object::new(
            "floor",
            quad(
                Vec3::new(-hx, floor_y, hz),
                Vec3::X * 2.0 * hx,
                Vec3::NEG_Z * 2.0 * hz,
                Vec2::new(2.0 * hx, 2.0 * hz),
            ),
            tiles.clone(),
            id,
        ),
        Object::new(
            "walls",
            merge(&[
                wall(Vec3::new(-hx, floor_y, -hz), Vec3::X * 2.0 * hx),
                wall(Vec3::new(hx, floor_y, hz), Vec3::NEG_X * 2.0 * hx),
                wall(Vec3::new(-hx, floor_y, hz), Vec3::NEG_Z * 2.0 * hz),
                wall(Vec3::new(hx, floor_y, -hz), Vec3::Z * 2.0 * hz),
            ]),
            tiles,
            id,
        ),
    ];

    objects.push(ladder(hx));
    objects.push(Object::new(
        "ball",
        uv_sphere(0.3, 24, 48),
        Material::diffuse(0.85, 0.35, 0.1),
        Mat4::from_translation(Vec3::new(-0.7, floor_y + 0.3, -0.8)),
    ));

    let mut water = Object::new(
        "water",
        water_mesh(hx + 0.5, hz + 0.5, 40, 56),
        Material::glass(WATER_IOR),
        id,
    )
    .with_roles(Roles::REFRACTOR | Roles::CAUSTIC_CASTER);
    water.motion = Motion {
        keys: vec![(0.0, Vec3::ZERO), (2.0, Vec3::new(0.3, 0.0, 0.2))],
    };
    objects.push(water);

    // The sun: 32 m away, from +x, +z and high above. 3000 W/sr gives the coping about
    // 3 W/m^2 (a white diffuse surface there has radiance near 0.9); under water the caustics
    // bring roughly the transmitted share of that, focused and spread by the waves.
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![tile_texture()],
        lights: vec![Light {
            name: "sun".into(),
            position: Vec3::new(5.0, 30.0, 10.0),
            intensity: Vec3::splat(3000.0),
            kind: crate::LightKind::Point,
        }],
        camera: keys[0].1,
        camera_path: CameraPath { keys },
        volumes: vec![],
        medium: murk.filter(|m| m.extinction > 0.0).map(water_medium),
        background: Vec3::new(0.35, 0.5, 0.75),
    })
}

/// The `light` parameter of both pools.
pub const LIGHT_HELP: &str = "point: the sun as a point light 32 m away (the default); sun: a \
                              directional light from the same direction, as bright at the pool";

/// The pool under a directional sun: from where the point light stands, its irradiance the
/// point light's at the origin (`I / d^2`), so the pool is as bright but every shadow and
/// caustic is cast by parallel light, as under the real sun of the screen-space photon paper.
pub fn sun_lit(mut scene: Scene) -> Scene {
    for light in &mut scene.lights {
        let d2 = light.position.length_squared();
        light.intensity /= d2;
        light.kind = crate::LightKind::Directional {
            direction: -light.position.normalize(),
        };
    }
    scene
}

/// The ladder on the right wall (at x = `hx`): two rails 12 cm off the wall and five rungs,
/// from near the floor to above the water; the sun, on the +x side, throws its shadow into
/// the pool.
fn ladder(hx: f32) -> Object {
    let (x0, x1) = (hx - 0.16, hx - 0.12);
    let (za, zb) = (-0.85, -0.35);
    let mut parts = vec![
        cuboid(
            Vec3::new(x0, -1.35, za - 0.02),
            Vec3::new(x1, 0.55, za + 0.02),
        ),
        cuboid(
            Vec3::new(x0, -1.35, zb - 0.02),
            Vec3::new(x1, 0.55, zb + 0.02),
        ),
    ];
    for y in [-1.1, -0.8, -0.5, -0.2, 0.1] {
        parts.push(cuboid(
            Vec3::new(x0 - 0.01, y, za),
            Vec3::new(x1, y + 0.03, zb),
        ));
    }
    Object::new(
        "ladder",
        merge(&parts),
        Material::diffuse(0.7, 0.7, 0.72),
        Mat4::IDENTITY,
    )
}

/// Keys of a camera path.
type CameraKeys = Vec<(f32, Camera)>;

/// The camera paths: a swimmer under the surface near the shallow end looking down the pool
/// at the ball and the ladder, drifting sideways; and a person standing at the pool's end.
fn cameras() -> (CameraKeys, CameraKeys) {
    let cam = |eye: Vec3, target: Vec3| Camera {
        eye,
        target,
        up: Vec3::Y,
        fov_y_deg: 60.0,
        orthographic: None,
    };
    let target = Vec3::new(-0.1, -1.2, -1.0);
    let below = vec![
        (0.0, cam(Vec3::new(0.3, -0.55, 2.7), target)),
        (1.0, cam(Vec3::new(-0.5, -0.6, 2.6), target)),
        (2.0, cam(Vec3::new(0.8, -0.5, 2.5), target)),
    ];
    let above_target = Vec3::new(0.0, -1.0, -0.5);
    let above = vec![
        (0.0, cam(Vec3::new(0.5, 1.6, 4.4), above_target)),
        (1.0, cam(Vec3::new(-0.4, 1.7, 4.3), above_target)),
        (2.0, cam(Vec3::new(1.2, 1.5, 4.2), above_target)),
    ];
    (below, above)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pool_is_valid_and_the_water_covers_the_pool_at_every_time() {
        for view in ["below", "above"] {
            pool(view, None).unwrap().validate().unwrap();
        }
        assert!(pool("sideways", None).is_err());
        let scene = pool("below", None).unwrap();
        let water = scene.objects.iter().find(|o| o.name == "water").unwrap();
        assert!(water.roles.contains(Roles::CAUSTIC_CASTER));
        for t in [0.0, 1.0, 2.0] {
            let world = water.world_at(t);
            let (lo, hi) = water.mesh.bounds();
            let (lo, hi) = (world.transform_point3(lo), world.transform_point3(hi));
            assert!(
                lo.x < -HALF_WIDTH && hi.x > HALF_WIDTH,
                "t = {t}: {lo} {hi}"
            );
            assert!(
                lo.z < -HALF_LENGTH && hi.z > HALF_LENGTH,
                "t = {t}: {lo} {hi}"
            );
            // The waves stay below the coping.
            assert!(hi.y < COPING && lo.y > -0.1, "t = {t}: {lo} {hi}");
        }
    }

    #[test]
    fn the_swimmer_is_under_water_and_sees_the_ball_and_the_ladder() {
        let scene = pool("below", None).unwrap();
        let ball = scene.objects.iter().find(|o| o.name == "ball").unwrap();
        let ladder = scene.objects.iter().find(|o| o.name == "ladder").unwrap();
        for (_, cam) in &scene.camera_path.keys {
            assert!(
                cam.eye.y < -0.1,
                "the camera at {} is not under water",
                cam.eye
            );
            for o in [ball, ladder] {
                let p = cam.project(o.center_at(0.0), 160, 120).unwrap();
                assert!(
                    p.x > 0.0 && p.x < 160.0 && p.y > 0.0 && p.y < 120.0,
                    "{}",
                    o.name
                );
            }
        }
    }

    #[test]
    fn the_murky_water_is_a_medium_below_every_trough() {
        let murk = Murk {
            extinction: 0.2,
            albedo: 0.9,
            anisotropy: 0.2,
        };
        let scene = pool("below", Some(murk)).unwrap();
        let m = scene.medium.as_ref().expect("a medium");
        assert!((m.extinction().x - 0.2).abs() < 1e-6 && (m.scattering.x - 0.18).abs() < 1e-6);
        let water = scene.objects.iter().find(|o| o.name == "water").unwrap();
        for t in [0.0, 0.5, 1.0, 1.5, 2.0] {
            let lowest = water
                .mesh
                .positions
                .iter()
                .map(|p| water.world_at(t).transform_point3(*p).y)
                .fold(f32::INFINITY, f32::min);
            assert!(lowest > m.max.y, "t = {t}: a trough at {lowest}");
        }
        assert!(
            pool(
                "below",
                Some(Murk {
                    extinction: 0.0,
                    ..murk
                })
            )
            .unwrap()
            .medium
            .is_none()
        );
    }

    #[test]
    fn surface_normals_follow_the_height_gradient() {
        let (x, z, e) = (0.37, -1.21, 1e-3);
        let (_, g) = surface_height(x, z);
        let dx = (surface_height(x + e, z).0 - surface_height(x - e, z).0) / (2.0 * e);
        let dz = (surface_height(x, z + e).0 - surface_height(x, z - e).0) / (2.0 * e);
        assert!(
            (g.x - dx).abs() < 1e-3 && (g.y - dz).abs() < 1e-3,
            "{g} vs {dx} {dz}"
        );
    }
}
