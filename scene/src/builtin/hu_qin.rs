//! The `hu-qin` scene: one glass refractor in front of a few nearby diffuse meshes, on a
//! floor before a checker backdrop, lit by one point light that makes the refractor cast a
//! caustic on the floor in view: the setting of Hu and Qin 2006 ("Interactive approximate
//! rendering of reflections, refractions, and caustics", Table 1 and figure 24: a sphere of
//! index 1.15, a teapot or a bunny, with nearby geometry seen through it).
//!
//! The refractor (about 0.55 m across, its bounding box centred at [`REFRACTOR_CENTRE`],
//! 0.35 m above the floor) is one of:
//!
//! - `sphere`: a UV sphere of radius 0.28 m;
//! - `teapot`: a teapot built from [`crate::mesh`]: a lofted body with a lid and knob, a
//!   tapered spout and a handle (two tubes), each part closed (watertight) with outward
//!   normals; the spout and handle reach a few centimetres into the body, so the solid is the
//!   union of three closed parts (the small overlaps are glass seen through glass). The handle
//!   and spout make it concave;
//! - `bunny`: the Stanford bunny of `assets/bunny.glb`, 0.55 m tall;
//! - `morph`: the sphere with a [`Morph`] target, a tilted peanut (each vertex scaled
//!   radially by `0.85 (1 + 0.35 (2 (n.a)^2 - 1))`, `n` its direction, `a` the peanut's
//!   axis), weight 0 -> 1 -> 0 over the camera path: a deforming refractor, what image-space
//!   refraction renders without preprocessing.
//!
//! There is no room: the environment is the sky (the background radiance), the floor and the
//! backdrop wall.
//!
//! Options for the paper's other settings ([`HuQin`]): `environment=distant` takes the nearby
//! meshes, the floor and the wall away and puts the refractor in the middle of a checkered
//! hall 60 m across (the paper's section-2.1 setting: an environment map of a distant
//! scene, where the map from the object's centre is nearly exact); `lights=2` adds a second
//! light on the right (figure 27: caustics from two lights); `metal=1` makes the refractor
//! polished gold (figure 26: reflective caustics).

use super::assets::bunny_mesh;
use super::textures::{floor_and_checker_wall, wall_checker};
use crate::mesh::{Ring, cuboid, cylinder, loft, merge, quad, smooth_normals, tube, uv_sphere};
use crate::{Camera, CameraPath, Light, Material, Mesh, Morph, Object, Roles, Scene, SceneError};
use glam::{Mat4, Quat, Vec2, Vec3};

/// The values of the `refractor` parameter.
pub const REFRACTOR_HELP: &str = "the glass object: sphere, teapot, bunny, morph (the sphere \
                                  deforming into a peanut and back over the camera path)";

/// Where the refractor's bounding box is centred (at time 0 for `morph`).
pub const REFRACTOR_CENTRE: Vec3 = Vec3::new(0.0, 0.35, 0.0);

/// Radius of the `sphere` (and of `morph` at weight 0), metres.
const SPHERE_RADIUS: f32 = 0.28;

/// Height of the `bunny`, metres.
const BUNNY_HEIGHT: f32 = 0.55;

/// Length of the camera path (and of the morph's cycle), seconds.
const DURATION: f32 = 2.0;

/// The options of `hu-qin`.
#[derive(Clone, Debug, PartialEq)]
pub struct HuQin {
    /// The refractor, one of [`REFRACTOR_HELP`].
    pub refractor: String,
    /// Its index of refraction (in [`Material::IOR_RANGE`]).
    pub ior: f32,
    /// The small sphere beside the refractor gold instead of blue diffuse: a reflector that
    /// the refractor sees and that sees the refractor (recursive reflections and refractions,
    /// the paper's figure 1b and 24g).
    pub gold_sphere: bool,
    /// No nearby geometry: the refractor alone in a checkered hall 60 m across (section 2.1's
    /// distant environment).
    pub distant: bool,
    /// Lights: 1, or 2 (a second light on the right, figure 27).
    pub lights: u32,
    /// The refractor polished gold instead of glass (reflective caustics, figure 26).
    pub metal: bool,
}

