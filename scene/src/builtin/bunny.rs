//! The `refraction-bunny` scene: a glass Stanford bunny on a floor in front of a checker
//! wall, with coloured boxes beside and behind it (the nearby geometry that refraction
//! techniques must find through the glass).
//!
//! The bunny mesh is `assets/bunny.glb` (3674 triangles, height 1, base at y = 0, centred
//! on x = z = 0; see `assets/README.md` for its source, licence and conversion), embedded
//! in the crate and read with the glTF importer ([`super::assets::bunny_mesh`]).

use super::assets::bunny_mesh;
use super::textures::{floor_and_checker_wall, wall_checker};
use crate::mesh::cuboid;
use crate::{Camera, CameraPath, Light, Material, Motion, Object, Roles, Scene, SceneError};
use glam::{Mat4, Quat, Vec3};

/// Height of the bunny in the scene, metres.
const BUNNY_HEIGHT: f32 = 0.6;

/// `refraction-bunny` with the bunny's index of refraction `ior` (in
/// [`Material::IOR_RANGE`]).
pub fn refraction_bunny(ior: f32) -> Result<Scene, SceneError> {
    super::check_ior(ior)?;
    let mesh = bunny_mesh()?;

    let mut objects = room();

    // The bunny: 0.6 m tall, standing on the floor just behind the origin; over the camera
    // path it slides 0.15 m to the right and back.
    let mut bunny = Object::new(
        "bunny",
        mesh,
        Material::glass(ior),
        Mat4::from_scale_rotation_translation(
            Vec3::splat(BUNNY_HEIGHT),
            Quat::IDENTITY,
            Vec3::new(0.0, 0.0, -0.1),
        ),
    )
    .with_roles(Roles::REFRACTOR | Roles::CAUSTIC_CASTER);
    bunny.motion = Motion {
        keys: vec![
            (0.0, Vec3::ZERO),
            (1.0, Vec3::new(0.15, 0.0, 0.0)),
            (2.0, Vec3::ZERO),
        ],
    };
    objects.push(bunny);

    // Camera: looks at the bunny from 1.7 m, slightly from above, so that the wall fills
    // the background behind all but the bunny's feet. The path orbits the target by
    // +-12 degrees about the vertical axis.
    let target = Vec3::new(0.0, 0.32, -0.15);
    let orbit = |deg: f32| Camera {
        eye: target + Quat::from_rotation_y(deg.to_radians()) * Vec3::new(0.0, 0.18, 1.7),
        target,
        up: Vec3::Y,
        fov_y_deg: 45.0,
        orthographic: None,
    };
    let camera = orbit(0.0);

    // Light: 32 W/sr above and just behind the camera, so that the bunny's caustic falls
    // on the floor behind it. Seen from the camera path, the light checker cells of the
    // wall (albedo 0.64, linear) have radiance 0.64 / pi * 32 * cos / d^2 of 0.17-0.65,
    // median 0.41 (the dark cells, albedo 0.07, about a tenth of that); the floor around
    // the bunny about 0.6.
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![wall_checker()],
        lights: vec![Light {
            name: "key light".into(),
            position: Vec3::new(0.3, 2.5, 1.6),
            intensity: Vec3::splat(32.0),
            kind: crate::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (1.0, orbit(12.0)), (2.0, orbit(-12.0))],
        },
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    })
}

