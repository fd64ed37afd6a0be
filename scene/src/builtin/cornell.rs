//! The `cornell-sphere` and `cornell-box` scenes: a closed 2 m room with red and green side
//! walls and one point light under the ceiling, holding one sphere of a chosen material that
//! moves 0.5 m along x over the camera path; `cornell-box` adds a tall box that makes the room
//! concave (the distance-impostor paper's hard case).

use crate::mesh::{cuboid, quad, uv_sphere};
use crate::{Camera, CameraPath, Light, Material, Motion, Object, Roles, Scene, SceneError};
use glam::{Mat4, Quat, Vec2, Vec3};

/// The values of the `material` parameter.
pub const MATERIAL_HELP: &str = "sphere material: glass-1.5, glass-1.1, glass-0.75, mirror, gold, \
                                 copper, diffuse";

/// The `light` parameter of both rooms.
pub const LIGHT_HELP: &str = "point: the ceiling's point light; spot: a spot hanging there, \
                              pointing down, full within 20 degrees of the vertical and dark \
                              beyond 30";

pub const CAMERA_HELP: &str = "pinhole: the perspective view from the room's front; \
                               orthographic: a parallel view 1.2 m high looking 45 degrees down \
                               at the sphere and the floor round it, sliding 4 cm and zooming \
                               in by 5% over the camera path";

pub const SCREEN_HELP: &str = "none: the room as it is; perforated: a panel 0.7 m wide and \
                               0.9 m high stands on the floor at the left, behind the sphere, \
                               cut out by its texture's alpha into 6 x 6 round holes (glTF's \
                               MASK): the room shows through it and it throws a dotted shadow \
                               onto the wall behind";

/// Holes per side of [`perforated_screen`]'s texture.
const SCREEN_HOLES: u32 = 6;
/// Where [`perforated_screen`] stands: its x extent and its plane (z); it is 0.9 m high.
pub const SCREEN_X: std::ops::Range<f32> = -0.9..-0.2;
pub const SCREEN_Z: f32 = -0.55;

/// The room with a perforated panel standing on the floor, left of centre and behind the
/// sphere (which passes before it over the camera path), facing the camera and the light: a
/// diffuse panel whose texture's alpha is 0 in 6 x 6 round holes (a quarter of the panel's
/// area) and 1 elsewhere, cut out at 0.5 ([`Material::Diffuse`]'s `cutout`). The red wall and
/// the back wall show through the holes, and the light throws the panel's dotted shadow onto
/// them and the floor behind it.
pub fn perforated_screen(mut scene: Scene) -> Scene {
    let size = 96;
    let cell = size / SCREEN_HOLES;
    let mut texture =
        super::textures::from_texels("perforated screen", size, |_, _| [205, 120, 60]);
    for j in 0..size {
        for i in 0..size {
            // Texel centres within 0.28 cells of a hole's centre are open.
            let centre = |k: u32| (k % cell) as f32 + 0.5 - cell as f32 * 0.5;
            let r = (centre(i).powi(2) + centre(j).powi(2)).sqrt() / cell as f32;
            if r < 0.28 {
                texture.rgba8[(4 * (j * size + i) + 3) as usize] = 0;
            }
        }
    }
    let index = scene.textures.len();
    scene.textures.push(texture);
    let panel = quad(
        Vec3::new(SCREEN_X.start, 0.0, SCREEN_Z),
        Vec3::X * (SCREEN_X.end - SCREEN_X.start),
        Vec3::Y * 0.9,
        Vec2::ONE,
    );
    let material = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(index),
        cutout: Some(0.5),
    };
    scene.objects.push(Object::new(
        "perforated screen",
        panel,
        material,
        Mat4::IDENTITY,
    ));
    scene
}

/// The room seen by an orthographic camera (`Camera::orthographic`): looking 45 degrees down
/// at the sphere and the floor round it (its caustic), the view 1.2 m high. The view's plane
/// lies inside the room however the camera slides (every ray starts inside; the walls face
/// inwards).
pub fn orthographic_view(mut scene: Scene) -> Scene {
    let camera = Camera {
        eye: Vec3::new(0.0, 1.25, 0.55),
        target: Vec3::new(0.0, 0.25, -0.45),
        up: Vec3::Y,
        fov_y_deg: 45.0,
        orthographic: Some(0.6),
    };
    let slid = Vec3::new(0.04, 0.0, 0.0);
    let moved = Camera {
        eye: camera.eye + slid,
        target: camera.target + slid,
        orthographic: Some(0.6 * 0.95),
        ..camera
    };
    scene.camera = camera;
    scene.camera_path = CameraPath {
        keys: vec![(0.0, camera), (1.0, moved), (2.0, camera)],
    };
    scene
}

/// The room lit by a spot instead of its point light: the ceiling light pointing straight down,
/// full within 20 degrees of the vertical and dark beyond 30 (a pool of light round the
/// sphere, the walls dark but for the cone's edge), 1.6 times as intense.
pub fn spot_lit(mut scene: Scene) -> Scene {
    for light in &mut scene.lights {
        light.name = "ceiling spot".into();
        light.intensity *= 1.6;
        light.kind = crate::LightKind::Spot {
            direction: Vec3::NEG_Y,
            inner_cone: 20f32.to_radians(),
            outer_cone: 30f32.to_radians(),
        };
    }
    scene
}

