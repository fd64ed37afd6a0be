//! The built-in named scenes: the equal ground every technique is compared on.
//!
//! A scene is named by a spec `name` or `name:key=value,key=value`, for example
//! `cornell-sphere:material=mirror` or `city:buildings=64`. Each scene declares its
//! parameters (name, default, meaning) so `harness list --params` and `harness sweep` can
//! read them.

use crate::mesh::{cuboid, cylinder, quad, uv_sphere};
use crate::{
    Camera, CameraPath, DensityProfile, Material, Motion, Object, PointLight, Roles, Scene,
    SceneError, Texture, Volume,
};
use glam::{Mat4, Quat, Vec2, Vec3};
use std::collections::BTreeMap;

/// A declared scene parameter.
#[derive(Clone, Debug)]
pub struct SceneParam {
    pub name: &'static str,
    pub default: &'static str,
    pub help: &'static str,
}

/// A built-in scene and what can be changed about it.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    pub name: &'static str,
    pub description: &'static str,
    pub params: Vec<SceneParam>,
}

const MATERIAL_HELP: &str = "sphere material: glass-1.5, glass-1.1, glass-0.75, mirror, gold, \
                             copper, diffuse";

/// Every built-in scene.
pub fn builtin_scenes() -> Vec<SceneInfo> {
    let material = |default| SceneParam {
        name: "material",
        default,
        help: MATERIAL_HELP,
    };
    vec![
        SceneInfo {
            name: "cornell-sphere",
            description: "closed Cornell-style room, one point light, one sphere that moves \
                          along x over the camera path",
            params: vec![
                material("glass-1.5"),
                SceneParam {
                    name: "sphere_x",
                    default: "0",
                    help: "sphere centre x (m), -0.6..0.6",
                },
            ],
        },
        SceneInfo {
            name: "cornell-box",
            description: "the same room with a tall box that makes it concave (the distance-\
                          impostor paper's hard case)",
            params: vec![
                material("mirror"),
                SceneParam {
                    name: "sphere_x",
                    default: "0",
                    help: "sphere centre x (m), -0.6..0.6",
                },
            ],
        },
        SceneInfo {
            name: "refraction-bunny",
            description: "a glass Stanford bunny in front of a checker wall with nearby boxes",
            params: vec![SceneParam {
                name: "ior",
                default: "1.5",
                help: "bunny index of refraction",
            }],
        },
        SceneInfo {
            name: "city",
            description: "a grid of box buildings plus a cylinder and a sphere building; \
                          camera path along a street",
            params: vec![
                SceneParam {
                    name: "buildings",
                    default: "16",
                    help: "number of buildings (>= 2)",
                },
                SceneParam {
                    name: "rooms_per_building",
                    default: "1000",
                    help: "rooms per building; sets the room size of each hull",
                },
                SceneParam {
                    name: "interiors",
                    default: "1",
                    help: "1: the (at most 3) box buildings beside the start of the street get real \
                           interiors (window holes, room planes) when rooms_per_building <= 100000; 0: none",
                },
            ],
        },
        SceneInfo {
            name: "smoke",
            description: "ground plane and posts/logs crossing a large soft volume, plus a \
                          particle cloud",
            params: vec![SceneParam {
                name: "particles",
                default: "24",
                help: "particles in the cloud",
            }],
        },
    ]
}

