//! The scenes the examples build in code with `scene`'s API (objects, materials, roles,
//! lights, volumes, buildings), where `scene::load`'s built-ins do not show what a crate needs.

use glam::{Mat4, Quat, Vec2, Vec3};
use scene::builtin::textures::checker_texture;
use scene::mesh::{cuboid, cylinder, quad, uv_sphere};
use scene::{
    Building, Camera, CameraPath, DensityProfile, Material, Motion, Object, PointLight, Roles,
    Scene, Volume,
};

/// A 3 x 2.5 x 3 m room (checker floor, coloured walls, one light under the ceiling) with a
/// mirror sphere and a glass sphere, and the camera looking at them from near the front wall.
pub fn mirror_and_glass_room() -> Scene {
    let wall = |name: &str, origin: Vec3, u: Vec3, v: Vec3, material: Material| {
        // `quad`'s normal is u x v: every wall faces into the room.
        Object::new(
            name,
            quad(origin, u, v, Vec2::ONE),
            material,
            Mat4::IDENTITY,
        )
    };
    let (w, h) = (3.0, 2.5);
    let mut objects = vec![
        wall(
            "floor",
            Vec3::new(-1.5, 0.0, 1.5),
            Vec3::X * w,
            Vec3::NEG_Z * w,
            Material::Diffuse {
                albedo: Vec3::splat(0.8),
                texture: Some(0),
            },
        ),
        wall(
            "ceiling",
            Vec3::new(-1.5, h, -1.5),
            Vec3::X * w,
            Vec3::Z * w,
            Material::diffuse(0.8, 0.8, 0.8),
        ),
        wall(
            "back wall",
            Vec3::new(-1.5, 0.0, -1.5),
            Vec3::X * w,
            Vec3::Y * h,
            Material::diffuse(0.75, 0.7, 0.55),
        ),
        wall(
            "front wall",
            Vec3::new(1.5, 0.0, 1.5),
            Vec3::NEG_X * w,
            Vec3::Y * h,
            Material::diffuse(0.55, 0.55, 0.75),
        ),
        wall(
            "left wall",
            Vec3::new(-1.5, 0.0, 1.5),
            Vec3::NEG_Z * w,
            Vec3::Y * h,
            Material::diffuse(0.75, 0.15, 0.12),
        ),
        wall(
            "right wall",
            Vec3::new(1.5, 0.0, -1.5),
            Vec3::Z * w,
            Vec3::Y * h,
            Material::diffuse(0.15, 0.6, 0.2),
        ),
    ];
    // The specular objects carry the role the technique looks for.
    objects.push(
        Object::new(
            "mirror sphere",
            uv_sphere(0.45, 48, 96),
            Material::perfect_mirror(),
            Mat4::from_translation(Vec3::new(-0.6, 0.45, -0.4)),
        )
        .with_roles(Roles::REFLECTOR),
    );
    objects.push(
        Object::new(
            "glass sphere",
            uv_sphere(0.4, 48, 96),
            Material::glass(1.5),
            Mat4::from_translation(Vec3::new(0.6, 0.4, 0.1)),
        )
        .with_roles(Roles::REFRACTOR),
    );
    let camera = Camera {
        eye: Vec3::new(0.0, 1.3, 1.4),
        target: Vec3::new(0.0, 0.5, -0.4),
        up: Vec3::Y,
        fov_y_deg: 65.0,
    };
    Scene {
        name: "mirror and glass room".into(),
        objects,
        textures: vec![checker_texture(
            "floor",
            64,
            8,
            [220, 220, 220],
            [40, 40, 60],
        )],
        lights: vec![PointLight {
            name: "ceiling light".into(),
            position: Vec3::new(0.0, 2.3, 0.2),
            intensity: Vec3::splat(4.0),
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

/// A yard: checker ground, three posts and a log crossing a large smoke volume (density
/// falling to zero at its sphere, textured by noise), a few soft particles rising beside it,
/// one light high up, and the camera in front.
pub fn smoky_yard() -> Scene {
    let wood = Material::diffuse(0.45, 0.3, 0.18);
    let mut objects = vec![Object::new(
        "ground",
        // `quad`'s normal is u x v: +Y.
        quad(
            Vec3::new(-6.0, 0.0, 6.0),
            Vec3::X * 12.0,
            Vec3::NEG_Z * 12.0,
            Vec2::splat(6.0),
        ),
        Material::Diffuse {
            albedo: Vec3::splat(0.8),
            texture: Some(0),
        },
        Mat4::IDENTITY,
    )];
    for (k, x) in [-1.2f32, 0.3, 1.4].into_iter().enumerate() {
        objects.push(Object::new(
            &format!("post {k}"),
            cylinder(0.12, 2.6, 16),
            wood.clone(),
            Mat4::from_translation(Vec3::new(x, 0.0, -0.4 + 0.5 * k as f32)),
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
    // The smoke: extinction 0.6 per metre at the centre, falling to zero at the sphere,
    // +-45 % noise with features of a third of the radius.
    let profile = DensityProfile {
        falloff: 1.0,
        noise: 0.45,
        noise_frequency: 3.0,
    };
    let mut volumes = vec![Volume {
        name: "smoke".into(),
        center: Vec3::new(0.0, 1.0, 0.0),
        radius: 1.5,
        color: Vec3::new(0.8, 0.8, 0.85),
        density: 0.6,
        profile,
        particle: false,
        motion: Motion::default(),
    }];
    // Soft particles that rise 0.25 m per second.
    for (k, center) in [
        Vec3::new(2.2, 0.6, 1.4),
        Vec3::new(2.8, 1.1, 1.0),
        Vec3::new(2.4, 1.6, 1.8),
        Vec3::new(3.1, 0.5, 2.0),
    ]
    .into_iter()
    .enumerate()
    {
        volumes.push(Volume {
            name: format!("particle {k}"),
            center,
            radius: 0.35,
            color: Vec3::new(0.7, 0.7, 0.75),
            density: 1.8,
            profile: DensityProfile {
                falloff: 2.0,
                ..profile
            },
            particle: true,
            motion: Motion {
                keys: vec![(0.0, Vec3::ZERO), (2.0, Vec3::Y * 0.5)],
            },
        });
    }
    let camera = Camera {
        eye: Vec3::new(0.8, 1.6, 5.5),
        target: Vec3::new(0.8, 0.9, 0.0),
        up: Vec3::Y,
        fov_y_deg: 55.0,
    };
    Scene {
        name: "smoky yard".into(),
        objects,
        textures: vec![checker_texture(
            "ground",
            64,
            8,
            [200, 200, 200],
            [120, 120, 120],
        )],
        lights: vec![PointLight {
            name: "light".into(),
            position: Vec3::new(-2.0, 5.0, 3.0),
            intensity: Vec3::splat(30.0),
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes,
        medium: None,
        background: Vec3::new(0.05, 0.06, 0.08),
    }
}

/// A street: ground, two box buildings and a round tower. A hull is an ordinary object with
/// the `building` role and a `Building` (its room size); the technique draws the rooms
/// behind its windows, the window pattern coming from the room grid (one window per room and
/// face, `scene::builtin::city::is_window`). One far, sun-like light; the camera on the street.
pub fn street() -> Scene {
    let facade = Material::diffuse(0.7, 0.62, 0.5);
    let building = |name: &str, mesh, at: Vec3, room_size: Vec3| {
        let mut hull = Object::new(name, mesh, facade.clone(), Mat4::from_translation(at))
            .with_roles(Roles::BUILDING);
        hull.building = Some(Building { room_size });
        hull
    };
    let objects = vec![
        Object::new(
            "ground",
            // `quad`'s normal is u x v: +Y.
            quad(
                Vec3::new(-60.0, 0.0, 60.0),
                Vec3::X * 120.0,
                Vec3::NEG_Z * 120.0,
                Vec2::ONE,
            ),
            Material::diffuse(0.3, 0.3, 0.3),
            Mat4::IDENTITY,
        ),
        // Hulls in object space start at their bounding-box minimum: the room grid does too.
        building(
            "office",
            cuboid(Vec3::new(-8.0, 0.0, -8.0), Vec3::new(8.0, 24.0, 8.0)),
            Vec3::new(-11.0, 0.0, 0.0),
            Vec3::new(4.0, 3.0, 4.0),
        ),
        building(
            "flats",
            cuboid(Vec3::new(-7.0, 0.0, -7.0), Vec3::new(7.0, 18.0, 7.0)),
            Vec3::new(10.0, 0.0, 4.0),
            Vec3::new(3.5, 3.6, 3.5),
        ),
        building(
            "tower",
            cylinder(6.0, 36.0, 32),
            Vec3::new(2.0, 0.0, -24.0),
            Vec3::new(3.0, 3.0, 3.0),
        ),
    ];
    let camera = Camera {
        eye: Vec3::new(0.0, 4.0, 30.0),
        target: Vec3::new(0.0, 12.0, 0.0),
        up: Vec3::Y,
        fov_y_deg: 60.0,
    };
    Scene {
        name: "street".into(),
        objects,
        textures: vec![],
        lights: vec![PointLight {
            name: "sun-like light".into(),
            position: Vec3::new(250.0, 400.0, 300.0),
            intensity: Vec3::splat(4.0e5),
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.35, 0.45, 0.6),
    }
}
