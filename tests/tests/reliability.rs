//! Bad input, real files and hard limits (issue #20): each test below is a case that once
//! panicked, produced NaN pixels, read a file outside the scene's folder, scored a black image
//! as perfect, or ran without bound, and it failed before its fix. The command-line cases are
//! in `harness/tests/reliability.rs`, the loader's fuzzing in `scene/tests/gltf_fuzz.rs`.

use glam::{Mat4, Vec3};
use gpu::GpuTimer;
use proptest::prelude::*;
use scene::{Camera, GpuScene, Material, Object, Scene, Technique, View, runner};
use std::path::{Path, PathBuf};
use testkit::gltf::{Glb, small_scene};
use testkit::{context, gpu_lock};
use truth::reference::{self, ReferenceOptions};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir()
        .join(format!("reliability-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn no_photons() -> ReferenceOptions {
    ReferenceOptions {
        photons: 0,
        ..ReferenceOptions::default()
    }
}

/// The reference of `scene`'s default camera at `size`, without caustics.
fn reference_image(scene: &Scene, size: u32) -> gpu::HdrImage {
    reference::render(scene, &scene.camera, 0.0, size, size, &no_photons()).image
}

fn load_error(path: &Path) -> String {
    match scene::load(path.to_str().unwrap()) {
        Ok(_) => panic!("{} loaded, an error was expected", path.display()),
        Err(e) => e.to_string(),
    }
}

/// Renders `technique` on `scene` from each camera after one prepare; every image.
fn render_views(
    technique: &mut dyn Technique,
    scene: &Scene,
    cameras: &[Camera],
    size: u32,
) -> Result<Vec<gpu::HdrImage>, String> {
    let ctx = context();
    let mut gpu_scene = GpuScene::new(ctx, scene).map_err(|e| e.to_string())?;
    let target = gpu::Target::new(ctx, size, size).map_err(|e| e.to_string())?;
    let mut timer = GpuTimer::new(ctx, 64);
    runner::update_scene(ctx, &mut timer, &mut gpu_scene, 0.0).map_err(|e| e.to_string())?;
    runner::prepare(ctx, &mut timer, technique, &gpu_scene).map_err(|e| e.to_string())?;
    let mut images = Vec::new();
    for camera in cameras {
        let view = View {
            camera: *camera,
            time: 0.0,
            width: size,
            height: size,
        };
        runner::render_frame(ctx, &mut timer, technique, &mut gpu_scene, &view, &target)
            .map_err(|e| e.to_string())?;
        images.push(target.read(ctx).map_err(|e| e.to_string())?);
    }
    Ok(images)
}

// ---- 1. Camera bases ------------------------------------------------------------------

/// A top-down camera with up = +Y (the file) loads, and the reference and the raster
/// pass render it without a panic or a NaN (obvhs asserted on the NaN ray direction).
#[test]
fn top_down_camera_with_parallel_up_renders() {
    let mut glb = Glb::from_scene(&small_scene());
    glb.set_camera(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::Y);
    let path = glb.write_glb(&dir("top-down"), "top-down");
    let scene = scene::load(path.to_str().unwrap()).expect("the file loads");
    assert_eq!(
        scene.camera.up,
        Vec3::Y,
        "the degenerate up is kept as given"
    );
    let truth = reference_image(&scene, 24);
    assert_eq!(truth.non_finite_count(), 0);
    assert!(harness::score::black_reference(&truth).is_none());
    let _lock = gpu_lock();
    let mut raster = testkit::technique(scene::foundation::techniques(), "raster");
    let images = render_views(raster.as_mut(), &scene, &[scene.camera], 24).unwrap();
    assert_eq!(images[0].non_finite_count(), 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any camera `validate` accepts has an orthonormal basis, a finite view matrix and unit
    /// ray directions, whatever its up vector (zero, parallel or opposite to the view, not
    /// finite).
    #[test]
    fn every_camera_has_an_orthonormal_basis(
        eye in testkit::strategies::vec3_in(-5.0, 5.0),
        dir in testkit::strategies::direction_with_zeros(),
        up in prop_oneof![
            testkit::strategies::unit_vector(),
            Just(Vec3::Y), Just(Vec3::NEG_Y), Just(Vec3::ZERO), Just(Vec3::splat(f32::NAN)),
        ],
        parallel in any::<bool>(),
    ) {
        let up = if parallel { dir * 3.0 } else { up };
        let camera = Camera { eye, target: eye + dir, up, fov_y_deg: 60.0 , orthographic: None };
        let (f, r, u) = camera.basis();
        for v in [f, r, u] {
            prop_assert!((v.length() - 1.0).abs() < 1e-4, "{v}");
        }
        prop_assert!(f.dot(r).abs() < 1e-4 && f.dot(u).abs() < 1e-4 && r.dot(u).abs() < 1e-4);
        prop_assert!(camera.view().is_finite());
        for (x, y) in [(0.0, 0.0), (16.0, 16.0), (32.0, 7.0)] {
            let d = camera.ray_dir(x, y, 32, 32);
            prop_assert!(d.is_finite() && (d.length() - 1.0).abs() < 1e-4, "{d}");
        }
    }
}

/// Rays through the BVH with zero direction components, or no usable direction at all, miss
/// or hit; they never panic.
#[test]
fn degenerate_rays_never_panic_in_the_bvh() {
    let scene = small_scene();
    let bvh = scene::bvh::SceneBvh::build(&scene, 0.0);
    let o = Vec3::new(0.1, 1.0, 1.5);
    assert!(bvh.closest_hit(o, Vec3::NEG_Y, f32::INFINITY).is_some());
    assert!(bvh.closest_hit(o, Vec3::ZERO, f32::INFINITY).is_none());
    assert!(bvh.closest_hit(o, Vec3::splat(f32::NAN), 10.0).is_none());
    assert!(!bvh.any_hit(Vec3::splat(f32::INFINITY), Vec3::Y, 10.0));
}

// ---- 3. Degenerate normals, unphysical materials, overflowing transforms ---------------

/// An all-zero NORMAL accessor: the importer falls back to geometric normals (and says so),
/// so the raster pass and the techniques have no NaN pixel (before: 1254-1508 of 4096).
#[test]
fn zero_normals_fall_back_to_geometric_normals() {
    let mut glb = Glb::from_scene(&small_scene());
    for mesh in 0..2 {
        let normals = glb.attribute(mesh, "NORMAL");
        glb.accessor_bytes(normals).fill(0);
    }
    // Finite but so large that their squared length overflows: as bad as zero.
    let normals = glb.attribute(2, "NORMAL");
    for chunk in glb.accessor_bytes(normals).chunks_exact_mut(4) {
        chunk.copy_from_slice(&1e30f32.to_le_bytes());
    }
    let path = glb.write_glb(&dir("zero-normals"), "zero-normals");
    let (scene, notes) = scene::load_noted(path.to_str().unwrap()).expect("loads");
    assert!(
        notes.iter().any(|n| n.contains("geometric normals")),
        "{notes:?}"
    );
    for o in &scene.objects {
        assert!(
            o.mesh
                .normals
                .iter()
                .all(|n| (n.length() - 1.0).abs() < 1e-5)
        );
    }
    let _lock = gpu_lock();
    for id in ["raster", "envmap/classic", "impostors/false-position-4"] {
        let mut t = testkit::technique(harness::registry(), id);
        let image = render_views(t.as_mut(), &scene, &[scene.camera], 32).unwrap();
        assert_eq!(image[0].non_finite_count(), 0, "{id}");
    }
}

/// Material parameters outside their physical range are refused with the range in the
/// message (before: metal n = -1 or k = 1e30 made 915 of 1024 reference pixels NaN).
#[test]
fn unphysical_materials_are_refused_with_their_range() {
    let cases = [
        (
            serde_json::json!({"kind": "metal", "n": [-1.0, -1.0, -1.0], "k": [1.0, 1.0, 1.0]}),
            "outside [0, 10]",
        ),
        (
            serde_json::json!({"kind": "metal", "n": [0.2, 0.2, 0.2], "k": [1e30, 1.0, 1.0]}),
            "metal k",
        ),
        (
            serde_json::json!({"kind": "glass", "ior": 1e9}),
            "outside [0.25, 4]",
        ),
        (
            serde_json::json!({"kind": "diffuse", "albedo": [2.0, 0.5, 0.5]}),
            "outside [0, 1]",
        ),
    ];
    let d = dir("materials");
    for (i, (extras, expected)) in cases.into_iter().enumerate() {
        let mut glb = Glb::from_scene(&small_scene());
        glb.set_material_extras(2, extras);
        let message = load_error(&glb.write_glb(&d, &format!("m{i}")));
        assert!(message.contains(expected), "{message}");
    }
}

/// A node scale of 1e19 is refused for its world-space extent (before: NaN in 23
/// techniques); a node scale of 1e-4 around vertices scaled by 1e4 (the same world size)
/// loads (before: refused as singular).
#[test]
fn transforms_are_judged_by_their_world_space_result() {
    let d = dir("transforms");
    let mut huge = Glb::from_scene(&small_scene());
    let node = huge.node("box");
    huge.json["nodes"][node]["scale"] = serde_json::json!([1e19, 1e19, 1e19]);
    let message = load_error(&huge.write_glb(&d, "huge"));
    assert!(message.contains("world coordinates up to"), "{message}");

    let mut tiny = Glb::from_scene(&small_scene());
    let node = tiny.node("box");
    tiny.json["nodes"][node]["scale"] = serde_json::json!([1e-4, 1e-4, 1e-4]);
    let positions = tiny.attribute(1, "POSITION");
    for chunk in tiny.accessor_bytes(positions).chunks_exact_mut(4) {
        let v = f32::from_le_bytes(chunk.try_into().unwrap()) * 1e4;
        chunk.copy_from_slice(&v.to_le_bytes());
    }
    for key in ["min", "max"] {
        let scaled: Vec<f64> = tiny.json["accessors"][positions][key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap() * 1e4)
            .collect();
        tiny.json["accessors"][positions][key] = serde_json::json!(scaled);
    }
    let path = tiny.write_glb(&d, "tiny");
    let scene = scene::load(path.to_str().unwrap()).expect("a tiny scale of big vertices loads");
    let original = small_scene();
    let world = |s: &Scene| {
        s.objects[1]
            .world_at(0.0)
            .transform_point3(s.objects[1].mesh.positions[0])
    };
    assert!(world(&scene).distance(world(&original)) < 1e-5);
    // A far camera-path key is refused like a far camera.
    let mut far = small_scene();
    let mut key = far.camera;
    key.eye.x = 1e7;
    far.camera_path.keys = vec![(0.0, far.camera), (1.0, key)];
    assert!(
        far.validate()
            .unwrap_err()
            .to_string()
            .contains("or its path")
    );
    // A transform that flattens the object is still refused.
    let mut flat = Glb::from_scene(&small_scene());
    let node = flat.node("box");
    flat.json["nodes"][node]["scale"] = serde_json::json!([1.0, 1e-9, 1.0]);
    assert!(load_error(&flat.write_glb(&d, "flat")).contains("singular"));
}

// ---- 4. Files outside the scene's folder ------------------------------------------------

/// Buffer URIs that point outside the glTF's folder (absolute, `../`, %-encoded `../`, a
/// symbolic link out of it), at a FIFO or at a device are refused before anything is read
/// (before: `/etc/passwd` was read and its size reported, a FIFO blocked forever, `/dev/zero`
/// was read until memory ran out).
#[test]
fn only_regular_files_inside_the_folder_are_read() {
    let root = dir("sandbox");
    let folder = root.join("scene");
    std::fs::create_dir_all(&folder).unwrap();
    let glb = Glb::from_scene(&small_scene());
    std::fs::write(root.join("outside.bin"), &glb.bin).unwrap();
    std::os::unix::fs::symlink(root.join("outside.bin"), folder.join("link.bin")).unwrap();
    let fifo = folder.join("fifo.bin");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    let cases: Vec<(&str, &str)> = vec![
        ("/etc/passwd", "absolute path"),
        ("/dev/zero", "absolute path"),
        ("../outside.bin", "outside the glTF's folder"),
        ("%2e%2e/outside.bin", "outside the glTF's folder"),
        ("..%2Foutside.bin", "outside the glTF's folder"),
        ("link.bin", "outside the glTF's folder"),
        ("missing/../../outside.bin", "outside the glTF's folder"),
        ("a%00b.bin", "control characters"),
    ];
    for (i, (uri, expected)) in cases.iter().enumerate() {
        let message = load_error(&glb.write_gltf(&folder, &format!("case{i}"), Some(uri)));
        assert!(message.contains(expected), "{uri}: {message}");
        assert!(!message.contains('\0'), "{uri}: a raw NUL in {message:?}");
        assert!(
            !message.contains("passwd") || message.contains("absolute"),
            "{message}"
        );
    }
    if made.is_ok_and(|s| s.success()) {
        let message = load_error(&glb.write_gltf(&folder, "fifo", Some("fifo.bin")));
        assert!(message.contains("not a regular file"), "{message}");
    }
    // A file inside the folder still loads, and only its declared byteLength is read: a
    // sparse 8 GB file behind a small buffer costs nothing.
    let big = folder.join("big.bin");
    std::fs::write(&big, &glb.bin).unwrap();
    std::fs::OpenOptions::new()
        .write(true)
        .open(&big)
        .unwrap()
        .set_len(8 << 30)
        .unwrap();
    let path = glb.write_gltf(&folder, "big", Some("big.bin"));
    scene::load(path.to_str().unwrap()).expect("a buffer file longer than byteLength loads");
}

// ---- 5. Scenes without lights and black references --------------------------------------

/// A glTF file without `KHR_lights_punctual` (every Khronos sample model without lights,
/// the project's own bunny.glb) gets a default key light and a sky, with a note; its
/// reference is no longer black (before: every technique scored RMSE 0, PSNR inf, FLIP 0).
#[test]
fn files_without_lights_get_default_lighting() {
    let mut glb = Glb::from_scene(&small_scene());
    glb.remove_lights();
    let path = glb.write_glb(&dir("no-lights"), "no-lights");
    let (scene, notes) = scene::load_noted(path.to_str().unwrap()).unwrap();
    assert_eq!(scene.lights.len(), 1);
    assert!(
        notes.iter().any(|n| n.contains("default key light")),
        "{notes:?}"
    );
    assert_eq!(scene.background, scene::DEFAULT_SKY);
    let truth = reference_image(&scene, 32);
    assert!(harness::score::black_reference(&truth).is_none());
    // The project's own asset, which has no light either.
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/../scene/assets/bunny.glb");
    let (bunny, notes) = scene::load_noted(bunny).unwrap();
    assert_eq!(bunny.lights.len(), 1, "{notes:?}");
    let truth = reference_image(&bunny, 32);
    assert!(harness::score::black_reference(&truth).is_none());
}

/// A comparison against a black reference is flagged invalid instead of scored.
#[test]
fn black_references_are_not_scored() {
    let black = gpu::HdrImage::new(16, 16);
    assert!(harness::score::black_reference(&black).is_some());
    let mut lit = black.clone();
    for p in lit.pixels.iter_mut().take(16) {
        *p = [0.5, 0.5, 0.5, 1.0];
    }
    assert!(harness::score::black_reference(&lit).is_none());
}

// ---- 7. Scale: many lights, many objects, many triangles --------------------------------

fn boxes(count: usize) -> Vec<Object> {
    (0..count)
        .map(|i| {
            let x = (i % 50) as f32 * 0.1 - 2.5;
            let z = (i / 50) as f32 * 0.1 - 2.0;
            Object::new(
                &format!("box {i}"),
                scene::mesh::cuboid(Vec3::new(x, 0.0, z), Vec3::new(x + 0.05, 0.1, z + 0.05)),
                Material::diffuse(0.6, 0.6, 0.6),
                Mat4::IDENTITY,
            )
        })
        .collect()
}

/// A thousand point lights and two thousand objects: the reference renders them (before it
/// failed), the GPU scene refuses the lights with its limit named (before: a wgpu
/// validation error about 6006 layers).
#[test]
fn thousands_of_lights_and_objects() {
    let mut scene = small_scene();
    scene.objects.extend(boxes(2000));
    scene.lights = (0..1000)
        .map(|i| scene::Light {
            name: format!("light {i}"),
            position: Vec3::new(
                (i % 10) as f32 * 0.4 - 2.0,
                2.0 + (i / 100) as f32 * 0.1,
                ((i / 10) % 10) as f32 * 0.4 - 2.0,
            ),
            intensity: Vec3::splat(0.01),
            kind: scene::LightKind::Point,
        })
        .collect();
    scene.validate().unwrap();
    let start = std::time::Instant::now();
    let truth = reference::render(&scene, &scene.camera, 0.0, 24, 24, &no_photons());
    assert_eq!(truth.image.non_finite_count(), 0);
    assert!(harness::score::black_reference(&truth.image).is_none());
    assert!(start.elapsed().as_secs() < 60, "{:?}", start.elapsed());
    let error = GpuScene::new(context(), &scene)
        .err()
        .expect("over the light limit");
    let layers = context().device.limits().max_texture_array_layers;
    let limit = format!("takes at most {}", (layers / 6).min(4681));
    assert!(error.to_string().contains(&limit), "{error}");
    let many = scene::shadow_map_size(5000, 2048).unwrap_err().to_string();
    assert!(many.contains("takes at most 341"), "{many}");
    // Within the limit the shadow maps get coarser instead.
    assert_eq!(scene::shadow_map_size(300, 2048).unwrap(), 128);
    assert_eq!(scene::shadow_map_size(1, 2048).unwrap(), 1024);
}

/// Per-object maps have a budget: 200 glass spheres are refused by the techniques that keep
/// a map per object, with the limit named (before: 5.9 GB and 219 s for one frame).
#[test]
fn per_object_maps_have_a_budget() {
    let mut scene = small_scene();
    for i in 0..200 {
        let x = (i % 20) as f32 * 0.2 - 2.0;
        let z = (i / 20) as f32 * 0.2 - 1.0;
        scene.objects.push(
            Object::new(
                &format!("sphere {i}"),
                scene::mesh::uv_sphere(0.05, 6, 8),
                Material::glass(1.5),
                Mat4::from_translation(Vec3::new(x, 0.5, z)),
            )
            .with_roles(scene::Roles::REFRACTOR | scene::Roles::CAUSTIC_CASTER),
        );
    }
    let _lock = gpu_lock();
    let mut t = testkit::technique(harness::registry(), "impostors/caustics");
    let error = render_views(t.as_mut(), &scene, &[scene.camera], 16).unwrap_err();
    assert!(
        error.contains("budget") && error.contains("at most"),
        "{error}"
    );
}

/// More triangles than the renderers accept is one sentence naming the limit (before: 2000
/// spheres of 9024 triangles took 120 s and 8 GB).
#[test]
fn triangle_count_is_limited() {
    let mut scene = small_scene();
    let mut mesh = scene.objects[1].mesh.clone();
    let n = scene::MAX_TRIANGLES + 1;
    mesh.indices = (0..n).flat_map(|_| [0, 1, 2]).collect();
    scene.objects.push(Object::new(
        "many",
        mesh,
        Material::diffuse(0.5, 0.5, 0.5),
        Mat4::IDENTITY,
    ));
    let error = scene.validate().unwrap_err().to_string();
    assert!(error.contains("accept at most 4000000"), "{error}");
}

// ---- 10. Textures are not padded to squares ---------------------------------------------

#[test]
fn texture_arrays_are_not_padded_to_squares() {
    let texture = |w, h| scene::Texture {
        name: "t".into(),
        width: w,
        height: h,
        rgba8: vec![255; (4 * w * h) as usize],
    };
    assert_eq!(scene::albedo_array_extent(&[texture(16384, 2)]), (16384, 2));
    assert_eq!(
        scene::albedo_array_extent(&[texture(8, 2), texture(3, 5)]),
        (8, 5)
    );
    let mut scene = small_scene();
    scene.textures.push(texture(4096, 2));
    scene.objects[0].material = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    GpuScene::new(context(), &scene).expect("a 4096 x 2 texture uploads");
}

// ---- 11. Panics are failures ---------------------------------------------------------

/// A technique that panics: `compare` catches it as the last guard, but the row is a failure
/// and the report lists it, which makes the binary exit non-zero.
#[test]
fn a_panicking_technique_is_a_listed_failure() {
    struct Panics;
    impl Technique for Panics {
        fn id(&self) -> String {
            "test/panics".into()
        }
        fn description(&self) -> String {
            "panics in render".into()
        }
        fn supports(&self, _: &Scene) -> bool {
            true
        }
        fn prepare(&mut self, _: &mut scene::Frame, _: &GpuScene) -> scene::TechniqueResult<()> {
            Ok(())
        }
        fn render(
            &mut self,
            _: &mut scene::Frame,
            _: &GpuScene,
            _: &View,
            _: &gpu::Target,
        ) -> scene::TechniqueResult<()> {
            panic!("deliberately")
        }
    }
    let factory = || -> Vec<Box<dyn Technique>> { vec![Box::new(Panics)] };
    let ground_truth = harness::CpuReference::fixed(no_photons());
    let env = harness::Env {
        ctx: context(),
        techniques: &factory,
        ground_truth: &ground_truth,
        progress: false,
    };
    let out = dir("panics");
    let opts = harness::compare::CompareOptions {
        scenes: vec!["cornell-sphere".into()],
        techniques: None,
        all_variants: true,
        size: harness::Size::new(16, 16),
        frames: harness::Frames {
            timed: 1,
            warmup: 0,
            errors: 1,
            timed_budget_s: 0.0,
        },
    };
    let _lock = gpu_lock();
    let report =
        harness::compare::run(&env, &opts, &harness::engine::ExecOptions::new(&out)).unwrap();
    assert_eq!(report.panics.len(), 1, "{:?}", report.errors);
    assert!(
        report.rows[0]
            .error
            .as_deref()
            .unwrap()
            .starts_with("panicked: ")
    );
}

// ---- 12. Any camera, any material: finite pixels from every technique --------------------

/// A camera anywhere in or around the scene (inside objects too), looking anywhere, with any
/// up vector.
fn any_camera(lo: Vec3, hi: Vec3) -> impl Strategy<Value = Camera> {
    let pad = (hi - lo) * 0.25;
    (
        testkit::strategies::vec3_in(0.0, 1.0),
        testkit::strategies::direction_with_zeros(),
        prop_oneof![
            testkit::strategies::unit_vector(),
            Just(Vec3::Y),
            Just(Vec3::ZERO)
        ],
        any::<bool>(),
        10.0f32..120.0,
    )
        .prop_map(move |(s, dir, up, parallel, fov)| {
            let eye = lo - pad + s * (hi - lo + 2.0 * pad);
            Camera {
                eye,
                target: eye + dir,
                up: if parallel { -dir } else { up },
                fov_y_deg: fov,
                orthographic: None,
            }
        })
}

fn scene_bounds(scene: &Scene) -> (Vec3, Vec3) {
    scene::bvh::SceneBvh::build(scene, 0.0).bounds()
}

/// The first built-in scene each registered technique supports.
fn technique_scenes() -> Vec<(String, Scene)> {
    let scenes: Vec<Scene> = scene::builtin::builtin_scenes()
        .iter()
        .map(|s| scene::load(s.name).unwrap())
        .collect();
    harness::registry()
        .into_iter()
        .filter(|t| t.id() != "reference" && context().require(t.required_features()).is_ok())
        .filter_map(|t| {
            let scene = scenes.iter().find(|s| t.supports(s))?;
            Some((t.id(), scene.clone()))
        })
        .collect()
}

/// Every technique and the reference, from random cameras (any orientation, inside objects):
/// finite pixels only.
#[test]
fn every_technique_renders_finite_pixels_from_any_camera() {
    let config = ProptestConfig {
        cases: 1,
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    let _lock = gpu_lock();
    let pairs = technique_scenes();
    assert!(pairs.len() > 40, "{} techniques", pairs.len());
    let rendered = std::cell::Cell::new(0);
    for (id, scene) in pairs {
        let (lo, hi) = scene_bounds(&scene);
        let cameras = proptest::collection::vec(any_camera(lo, hi), 4);
        // A runner per technique: each draws its own cameras (a runner runs its cases once).
        proptest::test_runner::TestRunner::new(config.clone())
            .run(&cameras, |cameras| {
                let mut t = testkit::technique(harness::registry(), &id);
                let images = render_views(t.as_mut(), &scene, &cameras, 16)
                    .map_err(|e| TestCaseError::fail(format!("{id}: {e}")))?;
                for (camera, image) in cameras.iter().zip(&images) {
                    prop_assert_eq!(image.non_finite_count(), 0, "{} from {:?}", id, camera);
                }
                rendered.set(rendered.get() + images.len());
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{id} on {}: {e}", scene.name));
    }
    println!("{} images from random cameras, all finite", rendered.get());
    let scene = scene::load("cornell-sphere").unwrap();
    let (lo, hi) = scene_bounds(&scene);
    proptest!(ProptestConfig::with_cases(8), |(camera in any_camera(lo, hi))| {
        let image = reference::render(&scene, &camera, 0.0, 12, 12, &ReferenceOptions { photons: 2000, ..ReferenceOptions::default() }).image;
        prop_assert_eq!(image.non_finite_count(), 0, "{:?}", camera);
    });
}

/// Glass of any index in [0.5, 2.5] and metal of any n and k in [0, 10]: every technique that
/// renders `cornell-sphere`, and the reference, give finite pixels.
#[test]
fn every_technique_renders_finite_pixels_for_any_material() {
    let material = prop_oneof![
        (0.5f32..2.5).prop_map(Material::glass),
        (
            testkit::strategies::vec3_in(0.0, 10.0),
            testkit::strategies::vec3_in(0.0, 10.0)
        )
            .prop_map(|(n, k)| Material::Metal { n, k }),
    ];
    let base = scene::load("cornell-sphere").unwrap();
    let sphere = base
        .objects
        .iter()
        .position(|o| o.material.is_specular())
        .unwrap();
    let ids: Vec<String> = harness::registry()
        .iter()
        .filter(|t| t.id() != "reference" && t.supports(&base))
        .filter(|t| context().require(t.required_features()).is_ok())
        .map(|t| t.id())
        .collect();
    let _lock = gpu_lock();
    let rendered = std::cell::Cell::new(0);
    proptest!(ProptestConfig { cases: 3, failure_persistence: None, ..ProptestConfig::default() }, |(m in material)| {
        let mut scene = base.clone();
        scene.objects[sphere].material = m.clone();
        scene.validate().unwrap();
        let truth = reference::render(&scene, &scene.camera, 0.0, 12, 12, &ReferenceOptions { photons: 2000, ..ReferenceOptions::default() }).image;
        prop_assert_eq!(truth.non_finite_count(), 0, "reference with {:?}", m);
        for id in &ids {
            let mut t = testkit::technique(harness::registry(), id);
            let images = render_views(t.as_mut(), &scene, &[scene.camera], 16)
                .map_err(|e| TestCaseError::fail(format!("{id}: {e}")))?;
            prop_assert_eq!(images[0].non_finite_count(), 0, "{} with {:?}", id, m);
            rendered.set(rendered.get() + 1);
        }
    });
    println!("{} images of random materials, all finite", rendered.get());
    assert!(rendered.get() >= 3 * ids.len());
}