/// Parses `name` or `name:key=value,...` into the name and its parameters.
pub fn parse_spec(spec: &str) -> Result<(String, BTreeMap<String, String>), SceneError> {
    let (name, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let mut params = BTreeMap::new();
    for pair in rest.split(',').filter(|s| !s.is_empty()) {
        let (k, v) = pair
            .split_once('=')
            .ok_or_else(|| SceneError::BadParam(format!("\"{pair}\" is not key=value")))?;
        params.insert(k.trim().to_string(), v.trim().to_string());
    }
    Ok((name.to_string(), params))
}

/// Builds a built-in scene by name with the given parameters (unknown parameters are errors).
pub fn build(name: &str, params: &BTreeMap<String, String>) -> Result<Scene, SceneError> {
    let info = builtin_scenes()
        .into_iter()
        .find(|s| s.name == name)
        .ok_or_else(|| SceneError::UnknownScene(name.to_string(), scene_names()))?;
    for key in params.keys() {
        if !info.params.iter().any(|p| p.name == key) {
            let known: Vec<_> = info.params.iter().map(|p| p.name).collect();
            return Err(SceneError::BadParam(format!(
                "scene {name} has no parameter \"{key}\" (it has: {})",
                known.join(", ")
            )));
        }
    }
    let get = |key: &str| -> String {
        params.get(key).cloned().unwrap_or_else(|| {
            info.params
                .iter()
                .find(|p| p.name == key)
                .map(|p| p.default.to_string())
                .unwrap_or_default()
        })
    };
    let mut scene = match name {
        "cornell-sphere" => cornell(false, &get("material"), num(&get("sphere_x"), "sphere_x")?)?,
        "cornell-box" => cornell(true, &get("material"), num(&get("sphere_x"), "sphere_x")?)?,
        "refraction-bunny" => crate::bunny::refraction_bunny(num(&get("ior"), "ior")?)?,
        "city" => crate::city::city(
            num(&get("buildings"), "buildings")? as usize,
            num(&get("rooms_per_building"), "rooms_per_building")?,
            num(&get("interiors"), "interiors")?,
        )?,
        "smoke" => smoke(num(&get("particles"), "particles")? as usize),
        _ => unreachable!("checked against builtin_scenes above"),
    };
    scene.name = spec_string(name, params);
    scene.validate()?;
    Ok(scene)
}

fn spec_string(name: &str, params: &BTreeMap<String, String>) -> String {
    if params.is_empty() {
        return name.to_string();
    }
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    format!("{name}:{}", kv.join(","))
}

fn scene_names() -> String {
    builtin_scenes()
        .iter()
        .map(|s| s.name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn num(value: &str, key: &str) -> Result<f32, SceneError> {
    value
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| SceneError::BadParam(format!("{key}={value} is not a finite number")))
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
    };
    let moved = Camera {
        eye: Vec3::new(0.3, 1.1, 0.9),
        ..camera
    };
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![],
        lights: vec![PointLight {
            name: "ceiling light".into(),
            position: Vec3::new(0.0, 1.85, 0.0),
            intensity: Vec3::splat(2.5),
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (1.0, moved), (2.0, camera)],
        },
        volumes: vec![],
        background: Vec3::ZERO,
    })
}

/// Checkerboard texture, sRGB RGBA8, `cells` x `cells` squares.
pub fn checker_texture(name: &str, size: u32, cells: u32, a: [u8; 3], b: [u8; 3]) -> Texture {
    let mut rgba8 = Vec::with_capacity((size * size * 4) as usize);
    for j in 0..size {
        for i in 0..size {
            let c = if (i * cells / size + j * cells / size) % 2 == 0 {
                a
            } else {
                b
            };
            rgba8.extend_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
    Texture {
        name: name.to_string(),
        width: size,
        height: size,
        rgba8,
    }
}

/// The big smoke volume's density profile: a falloff to zero at the sphere, textured by noise
/// with features of about a third of the radius.
pub const SMOKE_PROFILE: DensityProfile = DensityProfile {
    falloff: 1.0,
    noise: 0.45,
    noise_frequency: 3.0,
};

fn smoke(particles: usize) -> Scene {
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
        lights: vec![PointLight {
            name: "light".into(),
            position: Vec3::new(-2.0, 5.0, 3.0),
            intensity: Vec3::splat(30.0),
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (2.0, side)],
        },
        volumes,
        background: Vec3::new(0.05, 0.06, 0.08),
    }
}