/// `cornell-sphere`: the room and the sphere (`material` one of [`MATERIAL_HELP`], centre at
/// `x = sphere_x`).
pub fn cornell_sphere(material: &str, sphere_x: f32) -> Result<Scene, SceneError> {
    cornell(false, material, sphere_x)
}

/// `cornell-box`: [`cornell_sphere`] plus a tall box.
pub fn cornell_box(material: &str, sphere_x: f32) -> Result<Scene, SceneError> {
    cornell(true, material, sphere_x)
}

fn sphere_material(name: &str) -> Result<(Material, Roles), SceneError> {
    let refr = Roles::REFRACTOR | Roles::CAUSTIC_CASTER;
    let refl = Roles::REFLECTOR | Roles::CAUSTIC_CASTER;
    Ok(match name {
        "glass-1.5" => (Material::glass(1.5), refr),
        "glass-1.1" => (Material::glass(1.1), refr),
        "glass-0.75" => (Material::glass(0.75), refr),
        "mirror" => (Material::perfect_mirror(), refl),
        "gold" => (Material::gold(), refl),
        "copper" => (Material::copper(), refl),
        "diffuse" => (Material::diffuse(0.7, 0.7, 0.7), Roles::NONE),
        other => {
            return Err(SceneError::BadParam(format!(
                "unknown material \"{other}\" ({MATERIAL_HELP})"
            )));
        }
    })
}

/// Room interior: x in [-1, 1], y in [0, 2], z in [-1, 1], walls facing inwards.
fn room_objects() -> Vec<Object> {
    let id = Mat4::IDENTITY;
    let white = Material::diffuse(0.75, 0.75, 0.75);
    let wall = |name: &str, origin: Vec3, u: Vec3, v: Vec3, m: Material| {
        Object::new(name, quad(origin, u, v, Vec2::ONE), m, id)
    };
    vec![
        wall(
            "floor",
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::X * 2.0,
            Vec3::NEG_Z * 2.0,
            white.clone(),
        ),
        wall(
            "ceiling",
            Vec3::new(-1.0, 2.0, -1.0),
            Vec3::X * 2.0,
            Vec3::Z * 2.0,
            white.clone(),
        ),
        wall(
            "back wall",
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::X * 2.0,
            Vec3::Y * 2.0,
            white.clone(),
        ),
        wall(
            "front wall",
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::NEG_X * 2.0,
            Vec3::Y * 2.0,
            Material::diffuse(0.55, 0.55, 0.75),
        ),
        wall(
            "left wall",
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::NEG_Z * 2.0,
            Vec3::Y * 2.0,
            Material::diffuse(0.75, 0.15, 0.12),
        ),
        wall(
            "right wall",
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::Z * 2.0,
            Vec3::Y * 2.0,
            Material::diffuse(0.15, 0.65, 0.15),
        ),
    ]
}

fn cornell(tall_box: bool, material: &str, sphere_x: f32) -> Result<Scene, SceneError> {
    let (mat, roles) = sphere_material(material)?;
    let mut objects = room_objects();
    if tall_box {
        let bx = cuboid(Vec3::new(-0.25, 0.0, -0.25), Vec3::new(0.25, 1.3, 0.25));
        let t = Mat4::from_rotation_translation(
            Quat::from_rotation_y(0.35),
            Vec3::new(0.5, 0.0, -0.45),
        );
        objects.push(Object::new(
            "tall box",
            bx,
            Material::diffuse(0.8, 0.75, 0.3),
            t,
        ));
    }
    let center = Vec3::new(sphere_x, 0.55, -0.1);
    let mut sphere = Object::new(
        "sphere",
        uv_sphere(0.3, 48, 96),
        mat,
        Mat4::from_translation(center),
    )
    .with_roles(roles);
    // Over the camera path the sphere moves 0.5 m along x and back (paper, figure 5).
    sphere.motion = Motion {
        keys: vec![
            (0.0, Vec3::ZERO),
            (1.0, Vec3::new(-0.5, 0.0, 0.0)),
            (2.0, Vec3::ZERO),
        ],
    };
    objects.push(sphere);
    let camera = Camera {
        eye: Vec3::new(0.0, 1.0, 0.95),
        target: Vec3::new(0.0, 0.5, -0.5),
        up: Vec3::Y,
        fov_y_deg: 62.0,
        orthographic: None,
    };
    let moved = Camera {
        eye: Vec3::new(0.3, 1.1, 0.9),
        ..camera
    };
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![],
        lights: vec![Light {
            name: "ceiling light".into(),
            position: Vec3::new(0.0, 1.85, 0.0),
            intensity: Vec3::splat(2.5),
            kind: crate::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (1.0, moved), (2.0, camera)],
        },
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    })
}
