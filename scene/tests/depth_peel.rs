//! Depth peeling of a `GpuScene` of UV spheres against the analytic spheres.
//!
//! Every sphere is one object: the unit UV sphere `scene::mesh::uv_sphere(1, STACKS, SLICES)`
//! placed by a non-identity transform (scale = radius, a quarter turn about +Y, translation =
//! centre), so the peeler must apply each object's transform and normal matrix to land on the
//! analytic sphere.
//!
//! Tolerances: a UV sphere with `SLICES` x `STACKS` quads lies inside the true sphere by at most
//! its sagitta `1 - cos(half the quad diagonal angle)` (about 2.4e-3 for a unit sphere here,
//! scaled by the radius), so a distance along a view ray may differ by
//! `radius * sagitta / cos(incidence)`; pixels whose ray passes within 0.1 radius of the
//! silhouette are skipped (the mesh silhouette is inside the sphere's). Where the ray meets a
//! mesh vertex (the image centre here: the quarter turn maps the mesh's equator vertices at
//! +-Z onto vertices) the distance is exact up to rounding: 1e-4. Normals are the interpolated
//! vertex normals of a sphere, which equal the direction of the interpolated surface point from
//! the centre: 1e-3 in the dot product.

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gpu::GpuError;
use scene::{DepthPeeler, GpuScene, Material, Motion, Object, ObjectFilter, Scene};

const SLICES: u32 = 64;
const STACKS: u32 = 32;
/// Odd, so that the centre pixel's ray is the camera axis.
const SIZE: u32 = 65;
const FOV_Y_DEGREES: f32 = 50.0;
/// Where the first sphere of every test sits (away from the origin, so that a missing
/// translation shows).
const CENTER: Vec3 = Vec3::new(0.5, -0.25, -1.0);

#[derive(Clone, Copy)]
struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    fn object(self, name: &str) -> Object {
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::splat(self.radius),
            Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            self.center,
        );
        Object::new(
            name,
            scene::mesh::uv_sphere(1.0, STACKS, SLICES),
            Material::diffuse(0.8, 0.8, 0.8),
            transform,
        )
    }
}

fn scene_of(objects: Vec<Object>) -> Scene {
    Scene {
        name: "depth peel test".into(),
        objects,
        textures: vec![],
        lights: vec![],
        camera: scene::Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: FOV_Y_DEGREES,
            orthographic: None,
        },
        camera_path: Default::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

/// Largest distance of the mesh inside the sphere, for a unit radius.
fn sagitta() -> f32 {
    let (dt, dp) = (
        std::f32::consts::PI / STACKS as f32,
        std::f32::consts::TAU / SLICES as f32,
    );
    1.0 - (0.5 * (dt * dt + dp * dp).sqrt()).cos()
}

struct Camera {
    eye: Vec3,
    view_proj: Mat4,
}

impl Camera {
    /// On the line through `target` parallel to +Z, at distance `z`, looking at `target`.
    fn behind(target: Vec3, z: f32) -> Self {
        let eye = target + Vec3::new(0.0, 0.0, z);
        let proj = glam::camera::rh::proj::directx::perspective(
            FOV_Y_DEGREES.to_radians(),
            1.0,
            0.1,
            20.0,
        );
        let view = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y);
        Self {
            eye,
            view_proj: proj * view,
        }
    }

    /// Unit direction of the ray through the centre of pixel (i, j), row 0 at the top.
    fn ray(&self, i: u32, j: u32) -> Vec3 {
        let ndc = Vec2::new(
            (i as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
            1.0 - (j as f32 + 0.5) / SIZE as f32 * 2.0,
        );
        let inv = self.view_proj.inverse();
        let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.eye).normalize()
    }
}

struct Peeled {
    layers: Vec<Vec<[f32; 4]>>,
    depths: Vec<Vec<f32>>,
    spans: Vec<(String, f64)>,
}

