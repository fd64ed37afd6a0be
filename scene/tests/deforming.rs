//! A deforming object on the GPU: `GpuScene::set_time` rewrites its vertices, so the shared
//! raster pass draws the morphed surface at each time, and re-renders the shadow maps, so the
//! shadow it casts deforms with it.
//!
//! The object is a diffuse unit UV sphere at the origin whose `Morph` target is the sphere of
//! radius 2 (weight 0 at t = 0, 1 at t = 1), above a floor at y = -2.2 lit by a point light
//! 8 m above the sphere's centre. The raster pass writes the distance from the eye in alpha,
//! so the centre pixel reads the distance to the sphere's front (the eye's distance to the
//! centre minus the radius, within the mesh's sagitta), and a floor point 2.2 m from the
//! light's axis is lit under the small sphere (its shadow has a radius of about 1.3 m there)
//! and shadowed under the large one (about 2.6 m).

use glam::{Mat4, Vec2, Vec3};
use gpu::Target;
use scene::{Camera, GpuScene, Light, Material, Morph, Object, ObjectFilter, RasterTarget, Scene};

const SIZE: u32 = 65;

fn morphing_scene() -> Scene {
    let mesh = scene::mesh::uv_sphere(1.0, 32, 64);
    let morph = Morph {
        positions: mesh.positions.iter().map(|p| *p * 2.0).collect(),
        normals: mesh.normals.clone(),
        keys: vec![(0.0, 0.0), (1.0, 1.0)],
    };
    let sphere = Object::new(
        "morphing sphere",
        mesh,
        Material::diffuse(0.6, 0.6, 0.6),
        Mat4::IDENTITY,
    )
    .with_morph(morph);
    let floor = Object::new(
        "floor",
        scene::mesh::quad(
            Vec3::new(-6.0, -2.2, 6.0),
            Vec3::X * 12.0,
            Vec3::NEG_Z * 12.0,
            Vec2::ONE,
        ),
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    );
    Scene {
        name: "deforming".into(),
        objects: vec![sphere, floor],
        textures: vec![],
        lights: vec![Light {
            name: "light".into(),
            position: Vec3::new(0.0, 8.0, 0.0),
            intensity: Vec3::splat(200.0),
            kind: scene::LightKind::Point,
        }],
        camera: Camera {
            eye: Vec3::new(0.0, 0.5, 9.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            orthographic: None,
        },
        camera_path: Default::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

/// Renders the raster pass of `gpu_scene` at `time` with the scene's camera.
fn raster_at(gpu_scene: &mut GpuScene, target: &Target, time: f32) -> gpu::HdrImage {
    let ctx = testkit::context();
    let camera = gpu_scene.scene.camera;
    testkit::submit(ctx, gpu_scene, time, |frame, s| {
        s.raster(
            frame,
            &RasterTarget::of(target, true),
            camera.view_proj(SIZE, SIZE),
            camera.eye,
            &ObjectFilter::All,
            false,
        )
    });
    target.read(ctx).expect("read back")
}

#[test]
fn set_time_on_a_morphing_object_changes_what_the_raster_pass_draws() {
    let _gpu = testkit::gpu_lock();
    let ctx = testkit::context();
    let scene = morphing_scene();
    assert!(scene.objects[0].is_deforming());
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let target = Target::new(ctx, SIZE, SIZE).expect("target");
    let camera = scene.camera;
    let centre = SIZE / 2;
    let floor_point = Vec3::new(2.2, -2.2, 0.0);
    let p = camera.project(floor_point, SIZE, SIZE).unwrap();
    let (fx, fy) = (p.x as u32, p.y as u32);
    let luminance = |px: [f32; 4]| (px[0] + px[1] + px[2]) / 3.0;

    let mut images = Vec::new();
    // Back to t = 0 last: the rewritten vertices return to the base mesh.
    for (time, radius) in [(0.0, 1.0), (1.0, 2.0), (0.5, 1.5), (0.0, 1.0)] {
        let image = raster_at(&mut gpu_scene, &target, time);
        assert_eq!(image.non_finite_count(), 0);
        let front = image.get(centre, centre)[3];
        let expected = camera.eye.length() - radius;
        assert!(
            (front - expected).abs() < 0.01 * radius,
            "t = {time}: the sphere's front is {front} m from the eye, expected {expected}"
        );
        // The floor point is seen (not the sphere) at every time.
        let floor = image.get(fx, fy);
        let along = camera.eye.distance(floor_point);
        assert!(
            (floor[3] - along).abs() < 0.1,
            "t = {time}: the floor point's pixel is {} m away, expected {along}",
            floor[3]
        );
        images.push((time, luminance(floor), image));
    }
    let (lit, shadowed) = (images[0].1, images[1].1);
    assert!(
        lit > 0.1 && shadowed < 0.1 * lit,
        "the floor 2.2 m off the light's axis should be lit under the unit sphere ({lit}) and \
         in the radius-2 sphere's shadow ({shadowed}): the shadow maps follow the deformation"
    );
    assert!(
        images[0].2 != images[1].2,
        "the images at t = 0 and 1 are the same"
    );
    assert!(
        images[0].2 == images[3].2,
        "t = 0 after t = 1 draws what the first t = 0 drew"
    );
}

/// Shadow maps kept up to date face by face (`GpuScene::set_time` draws again only the cube
/// faces a moving or deforming object enters or leaves) hold, texel for texel, what drawing
/// every face at that time holds: along cornell-sphere's path (a moving sphere), chess's (a
/// moving pawn) and this deforming sphere's.
#[test]
fn shadow_maps_drawn_face_by_face_equal_drawn_whole() {
    let ctx = testkit::context();
    let scenes = [
        scene::load("cornell-sphere").unwrap(),
        scene::load("chess").unwrap(),
        morphing_scene(),
    ];
    for scene in scenes {
        // The morph runs from 0 to 1; the built-in scenes' motion over their camera path.
        let end = scene.camera_path.duration().max(1.0);
        let mut stepped = GpuScene::new(ctx, &scene).unwrap();
        let mut timer = gpu::GpuTimer::new(ctx, 8);
        let _lock = testkit::gpu_lock();
        for i in 0..=4 {
            let time = end * i as f32 / 4.0;
            scene::runner::update_scene(ctx, &mut timer, &mut stepped, time).unwrap();
            let mut whole = GpuScene::new(ctx, &scene).unwrap();
            scene::runner::update_scene(ctx, &mut timer, &mut whole, time).unwrap();
            let (a, b) = (
                stepped.read_shadow_maps(ctx).unwrap(),
                whole.read_shadow_maps(ctx).unwrap(),
            );
            for (layer, (a, b)) in a.iter().zip(&b).enumerate() {
                assert!(
                    a == b,
                    "{} objects, time {time}: shadow layer {layer} differs from the map drawn whole",
                    scene.objects.len()
                );
            }
        }
    }
}

/// The face test that decides which faces are drawn again: every point of a sphere lies in a
/// face (the one of its largest component) that the test says the sphere reaches.
#[test]
fn a_sphere_reaches_the_face_of_every_point_in_it() {
    let mut seed = 0x1234_5678u32;
    let mut next = || {
        seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
    };
    for _ in 0..20_000 {
        let c = Vec3::new(next(), next(), next()) * 3.0;
        let r = (next() + 1.0) * 0.5;
        let p = c + Vec3::new(next(), next(), next()).normalize_or_zero() * r * next().abs();
        let a = p.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let face = 2 * axis + usize::from(p[axis] < 0.0);
        assert!(
            scene::sphere_meets_cube_face(c, r, face),
            "sphere {c} r {r} holds {p}, which face {face} sees"
        );
    }
    // A small sphere far along +X reaches +X alone.
    let hits: Vec<usize> = (0..6)
        .filter(|&f| scene::sphere_meets_cube_face(Vec3::new(5.0, 0.1, -0.2), 0.5, f))
        .collect();
    assert_eq!(hits, vec![0]);
}

/// Shadow maps of chosen casters (`CasterShadowMaps`, what an engine's transparent surfaces
/// that cast no shadow need): with every object a caster they hold the scene's own maps
/// texel for texel; without the sphere of cornell-sphere no texel is nearer than the scene's
/// (taking casters away can only open the view) and the sphere's texels are farther.
#[test]
fn caster_shadow_maps_hold_the_chosen_casters() {
    let ctx = testkit::context();
    let scene = scene::load("cornell-sphere").unwrap();
    let sphere = (scene.objects.iter())
        .position(|o| o.material.is_specular())
        .expect("cornell-sphere has its sphere");
    let mut gpu_scene = GpuScene::new(ctx, &scene).unwrap();
    let mut timer = gpu::GpuTimer::new(ctx, 8);
    let _lock = testkit::gpu_lock();
    scene::runner::update_scene(ctx, &mut timer, &mut gpu_scene, 0.0).unwrap();
    let own = gpu_scene.read_shadow_maps(ctx).unwrap();
    let mut drawn = |filter| {
        let maps = scene::CasterShadowMaps::new(ctx, &gpu_scene, filter);
        scene::runner::record(ctx, &mut timer, "casters", |frame| {
            maps.render(frame, &gpu_scene);
            Ok(())
        })
        .unwrap();
        maps.read(ctx).unwrap()
    };
    assert_eq!(drawn(scene::ObjectFilter::All), own);
    let floats = |bytes: &[u8]| bytemuck::cast_slice::<u8, f32>(bytes).to_vec();
    let (mut farther, mut nearer) = (0usize, 0usize);
    for (a, b) in drawn(scene::ObjectFilter::Except(vec![sphere]))
        .iter()
        .zip(&own)
    {
        for (without, with) in floats(a).into_iter().zip(floats(b)) {
            farther += (without > with * 1.001) as usize;
            nearer += (without < with * 0.999) as usize;
        }
    }
    println!("texels farther without the sphere: {farther}; nearer: {nearer}");
    assert_eq!(nearer, 0);
    assert!(
        farther > 1000,
        "the sphere's shadow is gone: {farther} texels"
    );
}