impl Default for HuQin {
    fn default() -> Self {
        Self {
            refractor: "sphere".into(),
            ior: 1.15,
            gold_sphere: false,
            distant: false,
            lights: 1,
            metal: false,
        }
    }
}

/// Half the side of the `environment=distant` hall, metres.
const HALL_HALF: f32 = 30.0;

/// `hu-qin` with the options `o`.
pub fn hu_qin(o: &HuQin) -> Result<Scene, SceneError> {
    let glass = refractor(o)?;

    // Floor y = 0 from z = -1.4 to 2.6; checker wall at z = -1.4 facing +z, 6 x 3 m, the
    // texture repeated 3 x 1.5 times (8 x 8 cells each): 0.25 m cells.
    let mut objects = floor_and_checker_wall(2.6, 4.0, -1.4).to_vec();

    objects.extend(nearby_meshes(o.gold_sphere));
    objects.push(glass);
    if o.distant {
        // Only the refractor stays (the caustic caster; not the gold sphere), in the middle of
        // the hall.
        objects.retain(|obj| obj.roles.contains(Roles::CAUSTIC_CASTER));
        objects.extend(distant_hall());
    }

    // Camera: looks at the refractor from about 1.75 m, somewhat from above, so that the
    // refractor fills about half the image height and the nearby meshes show beside and
    // through it; the path orbits the target by +-15 degrees about the vertical axis.
    let target = Vec3::new(0.0, 0.3, -0.1);
    let orbit = |deg: f32| Camera {
        eye: target + Quat::from_rotation_y(deg.to_radians()) * Vec3::new(0.0, 0.5, 1.7),
        target,
        up: Vec3::Y,
        fov_y_deg: 40.0,
        orthographic: None,
    };
    let camera = orbit(0.0);

    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![wall_checker()],
        // Left of, above and in front of the refractor: its caustic falls on the floor to its
        // right and a little behind it, in view.
        lights: lights(o)?,
        camera,
        camera_path: CameraPath {
            keys: vec![
                (0.0, camera),
                (0.5 * DURATION, orbit(15.0)),
                (DURATION, orbit(-15.0)),
            ],
        },
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.25, 0.3, 0.4),
    })
}

/// The refractor (or, with `metal`, the gold reflector): its mesh (and morph), centred at
/// [`REFRACTOR_CENTRE`].
fn refractor(o: &HuQin) -> Result<Object, SceneError> {
    let (refractor, ior) = (o.refractor.as_str(), o.ior);
    super::check_ior(ior)?;
    let (mesh, morph) = match refractor {
        "sphere" => (uv_sphere(SPHERE_RADIUS, 32, 64), None),
        "teapot" => (teapot(), None),
        "bunny" => {
            let mut mesh = bunny_mesh()?;
            for p in &mut mesh.positions {
                *p *= BUNNY_HEIGHT;
            }
            (mesh, None)
        }
        "morph" => {
            let sphere = uv_sphere(SPHERE_RADIUS, 32, 64);
            let morph = peanut_target(&sphere);
            (sphere, Some(morph))
        }
        other => {
            return Err(SceneError::BadParam(format!(
                "unknown refractor \"{other}\" ({REFRACTOR_HELP})"
            )));
        }
    };
    let (lo, hi) = mesh.bounds();
    let (material, role) = match o.metal {
        true => (Material::gold(), Roles::REFLECTOR),
        false => (Material::glass(ior), Roles::REFRACTOR),
    };
    let mut glass = Object::new(
        refractor,
        mesh,
        material,
        Mat4::from_translation(REFRACTOR_CENTRE - (lo + hi) * 0.5),
    )
    .with_roles(role | Roles::CAUSTIC_CASTER);
    glass.morph = morph;
    Ok(glass)
}