/// Moves the scene to `time`, peels it in one submission (GPU validation errors fail the
/// test) and reads every layer back.
fn peel_with(
    peeler: &DepthPeeler,
    gpu_scene: &mut GpuScene,
    filter: &ObjectFilter,
    camera: &Camera,
    time: f32,
) -> Peeled {
    let ctx = testkit::context();
    let spans = ctx
        .validated(|| {
            testkit::submit(ctx, gpu_scene, time, |frame, s| {
                peeler
                    .peel(frame, s, filter, camera.view_proj, camera.eye)
                    .expect("peel")
            })
        })
        .expect("no validation error");
    let layers = peeler.layers();
    Peeled {
        layers: (0..layers)
            .map(|l| peeler.read_layer(ctx, l).expect("read layer"))
            .collect(),
        depths: (0..layers)
            .map(|l| peeler.read_depth(ctx, l).expect("read depth"))
            .collect(),
        spans,
    }
}

fn peel(scene: &Scene, filter: &ObjectFilter, camera: &Camera, layers: u32) -> Peeled {
    let ctx = testkit::context();
    let mut gpu_scene = GpuScene::new(ctx, scene).expect("scene uploads");
    let peeler = DepthPeeler::new(ctx, &gpu_scene, SIZE, SIZE, layers).expect("peeler");
    peel_with(&peeler, &mut gpu_scene, filter, camera, 0.0)
}

fn at(image: &[[f32; 4]], i: u32, j: u32) -> Vec4 {
    Vec4::from_array(image[(j * SIZE + i) as usize])
}

/// Checks `layers[first]` and `layers[first + 1]` against the front and back of `sphere` at
/// every pixel away from its silhouette, and that both are empty where the ray misses it.
/// Returns (hits, misses).
fn check_sphere(peeled: &Peeled, first: usize, sphere: Sphere, camera: &Camera) -> (u32, u32) {
    let (front, back) = (&peeled.layers[first], &peeled.layers[first + 1]);
    let sag = sphere.radius * sagitta();
    let (mut hits, mut misses) = (0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let d = camera.ray(i, j);
            let t = gpu::prelude::ray_sphere(camera.eye, d, sphere.center, sphere.radius);
            let pixel = (j * SIZE + i) as usize;
            // Distance of the ray from the sphere centre, compared with the radius.
            let miss_distance = (camera.eye - sphere.center).cross(d).length() - sphere.radius;
            if miss_distance > 0.0 {
                for layer in [front, back] {
                    assert_eq!(at(layer, i, j), Vec4::ZERO, "({i}, {j}) misses the sphere");
                }
                misses += 1;
                continue;
            }
            if miss_distance > -0.1 * sphere.radius {
                continue; // near the silhouette
            }
            hits += 1;
            for (layer, t_exact, outward, name) in
                [(front, t.x, -1.0, "front"), (back, t.y, 1.0, "back")]
            {
                let texel = at(layer, i, j);
                let p_exact = camera.eye + t_exact * d;
                let cos_incidence = ((p_exact - sphere.center) / sphere.radius).dot(d).abs();
                let tol = 1.2 * sag / cos_incidence + 1e-4;
                assert!(
                    (texel.w - t_exact).abs() <= tol,
                    "{name} distance at ({i}, {j}): {} vs analytic {t_exact} (tol {tol})",
                    texel.w
                );
                let n = texel.truncate();
                let p = camera.eye + texel.w * d;
                assert!(
                    (n.length() - 1.0).abs() < 1e-4,
                    "{name} normal at ({i}, {j}) not unit: {n}"
                );
                assert!(
                    n.dot((p - sphere.center).normalize()) > 1.0 - 1e-3,
                    "{name} normal at ({i}, {j}) {n} is not radial at {p}"
                );
                assert!(
                    outward * n.dot(d) > 0.0,
                    "{name} normal at ({i}, {j}) {n} does not point outward"
                );
            }
            let (zf, zb) = (peeled.depths[first][pixel], peeled.depths[first + 1][pixel]);
            assert!(
                0.0 < zf && zf < zb && zb < 1.0,
                "depths at ({i}, {j}): front {zf}, back {zb}"
            );
        }
    }
    (hits, misses)
}

fn assert_empty(peeled: &Peeled, layer: usize) {
    assert!(
        peeled.layers[layer].iter().all(|t| *t == [0.0; 4]),
        "layer {layer} must be empty"
    );
    assert!(
        peeled.depths[layer].iter().all(|z| *z == 1.0),
        "layer {layer}'s depth must be the clear value 1"
    );
}

