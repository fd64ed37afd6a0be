//! The passes of a frame, each stating what it reads and writes; `Refraction::render` orders
//! them.

use super::*;

/// The passes of a frame, each stating what it reads and writes; [`Refraction`]'s `render`
/// orders them.
impl State {
    /// The specular objects, in the order of their maps.
    pub(super) fn specular(&self) -> Vec<usize> {
        self.maps.iter().map(|m| m.object).collect()
    }

    pub(super) fn screen(&self) -> &Screen {
        self.screen.as_ref().expect("ensure_screen made it")
    }

    /// Writes the frame's uniforms: the eye, each object's refraction parameters and the
    /// one-interface parameters its recursive impostor is drawn with.
    pub(super) fn write_frame_params(&self, ctx: &Context, eye: &Eye, params: &[ParamsGpu]) {
        self.eye.write(ctx, &EyeGpu::from(eye));
        for (map, p) in self.maps.iter().zip(params) {
            map.params.write(ctx, p);
            let one_interface = ParamsGpu {
                variant: Variant::OneInterface.wgsl_id(),
                ..*p
            };
            map.impostor_params.write(ctx, &one_interface);
        }
    }

    /// The environment ("regenerate" span). Reads: the scene. Writes: each object's cube map
    /// of everything but itself and its rectangles (and of everything but itself, for
    /// recursive impostors), or once the engine's room probe without the specular objects.
    pub(super) fn regenerate(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        host: &dyn gpu::DrawScene,
        probe_to_capture: Option<(std::rc::Rc<CubeTarget>, Vec3)>,
    ) {
        let depth_range = (0.01, 2.0 * scene::BACKGROUND_DISTANCE);
        let cube = |frame: &mut Frame, cube: &CubeTarget, centre: Vec3, left_out: &[usize]| {
            let objects = gpu::Objects::AllBut(left_out);
            gpu::host::draw_scene_cube(frame, host, cube, centre, depth_range, objects);
        };
        if let Some((probe, centre)) = probe_to_capture {
            // The engine's baked probe: the scene without its specular objects, once.
            cube(frame, &probe, centre, &self.specular());
        }
        // What `prepare` built decides, not the settings since.
        let per_object = match self.room_probe.is_some() {
            true => &[][..],
            false => &self.maps[..],
        };
        let in_rectangles = self
            .rectangles
            .as_ref()
            .map(|r| r.objects())
            .unwrap_or_default();
        for map in per_object {
            let centre = scene.scene.objects[map.object].center_at(scene.time());
            let mut left_out = in_rectangles.clone();
            left_out.push(map.object);
            cube(frame, &map.cube, centre, &left_out);
            if let Some(full) = &map.full_cube {
                cube(frame, full, centre, &[map.object]);
            }
        }
    }

    /// The rectangle impostors of nearby geometry ("impostors" span). Reads: the scene, and
    /// for recursive impostors the specular objects drawn with one interface. Writes: each
    /// rectangle's texture.
    pub(super) fn impostors(&self, frame: &mut Frame, scene: &GpuScene, rects: &Rectangles) {
        let screen = self.screen();
        let mut draw = |frame: &mut Frame, object: usize, view_proj, eye, target: RasterTarget| {
            let i = self.maps.iter().position(|m| m.object == object);
            let (Some(i), Some(pipeline)) = (i, &self.impostor_pipeline) else {
                return;
            };
            let camera = scene.camera_bind_group(frame.gpu, view_proj, eye);
            let background = scene.scene.background;
            let label = "recursive impostor";
            let mut pass = scene::begin_scene_pass(frame.encoder, &target, background, label);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            pass.set_bind_group(2, &screen.impostor_groups[i], &[]);
            scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![object]));
        };
        let recursive = self.impostor_pipeline.is_some();
        rects.render(frame, scene, if recursive { Some(&mut draw) } else { None });
    }

    /// The refractor's front and back buffers from the eye ("buffers" span). Reads: the
    /// specular objects. Writes: `screen.front` and `screen.back` (normal and depth).
    pub(super) fn front_back(&self, frame: &mut Frame, scene: &GpuScene, camera: &wgpu::BindGroup) {
        let screen = self.screen();
        let specular = ObjectFilter::Only(self.specular());
        for (pipeline, buffer) in [
            (&self.front_pipeline, &screen.front),
            (&self.back_pipeline, &screen.back),
        ] {
            let mut pass = gpu::pass::begin(
                frame.encoder,
                "front/back buffer",
                &[gpu::pass::color(buffer, gpu::pass::CLEAR_BLACK)],
                Some(gpu::pass::depth(&screen.depth, gpu::pass::CLEAR_FAR)),
                None,
            );
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, camera, &[]);
            pass.set_bind_group(1, scene.bind_group(), &[]);
            scene.draw_objects(&mut pass, &specular);
        }
    }

    /// The refraction ("lookup" span). Reads: the buffers, the environment maps, the
    /// rectangles. Writes: the specular objects' colour and depth into the target.
    pub(super) fn lookup(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        main: &RasterTarget,
    ) {
        let target = RasterTarget {
            clear: false,
            ..*main
        };
        let background = scene.scene.background;
        let label = "image-space refraction";
        let mut pass = scene::begin_scene_pass(frame.encoder, &target, background, label);
        pass.set_pipeline(&self.refract_pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        for (k, (map, group)) in self.maps.iter().zip(&self.screen().groups).enumerate() {
            pass.set_bind_group(2, group, &[]);
            if let Some(rects) = &self.rectangles {
                pass.set_bind_group(3, &rects.refractors[k].group, &[]);
            }
            scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![map.object]));
        }
    }
}