/// The nearby meshes, 0.65-0.75 m from the refractor, turned to show the camera faces the
/// light reaches: a red box behind it on the left, a green cylinder and a blue (or gold)
/// sphere just behind it (seen through it from the camera), a yellow box behind it on the
/// right, past the caustic.
fn nearby_meshes(gold_sphere: bool) -> Vec<Object> {
    let mut meshes = Vec::new();
    let placed = |name: &str, mesh: Mesh, at: Vec3, yaw: f32, m: Material| {
        Object::new(
            name,
            mesh,
            m,
            Mat4::from_rotation_translation(Quat::from_rotation_y(yaw), at),
        )
    };
    let block = |x: f32, y: f32, z: f32| {
        cuboid(
            Vec3::new(-x * 0.5, 0.0, -z * 0.5),
            Vec3::new(x * 0.5, y, z * 0.5),
        )
    };
    meshes.push(placed(
        "red box",
        block(0.25, 0.4, 0.25),
        Vec3::new(-0.5, 0.0, -0.45),
        0.4,
        Material::diffuse(0.75, 0.12, 0.1),
    ));
    meshes.push(placed(
        "green cylinder",
        cylinder(0.08, 0.45, 32),
        Vec3::new(0.17, 0.0, -0.7),
        0.0,
        Material::diffuse(0.15, 0.6, 0.2),
    ));
    let small_sphere = placed(
        if gold_sphere {
            "gold sphere"
        } else {
            "blue sphere"
        },
        uv_sphere(0.12, 16, 32),
        Vec3::new(-0.17, 0.12, -0.65),
        0.0,
        if gold_sphere {
            Material::gold()
        } else {
            Material::diffuse(0.12, 0.22, 0.75)
        },
    );
    meshes.push(if gold_sphere {
        small_sphere.with_roles(Roles::REFLECTOR)
    } else {
        small_sphere
    });
    meshes.push(placed(
        "yellow box",
        block(0.2, 0.3, 0.2),
        Vec3::new(0.62, 0.0, -0.42),
        -0.4,
        Material::diffuse(0.8, 0.68, 0.15),
    ));
    meshes
}

/// The lights: the key light left of, above and in front of the refractor (its caustic falls
/// on the floor to its right and a little behind it, in view), and with `lights=2` a second,
/// dimmer one on the right. In the distant hall both are brightened to light walls 30 m away
/// as the near scene's light lights its floor.
fn lights(o: &HuQin) -> Result<Vec<Light>, SceneError> {
    if !(1..=2).contains(&o.lights) {
        return Err(SceneError::BadParam(format!(
            "lights={} is not 1 or 2",
            o.lights
        )));
    }
    let gain = if o.distant { 400.0 } else { 1.0 };
    let mut lights = vec![Light {
        name: "key light".into(),
        position: Vec3::new(-1.2, 1.8, 0.5),
        intensity: Vec3::splat(14.0 * gain),
        kind: crate::LightKind::Point,
    }];
    if o.lights == 2 {
        lights.push(Light {
            name: "fill light".into(),
            position: Vec3::new(1.4, 1.5, 0.9),
            intensity: Vec3::splat(9.0 * gain),
            kind: crate::LightKind::Point,
        });
    }
    Ok(lights)
}