/// A sphere of radius 1.25 at `CENTER` seen along -Z from 3.75 away: layer 0 is the front
/// surface, layer 1 the back surface, layer 2 empty, with outward world normals, at every
/// pixel away from the silhouette; the peel is timed as "depth peel".
#[test]
fn sphere_peels_into_front_back_and_empty() {
    let _gpu = testkit::gpu_lock();
    let sphere = Sphere {
        center: CENTER,
        radius: 1.25,
    };
    let camera = Camera::behind(CENTER, 3.0 * sphere.radius);
    let peeled = peel(
        &scene_of(vec![sphere.object("sphere")]),
        &ObjectFilter::All,
        &camera,
        3,
    );
    let (front, back) = (&peeled.layers[0], &peeled.layers[1]);

    // The centre pixel looks down the axis through mesh vertices at CENTER +- (0, 0, r).
    let c = SIZE / 2;
    let (f, b) = (at(front, c, c), at(back, c, c));
    assert!(
        (f.w - 2.5).abs() < 1e-4,
        "front distance at the centre {} (want 2.5)",
        f.w
    );
    assert!(
        (b.w - 5.0).abs() < 1e-4,
        "back distance at the centre {} (want 5)",
        b.w
    );
    assert!(
        (f.truncate() - Vec3::Z).length() < 1e-3,
        "front normal {}",
        f.truncate()
    );
    assert!(
        (b.truncate() - Vec3::NEG_Z).length() < 1e-3,
        "back normal {}",
        b.truncate()
    );
    assert_empty(&peeled, 2);

    let (hits, misses) = check_sphere(&peeled, 0, sphere, &camera);
    assert!(
        hits > 1000 && misses > 100,
        "the image should show the sphere and its surroundings ({hits} hits, {misses} misses)"
    );
    if testkit::context().has_timestamps() {
        assert!(
            peeled.spans.iter().any(|(label, _)| label == "depth peel"),
            "no \"depth peel\" span in {:?}",
            peeled.spans
        );
    }
}

/// The two spheres of the next tests on the camera axis: radius 1 at `CENTER` and radius 0.5
/// at `CENTER - (0, 0, 3)`, the far one first in the object list (so that the order of the
/// layers is the order in depth, not in drawing).
fn two_spheres() -> (Scene, Sphere, Sphere) {
    let near = Sphere {
        center: CENTER,
        radius: 1.0,
    };
    let far = Sphere {
        center: CENTER - Vec3::new(0.0, 0.0, 3.0),
        radius: 0.5,
    };
    let scene = scene_of(vec![far.object("far"), near.object("near")]);
    (scene, near, far)
}

/// The four surfaces of [`two_spheres`] at the centre pixel seen from `Camera::behind` the
/// near one (3 m): distance and normal, nearest first.
const TWO_SPHERES_ON_THE_AXIS: [(f32, Vec3); 4] = [
    (2.0, Vec3::Z),
    (4.0, Vec3::NEG_Z),
    (5.5, Vec3::Z),
    (6.5, Vec3::NEG_Z),
];

fn assert_centre_layers(peeled: &Peeled, want: &[(f32, Vec3)]) {
    let c = SIZE / 2;
    for (layer, &(distance, normal)) in want.iter().enumerate() {
        let texel = at(&peeled.layers[layer], c, c);
        assert!(
            (texel.w - distance).abs() < 1e-4,
            "layer {layer}: distance {} (want {distance})",
            texel.w
        );
        assert!(
            (texel.truncate() - normal).length() < 1e-3,
            "layer {layer}: normal {}",
            texel.truncate()
        );
    }
    let empty = want.len();
    assert_eq!(at(&peeled.layers[empty], c, c), Vec4::ZERO);
    assert_eq!(peeled.depths[empty][(c * SIZE + c) as usize], 1.0);
}

/// Two spheres on the axis give four surfaces in order at the centre pixel, then an empty
/// layer.
#[test]
fn two_spheres_peel_in_order() {
    let _gpu = testkit::gpu_lock();
    let (scene, near, _) = two_spheres();
    let camera = Camera::behind(near.center, 3.0);
    let peeled = peel(&scene, &ObjectFilter::All, &camera, 5);
    assert_centre_layers(&peeled, &TWO_SPHERES_ON_THE_AXIS);
}

