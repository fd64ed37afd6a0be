//! The uploaded scene as a technique's host (`gpu::DrawScene`): a cube map drawn through the
//! trait is, bit for bit, the one `GpuScene::raster_cube` draws, so every technique that now
//! asks its host for its maps (impostors, image-space refraction, the many-object environment
//! impostor of refractor and height maps) renders what it rendered before the trait existed.
//! And a pass's objects keep the renderer's indices.

use gpu::cube::CubeTarget;
use gpu::{Objects, read_texture_bytes};
use scene::{BACKGROUND_DISTANCE, Frame, GpuScene, ObjectFilter};

#[test]
fn a_cube_drawn_through_the_trait_is_the_raster_cube() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let scene = scene::load("cornell-sphere").unwrap();
    let specular = scene.specular_objects()[0];
    let centre = scene.objects[specular].center_at(0.0);
    let mut uploaded = GpuScene::new(ctx, &scene).unwrap();
    let format = wgpu::TextureFormat::Rgba16Float;
    let [by_raster, by_trait] = ["raster_cube", "draw_scene_cube"]
        .map(|label| CubeTarget::new(ctx, 32, format, label).unwrap());
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    Frame::untimed(ctx, &mut encoder, |frame| {
        uploaded.set_time(frame, 0.0);
        let others = ObjectFilter::Except(vec![specular]);
        uploaded.raster_cube(frame, &by_raster, centre, &others, false);
        let depth_range = (0.01, 2.0 * BACKGROUND_DISTANCE);
        let others = Objects::AllBut(&[specular]);
        gpu::host::draw_scene_cube(frame, &uploaded, &by_trait, centre, depth_range, others);
    });
    ctx.queue.submit([encoder.finish()]);
    for face in 0..6 {
        let raster = read_texture_bytes(ctx, &by_raster.color, face, 8).unwrap();
        let host = read_texture_bytes(ctx, &by_trait.color, face, 8).unwrap();
        assert!(raster.iter().any(|&b| b != 0), "face {face} holds the room");
        assert_eq!(raster, host, "face {face}");
    }
}

/// A renderer's own formats keep its alpha; the harness's targets take every channel (the
/// distance in alpha).
#[test]
fn a_renderers_alpha_is_kept() {
    let own = gpu::TargetFormats::new(
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Depth24Plus,
    );
    let writes = |formats: gpu::TargetFormats| formats.color_target().unwrap().write_mask;
    assert_eq!(writes(own), wgpu::ColorWrites::COLOR);
    assert_eq!(writes(gpu::TargetFormats::HDR), wgpu::ColorWrites::ALL);
}

/// A renderer's objects uploaded for a pass keep the renderer's indices: every list a
/// technique hands its host names them as the renderer does (an index the pass does not hold
/// names nothing), and an offset moves an object without undoing its rotation.
#[test]
fn a_pass_names_its_objects_by_the_renderers_indices() {
    use glam::{Mat4, Vec3};
    use gpu::{DrawScene, HostedMesh, SceneView};
    use scene::hosted::{HostedObjects, HostedPiece, empty_scene};
    use std::cell::RefCell;

    /// A host that notes the object lists it is asked to draw.
    struct Recorder(RefCell<Vec<String>>);
    impl DrawScene for Recorder {
        fn draw_scene(&self, _: &mut Frame, view: &SceneView) {
            self.0.borrow_mut().push(format!("{:?}", view.objects));
        }
    }

    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let ball = scene::mesh::uv_sphere(0.5, 6, 8);
    let mesh = HostedMesh {
        positions: ball.positions.clone(),
        normals: ball.normals.clone(),
        indices: ball.indices.clone(),
    };
    let piece = |host_index, position| HostedPiece {
        mesh: &mesh,
        material: scene::Material::Glass { ior: 1.5 },
        host_index,
        position,
    };
    let pieces = [piece(6, Vec3::X), piece(9, -Vec3::X)];
    let mut objects = HostedObjects::new(ctx, &pieces).unwrap();
    let recorder = Recorder(RefCell::new(Vec::new()));
    let target = |format| {
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: 4,
                height: 4,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        texture.create_view(&Default::default())
    };
    let (color, depth) = (target(gpu::HDR_FORMAT), target(gpu::DEPTH_FORMAT));
    objects.set_offset(1, Vec3::new(0.0, 2.0, 0.0));
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    Frame::untimed(ctx, &mut encoder, |frame| {
        let (uploaded, host) = objects.for_frame(frame, &recorder);
        let moved = uploaded.scene.objects[1].transform;
        assert_eq!(moved, Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)));
        for list in [
            Objects::All,
            Objects::AllBut(&[0, 1]),
            Objects::Only(&[1, 5]),
        ] {
            let view = SceneView {
                view_proj: Mat4::IDENTITY,
                eye: Vec3::ZERO,
                objects: list,
                color: &color,
                color_format: gpu::HDR_FORMAT,
                depth: &depth,
            };
            host.draw_scene(frame, &view);
        }
    });
    ctx.queue.submit([encoder.finish()]);
    assert_eq!(*recorder.0.borrow(), ["All", "AllBut([6, 9])", "Only([9])"]);

    // A scene of the pass's own (a building with its rooms, say): an offset keeps its turn.
    let turned = Mat4::from_rotation_y(0.5) * Mat4::from_scale(Vec3::splat(2.0));
    let mut scene = empty_scene();
    scene.objects.push(scene::Object::new(
        "turned",
        ball.clone(),
        scene::Material::diffuse(0.5, 0.5, 0.5),
        Mat4::from_translation(Vec3::X) * turned,
    ));
    let mut objects = HostedObjects::of_scene(ctx, &scene, vec![3]).unwrap();
    objects.set_offset(0, Vec3::Z);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    Frame::untimed(ctx, &mut encoder, |frame| {
        let (uploaded, _) = objects.for_frame(frame, &recorder);
        let placed = uploaded.scene.objects[0].transform;
        assert!(placed.abs_diff_eq(Mat4::from_translation(Vec3::Z) * turned, 1e-6));
    });
    ctx.queue.submit([encoder.finish()]);
    assert!(
        HostedObjects::of_scene(ctx, &scene, vec![3, 4]).is_err(),
        "one index per object"
    );
}
