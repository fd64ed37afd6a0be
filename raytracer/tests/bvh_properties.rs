//! Properties of the traversal twin (`raytracer::bvh::FlatBvh`): on random scenes and random
//! rays it finds the same nearest hit as the reference's BVH (`scene::bvh::SceneBvh`, obvhs'
//! CWBVH), and any-hit agrees with closest-hit. The rays include the hard cases of a BVH:
//! rays starting inside boxes (inside a closed box mesh and inside the tree's node bounds),
//! axis-parallel rays (zero direction components, both signs), and rays aimed exactly at
//! triangle edges and vertices (grazing, where a watertight test must not let a ray through).

use glam::{Mat4, Quat, Vec2, Vec3};
use obvhs::{ray::Ray, rt_triangle::RtTriangle};
use proptest::prelude::*;
use raytracer::bvh::FlatBvh;
use scene::bvh::{SceneBvh, WorldTriangles, intersect};
use scene::mesh::{cuboid, quad, uv_sphere};
use scene::{Camera, CameraPath, Material, Object, Scene};
use testkit::strategies::{direction_with_zeros, unit_vector, vec3_in};

fn scene_of(objects: Vec<Object>) -> Scene {
    Scene {
        name: "random".into(),
        objects,
        textures: vec![],
        lights: vec![],
        camera: Camera {
            eye: Vec3::Z,
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 60.0,
            orthographic: None,
        },
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

/// One object of a random scene: a box, a sphere or a quad, placed and rotated at random.
fn object() -> impl Strategy<Value = Object> {
    (
        0u8..3,
        vec3_in(-3.0, 3.0),
        vec3_in(0.2, 1.5),
        unit_vector(),
        0.0f32..std::f32::consts::TAU,
    )
        .prop_map(|(kind, at, size, axis, angle)| {
            let mesh = match kind {
                0 => cuboid(-size * 0.5, size * 0.5),
                1 => uv_sphere(size.x * 0.5, 12, 8),
                _ => quad(
                    -0.5 * Vec3::new(size.x, size.y, 0.0),
                    Vec3::X * size.x,
                    Vec3::Y * size.y,
                    Vec2::ONE,
                ),
            };
            let transform = Mat4::from_rotation_translation(Quat::from_axis_angle(axis, angle), at);
            Object::new("random", mesh, Material::diffuse(0.5, 0.5, 0.5), transform)
        })
}

fn scene() -> impl Strategy<Value = Scene> {
    prop::collection::vec(object(), 1..8).prop_map(scene_of)
}

/// The three ways of finding a ray's nearest hit: the twin, the reference's BVH, and every
/// triangle tested in turn (the ground truth of both BVHs).
struct Queries {
    flat: FlatBvh,
    reference: SceneBvh,
    all: Vec<RtTriangle>,
}

impl Queries {
    fn of(s: &Scene) -> Self {
        Queries {
            flat: FlatBvh::build(s, 0.0).unwrap(),
            reference: SceneBvh::build(s, 0.0),
            all: WorldTriangles::of(s, 0.0)
                .triangles
                .iter()
                .map(RtTriangle::from)
                .collect(),
        }
    }

    fn brute_force(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let ray = Ray::new(o.into(), d.into(), 0.0, t_max);
        self.all
            .iter()
            .map(|t| intersect(t, &ray))
            .filter(|t| t.is_finite())
            .min_by(f32::total_cmp)
    }

    /// The twin finds exactly the nearest hit of all triangles (the same triangle test, so the
    /// same distance to the bit), the reference's BVH the same one, and any-hit agrees.
    fn assert_same_hit(&self, o: Vec3, d: Vec3, t_max: f32) {
        let truth = self.brute_force(o, d, t_max);
        let twin = self.flat.closest_hit(o, d, t_max);
        let reference = self.reference.closest_hit(o, d, t_max);
        assert_eq!(
            twin.map(|h| h.t),
            truth,
            "o {o:?} d {d:?} t_max {t_max}: twin {twin:?}, every triangle {truth:?}"
        );
        assert_eq!(
            reference.map(|h| h.t),
            truth,
            "o {o:?} d {d:?} t_max {t_max}: reference BVH {reference:?}, every triangle {truth:?}"
        );
        if let (Some(a), Some(b)) = (twin, reference) {
            // On a shared edge the two may pick either triangle (the same point).
            if a.object == b.object && a.triangle == b.triangle {
                assert_eq!(a, b, "the same triangle, different attributes");
            }
        }
        assert_eq!(
            self.flat.any_hit(o, d, t_max),
            truth.is_some(),
            "o {o:?} d {d:?}: any-hit disagrees"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn random_rays_find_the_reference_hit(
        s in scene(),
        rays in prop::collection::vec((vec3_in(-5.0, 5.0), unit_vector(), 0.5f32..20.0), 32),
    ) {
        let q = Queries::of(&s);
        for (o, d, t_max) in rays {
            q.assert_same_hit(o, d, t_max);
            q.assert_same_hit(o, d, f32::INFINITY);
        }
    }

    #[test]
    fn axis_parallel_rays_and_rays_from_inside_boxes(
        s in scene(),
        rays in prop::collection::vec((0usize..64, vec3_in(-0.45, 0.45), direction_with_zeros()), 32),
    ) {
        let q = Queries::of(&s);
        for (i, local, d) in rays {
            // A point inside an object's bounds (inside a box mesh for boxes) and inside
            // the nodes above it.
            let object = &s.objects[i % s.objects.len()];
            let o = object.center_at(0.0) + local * object.bounding_radius_at(0.0);
            q.assert_same_hit(o, d, f32::INFINITY);
        }
    }

    #[test]
    fn rays_grazing_edges_and_vertices(
        s in scene(),
        rays in prop::collection::vec((0usize..100_000, 0.0f32..=1.0, 0u8..3, vec3_in(-6.0, 6.0)), 32),
    ) {
        let q = Queries::of(&s);
        let world = WorldTriangles::of(&s, 0.0);
        for (i, f, edge, from) in rays {
            // Aim at a point on an edge (f in [0, 1]: the vertices included), to rounding:
            // the ray meets the edge or passes a hair beside it, where only a watertight test
            // and boxes that keep their faces give the same answer as testing every triangle.
            let t = &world.triangles[i % world.triangles.len()];
            let v: [Vec3; 3] = [t.v0.into(), t.v1.into(), t.v2.into()];
            let (a, b) = (v[edge as usize], v[(edge as usize + 1) % 3]);
            let target = a.lerp(b, f);
            let d = (target - from).normalize_or_zero();
            if d == Vec3::ZERO {
                continue;
            }
            q.assert_same_hit(from, d, f32::INFINITY);
        }
    }
}

/// A mesh of many triangles (a fine sphere, the BVH several levels deep) and rays of the
/// camera, axis-parallel rays through it and rays along its surface.
#[test]
fn a_deep_tree_agrees_on_camera_rays() {
    let sphere = Object::new(
        "sphere",
        uv_sphere(1.0, 48, 96),
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    );
    let floor = Object::new(
        "floor",
        quad(
            Vec3::new(-3.0, -1.0, -3.0),
            Vec3::X * 6.0,
            Vec3::Z * 6.0,
            Vec2::ONE,
        ),
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    );
    let s = scene_of(vec![sphere, floor]);
    let q = Queries::of(&s);
    assert!(q.flat.depth > 8, "depth {}", q.flat.depth);
    let camera = Camera {
        eye: Vec3::new(0.3, 0.8, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 45.0,
        orthographic: None,
    };
    for y in 0..48 {
        for x in 0..48 {
            let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, 48, 48);
            q.assert_same_hit(camera.eye, d, f32::INFINITY);
        }
    }
    for k in -20..=20 {
        let o = Vec3::new(k as f32 * 0.05, 0.0, 5.0);
        q.assert_same_hit(o, Vec3::NEG_Z, f32::INFINITY);
        // In the floor's plane: grazing the floor, tangent to the sphere's lowest vertex.
        q.assert_same_hit(Vec3::new(-5.0, -1.0, o.x), Vec3::X, 10.0);
    }
}

#[test]
fn an_empty_scene_misses_everything() {
    let flat = FlatBvh::build(&scene_of(vec![]), 0.0).unwrap();
    assert!(flat.nodes.is_empty());
    assert!(
        flat.closest_hit(Vec3::ZERO, Vec3::X, f32::INFINITY)
            .is_none()
    );
    assert!(!flat.any_hit(Vec3::ZERO, Vec3::X, 1.0));
}

#[test]
fn bad_rays_miss_instead_of_panicking() {
    let s = scene_of(vec![Object::new(
        "box",
        cuboid(Vec3::ZERO, Vec3::ONE),
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    )]);
    let flat = FlatBvh::build(&s, 0.0).unwrap();
    for (o, d, t) in [
        (Vec3::NAN, Vec3::X, 1.0),
        (Vec3::ZERO, Vec3::ZERO, 1.0),
        (Vec3::ZERO, Vec3::splat(f32::INFINITY), 1.0),
        (Vec3::ZERO, Vec3::X, -1.0),
        (Vec3::ZERO, Vec3::X, f32::NAN),
    ] {
        assert!(flat.closest_hit(o, d, t).is_none());
    }
}

/// An alpha cut-out (`scene::Material::Diffuse`'s `cutout`): the twin (the cut-out table the
/// GPU reads, `raytracer::bvh::in_hole`) and the reference's BVH (`scene::Texture::
/// sample_alpha`) skip the same holes: the same object at the same distance on every camera
/// ray of the perforated Cornell room, with rays through holes among them.
#[test]
fn cut_outs_are_skipped_as_the_reference_skips_them() {
    let spec = scene::builtin::CUTOUT_VARIANTS[0];
    let s = scene::load(spec).unwrap();
    let flat = FlatBvh::build(&s, 0.0).unwrap();
    let reference = SceneBvh::build(&s, 0.0);
    let screen = s.objects.iter().position(|o| o.material.cutout().is_some());
    let screen = screen.expect("a cut-out object");
    let camera = s.camera_at(0.0);
    let (mut on_screen, mut behind_screen) = (0, 0);
    let n = 96;
    for y in 0..n {
        for x in 0..n {
            let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, n, n);
            let twin = flat.closest_hit(camera.eye, d, f32::INFINITY);
            let truth = reference.closest_hit(camera.eye, d, f32::INFINITY);
            let (a, b) = (twin.unwrap(), truth.unwrap());
            assert_eq!(a.object, b.object, "pixel ({x}, {y}): {a:?} vs {b:?}");
            assert_eq!(a.t, b.t, "pixel ({x}, {y})");
            // A hit beyond the screen's plane through its rectangle went through a hole.
            use scene::builtin::cornell::{SCREEN_X, SCREEN_Z};
            let at = camera.eye + d * ((SCREEN_Z - camera.eye.z) / d.z);
            let inside = SCREEN_X.contains(&at.x) && (0.0..0.9).contains(&at.y);
            if a.object == screen {
                on_screen += 1;
            } else if inside && a.t > (at - camera.eye).length() {
                behind_screen += 1;
            }
        }
    }
    // A quarter of the screen is holes.
    assert!(on_screen > 200, "{on_screen} rays hit the screen");
    let open = behind_screen as f32 / (on_screen + behind_screen) as f32;
    assert!(
        (0.15..0.35).contains(&open),
        "{behind_screen} of the screen's rays pass"
    );
}