/// `ObjectFilter::Only` peels the selected object alone: with only the far sphere, layers 0
/// and 1 are its front and back at every pixel (the near sphere, which hides its centre,
/// is not there) and layer 2 is empty; with only the near sphere, two layers then nothing.
/// `Except` of the other object gives the same layers bit for bit.
#[test]
fn only_filter_peels_the_selected_object_alone() {
    let _gpu = testkit::gpu_lock();
    let ctx = testkit::context();
    let (scene, near, far) = two_spheres();
    let camera = Camera::behind(near.center, 3.0);
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let peeler = DepthPeeler::new(ctx, &gpu_scene, SIZE, SIZE, 3).expect("peeler");

    let only_far = peel_with(
        &peeler,
        &mut gpu_scene,
        &ObjectFilter::Only(vec![0]),
        &camera,
        0.0,
    );
    assert_centre_layers(&only_far, &[(5.5, Vec3::Z), (6.5, Vec3::NEG_Z)]);
    let (hits, misses) = check_sphere(&only_far, 0, far, &camera);
    assert!(
        hits > 50 && misses > 1000,
        "the image should show the far sphere and its surroundings ({hits} hits, {misses} misses)"
    );
    assert_empty(&only_far, 2);

    let except_near = peel_with(
        &peeler,
        &mut gpu_scene,
        &ObjectFilter::Except(vec![1]),
        &camera,
        0.0,
    );
    assert_eq!(except_near.layers, only_far.layers);
    assert_eq!(except_near.depths, only_far.depths);

    let only_near = peel_with(
        &peeler,
        &mut gpu_scene,
        &ObjectFilter::Only(vec![1]),
        &camera,
        0.0,
    );
    assert_centre_layers(&only_near, &[(2.0, Vec3::Z), (4.0, Vec3::NEG_Z)]);
    check_sphere(&only_near, 0, near, &camera);
    assert_empty(&only_near, 2);
}

/// A sphere with a `Motion` (0.6 m along +x and 0.3 m along +y over one second) peeled at
/// t = 0 and t = 1 with the same peeler lands, at each time, on the analytic sphere around
/// `Object::center_at(t)`, and the two images differ. The peeler is made on another
/// `GpuScene` (every upload has the same layouts).
#[test]
fn moving_object_is_peeled_where_its_transform_says() {
    let _gpu = testkit::gpu_lock();
    let ctx = testkit::context();
    let sphere = Sphere {
        center: CENTER,
        radius: 0.75,
    };
    let mut object = sphere.object("moving");
    object.motion = Motion {
        keys: vec![(0.0, Vec3::ZERO), (1.0, Vec3::new(0.6, 0.3, 0.0))],
    };
    let scene = scene_of(vec![object.clone()]);
    let camera = Camera::behind(CENTER, 4.0);
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let other = GpuScene::new(ctx, &two_spheres().0).expect("scene uploads");
    let peeler = DepthPeeler::new(ctx, &other, SIZE, SIZE, 3).expect("peeler");

    let mut fronts = Vec::new();
    for time in [0.0, 1.0] {
        let peeled = peel_with(&peeler, &mut gpu_scene, &ObjectFilter::All, &camera, time);
        let moved = Sphere {
            center: object.center_at(time),
            radius: sphere.radius,
        };
        let (hits, misses) = check_sphere(&peeled, 0, moved, &camera);
        assert!(
            hits > 300 && misses > 1000,
            "at t = {time} the image should show the sphere and its surroundings ({hits} hits, \
             {misses} misses)"
        );
        assert_empty(&peeled, 2);
        fronts.push(peeled.layers[0].clone());
    }
    assert_eq!(
        object.center_at(1.0) - object.center_at(0.0),
        Vec3::new(0.6, 0.3, 0.0)
    );
    let changed = fronts[0]
        .iter()
        .zip(&fronts[1])
        .filter(|(a, b)| (a[3] == 0.0) != (b[3] == 0.0))
        .count();
    assert!(
        changed > 100,
        "only {changed} pixels changed coverage between t = 0 and t = 1"
    );
}