/// The `environment=distant` hall: floor, ceiling and four walls of a cube 60 m across
/// centred under the refractor (floor 15 m below it), each facing in and checkered with the
/// wall's texture (2.5 m cells).
fn distant_hall() -> Vec<Object> {
    let h = HALL_HALF;
    let (lo, hi) = (Vec3::new(-h, -15.0, -h), Vec3::new(h, 2.0 * h - 15.0, h));
    let checker = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    let tint = |r, g, b| Material::Diffuse {
        albedo: Vec3::new(r, g, b),
        texture: Some(0),
        cutout: None,
    };
    let size = 2.0 * h;
    // (name, corner, u edge, v edge, material): each quad's normal is u x v, facing in.
    let faces = [
        (
            "hall floor",
            Vec3::new(lo.x, lo.y, hi.z),
            Vec3::X,
            Vec3::NEG_Z,
            checker.clone(),
        ),
        (
            "hall ceiling",
            Vec3::new(lo.x, hi.y, lo.z),
            Vec3::X,
            Vec3::Z,
            tint(0.8, 0.85, 1.0),
        ),
        (
            "hall back",
            Vec3::new(lo.x, lo.y, lo.z),
            Vec3::X,
            Vec3::Y,
            checker.clone(),
        ),
        (
            "hall front",
            Vec3::new(hi.x, lo.y, hi.z),
            Vec3::NEG_X,
            Vec3::Y,
            tint(1.0, 0.9, 0.8),
        ),
        (
            "hall left",
            Vec3::new(lo.x, lo.y, hi.z),
            Vec3::NEG_Z,
            Vec3::Y,
            tint(1.0, 0.75, 0.7),
        ),
        (
            "hall right",
            Vec3::new(hi.x, lo.y, lo.z),
            Vec3::Z,
            Vec3::Y,
            tint(0.7, 0.9, 0.75),
        ),
    ];
    faces
        .into_iter()
        .map(|(name, corner, u, v, material)| {
            Object::new(
                name,
                quad(corner, u * size, v * size, Vec2::splat(3.0)),
                material,
                Mat4::IDENTITY,
            )
        })
        .collect()
}

/// The morph target of `sphere` (a [`uv_sphere`] about the origin): every vertex scaled
/// radially into a tilted peanut, normals recomputed from the displaced surface; weight
/// 0 -> 1 -> 0 over the camera path.
fn peanut_target(sphere: &Mesh) -> Morph {
    let axis = Vec3::new(1.0, 0.5, 0.3).normalize();
    let mut target = sphere.clone();
    for p in &mut target.positions {
        let n = p.normalize_or_zero();
        let c = n.dot(axis);
        *p *= 0.85 * (1.0 + 0.35 * (2.0 * c * c - 1.0));
    }
    smooth_normals(&mut target);
    Morph {
        positions: target.positions,
        normals: target.normals,
        keys: vec![(0.0, 0.0), (0.5 * DURATION, 1.0), (DURATION, 0.0)],
    }
}

