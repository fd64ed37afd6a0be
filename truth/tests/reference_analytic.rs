//! The reference renderer against closed-form answers: a lit diffuse plane, and a metal and
//! a glass sphere over that plane, whose pixels are recomputed here with the analytic
//! sphere (`gpu::prelude::ray_sphere`), the shared reflect/refract/Fresnel functions, and
//! the plane's radiance worked out by hand.

use glam::{Mat4, Vec2, Vec3};
use gpu::prelude::{fresnel_dielectric, fresnel_nk, ray_sphere, reflect_dir, refract_dir};
use scene::builtin::textures::checker_texture;
use scene::mesh::{quad, uv_sphere};
use scene::{Camera, CameraPath, Light, Material, Motion, Object, Roles, Scene, Volume};
use std::f32::consts::FRAC_1_PI;
use truth::reference::{ReferenceOptions, render};

const FLOOR_HALF: f32 = 50.0;
const FLOOR_ALBEDO: Vec3 = Vec3::new(0.6, 0.55, 0.5);
const LIGHT_POS: Vec3 = Vec3::new(1.5, 3.0, 1.0);
const LIGHT_I: Vec3 = Vec3::new(4.0, 4.0, 4.0);
const BACKGROUND: Vec3 = Vec3::new(0.2, 0.3, 0.4);
const CENTER: Vec3 = Vec3::new(0.0, 0.8, 0.0);
const RADIUS: f32 = 0.5;

fn floor() -> Object {
    Object::new(
        "floor",
        quad(
            Vec3::new(-FLOOR_HALF, 0.0, FLOOR_HALF),
            Vec3::X * 2.0 * FLOOR_HALF,
            Vec3::NEG_Z * 2.0 * FLOOR_HALF,
            Vec2::ONE,
        ),
        Material::Diffuse {
            albedo: FLOOR_ALBEDO,
            texture: None,
            cutout: None,
        },
        Mat4::IDENTITY,
    )
}