/// Bad input gives an error naming the problem, not a panic; an empty selection gives empty
/// layers.
#[test]
fn bad_input_is_an_error() {
    let _gpu = testkit::gpu_lock();
    let ctx = testkit::context();
    let (scene, _, _) = two_spheres();
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    assert!(matches!(
        DepthPeeler::new(ctx, &gpu_scene, 64, 64, 0),
        Err(GpuError::InvalidInput(_))
    ));
    let max_layers = ctx.device.limits().max_texture_array_layers;
    assert!(matches!(
        DepthPeeler::new(ctx, &gpu_scene, 16, 16, max_layers + 1),
        Err(GpuError::InvalidInput(_))
    ));
    assert!(matches!(
        DepthPeeler::new(ctx, &gpu_scene, 0, 64, 2),
        Err(GpuError::SizeOverLimit { .. })
    ));
    let max = ctx.device.limits().max_texture_dimension_2d;
    assert!(matches!(
        DepthPeeler::new(ctx, &gpu_scene, max + 1, 16, 2),
        Err(GpuError::SizeOverLimit { .. })
    ));

    let peeler = DepthPeeler::new(ctx, &gpu_scene, 16, 16, 2).expect("peeler");
    let camera = Camera::behind(CENTER, 3.0);
    let mut nan = camera.view_proj;
    nan.x_axis.x = f32::NAN;
    let errors = std::cell::RefCell::new(Vec::new());
    testkit::submit(ctx, &mut gpu_scene, 0.0, |frame, s| {
        let mut errors = errors.borrow_mut();
        errors.push(
            peeler
                .peel(frame, s, &ObjectFilter::All, nan, camera.eye)
                .unwrap_err(),
        );
        errors.push(
            peeler
                .peel(
                    frame,
                    s,
                    &ObjectFilter::All,
                    camera.view_proj,
                    Vec3::new(0.0, f32::INFINITY, 0.0),
                )
                .unwrap_err(),
        );
        errors.push(
            peeler
                .peel(
                    frame,
                    s,
                    &ObjectFilter::Only(vec![2]),
                    camera.view_proj,
                    camera.eye,
                )
                .unwrap_err(),
        );
    });
    let errors = errors.into_inner();
    for err in &errors {
        assert!(matches!(err, GpuError::InvalidInput(_)), "{err}");
    }
    assert!(errors[0].to_string().contains("finite"), "{}", errors[0]);
    assert!(errors[1].to_string().contains("finite"), "{}", errors[1]);
    assert!(errors[2].to_string().contains("object 2"), "{}", errors[2]);
    assert!(matches!(
        peeler.read_layer(ctx, 2),
        Err(GpuError::InvalidInput(_))
    ));
    assert!(matches!(
        peeler.read_depth(ctx, 2),
        Err(GpuError::InvalidInput(_))
    ));

    // An empty selection gives empty layers.
    let peeled = peel_with(
        &peeler,
        &mut gpu_scene,
        &ObjectFilter::Only(vec![]),
        &camera,
        0.0,
    );
    assert_empty(&peeled, 0);
    assert_empty(&peeled, 1);
}

