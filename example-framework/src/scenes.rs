//! The scenes the examples build in code with `scene`'s API (objects, materials, roles,
//! lights, buildings), where `scene::load`'s built-ins do not show what a crate needs.

use glam::{Mat4, Vec2, Vec3};
use scene::builtin::textures::checker_texture;
use scene::mesh::{cuboid, cylinder, quad, uv_sphere};
use scene::{Building, Camera, CameraPath, Light, Material, Object, Roles, Scene};

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
                cutout: None,
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
        orthographic: None,
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
        lights: vec![Light {
            name: "ceiling light".into(),
            position: Vec3::new(0.0, 2.3, 0.2),
            intensity: Vec3::splat(4.0),
            kind: scene::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
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
        orthographic: None,
    };
    Scene {
        name: "street".into(),
        objects,
        textures: vec![],
        lights: vec![Light {
            name: "sun-like light".into(),
            position: Vec3::new(250.0, 400.0, 300.0),
            intensity: Vec3::splat(4.0e5),
            kind: scene::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.35, 0.45, 0.6),
    }
}