/// The room: floor y = 0 from z = -1.2 to 2.5, checker wall at z = -1.2 facing +z (6 x 3 m, so
/// that it fills the background of the camera path; the texture repeats 3 x 1.5 times, 8 x 8
/// cells each, so a cell is 0.25 m), and three boxes around the bunny.
fn room() -> Vec<Object> {
    let mut objects = floor_and_checker_wall(2.5, 3.7, -1.2).to_vec();
    let bx = |name: &str, size: Vec3, at: Vec3, yaw: f32, m: Material| {
        let mesh = cuboid(
            Vec3::new(-size.x * 0.5, 0.0, -size.z * 0.5),
            Vec3::new(size.x * 0.5, size.y, size.z * 0.5),
        );
        Object::new(
            name,
            mesh,
            m,
            Mat4::from_rotation_translation(Quat::from_rotation_y(yaw), at),
        )
    };
    objects.push(bx(
        "red box",
        Vec3::new(0.3, 0.4, 0.3),
        Vec3::new(-0.7, 0.0, -0.25),
        0.3,
        Material::diffuse(0.75, 0.15, 0.12),
    ));
    objects.push(bx(
        "blue box",
        Vec3::new(0.35, 0.7, 0.35),
        Vec3::new(0.55, 0.0, -0.75),
        -0.25,
        Material::diffuse(0.15, 0.25, 0.75),
    ));
    objects.push(bx(
        "yellow box",
        Vec3::new(0.2, 0.2, 0.2),
        Vec3::new(0.5, 0.0, 0.3),
        0.6,
        Material::diffuse(0.8, 0.7, 0.2),
    ));
    objects
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bunny_scene_is_valid_and_sized() {
        let scene = refraction_bunny(1.5).unwrap();
        scene.validate().unwrap();
        let bunny = scene.objects.iter().find(|o| o.name == "bunny").unwrap();
        assert_eq!(bunny.material, Material::glass(1.5));
        assert!(
            bunny.roles.contains(Roles::REFRACTOR) && bunny.roles.contains(Roles::CAUSTIC_CASTER)
        );
        let world = bunny.world_at(0.0);
        let (lo, hi) = bunny
            .mesh
            .positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            );
        assert!(lo.y.abs() < 1e-5, "bunny does not stand on the floor: {lo}");
        assert!(
            (hi.y - lo.y - BUNNY_HEIGHT).abs() < 1e-4,
            "bunny height {}",
            hi.y - lo.y
        );
        assert!(!bunny.motion.is_static());
        // The bunny is in view at every key of the camera path.
        for (_, cam) in &scene.camera_path.keys {
            let p = cam.project(bunny.center_at(0.0), 160, 120).unwrap();
            assert!(p.x > 0.0 && p.x < 160.0 && p.y > 0.0 && p.y < 120.0);
        }
        assert!(refraction_bunny(f32::NAN).is_err());
    }

    /// The wall fills much of the view, and where the camera sees it the light checker cells
    /// have radiance (the diffuse shading of DESIGN.md, without occlusion) of 0.3-0.7 over
    /// the middle half of the wall pixels and nowhere below 0.12 or above 0.8.
    #[test]
    fn wall_radiance_is_moderate() {
        let s = refraction_bunny(1.5).unwrap();
        let light = &s.lights[0];
        let albedo = crate::srgb_to_linear(210);
        let (w, h) = (64, 36);
        for (_, cam) in &s.camera_path.keys {
            let mut seen = vec![];
            for j in 0..h {
                for i in 0..w {
                    let d = cam.ray_dir(i as f32 + 0.5, j as f32 + 0.5, w, h);
                    let p = cam.eye + d * ((-1.2 - cam.eye.z) / d.z);
                    if d.z >= 0.0 || p.y < 0.0 {
                        continue; // the ray meets the floor first
                    }
                    assert!(
                        p.x.abs() < 3.0 && p.y < 3.0,
                        "the view leaves the wall at {p}"
                    );
                    let to_light = light.position - p;
                    let radiance = albedo / std::f32::consts::PI
                        * light.intensity.x
                        * to_light.normalize().z.max(0.0)
                        / to_light.length_squared();
                    assert!(
                        (0.12..0.8).contains(&radiance),
                        "wall radiance {radiance} at {p}"
                    );
                    seen.push(radiance);
                }
            }
            assert!(
                seen.len() > (w * h * 2 / 5) as usize,
                "the wall covers only {} pixels",
                seen.len()
            );
            seen.sort_by(f32::total_cmp);
            let (q1, q3) = (seen[seen.len() / 4], seen[seen.len() * 3 / 4]);
            assert!(q1 > 0.3 && q3 < 0.7, "wall radiance quartiles {q1} {q3}");
        }
    }
}