/// On built-in scenes (the pool's waves and ladder, the bunny, the chess pieces), along each
/// camera path: at every pixel the non-empty layers come first, their clip depths strictly
/// increase (their distances do not decrease beyond rounding: two surfaces in contact, the
/// bunny's base on the floor, may round to the same f32 distance), and each holds the index of
/// a scene object in its surface texture: at layer 0 the object that the reference's BVH finds
/// along the pixel centre's ray (all but a few silhouette pixels, where the tessellated mesh
/// and a neighbouring triangle may differ).
#[test]
fn builtin_scenes_peel_into_strictly_increasing_layers() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let size = 48;
    // The perforated screen: no layer holds its holes (the reference's BVH skips them too).
    let specs = ["pool", "refraction-bunny", "chess"];
    for spec in specs.into_iter().chain(scene::builtin::CUTOUT_VARIANTS) {
        let scene = scene::load(spec).expect("scene");
        let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
        let layers = 8;
        let peeler = DepthPeeler::new(ctx, &gpu_scene, size, size, layers).expect("peeler");
        for time in [0.0, scene.camera_path.duration()] {
            let cam = scene.camera_at(time);
            let camera = Camera {
                view_proj: cam.view_proj(size, size),
                eye: cam.eye,
            };
            peel_with(&peeler, &mut gpu_scene, &ObjectFilter::All, &camera, time);
            let read: Vec<_> = (0..layers)
                .map(|l| {
                    (
                        peeler.read_layer(ctx, l).expect("layer"),
                        peeler.read_surface(ctx, l).expect("surface"),
                        peeler.read_depth(ctx, l).expect("depth"),
                    )
                })
                .collect();
            let mut deepest = 0;
            let bvh = scene::bvh::SceneBvh::build(&scene, time);
            let (mut covered, mut same_object) = (0, 0);
            // Pixels seen through a cut-out's holes, and those whose layer 0 is what the BVH
            // sees there (without the discard it would be the screen itself).
            let screen = scene
                .objects
                .iter()
                .position(|o| o.material.cutout().is_some());
            let solid = screen.map(|s| {
                let mut opaque = scene.clone();
                if let Material::Diffuse { cutout, .. } = &mut opaque.objects[s].material {
                    *cutout = None;
                }
                scene::bvh::SceneBvh::build(&opaque, time)
            });
            let (mut through_holes, mut peeled_through) = (0, 0);
            for p in 0..(size * size) as usize {
                let (x, y) = (
                    (p as u32 % size) as f32 + 0.5,
                    (p as u32 / size) as f32 + 0.5,
                );
                let ray = cam.ray_dir(x, y, size, size);
                if let Some(hit) = bvh.closest_hit(cam.eye, ray, f32::INFINITY) {
                    covered += 1;
                    same_object += (read[0].1[p][0] == hit.object as f32) as usize;
                    // Where the screen without its holes would be seen: a hole.
                    let solid_hit = solid
                        .as_ref()
                        .and_then(|b| b.closest_hit(cam.eye, ray, hit.t));
                    if solid_hit.is_some_and(|h| Some(h.object) == screen && h.object != hit.object)
                    {
                        through_holes += 1;
                        peeled_through += (read[0].1[p][0] == hit.object as f32) as usize;
                    }
                }
                let (mut previous, mut previous_depth) = (0.0, -1.0);
                let mut ended = false;
                for (l, (layer, surface, depth)) in read.iter().enumerate() {
                    let d = layer[p][3];
                    if d <= 0.0 {
                        ended = true;
                        assert_eq!(surface[p], [0.0; 4], "{spec} t={time} pixel {p} layer {l}");
                        continue;
                    }
                    assert!(
                        !ended,
                        "{spec} t={time} pixel {p}: layer {l} after an empty one"
                    );
                    // Distances come from the interpolated world position, depths from the
                    // clip position: their roundings differ by an ulp or so.
                    assert!(
                        d >= previous * (1.0 - 1e-5),
                        "{spec} t={time} pixel {p}: {d} after {previous}"
                    );
                    assert!(
                        depth[p] > previous_depth,
                        "{spec} t={time} pixel {p}: clip depth {} after {previous_depth}",
                        depth[p]
                    );
                    previous_depth = depth[p];
                    let object = surface[p][0];
                    assert!(
                        object.fract() == 0.0 && (object as usize) < scene.objects.len(),
                        "{spec} pixel {p} layer {l}: object {object}"
                    );
                    assert_eq!(surface[p][3], 1.0);
                    previous = d;
                    deepest = deepest.max(l + 1);
                }
            }
            assert!(deepest >= 2, "{spec}: only {deepest} layers anywhere");
            if screen.is_some() {
                assert!(
                    through_holes >= 10,
                    "{spec}: {through_holes} pixels through holes"
                );
                assert!(
                    peeled_through as f64 >= 0.9 * through_holes as f64,
                    "{spec} t={time}: layer 0 sees through {peeled_through} of {through_holes} holes"
                );
            }
            assert!(
                same_object as f64 >= 0.97 * covered as f64,
                "{spec} t={time}: layer 0 names the BVH's object at {same_object} of {covered} pixels"
            );
        }
    }
}

