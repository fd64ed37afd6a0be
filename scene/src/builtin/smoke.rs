//! The `smoke` scene: a ground plane, posts and a log crossing a large soft volume (textured,
//! centre opacity about 0.67), plus a cloud of soft particles that rise over the camera path.

use super::textures::checker_texture;
use crate::mesh::{cylinder, quad};
use crate::{Camera, CameraPath, DensityProfile, Light, Material, Motion, Object, Scene, Volume};
use glam::{Mat4, Quat, Vec2, Vec3};

/// The big smoke volume's density profile: a falloff to zero at the sphere, textured by noise
/// with features of about a third of the radius.
pub const SMOKE_PROFILE: DensityProfile = DensityProfile {
    falloff: 1.0,
    noise: 0.45,
    noise_frequency: 3.0,
};

/// `smoke` with `particles` particles in the cloud.
pub fn smoke(particles: usize) -> Scene {
    let wood = Material::diffuse(0.45, 0.3, 0.18);
    let mut objects = vec![Object::new(
        "ground",
        quad(
            Vec3::new(-6.0, 0.0, 6.0),
            Vec3::X * 12.0,
            Vec3::NEG_Z * 12.0,
            Vec2::splat(6.0),
        ),
        Material::Diffuse {
            albedo: Vec3::splat(0.8),
            texture: Some(0),
            cutout: None,
        },
        Mat4::IDENTITY,
    )];
    for (k, x) in [-1.2f32, 0.3, 1.4].iter().enumerate() {
        objects.push(Object::new(
            &format!("post {k}"),
            cylinder(0.12, 2.6, 16),
            wood.clone(),
            Mat4::from_translation(Vec3::new(*x, 0.0, -0.4 + 0.5 * k as f32)),
        ));
    }
    objects.push(Object::new(
        "log",
        cylinder(0.15, 4.0, 16),
        wood,
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            Vec3::new(2.0, 0.15, 0.2),
        ),
    ));
    // Semi-transparent like the thesis's figures: the big volume's centre chord has optical
    // depth 4/3 * 0.55 * 1.5 = 1.1 (opacity 0.67 before the texture's +-45%); a particle's
    // (k = 2) is 16/15 * 1.8 * R = 0.48-0.86 (opacity 0.38-0.58), fading smoothly to its rim.
    let mut volumes = vec![Volume {
        name: "smoke".into(),
        center: Vec3::new(0.0, 1.0, 0.0),
        radius: 1.5,
        color: Vec3::new(0.8, 0.8, 0.85),
        density: 0.55,
        profile: SMOKE_PROFILE,
        particle: false,
        motion: Motion::default(),
    }];
    for p in 0..particles {
        let h = |k: u32| gpu::prelude::hash_to_unit(p as u32 * 4 + k);
        let center = Vec3::new(
            2.5 + (h(0) - 0.5) * 2.0,
            0.4 + h(1) * 1.8,
            1.5 + (h(2) - 0.5) * 2.0,
        );
        volumes.push(Volume {
            name: format!("particle {p}"),
            center,
            radius: 0.25 + 0.2 * h(3),
            color: Vec3::new(0.7, 0.7, 0.75),
            density: 1.8,
            profile: DensityProfile {
                falloff: 2.0,
                ..SMOKE_PROFILE
            },
            particle: true,
            motion: Motion {
                keys: vec![(0.0, Vec3::ZERO), (2.0, Vec3::Y * 0.5)],
            },
        });
    }
    let camera = Camera {
        eye: Vec3::new(0.5, 1.6, 5.5),
        target: Vec3::new(0.5, 0.9, 0.0),
        up: Vec3::Y,
        fov_y_deg: 55.0,
        orthographic: None,
    };
    let side = Camera {
        eye: Vec3::new(3.5, 1.8, 4.5),
        ..camera
    };
    Scene {
        name: String::new(),
        objects,
        textures: vec![checker_texture(
            "ground",
            64,
            8,
            [200, 200, 200],
            [120, 120, 120],
        )],
        lights: vec![Light {
            name: "light".into(),
            position: Vec3::new(-2.0, 5.0, 3.0),
            intensity: Vec3::splat(30.0),
            kind: crate::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (2.0, side)],
        },
        volumes,
        medium: None,
        background: Vec3::new(0.05, 0.06, 0.08),
    }
}