/// A glass teapot about 0.55 m across and 0.4 m tall, its base at y = 0, body round the y
/// axis, spout towards +x and handle towards -x: three closed parts (see the module
/// documentation).
fn teapot() -> Mesh {
    // Body and lid as one surface of revolution: base, belly, shoulder, rim, a dome lid and a
    // knob closed by an apex.
    let outline = [
        (0.0, 0.12),
        (0.015, 0.15),
        (0.05, 0.18),
        (0.1, 0.198),
        (0.15, 0.2),
        (0.2, 0.19),
        (0.245, 0.165),
        (0.28, 0.13),
        (0.3, 0.11),
        (0.305, 0.09),
        (0.33, 0.075),
        (0.35, 0.045),
        (0.355, 0.022),
        (0.375, 0.03),
        (0.395, 0.02),
        (0.4, 0.0),
    ];
    let rings: Vec<Ring> = outline.iter().map(|&(y, r)| Ring::circle(y, r)).collect();
    let body = loft(&rings, 48, 40.0);

    // Spout: a tapered tube from inside the lower body (which is about 0.2 m wide there) out
    // and up, along a quadratic Bezier curve.
    let (p0, p1, p2) = (
        Vec3::new(0.13, 0.1, 0.0),
        Vec3::new(0.25, 0.13, 0.0),
        Vec3::new(0.3, 0.31, 0.0),
    );
    let n = 16;
    let spout_path: Vec<Vec3> = (0..=n)
        .map(|i| {
            let t = i as f32 / n as f32;
            p0 * (1.0 - t) * (1.0 - t) + p1 * 2.0 * t * (1.0 - t) + p2 * t * t
        })
        .collect();
    let spout_radii: Vec<f32> = (0..=n)
        .map(|i| 0.045 - 0.022 * i as f32 / n as f32)
        .collect();
    let spout = tube(&spout_path, &spout_radii, 24);

    // Handle: a half ellipse on the -x side from y = 0.08 to 0.25 whose ends go straight
    // into the body wall (0.16-0.19 m from the axis there) to 0.12 m from the axis.
    let handle_path: Vec<Vec3> = (0..=n)
        .map(|i| {
            let a = std::f32::consts::PI * (i as f32 / n as f32 - 0.5);
            Vec3::new(-0.12 - 0.13 * a.cos(), 0.165 + 0.085 * a.sin(), 0.0)
        })
        .collect();
    let handle = tube(&handle_path, &vec![0.022; n + 1], 20);
    merge(&[body, spout, handle])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refractor(scene: &Scene) -> &Object {
        scene
            .objects
            .iter()
            .find(|o| o.material.is_specular())
            .unwrap()
    }

    /// The paper's other settings: the distant hall keeps only the refractor, encloses the
    /// camera path and the light, and is far (every wall at least 14 m from the refractor);
    /// `lights=2` adds a light; `metal=1` makes the refractor gold and still a caustic caster.
    #[test]
    fn distant_hall_two_lights_and_metal_are_what_they_say() {
        let distant = hu_qin(&HuQin {
            distant: true,
            ..Default::default()
        })
        .unwrap();
        distant.validate().unwrap();
        assert_eq!(distant.specular_objects().len(), 1);
        let centre = refractor(&distant).center_at(0.0);
        let walls: Vec<&Object> = distant
            .objects
            .iter()
            .filter(|o| o.name.starts_with("hall"))
            .collect();
        assert_eq!((walls.len(), distant.objects.len()), (6, 7));
        let (lo, hi) = crate::world_bounds(&distant.objects);
        let inside = |p: Vec3| p.cmpgt(lo).all() && p.cmplt(hi).all();
        assert!(distant.lights.iter().all(|l| inside(l.position)));
        assert!(distant.camera_path.keys.iter().all(|(_, c)| inside(c.eye)));
        for wall in walls {
            let (a, b) = wall.bounds_at(0.0);
            let nearest = centre.clamp(a, b).distance(centre);
            assert!(nearest >= 14.0, "{} is {nearest} m away", wall.name);
        }
        let two = hu_qin(&HuQin {
            lights: 2,
            ..Default::default()
        })
        .unwrap();
        assert_eq!(two.lights.len(), 2);
        assert!(
            hu_qin(&HuQin {
                lights: 3,
                ..Default::default()
            })
            .is_err()
        );
        let metal = hu_qin(&HuQin {
            metal: true,
            ..Default::default()
        })
        .unwrap();
        let gold = refractor(&metal);
        assert_eq!(gold.material, Material::gold());
        assert!(
            gold.roles
                .contains(Roles::REFLECTOR | Roles::CAUSTIC_CASTER)
        );
        assert!(crate::emission::caustic_casters(&metal).len() == 1);
    }

    #[test]
    fn every_refractor_is_valid_sized_and_placed() {
        for name in ["sphere", "teapot", "bunny", "morph"] {
            let scene = hu_qin(&HuQin {
                refractor: name.into(),
                ..Default::default()
            })
            .unwrap();
            scene.validate().unwrap();
            assert_eq!(scene.specular_objects().len(), 1, "{name}");
            let glass = refractor(&scene);
            assert_eq!(glass.material, Material::glass(1.15));
            assert!(
                glass
                    .roles
                    .contains(Roles::REFRACTOR | Roles::CAUSTIC_CASTER)
            );
            let centre = glass.center_at(0.0);
            assert!(centre.distance(REFRACTOR_CENTRE) < 1e-4, "{name}: {centre}");
            let (lo, hi) = glass.bounds_at(0.0);
            let size = (hi - lo).max_element();
            assert!((0.5..=0.62).contains(&size), "{name}: {size} m across");
            assert!(
                centre.y - 0.5 * (hi.y - lo.y) > 0.0,
                "{name}: below the floor"
            );
            // The refractor is in view along the whole path.
            for (_, cam) in &scene.camera_path.keys {
                let p = cam.project(centre, 256, 256).unwrap();
                assert!((64.0..192.0).contains(&p.x) && (64.0..192.0).contains(&p.y));
            }
            // No nearby mesh's bounding sphere holds the refractor's centre; each is within
            // 0.5-1 m of it.
            for o in &scene.objects {
                if o.material.is_specular() || o.name == "floor" || o.name == "checker wall" {
                    continue;
                }
                let d = o.center_at(0.0).distance(centre);
                assert!(d > o.bounding_radius_at(0.0), "{name}: {} holds it", o.name);
                let xz = (o.center_at(0.0) - centre) * Vec3::new(1.0, 0.0, 1.0);
                assert!((0.5..=1.0).contains(&xz.length()), "{}: {d}", o.name);
            }
        }
        assert!(matches!(
            hu_qin(&HuQin { refractor: "cube".into(), ..Default::default() }),
            Err(SceneError::BadParam(m)) if m.contains("sphere, teapot, bunny, morph")
        ));
        assert!(
            hu_qin(&HuQin {
                ior: 5.0,
                ..Default::default()
            })
            .is_err()
        );
    }

    /// The teapot is closed with outward normals: every edge (by position) is used once in
    /// each direction, the enclosed volume is positive, and every triangle winds with its
    /// vertex normals.
    #[test]
    fn the_teapot_is_closed_and_faces_outwards() {
        let mesh = teapot();
        let key = |i: u32| mesh.positions[i as usize].to_array().map(f32::to_bits);
        let mut edges = std::collections::HashMap::new();
        for t in mesh.indices.chunks(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((key(a), key(b))).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge used {count} times one way");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its twin");
        }
        let mut volume = 0.0;
        for t in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
            volume += a.dot(b.cross(c)) / 6.0;
            let face = (b - a).cross(c - a);
            if face.length() > 1e-9 {
                let n: Vec3 = t.iter().map(|&i| mesh.normals[i as usize]).sum();
                assert!(
                    face.dot(n) > 0.0,
                    "triangle {t:?} winds against its normals"
                );
            }
        }
        assert!(volume > 0.02, "{volume} m^3");
        assert!(mesh.triangle_count() < 5000);
    }

    #[test]
    fn the_morphing_refractor_deforms_along_the_path() {
        let scene = hu_qin(&HuQin {
            refractor: "morph".into(),
            ..Default::default()
        })
        .unwrap();
        let glass = refractor(&scene);
        assert!(glass.is_deforming());
        let morph = glass.morph.as_ref().unwrap();
        assert_eq!(morph.weight(0.0), 0.0);
        assert_eq!(morph.weight(0.5 * DURATION), 1.0);
        assert_eq!(morph.weight(DURATION), 0.0);
        assert_eq!(scene.camera_path.duration(), DURATION);
        // At the middle of the path the peanut is longer than the sphere along its axis and
        // narrower across it, and it stays above the floor.
        let (lo, hi) = glass.bounds_at(0.5 * DURATION);
        assert!((hi - lo).max_element() > 2.0 * SPHERE_RADIUS * 1.05);
        assert!((hi - lo).min_element() < 2.0 * SPHERE_RADIUS * 0.9);
        let world = glass.world_at(0.5 * DURATION);
        let lowest = glass
            .positions_at(0.5 * DURATION)
            .iter()
            .map(|p| world.transform_point3(*p).y)
            .fold(f32::INFINITY, f32::min);
        assert!(lowest > 0.05, "{lowest}");
        assert!(morph.normals.iter().all(|n| n.is_normalized()));
    }
}