fn scene_with(objects: Vec<Object>, camera: Camera) -> Scene {
    Scene {
        name: "analytic".into(),
        objects,
        textures: vec![],
        lights: vec![Light {
            name: "light".into(),
            position: LIGHT_POS,
            intensity: LIGHT_I,
            kind: scene::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: BACKGROUND,
    }
}

fn sphere_scene(material: Material, camera: Camera) -> Scene {
    let sphere = Object::new(
        "sphere",
        uv_sphere(RADIUS, 64, 128),
        material,
        Mat4::from_translation(CENTER),
    )
    .with_roles(Roles::REFLECTOR | Roles::CAUSTIC_CASTER);
    scene_with(vec![floor(), sphere], camera)
}

/// The scene of the tests in closed form: the analytic sphere (or none) over the floor
/// plane y = 0, one point light, the background elsewhere.
struct Analytic {
    sphere: Option<Material>,
    max_depth: u32,
    /// The floor's emission (`Object::emission`).
    floor_emission: Vec3,
}

impl Analytic {
    /// Distance to the analytic sphere along the ray, if ahead (t > 1e-4).
    fn sphere_t(o: Vec3, d: Vec3) -> Option<f32> {
        let s = ray_sphere(o, d, CENTER, RADIUS);
        if s.x > s.y {
            return None;
        }
        if s.x > 1e-4 {
            Some(s.x)
        } else if s.y > 1e-4 {
            Some(s.y)
        } else {
            None
        }
    }

    /// Radiance of the floor at p by hand: albedo / pi * I * cos / d^2, shadowed by the
    /// sphere whatever its material.
    fn floor_radiance(&self, p: Vec3) -> Vec3 {
        let to_l = LIGHT_POS - p;
        let dist = to_l.length();
        let l = to_l / dist;
        if self.sphere.is_some() {
            let s = ray_sphere(p, l, CENTER, RADIUS);
            if s.x <= s.y && s.y > 0.0 && s.x < dist {
                return self.floor_emission;
            }
        }
        self.floor_emission + FLOOR_ALBEDO * FRAC_1_PI * LIGHT_I * l.y / (dist * dist)
    }

    fn radiance(&self, o: Vec3, d: Vec3, depth: u32) -> Vec3 {
        let t_sphere = if self.sphere.is_some() {
            Self::sphere_t(o, d)
        } else {
            None
        };
        let t_floor = if d.y < 0.0 {
            let t = -o.y / d.y;
            let p = o + d * t;
            (p.x.abs() <= FLOOR_HALF && p.z.abs() <= FLOOR_HALF).then_some(t)
        } else {
            None
        };
        match (t_sphere, t_floor) {
            (Some(ts), tf) if tf.is_none_or(|tf| ts < tf) => {
                if depth >= self.max_depth {
                    return Vec3::ZERO;
                }
                let p = o + d * ts;
                let n = (p - CENTER) / RADIUS;
                let front = d.dot(n) < 0.0;
                let n = if front { n } else { -n };
                let cos_i = (-d).dot(n).clamp(0.0, 1.0);
                let refl = reflect_dir(d, n).normalize();
                match self.sphere.as_ref().unwrap() {
                    Material::Metal { n: eta, k } => {
                        fresnel_nk(cos_i, *eta, *k) * self.radiance(p + n * 1e-4, refl, depth + 1)
                    }
                    Material::Glass { ior } => {
                        let eta_rel = if front { *ior } else { 1.0 / ior };
                        let f = fresnel_dielectric(cos_i, eta_rel);
                        let t = refract_dir(d, n, 1.0 / eta_rel);
                        let r = self.radiance(p + n * 1e-4, refl, depth + 1);
                        if t.w == 0.0 || f >= 1.0 {
                            r
                        } else {
                            f * r + (1.0 - f) * self.radiance(p - n * 1e-4, t.truncate(), depth + 1)
                        }
                    }
                    Material::Diffuse { .. } => unreachable!(),
                }
            }
            (_, Some(tf)) => self.floor_radiance(o + d * tf),
            _ => BACKGROUND,
        }
    }
}

/// Compares the reference with the analytic scene on every pixel where the analytic answer
/// is smooth: pixels whose value changes by more than `smooth_tol` (relative) within
/// +-0.35 px (silhouettes,
/// shadow edges seen in the sphere, where the tessellated mesh and the exact sphere may
/// disagree by a pixel) are left out. Returns (pixels compared, pixels showing the sphere).
fn compare(
    scene: &Scene,
    analytic: &Analytic,
    size: u32,
    rel_tol: f32,
    smooth_tol: f32,
) -> (usize, usize) {
    let cam = scene.camera;
    let opts = ReferenceOptions {
        photons: 0,
        max_depth: analytic.max_depth,
        ..Default::default()
    };
    let r = render(scene, &cam, 0.0, size, size, &opts);
    assert_eq!(r.image.non_finite_count(), 0);
    let (mut compared, mut on_sphere, mut worst) = (0, 0, 0.0f32);
    for y in 0..size {
        for x in 0..size {
            let at = |dx: f32, dy: f32| {
                let d = cam.ray_dir(x as f32 + 0.5 + dx, y as f32 + 0.5 + dy, size, size);
                analytic.radiance(cam.eye, d, 0)
            };
            let centre = at(0.0, 0.0);
            let smooth = [(0.35, 0.0), (-0.35, 0.0), (0.0, 0.35), (0.0, -0.35)]
                .iter()
                .all(|&(dx, dy)| {
                    (at(dx, dy) - centre).abs().max_element()
                        <= smooth_tol * centre.max_element() + 1e-4
                });
            if !smooth {
                continue;
            }
            let d = cam.ray_dir(x as f32 + 0.5, y as f32 + 0.5, size, size);
            if analytic.sphere.is_some() && Analytic::sphere_t(cam.eye, d).is_some() {
                on_sphere += 1;
            }
            let p = r.image.get(x, y);
            let got = Vec3::new(p[0], p[1], p[2]);
            let err = (got - centre).abs().max_element();
            let tol = rel_tol * centre.max_element() + 2e-4;
            worst = worst.max(err / (centre.max_element() + 1e-3));
            assert!(
                err <= tol,
                "pixel ({x}, {y}): reference {got:?}, analytic {centre:?}"
            );
            compared += 1;
        }
    }
    println!(
        "compared {compared} pixels ({on_sphere} on the sphere), worst relative error {worst:.2e}"
    );
    (compared, on_sphere)
}

#[test]
fn diffuse_plane_is_exactly_the_shading_formula() {
    let camera = Camera {
        eye: Vec3::new(0.0, 2.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let scene = scene_with(vec![floor()], camera);
    let analytic = Analytic {
        sphere: None,
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    let (compared, _) = compare(&scene, &analytic, 48, 1e-4, f32::INFINITY);
    assert_eq!(compared, 48 * 48);
}

#[test]
fn perfect_mirror_sphere_matches_closed_form() {
    let camera = Camera {
        eye: Vec3::new(0.3, 1.2, 2.6),
        target: CENTER,
        up: Vec3::Y,
        fov_y_deg: 28.0,
        orthographic: None,
    };
    let scene = sphere_scene(Material::perfect_mirror(), camera);
    let analytic = Analytic {
        sphere: Some(Material::perfect_mirror()),
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    let (compared, on_sphere) = compare(&scene, &analytic, 64, 0.01, 0.03);
    assert!(on_sphere > 400, "only {on_sphere} sphere pixels compared");
    assert!(compared > 64 * 64 / 2);
}

#[test]
fn gold_sphere_matches_closed_form_per_channel() {
    let camera = Camera {
        eye: Vec3::new(-0.4, 1.4, 2.4),
        target: CENTER,
        up: Vec3::Y,
        fov_y_deg: 30.0,
        orthographic: None,
    };
    let scene = sphere_scene(Material::gold(), camera);
    let analytic = Analytic {
        sphere: Some(Material::gold()),
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    let (_, on_sphere) = compare(&scene, &analytic, 64, 0.01, 0.03);
    assert!(on_sphere > 400, "only {on_sphere} sphere pixels compared");
}

#[test]
fn glass_sphere_matches_closed_form() {
    let camera = Camera {
        eye: Vec3::new(0.2, 1.6, 2.8),
        target: Vec3::new(0.0, 0.6, 0.0),
        up: Vec3::Y,
        fov_y_deg: 30.0,
        orthographic: None,
    };
    let glass = Material::glass(1.5);
    let scene = sphere_scene(glass.clone(), camera);
    let analytic = Analytic {
        sphere: Some(glass),
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    let (_, on_sphere) = compare(&scene, &analytic, 64, 0.01, 0.03);
    assert!(on_sphere > 300, "only {on_sphere} sphere pixels compared");
}

/// A textured plane: albedo times the bilinear, sRGB-decoded texture at the hit's uv.
#[test]
fn textured_plane_multiplies_albedo_by_texture() {
    let camera = Camera {
        eye: Vec3::new(0.0, 1.5, 1.5),
        target: Vec3::new(0.0, 0.0, -0.5),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let mut plane = floor();
    plane.material = Material::Diffuse {
        albedo: Vec3::new(0.9, 0.8, 1.0),
        texture: Some(0),
        cutout: None,
    };
    // uv_scale 40 so that the checker's cells are a few pixels wide.
    plane.mesh = quad(
        Vec3::new(-FLOOR_HALF, 0.0, FLOOR_HALF),
        Vec3::X * 2.0 * FLOOR_HALF,
        Vec3::NEG_Z * 2.0 * FLOOR_HALF,
        Vec2::splat(40.0),
    );
    let mut scene = scene_with(vec![plane], camera);
    scene.textures.push(checker_texture(
        "checker",
        16,
        4,
        [250, 40, 40],
        [30, 60, 200],
    ));
    let size = 48;
    let opts = ReferenceOptions {
        photons: 0,
        ..Default::default()
    };
    let r = render(&scene, &camera, 0.0, size, size, &opts);
    let analytic = Analytic {
        sphere: None,
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    for y in 0..size {
        for x in 0..size {
            let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, size, size);
            assert!(d.y < 0.0);
            let p = camera.eye - d * (camera.eye.y / d.y);
            // quad(): uv = (0, s) at the origin corner, u along the first edge, v decreasing
            // along the second.
            let s = (p.x + FLOOR_HALF) / (2.0 * FLOOR_HALF);
            let t = (FLOOR_HALF - p.z) / (2.0 * FLOOR_HALF);
            let uv = Vec2::new(s, 1.0 - t) * 40.0;
            let tex = scene.textures[0].sample(uv);
            let want = analytic.floor_radiance(p) / FLOOR_ALBEDO * Vec3::new(0.9, 0.8, 1.0) * tex;
            let px = r.image.get(x, y);
            let got = Vec3::new(px[0], px[1], px[2]);
            assert!(
                (got - want).abs().max_element() <= 2e-3 * want.max_element() + 1e-5,
                "pixel ({x}, {y}): {got:?} vs {want:?}"
            );
        }
    }
}

/// Index below 1 (an air bubble in water, as it were): total internal reflection on entry.
#[test]
fn low_index_glass_sphere_matches_closed_form() {
    let camera = Camera {
        eye: Vec3::new(0.2, 1.6, 2.8),
        target: Vec3::new(0.0, 0.6, 0.0),
        up: Vec3::Y,
        fov_y_deg: 30.0,
        orthographic: None,
    };
    let glass = Material::glass(0.75);
    let scene = sphere_scene(glass.clone(), camera);
    let analytic = Analytic {
        sphere: Some(glass),
        max_depth: 8,
        floor_emission: Vec3::ZERO,
    };
    let (_, on_sphere) = compare(&scene, &analytic, 64, 0.01, 0.03);
    assert!(on_sphere > 300, "only {on_sphere} sphere pixels compared");
}

/// `max_depth = 0`: specular surfaces are black, diffuse ones unchanged.
#[test]
fn depth_zero_makes_specular_black() {
    let camera = Camera {
        eye: Vec3::new(0.3, 1.2, 2.6),
        target: CENTER,
        up: Vec3::Y,
        fov_y_deg: 28.0,
        orthographic: None,
    };
    let scene = sphere_scene(Material::perfect_mirror(), camera);
    let opts = ReferenceOptions {
        photons: 0,
        max_depth: 0,
        ..Default::default()
    };
    let r = render(&scene, &camera, 0.0, 32, 32, &opts);
    for (i, id) in r.object_ids.iter().enumerate() {
        if *id == 1 {
            assert_eq!(&r.image.pixels[i][..3], &[0.0, 0.0, 0.0]);
        }
    }
}

#[test]
fn object_ids_and_mask() {
    let camera = Camera {
        eye: Vec3::new(0.0, 1.2, 3.0),
        target: CENTER,
        up: Vec3::Y,
        fov_y_deg: 40.0,
        orthographic: None,
    };
    let mut scene = sphere_scene(Material::perfect_mirror(), camera);
    // A volume in front of the floor on the left half of the image, not touching the sphere.
    scene.volumes.push(Volume {
        name: "fog".into(),
        center: Vec3::new(-1.0, 0.3, 1.0),
        radius: 0.3,
        color: Vec3::ONE,
        density: 1.0,
        profile: scene::DensityProfile::UNIFORM,
        particle: false,
        motion: Motion::default(),
    });
    let size = 48;
    let r = render(
        &scene,
        &camera,
        0.0,
        size,
        size,
        &ReferenceOptions {
            photons: 0,
            ..Default::default()
        },
    );
    let (mut fog, mut sphere) = (0, 0);
    for y in 0..size {
        for x in 0..size {
            let i = (y * size + x) as usize;
            let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, size, size);
            let hits_sphere = Analytic::sphere_t(camera.eye, d).is_some();
            let v = ray_sphere(camera.eye, d, Vec3::new(-1.0, 0.3, 1.0), 0.3);
            let crosses_fog = v.x <= v.y && v.y > 0.0;
            // Away from the silhouette, the mesh and the analytic sphere agree.
            let near_edge = {
                let s = (camera.eye - CENTER).cross(d).length();
                (s - RADIUS).abs() < 0.02
            };
            if !near_edge {
                let on_floor = d.y < 0.0 && {
                    let p = camera.eye - d * (camera.eye.y / d.y);
                    p.x.abs() <= FLOOR_HALF && p.z.abs() <= FLOOR_HALF
                };
                let expect_id = if hits_sphere {
                    1
                } else if on_floor {
                    0
                } else {
                    -1
                };
                assert_eq!(r.object_ids[i], expect_id, "pixel {x},{y}");
                let v_edge = (camera.eye - Vec3::new(-1.0, 0.3, 1.0)).cross(d).length();
                if (v_edge - 0.3).abs() > 0.01 {
                    assert_eq!(r.mask[i], hits_sphere || crosses_fog, "pixel {x},{y}");
                }
            }
            fog += crosses_fog as u32;
            sphere += hits_sphere as u32;
        }
    }
    assert!(fog > 10 && sphere > 200, "fog {fog}, sphere {sphere}");
}

/// An emissive floor adds its emission to what it reflects, seen directly and in a mirror
/// sphere (times the sphere's Fresnel term), and lights nothing: the sphere's shadow on the
/// floor still shows the emission alone.
#[test]
fn emission_is_seen_directly_and_in_a_mirror_and_lights_nothing() {
    let camera = Camera {
        eye: Vec3::new(0.3, 1.2, 2.6),
        target: CENTER,
        up: Vec3::Y,
        fov_y_deg: 40.0,
        orthographic: None,
    };
    let emission = Vec3::new(0.3, 0.15, 0.05);
    let mut scene = sphere_scene(Material::perfect_mirror(), camera);
    scene.objects[0].emission = emission;
    scene.validate().unwrap();
    let analytic = Analytic {
        sphere: Some(Material::perfect_mirror()),
        max_depth: 8,
        floor_emission: emission,
    };
    let (compared, on_sphere) = compare(&scene, &analytic, 64, 0.01, 0.03);
    assert!(on_sphere > 200, "only {on_sphere} sphere pixels compared");
    assert!(compared > 64 * 64 / 2);
}

/// The floor under a spot or a sun, by hand, pixel by pixel: `albedo / pi * I f(w) cos / d^2`
/// for the spot (its falloff `f` at the direction `w` it sends the light), `albedo / pi * E
/// cos` for the sun, whose shadow of a diffuse ball is the ball's disc cast along its
/// direction. Pixels within half a pixel of the cone's edge or the shadow's are left out.
#[test]
fn spot_and_sun_light_the_floor_as_the_formula_says() {
    let camera = Camera {
        eye: Vec3::new(0.0, 3.0, 3.5),
        target: Vec3::new(0.0, 0.0, 0.3),
        up: Vec3::Y,
        fov_y_deg: 55.0,
        orthographic: None,
    };
    let spot = Light {
        kind: scene::LightKind::Spot {
            direction: Vec3::new(0.2, -1.0, 0.0).normalize(),
            inner_cone: 0.25,
            outer_cone: 0.45,
        },
        ..Light::point("spot", LIGHT_POS, LIGHT_I)
    };
    let sun_direction = Vec3::new(-0.4, -1.0, -0.3).normalize();
    let sun = Light {
        kind: scene::LightKind::Directional {
            direction: sun_direction,
        },
        ..Light::point("sun", LIGHT_POS, Vec3::new(1.5, 1.4, 1.2))
    };
    let ball = Object::new(
        "ball",
        uv_sphere(RADIUS, 64, 128),
        Material::Diffuse {
            albedo: Vec3::splat(0.5),
            texture: None,
            cutout: None,
        },
        Mat4::from_translation(CENTER),
    );
    let size = 48;
    for (light, objects) in [(spot, vec![floor()]), (sun, vec![floor(), ball])] {
        let mut scene = scene_with(objects, camera);
        scene.lights = vec![light.clone()];
        // Worked out here, not through scene::Light: glTF's spot falloff, the square of a
        // linear ramp in the cosine between the cones.
        let by_hand = |p: Vec3| match light.kind {
            scene::LightKind::Directional { direction } => {
                let s = ray_sphere(p, -direction, CENTER, RADIUS);
                if s.x <= s.y && s.y > 0.0 {
                    return Vec3::ZERO;
                }
                FLOOR_ALBEDO * FRAC_1_PI * light.intensity * (-direction.y)
            }
            scene::LightKind::Spot {
                direction,
                inner_cone,
                outer_cone,
            } => {
                let to_l = light.position - p;
                let d2 = to_l.length_squared();
                let cos_axis = direction.dot(-to_l / d2.sqrt());
                let ramp = ((cos_axis - outer_cone.cos()) / (inner_cone.cos() - outer_cone.cos()))
                    .clamp(0.0, 1.0);
                FLOOR_ALBEDO * FRAC_1_PI * light.intensity * (ramp * ramp) * (to_l.y / d2.sqrt())
                    / d2
            }
            scene::LightKind::Point => unreachable!(),
        };
        let has_ball = scene.objects.len() > 1;
        // The floor's radiance seen through (x, y), or None where the ball hides it.
        let floor_at = |x: f32, y: f32| {
            let d = camera.ray_dir(x, y, size, size);
            let on_ball = ray_sphere(camera.eye, d, CENTER, RADIUS);
            if has_ball && on_ball.x <= on_ball.y && on_ball.y > 0.0 {
                return None;
            }
            Some(by_hand(camera.eye + d * (-camera.eye.y / d.y)))
        };
        let opts = ReferenceOptions {
            photons: 0,
            ..Default::default()
        };
        let r = render(&scene, &camera, 0.0, size, size, &opts);
        assert_eq!(r.image.non_finite_count(), 0);
        let (mut compared, mut lit, mut dark) = (0, 0, 0);
        for y in 0..size {
            for x in 0..size {
                let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
                let Some(centre) = floor_at(fx, fy) else {
                    continue;
                };
                let edge = [(0.5, 0.0), (-0.5, 0.0), (0.0, 0.5), (0.0, -0.5)]
                    .iter()
                    .any(|&(dx, dy)| {
                        floor_at(fx + dx, fy + dy).is_none_or(|v| {
                            (v - centre).abs().max_element() > 0.2 * centre.max_element() + 1e-4
                        })
                    });
                if edge {
                    continue;
                }
                let p = r.image.get(x, y);
                let got = Vec3::new(p[0], p[1], p[2]);
                assert!(
                    (got - centre).abs().max_element() <= 1e-4 * centre.max_element() + 2e-5,
                    "{} light, pixel ({x}, {y}): reference {got}, by hand {centre}",
                    light.kind_name()
                );
                compared += 1;
                if centre.max_element() > 0.0 {
                    lit += 1;
                } else {
                    dark += 1;
                }
            }
        }
        println!(
            "{}: {compared} pixels, {lit} lit, {dark} dark",
            light.kind_name()
        );
        assert!(lit > 100 && dark > 15, "{lit} lit and {dark} dark pixels");
    }
}

/// A quad cut out by its texture's alpha (`Material::Diffuse`'s `cutout`) in front of a wall:
/// closest- and any-hit queries pass through its holes and stop on the rest, whether the hole
/// is wide or a texel, and a threshold above every alpha leaves no surface.
#[test]
fn rays_pass_through_the_holes_of_an_alpha_cut_out() {
    use scene::{Texture, bvh::SceneBvh};
    // Alpha 0 in the left half (texels 0 to 3), 1 in the right, one opaque texel (1) inside
    // the hole and one clear texel (6) inside the solid half: bilinear between texel centres,
    // so at the centre of texel 1 the alpha is exactly 1.
    let alpha = [0u8, 255, 0, 0, 255, 255, 0, 255];
    let texture = Texture {
        name: "mask".into(),
        width: 8,
        height: 1,
        rgba8: alpha.iter().flat_map(|&a| [200, 200, 200, a]).collect(),
    };
    let panel = |cutout| {
        Object::new(
            "panel",
            quad(Vec3::ZERO, Vec3::X, Vec3::Y, Vec2::ONE),
            Material::Diffuse {
                albedo: Vec3::ONE,
                texture: Some(0),
                cutout: Some(cutout),
            },
            Mat4::IDENTITY,
        )
    };
    let wall = Object::new(
        "wall",
        quad(
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::X * 3.0,
            Vec3::Y * 3.0,
            Vec2::ONE,
        ),
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    );
    let mut scene = scene::load("cornell-sphere").unwrap();
    scene.objects = vec![panel(0.5), wall];
    scene.textures = vec![texture];
    scene.validate().unwrap();
    let bvh = SceneBvh::build(&scene, 0.0);
    // u at the centre of texel i: (i + 0.5) / 8; the quad's uv is its (x, 1 - y).
    let through = |u: f32| Vec3::new(u, 0.5, 1.0);
    for (texel, opaque) in [
        (0.0, false),
        (2.5, false),
        (1.0, true),
        (5.0, true),
        (6.0, false),
    ] {
        let o = through((texel + 0.5) / 8.0);
        let h = bvh.closest_hit(o, Vec3::NEG_Z, f32::INFINITY).unwrap();
        let expected = if opaque { (0, 1.0) } else { (1, 2.0) };
        assert_eq!((h.object, h.t), expected, "texel {texel}");
        assert_eq!(bvh.any_hit(o, Vec3::NEG_Z, 1.5), opaque, "texel {texel}");
    }
    // Threshold 1 cuts out the texel of alpha 254 / 255 too.
    scene.objects[0] = panel(1.0);
    scene.textures[0].rgba8[4 * 1 + 3] = 254;
    let bvh = SceneBvh::build(&scene, 0.0);
    let h = bvh.closest_hit(through(1.5 / 8.0), Vec3::NEG_Z, f32::INFINITY);
    assert_eq!(h.unwrap().object, 1);
}