/// Section 2.2's layer count: a peeler that counts the depth complexity first gives, layer
/// for layer, what peeling every layer gives (the passes past the complexity are empty either
/// way), and the count is the deepest pixel's number of surfaces (two spheres on the axis:
/// four; the built-in views: at least what was peeled, and all of it when the cap is higher).
#[test]
fn counted_peels_match_full_peels() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    if !scene::layer_count::LayerCounter::available(ctx) {
        let gpu_scene = GpuScene::new(ctx, &two_spheres().0).expect("scene uploads");
        let mut peeler = DepthPeeler::new(ctx, &gpu_scene, SIZE, SIZE, 6).expect("peeler");
        assert!(peeler.count_layers(ctx, &gpu_scene).is_err());
        println!("not run: the adapter lacks INDIRECT_FIRST_INSTANCE");
        return;
    }
    let (scene, near, _) = two_spheres();
    let camera = Camera::behind(near.center, 3.0);
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let mut counted = DepthPeeler::new(ctx, &gpu_scene, SIZE, SIZE, 6).expect("peeler");
    counted.count_layers(ctx, &gpu_scene).expect("counter");
    let peeled = peel_with(&counted, &mut gpu_scene, &ObjectFilter::All, &camera, 0.0);
    assert_eq!(counted.counted_complexity(ctx).unwrap().unwrap(), 4);
    assert_centre_layers(&peeled, &TWO_SPHERES_ON_THE_AXIS);
    // The far sphere alone: two.
    peel_with(
        &counted,
        &mut gpu_scene,
        &ObjectFilter::Only(vec![0]),
        &camera,
        0.0,
    );
    assert_eq!(counted.counted_complexity(ctx).unwrap().unwrap(), 2);

    let size = 48;
    for (spec, layers) in [("pool", 8), ("refraction-bunny", 8), ("chess", 4)] {
        let scene = scene::load(spec).expect("scene");
        let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
        let full = DepthPeeler::new(ctx, &gpu_scene, size, size, layers).expect("peeler");
        let mut counted = DepthPeeler::new(ctx, &gpu_scene, size, size, layers).expect("peeler");
        counted.count_layers(ctx, &gpu_scene).expect("counter");
        let cam = scene.camera_at(0.0);
        let camera = Camera {
            view_proj: cam.view_proj(size, size),
            eye: cam.eye,
        };
        peel_with(&full, &mut gpu_scene, &ObjectFilter::All, &camera, 0.0);
        peel_with(&counted, &mut gpu_scene, &ObjectFilter::All, &camera, 0.0);
        let mut deepest = 0;
        for l in 0..layers {
            let (a, b) = (
                full.read_layer(ctx, l).unwrap(),
                counted.read_layer(ctx, l).unwrap(),
            );
            assert!(a == b, "{spec}: layer {l} differs");
            if a.iter().any(|t| t[3] > 0.0) {
                deepest = l + 1;
            }
        }
        let complexity = counted.counted_complexity(ctx).unwrap().unwrap();
        println!(
            "{spec}: depth complexity {complexity}, {deepest} of {layers} layers hold surfaces"
        );
        assert!(
            complexity >= deepest,
            "{spec}: counted {complexity}, peeled {deepest}"
        );
        // The count is never below the layers peeled; it could exceed them where two surfaces
        // lie closer than the peeler's epsilon (they count twice, peel once), which these views
        // do not have: below the cap the two are equal.
        if deepest < layers {
            assert_eq!(complexity, deepest, "{spec}");
        }
    }
}

/// The reduce-max reaches every pixel of an image larger than one dispatch of 65 535 groups
/// of 64 covers (4 194 240 pixels, the first 1823 rows here): two spheres seen near the
/// bottom of a 2300 x 2300 view count their four surfaces. A dispatch capped without the
/// stride counts 2 (tried: the far sphere's rim reaches into the rows it covers).
#[test]
fn the_count_reaches_pixels_past_one_dispatch() {
    let ctx = testkit::context();
    if !scene::layer_count::LayerCounter::available(ctx) {
        println!("not run: the adapter lacks INDIRECT_FIRST_INSTANCE");
        return;
    }
    let _lock = testkit::gpu_lock();
    let (scene, near, _) = two_spheres();
    let gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let size = 2300;
    let counter =
        scene::layer_count::LayerCounter::new(ctx, &gpu_scene, size, size, 6).expect("counter");
    let camera = Camera::behind(near.center, 3.0);
    // Moved down in clip space: the spheres' centre projects 92% of the way down the image.
    let down = Mat4::from_translation(Vec3::new(0.0, -0.84, 0.0));
    let group = gpu_scene.camera_bind_group(ctx, down * camera.view_proj, camera.eye);
    let depth = gpu::depth_texture(ctx, size, size, 1, "count depth");
    let depth_view = depth.create_view(&Default::default());
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    counter.count(
        &mut encoder,
        &gpu_scene,
        &ObjectFilter::All,
        &group,
        &depth_view,
        None,
    );
    ctx.queue.submit([encoder.finish()]);
    assert_eq!(counter.complexity(ctx).unwrap(), 4);
}
