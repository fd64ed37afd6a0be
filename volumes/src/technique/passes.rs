//! The passes of a frame, in the order of the module's docs, each stating what it reads and
//! writes.

use super::*;

/// What the passes of one frame read: the scene, the view, the target, the prepared
/// resources and the view-sized buffers. The passes in the order of the module's docs.
pub(super) struct FramePasses<'a> {
    pub(super) scene: &'a GpuScene,
    pub(super) view: &'a View,
    pub(super) target: &'a Target,
    pub(super) res: &'a Resources,
    pub(super) buffers: &'a FrameBuffers,
}

impl FramePasses<'_> {
    pub(super) fn view_proj(&self) -> glam::Mat4 {
        self.view
            .camera
            .view_proj(self.target.width, self.target.height)
    }

    /// 1. The thesis's depth pre-pass. Reads: the scene. Writes: the scene's distance from the
    ///    eye (`buffers.distance_view`, R16Float, cleared to the background distance).
    pub(super) fn scene_distance(&self, frame: &mut Frame) {
        let (scene, buffers) = (self.scene, self.buffers);
        let camera_group =
            scene.camera_bind_group(frame.gpu, self.view_proj(), self.view.camera.eye);
        let background = Load::Clear(wgpu::Color {
            r: BACKGROUND_DISTANCE as f64,
            g: 0.0,
            b: 0.0,
            a: 0.0,
        });
        let mut pass = pass::begin(
            frame.encoder,
            "volumes scene distance",
            &[pass::color(&buffers.distance_view, background)],
            Some(pass::depth(&buffers.distance_depth_view, pass::CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(&self.res.distance_pipeline);
        pass.set_bind_group(0, &camera_group, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::All);
    }

    /// 2. The diffuse scene. Reads: the scene and its shadow maps. Writes: the float colour
    ///    buffer and the target's depth, both cleared.
    pub(super) fn diffuse_scene(&self, frame: &mut Frame) {
        let scene_target = RasterTarget {
            color: &self.buffers.scene_color_view,
            depth: &self.target.depth_view,
            format: FLOAT_BUFFER_FORMAT,
            clear: true,
        };
        let (eye, all) = (self.view.camera.eye, &ObjectFilter::All);
        self.scene
            .raster(frame, &scene_target, self.view_proj(), eye, all, true);
    }

    /// 3. 8-bit slices only: from here on the frame is 8 bits per channel. Reads: the float
    ///    colour buffer. Writes: the 8-bit buffer.
    pub(super) fn to_bytes(&self, frame: &mut Frame) {
        let (res, buffers) = (self.res, self.buffers);
        let (Some(bytes_view), Some(pipeline), Some(group)) = (
            &buffers.bytes_view,
            &res.to_bytes_pipeline,
            &buffers.to_bytes_bind_group,
        ) else {
            return;
        };
        let mut pass = pass::begin(
            frame.encoder,
            "volumes to 8-bit",
            &[pass::color(bytes_view, CLEAR_OPAQUE_BLACK)],
            None,
            None,
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        gpu::fullscreen::draw(&mut pass);
    }

    /// The buffer the volumes blend into: the 8-bit one for 8-bit slices, else the float one.
    pub(super) fn work_view(&self) -> &wgpu::TextureView {
        let buffers = self.buffers;
        buffers
            .bytes_view
            .as_ref()
            .unwrap_or(&buffers.scene_color_view)
    }

    /// 5. Into the HDR target. Reads: the work buffer. Writes: the target's colour (alpha 1).
    pub(super) fn resolve(&self, frame: &mut Frame) {
        let mut pass = pass::begin(
            frame.encoder,
            "volumes resolve",
            &[pass::color(&self.target.color_view, CLEAR_OPAQUE_BLACK)],
            None,
            None,
        );
        pass.set_pipeline(&self.res.resolve_pipeline);
        pass.set_bind_group(0, &self.buffers.resolve_bind_group, &[]);
        gpu::fullscreen::draw(&mut pass);
    }
}

impl VolumeTechnique {
    /// 4. The volumes, back to front, in one instanced draw ("volumes" span). Reads: the
    ///    placed volumes, the thickness texture, the scene's distance or depth (ray-traced and
    ///    depth-fade variants). Writes: the work buffer, blended premultiplied over; billboards
    ///    and slices depth-tested against the target's depth without writing it.
    pub(super) fn draw_volumes(&self, frame: &mut Frame, passes: &FramePasses) {
        let FramePasses {
            scene,
            view,
            target,
            res,
            buffers,
        } = *passes;
        let camera = &view.camera;
        let placed = placed_volumes(&scene.scene.volumes, self.variant.set, camera, view.time);
        if placed.is_empty() {
            return;
        }
        let view_proj = passes.view_proj();
        let globals = GlobalsGpu {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: camera.eye.extend(1.0).to_array(),
            viewport: [target.width as f32, target.height as f32, 0.0, 0.0],
        };
        let records: Vec<VolumeGpu> = placed
            .iter()
            .map(|v| self.volume_record(v, &scene.scene.volumes))
            .collect();
        let reads_depth = self.reads_scene_depth();
        let distance_view = if reads_depth && !self.reads_depth_buffer() {
            &buffers.distance_view
        } else {
            &res.dummy_distance_view
        };
        let depth_view = if self.reads_depth_buffer() {
            &target.depth_view
        } else {
            &res.dummy_depth_view
        };
        let draw = VolumeDraw {
            pipeline: &res.volume_pipeline,
            layout: &res.volume_layout,
            thickness: &res.thickness_view,
            distance: distance_view,
            depth: depth_view,
            color: passes.work_view(),
            // Billboards and slices test against the scene's depth without writing it.
            depth_test: (!reads_depth).then_some(&target.depth_view),
        };
        self.record_volumes(frame, &draw, &globals, &records);
    }

    /// Records the volume pass (span "volumes"): `records` in one instanced draw, blended
    /// over `draw.color`. The harness's frame and a renderer's own frame
    /// ([`crate::SoftVolumePass`]) both draw through it.
    pub(crate) fn record_volumes(
        &self,
        frame: &mut Frame,
        draw: &VolumeDraw,
        globals: &GlobalsGpu,
        records: &[VolumeGpu],
    ) {
        let ctx = frame.gpu;
        let globals = gpu::Uniform::new(ctx, "volumes globals", globals);
        let volume_buffer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("volumes"),
                contents: bytemuck::cast_slice(records),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let group = bind::group(
            ctx,
            "volumes",
            draw.layout,
            &[
                globals.binding(),
                volume_buffer.as_entire_binding(),
                bind::view(draw.thickness),
                bind::sampler_resource(&ctx.samplers.linear_clamp),
                bind::view(draw.distance),
                bind::view(draw.depth),
            ],
        );
        frame.span("volumes", |frame| {
            // A read-only depth attachment (no depth ops), which `pass::depth` does not make.
            let depth_test = draw
                .depth_test
                .map(|view| wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: None,
                    stencil_ops: None,
                });
            let mut pass = pass::begin(
                frame.encoder,
                "volumes",
                &[pass::color(draw.color, Load::Keep)],
                depth_test,
                None,
            );
            pass.set_pipeline(draw.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..6, 0..records.len() as u32 * self.slice_count());
        });
    }
}

/// What one volume pass draws with and into.
pub(crate) struct VolumeDraw<'a> {
    pub(crate) pipeline: &'a wgpu::RenderPipeline,
    pub(crate) layout: &'a wgpu::BindGroupLayout,
    pub(crate) thickness: &'a wgpu::TextureView,
    /// The scene's distance texture (or a 1 x 1 stand-in where the variant reads none).
    pub(crate) distance: &'a wgpu::TextureView,
    /// The scene's depth buffer, sampled (or a 1 x 1 stand-in).
    pub(crate) depth: &'a wgpu::TextureView,
    /// The colour the volumes blend over.
    pub(crate) color: &'a wgpu::TextureView,
    /// The depth attachment billboards and slices are tested against, if any.
    pub(crate) depth_test: Option<&'a wgpu::TextureView>,
}
